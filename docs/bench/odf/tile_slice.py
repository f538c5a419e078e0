#!/usr/bin/env python3
"""A whole-brain-sized axial slab of real fibre ODFs for the ODF speed bench: two axial slices
of an MRtrix image of SH series (the test fit of DIPY's small_64D by MRtrix 3.0.3 `dwi2fod`,
4x4 voxels a slice) tiled N x N times into a (4N)x(4N)x2 image, written as a MRtrix .mif with
the input's voxel size, transform and every header line but dim/layout/file.

Plain Python (no numpy): the .mif's layout is read as MRtrix defines it (for each axis its
stride rank, a minus sign for an axis stored from its far end).

usage: tile_slice.py IN.mif[.gz] OUT.mif [N (default 25)] [z0 (default 1)]
"""
import gzip
import struct
import sys


def read_mif(path):
    raw = gzip.open(path, "rb").read() if path.endswith(".gz") else open(path, "rb").read()
    end = raw.index(b"\nEND\n")
    lines = raw[:end].decode("latin-1").split("\n")
    assert lines[0] == "mrtrix image", "not a MRtrix image"
    head = {}
    extra = []
    for line in lines[1:]:
        key, _, value = line.partition(":")
        key, value = key.strip(), value.strip()
        if key in ("dim", "layout", "file", "datatype"):
            head[key] = value
        else:
            extra.append(line)
    dim = [int(v) for v in head["dim"].split(",")]
    layout = head["layout"].split(",")
    assert head["datatype"] == "Float32LE", "this script reads Float32LE only"
    name, offset = head["file"].split()
    assert name == ".", "detached data is not read here"
    data = raw[int(offset):]
    count = 1
    for d in dim:
        count *= d
    values = struct.unpack("<%df" % count, data[: 4 * count])
    # Strides from the ranks: the rank-0 axis is fastest.
    ranks = [abs(int(v)) for v in layout]
    reverse = [v.strip().startswith("-") for v in layout]
    stride = [0] * len(dim)
    step = 1
    for rank in range(len(dim)):
        axis = ranks.index(rank)
        stride[axis] = step
        step *= dim[axis]

    def at(idx):
        off = 0
        for a, i in enumerate(idx):
            j = dim[a] - 1 - i if reverse[a] else i
            off += j * stride[a]
        return values[off]

    return dim, at, extra


def mif_header(lines):
    """A .mif header of `lines` (from "mrtrix image" on, without file and END) with its data
    offset, padded with zeros to that offset (a multiple of 16)."""
    text = "\n".join(lines) + "\nfile: . "
    # The data offset counts its own digits.
    base = len(text.encode()) + len("\nEND\n") + 8
    offset = (base + 15) // 16 * 16
    text += str(offset).rjust(8) + "\nEND\n"
    blob = text.encode()
    return blob + b"\0" * (offset - len(blob))


def main():
    src, out = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 25
    z0 = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    dim, at, extra = read_mif(src)
    nx, ny, nv = dim[0] * n, dim[1] * n, dim[3]
    # Written volume-fastest, then x, y, z (layout +1,+2,+3,+0), as mrconvert writes SH images.
    out_values = []
    for z in range(2):
        for y in range(ny):
            for x in range(nx):
                idx = (x % dim[0], y % dim[1], z0 + z)
                out_values.extend(at(idx + (v,)) for v in range(nv))
    header = ["mrtrix image", "dim: %d,%d,2,%d" % (nx, ny, nv), "layout: +1,+2,+3,+0",
              "datatype: Float32LE"] + extra
    with open(out, "wb") as f:
        f.write(mif_header(header))
        f.write(struct.pack("<%df" % len(out_values), *out_values))
    print("wrote %s: %dx%dx2, %d coefficients" % (out, nx, ny, nv))


if __name__ == "__main__":
    main()
