# Shared by measure.sh and measure_thin.sh (sourced): the binary ($1, default
# target/release/tensorglyph), the issue's three views, and `row LABEL VIEW METHOD GLYPH ARGS…`,
# which prints one CSV row of `render ARGS --reference-check`.
set -euo pipefail
bin=${1:-target/release/tensorglyph}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
views=("default|" "zoom6|--zoom 6 --azimuth 17 --elevation -23" "ortho+x|--ortho --view +x")
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
