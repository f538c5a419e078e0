#!/usr/bin/env python3
"""Writes the DTI test files in this folder: the same world-frame tensors in every layout and
frame tensorglyph reads, plus bad inputs, and `expected.json` with numpy's truth.

    pip install nibabel numpy
    python3 tests/data/dti/make_dti_files.py

The field (5x4x3 voxels) has, at voxel v (x fastest), its largest eigenvector along world axis
v % 3 (x, y, z) and random smaller eigenvalues and roll about that axis, so a reader that gets
the order or the frame wrong moves e1 off that axis. Each file stores the tensors in its own
frame (`D_file = Qᵀ D_world Q`, Q the rotation the reader applies), rounded to float32; the
expected eigenvalues are numpy's `eigh` of exactly those float32 numbers, in float64.

NRRD files are written here too: headers by hand (data raw, gzip or ascii), and where Teem's
`unu` is installed (Debian's teem-apps: `teem-unu`) a few by `unu make` and `unu save` from raw
floats written here, read back by `unu` to check that they hold what was meant. Without `unu`
those are left as they are (they are committed, so tests never need it).
"""
import gzip
import json
import os
import shutil
import subprocess

import nibabel as nib
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DIMS = (5, 4, 3)
N = DIMS[0] * DIMS[1] * DIMS[2]
rng = np.random.default_rng(14)


def rot(axis, deg):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    r = np.eye(3)
    r[i, i] = c
    r[j, j] = c
    r[i, j] = -s
    r[j, i] = s
    return r


def world_tensors():
    """D_world[v] (N x 3 x 3), x fastest, and the world axis of each e1."""
    out = np.zeros((N, 3, 3))
    axes = np.zeros(N, dtype=int)
    for v in range(N):
        axis = v % 3
        l1 = rng.uniform(1.4e-3, 2.0e-3)
        l2 = rng.uniform(0.3e-3, 0.6e-3)
        l3 = rng.uniform(0.1e-3, 0.25e-3)
        # A frame with e1 on the axis and a random roll about it.
        others = [a for a in range(3) if a != axis]
        e = np.zeros((3, 3))
        e[axis, 0] = 1.0
        t = rng.uniform(0, np.pi)
        e[others[0], 1], e[others[1], 1] = np.cos(t), np.sin(t)
        e[:, 2] = np.cross(e[:, 0], e[:, 1])
        out[v] = e @ np.diag([l1, l2, l3]) @ e.T
        axes[v] = axis
    return out, axes


D_WORLD, AXES = world_tensors()


def polar(m):
    u, _, vt = np.linalg.svd(m)
    return u @ vt


def frame_rotation(frame, affine):
    m = affine[:3, :3]
    if frame == "world":
        return np.eye(3)
    r = polar(m)
    if frame == "fsl" and np.linalg.det(m) > 0:
        r = r @ np.diag([-1.0, 1.0, 1.0])
    return r


def affine_of(rotation, sizes, origin):
    a = np.eye(4)
    a[:3, :3] = rotation @ np.diag(sizes)
    a[:3, 3] = origin
    return a


AFFINES = {
    "oblique": affine_of(rot(2, 30) @ rot(0, 20), [2.0, 2.5, 3.0], [-10.0, 5.0, 3.0]),
    "flipped": affine_of(np.diag([-1.0, 1.0, 1.0]), [2.0, 2.0, 2.0], [8.0, -4.0, -2.0]),
    "plain": affine_of(np.eye(3), [2.0, 2.0, 2.0], [0.0, 0.0, 0.0]),
}

ORDERS = {
    "fsl": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
    "mrtrix": [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)],
    "nifti": [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
    "nrrd": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
}

expected = {"dims": list(DIMS), "files": {}}


def file_tensors(frame, affine, dtype=np.float32):
    q = frame_rotation(frame, affine)
    d = np.einsum("ji,vjk,kl->vil", q, D_WORLD, q)  # Qᵀ D Q
    return d.astype(dtype)


def record(name, stored, args, e1_axes=AXES, extra=None):
    s = stored.astype(np.float64)
    w, _ = np.linalg.eigh(s)
    entry = {
        "args": args,
        "eigenvalues": w[:, ::-1].tolist(),
        "e1_axis": [int(a) for a in e1_axes],
    }
    if extra:
        entry.update(extra)
    expected["files"][name] = entry


def components(d, order):
    return np.stack([d[:, i, j] for i, j in ORDERS[order]], axis=-1)


def to_volume(per_voxel):
    """(N, C) in x-fastest order -> (X, Y, Z, C)."""
    c = per_voxel.shape[1]
    return per_voxel.reshape(DIMS[2], DIMS[1], DIMS[0], c).transpose(2, 1, 0, 3)


def save_nifti(name, data, affine, sform=True, qform=False, intent=None):
    img = nib.Nifti1Image(data, affine)
    h = img.header
    if sform:
        img.set_sform(affine, code=2)
    else:
        img.set_sform(None, code=0)
    if qform:
        img.set_qform(affine, code=1)
    else:
        img.set_qform(None, code=0)
    if intent:
        h.set_intent(intent)
    nib.save(img, os.path.join(HERE, name))


def nifti_six(name, frame, aff, order, args, five_d=False, dtype=np.float32, **kw):
    d = file_tensors(frame, AFFINES[aff], dtype)
    vol = to_volume(components(d, order))
    if five_d:
        vol = vol[:, :, :, None, :]
    save_nifti(name, vol, AFFINES[aff], **kw)
    record(name, d, args)


# Every layout of the same tensors on the oblique lattice.
nifti_six("fsl4d_oblique.nii.gz", "voxel", "oblique", "fsl", [])
nifti_six("fsl4d_oblique_f64.nii", "voxel", "oblique", "fsl", [], dtype=np.float64)
nifti_six("mrtrix_oblique.nii.gz", "world", "oblique", "mrtrix",
          ["--order", "mrtrix", "--tensor-frame", "world"])
nifti_six("dipy5d_oblique.nii.gz", "voxel", "oblique", "nifti", [], five_d=True,
          intent="symmetric matrix")
nifti_six("qform_oblique.nii.gz", "voxel", "oblique", "fsl", [], sform=False, qform=True)
d9 = file_tensors("voxel", AFFINES["oblique"])
save_nifti("full9_oblique.nii.gz", to_volume(d9.reshape(N, 9)), AFFINES["oblique"])
# Nine volumes are three peaks as likely as a full tensor: the file is read as tensors when
# --holds says so.
record("full9_oblique.nii.gz", d9, ["--holds", "tensors"])
# FSL's own frame: the x-flip applies (positive determinant) ...
nifti_six("fslframe_oblique.nii.gz", "fsl", "oblique", "fsl", ["--tensor-frame", "fsl"])
# ... and not where the matrix already flips (negative determinant): fsl and voxel agree.
nifti_six("fsl4d_flipped.nii.gz", "voxel", "flipped", "fsl", ["--tensor-frame", "fsl"])
nifti_six("fsl4d_plain.nii", "voxel", "plain", "fsl", [])



# FSL dtifit's eigen outputs (PREFIX_L1..L3: 3-D eigenvalue maps; PREFIX_V1..V3: 4-D, the
# eigenvectors' x, y, z), computed from the voxel-frame tensors. The truth is numpy's eigh of
# T = sum(l_i v_i v_i^T) of exactly the float32 numbers stored.
def fsl_eigen(prefix, aff, ext, args):
    d = file_tensors("voxel", AFFINES[aff], np.float64)
    w, v = np.linalg.eigh(d)
    w, v = w[:, ::-1].astype(np.float32), v[:, :, ::-1].astype(np.float32)
    for k in range(3):
        save_nifti(f"{prefix}_L{k + 1}{ext}", to_volume(w[:, k:k + 1])[..., 0], AFFINES[aff])
        save_nifti(f"{prefix}_V{k + 1}{ext}", to_volume(v[:, :, k]), AFFINES[aff])
    w64, v64 = w.astype(np.float64), v.astype(np.float64)
    t = np.einsum("vk,vik,vjk->vij", w64, v64, v64)
    record(prefix, t, args, extra={"eigen_set": [f"{prefix}_{m}{ext}" for m in
                                                 ("L1", "L2", "L3", "V1", "V2", "V3")],
                                   "stored_eigenvalues": w64.tolist()})


fsl_eigen("fsl_eigen_oblique", "oblique", ".nii.gz", [])
fsl_eigen("fsl_eigen_flipped", "flipped", ".nii", [])


# ANTs/ITK: itk::NiftiImageIO writes a DiffusionTensor3D image 5-D (X, Y, Z, 1, 6) with intent
# SYMMATRIX, turning ITK's upper triangle (xx xy xz yy yz zz) into NIfTI's lower one; tensors
# in voxel axes (ANTs rotates them by the direction matrix); sform = qform (codes 1 and 2),
# pixdim[0] = qfac, units mm and s, no scaling.
def save_itk(name, data, affine, intent):
    img = nib.Nifti1Image(data, affine)
    img.set_qform(affine, code=2)
    img.set_sform(affine, code=1)
    h = img.header
    h.set_intent(intent)
    h.set_xyzt_units("mm", "sec")
    path = os.path.join(HERE, name)
    nib.save(img, path)
    # nibabel writes "no scaling" as NaN; ITK writes slope 1, intercept 0.
    with open(path, "rb") as f:
        b = bytearray(gzip.decompress(f.read()))
    b[112:120] = np.array([1.0, 0.0], "<f4").tobytes()
    with open(path, "wb") as f:
        f.write(gzip.compress(bytes(b), mtime=0))


d = file_tensors("voxel", AFFINES["oblique"])
save_itk("ants5d_oblique.nii.gz", to_volume(components(d, "nifti"))[:, :, :, None, :],
         AFFINES["oblique"], "symmetric matrix")
record("ants5d_oblique.nii.gz", d, [])
# The same tensors as an ITK 6-vector image (intent VECTOR): ITK's order, unreordered.
save_itk("itk5d_vector_oblique.nii.gz", to_volume(components(d, "fsl"))[:, :, :, None, :],
         AFFINES["oblique"], "vector")
record("itk5d_vector_oblique.nii.gz", d, [])

# Bad inputs.
save_nifti("bad_scalar3d.nii.gz", np.ones(DIMS, np.float32), AFFINES["plain"])
save_nifti("bad_five_volumes.nii.gz", np.ones(DIMS + (5,), np.float32), AFFINES["plain"])
save_nifti("bad_int16.nii.gz", np.ones(DIMS + (6,), np.int16), AFFINES["plain"])
with open(os.path.join(HERE, "fsl4d_oblique.nii.gz"), "rb") as f:
    whole = gzip.decompress(f.read())
with open(os.path.join(HERE, "bad_truncated.nii.gz"), "wb") as f:
    f.write(gzip.compress(whole[: len(whole) - 100], mtime=0)[:-30])
with open(os.path.join(HERE, "bad_short_data.nii"), "wb") as f:
    f.write(whole[: len(whole) - 8])
# vox_offset beyond the end of the file (the data itself whole).
h = bytearray(whole)
h[108:112] = np.array([4096.0], "<f4").tobytes()
with open(os.path.join(HERE, "bad_vox_offset.nii"), "wb") as f:
    f.write(bytes(h))
# NIfTI-2 (a 540-byte header), which the reader refuses.
d = file_tensors("voxel", AFFINES["oblique"])
nib.save(nib.Nifti2Image(to_volume(components(d, "fsl")), AFFINES["oblique"]),
         os.path.join(HERE, "bad_nifti2.nii.gz"))
# A 3-D map of different dimensions, to stand in for one of an FSL eigen set.
save_nifti("bad_eigen_other_dims.nii.gz", np.ones((5, 4, 2), np.float32), AFFINES["oblique"])


# NRRD: world-frame tensors after the measurement frame, in RAS or LPS space.
def nrrd_content(space, aff, masked=False, mframe=None):
    """What a NRRD file in `space` holds for the world tensors: per-voxel values (confidence
    first when masked), the tensors as stored, space directions (columns), origin, measurement
    frame, and what record() needs of masked voxels."""
    a = AFFINES[aff].copy()
    flip = np.diag([-1.0, -1.0, 1.0]) if space == "left-posterior-superior" else np.eye(3)
    # The same world (RAS) positions and tensors, said in the file's space.
    dirs = flip @ a[:3, :3]
    origin = flip @ a[:3, 3]
    mf = np.eye(3) if mframe is None else mframe
    # Tensors in space axes, then in the measurement frame: D_space = M D_m Mᵀ.
    d_space = np.einsum("ij,vjk,lk->vil", flip, D_WORLD, flip)
    d_m = np.einsum("ji,vjk,kl->vil", mf, d_space, mf).astype(np.float32)
    comps = components(d_m, "nrrd")
    extra = {}
    if masked:
        conf = np.ones(N, np.float32)
        low = np.arange(N) % 7 == 3
        conf[low] = 0.25
        conf[np.arange(N) % 7 == 5] = 0.5  # exactly 0.5 is kept, as in Teem
        comps = np.concatenate([conf[:, None], comps], axis=1)
        extra = {"masked": int(low.sum()), "masked_voxels": np.nonzero(low)[0].tolist()}
    return comps, d_m, dirs, origin, mf, extra


def vec(v):
    return "(" + ",".join(repr(float(x)) for x in v) + ")"


def nrrd(name, space, aff, encoding="raw", masked=False, detached=False, mframe=None, kinds="3D-symmetric-matrix"):
    comps, d_m, dirs, origin, mf, extra = nrrd_content(space, aff, masked, mframe)
    if masked:
        kinds = "3D-masked-symmetric-matrix"
    ncomp = comps.shape[1]
    if encoding == "ascii":
        body = "\n".join(" ".join(repr(float(x)) for x in row) for row in comps).encode() + b"\n"
    else:
        body = comps.astype("<f4").tobytes()
        if encoding == "gzip":
            body = gzip.compress(body, mtime=0)
    lines = [
        "NRRD0004",
        "# written by make_dti_files.py",
        "type: float",
        "dimension: 4",
        f"space: {space}",
        f"sizes: {ncomp} {DIMS[0]} {DIMS[1]} {DIMS[2]}",
        "space directions: none " + " ".join(vec(dirs[:, i]) for i in range(3)),
        f"kinds: {kinds} space space space",
        "endian: little",
        f"encoding: {encoding}",
        "space origin: " + vec(origin),
    ]
    if mframe is not None:
        lines.append("measurement frame: " + " ".join(vec(mf[:, i]) for i in range(3)))
    if detached:
        data_name = name.rsplit(".", 1)[0] + ".raw"
        lines.append(f"data file: {data_name}")
        with open(os.path.join(HERE, data_name), "wb") as f:
            f.write(body)
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(("\n".join(lines) + "\n").encode())
    else:
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(("\n".join(lines) + "\n\n").encode() + body)
    record(name, d_m, [], AXES, extra)


nrrd("nrrd_raw_oblique.nrrd", "right-anterior-superior", "oblique")
nrrd("nrrd_gzip_lps.nrrd", "left-posterior-superior", "oblique", encoding="gzip")
nrrd("nrrd_ascii_flipped.nrrd", "right-anterior-superior", "flipped", encoding="ascii")
nrrd("nrrd_mframe_lps.nrrd", "left-posterior-superior", "oblique", mframe=rot(2, 90) @ rot(1, 15))
nrrd("nrrd_masked.nrrd", "right-anterior-superior", "plain", masked=True)
nrrd("nrrd_detached.nhdr", "left-posterior-superior", "oblique", detached=True)
# Bad NRRD: unknown kinds, detached data too short or missing, sizes beyond the data.
nrrd("bad_kinds.nrrd", "right-anterior-superior", "plain", kinds="3D-tensor")
del expected["files"]["bad_kinds.nrrd"]
nrrd("bad_short_detached.nhdr", "right-anterior-superior", "plain", detached=True)
del expected["files"]["bad_short_detached.nhdr"]
p = os.path.join(HERE, "bad_short_detached.raw")
with open(p, "rb") as f:
    b = f.read()
with open(p, "wb") as f:
    f.write(b[:-4])
with open(os.path.join(HERE, "bad_missing_detached.nhdr"), "wb") as f:
    f.write(b"NRRD0004\ntype: float\ndimension: 4\nsizes: 6 5 4 3\n"
            b"kinds: 3D-symmetric-matrix space space space\nendian: little\nencoding: raw\n"
            b"data file: no_such_file.raw\n")
with open(os.path.join(HERE, "nrrd_raw_oblique.nrrd"), "rb") as f:
    b = f.read()
with open(os.path.join(HERE, "bad_short_data.nrrd"), "wb") as f:
    f.write(b[:-4])
# Five values per voxel where 3D-symmetric-matrix has six; a 3-D scalar volume.
with open(os.path.join(HERE, "bad_components.nrrd"), "wb") as f:
    f.write(b.replace(b"sizes: 6 5 4 3", b"sizes: 5 5 4 3", 1))
with open(os.path.join(HERE, "bad_scalar3d.nrrd"), "wb") as f:
    f.write(b"NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nkinds: space space space\n"
            b"endian: little\nencoding: raw\n\n" + np.ones(N, "<f4").tobytes())



# NRRD files written by Teem's own unu from raw floats written here; each is read back by unu
# and must hold exactly the numbers meant.
UNU = shutil.which("unu") or shutil.which("teem-unu")


def unu(*args):
    subprocess.run([UNU, *args], cwd=HERE, check=True, capture_output=True)


def unu_values(name):
    """The values Teem reads from `name`, as float32."""
    out = subprocess.run([UNU, "save", "-i", name, "-f", "nrrd", "-e", "raw", "-en", "little",
                          "-o", "-"], cwd=HERE, check=True, capture_output=True).stdout
    return np.frombuffer(out[out.index(b"\n\n") + 2:], "<f4")


def teem(name, space, aff, masked=False, mframe=None, encoding="raw", skip=None, endian="little"):
    """`unu make` a NRRD of the world tensors: attached (then `unu save -e ENCODING`), or with
    `skip = (lines, bytes)` a detached header (`unu make -h`) whose data file starts with that
    many text lines and junk bytes (inside the inflated stream for gzip, as Teem reads it)."""
    comps, d_m, dirs, origin, mf, extra = nrrd_content(space, aff, masked, mframe)
    kinds = "3D-masked-symmetric-matrix" if masked else "3D-symmetric-matrix"
    values = comps.astype(">f4" if endian == "big" else "<f4").tobytes()
    geometry = ["-t", "float", "-s", str(comps.shape[1]), *map(str, DIMS),
                "-k", kinds, "space", "space", "space", "-en", endian,
                "-spc", {"left-posterior-superior": "LPS"}.get(space, "RAS"),
                "-orig", vec(origin),
                "-dirs", "none " + " ".join(vec(dirs[:, i]) for i in range(3))]
    if mframe is not None:
        geometry += ["-mf", " ".join(vec(mf[:, i]) for i in range(3))]
    if skip is None:
        raw = name + ".tmp.raw"
        with open(os.path.join(HERE, raw), "wb") as f:
            f.write(values)
        unu("make", "-i", raw, *geometry, "-o", name + ".tmp.nrrd")
        unu("save", "-i", name + ".tmp.nrrd", "-f", "nrrd", "-e", encoding, "-o", name)
        for t in (raw, name + ".tmp.nrrd"):
            os.remove(os.path.join(HERE, t))
    else:
        lines, junk = skip
        data_name = name.rsplit(".", 1)[0] + (".raw.gz" if encoding == "gzip" else ".raw")
        inner = b"\xa5" * junk + values
        body = gzip.compress(inner, mtime=0) if encoding == "gzip" else inner
        text = b"".join(b"preamble line %d\n" % i for i in range(lines))
        with open(os.path.join(HERE, data_name), "wb") as f:
            f.write(text + body)
        unu("make", "-h", "-i", data_name, *geometry, "-e", encoding,
            "-ls", str(lines), "-bs", str(junk), "-o", name)
    got = unu_values(name)
    assert np.array_equal(got, comps.reshape(-1)), f"unu reads other numbers from {name}"
    record(name, d_m, [], AXES, extra)


if UNU:
    teem("teem_masked_lps.nrrd", "left-posterior-superior", "oblique", masked=True,
         mframe=rot(2, 90) @ rot(1, 15), encoding="gzip")
    teem("teem_skip_bigendian.nhdr", "right-anterior-superior", "oblique", skip=(2, 3),
         endian="big")
    teem("teem_skip_gzip.nhdr", "left-posterior-superior", "flipped", skip=(1, 4),
         encoding="gzip")
else:
    # Keep the committed files' truth.
    with open(os.path.join(HERE, "expected.json")) as f:
        old = json.load(f)["files"]
    for name in ("teem_masked_lps.nrrd", "teem_skip_bigendian.nhdr", "teem_skip_gzip.nhdr"):
        if name in old:
            expected["files"][name] = old[name]
    print("unu not found: the Teem-written NRRD files are left as they are")

with open(os.path.join(HERE, "expected.json"), "w") as f:
    json.dump(expected, f, indent=1)
    f.write("\n")
