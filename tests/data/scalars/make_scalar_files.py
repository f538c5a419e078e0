#!/usr/bin/env python3
"""Writes the NIfTI and NRRD scalar volumes in this folder, and `expected.json` with numpy's
truth: each file's values in file order (x fastest) and its voxel-to-world matrix in RAS+.

    pip install nibabel numpy; apt install teem-apps     (for teem-unu)
    python3 tests/data/scalars/make_scalar_files.py

(The VTK files come from `make_vtk_scalars.py`, which needs VTK's Python.)

NIfTI files are written by nibabel on the lattice of `tests/data/dti/fsl4d_oblique.nii.gz` (its
affine), one per datatype; values are nibabel's `get_fdata()` (scl_slope and scl_inter
applied). NRRD files are written by Teem's `unu make`; `lps_f32_gzip.nrrd` has exactly the
geometry of `tests/data/dti/nrrd_gzip_lps.nrrd` (copied from its header) and holds each voxel's
file-order index, so a reader that places it in another world than the tensors' shows it.
Their RAS+ matrix is numpy's: LPS directions and origin with x and y negated.
"""
import gzip
import json
import os
import re
import subprocess
import tempfile

import nibabel as nib
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DTI = os.path.join(os.path.dirname(HERE), "dti")
DIMS = (5, 4, 3)
rng = np.random.default_rng(7)
expected = {"files": {}}


def flat(a):
    return np.asarray(a).reshape(-1, order="F")


def record(name, values, affine):
    expected["files"][name] = {
        "dims": list(DIMS),
        "values": [float(v) for v in flat(values)],
        "voxel_to_world": np.asarray(affine, dtype=np.float64).tolist(),
    }


# ---------------------------------------------------------------- NIfTI
AFFINE = nib.load(os.path.join(DTI, "fsl4d_oblique.nii.gz")).affine


def nifti(name, data, dtype=None, sform=True, header=None):
    img = nib.Nifti1Image(data, AFFINE, header=header)
    if dtype is not None:
        img.set_data_dtype(dtype)
    if not sform:
        img.set_sform(None, code=0)
        img.set_qform(AFFINE, code=1)
    path = os.path.join(HERE, name)
    nib.save(img, path)
    back = nib.load(path)
    record(name, back.get_fdata()[..., 0] if back.ndim == 4 else back.get_fdata(), back.affine)
    return back


nifti("u8.nii.gz", rng.integers(0, 256, DIMS).astype(np.uint8))
nifti("i8.nii.gz", rng.integers(-128, 128, DIMS).astype(np.int8))
scaled = nifti("i16_scaled.nii.gz", rng.uniform(-50.0, 900.0, DIMS), dtype=np.int16)
assert scaled.dataobj.slope != 1.0 and scaled.dataobj.inter != 0.0, "nibabel did not scale"
nifti("u16.nii", rng.integers(0, 65536, DIMS).astype(np.uint16))
nifti("i32.nii.gz", rng.integers(-1_000_000, 1_000_000, DIMS).astype(np.int32))
nifti("f32_qform.nii.gz", rng.normal(0.0, 1.0, DIMS).astype(np.float32), sform=False)
nifti("f64_bigendian.nii", rng.normal(0.0, 1e3, DIMS), header=nib.Nifti1Header(endianness=">"))
nifti("f32_4d1.nii.gz", rng.uniform(0.0, 1.0, DIMS + (1,)).astype(np.float32))

# Bad inputs: a datatype that is no scalar, two volumes, data cut short.
nib.save(nib.Nifti1Image(np.ones(DIMS, np.complex64), AFFINE), os.path.join(HERE, "bad_complex.nii.gz"))
nib.save(nib.Nifti1Image(np.ones(DIMS + (2,), np.float32), AFFINE), os.path.join(HERE, "bad_two_volumes.nii.gz"))
with open(os.path.join(HERE, "u16.nii"), "rb") as f:
    whole = f.read()
with open(os.path.join(HERE, "bad_short.nii"), "wb") as f:
    f.write(whole[:-2])
with open(os.path.join(HERE, "bad_truncated.nii.gz"), "wb") as f:
    f.write(gzip.compress(whole, mtime=0)[:-40])


# ---------------------------------------------------------------- NRRD
def header_field(path, key):
    with open(path, "rb") as f:
        head = f.read().split(b"\n\n", 1)[0].decode()
    return re.search(rf"^{key}: (.*)$", head, re.M).group(1)


def vectors(text):
    return [np.array([float(x) for x in v.split(",")]) for v in re.findall(r"\(([^)]*)\)", text)]


def unu(name, data, ntype, encoding, space=None, dirs=None, origin=None, spacings=None,
        endian="little"):
    """`unu make` a NRRD of `data` (X×Y×Z), `unu save` it with `encoding` and `endian` (a
    `.nhdr` name gives a detached header and data file), and record its RAS+ matrix."""
    out = os.path.join(HERE, name)
    make = ["teem-unu", "make", "-t", ntype, "-s", *map(str, DIMS), "-e", "raw", "-en", "little"]
    if space:
        make += ["-spc", space, "-orig", origin, "-dirs", dirs, "-k", "space", "space", "space"]
    if spacings:
        make += ["-sp", *map(str, spacings)]
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "in.raw")
        with open(src, "wb") as f:
            f.write(flat(data).astype(data.dtype.newbyteorder("<")).tobytes())
        made = os.path.join(tmp, "made.nrrd")
        subprocess.run(make + ["-i", src, "-o", made], check=True)
        subprocess.run(["teem-unu", "save", "-f", "nrrd", "-e", encoding, "-en", endian,
                        "-i", made, "-o", name], check=True, cwd=HERE)
    if space:
        cols = vectors(dirs)
        a = np.eye(4)
        a[:3, :3] = np.column_stack(cols)
        a[:3, 3] = vectors(origin)[0]
        if space in ("LPS", "left-posterior-superior"):
            a = np.diag([-1.0, -1.0, 1.0, 1.0]) @ a
    else:
        a = np.diag(list(spacings) + [1.0])
    record(name, data.astype(np.float64), a)


lps = os.path.join(DTI, "nrrd_gzip_lps.nrrd")
LPS_DIRS = " ".join(f"({v})" for v in re.findall(r"\(([^)]*)\)", header_field(lps, "space directions")))
LPS_ORIGIN = header_field(lps, "space origin")
RAS_DIRS = "(2,0,0) (0.3,2.5,0) (0,-0.4,3)"
RAS_ORIGIN = "(-10,5,3)"

index = np.arange(np.prod(DIMS), dtype=np.float32).reshape(DIMS, order="F")
unu("lps_f32_gzip.nrrd", index, "float", "gzip", "LPS", LPS_DIRS, LPS_ORIGIN)
unu("ras_u8_raw.nrrd", rng.integers(0, 256, DIMS).astype(np.uint8), "uchar", "raw",
    "RAS", RAS_DIRS, RAS_ORIGIN)
unu("i16_big_detached.nhdr", rng.integers(-30000, 30000, DIMS).astype(np.int16), "short", "raw",
    "LPS", RAS_DIRS, RAS_ORIGIN, endian="big")
unu("f64_ascii.nrrd", rng.normal(0.0, 1.0, DIMS), "double", "ascii", "RAS", RAS_DIRS, RAS_ORIGIN)
unu("u16_spacings.nrrd", rng.integers(0, 65536, DIMS).astype(np.uint16), "ushort", "gzip",
    spacings=(1.5, 2.0, 2.5))
# A 2-D colour image has three axes too; its first is no space axis.
with tempfile.TemporaryDirectory() as tmp:
    src = os.path.join(tmp, "rgb.raw")
    with open(src, "wb") as f:
        f.write(bytes(range(60)))
    subprocess.run(["teem-unu", "make", "-t", "uchar", "-s", "3", "5", "4", "-e", "raw",
                    "-k", "3-color", "space", "space", "-i", src, "-o", "bad_rgb.nrrd"],
                   check=True, cwd=HERE)
with open(os.path.join(HERE, "ras_u8_raw.nrrd"), "rb") as f:
    b = f.read()
with open(os.path.join(HERE, "bad_short.nrrd"), "wb") as f:
    f.write(b[:-3])

with open(os.path.join(HERE, "expected.json"), "w") as f:
    json.dump(expected, f, indent=1)
    f.write("\n")
