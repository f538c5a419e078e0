#!/bin/sh
# The ambient-occlusion pictures of the book's "Figures" chapter: grid40 and DIPY's fit of its
# small_101D DWI (every slice, seen from above at an angle), each without and with --ao.
# Run from the repository's root: sh docs/images/make_ao_images.sh
# (TG names the binary; default: the debug build).
set -e
TG=${TG:-target/debug/tensorglyph}
"$TG" demo -o docs/images/ao_grid40_off.png --size 480x360 --ssaa 2 --zoom 1.6 --quiet
"$TG" demo -o docs/images/ao_grid40_on.png --size 480x360 --ssaa 2 --zoom 1.6 --ao 1 --quiet
F=tests/data/dti/dipy_small101/tensors.nii.gz
"$TG" render "$F" -o docs/images/ao_dti_off.png --slice all --view iso --elevation 20 --size 480x360 --ssaa 2 --quiet
"$TG" render "$F" -o docs/images/ao_dti_on.png --slice all --view iso --elevation 20 --size 480x360 --ssaa 2 --ao 1 --quiet
