#!/usr/bin/env python3
"""Fits DIPY's tensor model to real diffusion data and writes what DIPY's own `dipy_fit_dti`
workflow writes, plus scalar volumes and masks beside it, into `dipy_small101/`:

    pip install dipy nibabel numpy     (dipy 1.12)
    python3 tests/data/dti/make_dipy_fit.py

Source: `small_101D.nii.gz` (+ .bval, .bvec), 6x10x10 voxels of real DWI shipped with DIPY
(`dipy.data.get_fnames(name="small_101D")`; 101 gradient directions and one b0).

- `tensors.nii.gz`, `fa.nii.gz`: written by DIPY's `ReconstDtiFlow` itself (the workflow
  behind `dipy_fit_dti`; WLS fit, `nifti_tensor=True`): the tensor as a 5-D X×Y×Z×1×6 volume of
  `lower_triangular` values (xx xy yy xz yz zz) with intent SYMMATRIX (`nifti1_symmat`). DIPY
  1.12 writes it in float64 (the FA map in float32). The workflow is given a mask of every
  voxel (its command line needs one), so every voxel is fitted.
- `b0.nii.gz`: the mean of the b0 volumes (b <= 50, the workflow's threshold), float32.
- `mask.nii.gz`: uint8, 1 where DIPY's FA > 0.3, on the tensors' lattice.
- `mask_coarse.nii.gz`: float32 on another lattice (axis-aligned 4 mm voxels, shifted, not
  covering the whole tensor volume), holding zeros, non-zero values, NaN and +inf.

All volumes carry the source's affine (sform and its code as DIPY and nibabel write them)
except `mask_coarse.nii.gz`, which has its own.

`expected.json` holds numpy's truth, voxels in file order (x fastest):
- `eigenvalues`: `numpy.linalg.eigh` of the stored tensors, in float64, descending;
- `fa`: DIPY's `fractional_anisotropy` of those eigenvalues (float64);
- `fa_file`, `b0_file`: the values nibabel reads from `fa.nii.gz` and `b0.nii.gz`;
- `affine`: the tensor file's voxel-to-world matrix as nibabel reads it;
- `mask_kept`, `mask_coarse_kept`: the voxels each mask keeps, by numpy's own nearest-voxel
  rule: the world position taken into the mask's voxel space by the inverse of its affine,
  rounded half up, kept when inside the mask and its value is non-zero and finite.
"""
import json
import os
import shutil
import tempfile

import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.data import get_fnames
from dipy.io.gradients import read_bvals_bvecs
from dipy.io.image import save_nifti
from dipy.reconst.dti import fractional_anisotropy
from dipy.workflows.reconst import ReconstDtiFlow

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dipy_small101")
B0_THRESHOLD = 50.0


def flat(a):
    """A volume's values in file order (x fastest)."""
    return np.asarray(a).reshape(-1, order="F")


def nearest_kept(mask_img, positions):
    """File-order indices of `positions` whose nearest voxel of `mask_img` is non-zero and
    finite; none at a rounding tie (the script fails rather than guess)."""
    inv = np.linalg.inv(mask_img.affine)
    data = np.asarray(mask_img.dataobj, dtype=np.float64)
    v = (inv @ np.c_[positions, np.ones(len(positions))].T).T[:, :3]
    frac = v - np.floor(v)
    assert np.abs(frac - 0.5).min() > 1e-6, "a position is half-way between mask voxels"
    r = np.floor(v + 0.5).astype(int)
    inside = np.all((r >= 0) & (r < np.array(data.shape[:3])), axis=1)
    kept = []
    for n in np.nonzero(inside)[0]:
        x = data[tuple(r[n])]
        if np.isfinite(x) and x != 0:
            kept.append(int(n))
    return kept, int((~inside).sum())


def main():
    os.makedirs(HERE, exist_ok=True)
    fdata, fbval, fbvec = get_fnames(name="small_101D")
    src = nib.load(fdata)
    affine = src.affine
    dims = src.shape[:3]

    with tempfile.TemporaryDirectory() as tmp:
        every = os.path.join(tmp, "every_voxel.nii.gz")
        nib.save(nib.Nifti1Image(np.ones(dims, np.uint8), affine), every)
        out = os.path.join(tmp, "out")
        ReconstDtiFlow(force=True).run(
            fdata,
            fbval,
            fbvec,
            every,
            b0_threshold=B0_THRESHOLD,
            save_metrics=["tensor", "fa"],
            nifti_tensor=True,
            out_dir=out,
        )
        for name in ["tensors.nii.gz", "fa.nii.gz"]:
            shutil.copyfile(os.path.join(out, name), os.path.join(HERE, name))

    bvals, bvecs = read_bvals_bvecs(fbval, fbvec)
    gtab = gradient_table(bvals, bvecs=bvecs, b0_threshold=B0_THRESHOLD)
    b0 = src.get_fdata()[..., gtab.b0s_mask].mean(axis=-1).astype(np.float32)
    save_nifti(os.path.join(HERE, "b0.nii.gz"), b0, affine)

    ten = nib.load(os.path.join(HERE, "tensors.nii.gz"))
    assert ten.shape == dims + (1, 6), ten.shape
    assert int(ten.header["intent_code"]) == 1005
    low = np.asarray(ten.dataobj)[:, :, :, 0, :]  # xx xy yy xz yz zz, as stored
    n = int(np.prod(dims))
    low = low.reshape(n, 6, order="F").astype(np.float64)
    d = np.zeros((n, 3, 3))
    for c, (i, j) in enumerate([(0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (2, 2)]):
        d[:, i, j] = low[:, c]
        d[:, j, i] = low[:, c]
    w = np.linalg.eigh(d)[0][:, ::-1]
    fa = fractional_anisotropy(w)

    fa_img = nib.load(os.path.join(HERE, "fa.nii.gz"))
    fa_file = flat(np.asarray(fa_img.dataobj, dtype=np.float64))
    b0_file = flat(np.asarray(nib.load(os.path.join(HERE, "b0.nii.gz")).dataobj, np.float64))

    ijk = np.array([[i, j, k] for k in range(dims[2]) for j in range(dims[1]) for i in range(dims[0])])
    pos = (ten.affine @ np.c_[ijk, np.ones(n)].T).T[:, :3]

    mask = (np.asarray(fa_img.dataobj) > 0.3).astype(np.uint8)
    save_nifti(os.path.join(HERE, "mask.nii.gz"), mask, affine)
    mask_img = nib.load(os.path.join(HERE, "mask.nii.gz"))
    mask_kept, mask_out = nearest_kept(mask_img, pos)
    assert mask_out == 0 and 0 < len(mask_kept) < n
    assert mask_kept == [int(v) for v in np.nonzero(flat(mask))[0]]

    # Coarser, shifted and axis-aligned (the tensors' lattice is slightly oblique), and
    # smaller than the tensors' extent along y, so that some glyphs fall outside it.
    lo = pos.min(axis=0)
    hi = pos.max(axis=0)
    coarse_affine = np.diag([4.0, 4.0, 4.0, 1.0])
    coarse_affine[:3, 3] = lo + np.array([1.3, 5.1, 0.7])
    cdims = tuple(int(x) for x in np.ceil((hi - lo) / 4.0) + 1)
    cdims = (cdims[0], cdims[1] - 2, cdims[2])
    ci = np.indices(cdims)
    pattern = (ci[0] + 2 * ci[1] + 3 * ci[2]) % 4
    coarse = np.choose(pattern, [0.0, 1.0, -2.5, np.nan]).astype(np.float32)
    coarse[0, 0, 0] = np.inf
    coarse_img = nib.Nifti1Image(coarse, coarse_affine)
    nib.save(coarse_img, os.path.join(HERE, "mask_coarse.nii.gz"))
    coarse_kept, coarse_out = nearest_kept(nib.load(os.path.join(HERE, "mask_coarse.nii.gz")), pos)
    assert coarse_out > 0 and 0 < len(coarse_kept) < n - coarse_out

    expected = {
        "dims": list(dims),
        "affine": ten.affine.tolist(),
        "eigenvalues": w.tolist(),
        "fa": fa.tolist(),
        "fa_file": fa_file.tolist(),
        "b0_file": b0_file.tolist(),
        "mask_kept": mask_kept,
        "mask_coarse_kept": coarse_kept,
        "mask_coarse_outside": coarse_out,
    }
    with open(os.path.join(HERE, "expected.json"), "w") as f:
        json.dump(expected, f)
        f.write("\n")
    print(f"{n} voxels; mask keeps {len(mask_kept)}, coarse mask {len(coarse_kept)} "
          f"({coarse_out} outside it)")


if __name__ == "__main__":
    main()
