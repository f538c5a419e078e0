#!/usr/bin/env python3
"""Three finite-element stress fields solved with scikit-fem, for the stress defaults and the
yield-criterion colourings (tests/stress_fields.rs, the book's "Stress and strain" chapter).

    python3 -m venv fem-env && fem-env/bin/pip install scikit-fem meshio vtk
    fem-env/bin/python tests/data/stress/make_fem_fields.py     # about a minute
    fem-env/bin/python tests/data/stress/yield_truth.py         # VTK's values, see there

(tested with scikit-fem 12.0.2, meshio 5.3.5, numpy 2.4.6, scipy 1.17.1). Linear elasticity,
three meshes, loads and element types, each written as a VTK XML UnstructuredGrid by meshio
(zlib-compressed, inline base64) beside this script:

cantilever_twist.vtu: a 6 x 1 x 1 m steel cantilever (E = 210 GPa, nu = 0.3) on 4,051 linear
  (P1) tetrahedra: the Delaunay tetrahedralisation (scipy's Qhull) of a 24 x 5 x 5 lattice,
  twice as fine along x near the clamp, each vertex moved at random by up to 0.3 of a cell
  (seed 7), so that the cell centres are as irregular as a mesher's.
  Clamped at x = 0; at x = 6 a downward traction of 1 MN in all (bending) plus a traction
  growing linearly from the axis, tau = 30 MPa/m x r, turning about +x (twist, 5 MN m).
  Cell data "stress (Pa)": the Cauchy stress of each cell (constant in a P1 element), 9
  components, row-major; "von_mises" (Pa).

plate_hole.vtu: a 200 x 200 x 10 mm plate with a central hole of radius 10 mm under a uniaxial
  tension of 100 MPa along x (applied on x = +-100 mm), steel in MPa (E = 210000, nu = 0.3), on
  1,792 trilinear hexahedra (an O-grid of 64 x 14 cells, graded towards the hole, 2 through the
  thickness); symmetry planes x = 0, y = 0, z = 0 hold it still. The stress at the quadrature
  points is L2-projected onto the trilinear nodal basis: point data "stress (MPa)", 6
  components in VTK's order XX, YY, ZZ, XY, YZ, XZ. Its truth is Kirsch's: sigma_xx at the
  top of the hole is 3 x 100 MPa in an infinite plate (3.03 for this width, Howland); the
  script prints the FE value and checks it within 10 %.

notched_bar.vtu: a 40 x 10 x 10 mm bar with a semicircular notch of radius 3 mm across its top
  face at mid-length, clamped at x = 0 and pulled by 100 MPa on x = 40 (MPa, mm, steel), on
  3,840 quadratic (P2) tetrahedra (a 40 x 4 x 4 tensor mesh graded towards the notch, split six
  ways, then bent to the notch's shape). The stress is evaluated at each cell's centroid:
  cell data "sigma", 9 components, row-major, no unit in its name (the units are given with
  --units MPa).

stress_fields.json: what each file holds (cells, tensors, location, array, units) and the
checks above.
"""
import json
import os

import meshio
import numpy as np
from scipy.spatial import Delaunay
from skfem import (Basis, ElementHex1, ElementTetP1, ElementTetP2, ElementVector,
                   FacetBasis, LinearForm, MeshHex, MeshTet, asm, condense, solve)
from skfem.helpers import sym_grad
from skfem.io.meshio import to_meshio
from skfem.models.elasticity import lame_parameters, linear_elasticity, linear_stress

HERE = os.path.dirname(os.path.abspath(__file__))


def von_mises(s):
    """von Mises stress of (n, 3, 3) tensors."""
    d = s - np.trace(s, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    return np.sqrt(1.5 * np.einsum("nij,nij->n", d, d))


def voigt6(s):
    """(n, 3, 3) symmetric tensors as VTK's six components XX, YY, ZZ, XY, YZ, XZ."""
    return np.stack([s[:, 0, 0], s[:, 1, 1], s[:, 2, 2], s[:, 0, 1], s[:, 1, 2], s[:, 0, 2]], 1)


def write(path, mesh, point_data=None, cell_data=None, active=None):
    m = to_meshio(mesh, point_data=point_data or {}, cell_data=cell_data or {})
    meshio.write(path, m, file_format="vtu", binary=True, compression="zlib")
    if active:
        # meshio sets no active attributes; mark the tensors (the header is plain XML).
        where, name = active
        with open(path, "r", encoding="ascii") as fh:
            text = fh.read()
        tag = f"<{where}>"
        assert text.count(tag) == 1, "unexpected meshio output"
        text = text.replace(tag, f'<{where} Tensors="{name}">')
        with open(path, "w", encoding="ascii") as fh:
            fh.write(text)


def elasticity(mesh, elem, E, nu):
    basis = Basis(mesh, ElementVector(elem))
    lam, mu = lame_parameters(E, nu)
    return basis, lam, mu, asm(linear_elasticity(lam, mu), basis)


def cell_stress(mesh, elem, u, lam, mu, centroid):
    """The Cauchy stress at each cell's centroid (reference coordinates `centroid`)."""
    quad = (np.array(centroid, dtype=float).reshape(-1, 1), np.array([1.0]))
    b = Basis(mesh, ElementVector(elem), quadrature=quad)
    s = linear_stress(lam, mu)(sym_grad(b.interpolate(u)))  # (3, 3, cells, 1)
    return np.ascontiguousarray(s[:, :, :, 0].transpose(2, 0, 1))


def delaunay_box(L, B, H, nx, ny, nz, seed):
    """Tetrahedra of a box as a mesher makes them: the Delaunay tetrahedralisation (scipy's
    Qhull) of a lattice of nx x ny x nz cells, twice as fine along x near x = 0, each vertex
    moved at random by up to 0.3 of a cell within its face, edge or the interior."""
    u = np.linspace(0, 1, nx + 1)
    xs = L * (0.5 * u + 0.5 * u * u)
    p = np.array(np.meshgrid(xs, np.linspace(0, B, ny + 1), np.linspace(0, H, nz + 1),
                             indexing="ij")).reshape(3, -1)
    step = np.array([np.gradient(xs)[np.searchsorted(xs, p[0])], np.full(p.shape[1], B / ny),
                     np.full(p.shape[1], H / nz)])
    free = np.array([(p[0] > 0) & (p[0] < L), (p[1] > 0) & (p[1] < B), (p[2] > 0) & (p[2] < H)])
    rng = np.random.default_rng(seed)
    p = p + free * step * rng.uniform(-0.3, 0.3, p.shape)
    t = Delaunay(p.T).simplices.T
    # Qhull may leave flat tetrahedra on the faces: drop them.
    a, b, c, d = (p[:, t[k]] for k in range(4))
    vol = np.abs(np.einsum("ij,ij->j", np.cross(b - a, c - a, axis=0), d - a)) / 6
    t = t[:, vol > 1e-6 * (L / nx) * (B / ny) * (H / nz)]
    return MeshTet(p, t)


def cantilever_twist():
    L, B, H = 6.0, 1.0, 1.0
    E, NU = 210e9, 0.3
    F, TAU = 1.0e6, 30.0e6  # end load (N), twist traction per metre from the axis (Pa/m)
    mesh = delaunay_box(L, B, H, 24, 5, 5, seed=7)
    basis, lam, mu, K = elasticity(mesh, ElementTetP1(), E, NU)
    end = FacetBasis(mesh, basis.elem, facets=mesh.facets_satisfying(lambda x: np.isclose(x[0], L)))

    @LinearForm
    def load(v, w):
        y, z = w.x[1] - B / 2, w.x[2] - H / 2
        # Bending: -z; twist about +x: (0, -z, y) tau.
        return -F / (B * H) * v[2] + TAU * (-z * v[1] + y * v[2])

    f = asm(load, end)
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    u = solve(*condense(K, f, D=clamped))
    sigma = cell_stress(mesh, ElementTetP1(), u, lam, mu, [0.25, 0.25, 0.25])
    path = os.path.join(HERE, "cantilever_twist.vtu")
    write(path, mesh, cell_data={"stress (Pa)": [sigma.reshape(-1, 9)],
                                 "von_mises": [von_mises(sigma)]},
          active=("CellData", "stress (Pa)"))
    torque = TAU * (B * H**3 + H * B**3) / 12
    # Beam theory a section away from the clamp: bending M c / I, twist tau_max = T / (0.208 a^3).
    x = mesh.p[:, mesh.t].mean(axis=1)
    mid = np.abs(x[0] - L / 2) < 0.25
    return path, {
        "mesh": "P1 tetrahedra", "cells": int(mesh.nelements), "tensors": int(mesh.nelements),
        "location": "cell", "array": "stress (Pa)", "components": 9, "units": "Pa",
        "load": {"end_force_N": F, "torque_Nm": torque},
        "mid_span": {
            "fe_max_abs_sigma_xx": float(np.abs(sigma[mid, 0, 0]).max()),
            "bending_Mc_over_I": F * (L / 2) * (H / 2) / (B * H**3 / 12),
            "fe_max_shear": float(np.hypot(sigma[mid, 0, 1], sigma[mid, 0, 2]).max()),
            "torsion_T_over_0.208a3": torque / (0.208 * B**3),
        },
    }


def o_grid(a, w, t, n_theta, n_r, n_z, grading):
    """Hexahedra filling the square [-w, w]^2 minus the disc of radius a, t thick: rays from
    the hole to the square's edge, nodes spaced geometrically outward."""
    logical = MeshHex.init_tensor(np.arange(n_theta + 1, dtype=float),
                                  np.arange(n_r + 1, dtype=float),
                                  np.linspace(-t / 2, t / 2, n_z + 1))
    i, j, z = logical.p
    theta = 2 * np.pi * i / n_theta
    s = (grading ** j - 1) / (grading ** n_r - 1)
    c, sn = np.cos(theta), np.sin(theta)
    edge = w / np.maximum(np.abs(c), np.abs(sn))
    radius = (1 - s) * a + s * edge
    p = np.vstack([radius * c, radius * sn, z])
    # Close the ring: the last column of nodes is the first.
    key = np.where(np.isclose(i, n_theta), 0, i)
    ids = {}
    remap = np.empty(len(i), dtype=np.int64)
    for n in range(len(i)):
        k = (int(key[n]), int(round(j[n])), round(float(z[n]), 9))
        remap[n] = ids.setdefault(k, len(ids))
    pts = np.zeros((3, len(ids)))
    pts[:, remap] = p
    return MeshHex(pts, remap[logical.t])


def plate_hole():
    A, W, T = 10.0, 100.0, 10.0  # hole radius, half width, thickness (mm)
    E, NU, S = 210000.0, 0.3, 100.0  # MPa
    mesh = o_grid(A, W, T, 64, 14, 2, 1.22)
    basis, lam, mu, K = elasticity(mesh, ElementHex1(), E, NU)
    ends = FacetBasis(mesh, basis.elem,
                      facets=mesh.facets_satisfying(lambda x: np.isclose(np.abs(x[0]), W)))

    @LinearForm
    def load(v, w):
        return S * np.sign(w.x[0]) * v[0]

    f = asm(load, ends)
    dofs = basis.get_dofs
    fixed = np.concatenate([
        dofs(lambda x: np.isclose(x[0], 0.0)).nodal["u^1"],
        dofs(lambda x: np.isclose(x[1], 0.0)).nodal["u^2"],
        dofs(lambda x: np.isclose(x[2], 0.0)).nodal["u^3"],
    ])
    u = solve(*condense(K, f, D=fixed))
    sigma_qp = linear_stress(lam, mu)(sym_grad(basis.interpolate(u)))
    nodal = basis.with_element(ElementHex1())
    sigma = np.zeros((mesh.nvertices, 3, 3))
    for a in range(3):
        for b in range(a, 3):
            sigma[:, a, b] = sigma[:, b, a] = nodal.project(sigma_qp[a, b])
    path = os.path.join(HERE, "plate_hole.vtu")
    write(path, mesh, point_data={"stress (MPa)": voigt6(sigma)},
          active=("PointData", "stress (MPa)"))
    top = np.isclose(mesh.p[0], 0.0) & np.isclose(mesh.p[1], A) & np.isclose(mesh.p[2], 0.0)
    kt = float(sigma[top, 0, 0].mean() / S)
    d_over_w = A / W
    howland = (2 + (1 - d_over_w) ** 3) / (1 - d_over_w)  # Heywood's fit, on the gross section
    assert abs(kt - howland) < 0.1 * howland, f"plate: Kt {kt} vs {howland}"
    return path, {
        "mesh": "trilinear hexahedra", "cells": int(mesh.nelements),
        "tensors": int(mesh.nvertices), "location": "point", "array": "stress (MPa)",
        "components": 6, "units": "MPa",
        "kirsch": {"fe_sigma_xx_top_of_hole_over_s": kt, "infinite_plate": 3.0,
                   "finite_width_heywood": howland},
    }


def notched_bar():
    L, B, H, R = 40.0, 10.0, 10.0, 3.0  # length, width, height, notch radius (mm)
    E, NU, S = 210000.0, 0.3, 100.0
    # x nodes denser near the notch (x = L/2).
    u = np.linspace(-1, 1, 41)
    xs = L / 2 + L / 2 * np.sign(u) * np.abs(u) ** 1.6
    mesh = MeshTet.init_tensor(xs, np.linspace(0, B, 5), np.linspace(0, H, 5))
    p = mesh.p.copy()
    depth = R * np.sqrt(np.clip(1 - ((p[0] - L / 2) / R) ** 2, 0, None))
    p[2] = p[2] * (H - depth) / H
    mesh = MeshTet(p, mesh.t)
    elem = ElementTetP2()
    basis, lam, mu, K = elasticity(mesh, elem, E, NU)
    end = FacetBasis(mesh, basis.elem, facets=mesh.facets_satisfying(lambda x: np.isclose(x[0], L)))

    @LinearForm
    def load(v, w):
        return S * v[0]

    f = asm(load, end)
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    disp = solve(*condense(K, f, D=clamped))
    sigma = cell_stress(mesh, elem, disp, lam, mu, [0.25, 0.25, 0.25])
    path = os.path.join(HERE, "notched_bar.vtu")
    write(path, mesh, cell_data={"sigma": [sigma.reshape(-1, 9)]}, active=("CellData", "sigma"))
    # The net section's nominal stress and the largest sigma_xx at the notch root.
    x = mesh.p[:, mesh.t].mean(axis=1)
    root = np.abs(x[0] - L / 2) < 1.0
    nominal = S * H / (H - R)
    return path, {
        "mesh": "quadratic (P2) tetrahedra", "cells": int(mesh.nelements),
        "tensors": int(mesh.nelements), "location": "cell", "array": "sigma", "components": 9,
        "units": None,
        "notch": {"fe_max_sigma_xx_at_root": float(sigma[root, 0, 0].max()),
                  "net_section_nominal": nominal,
                  "ratio": float(sigma[root, 0, 0].max() / nominal)},
    }


def main():
    report = {}
    for make in (cantilever_twist, plate_hole, notched_bar):
        path, info = make()
        name = os.path.basename(path)
        info["bytes"] = os.path.getsize(path)
        report[name] = info
        print(name, json.dumps(info))
    with open(os.path.join(HERE, "stress_fields.json"), "w") as fh:
        json.dump(report, fh, indent=1)
        fh.write("\n")


if __name__ == "__main__":
    main()
