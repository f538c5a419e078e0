#!/usr/bin/env python3
"""A real finite-element stress field: a 3-D cantilever beam solved with scikit-fem.

Run with a Python that has scipy (the pyenv `python3` here; Debian's /usr/bin/python3 has VTK
but no scipy, and VTK is not needed: meshio writes the file):

    python3 -m pip install scikit-fem meshio      # tested with scikit-fem 12.0.2, meshio 5.3.5
    python3 tests/data/stress/make_beam.py

It takes about a minute (most of it scipy's sparse direct solve) and writes, beside this script:

beam.vtu: VTK XML UnstructuredGrid (meshio, zlib-compressed inline base64) of a 10 x 1 x 1 m
steel beam (E = 210 GPa, nu = 0.3), 60 x 6 x 6 = 2160 hexahedra, 61 x 7 x 7 = 2989 points,
clamped (u = 0) on its x = 0 face and loaded by a uniform downward (-z) traction on its x = 10
face totalling F = 1 MN. Displacements are trilinear (8-node hexahedra, fully integrated; with
6 elements through the depth their shear locking stiffens the beam by only ~2 %, and scikit-fem's
27-node hexahedra assemble far too slowly). The Cauchy stress sigma = lambda tr(eps) I + 2 mu eps
is computed at the quadrature points and L2-projected onto the same trilinear nodal basis,
giving one tensor per mesh point.
Point data:
  stress        9 components, row-major 3x3 (symmetric), Pa; the active tensors
  displacement  3 components, m; the active vectors
  von_mises     1 component, Pa
Point i of the file is mesh vertex i in scikit-fem's order; the JSON's indices are into the
file's points (its positions are given too).

beam_expected.json: truth computed in numpy from the arrays read back from beam.vtu: the tensor
count, and for the 5 points with the largest von Mises stress and 5 random points (seed 12345)
the index, position, tensor and its eigenvalues (numpy.linalg.eigvalsh, descending); plus a
check against Euler-Bernoulli beam theory, sigma_xx = M c / I with M = F (L - x), c = H / 2,
I = B H^3 / 12. At the clamp the FE value is larger than the estimate (the clamp's restraint of
the Poisson contraction concentrates stress at the edges); a beam depth or more away the two
agree within a few per cent.
"""
import json
import os

import meshio
import numpy as np
from skfem import (Basis, ElementHex1, ElementVector, FacetBasis, LinearForm,
                   MeshHex, asm, condense, solve)
from skfem.helpers import sym_grad
from skfem.io.meshio import to_meshio
from skfem.models.elasticity import lame_parameters, linear_elasticity, linear_stress

HERE = os.path.dirname(os.path.abspath(__file__))

L, B, H = 10.0, 1.0, 1.0  # length (x), width (y), height (z), m
NX, NY, NZ = 60, 6, 6  # elements along each axis
E, NU = 210e9, 0.3  # Young's modulus (Pa), Poisson's ratio
F = 1.0e6  # total downward end load, N
SEED = 12345


def solve_beam():
    mesh = MeshHex.init_tensor(np.linspace(0, L, NX + 1), np.linspace(0, B, NY + 1),
                               np.linspace(0, H, NZ + 1))
    basis = Basis(mesh, ElementVector(ElementHex1()))
    lam, mu = lame_parameters(E, NU)
    K = asm(linear_elasticity(lam, mu), basis)

    end = FacetBasis(mesh, basis.elem, facets=mesh.facets_satisfying(lambda x: np.isclose(x[0], L)))
    traction = F / (B * H)

    @LinearForm
    def load(v, w):
        return -traction * v[2]

    f = asm(load, end)
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    u = solve(*condense(K, f, D=clamped))

    # Stress at the quadrature points, then L2-projected onto the trilinear nodal basis.
    sigma_qp = linear_stress(lam, mu)(sym_grad(basis.interpolate(u)))  # (3, 3, elems, qp)
    nodal = basis.with_element(ElementHex1())
    sigma = np.zeros((mesh.nvertices, 3, 3))
    for i in range(3):
        for j in range(i, 3):
            sigma[:, i, j] = sigma[:, j, i] = nodal.project(sigma_qp[i, j])
    # Displacement at the vertices: the vector basis's vertex DOFs, components interleaved.
    disp = u[basis.nodal_dofs[:, :mesh.nvertices]].T.copy()
    return mesh, sigma, disp


def von_mises(s):
    """von Mises stress of (n, 3, 3) tensors."""
    d = s - np.trace(s, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    return np.sqrt(1.5 * np.einsum("nij,nij->n", d, d))


def write_vtu(path, mesh, sigma, disp):
    m = to_meshio(mesh, point_data={
        "stress": sigma.reshape(-1, 9),
        "displacement": disp,
        "von_mises": von_mises(sigma),
    })
    meshio.write(path, m, file_format="vtu", binary=True, compression="zlib")
    # meshio sets no active attributes; mark them (the header is plain XML: data is base64).
    with open(path, "r", encoding="ascii") as fh:
        text = fh.read()
    assert text.count("<PointData>") == 1, "unexpected meshio output"
    text = text.replace("<PointData>",
                        '<PointData Tensors="stress" Vectors="displacement" Scalars="von_mises">')
    with open(path, "w", encoding="ascii") as fh:
        fh.write(text)


def beam_theory(points, s):
    """Largest |sigma_xx| over the FE points of a cross-section vs. Euler-Bernoulli M c / I."""
    c, inertia = H / 2, B * H**3 / 12
    out = []
    for x in (0.0, 0.5, 1.0, 2.0, 5.0, 8.0):
        on = np.isclose(points[:, 0], x)
        fe = float(np.abs(s[on, 0, 0]).max())
        eb = F * (L - x) * c / inertia
        out.append({"x": x, "fe_max_abs_sigma_xx": fe, "euler_bernoulli": eb,
                    "ratio": fe / eb})
    # Shear on the neutral axis at mid-span: 1.5 F / A for a rectangle (Jourawski).
    mid = np.isclose(points[:, 0], L / 2) & np.isclose(points[:, 2], H / 2)
    shear = {"x": L / 2, "fe_mean_abs_sigma_xz_neutral_axis": float(np.abs(s[mid, 0, 2]).mean()),
             "jourawski_1.5F_over_A": 1.5 * F / (B * H)}
    shear["ratio"] = shear["fe_mean_abs_sigma_xz_neutral_axis"] / shear["jourawski_1.5F_over_A"]
    return out, shear


def expected(path):
    """Truth from the file itself (read back with meshio), computed in numpy."""
    m = meshio.read(path)
    pts = np.asarray(m.points, dtype=float)
    s = np.asarray(m.point_data["stress"], dtype=float).reshape(-1, 3, 3)
    assert np.allclose(s, s.transpose(0, 2, 1), rtol=0, atol=1e-9 * np.abs(s).max())
    vm = von_mises(s)
    top = [int(i) for i in np.argsort(vm)[::-1][:5]]
    rest = np.setdiff1d(np.arange(len(s)), top)
    rnd = [int(i) for i in np.sort(np.random.default_rng(SEED).choice(rest, 5, replace=False))]
    samples = []
    for kind, idx in (("max_von_mises", top), ("random", rnd)):
        for i in idx:
            samples.append({
                "index": i,
                "kind": kind,
                "position": pts[i].tolist(),
                "tensor": s[i].reshape(9).tolist(),
                "eigenvalues_desc": np.linalg.eigvalsh(s[i])[::-1].tolist(),
                "von_mises": float(vm[i]),
            })
    sections, shear = beam_theory(pts, s)
    d = np.asarray(m.point_data["displacement"], dtype=float)
    tip = float(-d[np.isclose(pts[:, 0], L), 2].mean())
    inertia = B * H**3 / 12
    tip_eb = F * L**3 / (3 * E * inertia)
    return {
        "file": os.path.basename(path),
        "array": "stress",
        "location": "point",
        "components": 9,
        "layout": "row-major 3x3, symmetric, Pa",
        "n_tensors": int(len(s)),
        "n_cells": int(sum(len(c.data) for c in m.cells)),
        "bounds": [pts.min(axis=0).tolist(), pts.max(axis=0).tolist()],
        "max_von_mises": float(vm.max()),
        "min_eigenvalue": float(np.linalg.eigvalsh(s).min()),
        "max_eigenvalue": float(np.linalg.eigvalsh(s).max()),
        "samples": samples,
        "beam_theory": {
            "load_N": F, "E_Pa": E, "nu": NU, "length": L, "width": B, "height": H,
            "sections_sigma_xx": sections,
            "shear_mid_span": shear,
            "tip_deflection": {"fe_mean": tip, "euler_bernoulli_FL3_over_3EI": tip_eb,
                               "ratio": tip / tip_eb},
        },
    }


def main():
    vtu = os.path.join(HERE, "beam.vtu")
    mesh, sigma, disp = solve_beam()
    write_vtu(vtu, mesh, sigma, disp)
    truth = expected(vtu)
    with open(os.path.join(HERE, "beam_expected.json"), "w") as fh:
        json.dump(truth, fh, indent=1)
        fh.write("\n")
    print(f"{vtu}: {truth['n_tensors']} tensors, {truth['n_cells']} cells, "
          f"{os.path.getsize(vtu)} bytes; max von Mises {truth['max_von_mises']:.4g} Pa")
    bt = truth["beam_theory"]
    for r in bt["sections_sigma_xx"]:
        print(f"x = {r['x']:4}: max |sigma_xx| FE {r['fe_max_abs_sigma_xx']:.4g} Pa, "
              f"M c / I {r['euler_bernoulli']:.4g} Pa, ratio {r['ratio']:.3f}")
    sh = bt["shear_mid_span"]
    print(f"mid-span neutral-axis |sigma_xz| FE {sh['fe_mean_abs_sigma_xz_neutral_axis']:.4g} Pa, "
          f"1.5 F / A {sh['jourawski_1.5F_over_A']:.4g} Pa, ratio {sh['ratio']:.3f}")
    td = bt["tip_deflection"]
    print(f"tip deflection FE {td['fe_mean']:.4g} m, F L^3 / 3EI {td['euler_bernoulli_FL3_over_3EI']:.4g} m "
          f"(shear adds a little), ratio {td['ratio']:.3f}")


if __name__ == "__main__":
    main()
