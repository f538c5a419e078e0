#!/usr/bin/env python3
"""Writes the MRtrix image files in this folder with MRtrix3's own tools, and `expected.json`,
what MRtrix reads back from each:

    apt-get install mrtrix3            (Debian's 3.0.3: mrconvert, dwi2tensor, mrinfo)
    pip install dipy nibabel numpy     (DIPY ships the small_101D DWI set)
    python3 tests/data/mif/make_mif.py

- `tensor_*`: the tensors of `../dti/mrtrix_oblique.nii.gz` (world-frame tensors in MRtrix's
  order D11 D22 D33 D12 D13 D23 on an oblique lattice, numpy's truth in `../dti/expected.json`)
  converted by `mrconvert` with other strides (`layout:`), datatypes, axes, compression and a
  detached data file (`.mih` + `.dat`);
- `dwi2tensor_small101.mif`: `dwi2tensor` on DIPY's small_101D DWI (whose lattice has a
  negative determinant: MRtrix writes it with `layout: -0,...`), and its NIfTI twin
  `dwi2tensor_small101.nii.gz` (`mrconvert`);
- `dwi_small101.mif.gz`: that DWI itself (UInt16LE, 102 volumes): a 4-D volume of many values;
- `scalar_*`: its first volume (or DIPY's mask) in every datatype MRtrix writes, with and without
  `scaling:`.

The truth of each file is MRtrix's own reading of it: `mrconvert FILE -strides 1,2,3,4
-datatype float64le` to a NIfTI file, loaded by nibabel (the values with `scaling:` applied, x
fastest in MRtrix's axes, which it may have permuted or flipped to be near RAS, and the affine
MRtrix writes for them: the voxels' world positions), with `mrinfo`'s datatype and strides.
The tests match voxels by world position, so they hold whatever axes either reader uses.
"""
import json
import os
import shutil
import subprocess
import tempfile

import nibabel as nib
import numpy as np
from dipy.data import get_fnames

HERE = os.path.dirname(os.path.abspath(__file__))
DTI = os.path.join(HERE, "..", "dti")


def run(*args):
    subprocess.run([str(a) for a in args], check=True)


def mrconvert(src, dst, *opts):
    run("mrconvert", "-quiet", "-force", src, dst, *opts)


def out(name):
    return os.path.join(HERE, name)


def truth(name, keep_volumes=None):
    """What MRtrix reads from `name`: values per voxel (x fastest) and their world positions."""
    path = out(name)
    with tempfile.TemporaryDirectory() as tmp:
        back = os.path.join(tmp, "back.nii")
        mrconvert(path, back, "-strides", "1,2,3,4"[: 2 * ndim(path) - 1], "-datatype", "float64le")
        img = nib.load(back)
        data = np.asarray(img.dataobj, dtype=np.float64)
    info = lambda opt: subprocess.run(["mrinfo", opt, path], check=True, capture_output=True,
                                      text=True).stdout.split()
    dims = list(data.shape[:3])
    volumes = int(np.prod(data.shape[3:])) if data.ndim > 3 else 1
    n = int(np.prod(dims))
    per_voxel = data.reshape(dims + [volumes], order="F").reshape(n, volumes, order="F")
    ijk = np.stack(np.meshgrid(*[np.arange(d) for d in dims], indexing="ij"), -1)
    ijk = ijk.reshape(n, 3, order="F")
    positions = ijk @ img.affine[:3, :3].T + img.affine[:3, 3]
    entry = {
        "dims": dims,
        "volumes": volumes,
        "datatype": " ".join(info("-datatype")),
        "strides": [int(s) for s in info("-strides")],
        "positions": positions.tolist(),
        "volume_sums": per_voxel.sum(axis=0).tolist(),
    }
    kept = range(volumes) if keep_volumes is None else keep_volumes
    entry["kept_volumes"] = list(kept)
    entry["values"] = per_voxel[:, list(kept)].tolist()
    return entry


def ndim(path):
    return len(subprocess.run(["mrinfo", "-size", path], check=True, capture_output=True,
                              text=True).stdout.split())


def main():
    for f in os.listdir(HERE):
        if f.endswith((".mif", ".mif.gz", ".mih", ".dat", ".nii.gz")):
            os.remove(out(f))
    expected = {}
    src = os.path.join(DTI, "mrtrix_oblique.nii.gz")
    tensors = {
        "tensor_oblique.mif": [],
        "tensor_volume_contiguous.mif": ["-strides", "2,3,4,1"],
        "tensor_reversed_f64be.mif.gz": ["-strides", "-1,3,-2,4", "-datatype", "float64be"],
        "tensor_permuted_f32be.mif": ["-axes", "1,0,2,3", "-datatype", "float32be"],
        "tensor_detached.mih": ["-strides", "-3,-2,-1,4"],
    }
    for name, opts in tensors.items():
        mrconvert(src, out(name), *opts)
        expected[name] = truth(name)

    dwi, bval, bvec = get_fnames(name="small_101D")
    run("dwi2tensor", "-quiet", "-force", "-fslgrad", bvec, bval, dwi,
        out("dwi2tensor_small101.mif"))
    expected["dwi2tensor_small101.mif"] = truth("dwi2tensor_small101.mif")
    mrconvert(out("dwi2tensor_small101.mif"), out("dwi2tensor_small101.nii.gz"))

    mrconvert(dwi, out("dwi_small101.mif.gz"), "-datatype", "uint16le")
    expected["dwi_small101.mif.gz"] = truth("dwi_small101.mif.gz", keep_volumes=[0, 1, 101])

    b0 = ["-coord", "3", "0", "-axes", "0,1,2"]
    mask = os.path.join(DTI, "dipy_small101", "mask.nii.gz")
    scalars = {
        "scalar_uint8.mif": (mask, ["-datatype", "uint8"]),
        "scalar_int8.mif": (mask, ["-datatype", "int8", "-strides", "-1,-2,3"]),
        "scalar_int16be_scaled.mif": (dwi, b0 + ["-datatype", "int16be", "-scaling", "10,0.5"]),
        "scalar_uint16be.mif": (dwi, b0 + ["-datatype", "uint16be", "-strides", "3,2,1"]),
        "scalar_int32le.mif.gz": (dwi, b0 + ["-datatype", "int32le"]),
        "scalar_uint32be.mif": (dwi, b0 + ["-datatype", "uint32be"]),
        "scalar_float32le.mif": (dwi, b0 + ["-datatype", "float32le"]),
        "scalar_float64be.mif": (dwi, b0 + ["-datatype", "float64be", "-strides", "2,-3,1"]),
        "scalar_float64le.mif": (dwi, b0 + ["-datatype", "float64le"]),
        "scalar_int16le.mif": (dwi, b0 + ["-datatype", "int16le", "-strides", "-3,1,2"]),
        "scalar_uint64le.mif": (dwi, b0 + ["-datatype", "uint64le"]),
        "scalar_int64be.mif": (dwi, b0 + ["-datatype", "int64be"]),
    }
    for name, (source, opts) in scalars.items():
        mrconvert(source, out(name), *opts)
        expected[name] = truth(name)

    with open(out("expected.json"), "w") as f:
        json.dump(expected, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    if shutil.which("mrconvert") is None:
        raise SystemExit("needs MRtrix3 (apt-get install mrtrix3)")
    main()
