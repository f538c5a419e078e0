#!/bin/sh
# The ODF pictures of the book's "ODF glyphs" chapter: DIPY's CSD fit of small_64D (its middle
# slice, face-on: crossing fibres) and MRtrix's dwi2fod fit of the same voxels (every slice, at
# an angle, with shadows), the slice coloured by amplitude with its colour bar, and MRtrix's fit
# with the sticks of its peaks over its ODFs (--peaks).
# Run from the repository's root: sh docs/images/make_odf_images.sh
# (TG names the binary; default: the debug build).
set -e
TG=${TG:-target/debug/tensorglyph}
"$TG" render tests/data/sh/dipy_lmax8_descoteaux07_legacy.nii.gz -o docs/images/odf_dipy_slice.png --size 480x360 --ssaa 2 --quiet
"$TG" render tests/data/sh/mrtrix_lmax8.mif -o docs/images/odf_mrtrix_3d.png --slice z=0 --slice z=1 --slice z=2 --slice z=3 --azimuth 35 --elevation 25 --zoom 1.5 --size 480x360 --ssaa 2 --shadows --quiet
"$TG" render tests/data/sh/dipy_lmax8_descoteaux07_legacy.nii.gz -o docs/images/odf_dipy_amplitude.png --color amplitude --legend --size 640x360 --ssaa 2 --quiet
"$TG" render tests/data/sh/mrtrix_lmax8.mif -o docs/images/odf_peaks_mrtrix.png --peaks --elevation 30 --size 480x360 --ssaa 2 --quiet
