//! The tessellated superquadric of `mesh:N`: one shared θ × φ grid on the unit sphere that the
//! vertex shader maps through each glyph's exponents (shaders/shape/superquadric_mesh.wgsl), and
//! that mapping's f64 twin.

use super::super::mesh::{Mesh, normalize, prism_sides, turn};

/// Latitude steps from pole to pole of the `mesh:N` superquadric grid: half the steps around
/// ([`prism_sides`]), so that θ and φ advance by the same angle 2π/S. Teem's `tend glyph` uses
/// 2·`-gr` steps around and `-gr` from pole to pole, default `-gr 10` (20 × 10): between levels 1
/// (12 × 6) and 2 (24 × 12).
pub fn superquadric_rings(level: u8) -> u32 {
    prism_sides(level) / 2
}

/// The shared parametric grid of tessellated superquadrics (`mesh:N`, as Teem's
/// `limnObjectPolarSuperquadFancyAdd` builds each glyph): θ × φ on the unit sphere with S =
/// [`prism_sides`] steps of θ around the local z axis and M = [`superquadric_rings`] steps of φ
/// from the pole z = 1 to z = −1, the poles single vertices. Each vertex stores its direction
/// d = (cos θ sin φ, sin θ sin φ, cos φ) as both position and normal (the unit sphere's); the
/// vertex shader maps d through the glyph's exponents to the superquadric
/// ([`superquadric_vertex`]). Exact zeros at the poles, on the equator (M even, level ≥ 1) and at
/// θ multiples of π/2 (S divisible by 4, level ≥ 1). S(M − 1) + 2 vertices, 2S(M − 1)
/// triangles (a fan at each pole, two per quad between rings).
pub fn superquadric_grid(level: u8) -> Mesh {
    let s = prism_sides(level);
    let m = superquadric_rings(level);
    let mut mesh = Mesh::default();
    let north = mesh.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
    // Ring j (1 ≤ j < M) starts at vertex 1 + (j − 1) S; φ = j π / M is the turn j / (2M).
    for j in 1..m {
        let (cp, sp) = turn(j, 2 * m);
        for k in 0..s {
            let (ct, st) = turn(k, s);
            let d = [ct * sp, st * sp, cp];
            mesh.push(d, d);
        }
    }
    let south = mesh.push([0.0, 0.0, -1.0], [0.0, 0.0, -1.0]);
    let ring = |j: u32, k: u32| 1 + (j - 1) * s + k % s;
    // θ runs counter-clockwise about +z, φ from +z down.
    for k in 0..s {
        mesh.indices.extend([north, ring(1, k), ring(1, k + 1)]);
    }
    for j in 1..m - 1 {
        for k in 0..s {
            let (a0, a1) = (ring(j, k), ring(j, k + 1));
            let (b0, b1) = (ring(j + 1, k), ring(j + 1, k + 1));
            mesh.indices.extend([a0, b0, b1, a0, b1, a1]);
        }
    }
    for k in 0..s {
        mesh.indices
            .extend([south, ring(m - 1, k + 1), ring(m - 1, k)]);
    }
    mesh
}

/// ln(1 − u) for 0 ≤ u ≤ 1/2 without the cancellation of 1 − u for small u (`sqm_ln1m`).
fn sq_ln1m(u: f64) -> f64 {
    if u < 0.0625 {
        -u * (1.0 + u * (0.5 + u * (1.0 / 3.0 + u * (0.25 + u * (0.2 + u / 6.0)))))
    } else {
        (1.0 - u).ln()
    }
}

/// ln(1 − e^(−w)) for w = e^lw (`sqm_ln_1m_exp_neg`), finite for every finite lw.
fn sq_ln_1m_exp_neg(lw: f64) -> f64 {
    if lw < -2.772_588_722_239_781 {
        let w = lw.exp();
        lw + (1.0 - w * (0.5 - w * (1.0 / 6.0 - w * (1.0 / 24.0 - w / 120.0)))).ln()
    } else if lw > 4.0 {
        0.0
    } else {
        (1.0 - (-lw.exp()).exp()).ln()
    }
}

/// ln |cos φ| from cos φ and sin φ (both nonzero), accurate near the poles (`sqm_ln_cos`).
fn sq_ln_cos(cz: f64, sp: f64) -> f64 {
    let a = cz.abs();
    if a > 0.5 {
        sq_ln1m(sp * sp / (1.0 + a))
    } else {
        a.ln()
    }
}

/// The f64 twin of `sqm_vertex` (shaders/superquadric_mesh.wgsl), formula for formula: the
/// grid direction `d` of [`superquadric_grid`] mapped through the exponents `e = (α, β, c)` to
/// the superquadric's surface, and the unit outward normal there, in local unit coordinates
/// (docs/book/src/developer/superquadric-derivation.md §1: local z the symmetry axis).
///
/// With (cos θ, sin θ) the direction of `d`'s (x, y) and (sin φ, cos φ) its distance from the
/// axis and its z (signed powers throughout):
///
/// ```text
/// x = cos^α θ sin^β φ,   y = sin^α θ R_c(|z|),   z = cos^β φ,
/// R_c(|z|) = K_c^(c/2),  K_c = 1 − |cos φ|^(2β/c)      (= sin^β φ for c = β),
/// ```
///
/// Kindlmann's surface with Teem's stretch of y by R_c / R_β for c ≠ β. The normal is the
/// gradient of the inside–outside function H (docs §4) at the vertex, where H = 1, u = |cos
/// θ|^α and w = |sin θ|^α (signed factors keep their coordinate's sign):
///
/// ```text
/// ∂H/∂x ∝ cos^(2−α) θ / sin^β φ,   ∂H/∂y ∝ sin^(2−α) θ / K_c^(c/2),
/// ∂H/∂z ∝ sgn(cos φ) (cos²θ |cos φ|^(2−β) / sin²φ + sin²θ |cos φ|^(2β/c − β) / K_c),
/// ```
///
/// which for c = β is sin^(−2) φ times Barr's parametric normal (cos^(2−α) θ sin^(2−β) φ,
/// sin^(2−α) θ sin^(2−β) φ, cos^(2−β) φ). Each component is formed as a natural logarithm and
/// all are scaled by the largest, so nothing overflows where the factors do (pinched β > 2
/// next to the equator, 2β/c ≈ 1e20) or underflows to a lost direction (exponents of 1e-20); a
/// component whose coordinate is exactly 0 is 0 (the mirror-symmetric limit, the bisector on
/// ridges), and the poles have normal ±z. No NaN for exponents from
/// 1e-30 up.
pub fn superquadric_vertex(d: [f64; 3], e: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let rho = d[0].hypot(d[1]);
    if rho == 0.0 {
        let s = if d[2] >= 0.0 { 1.0 } else { -1.0 };
        return ([0.0, 0.0, s], [0.0, 0.0, s]);
    }
    let l = (rho * rho + d[2] * d[2]).sqrt();
    let sp = (rho / l).min(1.0);
    let cz = (d[2] / l).clamp(-1.0, 1.0);
    let ct = (d[0] / rho).clamp(-1.0, 1.0);
    let st = (d[1] / rho).clamp(-1.0, 1.0);
    let [alpha, beta, c] = e;
    let (has_x, has_y, has_z) = (ct != 0.0, st != 0.0, cz != 0.0);
    let lct = if has_x { ct.abs().ln() } else { 0.0 };
    let lst = if has_y { st.abs().ln() } else { 0.0 };
    let lsp = sp.ln();
    let lcz = if has_z { sq_ln_cos(cz, sp) } else { 0.0 };
    let q = 2.0 * beta / c;
    let lk = if c == beta {
        2.0 * lsp
    } else if has_z {
        sq_ln_1m_exp_neg(q.ln() + (-lcz).max(f64::from(f32::MIN_POSITIVE)).ln())
    } else {
        0.0
    };
    let sgn = |v: f64| if v > 0.0 { 1.0 } else { -1.0 };
    let p = [
        if has_x {
            sgn(ct) * (alpha * lct + beta * lsp).exp()
        } else {
            0.0
        },
        if has_y {
            sgn(st) * (alpha * lst + 0.5 * c * lk).exp()
        } else {
            0.0
        },
        if has_z {
            sgn(cz) * (beta * lcz).exp()
        } else {
            0.0
        },
    ];
    let lx = (2.0 - alpha) * lct - beta * lsp;
    let ly = (2.0 - alpha) * lst - 0.5 * c * lk;
    let t1 = 2.0 * lct + (2.0 - beta) * lcz - 2.0 * lsp;
    let t2 = 2.0 * lst + (q - beta) * lcz - lk;
    let lz = if !has_x {
        t2
    } else if !has_y {
        t1
    } else {
        let m = t1.max(t2);
        m + (1.0 + (t1.min(t2) - m).exp()).ln()
    };
    let none = -3.0e38;
    let pick = |has: bool, v: f64| if has { v } else { none };
    let top = pick(has_x, lx).max(pick(has_y, ly)).max(pick(has_z, lz));
    let n = [
        if has_x {
            sgn(ct) * (lx - top).exp()
        } else {
            0.0
        },
        if has_y {
            sgn(st) * (ly - top).exp()
        } else {
            0.0
        },
        if has_z {
            sgn(cz) * (lz - top).exp()
        } else {
            0.0
        },
    ];
    (p, normalize(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::GlyphKind;
    use crate::shape::mesh::checks::{cross, dot};

    #[test]
    fn grid_stats() {
        let kind = GlyphKind::Superquadric.shape();
        // 6 × 3 steps: 6 · 2 rings + 2 poles; 6 · 2 fan triangles + 6 · 2 in the one band.
        assert_eq!(kind.mesh_stats(0), (14, 24));
        assert_eq!(kind.mesh_stats(6), (73346, 146688));
    }

    /// Exponents (α, β, c) across what the mappings give and beyond: the sphere, Kindlmann
    /// shapes down to γ = 10 (1e-20), Schultz–Kindlmann anchors and blends with c ≠ β (funk,
    /// zone 5), pinched thorns up to β_max = 5, a pinched cross-section (α = 5) and c on
    /// either side of β.
    const SQ_EXPONENTS: [[f64; 3]; 16] = [
        [1.0, 1.0, 1.0],
        [1.0, 0.216, 0.216],
        [0.3, 1.0, 1.0],
        [1e-20, 1e-20, 1e-20],
        [1.0, 1e-20, 1e-20],
        [1e-20, 1.0, 1.0],
        [1e-5, 2.0, 2.0],
        [2.0, 2.0, 2.0],
        [1.0, 3.0, 3.0],
        [1e-5, 3.0, 2.0],
        [0.55, 2.75, 2.3],
        [1.0, 5.0, 5.0],
        [0.5, 5.0, 2.0],
        [5.0, 1.0, 1.0],
        [1.0, 1.2, 3.0],
        [0.7, 1.6, 0.5],
    ];

    /// Smooth shapes (every exponent in (0, 2)), where H has a gradient everywhere off the
    /// poles.
    const SQ_SMOOTH: [[f64; 3]; 5] = [
        [1.0, 1.0, 1.0],
        [0.5, 0.8, 0.8],
        [1.5, 1.2, 1.2],
        [0.7, 1.6, 1.1],
        [1.2, 0.6, 0.9],
    ];

    /// The grid's directions as the GPU reads them (f32).
    fn grid_directions(level: u8) -> Vec<[f64; 3]> {
        superquadric_grid(level)
            .vertices
            .iter()
            .map(|v| v.position.map(f64::from))
            .collect()
    }

    fn gauge_at(e: [f64; 3], p: [f64; 3]) -> f64 {
        crate::glyph::superquadric::gauge(e, p.map(f64::abs))
    }

    #[test]
    fn superquadric_grid_has_exact_zeros_and_counts() {
        for level in 0..=3 {
            let m = superquadric_grid(level);
            let (s, r) = (
                prism_sides(level) as usize,
                superquadric_rings(level) as usize,
            );
            assert_eq!(m.vertices.len(), s * (r - 1) + 2);
            assert_eq!(m.triangles(), 2 * s * (r - 1));
            for v in &m.vertices {
                let p = v.position.map(f64::from);
                assert!((dot(p, p) - 1.0).abs() < 1e-6, "{v:?}");
                assert_eq!(v.position, v.normal);
            }
            let on =
                |f: &dyn Fn([f32; 3]) -> bool| m.vertices.iter().filter(|v| f(v.position)).count();
            assert_eq!(on(&|p| p[0] == 0.0 && p[1] == 0.0), 2, "poles");
            if level >= 1 {
                // The equator, and the two mirror planes (through the poles, counted once).
                assert_eq!(on(&|p| p[2] == 0.0), s, "equator");
                assert_eq!(on(&|p| p[0] == 0.0), 2 * (r - 1) + 2, "x = 0");
                assert_eq!(on(&|p| p[1] == 0.0), 2 * (r - 1) + 2, "y = 0");
            }
        }
        // Teem's default resolution (tend glyph -gr 10: 20 × 10) lies between levels 1 and 2.
        assert_eq!((prism_sides(1), superquadric_rings(1)), (12, 6));
        assert_eq!((prism_sides(2), superquadric_rings(2)), (24, 12));
    }

    /// Every grid vertex mapped through the twin lies on the superquadric: H = 1 to 1e-6, or
    /// where f64 rounds the vertex onto the cap plane |z| = 1 (β ≈ 1e-20: z = 1 − O(1e-20), where
    /// H jumps from ≤ 1 to ∞), the surface crosses the segment from 0.999999 to 1.000001 times
    /// the point. Normals are finite, unit and outward, and no coordinate is NaN, for every
    /// exponent set.
    #[test]
    fn superquadric_vertices_lie_on_the_surface() {
        for level in 0..=4 {
            let dirs = grid_directions(level);
            for e in SQ_EXPONENTS {
                let mut on_cap_plane = 0;
                for &d in &dirs {
                    let (p, n) = superquadric_vertex(d, e);
                    let what = format!("mesh:{level} {e:?} at {d:?}: {p:?}, {n:?}");
                    assert!(p.iter().chain(&n).all(|x| x.is_finite()), "{what}");
                    assert!((dot(n, n) - 1.0).abs() < 1e-12, "{what}");
                    assert!(dot(n, p) > 0.0, "{what}: normal not outward");
                    for (i, x) in p.iter().enumerate() {
                        // Coordinates keep the direction's sign and zeros.
                        assert!(x.abs() <= 1.0, "{what}");
                        assert_eq!(*x == 0.0, d[i] == 0.0, "{what}: zero");
                        assert!(*x == 0.0 || x.signum() == d[i].signum(), "{what}: sign");
                    }
                    let inner = gauge_at(e, p.map(|x| x * (1.0 - 1e-6)));
                    let outer = gauge_at(e, p.map(|x| x * (1.0 + 1e-6)));
                    assert!(inner <= 1.0 && outer >= 1.0, "{what}: {inner} .. {outer}");
                    let h = gauge_at(e, p);
                    if p[2].abs() < 1.0 || (p[0] == 0.0 && p[1] == 0.0) {
                        assert!((h - 1.0).abs() <= 1e-6, "{what}: H = {h}");
                    } else {
                        on_cap_plane += 1;
                    }
                }
                // Only exponents that round z to ±1 in f64 (β ≈ 1e-20) put vertices there.
                assert!(
                    on_cap_plane == 0 || e[1] < 1e-15,
                    "mesh:{level} {e:?}: {on_cap_plane}"
                );
            }
        }
    }

    /// Where the surface is smooth, the twin's normal is the direction of H's numerical
    /// gradient (central differences). Off the poles' neighbourhood, where H's derivatives
    /// grow without bound (|z| ≤ 0.95).
    #[test]
    fn superquadric_normals_are_the_gradient() {
        let h = 1e-6;
        let mut checked = 0;
        for e in SQ_SMOOTH {
            for d in grid_directions(4) {
                let (p, n) = superquadric_vertex(d, e);
                if p[2].abs() > 0.95 {
                    continue;
                }
                let grad = [0, 1, 2].map(|i| {
                    let (mut a, mut b) = (p, p);
                    a[i] += h;
                    b[i] -= h;
                    (gauge_at(e, a) - gauge_at(e, b)) / (2.0 * h)
                });
                let g = normalize(grad);
                let err = [0, 1, 2].map(|i| g[i] - n[i]);
                assert!(
                    dot(err, err).sqrt() < 1e-6,
                    "{e:?} at {d:?}: normal {n:?}, gradient {g:?}"
                );
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    /// The mapped grid stays consistently wound: no triangle of the mapped mesh turns its back
    /// to its own vertex normals (degenerate ones excepted: β ≈ 0 collapses the rings between
    /// pole and equator onto the caps' rims).
    #[test]
    fn mapped_superquadric_triangles_face_outward() {
        for level in 1..=4 {
            let grid = superquadric_grid(level);
            for e in SQ_EXPONENTS {
                let mapped: Vec<_> = grid
                    .vertices
                    .iter()
                    .map(|v| superquadric_vertex(v.position.map(f64::from), e))
                    .collect();
                for t in grid.indices.chunks_exact(3) {
                    let [a, b, c] = [0, 1, 2].map(|k| mapped[t[k] as usize]);
                    let ab = [0, 1, 2].map(|i| b.0[i] - a.0[i]);
                    let ac = [0, 1, 2].map(|i| c.0[i] - a.0[i]);
                    let face = cross(ab, ac);
                    // Degenerate: thinner than 1e-6 (the grid's f32 directions make slivers of
                    // ~1e-8 between vertices that β ≈ 0 maps onto the same rim point).
                    let bc = [0, 1, 2].map(|i| c.0[i] - b.0[i]);
                    let longest = [ab, ac, bc]
                        .map(|v| dot(v, v))
                        .into_iter()
                        .fold(0.0, f64::max);
                    if dot(face, face) <= 1e-12 * longest {
                        continue;
                    }
                    let ns = [0, 1, 2].map(|i| a.1[i] + b.1[i] + c.1[i]);
                    assert!(
                        dot(face, ns) > 0.0,
                        "mesh:{level} {e:?}: triangle {t:?} inward"
                    );
                }
            }
        }
    }

    /// No NaN or infinity for any direction (on or off the grid, in f32 as stored) and any
    /// exponent between 1e-30 and 5, the extremes mixed.
    #[test]
    fn superquadric_vertex_never_nan() {
        let extremes = [1e-30, 1e-20, 1e-5, 0.5, 1.0, 2.0, 3.0, 5.0];
        let mut dirs = grid_directions(6);
        let mut x = 0.5f64;
        for _ in 0..2000 {
            // Pseudo-random directions, some next to the poles and the mirror planes.
            let mut next = || {
                x = (x * 3.987 + 0.1234).fract();
                2.0 * x - 1.0
            };
            let v = [next(), next() * 1e-3f64.powf(next().abs() * 3.0), next()];
            dirs.push(normalize(v).map(|c| f64::from(c as f32)));
        }
        for &a in &extremes {
            for &b in &extremes {
                for &c in &extremes {
                    for d in dirs.iter().step_by(7) {
                        let (p, n) = superquadric_vertex(*d, [a, b, c]);
                        assert!(
                            p.iter().chain(&n).all(|v| v.is_finite()),
                            "{:?} at {d:?}: {p:?} {n:?}",
                            [a, b, c]
                        );
                        assert!((dot(n, n) - 1.0).abs() < 1e-12 && dot(n, p) > 0.0);
                    }
                }
            }
        }
    }
}
