#!/usr/bin/python3
"""Writes the VTK scalar volumes in this folder with VTK's own writers, and `expected_vtk.json`
with what VTK's own readers read back: every point's position and value, in point order.

Run with Debian's VTK Python:  /usr/bin/python3 tests/data/scalars/make_vtk_scalars.py

- `image_extent_dir.vti`: XML image data whose extent starts at (2, 0, 1), with a rotated
  Direction, a 3-component point array first, then the one-component `fa` (float32) and
  `label` (uint8): the reader takes the first one-component array, `fa`.
- `image_u8.vtk`: legacy binary STRUCTURED_POINTS, SCALARS unsigned_char.
- `image_i16_ascii.vtk`: legacy ASCII STRUCTURED_POINTS, SCALARS short.
- `bad_vectors_only.vti`: image data with no one-component point array.
"""
import json
import math
import os
import random

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))
rnd = random.Random(11)
expected = {"files": {}}


def image(extent, origin, spacing, direction=None):
    im = vtk.vtkImageData()
    im.SetExtent(*extent)
    im.SetOrigin(*origin)
    im.SetSpacing(*spacing)
    if direction:
        im.SetDirectionMatrix(*direction)
    return im


def array(cls, name, ncomp, values):
    a = cls()
    a.SetName(name)
    a.SetNumberOfComponents(ncomp)
    for v in values:
        a.InsertNextTuple(v if ncomp > 1 else [v])
    return a


def record(name, reader, array_name):
    reader.SetFileName(os.path.join(HERE, name))
    reader.Update()
    ds = reader.GetOutput()
    a = ds.GetPointData().GetArray(array_name)
    n = ds.GetNumberOfPoints()
    expected["files"][name] = {
        "dims": list(ds.GetDimensions()),
        "array": array_name,
        "positions": [list(ds.GetPoint(i)) for i in range(n)],
        "values": [a.GetTuple1(i) for i in range(n)],
    }


# XML, extent not at 0, rotated.
c, s = math.cos(math.radians(25)), math.sin(math.radians(25))
im = image((2, 6, 0, 3, 1, 3), (1.0, -2.0, 0.5), (0.5, 0.25, 1.5), (c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c))
n = im.GetNumberOfPoints()
pd = im.GetPointData()
pd.AddArray(array(vtk.vtkFloatArray, "vec", 3, [[rnd.random() for _ in range(3)] for _ in range(n)]))
pd.AddArray(array(vtk.vtkFloatArray, "fa", 1, [rnd.random() for _ in range(n)]))
pd.AddArray(array(vtk.vtkUnsignedCharArray, "label", 1, [rnd.randrange(256) for _ in range(n)]))
w = vtk.vtkXMLImageDataWriter()
w.SetInputData(im)
w.SetFileName(os.path.join(HERE, "image_extent_dir.vti"))
w.Write()
record("image_extent_dir.vti", vtk.vtkXMLImageDataReader(), "fa")

# Legacy, binary and ASCII.
for name, cls, lo, hi, binary in [
    ("image_u8.vtk", vtk.vtkUnsignedCharArray, 0, 255, True),
    ("image_i16_ascii.vtk", vtk.vtkShortArray, -32768, 32767, False),
]:
    im = image((0, 4, 0, 3, 0, 2), (-3.0, 4.0, 1.25), (2.0, 2.5, 3.0))
    sc = array(cls, "values", 1, [rnd.randint(lo, hi) for _ in range(im.GetNumberOfPoints())])
    im.GetPointData().SetScalars(sc)
    w = vtk.vtkStructuredPointsWriter()
    w.SetInputData(im)
    w.SetFileName(os.path.join(HERE, name))
    if binary:
        w.SetFileTypeToBinary()
    w.Write()
    record(name, vtk.vtkStructuredPointsReader(), "values")

im = image((0, 2, 0, 2, 0, 1), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
im.GetPointData().AddArray(array(vtk.vtkFloatArray, "vec", 3, [[1.0, 2.0, 3.0]] * im.GetNumberOfPoints()))
w = vtk.vtkXMLImageDataWriter()
w.SetInputData(im)
w.SetFileName(os.path.join(HERE, "bad_vectors_only.vti"))
w.Write()

with open(os.path.join(HERE, "expected_vtk.json"), "w") as f:
    json.dump(expected, f, indent=1)
    f.write("\n")
