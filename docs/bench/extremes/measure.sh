#!/bin/bash
# Issue 37's accuracy table: tests/data/extremes (discs k = 1e5, needles k = 1e4, a mix at
# k = 1e3 … 1e6) and grid40, every ray caster and kind, in the three views, as
# `render --reference-check` reports them. Usage: measure.sh [BINARY] > table.csv
# (run from the repository root; BINARY defaults to target/release/tensorglyph).
set -euo pipefail
bin=${1:-target/release/tensorglyph}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
views=("default|" "zoom6|--zoom 6 --azimuth 17 --elevation -23" "ortho+x|--ortho --view +x")
echo "field,view,method,glyph,covered_px,coverage,id,depth_p99,normal_p99_deg"
row() {
    local field=$1 view=$2 method=$3 glyph=$4; shift 4
    "$bin" render "$@" --method "$method" --glyph "$glyph" -o "$out/x.png" --reference-check --json 2>/dev/null |
        python3 -c '
import json, sys
d = json.load(sys.stdin)
def flat(d):
    out = {}
    for k, v in d.items():
        out.update(flat(v) if isinstance(v, dict) else {k: v})
    return out
a = flat(d)
print(",".join(sys.argv[1:5] + ["%d" % a["covered_pixels"]] + ["%.2e" % a[k] for k in
      ("coverage_mismatch", "id_mismatch", "depth_err_rel_p99")] + ["%.3e" % a["normal_err_deg_p99"]]))
' "$field" "$view" "$method" "$glyph"
}
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
