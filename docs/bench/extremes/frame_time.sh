#!/bin/bash
# grid40's frame at 1024x768 by two builds of tensorglyph, interleaved (BEFORE AFTER alternate
# ROUNDS times; each run the median of 5 frames): the ratio AFTER/BEFORE per method and glyph.
# Usage: frame_time.sh BEFORE AFTER [ROUNDS]   (run from the repository root)
# SCENE (default "--demo grid40") names another scene, e.g. the needles at k = 1e5, every chunk
# of them thin: SCENE="tests/data/extremes/needle_field_1e5.vtk --scale 0.8 --min-radius 0".
set -euo pipefail
before=$1 after=$2 rounds=${3:-3}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
scene=${SCENE:---demo grid40}
# shellcheck disable=SC2086
ms() { "$1" render $scene -o "$out/x.png" --frames 5 --json "${@:2}" 2>/dev/null |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["frame_ms"])'; }
echo "config,before_ms,after_ms,ratio"
for cfg in "--method gumhold" "--method gumhold --preset baseline" "--method sigg" "--method gumhold --glyph cylinder" "--method sigg --glyph cylinder"; do
    b=() a=()
    for _ in $(seq "$rounds"); do
        # shellcheck disable=SC2086
        b+=("$(ms "$before" $cfg)")
        # shellcheck disable=SC2086
        a+=("$(ms "$after" $cfg)")
    done
    python3 -c '
import statistics, sys
n = int(sys.argv[2]); v = list(map(float, sys.argv[3:]))
b, a = statistics.median(v[:n]), statistics.median(v[n:])
print("%s,%.1f,%.1f,%.3f" % (sys.argv[1], b, a, a / b))' "$cfg" "$rounds" "${b[@]}" "${a[@]}"
done
