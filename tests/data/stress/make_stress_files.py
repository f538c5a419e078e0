#!/usr/bin/python3
"""Stress fields written by VTK itself, for the scaling tests (tests/cli/scaling.rs).

Run with Debian's VTK Python:  /usr/bin/python3 tests/data/stress/make_stress_files.py

pointload.vti: vtkPointLoad, Boussinesq's solution for a point load on an elastic half-space
(stress ~ 1/r² near the load, a singularity at the load): 20×20×20 samples of the 9-component
stress tensor over [-10, 10]³, load 100, Poisson's ratio 0.3 (VTK's default). Its eigenvalues
span four orders of magnitude and almost every tensor is indefinite.
"""
import os

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))


def point_load(path):
    src = vtk.vtkPointLoad()
    src.SetLoadValue(100.0)
    src.SetSampleDimensions(20, 20, 20)
    src.SetModelBounds(-10, 10, -10, 10, -10, 10)
    src.Update()
    w = vtk.vtkXMLImageDataWriter()
    w.SetFileName(path)
    w.SetInputConnection(src.GetOutputPort())
    w.Write()


if __name__ == "__main__":
    point_load(os.path.join(HERE, "pointload.vti"))
