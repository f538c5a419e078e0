"""A whole-brain-sized FOD volume for timing `report` on ODF maps (issue: "Pipelines, second
step"): MRtrix's dwi2fod fit of DIPY's small_64D in this folder (4×4×4 voxels, lmax 8,
`mrtrix_lmax8.nii.gz`) tiled 25×30×25 times into 100×120×100 voxels (about a 2 mm brain's
lattice), zeroed outside the ellipsoid that fills the lattice (as a CSD fit writes zeros outside
its mask), written as float32 with the fit's 2 mm-scaled affine.

    python3 tests/data/sh/make_fod_brain.py OUT.nii.gz
"""

import sys
from pathlib import Path

import nibabel as nib
import numpy as np


def main(out: str) -> None:
    fit = nib.load(Path(__file__).with_name("mrtrix_lmax8.nii.gz"))
    tile = np.asarray(fit.dataobj, dtype=np.float32)
    reps = (25, 30, 25)
    data = np.tile(tile, reps + (1,))
    shape = np.array(data.shape[:3])
    ijk = np.indices(tuple(shape)).reshape(3, -1).T
    centre = (shape - 1) / 2.0
    inside = (((ijk - centre) / (shape / 2.0)) ** 2).sum(axis=1) <= 1.0
    data.reshape(-1, data.shape[3])[~inside] = 0.0
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    affine[:3, 3] = -centre * 2.0
    img = nib.Nifti1Image(data, affine)
    img.header.set_xyzt_units("mm")
    nib.save(img, out)


if __name__ == "__main__":
    main(sys.argv[1])
