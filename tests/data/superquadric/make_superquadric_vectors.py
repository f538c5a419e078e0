#!/usr/bin/env python3
"""Worked cases for superquadric glyphs (docs/book/src/developer/superquadric-derivation.md), computed at 50 digits with mpmath.

Writes tests/data/superquadric/superquadric_vectors.json beside this script:

- "mapping": eigenvalues (sorted descending) and sharpness -> exponents (alpha, beta, c), the
  symmetry axis (frame column) and, for indefinite tensors, Schultz-Kindlmann's (u, v) and zone.
  Written from the papers' definitions (Kindlmann 2004; Schultz and Kindlmann 2010, with the
  zone triangles and anchors of Teem's tenGlyphBqdAbcUv), not from the Rust code.
- "rays": a ray and a glyph -> first forward crossing (t, world point, unit outward normal), or
  a miss. The truth is built backwards and shares nothing with the Rust root finder: a surface
  point from the *parametric* form (angles theta, phi), a direction, and the ray origin placed a
  chosen distance t before the point. The normal is the gradient of the implicit function by
  high-precision numerical differentiation. That nothing is crossed before the point is checked
  by a dense scan (and, for the thin cases, by construction: the ray runs outside the unit box
  before it); the crossing is checked to be transversal at 1e-30.

Run: python3 tests/data/superquadric/make_superquadric_vectors.py  (needs numpy and mpmath).
"""

import json
import os

import mpmath as mp
import numpy as np

mp.mp.dps = 50


# ---------------------------------------------------------------- mapping (from the papers)

def westin_trace(ev):
    m = sorted((abs(x) for x in ev), reverse=True)
    s = sum(m)
    if s == 0:
        return None
    return (m[0] - m[1]) / s, 2 * (m[1] - m[2]) / s


def kindlmann(ev, gamma):
    w = westin_trace(ev)
    if w is None:
        return dict(alpha=1.0, beta=1.0, c=1.0, axis=2, mapping="kindlmann")
    cl, cp = min(w[0], 0.99), min(w[1], 0.99)
    negative = ev[0] <= 0 and ev[2] < 0
    major, minor = (2, 0) if negative else (0, 2)
    if cl >= cp:
        axis, a, b = major, (1 - cp) ** gamma, (1 - cl) ** gamma
    else:
        axis, a, b = minor, (1 - cl) ** gamma, (1 - cp) ** gamma
    return dict(alpha=a, beta=b, c=b, axis=axis, mapping="kindlmann")


VERTS = [(1, 1), (0.5, 1), (0.75, 0.75), (1, 0.5), (1, 0), (0.5, 0.5), (0, 1), (0, 0.5),
         (0.25, 0.25), (0.5, 0), (0, 0)]


def anchors(bmax):
    return dict(ball=(1, 1, 1), cyl=(1, 0, 0), half=(0.5, 0.5, 0.5), octa=(0, 2, 2),
                cone=(1, 2, 2), thorn=(1, bmax, bmax), funk=(0, bmax, 2))


# zone -> (corner indices, anchor names, axis); Teem's triangles, axis from the anchors.
ZONES = [((0, 1, 2), ("ball", "cyl", "half"), 0),
         ((0, 2, 3), ("ball", "half", "cyl"), 2),
         ((1, 3, 4), ("octa", "cone", "thorn"), 2),
         ((1, 4, 5), ("octa", "thorn", "funk"), 2),
         ((4, 5, 9), ("thorn", "funk", "cone"), 2),
         ((1, 5, 6), ("cone", "funk", "thorn"), 0),
         ((5, 6, 9), ("funk", "thorn", "octa"), 0),
         ((6, 7, 9), ("thorn", "cone", "octa"), 0),
         ((7, 8, 10), ("cyl", "half", "ball"), 0),
         ((8, 9, 10), ("half", "cyl", "ball"), 2)]


def sk_uv(ev):
    m = max(abs(x) for x in ev)
    x, y, z = (mp.mpf(e) / m for e in ev)
    u = (y + 1) / 2
    v = (z + 1) / 2 - u + 1 if x > -z else (x - 1) / 2 - u + 1
    return u, v


def sk_zone(u, v):
    if u > 0.5:
        if u + v > 1.5:
            return 0 if u < v else 1
        return 2 if 2 * u + v > 2 else (3 if u + v > 1 else 4)
    if u + v > 0.5:
        return 5 if u + v > 1 else (6 if 2 * u + v > 1 else 7)
    return 8 if u < v else 9


def schultz_kindlmann(ev, bmax):
    u, v = sk_uv(ev)
    zone = sk_zone(u, v)
    corners, names, axis = ZONES[zone]
    # Barycentric coordinates by solving the 3x3 system (not by areas, as the Rust code does).
    P = [VERTS[i] for i in corners]
    A = mp.matrix([[P[0][0], P[1][0], P[2][0]], [P[0][1], P[1][1], P[2][1]], [1, 1, 1]])
    lam = mp.lu_solve(A, mp.matrix([u, v, 1]))
    an = anchors(bmax)
    abc = [sum(lam[k] * an[names[k]][j] for k in range(3)) for j in range(3)]
    abc = [max(x, mp.mpf("1e-5")) for x in abc]
    return dict(alpha=float(abc[0]), beta=float(abc[1]), c=float(abc[2]), axis=axis,
                mapping="schultz_kindlmann", u=float(u), v=float(v), zone=zone)


def mapping(ev, gamma, bmax):
    if ev[0] > 0 and ev[2] < 0:
        return schultz_kindlmann(ev, bmax)
    return kindlmann([mp.mpf(x) for x in ev], gamma)


MAPPING_CASES = [
    ("isotropic", [2, 2, 2], 3, 3),
    ("zero", [0, 0, 0], 3, 3),
    ("linear_gamma3", [3, 1, 1], 3, 3),
    ("planar_gamma3", [2, 2, 0.5], 3, 3),
    ("generic_gamma3", [1, 0.6, 0.2], 3, 3),
    ("tie_cl_cp", [3, 2, 1], 3, 3),
    ("near_cylinder_gamma10", [1, 0.001, 0.001], 10, 3),
    ("near_cube_gamma10", [1, 0.75, 0.5], 10, 3),
    ("pure_line_capped", [1, 0, 0], 3, 3),
    ("negative_definite", [-1, -1, -3], 3, 3),
    ("gamma0_ellipsoid", [5, 2, 1], 0, 3),
    ("thorn_e3", [1, 1, -1], 3, 3),
    ("thorn_e1", [1, -1, -1], 3, 3),
    ("funk", [1, 0, -1], 3, 3),
    ("stress_2_-0.6_-1.5", [2, -0.6, -1.5], 3, 3),
    ("stress_1.5_0.6_-2", [1.5, 0.6, -2], 3, 3),
    ("zone2", [1, 0.8, -0.1], 3, 3),
    ("zone3", [1, 0.3, -0.5], 3, 3),
    ("zone4", [0.4, 0.3, -1], 3, 3),
    ("zone5", [1, -0.3, -0.6], 3, 3),
    ("zone6", [0.8, -0.2, -1], 3, 3),
    ("zone7", [0.2, -0.8, -1], 3, 3),
    ("betamax5", [1, 0.2, -0.7], 3, 5),
]


# ---------------------------------------------------------------- geometry

def spow(x, e):
    return mp.sign(x) * abs(x) ** e


def profile(az, e):
    """R_e(z) = (1 - |z|^(2/e))^(e/2)."""
    if az >= 1:
        return mp.mpf(0)
    return (1 - az ** (2 / e)) ** (e / 2)


def implicit(q, a, b, c):
    """> 0 outside, 0 on the surface, < 0 inside (local unit coordinates)."""
    x, y, z = (abs(t) for t in q)
    if b == c:
        # Barr's inside-outside function.
        if x == 0 and y == 0:
            s = mp.mpf(0)
        else:
            s = (x ** (2 / a) + y ** (2 / a)) ** (a / b)
        return s + z ** (2 / b) - 1
    if z >= 1:
        return z - 1 if (x == 0 and y == 0) else mp.mpf(1)
    return (x / profile(z, b)) ** (2 / a) + (y / profile(z, c)) ** (2 / a) - 1


def surface_point(theta, phi, a, b, c, signs=(1, 1, 1)):
    """First-octant parametric point (0 <= theta, phi <= pi/2), then mirrored by `signs`."""
    z = mp.cos(phi) ** b
    x = mp.cos(theta) ** a * mp.sin(phi) ** b
    y = mp.sin(theta) ** a * profile(z, c)
    return mp.matrix([signs[0] * x, signs[1] * y, signs[2] * z])


def rodrigues(axis, angle):
    k = mp.matrix(axis) / mp.norm(mp.matrix(axis))
    K = mp.matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return mp.eye(3) + mp.sin(angle) * K + (1 - mp.cos(angle)) * K * K


def grad_local(q, a, b, c):
    g = []
    for k in range(3):
        def f(t, k=k):
            qq = q.copy()
            qq[k] = t
            return implicit(qq, a, b, c)
        g.append(mp.diff(f, q[k]))
    return mp.matrix(g)


def fl(v):
    return [float(x) for x in v]


def ray_case(cid, desc, a, b, c, radii, frame, centre, theta, phi, signs, d_local_hint,
             dist, tol, normal_override=None, exit_case=False, mapped=None, q=None, graze=None):
    """A hit case: surface point from (theta, phi), or `q` in local unit coordinates; ray
    direction `d_local_hint` in the local frame, or with `graze = k` the hint's part tangent to
    the surface tilted inwards so that d.n = -k."""
    # The truth is for the exponents as stored (f64), held exactly.
    a, b, c = (mp.mpf(float(x)) for x in (a, b, c))
    radii = mp.matrix(radii)
    centre = mp.matrix(centre)
    if q is None:
        q = surface_point(theta, phi, a, b, c, signs)
    else:
        q = mp.matrix(q)
    assert abs(implicit(q, a, b, c)) < mp.mpf("1e-40"), (cid, implicit(q, a, b, c))
    P = centre + frame * mp.matrix([q[k] * radii[k] for k in range(3)])
    if normal_override is not None:
        gl = mp.matrix(normal_override)
    else:
        gl = grad_local(q, a, b, c)
    n = frame * mp.matrix([gl[k] / radii[k] for k in range(3)])
    n = n / mp.norm(n)
    d = frame * mp.matrix(d_local_hint)
    d = d / mp.norm(d)
    if graze is not None:
        tang = d - mp.fdot(d, n) * n
        tang = tang / mp.norm(tang)
        k = mp.mpf(graze)
        d = tang * mp.sqrt(1 - k * k) - k * n
    # Transversal: entering (d.n < 0) or, for an exit from inside, leaving.
    assert (mp.fdot(d, n) > 0) == exit_case, (cid, mp.fdot(d, n))
    o = P - dist * d
    # Round the origin and direction to f64 first: the truth is for the rays as stored.
    o64 = mp.matrix(fl(o))
    d64 = mp.matrix(fl(d))
    # Re-solve the crossing for the rounded ray by bisection near `dist`, to 1e-40.
    finv = frame.T

    def F(t):
        p = o64 + t * d64 - centre
        ql = finv * p
        return implicit(mp.matrix([ql[k] / radii[k] for k in range(3)]), a, b, c)

    h = mp.mpf("1e-11") * (1 + dist)
    lo, hi = dist - h, dist + h
    flo, fhi = F(lo), F(hi)
    if not exit_case:
        assert flo > 0 and fhi < 0, (cid, flo, fhi)
    else:
        assert flo < 0 and fhi > 0, (cid, flo, fhi)
    for _ in range(200):
        mid = (lo + hi) / 2
        if (F(mid) > 0) == (flo > 0):
            lo = mid
        else:
            hi = mid
    t = (lo + hi) / 2
    # Dense scan before the crossing: no earlier sign change (f64 numpy is enough to scan).
    ts = np.linspace(0.0, float(t) * (1 - 1e-9), 20001)
    sgn0 = F(mp.mpf(ts[0])) > 0
    assert sgn0 != exit_case, cid
    for tt in ts[:: max(1, len(ts) // 4000)]:
        assert (F(mp.mpf(tt)) > 0) == sgn0, (cid, tt)
    point = o64 + t * d64
    if mapped:
        shape = mapping(mapped["eigenvalues"], mp.mpf(mapped["gamma"]), mp.mpf(mapped["beta_max"]))
        axes = [2, 1, 0] if shape["axis"] == 0 else [0, 1, 2]
        eig = [None] * 3
        for k in range(3):
            eig[axes[k]] = fl(frame[:, k])
        mapped = dict(mapped, eigen_frame_cols=eig)
    case = dict(id=cid, description=desc, glyph=glyph_json(a, b, c, radii, frame, centre, mapped),
                ray=dict(origin=fl(o64), dir=fl(d64)), expected=dict(
                    hit=True, t=float(t), point=fl(point), normal=fl(n)), tol=tol,
                d_dot_n=float(mp.fdot(d64, n)))
    return case


def glyph_json(a, b, c, radii, frame, centre, mapped):
    g = dict(alpha=float(a), beta=float(b), c=float(c), radii=fl(radii),
             frame_cols=[fl(frame[:, k]) for k in range(3)], centre=fl(centre))
    if mapped:
        g["mapped"] = mapped
    return g


def miss_case(cid, desc, a, b, c, radii, frame, centre, o, d):
    a, b, c = (mp.mpf(float(x)) for x in (a, b, c))
    radii = mp.matrix(radii)
    centre = mp.matrix(centre)
    o = mp.matrix(o)
    d = mp.matrix(d)
    d = d / mp.norm(d)
    d64 = mp.matrix(fl(d))
    finv = frame.T
    for tt in np.linspace(0, 50, 200001)[::10]:
        p = o + mp.mpf(tt) * d64 - centre
        ql = finv * p
        v = implicit(mp.matrix([ql[k] / radii[k] for k in range(3)]), a, b, c)
        assert v > 0, (cid, tt, v)
    return dict(id=cid, description=desc, glyph=glyph_json(a, b, c, radii, frame, centre, None),
                ray=dict(origin=fl(o), dir=fl(d64)), expected=dict(hit=False), tol=0)


def main():
    out = dict(about=__doc__.strip().splitlines()[0],
               conventions=dict(
                   local="local z is the symmetry axis; frame_cols are the world directions of "
                         "local x, y, z; radii are local semi-axes",
                   solid="|z| <= 1 and (|x|/R_beta(z))^(2/alpha) + (|y|/R_c(z))^(2/alpha) <= 1, "
                         "R_e(z) = (1 - |z|^(2/e))^(e/2); c = beta is Barr's superquadric",
                   hit="first crossing with t > 0 (the exit when the origin is inside)",
                   tol="relative tolerance for t (of the glyph size) and absolute for the normal; "
                       "larger than 1e-12 only where the crossing is ill-conditioned"),
               mapping=[], rays=[])
    for cid, ev, g, bm in MAPPING_CASES:
        e = mapping(ev, mp.mpf(g), mp.mpf(bm))
        e = {k: (float(v) if isinstance(v, mp.mpf) else v) for k, v in e.items()}
        out["mapping"].append(dict(id=cid, eigenvalues=[float(x) for x in ev], gamma=float(g),
                                   beta_max=float(bm), expected=e))

    I = mp.eye(3)
    R1 = rodrigues([1, 2, 3], mp.mpf("0.7"))
    R2 = rodrigues([-2, 1, 0.5], mp.mpf("2.1"))
    rays = out["rays"]
    pi = mp.pi

    # Mapped glyphs: shapes straight from the mapping, so the tests also exercise from_shape.
    m_lin = kindlmann([mp.mpf(3), 1, 1], 3)
    rays.append(ray_case(
        "kindlmann_linear", "Kindlmann (3,1,1) gamma 3: axis e1, alpha 1, beta 0.216",
        m_lin["alpha"], m_lin["beta"], m_lin["c"], [0.3, 0.3, 0.9], R1, [10.5, -3.25, 7],
        pi / 5, pi / 3, (1, -1, 1), [-1, 0.4, -0.3], 6, 1e-12,
        mapped=dict(eigenvalues=[3, 1, 1], gamma=3, beta_max=3, frame_radii=[0.9, 0.3, 0.3])))

    # Near-cube, gamma 10: (1, 0.75, 0.5): cl = 1/9, cp = 1/3 -> axis e3.
    m_cube = kindlmann([mp.mpf(1), mp.mpf("0.75"), mp.mpf("0.5")], 10)
    a, b = m_cube["alpha"], m_cube["beta"]
    rays.append(ray_case(
        "near_cube_face", "gamma 10 near-cube, hit on a flat face", a, b, b, [1, 0.75, 0.5], R2,
        [0, 0, 0], pi / 7, pi / 2.3, (1, 1, -1), [-0.3, -0.2, 1], 4, 1e-12))
    # Thin crossing: a ray that only nicks the rounded corner. The corner region of the
    # near-cube is about 1e-3 wide; the ray enters nearly tangentially near (1, 1, 1) and its
    # chord inside the solid is far shorter than any fixed march step would be.
    rays.append(ray_case(
        "near_cube_thin_corner", "gamma 10 near-cube: a nearly tangent ray nicking a corner",
        a, b, b, [1, 0.75, 0.5], I, [0, 0, 0], pi / 4, mp.mpf("0.9553"), (1, 1, 1),
        [-1, 1, 0], 3, 1e-12, graze="1e-4"))
    # Sharper still: gamma 10 from the Westin cap, beta = 0.01^10 = 1e-20; a cap hit.
    m_cyl = kindlmann([mp.mpf(1), mp.mpf("0.001"), mp.mpf("0.001")], 10)
    rays.append(ray_case(
        "near_cylinder_cap", "beta 1e-20 near-cylinder: hit on the flat cap near the rim",
        m_cyl["alpha"], m_cyl["beta"], m_cyl["c"], [0.2, 0.2, 1], R1, [1, 2, 3],
        None, None, None, [0.1, 0.2, -1], 3, 1e-12, normal_override=[0, 0, 1],
        q=[mp.mpf("0.9") * mp.cos(0.3), mp.mpf("0.9") * mp.sin(0.3), 1]))
    rays.append(ray_case(
        "near_cylinder_side", "beta 1e-3 near-cylinder: hit on the side",
        1, mp.mpf("0.001"), mp.mpf("0.001"), [0.2, 0.3, 1], R2, [-4, 0.5, 2],
        mp.mpf("1.1"), mp.mpf("0.5") * pi / 2, (1, -1, -1), [-1, 0.5, 0.3], 2, 1e-12))
    # Exact zeros: identity frame, hits at the pole and in mirror planes.
    rays.append(ray_case(
        "pole", "ray along the axis onto the pole (0, 0, 1): powers of zero",
        mp.mpf("0.3"), mp.mpf("0.4"), mp.mpf("0.4"), [0.5, 0.5, 1], I, [0, 0, 0],
        0, 0, (1, 1, 1), [0, 0, -1], 2, 1e-12, normal_override=[0, 0, 1]))
    rays.append(ray_case(
        "plane_y0", "ray in the plane y = 0, hit with y exactly 0",
        mp.mpf("0.5"), mp.mpf("0.25"), mp.mpf("0.25"), [1, 0.5, 0.8], I, [0, 0, 0],
        0, pi / 3, (1, 1, 1), [-1, 0, -0.5], 3, 1e-12))
    rays.append(ray_case(
        "equator_z0", "ray in the plane z = 0 onto the equator of a boxy glyph",
        mp.mpf("0.2"), mp.mpf("0.3"), mp.mpf("0.3"), [1, 1, 0.4], I, [0, 0, 0],
        None, None, None, [-1, -0.3, 0], 3, 1e-12,
        q=[mp.cos(0.4) ** mp.mpf(0.2), mp.sin(0.4) ** mp.mpf(0.2), 0]))
    # Grazing: d.n about -1e-3 on an ellipsoid-like glyph.
    rays.append(ray_case(
        "grazing", "grazing ray on a rounded glyph (d.n ~ -1e-3)",
        mp.mpf("0.8"), mp.mpf("0.9"), mp.mpf("0.9"), [1, 0.8, 0.6], R1, [2, 2, 2],
        mp.mpf("0.7"), mp.mpf("1.0"), (1, 1, 1), [-0.55, 0.83, -0.05], 2.5, 1e-12,
        graze="1e-3"))
    # Eye inside: origin inside the solid, the hit is the exit.
    rays.append(ray_case(
        "eye_inside", "origin inside the glyph: the first crossing is the exit",
        mp.mpf("0.5"), mp.mpf("0.6"), mp.mpf("0.6"), [1, 0.7, 0.5], R2, [0.25, -0.5, 1],
        mp.mpf("0.5"), mp.mpf("1.1"), (1, -1, 1), [1, -0.4, 0.6], 0.3, 1e-12,
        exit_case=True))
    # Schultz-Kindlmann shapes.
    m_thorn = schultz_kindlmann([1, 1, -1], 3)
    rays.append(ray_case(
        "thorn", "Schultz-Kindlmann thorn (1, 3, 3): pinched profile",
        m_thorn["alpha"], m_thorn["beta"], m_thorn["c"], [0.8, 0.8, 0.8], R1, [0, 0, 0],
        mp.mpf("0.9"), mp.mpf("0.6"), (1, 1, 1), [-0.2, -0.3, -1], 3, 1e-12))
    rays.append(ray_case(
        "thorn_eye_in_box", "origin inside the bounding box, outside the pinched solid",
        1, 3, 3, [1, 1, 1], I, [0, 0, 0], mp.mpf("0.5"), mp.mpf("0.5"), (1, 1, 1),
        [-1, -1, -0.3], 0.2, 1e-12))
    m_funk = schultz_kindlmann([1, mp.mpf("0.1"), mp.mpf("-0.9")], 3)
    rays.append(ray_case(
        "funk_like", "Schultz-Kindlmann (1, 0.1, -0.9): c differs from beta",
        m_funk["alpha"], m_funk["beta"], m_funk["c"], [1, 0.1, 0.9], R2, [3, -1, 0.5],
        mp.mpf("0.8"), mp.mpf("0.7"), (1, 1, -1), [-0.3, -1, 0.4], 2, 1e-12,
        mapped=dict(eigenvalues=[1, 0.1, -0.9], gamma=3, beta_max=3,
                    frame_radii=[1, 0.1, 0.9])))
    rays.append(ray_case(
        "far_glyph", "a glyph far from the origin, seen from far away",
        mp.mpf("0.4"), mp.mpf("0.7"), mp.mpf("0.7"), [1e-3, 2e-3, 1.5e-3], R1,
        [1e4, -2e4, 3e3], mp.mpf("0.2"), mp.mpf("0.8"), (-1, 1, 1), [1, -0.2, -0.1], 1e3, 1e-12))
    # Misses.
    rays.append(miss_case(
        "miss_box_corner", "through the bounding box corner, past a sphere",
        1, 1, 1, [1, 1, 1], I, [0, 0, 0], [0.9, 0.9, -5], [0, 0, 1]))
    rays.append(miss_case(
        "miss_behind", "the glyph is behind the origin", mp.mpf("0.3"), mp.mpf("0.3"),
        mp.mpf("0.3"), [1, 1, 1], R1, [0, 0, 0], [0, 0, 3], [0.1, 0.05, 1]))
    with open(os.path.join(os.path.dirname(__file__), "superquadric_vectors.json"), "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(f"{len(out['mapping'])} mapping cases, {len(out['rays'])} ray cases")


if __name__ == "__main__":
    main()
