#!/usr/bin/env bash
# Build the viewer for the browser (WebGPU) into web/dist/: index.html, the wasm and its JS glue,
# a static site with nothing fetched from elsewhere. Serve it with any static server, e.g.
#   python3 -m http.server -d web/dist 8000
# and open http://127.0.0.1:8000/?demo=grid40.
#
# Needs: rustup's wasm32-unknown-unknown target and wasm-bindgen-cli at exactly the version of the
# wasm-bindgen crate in Cargo.lock, both installed here when missing (the CLI into target/tools by
# .ci/install-tool, so a clean clone always installs it).
set -euo pipefail
cd "$(dirname "$0")/.."

target=wasm32-unknown-unknown
profile=web-release
out=web/dist

if ! rustup target list --installed | grep -qx "$target"; then
    rustup target add "$target"
fi

# The CLI must match the crate it generates glue for, to the patch version.
want="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)"
wasm_bindgen="$(.ci/install-tool wasm-bindgen-cli "$want" wasm-bindgen)"

cargo build -p tensorglyph-web --target "$target" --profile "$profile"

rm -rf "$out"
mkdir -p "$out"
"$wasm_bindgen" --target web --no-typescript --out-dir "$out" \
    "target/$target/$profile/tensorglyph_web.wasm"

# No wasm-opt: Debian's binaryen (bookworm) shrinks the module by about a sixth but breaks
# wasm-bindgen's function table ("WebAssembly.Table.set(): Argument 1 is invalid"), so the page
# would not start.

cp web/index.html "$out/"
bytes="$(wc -c <"$out/tensorglyph_web_bg.wasm")"
echo "web/dist: $(du -sh "$out" | cut -f1) (the wasm: $bytes bytes)"
