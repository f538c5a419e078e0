#!/bin/sh
# MRtrix's sh2peaks of the CSD fit in this folder (Debian's mrtrix3 3.0.3): the three largest
# peaks of each voxel, 3 values each (9 volumes, NaN where a voxel has fewer), as pipelines keep
# them. The header's command_history ends with the sh2peaks line that names what the image is.
# Run from this folder: sh make_peaks.sh
set -e
sh2peaks mrtrix_lmax8.mif sh2peaks_lmax8.mif -num 3 -force -quiet
# The same peaks converted to NIfTI, as pipelines keep them (TractSeg, TractoFlow): 9 volumes,
# and nothing in a NIfTI header says they are peaks (--holds peaks does). MRtrix's `descrip`
# says who wrote it, so its directions are read in scanner axes, as sh2peaks wrote them.
mrconvert sh2peaks_lmax8.mif sh2peaks_lmax8.nii.gz -force -quiet
