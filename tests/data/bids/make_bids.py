#!/usr/bin/env python3
"""Writes a BIDS derivatives folder of diffusion tensors in BEP016 form, fitted by DIPY to the
real DWI sets DIPY ships, into `derivatives/` beside this script:

    pip install dipy nibabel numpy     (dipy 1.12)
    python3 tests/data/bids/make_bids.py

BEP016 (bids-standard/bids-bep016, `src/derivatives/05-diffusion-derivatives.md`) stores a tensor
fit as `sub-<label>[_ses-<label>]_model-DTI_param-tensor_dwimap.nii.gz`: six volumes Dxx, Dxy,
Dxz, Dyy, Dyz, Dzz (4-D, X×Y×Z×6) in µm²/ms, with one sidecar per model,
`…_model-DTI_dwimap.json`, whose REQUIRED `ReferenceAxes` says whether the tensor's axes are the
image's (`ijk`) or the scanner's (`xyz`), and `OrientationRepresentation` is `param`.

- `sub-01`: `small_101D` fitted by DIPY (WLS), tensors in the image axes (`ijk`);
- `sub-02`: the same tensors rotated to scanner axes, `D_xyz = R D_ijk Rᵀ` with R the rotation
  of the affine (its polar part): `xyz`. Read right, both give the same world tensors;
- `sub-03`: two sessions, `ses-1` fitted to `small_64D` and `ses-2` to `small_25` (`ijk`);
- `sub-04`: broken: its tensor file is cut short inside the gzip stream (the sidecar is fine);
- `sub-05`: `small_101D` fitted by MRtrix3's `dwi2tensor` (Debian's `mrtrix3` 3.0.3; IWLS),
  whose tensors are in scanner axes: `xyz` (written only where `dwi2tensor` is installed).

DIPY's gradient directions are FSL's bvecs: in the image axes when the affine's determinant is
negative (small_101D, small_64D), with x flipped when it is positive (small_25, as FSL stores
them); the script undoes that flip so that every `ijk` file is in the image axes as BEP016 says.

`expected.json` holds numpy's truth for each good file: the world principal eigenvector
(`numpy.linalg.eigh` of `R D_ijk Rᵀ`) and FA of every voxel (file order, x fastest), MD in
µm²/ms, and the FA/MD statistics a report states.
"""
import gzip
import json
import os
import shutil
import subprocess
import tempfile

import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.data import get_fnames
from dipy.io.gradients import read_bvals_bvecs
from dipy.reconst.dti import TensorModel, fractional_anisotropy

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "derivatives")
B0_THRESHOLD = 50.0
# mm²/s (what DIPY fits in, with b in s/mm²) to BEP016's µm²/ms.
TO_UM2_PER_MS = 1000.0


def fit(name):
    """DIPY's WLS tensors of a shipped DWI set, in the image axes, µm²/ms, (X, Y, Z, 3, 3)."""
    fdata, fbval, fbvec = get_fnames(name=name)
    img = nib.load(fdata)
    bvals, bvecs = read_bvals_bvecs(str(fbval), str(fbvec))
    gtab = gradient_table(bvals, bvecs=bvecs, b0_threshold=B0_THRESHOLD)
    data = np.asarray(img.dataobj, dtype=np.float64)
    d = TensorModel(gtab, fit_method="WLS").fit(data).quadratic_form
    if np.linalg.det(img.affine[:3, :3]) > 0:
        f = np.diag([-1.0, 1.0, 1.0])
        d = f @ d @ f
    return img.affine, d * TO_UM2_PER_MS


def mrtrix_fit(name):
    """MRtrix3's tensors of a shipped DWI set (scanner axes), µm²/ms, with the image's affine;
    None without dwi2tensor."""
    if shutil.which("dwi2tensor") is None:
        return None
    fdata, fbval, fbvec = get_fnames(name=name)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "dt.nii")
        subprocess.run(
            ["dwi2tensor", "-quiet", "-fslgrad", str(fbvec), str(fbval), str(fdata), out],
            check=True,
        )
        img = nib.load(out)
        v = np.asarray(img.dataobj, dtype=np.float64)  # D11 D22 D33 D12 D13 D23
        d = np.zeros(v.shape[:3] + (3, 3))
        for c, (i, j) in enumerate([(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]):
            d[..., i, j] = v[..., c]
            d[..., j, i] = v[..., c]
        return img.affine, d * TO_UM2_PER_MS


def rotation(affine):
    """The rotation (or reflection) part of the affine's linear part."""
    u, _, vt = np.linalg.svd(affine[:3, :3])
    return u @ vt


def six(d):
    """Dxx, Dxy, Dxz, Dyy, Dyz, Dzz as the last axis."""
    return np.stack(
        [d[..., 0, 0], d[..., 0, 1], d[..., 0, 2], d[..., 1, 1], d[..., 1, 2], d[..., 2, 2]],
        axis=-1,
    ).astype(np.float32)


DIPY_FIT = ("Diffusion tensor fitted by DIPY (WLS) to a DWI set DIPY ships", "wls")
MRTRIX_FIT = ("Diffusion tensor fitted by MRtrix3 dwi2tensor (IWLS) to a DWI set DIPY ships", "iwls")


def write(folder, stem, affine, tensors, axes, by=DIPY_FIT):
    os.makedirs(folder, exist_ok=True)
    img = nib.Nifti1Image(six(tensors), affine)
    img.header.set_xyzt_units("mm")
    path = os.path.join(folder, f"{stem}_model-DTI_param-tensor_dwimap.nii.gz")
    nib.save(img, path)
    sidecar = {
        "Description": by[0],
        "OrientationRepresentation": "param",
        "ReferenceAxes": axes,
        "Parameters": {"FitMethod": by[1], "OutlierRejection": False},
    }
    with open(os.path.join(folder, f"{stem}_model-DTI_dwimap.json"), "w") as f:
        json.dump(sidecar, f, indent=2)
        f.write("\n")
    return path


def truth(affine, d_ijk, world=None):
    """numpy's world tensors' principal eigenvectors, FA and MD, voxels in file order."""
    if world is None:
        r = rotation(affine)
        world = r @ d_ijk @ r.T
    n = int(np.prod(world.shape[:3]))
    flat = world.transpose(2, 1, 0, 3, 4).reshape(n, 3, 3)
    # The file holds float32: the truth is of what is stored.
    flat = flat.astype(np.float32).astype(np.float64)
    w, v = np.linalg.eigh(flat)
    w = w[:, ::-1]
    e1 = v[:, :, 2]
    fa = np.nan_to_num(fractional_anisotropy(w))
    md = w.mean(axis=1)
    return {
        "dims": list(world.shape[:3]),
        "e1_world": e1.tolist(),
        "fa": fa.tolist(),
        "md": md.tolist(),
        "fa_mean": float(fa.mean()),
        "md_mean": float(md.mean()),
    }


def main():
    if os.path.isdir(OUT):
        shutil.rmtree(OUT)
    os.makedirs(OUT)
    with open(os.path.join(OUT, "dataset_description.json"), "w") as f:
        json.dump(
            {
                "Name": "DIPY's small DWI sets fitted with DIPY's tensor model (BEP016)",
                "BIDSVersion": "1.10.0",
                "DatasetType": "derivative",
                "GeneratedBy": [{"Name": "dipy", "Version": __import__("dipy").__version__}],
            },
            f,
            indent=2,
        )
        f.write("\n")
    expected = {}
    a101, d101 = fit("small_101D")
    p = write(os.path.join(OUT, "sub-01", "dwi"), "sub-01", a101, d101, "ijk")
    expected[os.path.relpath(p, OUT)] = truth(a101, d101)
    r = rotation(a101)
    p = write(os.path.join(OUT, "sub-02", "dwi"), "sub-02", a101, r @ d101 @ r.T, "xyz")
    expected[os.path.relpath(p, OUT)] = truth(a101, d101)
    for ses, name in [("1", "small_64D"), ("2", "small_25")]:
        a, d = fit(name)
        folder = os.path.join(OUT, "sub-03", f"ses-{ses}", "dwi")
        p = write(folder, f"sub-03_ses-{ses}", a, d, "ijk")
        expected[os.path.relpath(p, OUT)] = truth(a, d)
    p = write(os.path.join(OUT, "sub-04", "dwi"), "sub-04", a101, d101, "ijk")
    with open(p, "rb") as f:
        whole = f.read()
    assert gzip.decompress(whole)
    with open(p, "wb") as f:
        f.write(whole[: len(whole) // 2])
    mrtrix = mrtrix_fit("small_101D")
    if mrtrix is None:
        print("dwi2tensor not found: no MRtrix3 fit (sub-05)")
    else:
        a, world = mrtrix
        p = write(os.path.join(OUT, "sub-05", "dwi"), "sub-05", a, world, "xyz", MRTRIX_FIT)
        expected[os.path.relpath(p, OUT)] = truth(a, None, world)
    with open(os.path.join(HERE, "expected.json"), "w") as f:
        json.dump(expected, f)
        f.write("\n")
    print(f"{len(expected)} good tensor files and one broken under {OUT}")


if __name__ == "__main__":
    main()
