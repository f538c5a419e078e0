#!/usr/bin/env bash
# Build the Python package's wheel for this Linux machine's architecture: abi3 (one wheel for
# CPython 3.9 and later) and manylinux_2_28 (glibc 2.28: RHEL/Rocky/Alma 8 and every newer
# distribution), checked by auditwheel. Installing it needs no Rust.
#
#   bash python/build-wheel.sh [--release] [OUT_DIR]      (OUT_DIR: target/wheels)
#
# The dev profile unless --release: CI builds and tests the dev wheel, whose dependencies are
# the ones `cargo test` compiled (the same profile and features, see python/Cargo.toml), so
# only the extension itself is compiled and linked. The wheels to hand out are --release.
#
# glibc 2.28 without an old system or a container: the extension's final link goes through
# zig (`maturin zig cc`, zig from PyPI's ziglang), which links against glibc 2.28's symbol
# versions. Only that link: rustc's `-C linker` for the last crate. maturin's own --zig names
# the target triple, which puts every dependency into a second target folder and compiles it
# again. The tools (maturin, ziglang, auditwheel; versions pinned below) go into
# target/tools/wheel-venv, so a clean clone installs them itself.
set -euo pipefail
cd "$(dirname "$0")/.."

profile=dev
if [ "${1:-}" = "--release" ]; then
    profile=release
    shift
fi
out="$(mkdir -p "${1:-target/wheels}" && cd "${1:-target/wheels}" && pwd)"

MATURIN=1.16.0 ZIGLANG=0.15.2 AUDITWHEEL=6.8.2
venv="$PWD/target/tools/wheel-venv"
if [ "$("$venv/bin/maturin" --version 2>/dev/null)" != "maturin $MATURIN" ] ||
    ! "$venv/bin/python" -c "import ziglang, auditwheel" 2>/dev/null; then
    rm -rf "$venv"
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q "maturin==$MATURIN" "ziglang==$ZIGLANG" "auditwheel==$AUDITWHEEL" || {
        echo "error: cannot install maturin $MATURIN, ziglang $ZIGLANG and auditwheel $AUDITWHEEL from PyPI into $venv" >&2
        exit 1
    }
fi

arch="$(uname -m)"
glibc=2.28
linker="$PWD/target/tools/zig-cc-$arch-$glibc"
# maturin's zig wrapper finds zig through the venv's python (python -m ziglang).
cat >"$linker" <<EOF
#!/bin/sh
PATH="$venv/bin:\$PATH" exec "$venv/bin/maturin" zig cc -- -target $arch-linux-gnu.$glibc "\$@"
EOF
chmod +x "$linker"

rm -f "$out"/tensorglyph-*-cp39-abi3-*.whl
PATH="$venv/bin:$PATH" maturin build -m python/Cargo.toml --profile "$profile" \
    --compatibility "manylinux_${glibc//./_}" --out "$out" -- -C linker="$linker"
wheel="$(ls "$out"/tensorglyph-*-cp39-abi3-manylinux_*"$arch".whl)"

# auditwheel's own reading of the extension's symbol versions and libraries.
audit="$("$venv/bin/auditwheel" show "$wheel")"
if ! grep -q "manylinux_${glibc//./_}_$arch" <<<"$audit"; then
    echo "$audit" >&2
    echo "error: auditwheel does not find $(basename "$wheel") consistent with manylinux_${glibc//./_}_$arch" >&2
    exit 1
fi
echo "$wheel ($(du -h "$wheel" | cut -f1), $profile, manylinux_${glibc//./_}_$arch by auditwheel)" >&2
echo "$wheel"
