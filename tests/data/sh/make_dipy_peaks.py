#!/usr/bin/env python3
"""Writes DIPY's peaks of the DIPY fit in this folder as DIPY saves them, and what they hold:

    pip install dipy nibabel numpy     (DIPY 1.12)
    python3 tests/data/sh/make_dipy_peaks.py

The fit: `dipy_lmax8_descoteaux07_legacy.nii.gz` (make_sh.py; 4×4×4 voxels, an oblique lattice
with a negative determinant). Each voxel's ODF is DIPY's `sh_to_sf` of its coefficients on
`repulsion724`, and its peaks DIPY's `peak_directions` (`relative_peak_threshold=0.5`,
`min_separation_angle=25`), at most 5 (the workflows' `npeaks`): unit directions in the voxel
axes, as DIPY finds them, their ODF values, zero where a voxel has fewer. Saved by DIPY's
`pam_to_niftis` from `niftis_to_pam`, as `dipy_fit_csd` saves them:

- `dipy_peaks_dirs.nii.gz` (`reshape_dirs=True`, the workflows' choice: 4-D, 3 values a peak,
  15 volumes, float32) and `dipy_peaks_values.nii.gz` (4-D, 5 volumes);
- `dipy5d_peak_dirs.nii.gz` (`reshape_dirs=False`: 5-D, X×Y×Z×5×3, as `peak_dirs` is held) and
  `dipy5d_peak_values.nii.gz`.

The truth, `dipy_peaks.json`, is read back from the files written (nibabel): per voxel its world
position (the affine), and its peaks as DIPY stored them (voxel axes, unit) with their values,
and turned into world axes by the rotation of the affine's linear part (numpy's SVD, U Vᵀ:
voxel sizes removed, the reflection of a negative determinant kept).
"""

import json
import os
import shutil
import tempfile

import nibabel as nib
import numpy as np
from dipy.data import get_sphere
from dipy.direction.peaks import peak_directions
from dipy.io.peaks import niftis_to_pam, pam_to_niftis
from dipy.reconst.shm import sh_to_sf

HERE = os.path.dirname(os.path.abspath(__file__))
NPEAKS = 5


def out(name):
    return os.path.join(HERE, name)


def main():
    img = nib.load(out("dipy_lmax8_descoteaux07_legacy.nii.gz"))
    coeffs = np.asarray(img.dataobj, dtype=np.float64)
    affine = img.affine
    sphere = get_sphere(name="repulsion724")
    odf = sh_to_sf(coeffs, sphere, sh_order_max=8, basis_type="descoteaux07", legacy=True)
    shape = coeffs.shape[:3]
    dirs = np.zeros(shape + (NPEAKS, 3))
    values = np.zeros(shape + (NPEAKS,))
    indices = np.full(shape + (NPEAKS,), -1, dtype=np.int32)
    for ijk in np.ndindex(shape):
        d, v, i = peak_directions(
            odf[ijk], sphere, relative_peak_threshold=0.5, min_separation_angle=25
        )
        n = min(len(v), NPEAKS)
        dirs[ijk][:n] = d[:n]
        values[ijk][:n] = v[:n]
        indices[ijk][:n] = i[:n]
    pam = niftis_to_pam(affine, dirs, values, indices, sphere=sphere)
    tmp = tempfile.mkdtemp()
    try:
        for reshape, d_name, v_name in [
            (True, "dipy_peaks_dirs.nii.gz", "dipy_peaks_values.nii.gz"),
            (False, "dipy5d_peak_dirs.nii.gz", "dipy5d_peak_values.nii.gz"),
        ]:
            pam_to_niftis(
                pam,
                fname_peaks_dir=out(d_name),
                fname_peaks_values=out(v_name),
                fname_peaks_indices=os.path.join(tmp, "indices.nii.gz"),
                fname_sphere=os.path.join(tmp, "sphere.txt"),
                reshape_dirs=reshape,
            )
    finally:
        shutil.rmtree(tmp)

    # The truth, from the files as written.
    d4 = nib.load(out("dipy_peaks_dirs.nii.gz"))
    stored = np.asarray(d4.dataobj, dtype=np.float64).reshape(shape + (NPEAKS, 3))
    d5 = np.asarray(nib.load(out("dipy5d_peak_dirs.nii.gz")).dataobj, dtype=np.float64)
    assert np.array_equal(stored, d5), "the two layouts hold the same peaks"
    vals = np.asarray(nib.load(out("dipy_peaks_values.nii.gz")).dataobj, dtype=np.float64)
    u, _, vt = np.linalg.svd(d4.affine[:3, :3])
    rotation = u @ vt
    voxels = {}
    for ijk in np.ndindex(shape):
        kept = [p for p in range(NPEAKS) if np.any(stored[ijk][p] != 0)]
        voxels[",".join(map(str, ijk))] = {
            "position": (d4.affine @ np.array([*ijk, 1.0]))[:3].tolist(),
            "voxel_axes": [stored[ijk][p].tolist() for p in kept],
            "world": [(rotation @ stored[ijk][p]).tolist() for p in kept],
            "values": [float(vals[ijk][p]) for p in kept],
        }
    truth = {
        "source": "DIPY peak_directions of dipy_lmax8_descoteaux07_legacy.nii.gz, saved by "
        "pam_to_niftis; read back with nibabel",
        "npeaks": NPEAKS,
        "voxels": voxels,
    }
    with open(out("dipy_peaks.json"), "w") as f:
        json.dump(truth, f, indent=1)


if __name__ == "__main__":
    main()
