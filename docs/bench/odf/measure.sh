#!/bin/sh
# ODF glyphs, speed against accuracy: each GPU method (the exact ray casters and the meshes of
# mesh:3 … mesh:6, 642 … 40962 vertices per glyph: DIPY's repulsion724 and finer) draws the same
# CSD fits in the same views, checked against the exact f64 reference; the rounds are
# interleaved (method by method, twice) so that a busy machine slows every method alike.
# Writes odf_speed.csv here: file, view, method, round, frame ms,
# covered pixels, coverage and id mismatch, depth p99 (radii), normal p99 (degrees).
# Run from the repository's root: sh docs/bench/odf/measure.sh (TG names the binary; default:
# the release build).
set -e
TG=${TG:-target/release/tensorglyph}
OUT=docs/bench/odf/odf_speed.csv
tmp=$(mktemp -d)
echo "file,view,method,round,frame_ms,covered_px,coverage_mismatch,id_mismatch,depth_p99,normal_p99_deg" >"$OUT"
for round in 1 2; do
    for f in dipy_lmax8_descoteaux07_legacy.nii.gz mrtrix_lmax12.mif.gz; do
        for view in slice 3d; do
            if [ "$view" = 3d ]; then
                V="--slice z=0 --slice z=1 --slice z=2 --slice z=3 --azimuth 35 --elevation 25 --zoom 2.5"
            else
                V=""
            fi
            for m in gumhold sigg mesh:3 mesh:4 mesh:5 mesh:6; do
                # shellcheck disable=SC2086
                "$TG" render "tests/data/sh/$f" $V --method "$m" --size 400x300 --frames 1 \
                    --reference-check --json -q -o "$tmp/x.png" >"$tmp/r.json"
                python3 - "$f" "$view" "$m" "$round" "$tmp/r.json" >>"$OUT" <<'PY'
import json, sys
f, view, m, rnd, path = sys.argv[1:]
j = json.load(open(path))
print(",".join([f, view, m, rnd] + [str(j[k]) for k in (
    "frame_ms", "covered_pixels", "coverage_mismatch", "id_mismatch",
    "depth_err_rel_p99", "normal_err_deg_p99")]))
PY
            done
        done
    done
done
rm -r "$tmp"
echo "wrote $OUT"
