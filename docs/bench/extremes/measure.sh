#!/bin/bash
# Issue 37's accuracy table: tests/data/extremes (discs k = 1e5, needles k = 1e4, a mix at
# k = 1e3 … 1e6) and grid40, every ray caster and kind, in the issue's three views, as
# `render --reference-check` reports them. Usage: measure.sh [BINARY] > table.csv
# (run from the repository root; BINARY defaults to target/release/tensorglyph).
source "$(dirname "$0")/common.sh"
echo "field,view,method,glyph,covered_px,coverage,id,depth_p99,normal_p99_deg"
for field in discs needles mixed; do
    for v in "${views[@]}"; do
        name=${v%%|*}; args=${v#*|}
        for glyph in ellipsoid cylinder capsule superquadric; do
            for method in gumhold sigg; do
                # shellcheck disable=SC2086
                row "$field" "$name" "$method" "$glyph" tests/data/extremes/$field.vtk \
                    --scale 0.8 --min-radius 0 --size 400x300 $args
            done
        done
    done
done
for v in "default|" "zoom4|--zoom 4" "ortho|--ortho"; do
    name=${v%%|*}; args=${v#*|}
    for glyph in ellipsoid cylinder superquadric; do
        for method in gumhold sigg; do
            # shellcheck disable=SC2086
            row grid40 "$name" "$method" "$glyph" --demo grid40 $args
        done
    done
done
