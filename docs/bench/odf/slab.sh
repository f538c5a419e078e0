#!/bin/sh
# ODF glyphs at whole-brain-slice scale (issue "Fibre ODFs at the cost of a tensor glyph"): the
# test fits of MRtrix dwi2fod (lmax 8 and 12), two axial slices tiled 25x25 into 100x100x2
# (tile_slice.py), the middle slice face-on at 1024x768: the exact frame, mesh:3's, and grid40's
# ellipsoids for the cost per covered pixel. Rounds interleaved; BASE names a second binary
# (the code before a change) measured in the same rounds. Writes slab.csv here: binary, scene,
# method, round, frame ms, scene ms, covered pixels, fragments per covered pixel.
# Run from the repository's root: sh docs/bench/odf/slab.sh
set -e
TG=${TG:-target/release/tensorglyph}
OUT=docs/bench/odf/slab.csv
tmp=$(mktemp -d)
python3 docs/bench/odf/tile_slice.py tests/data/sh/mrtrix_lmax8.mif "$tmp/slab8.mif" >/dev/null
python3 docs/bench/odf/tile_slice.py tests/data/sh/mrtrix_lmax12.mif.gz "$tmp/slab12.mif" >/dev/null
echo "binary,scene,method,round,frame_ms,scene_ms,covered_px,fragments_per_covered_px" >"$OUT"
for round in 1 2; do
    for bin in "$TG" ${BASE:+"$BASE"}; do
        for scene in slab8 slab12 grid40; do
            if [ "$scene" = grid40 ]; then
                IN="--demo grid40"
                METHODS="gumhold"
            else
                IN="$tmp/$scene.mif"
                METHODS="gumhold mesh:3"
            fi
            for m in $METHODS; do
                # shellcheck disable=SC2086
                "$bin" render $IN --method "$m" --size 1024x768 --frames 3 --json -q \
                    -o "$tmp/x.png" >"$tmp/r.json"
                python3 - "$bin" "$scene" "$m" "$round" "$tmp/r.json" >>"$OUT" <<'PY'
import json, sys
b, scene, m, rnd, path = sys.argv[1:]
j = json.load(open(path))
print(",".join([b, scene, m, rnd, "%.1f" % j["frame_ms"], "%.1f" % j["timings_ms"]["scene"],
                str(j["covered_pixels"]), "%.2f" % (j["fragments_per_covered_pixel"] or 0)]))
PY
            done
        done
    done
done
rm -r "$tmp"
cat "$OUT"
