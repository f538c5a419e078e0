#!/usr/bin/env python3
"""A whole-brain-sized volume of real fibre ODFs for the report's time and memory (the issue
"Pipelines, second step"): the test fit of DIPY's small_64D by MRtrix 3.0.3 `dwi2fod` (4x4x4
voxels, lmax 8) tiled NX x NY x NZ times (default 25 x 30 x 25: 100x120x100 voxels, 216 MB of
float32), written as a MRtrix .mif with the input's voxel size and transform.

Plain Python as tile_slice.py (whose reader it uses); the tiling is one voxel's 45 values
packed once and repeated, so 1.2 million voxels take seconds.

usage: tile_volume.py IN.mif[.gz] OUT.mif [NX NY NZ]
"""
import struct
import sys

from tile_slice import mif_header, read_mif


def main():
    src, out = sys.argv[1], sys.argv[2]
    reps = [int(v) for v in sys.argv[3:6]] if len(sys.argv) > 5 else [25, 30, 25]
    dim, at, extra = read_mif(src)
    nv = dim[3]
    packed = {}
    for z in range(dim[2]):
        for y in range(dim[1]):
            for x in range(dim[0]):
                packed[x, y, z] = struct.pack("<%df" % nv, *(at((x, y, z, v)) for v in range(nv)))
    n = [dim[a] * reps[a] for a in range(3)]
    header = ["mrtrix image", "dim: %d,%d,%d,%d" % (n[0], n[1], n[2], nv),
              "layout: +1,+2,+3,+0", "datatype: Float32LE"] + extra
    with open(out, "wb") as f:
        f.write(mif_header(header))
        for z in range(n[2]):
            for y in range(n[1]):
                # One row of x at a time: volume-fastest, then x.
                f.write(b"".join(packed[x % dim[0], y % dim[1], z % dim[2]] for x in range(n[0])))
    print("wrote %s: %dx%dx%d, %d coefficients" % (out, n[0], n[1], n[2], nv))


if __name__ == "__main__":
    main()
