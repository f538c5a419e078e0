#!/usr/bin/env python3
"""Writes the spherical-harmonic (SH) coefficient files in this folder with DIPY and MRtrix3,
and `expected.json`, what DIPY and MRtrix compute from each file:

    apt-get install mrtrix3            (Debian's 3.0.3: dwi2response, dwi2fod, sh2amp, sh2peaks)
    pip install dipy nibabel numpy     (DIPY 1.12 ships the small_64D DWI set)
    python3 tests/data/sh/make_sh.py

The data: DIPY's small_64D (10×10×10 voxels, b=1000, 64 directions, an oblique lattice with a
negative determinant). Constrained spherical deconvolution (CSD) is fitted to the whole set's
response and to a 4×4×4 block of it (voxels 3..6 along each axis), which keeps each file a few
tens of kB:

- `dipy_lmax8_descoteaux07_legacy.nii.gz`: DIPY's `ConstrainedSphericalDeconvModel` (response
  from `auto_response_ssst`), its `shm_coeff` saved as nibabel saves it, float64: DIPY's
  default basis, descoteaux07 with `legacy=True`;
- `dipy_lmax8_descoteaux07.nii.gz`: the same coefficients in the non-legacy descoteaux07 basis
  (DIPY's `convert_sh_from_legacy`);
- `dipy_lmax8_tournier07.nii.gz`: DIPY's `convert_sh_descoteaux_tournier` of the non-legacy
  ones: a DIPY-written tournier07 file, whose basis only the user can name (`--sh-basis
  tournier07`). (DIPY 1.12's conversion swaps m and −m without the Condon–Shortley sign, so
  its odd m > 0 coefficients come out negated: under DIPY's own `sh_to_sf` this file is
  another function than the other two. Its truth is DIPY's evaluation of what it holds.)
- `dipy_lmax12_descoteaux07_legacy_f32.nii.gz`: a lmax 12 fit (91 volumes), saved as float32;
- `mrtrix_lmax8.mif`: `dwi2fod csd` (response from `dwi2response tournier` on the whole set,
  the DWI given to MRtrix with `-fslgrad`), as MRtrix writes it (float32, tournier07, directions
  in scanner axes), and `mrtrix_lmax8.nii.gz`, its `mrconvert` to NIfTI;
- `mrtrix_lmax12.mif.gz`: `dwi2fod csd -lmax 12` of the same (91 volumes).

The truth, per file, in `expected.json`, always computed from the values read back from the
file written (nibabel for NIfTI; `mrconvert -datatype float64le -strides 1,2,3,4` to NIfTI for
MRtrix images), with each voxel's world position (the tests match voxels by position, so that
either reader's axis order holds):
- `amplitudes`: DIPY's `sh_to_sf` (with the file's basis and `legacy` flag) for the DIPY files,
  MRtrix's `sh2amp -datatype float64` (without `-nonnegative`) for the MRtrix images (which
  sh2amp computes in double but holds in a float32 image, `using value_type = float` in its
  source: float32 numbers, however they are written), and for those also
  `amplitudes_dipy`, DIPY's `sh_to_sf` in tournier07 with `legacy=False` (MRtrix's basis), along
  `directions` (x, y, z in the coefficients' own frame: voxel axes for DIPY, scanner axes for
  MRtrix; handed to both as angles computed by atan2): the six axis directions, three
  directions within 1e-4 rad of a pole, and 21 seeded random ones;
- `peaks`, by voxel (its place in `positions`): for 16 voxels of each DIPY file, DIPY's `peak_directions_nl` (seeded on `repulsion724`, refined
  by scipy's Nelder-Mead, xtol 1e-9) with `relative_peak_threshold=0.5` and
  `min_separation_angle=25`, the directions and values; for the MRtrix images, `sh2peaks`
  (default 60 seeds, `-num 3`), for every voxel, the directions and |amplitudes| of those found
  (MRtrix writes NaN for the rest, and amplitude × direction: a maximum of negative value comes
  out with its sign lost).
"""
import json
import os
import shutil
import subprocess
import tempfile

import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.core.sphere import Sphere
from dipy.data import get_fnames, get_sphere
from dipy.direction.peaks import peak_directions_nl
from dipy.io import read_bvals_bvecs
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst
from dipy.reconst.shm import convert_sh_descoteaux_tournier, convert_sh_from_legacy, sh_to_sf

HERE = os.path.dirname(os.path.abspath(__file__))
BLOCK = (slice(3, 7),) * 3
# The block in MRtrix's -coord terms (its axes are the NIfTI's for a file MRtrix reads).
# DIPY's refined peaks take seconds a voxel: 16 of the 64, spread by a seeded draw.
PEAK_VOXELS = sorted(np.random.default_rng(7).choice(64, 16, replace=False).tolist())
COORD = ["-coord", "0", "3:6", "-coord", "1", "3:6", "-coord", "2", "3:6"]


def run(*args, **kw):
    return subprocess.run([str(a) for a in args], check=True, **kw)


def out(name):
    return os.path.join(HERE, name)


def directions():
    d = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    for t in (1e-4, 1e-5):
        d.append([np.sin(t), 0.0, np.cos(t)])
    d.append([0.0, -np.sin(1e-5), -np.cos(1e-5)])
    rng = np.random.default_rng(39)
    r = rng.normal(size=(21, 3))
    d.extend(r.tolist())
    d = np.asarray(d, dtype=np.float64)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def angles(dirs):
    """Polar angle and azimuth of unit directions, by atan2: near a pole arccos(z) (DIPY's
    cart2sphere, MRtrix's cartesian2spherical) loses digits (at θ = 1e-7 it is 4e-11 rad off),
    which would be the truth's error, not the reader's."""
    theta = np.arctan2(np.hypot(dirs[:, 0], dirs[:, 1]), dirs[:, 2])
    return theta, np.arctan2(dirs[:, 1], dirs[:, 0])


def per_voxel(data, affine):
    """Voxels (x fastest) of a 4-D array: coefficient rows, ijk and world positions."""
    dims = list(data.shape[:3])
    n = int(np.prod(dims))
    rows = data.reshape(n, data.shape[3], order="F")
    ijk = np.stack(np.meshgrid(*[np.arange(d) for d in dims], indexing="ij"), -1)
    ijk = ijk.reshape(n, 3, order="F")
    positions = ijk @ affine[:3, :3].T + affine[:3, 3]
    return rows, ijk, positions


def dipy_truth(name, basis, legacy, lmax, dirs):
    img = nib.load(out(name))
    data = np.asarray(img.dataobj, dtype=np.float64)
    rows, ijk, positions = per_voxel(data, img.affine)
    theta, phi = angles(dirs)
    sphere = Sphere(theta=theta, phi=phi)
    amps = sh_to_sf(rows, sphere, sh_order_max=lmax, basis_type=basis, legacy=legacy)
    seeds = get_sphere(name="repulsion724")
    peaks = {}
    for v in PEAK_VOXELS:
        c = rows[v]

        def evaluate(s, c=c):
            return sh_to_sf(c, s, sh_order_max=lmax, basis_type=basis, legacy=legacy)

        dirs_v, vals = peak_directions_nl(
            evaluate, relative_peak_threshold=0.5, min_separation_angle=25, sphere=seeds,
            xtol=1e-9)
        peaks[str(v)] = {"directions": np.asarray(dirs_v).tolist(),
                         "values": np.asarray(vals).tolist()}
    return {
        "source": "dipy",
        "basis": basis if legacy is False or basis == "tournier07" else basis + "-legacy",
        "lmax": lmax,
        "count": data.shape[3],
        "dims": list(data.shape[:3]),
        "datatype": str(img.get_data_dtype()),
        "positions": positions.tolist(),
        "amplitudes": amps.tolist(),
        "peaks": peaks,
    }


def mrtrix_back(path, tmp, tag):
    """MRtrix's own reading of an image: values x fastest in its axes, and their affine."""
    back = os.path.join(tmp, tag + "_back.nii")
    run("mrconvert", "-quiet", "-force", path, back, "-strides", "1,2,3,4",
        "-datatype", "float64le")
    img = nib.load(back)
    return np.asarray(img.dataobj, dtype=np.float64), img.affine


def mrtrix_truth(name, lmax, dirs, tmp):
    path = out(name)
    data, affine = mrtrix_back(path, tmp, "coef")
    rows, ijk, positions = per_voxel(data, affine)
    dirfile = os.path.join(tmp, "dirs.txt")
    theta, phi = angles(dirs)
    # Azimuth and elevation (MRtrix's name for the polar angle), as dirgen writes them.
    np.savetxt(dirfile, np.column_stack([phi, theta]), fmt="%.17g")
    amp = os.path.join(tmp, "amp.mif")
    run("sh2amp", "-quiet", "-force", "-datatype", "float64", path, dirfile, amp)
    a, a_affine = mrtrix_back(amp, tmp, "amp")
    assert np.allclose(a_affine, affine)
    amps = a.reshape(rows.shape[0], a.shape[3], order="F")
    theta, phi = angles(dirs)
    dipy_amps = sh_to_sf(rows, Sphere(theta=theta, phi=phi), sh_order_max=lmax,
                         basis_type="tournier07", legacy=False)
    pk = os.path.join(tmp, "peaks.mif")
    run("sh2peaks", "-quiet", "-force", "-num", "3", path, pk)
    p, _ = mrtrix_back(pk, tmp, "peaks")
    p = p.reshape(rows.shape[0], p.shape[3], order="F").reshape(rows.shape[0], 3, 3)
    peaks = {}
    for i, v in enumerate(p):
        amps_v = np.linalg.norm(v, axis=1)
        ok = np.isfinite(amps_v) & (amps_v > 0)
        peaks[str(i)] = {"directions": (v[ok] / amps_v[ok, None]).tolist(),
                         "values": amps_v[ok].tolist()}
    return {
        "source": "mrtrix",
        "basis": "tournier07",
        "lmax": lmax,
        "count": data.shape[3],
        "dims": list(data.shape[:3]),
        "datatype": subprocess.run(["mrinfo", "-datatype", path], check=True,
                                   capture_output=True, text=True).stdout.strip(),
        "positions": positions.tolist(),
        "amplitudes": amps.tolist(),
        "amplitudes_dipy": dipy_amps.tolist(),
        "peaks": peaks,
    }


def dump(v, depth=0):
    """JSON with objects and lists of lists indented, lists of numbers on one line."""
    pad = "\n" + " " * (depth + 1)
    if isinstance(v, dict):
        items = [json.dumps(k) + ": " + dump(x, depth + 1) for k, x in v.items()]
        return "{" + pad + ("," + pad).join(items) + "\n" + " " * depth + "}"
    if isinstance(v, list) and v and isinstance(v[0], (list, dict)):
        return "[" + pad + ("," + pad).join(dump(x, depth + 1) for x in v) + "\n" + " " * depth + "]"
    return json.dumps(v, separators=(",", ":"))


def main():
    for f in os.listdir(HERE):
        if f.endswith((".mif", ".mif.gz", ".nii.gz")):
            os.remove(out(f))
    dwi, bval, bvec = get_fnames(name="small_64D")
    img = nib.load(dwi)
    data = np.asarray(img.dataobj, dtype=np.float64)
    bvals, bvecs = read_bvals_bvecs(bval, bvec)
    gtab = gradient_table(bvals, bvecs=bvecs)
    response, ratio = auto_response_ssst(gtab, data, roi_radii=10, fa_thr=0.7)
    block = img.slicer[BLOCK]
    sub = data[BLOCK]
    dirs = directions()
    expected = {"directions": dirs.tolist(), "files": {}}
    files = expected["files"]

    def save(name, coef, dtype=np.float64):
        nib.save(nib.Nifti1Image(coef.astype(dtype), block.affine), out(name))

    fit8 = ConstrainedSphericalDeconvModel(gtab, response, sh_order_max=8).fit(sub)
    legacy = np.asarray(fit8.shm_coeff, dtype=np.float64)
    plain = convert_sh_from_legacy(legacy, "descoteaux07")
    tournier = convert_sh_descoteaux_tournier(plain)
    save("dipy_lmax8_descoteaux07_legacy.nii.gz", legacy)
    save("dipy_lmax8_descoteaux07.nii.gz", plain)
    save("dipy_lmax8_tournier07.nii.gz", tournier)
    files["dipy_lmax8_descoteaux07_legacy.nii.gz"] = dipy_truth(
        "dipy_lmax8_descoteaux07_legacy.nii.gz", "descoteaux07", True, 8, dirs)
    files["dipy_lmax8_descoteaux07.nii.gz"] = dipy_truth(
        "dipy_lmax8_descoteaux07.nii.gz", "descoteaux07", False, 8, dirs)
    files["dipy_lmax8_tournier07.nii.gz"] = dipy_truth(
        "dipy_lmax8_tournier07.nii.gz", "tournier07", False, 8, dirs)
    fit12 = ConstrainedSphericalDeconvModel(gtab, response, sh_order_max=12).fit(sub)
    save("dipy_lmax12_descoteaux07_legacy_f32.nii.gz", fit12.shm_coeff, np.float32)
    files["dipy_lmax12_descoteaux07_legacy_f32.nii.gz"] = dipy_truth(
        "dipy_lmax12_descoteaux07_legacy_f32.nii.gz", "descoteaux07", True, 12, dirs)

    with tempfile.TemporaryDirectory() as tmp:
        mif = os.path.join(tmp, "dwi.mif")
        run("mrconvert", "-quiet", "-force", dwi, mif, "-fslgrad", bvec, bval)
        resp = os.path.join(tmp, "response.txt")
        run("dwi2response", "-quiet", "-force", "tournier", mif, resp, "-scratch", tmp)
        crop = os.path.join(tmp, "dwi_block.mif")
        run("mrconvert", "-quiet", "-force", mif, crop, *COORD)
        run("dwi2fod", "-quiet", "-force", "csd", crop, resp, out("mrtrix_lmax8.mif"),
            "-lmax", "8")
        run("mrconvert", "-quiet", "-force", out("mrtrix_lmax8.mif"),
            out("mrtrix_lmax8.nii.gz"))
        run("dwi2fod", "-quiet", "-force", "csd", crop, resp, out("mrtrix_lmax12.mif.gz"),
            "-lmax", "12")
        for name, lmax in [("mrtrix_lmax8.mif", 8), ("mrtrix_lmax8.nii.gz", 8),
                           ("mrtrix_lmax12.mif.gz", 12)]:
            files[name] = mrtrix_truth(name, lmax, dirs, tmp)

    with open(out("expected.json"), "w") as f:
        # One voxel's numbers to a line: thousands of 17-digit numbers, one per line, would
        # double the file.
        f.write(dump(expected) + "\n")


if __name__ == "__main__":
    if shutil.which("dwi2fod") is None:
        raise SystemExit("needs MRtrix3 (apt-get install mrtrix3)")
    main()
