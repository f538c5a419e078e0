#!/bin/sh
# The images of the book's "Stress and strain" chapter: the twisted cantilever of
# tests/data/stress/ (scikit-fem, P1 tetrahedra) with each glyph kind, at the defaults.
# Run from the repository's root: sh docs/images/make_stress_images.sh
# (TG names the binary; default: the debug build).
set -e
TG=${TG:-target/debug/tensorglyph}
F=tests/data/stress/cantilever_twist.vtu
for kind in ellipsoid cylinder capsule superquadric principal; do
    "$TG" render "$F" -o "docs/images/stress_$kind.png" --glyph "$kind" \
        --size 600x400 --ssaa 2 --legend --quiet
done
"$TG" render "$F" -o docs/images/stress_principal_arrows.png --glyph principal --arrows \
    --size 600x400 --ssaa 2 --legend --quiet
