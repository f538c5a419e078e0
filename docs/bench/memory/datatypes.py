#!/usr/bin/env python3
"""Peak memory of `tensorglyph render` against the project's aim, 64 MiB + 8x the bytes the
data holds (inflated, for gzip), for MRtrix tensor images of every datatype, plain and gzip.

Each file: 200x200x50 voxels x 6 tensor values (2 M tensors, a whole-brain DTI volume's size),
random positive-definite-ish values (diagonal 10..110, off-diagonal -20..20, scaled by 1e-4 for
integer types through `scaling`), written by this script in MRtrix's format (the header as
dwi2tensor writes it). The render is the default one (the middle axial slice, 320x240); its
JSON's peak_rss_bytes (the process's peak resident set, getrusage) is compared with the aim.

usage: python3 docs/bench/memory/datatypes.py [TG] > docs/bench/memory/datatypes.csv
"""
import gzip
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

TG = sys.argv[1] if len(sys.argv) > 1 else "target/release/tensorglyph"
DIMS = (200, 200, 50)
TYPES = ["Int8", "UInt8", "Int16LE", "UInt16LE", "Int32LE", "Float32LE", "Float64LE"]
NP = {"Int8": "i1", "UInt8": "u1", "Int16LE": "<i2", "UInt16LE": "<u2", "Int32LE": "<i4",
      "Float32LE": "<f4", "Float64LE": "<f8"}


def image(dt):
    nx, ny, nz = DIMS
    rng = np.random.default_rng(7)
    d = np.empty((6, nz, ny, nx))
    d[:3] = rng.uniform(10, 110, size=(3, nz, ny, nx))
    d[3:] = rng.uniform(-20, 20, size=(3, nz, ny, nx))
    if dt.startswith("Float"):
        data, scaling = (d * 1e-4).astype(NP[dt]), ""
    else:
        lo = 0 if dt.startswith("U") else -20
        data = np.clip(np.round(d), lo, 127).astype(NP[dt])
        scaling = "scaling: 0,0.0001\n"
    head = ("mrtrix image\ndim: %d,%d,%d,6\nvox: 1.25,1.25,1.25\nlayout: +0,+1,+2,+3\n"
            "datatype: %s\n%sfile: . " % (nx, ny, nz, dt, scaling))
    off = (len(head) + 20 + 15) // 16 * 16
    h = (head + "%d\nEND\n" % off).encode()
    return h + b"\0" * (off - len(h)) + data.tobytes(), data.nbytes


def main():
    print("datatype,gzip,data_bytes,file_bytes,peak_rss_bytes,aim_bytes,peak_over_aim")
    with tempfile.TemporaryDirectory() as tmp:
        for dt in TYPES:
            raw, nbytes = image(dt)
            for gz in (False, True):
                path = os.path.join(tmp, "t.mif.gz" if gz else "t.mif")
                with open(path, "wb") as f:
                    f.write(gzip.compress(raw, 1) if gz else raw)
                out = subprocess.run(
                    [TG, "render", path, "-o", os.path.join(tmp, "x.png"), "--size", "320x240",
                     "--json", "-q"], capture_output=True, text=True, check=True)
                peak = json.loads(out.stdout)["peak_rss_bytes"]
                aim = 64 * 2**20 + 8 * nbytes
                print("%s,%s,%d,%d,%d,%d,%.2f" % (dt, "yes" if gz else "no", nbytes,
                                                   os.path.getsize(path), peak, aim, peak / aim),
                      flush=True)
                os.remove(path)


if __name__ == "__main__":
    main()
