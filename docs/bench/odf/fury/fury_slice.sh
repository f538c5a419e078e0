#!/usr/bin/env bash
# FURY 2.1 (fury.actor.sph_glyph, sphere meshes deformed by a compute shader) against
# tensorglyph's exact ray-cast ODF glyphs (--method gumhold) on the same axial slice of 10x10 = 100
# real fibre ODFs (tests/data/sh/mrtrix_lmax8.mif, lmax 8, tiled; see fury_slice.py), 1024x768,
# the slice face-on, on whatever adapter wgpu finds (here lavapipe).
#
# Runs ROUNDS interleaved rounds, each one process per tool and setting:
#   tensorglyph   $TG render SLICE.mif --method gumhold --view -z ...  (median of FRAMES)
#   fury-noaa     fury_slice.py --aa noaa     (pixel_ratio 1, ppaa none)        (median of FRAMES)
#   fury-default  fury_slice.py --aa default  (FURY/pygfx defaults: 2x2 SSAA + DDAA)
# and writes fury_slice.csv (round, tool, frame_ms, whole_process_s; frame_ms is each tool's
# median submit -> device idle, whole_process_s the process's wall time, start to exit) and
# fury_slice_runs.jsonl (every run's full JSON), and round 1's images as PNGs
# (fury_slice_tensorglyph.png, fury_slice_fury_noaa.png; FURY's default-AA image, rendered at
# 2048x1536, is not kept).
# The machine may be busy with other work: compare the tools within a round (the printed ratios).
#
# usage (from anywhere): docs/bench/odf/fury/fury_slice.sh
#   env: ROUNDS (3), FRAMES (5), TG (target/release/tensorglyph), FURY_PY (/tmp/furyenv/bin/python; a Python
#   3.12 venv with fury==2.1.0 dipy==1.12.1, see fury_slice.py)
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../../.." && pwd)"
ROUNDS="${ROUNDS:-3}"
FRAMES="${FRAMES:-5}"
TG="${TG:-$ROOT/target/release/tensorglyph}"
FURY_PY="${FURY_PY:-/tmp/furyenv/bin/python}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/xdg}"
mkdir -p "$XDG_RUNTIME_DIR"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
CSV="$HERE/fury_slice.csv"
JSONL="$HERE/fury_slice_runs.jsonl"

"$FURY_PY" "$HERE/fury_slice.py" --mif "$ROOT/tests/data/sh/mrtrix_lmax8.mif" \
  --write-mif "$WORK/slice10.mif"
echo "round,tool,frame_ms,whole_process_s" > "$CSV"
: > "$JSONL"

now() { date +%s.%N; }

run() { # round tool command...: runs it, appends the CSV row and the JSON line
  local round="$1" tool="$2"; shift 2
  local t0 t1 out ms
  t0="$(now)"
  out="$("$@")"
  t1="$(now)"
  ms="$(printf '%s' "$out" | python3 -c '
import json, sys
d = json.loads(sys.stdin.read())
print("%.2f" % (d["frame_ms"] if "frame_ms" in d else d["runs"][0]["frame_ms"]))')"
  printf '%s,%s,%s,%.2f\n' "$round" "$tool" "$ms" "$(echo "$t1 - $t0" | bc -l)" >> "$CSV"
  printf '{"round": %s, "tool": "%s", "out": %s}\n' "$round" "$tool" "$out" >> "$JSONL"
  echo "round $round $tool: frame $ms ms, whole process $(echo "$t1 - $t0" | bc -l | cut -c1-6) s" >&2
}

for r in $(seq 1 "$ROUNDS"); do
  tgpng="$WORK/tg.png"; fnpng="$WORK/fn.png"; fdpng="$WORK/fd.png"
  if [ "$r" = 1 ]; then
    tgpng="$HERE/fury_slice_tensorglyph.png"
    fnpng="$HERE/fury_slice_fury_noaa.png"
  fi
  run "$r" tensorglyph "$TG" render "$WORK/slice10.mif" --method gumhold --size 1024x768 \
    --view=-z --background white --frames "$FRAMES" --json -q -o "$tgpng"
  run "$r" fury-noaa "$FURY_PY" "$HERE/fury_slice.py" --aa noaa --frames "$FRAMES" --json \
    --png "$fnpng" $([ "$r" = 1 ] && echo --check)
  run "$r" fury-default "$FURY_PY" "$HERE/fury_slice.py" --aa default --frames "$FRAMES" \
    --json --png "$fdpng"
done

python3 - "$CSV" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {}
for r in rows:
    by.setdefault(r["round"], {})[r["tool"]] = r
print("round  tg_ms  fury_noaa_ms  fury_default_ms  tg/fury_noaa  tg/fury_default  "
      "whole_s tg/noaa/default")
for k, v in by.items():
    tg, fn, fd = (float(v[t]["frame_ms"]) for t in ("tensorglyph", "fury-noaa", "fury-default"))
    w = "/".join(v[t]["whole_process_s"] for t in ("tensorglyph", "fury-noaa", "fury-default"))
    print("%5s %6.1f %13.1f %16.1f %13.2f %16.3f  %s" % (k, tg, fn, fd, tg / fn, tg / fd, w))
EOF
