#!/bin/bash
# Issue 37's needles at k = 1e4, 1e5 and 1e6 (tests/data/extremes/needle_field*.vtk: 1,000 each,
# thinner than a pixel at k >= 1e5), every ray caster and kind, in the issue's three views, at
# 1024x768 as `render --reference-check` reports them. Usage: measure_thin.sh [BINARY] > t.csv
# (run from the repository root; BINARY defaults to target/release/tensorglyph).
source "$(dirname "$0")/common.sh"
echo "k,view,method,glyph,covered_px,coverage,id,depth_p99,normal_p99_deg"
for k in 1e4 1e5 1e6; do
    file=tests/data/extremes/needle_field.vtk
    [ "$k" = 1e4 ] || file=tests/data/extremes/needle_field_$k.vtk
    for v in "${views[@]}"; do
        name=${v%%|*}; args=${v#*|}
        for glyph in ellipsoid cylinder capsule superquadric; do
            for method in gumhold sigg; do
                # shellcheck disable=SC2086
                row "$k" "$name" "$method" "$glyph" "$file" --scale 0.8 --min-radius 0 \
                    --size 1024x768 $args
            done
        done
    done
done
