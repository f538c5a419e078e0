#!/usr/bin/env python3
"""VTK's own principal stresses and yield criteria of every stress field in the tests, the truth
for `--color von-mises | tresca | sigma1 | sigma2 | sigma3 | mean | triaxiality`, their colour
ranges and `info`'s stress numbers (tests/cli/stress_fields.rs).

    fem-env/bin/pip install vtk          # VTK >= 9.3 has vtkYieldCriteria (tested with 9.7.2)
    fem-env/bin/python tests/data/stress/yield_truth.py

For each field VTK reads the file (vtkXMLGenericDataObjectReader), the tensor array is handed
to vtkYieldCriteria (which runs vtkTensorPrincipalInvariants first) as VTK's six components
XX, YY, ZZ, XY, YZ, XZ (the filters take 6-component arrays only: a 9-component array is
checked to be symmetric and its upper triangle taken), and gives per tensor "Sigma 1" >=
"Sigma 2" >= "Sigma 3" (vtkMath::Diagonalize3x3, ordered largest first), "Tresca Criterion"
|sigma3 - sigma1| and "Von Mises Criterion" sqrt(((s1-s2)^2 + (s2-s3)^2 + (s1-s3)^2) / 2).
VTK has no filter for the mean stress and the triaxiality: vtkArrayCalculator forms them from
VTK's principal values, mean = (s1 + s2 + s3) / 3 and triaxiality = mean / von Mises.

yield_truth.json, per file: the array, its location, the number of valid (not all-zero)
tensors, the largest |sigma|; per sample (the 8 largest and 8 smallest von Mises stresses,
the 8 largest sigma1, the 8 smallest sigma3 and 32 at random, seed 2024; indices in file
order) the three principal stresses and the five measures; each measure's minimum and maximum
over the valid tensors, and its 2nd and 98th percentiles by nearest rank (the value at sorted
position round(q (n - 1)), halves away from zero, of the finite values), the default colour
range.
"""
import json
import os

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
FIELDS = ["pointload.vti", "beam.vtu", "cantilever_twist.vtu", "plate_hole.vtu",
          "notched_bar.vtu"]
MEASURES = ["sigma1", "sigma2", "sigma3", "von_mises", "tresca", "mean", "triaxiality"]
SEED = 2024


def locate(name):
    """Beside this script."""
    return os.path.join(HERE, name)


def active_tensors(data):
    """(attributes, array, 'point' | 'cell') of the active tensors."""
    for attrs, where in ((data.GetPointData(), "point"), (data.GetCellData(), "cell")):
        t = attrs.GetTensors()
        if t is not None:
            return attrs, t, where
    raise ValueError("no active tensors")


def calculator(data, where, variables, function, result):
    calc = vtk.vtkArrayCalculator()
    calc.SetInputData(data)
    if where == "cell":
        calc.SetAttributeTypeToCellData()
    else:
        calc.SetAttributeTypeToPointData()
    for var, array in variables.items():
        calc.AddScalarVariable(var, array, 0)
    calc.SetFunction(function)
    calc.SetResultArrayName(result)
    calc.SetResultArrayType(vtk.VTK_DOUBLE)
    calc.Update()
    return calc.GetOutput()


def truth(path):
    reader = vtk.vtkXMLGenericDataObjectReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    attrs, array, where = active_tensors(data)
    name = array.GetName()
    t = vtk_to_numpy(array).astype(np.float64)
    if t.shape[1] == 9:
        m = t.reshape(-1, 3, 3)
        scale = np.abs(m).max()
        assert np.abs(m - m.transpose(0, 2, 1)).max() <= 1e-12 * scale, f"{path}: not symmetric"
        six = np.stack([m[:, 0, 0], m[:, 1, 1], m[:, 2, 2], m[:, 0, 1], m[:, 1, 2], m[:, 0, 2]], 1)
    else:
        six = t
    s6 = numpy_to_vtk(np.ascontiguousarray(six), deep=True, array_type=vtk.VTK_DOUBLE)
    s6.SetName("S6")
    attrs.AddArray(s6)

    yc = vtk.vtkYieldCriteria()
    yc.SetInputData(data)
    yc.UpdateInformation()
    for sel in (yc.GetPointDataArraySelection(), yc.GetCellDataArraySelection()):
        sel.DisableAllArrays()
    (yc.GetCellDataArraySelection() if where == "cell"
     else yc.GetPointDataArraySelection()).EnableArray("S6")
    yc.GetCriteriaSelection().EnableAllArrays()
    yc.Update()
    out = yc.GetOutput()
    names = {"sigma1": "S6 - Sigma 1", "sigma2": "S6 - Sigma 2", "sigma3": "S6 - Sigma 3",
             "von_mises": "S6 - Von Mises Criterion", "tresca": "S6 - Tresca Criterion"}
    out = calculator(out, where, {"s1": names["sigma1"], "s2": names["sigma2"],
                                  "s3": names["sigma3"]}, "(s1+s2+s3)/3", "mean")
    out = calculator(out, where, {"m": "mean", "vm": names["von_mises"]}, "m/vm", "triaxiality")
    names.update(mean="mean", triaxiality="triaxiality")
    oattrs = out.GetCellData() if where == "cell" else out.GetPointData()
    values = {k: vtk_to_numpy(oattrs.GetArray(v)).astype(np.float64) for k, v in names.items()}

    valid = np.any(six != 0.0, axis=1)
    n = int(valid.sum())
    largest = float(np.abs(np.stack([values["sigma1"], values["sigma3"]])[:, valid]).max())
    vm = np.where(valid, values["von_mises"], np.nan)
    order = np.argsort(vm[valid])
    idx = np.flatnonzero(valid)
    pick = set(idx[order[-8:]]) | set(idx[order[:8]])
    pick |= set(idx[np.argsort(values["sigma1"][valid])[-8:]])
    pick |= set(idx[np.argsort(values["sigma3"][valid])[:8]])
    rest = np.setdiff1d(idx, sorted(pick))
    pick |= set(np.random.default_rng(SEED).choice(rest, 32, replace=False))
    samples = []
    for i in sorted(int(i) for i in pick):
        samples.append({"index": i, **{k: float(values[k][i]) for k in MEASURES}})

    def pct(v, q):
        v = np.sort(v[np.isfinite(v)])
        return float(v[int(np.floor(q * (len(v) - 1) + 0.5))])

    ranges, percentiles = {}, {}
    for k in MEASURES:
        v = values[k][valid]
        fin = v[np.isfinite(v)]
        ranges[k] = [float(fin.min()), float(fin.max())]
        percentiles[k] = [pct(v, 0.02), pct(v, 0.98)]
    return {
        "array": name, "location": where, "components": int(t.shape[1]), "valid": n,
        "max_abs_sigma": largest, "ranges": ranges, "percentiles_2_98": percentiles,
        "samples": samples,
    }


def main():
    out = {"vtk": vtk.vtkVersion.GetVTKVersion(), "fields": {}}
    for name in FIELDS:
        out["fields"][name] = truth(locate(name))
        f = out["fields"][name]
        print(f"{name}: {f['valid']} tensors ({f['location']}), {len(f['samples'])} samples, "
              f"max |sigma| {f['max_abs_sigma']:.4g}, von Mises {f['ranges']['von_mises']}")
    with open(os.path.join(HERE, "yield_truth.json"), "w") as fh:
        json.dump(out, fh, indent=1)
        fh.write("\n")


if __name__ == "__main__":
    main()
