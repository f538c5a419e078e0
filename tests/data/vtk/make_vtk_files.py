#!/usr/bin/python3
"""Write small tensor fields with VTK's own writers, in every format the reader supports, and
record VTK's own read-back values in expected.json.

Run with Debian's VTK Python:  /usr/bin/python3 tests/data/vtk/make_vtk_files.py
Deterministic: the same VTK version writes the same bytes.
"""
import json
import math
import os
import sys

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))


# ---------------------------------------------------------------- values
def tensor9(i, salt):
    """Deterministic 9-component tensor: mostly symmetric with mixed-sign eigenvalues, every
    fourth one non-symmetric."""
    c = [round(2.5 * math.sin(1.7 * i + 0.9 * k + salt), 4) for k in range(9)]
    if i % 4 != 1:  # symmetrise
        for (a, b) in [(1, 3), (2, 6), (5, 7)]:
            c[b] = c[a]
    return c


def tensor6(i, salt):
    return [round(2.0 * math.cos(1.3 * i + 0.7 * k + salt) + (1.5 if k < 3 else 0.0), 4) for k in range(6)]


def make_array(name, ncomp, n, salt, special):
    a = vtk.vtkFloatArray()
    a.SetName(name)
    a.SetNumberOfComponents(ncomp)
    a.SetNumberOfTuples(n)
    for i in range(n):
        v = tensor9(i, salt) if ncomp == 9 else tensor6(i, salt)
        if special and i == 3:
            v = [0.0] * ncomp  # the all-zero tensor
        if special == "nan" and i == 5:
            v[0] = float("nan")
        a.SetTuple(i, v)
    return a


def add_arrays(ds, active_point, active_cell, special, extra=False):
    """Point arrays: pressure (1), stress (9), dti (6). Cell arrays: cellstress (9), celldti (6).
    With `extra`: also an id array (vtkIdType) and a string array before the tensors and a
    Float64 'dti64' (6)."""
    n, m = ds.GetNumberOfPoints(), ds.GetNumberOfCells()
    pd, cd = ds.GetPointData(), ds.GetCellData()
    p = vtk.vtkFloatArray()
    p.SetName("pressure")
    for i in range(n):
        p.InsertNextValue(0.5 * i)
    pd.AddArray(p)
    if extra:
        ids = vtk.vtkIdTypeArray()
        ids.SetName("ids")
        for i in range(n):
            ids.InsertNextValue(1000 + i)
        pd.AddArray(ids)
        labels = vtk.vtkStringArray()
        labels.SetName("labels")
        for i in range(n):
            labels.InsertNextValue(["", "a b", "x" * (70 + i)][i % 3])  # empty, space, long
        pd.AddArray(labels)
    for name, nc, salt in [("stress", 9, 0.1), ("dti", 6, 0.2)]:
        arr = make_array(name, nc, n, salt, special)
        if active_point == name:
            pd.SetTensors(arr)
        else:
            pd.AddArray(arr)
    if extra:
        d = vtk.vtkDoubleArray()
        d.SetName("dti64")
        d.SetNumberOfComponents(6)
        for i in range(n):
            d.InsertNextTuple([v + 1e-9 * (k + 1) for k, v in enumerate(tensor6(i, 0.5))])
        pd.AddArray(d)
    if m:
        for name, nc, salt in [("cellstress", 9, 0.3), ("celldti", 6, 0.4)]:
            arr = make_array(name, nc, m, salt, None)
            if active_cell == name:
                cd.SetTensors(arr)
            else:
                cd.AddArray(arr)


# ---------------------------------------------------------------- datasets
def image(direction):
    im = vtk.vtkImageData()
    im.SetDimensions(4, 3, 3)
    im.SetOrigin(1.0, -2.0, 0.5)
    im.SetSpacing(0.5, 0.25, 1.0)
    if direction:
        c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
        im.SetDirectionMatrix(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    return im


def rectilinear():
    g = vtk.vtkRectilinearGrid()
    g.SetDimensions(4, 3, 3)
    for axis, setter, vals in [("x", g.SetXCoordinates, [0.0, 0.3, 1.0, 1.2]),
                               ("y", g.SetYCoordinates, [0.0, 0.5, 0.75]),
                               ("z", g.SetZCoordinates, [-1.0, 0.0, 2.0])]:
        a = vtk.vtkFloatArray()
        a.SetName(axis + "_coordinates")  # unnamed arrays get a pointer-based name
        for v in vals:
            a.InsertNextValue(v)
        setter(a)
    return g


def warped_points(nx, ny, nz):
    pts = vtk.vtkPoints()
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                pts.InsertNextPoint(i + 0.1 * j * j, j + 0.05 * i * k, 0.8 * k + 0.1 * i)
    return pts


def structured():
    g = vtk.vtkStructuredGrid()
    g.SetDimensions(3, 3, 3)
    g.SetPoints(warped_points(3, 3, 3))
    return g


def unstructured():
    g = vtk.vtkUnstructuredGrid()
    g.SetPoints(warped_points(3, 3, 3))

    def p(i, j, k):
        return i + 3 * j + 9 * k

    def cube(i, j, k):
        return [p(i, j, k), p(i + 1, j, k), p(i + 1, j + 1, k), p(i, j + 1, k),
                p(i, j, k + 1), p(i + 1, j, k + 1), p(i + 1, j + 1, k + 1), p(i, j + 1, k + 1)]

    cells = [
        (vtk.VTK_HEXAHEDRON, cube(0, 0, 0)),
        (vtk.VTK_HEXAHEDRON, cube(1, 0, 0)),
        (vtk.VTK_TETRA, [p(0, 1, 0), p(1, 1, 0), p(0, 2, 0), p(0, 1, 1)]),
        (vtk.VTK_WEDGE, [p(1, 1, 0), p(2, 1, 0), p(1, 2, 0), p(1, 1, 1), p(2, 1, 1), p(1, 2, 1)]),
        (vtk.VTK_PYRAMID, [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1), p(0, 0, 2)]),
        (vtk.VTK_TETRA, [p(2, 2, 1), p(1, 2, 2), p(2, 1, 2), p(2, 2, 2)]),
        (vtk.VTK_HEXAHEDRON, cube(1, 1, 1)),
        (vtk.VTK_TRIANGLE, [p(0, 2, 2), p(1, 2, 2), p(0, 1, 2)]),
    ]
    for t, ids in cells:
        g.InsertNextCell(t, len(ids), ids)
    return g


def polydata():
    pd = vtk.vtkPolyData()
    pts = warped_points(4, 3, 2)
    pd.SetPoints(pts)
    verts = vtk.vtkCellArray()
    for i in range(pts.GetNumberOfPoints()):
        verts.InsertNextCell(1, [i])
    pd.SetVerts(verts)
    polys = vtk.vtkCellArray()
    polys.InsertNextCell(3, [0, 1, 4])
    polys.InsertNextCell(4, [12, 13, 17, 16])
    pd.SetPolys(polys)
    return pd


KINDS = {
    "image": lambda: image(False),
    "rect": rectilinear,
    "sgrid": structured,
    "ugrid": unstructured,
    "poly": polydata,
}
XML_EXT = {"image": "vti", "rect": "vtr", "sgrid": "vts", "ugrid": "vtu", "poly": "vtp"}


# ---------------------------------------------------------------- read-back
def read_back(path):
    if path.endswith(".vtk"):
        r = vtk.vtkDataSetReader()
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllTensorsOn()
        r.ReadAllFieldsOn()
    elif path.endswith(".pvti"):
        r = vtk.vtkXMLPImageDataReader()
    else:
        r = vtk.vtkXMLGenericDataObjectReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def tensor_arrays(ds):
    """All 9/6-component arrays in pick order: active point, active cell, then point, cell arrays."""
    out = []
    for loc, data in [("point", ds.GetPointData()), ("cell", ds.GetCellData())]:
        t = data.GetTensors()
        if t is not None and t.GetNumberOfComponents() in (6, 9):
            out.append((loc, t.GetName(), True))
    for loc, data in [("point", ds.GetPointData()), ("cell", ds.GetCellData())]:
        for k in range(data.GetNumberOfArrays()):
            a = data.GetArray(k)
            if a is not None and a.GetNumberOfComponents() in (6, 9):
                if (loc, a.GetName(), True) not in out:
                    out.append((loc, a.GetName(), False))
    return out


def jnum(v):
    return "nan" if math.isnan(v) else v


def expand6(c):
    xx, yy, zz, xy, yz, xz = c
    return [xx, xy, xz, xy, yy, yz, xz, yz, zz]


def describe(path, fmt, dataset, centres_of=None):
    """VTK's read-back of `path`. `centres_of`: compute cell centres on this dataset instead
    (same cells in the same order) when VTK's reader gets the cell connectivity wrong."""
    ds = read_back(path)
    n, m = ds.GetNumberOfPoints(), ds.GetNumberOfCells()
    centres = None
    if m:
        cc = vtk.vtkCellCenters()
        cc.SetInputData(centres_of if centres_of is not None else ds)
        cc.VertexCellsOff()
        cc.Update()
        centres = cc.GetOutput()
    arrays = []
    for loc, name, _active in tensor_arrays(ds):
        data = ds.GetPointData() if loc == "point" else ds.GetCellData()
        a = data.GetArray(name)
        nt = a.GetNumberOfTuples()
        idx = sorted({0, 1, 3, 5, nt // 2, nt - 1} & set(range(nt)))
        samples = []
        for i in idx:
            pos = ds.GetPoint(i) if loc == "point" else centres.GetPoint(i)
            c = list(a.GetTuple(i))
            t = c if len(c) == 9 else expand6(c)
            samples.append({"index": i, "position": list(pos), "tensor": [jnum(v) for v in t]})
        arrays.append({"name": name, "components": a.GetNumberOfComponents(), "location": loc,
                       "tuples": nt, "samples": samples})
    dims = None
    if dataset in ("ImageData", "RectilinearGrid", "StructuredGrid"):
        dims = list(ds.GetDimensions())
    entry = {"format": fmt, "dataset": dataset, "points": n, "cells": m, "dims": dims,
             "default": arrays[0]["name"] if arrays else None, "arrays": arrays}
    if dataset == "ImageData":
        entry["origin"] = list(ds.GetOrigin())
        entry["spacing"] = list(ds.GetSpacing())
        d = ds.GetDirectionMatrix()
        entry["direction"] = [[d.GetElement(i, j) for j in range(3)] for i in range(3)]
    return entry


DATASET_NAME = {"image": "ImageData", "rect": "RectilinearGrid", "sgrid": "StructuredGrid",
                "ugrid": "UnstructuredGrid", "poly": "PolyData"}


# ---------------------------------------------------------------- writing
def main():
    expected = {}
    for f in os.listdir(HERE):
        if f.endswith((".vtk", ".vti", ".vtr", ".vts", ".vtu", ".vtp", ".pvti")):
            os.remove(os.path.join(HERE, f))

    # Legacy: (kind, active point tensors, active cell tensors, tag)
    legacy_cases = [
        ("image", "stress", None, "T9"),
        ("image", "dti", None, "T6"),
        ("image", None, "cellstress", "cellT9"),
        ("image", None, None, "field"),
        ("rect", "stress", None, "T9"),
        ("sgrid", "dti", None, "T6"),
        ("ugrid", "stress", None, "T9"),
        ("ugrid", None, "celldti", "cellT6"),
        ("poly", "stress", None, "T9"),
        ("poly", None, None, "field"),
    ]
    for version in (42, 51):
        for binary in (False, True):
            for kind, ap, ac, tag in legacy_cases:
                ds = KINDS[kind]()
                add_arrays(ds, ap, ac, "nan" if binary else "zero", extra=(tag == "field"))
                enc = "bin" if binary else "ascii"
                name = f"legacy{version}_{enc}_{kind}_{tag}.vtk"
                path = os.path.join(HERE, name)
                w = vtk.vtkDataSetWriter()
                w.SetFileVersion(version)
                w.SetInputData(ds)
                w.SetFileName(path)
                if binary:
                    w.SetFileTypeToBinary()
                else:
                    w.SetFileTypeToASCII()
                assert w.Write() == 1, name
                expected[name] = describe(path, "legacy-binary" if binary else "legacy-ascii",
                                          DATASET_NAME[kind])

    # XML: (mode, encode appended, compressor, header)
    xml_modes = [
        ("ascii", None, None, 32),
        ("binary", None, None, 32),
        ("binary", None, "zlib", 64),
        ("binary", None, "lzma", 32),
        ("appended", True, "lz4", 32),
        ("appended", True, None, 64),
        ("appended", False, None, 64),
        ("appended", False, "zlib", 32),
        ("appended", False, "lzma", 64),
        ("appended", False, "lz4", 64),
    ]
    writers = {"image": vtk.vtkXMLImageDataWriter, "rect": vtk.vtkXMLRectilinearGridWriter,
               "sgrid": vtk.vtkXMLStructuredGridWriter, "ugrid": vtk.vtkXMLUnstructuredGridWriter,
               "poly": vtk.vtkXMLPolyDataWriter}

    def configure(w, mode, enc, comp, header):
        {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary,
         "appended": w.SetDataModeToAppended}[mode]()
        if enc is not None:
            w.SetEncodeAppendedData(enc)
        {None: w.SetCompressorTypeToNone, "zlib": w.SetCompressorTypeToZLib,
         "lz4": w.SetCompressorTypeToLZ4, "lzma": w.SetCompressorTypeToLZMA}[comp]()
        if header == 64:
            w.SetHeaderTypeToUInt64()
        else:
            w.SetHeaderTypeToUInt32()

    for mi, (mode, enc, comp, header) in enumerate(xml_modes):
        for kind in KINDS:
            ds = image(mi % 2 == 1) if kind == "image" else KINDS[kind]()
            # alternate: active point tensors / active cell tensors / plain arrays only
            ap, ac = [("stress", None), (None, "cellstress"), (None, None), ("dti", None)][mi % 4]
            add_arrays(ds, ap, ac, "zero" if mode == "ascii" else "nan", extra=mi in (0, 2, 6))
            tag = mode if mode != "appended" else ("appb64" if enc else "appraw")
            name = f"xml_{kind}_{tag}_{comp or 'none'}_u{header}.{XML_EXT[kind]}"
            path = os.path.join(HERE, name)
            w = writers[kind]()
            w.SetInputData(ds)
            w.SetFileName(path)
            configure(w, mode, enc, comp, header)
            assert w.Write() == 1, name
            expected[name] = describe(path, XML_EXT[kind], DATASET_NAME[kind])

    # Big-endian XML.
    for kind, mode, enc, comp in [("image", "binary", None, "zlib"), ("ugrid", "appended", False, None)]:
        ds = image(True) if kind == "image" else KINDS[kind]()
        add_arrays(ds, "stress", "celldti", "nan", extra=True)
        tag = mode if mode != "appended" else "appraw"
        name = f"xml_{kind}_{tag}_{comp or 'none'}_bigendian.{XML_EXT[kind]}"
        path = os.path.join(HERE, name)
        w = writers[kind]()
        w.SetInputData(ds)
        w.SetFileName(path)
        configure(w, mode, enc, comp, 64)
        w.SetByteOrderToBigEndian()
        assert w.Write() == 1, name
        expected[name] = describe(path, XML_EXT[kind], DATASET_NAME[kind])

    # Serial files with two pieces (cut by VTK's piece extractors).
    for kind, extractor in [("ugrid", vtk.vtkExtractUnstructuredGridPiece),
                            ("poly", vtk.vtkExtractPolyDataPiece)]:
        ds = KINDS[kind]()
        add_arrays(ds, None, "cellstress", "nan")
        ex = extractor()
        ex.SetInputData(ds)
        name = f"xml_{kind}_2pieces_appraw_zlib_u64.{XML_EXT[kind]}"
        path = os.path.join(HERE, name)
        w = writers[kind]()
        w.SetInputConnection(ex.GetOutputPort())
        w.SetFileName(path)
        w.SetNumberOfPieces(2)
        configure(w, "appended", False, "zlib", 64)
        assert w.Write() == 1, name
        # VTK 9.1's vtkXMLPolyDataReader scrambles the polygon connectivity of the second piece
        # when it merges pieces (cell 24 becomes triangle 11-12-13 instead of 0-1-4), so take
        # the cell centres from the dataset that was written (the pieces keep its cell order:
        # verts of both pieces, then polys). Values, counts and order come from the read-back.
        expected[name] = describe(path, XML_EXT[kind], DATASET_NAME[kind],
                                  centres_of=ds if kind == "poly" else None)

    # Parallel image data: 2 or 3 pieces beside the .pvti.
    for pi, (pieces, mode, enc, comp, header, direction) in enumerate([
            (2, "appended", False, "zlib", 64, True),
            (3, "binary", None, None, 32, False)]):
        ds = image(direction)
        ds.SetDimensions(5, 4, 3)
        add_arrays(ds, "stress" if pi == 0 else None, None if pi == 0 else "celldti", "nan")
        name = f"pvti_{pieces}pieces_{mode}.pvti"
        path = os.path.join(HERE, name)
        # vtkXMLPImageDataWriter on an in-memory image writes the whole extent into every piece,
        # so cut the pieces with vtkExtractVOI, write each with VTK's serial writer, and write
        # the small .pvti index the way VTK 9.1's vtkXMLPImageDataWriter does (it writes no
        # Direction attribute, and vtkXMLPImageDataReader ignores the pieces' Direction).
        whole = [0, 4, 0, 3, 0, 2]
        axis = 0 if pieces == 2 else 1
        cuts = [0, 2, 4] if pieces == 2 else [0, 1, 2, 3]
        extents, sources = [], []
        for p in range(pieces):
            ext = list(whole)
            ext[2 * axis], ext[2 * axis + 1] = cuts[p], cuts[p + 1]
            voi = vtk.vtkExtractVOI()
            voi.SetInputData(ds)
            voi.SetVOI(*ext)
            voi.Update()
            src = f"{name[:-5]}_{p}.vti"
            w = vtk.vtkXMLImageDataWriter()
            w.SetInputData(voi.GetOutput())
            w.SetFileName(os.path.join(HERE, src))
            configure(w, mode, enc, comp, header)
            assert w.Write() == 1, src
            extents.append(" ".join(map(str, ext)))
            sources.append(src)
        pd_active = ' Tensors="stress"' if pi == 0 else ""
        cd_active = ' Tensors="celldti"' if pi == 1 else ""
        lines = [
            '<?xml version="1.0"?>',
            f'<VTKFile type="PImageData" version="1.0" byte_order="LittleEndian" header_type="UInt{header}">',
            f'  <PImageData WholeExtent="{" ".join(map(str, whole))}" GhostLevel="0" Origin="1 -2 0.5" '
            f'Spacing="0.5 0.25 1">',  # VTK 9.1 writes no Direction here
            f'    <PPointData{pd_active}>',
            '      <PDataArray type="Float32" Name="pressure"/>',
            '      <PDataArray type="Float32" Name="stress" NumberOfComponents="9"/>',
            '      <PDataArray type="Float32" Name="dti" NumberOfComponents="6"/>',
            '    </PPointData>',
            f'    <PCellData{cd_active}>',
            '      <PDataArray type="Float32" Name="cellstress" NumberOfComponents="9"/>',
            '      <PDataArray type="Float32" Name="celldti" NumberOfComponents="6"/>',
            '    </PCellData>',
        ] + [f'    <Piece Extent="{e}" Source="{s_}"/>' for e, s_ in zip(extents, sources)] + [
            '  </PImageData>',
            '</VTKFile>',
        ]
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
        expected[name] = describe(path, "pvti", "ImageData")

    with open(os.path.join(HERE, "expected.json"), "w") as f:
        f.write("{\n")
        f.write(",\n".join(json.dumps(k) + ": " + json.dumps(v, separators=(",", ":"))
                            for k, v in sorted(expected.items())))
        f.write("\n}\n")
    print(f"wrote {len(expected)} files", file=sys.stderr)


if __name__ == "__main__":
    main()
