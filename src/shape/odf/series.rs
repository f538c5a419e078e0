//! The series in the plain basis the GPU evaluates: conversion from every basis, evaluation,
//! and the rigorous bounds a glyph is scaled and cast with (the module doc of [`super`]).

use glam::DVec3;

use crate::sh::{ShBasis, ShError, convert, degrees, lmax_of_count};
use crate::shape::ellipsoid::icosphere;

/// The plain coefficients of a series (`basis`, any lmax) scaled by `k`: r~ = k·f.
pub fn plain_of(c: &[f64], basis: ShBasis, k: f64) -> Result<Vec<f64>, ShError> {
    let t = convert(c, basis, ShBasis::Tournier07)?;
    let lmax = lmax_of_count(c.len())?;
    Ok(degrees(lmax)
        .zip(t)
        .map(|((_, m), v)| k * v * plain_factor(m))
        .collect())
}

/// plain = tournier07 × this.
fn plain_factor(m: i32) -> f64 {
    if m == 0 {
        1.0
    } else if m % 2 == 0 {
        std::f64::consts::SQRT_2
    } else {
        -std::f64::consts::SQRT_2
    }
}

/// Σₗ ‖cₗ‖ √((2l+1)/4π) and Σₗ ‖cₗ‖ √(l(l+1)(2l+1)/4π) for plain coefficients: bounds of |f|
/// and of |∇_S f| on the sphere (module doc).
pub fn series_bounds(plain: &[f64], lmax: u32) -> (f64, f64) {
    let mut norms = vec![0.0; lmax as usize + 1];
    for ((l, m), &p) in degrees(lmax).zip(plain) {
        let c = p / plain_factor(m);
        norms[l as usize] += c * c;
    }
    let four_pi = 4.0 * std::f64::consts::PI;
    norms
        .iter()
        .enumerate()
        .fold((0.0, 0.0), |(v, g), (l, &n2)| {
            let l = l as f64;
            let n = n2.sqrt();
            (
                v + n * ((2.0 * l + 1.0) / four_pi).sqrt(),
                g + n * (l * (l + 1.0) * (2.0 * l + 1.0) / four_pi).sqrt(),
            )
        })
}

/// Directions on which a series is sampled, and their covering radius: every direction lies
/// within `cover` (rad) of one of them or of its opposite. The series have even degrees only
/// (f(−u) = f(u)), so one direction of each opposite pair samples both: half the products and
/// half the scans of a scene's build, every bound unchanged.
pub struct Sphere {
    pub directions: Vec<DVec3>,
    /// The directions' x, y and z as three arrays (for loops the compiler vectorises).
    pub components: [Vec<f64>; 3],
    pub cover: f64,
}

/// The geodesic sphere of icosphere level 4 (2562 directions, 1281 kept) for lmax ≤ 8, of level 5 (10242, 5121 kept)
/// above: fine enough that Bernstein's bound below stays tight. The covering radius is the
/// largest circumradius of the triangles (each point of a triangle lies within it of a
/// corner), computed, with 1 % to spare.
pub fn sphere_for(lmax: u32) -> &'static Sphere {
    static SPHERES: [std::sync::OnceLock<Sphere>; 2] =
        [std::sync::OnceLock::new(), std::sync::OnceLock::new()];
    let k = usize::from(lmax > 8);
    SPHERES[k].get_or_init(|| {
        let mesh = icosphere(4 + k as u8);
        let all: Vec<DVec3> = mesh
            .vertices
            .iter()
            .map(|v| DVec3::from(v.position.map(f64::from)).normalize())
            .collect();
        let cover = mesh
            .indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|i| all[t[i] as usize]);
                let n = (b - a).cross(c - a).normalize();
                let n = if n.dot(a) < 0.0 { -n } else { n };
                n.dot(a).clamp(-1.0, 1.0).acos()
            })
            .fold(0.0, f64::max);
        // The icosphere is symmetric about its centre: keep the direction of each opposite
        // pair on the upper side (z, then y, then x deciding; the tolerance takes a pair whose
        // decisive coordinates round to ±tiny as one).
        const TIE: f64 = 1e-9;
        let upper = |u: &DVec3| {
            u.z > TIE || (u.z.abs() <= TIE && (u.y > TIE || (u.y.abs() <= TIE && u.x > 0.0)))
        };
        let directions: Vec<DVec3> = all.into_iter().filter(upper).collect();
        Sphere {
            components: [0, 1, 2].map(|i| directions.iter().map(|u| u[i]).collect()),
            directions,
            cover: cover * 1.01,
        }
    })
}

/// The values of a series at each direction of [`sphere_for`] its lmax: a dot product per
/// direction with [`basis_table`]'s row (a scene's build spent nearly all its time here when
/// each direction ran the recurrence: 1.9 ms of CPU a voxel at lmax 8).
pub fn sampled_values(plain: &[f64], lmax: u32) -> Vec<f64> {
    let dirs = &sphere_for(lmax).directions;
    match basis_table(lmax).filter(|t| t.len() == dirs.len() * plain.len()) {
        Some(table) => table
            .chunks_exact(plain.len())
            .map(|row| dot(row, plain))
            .collect(),
        None => dirs.iter().map(|&u| plain_value(plain, lmax, u)).collect(),
    }
}

/// [`sampled_values`] of many series of one lmax at once: the plain coefficients side by side
/// (`plains`, each `count_of_lmax(lmax)` long) times the basis table, one matrix product (a
/// blocked, vectorised GEMM: a scene of 10,000 lmax-12 glyphs spent about 2 s of its 3.4 s build
/// on the per-series dot products). Column j of the result (column-major, `directions × series`)
/// is series j's values.
pub fn sampled_values_many(plains: &[&[f64]], lmax: u32) -> nalgebra::DMatrix<f64> {
    let dirs = sphere_for(lmax).directions.len();
    let count = crate::sh::count_of_lmax(lmax).unwrap_or(0);
    let basis = basis_matrix(lmax);
    match basis.filter(|b| b.ncols() == count && plains.iter().all(|p| p.len() == count)) {
        Some(b) => {
            let c = nalgebra::DMatrix::from_fn(count, plains.len(), |i, j| plains[j][i]);
            b * c
        }
        None => nalgebra::DMatrix::from_fn(dirs, plains.len(), |i, j| {
            plain_value(plains[j], lmax, sphere_for(lmax).directions[i])
        }),
    }
}

/// [`basis_table`] as a matrix (directions × coefficients), made once per lmax.
fn basis_matrix(lmax: u32) -> Option<&'static nalgebra::DMatrix<f64>> {
    const KEPT: usize = 16;
    static MATRICES: [std::sync::OnceLock<Option<nalgebra::DMatrix<f64>>>; KEPT] =
        [const { std::sync::OnceLock::new() }; KEPT];
    let n = crate::sh::count_of_lmax(lmax).ok()?;
    MATRICES
        .get((lmax / 2) as usize)?
        .get_or_init(|| {
            let table = basis_table(lmax)?;
            Some(nalgebra::DMatrix::from_row_slice(table.len() / n, n, table))
        })
        .as_ref()
}

/// The smallest and largest of `values`.
pub fn range_of(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

/// The smallest and largest value of a series on [`sphere_for`] its lmax ([`sampled_values`]).
pub fn sampled_range(plain: &[f64], lmax: u32) -> (f64, f64) {
    range_of(&sampled_values(plain, lmax))
}

/// Σ aᵢbᵢ in four running sums (which the compiler keeps in vector lanes).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, a1) = a.split_at(a.len() / 4 * 4);
    let (b4, b1) = b.split_at(a4.len().min(b.len()));
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = a1.iter().zip(b1).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// The plain basis functions at each direction of [`sphere_for`] `lmax`, a row of
/// `count_of_lmax(lmax)` per direction, made once per lmax (lmax 8: 0.9 MB; lmax 12: 7.5 MB);
/// `None` for an lmax with no SH count.
pub fn basis_table(lmax: u32) -> Option<&'static [f64]> {
    const KEPT: usize = 16;
    static TABLES: [std::sync::OnceLock<Vec<f64>>; KEPT] =
        [const { std::sync::OnceLock::new() }; KEPT];
    let n = crate::sh::count_of_lmax(lmax).ok()?;
    let slot = TABLES.get((lmax / 2) as usize)?;
    Some(slot.get_or_init(|| {
        let dirs = &sphere_for(lmax).directions;
        let mut t = vec![0.0; dirs.len() * n];
        for (row, &u) in t.chunks_exact_mut(n).zip(dirs) {
            plain_basis(lmax, u, row);
        }
        t
    }))
}

/// Each plain basis function at unit `u`, in the plain order (`out`: `count_of_lmax(lmax)`
/// values): [`plain_value_gradient`]'s terms without their coefficients.
fn plain_basis(lmax: u32, u: DVec3, out: &mut [f64]) {
    let (x, y, z) = (u.x, u.y, u.z);
    let (mut c, mut s) = (1.0, 0.0);
    let mut seed = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    for m in 0..=lmax {
        let mf = f64::from(m);
        if m > 0 {
            seed *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let (mut q2, mut q1) = (0.0, seed);
        for l in m..=lmax {
            if l > m {
                let lf = f64::from(l);
                let q0 = if l == m + 1 {
                    (2.0 * mf + 3.0).sqrt() * z * q1
                } else {
                    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                    let bb = (((lf - 1.0) * (lf - 1.0) - mf * mf)
                        / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0))
                        .sqrt();
                    a * (z * q1 - bb * q2)
                };
                (q2, q1) = (q1, q0);
            }
            if l % 2 != 0 {
                continue;
            }
            let base = (l * (l + 1) / 2) as usize;
            out[base + m as usize] = q1 * c;
            if m > 0 {
                out[base - m as usize] = q1 * s;
            }
        }
    }
}

/// Rigorous bounds of a series whose sampled range ([`sampled_range`]) is `(min, max)`: G ≥
/// |∇_S f| and R ≥ f everywhere. G is the smaller of the addition theorem's bound
/// ([`series_bounds`]) and Bernstein's inequality for spherical polynomials of degree L,
/// |∇_S f| ≤ L ‖f‖∞ (along any great circle f is a trigonometric polynomial of degree ≤ L),
/// with ‖f‖∞ ≤ max(|min|, |max|) / (1 − L·cover) (the sample nearest any point is within
/// `cover` of it); R the smaller of the addition theorem's and max + G·cover.
pub fn rigorous_bounds(plain: &[f64], lmax: u32, (min, max): (f64, f64)) -> (f64, f64) {
    let cover = sphere_for(lmax).cover;
    let (vb, g_cs) = series_bounds(plain, lmax);
    let shrink = 1.0 - f64::from(lmax) * cover;
    let g_bernstein = if shrink > 0.0 {
        f64::from(lmax) * min.abs().max(max.abs()) / shrink
    } else {
        f64::INFINITY
    };
    let g = g_cs.min(g_bernstein);
    (g, vb.min(max + g * cover))
}

/// The plain series at unit `u`.
pub fn plain_value(plain: &[f64], lmax: u32, u: DVec3) -> f64 {
    plain_value_gradient(plain, lmax, u).0
}

/// The plain series at unit `u` and the gradient of its polynomial extension.
pub fn plain_value_gradient(plain: &[f64], lmax: u32, u: DVec3) -> (f64, DVec3) {
    let (x, y, z) = (u.x, u.y, u.z);
    let mut f = 0.0;
    let mut grad = DVec3::ZERO;
    // (x + iy)^m = c + i s, and (x + iy)^(m−1).
    let (mut c, mut s) = (1.0, 0.0);
    let (mut c1, mut s1) = (0.0, 0.0);
    let mut seed = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    for m in 0..=lmax {
        if m > 0 {
            let mf = f64::from(m);
            seed *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (c1, s1) = (c, s);
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let mf = f64::from(m);
        // ∂/∂x, ∂/∂y of Re and Im (x + iy)^m.
        let (cx, cy) = (mf * c1, -mf * s1);
        let (sx, sy) = (mf * s1, mf * c1);
        // Q_l^m and dQ/dz for l = m, m + 1, …
        let (mut q2, mut d2) = (0.0, 0.0);
        let (mut q1, mut d1) = (seed, 0.0);
        for l in m..=lmax {
            if l > m {
                let lf = f64::from(l);
                let (q0, d0) = if l == m + 1 {
                    let a = (2.0 * mf + 3.0).sqrt();
                    (a * z * q1, a * q1)
                } else {
                    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                    let bb = (((lf - 1.0) * (lf - 1.0) - mf * mf)
                        / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0))
                        .sqrt();
                    (a * (z * q1 - bb * q2), a * (q1 + z * d1 - bb * d2))
                };
                (q2, d2) = (q1, d1);
                (q1, d1) = (q0, d0);
            }
            if l % 2 != 0 {
                continue;
            }
            let base = (l * (l + 1) / 2) as usize;
            let pc = plain[base + m as usize];
            f += pc * q1 * c;
            grad += pc * DVec3::new(q1 * cx, q1 * cy, d1 * c);
            if m > 0 {
                let ps = plain[base - m as usize];
                f += ps * q1 * s;
                grad += ps * DVec3::new(q1 * sx, q1 * sy, d1 * s);
            }
        }
    }
    (f, grad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::ShEval;
    use crate::shape::odf::test_util::{lcg, random_dir};

    /// The block product gives each series' own values (to rounding), at both spheres.
    #[test]
    fn many_series_at_once_are_each_series() {
        let mut seed = 3;
        for lmax in [4, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let plains: Vec<Vec<f64>> = (0..5)
                .map(|_| (0..n).map(|_| lcg(&mut seed)).collect())
                .collect();
            let refs: Vec<&[f64]> = plains.iter().map(|p| p.as_slice()).collect();
            let many = sampled_values_many(&refs, lmax);
            for (j, p) in plains.iter().enumerate() {
                let one = sampled_values(p, lmax);
                assert_eq!(many.nrows(), one.len());
                for (a, b) in many.column(j).iter().zip(&one) {
                    assert!(
                        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                        "lmax {lmax}: {a} {b}"
                    );
                }
            }
        }
    }

    /// The table's rows are the plain series' terms: a series' value at each sampled direction
    /// is its dot product with the row, to rounding, at every lmax the reader takes to 12.
    #[test]
    fn basis_table_rows_evaluate_the_plain_series() {
        let mut seed = 7;
        for lmax in [2, 4, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let plain: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            let table = basis_table(lmax).unwrap();
            let dirs = &sphere_for(lmax).directions;
            assert_eq!(table.len(), dirs.len() * n);
            for (k, &u) in dirs.iter().enumerate().step_by(97) {
                let want = plain_value(&plain, lmax, u);
                let got = dot(&table[k * n..(k + 1) * n], &plain);
                assert!(
                    (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "lmax {lmax}"
                );
            }
            let (lo, hi) = sampled_range(&plain, lmax);
            let direct = dirs.iter().map(|&u| plain_value(&plain, lmax, u));
            let (dlo, dhi) = direct.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
            assert!(
                (lo - dlo).abs() <= 1e-12 && (hi - dhi).abs() <= 1e-12,
                "lmax {lmax}"
            );
        }
        assert!(basis_table(3).is_none());
    }

    /// The plain series is the tournier07 series (and so, by the SH tests, DIPY's and MRtrix's)
    /// in every basis, and its gradient's tangential part is ShEval's sphere gradient.
    #[test]
    fn plain_series_is_each_basis_series() {
        let mut seed = 7;
        for lmax in [0, 2, 4, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            for basis in [
                ShBasis::Tournier07,
                ShBasis::Descoteaux07,
                ShBasis::Descoteaux07Legacy,
            ] {
                let plain = plain_of(&c, basis, 1.0).unwrap();
                let mut ev = ShEval::new(lmax, basis).unwrap();
                for _ in 0..50 {
                    let u = random_dir(&mut seed);
                    let (want, wg) = ev.value_gradient(&c, u.to_array());
                    let (got, grad) = plain_value_gradient(&plain, lmax, u);
                    let tangential = grad - grad.dot(u) * u;
                    assert!(
                        (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                        "{lmax} {basis:?}"
                    );
                    let e = (tangential - DVec3::from(wg)).length();
                    assert!(e <= 1e-11 * (1.0 + DVec3::from(wg).length()), "{lmax} {e}");
                }
                // At the poles too (ShEval takes φ = 0 there).
                for u in [DVec3::Z, -DVec3::Z] {
                    let want = ev.value(&c, u.to_array());
                    assert!(
                        (plain_value(&plain, lmax, u) - want).abs() < 1e-12 * (1.0 + want.abs())
                    );
                }
            }
        }
    }

    /// The bounds hold: no sampled value or gradient exceeds them.
    #[test]
    fn series_bounds_bound() {
        let mut seed = 11;
        for lmax in [2, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
            let (vb, gb) = series_bounds(&plain, lmax);
            for _ in 0..2000 {
                let u = random_dir(&mut seed);
                let (v, grad) = plain_value_gradient(&plain, lmax, u);
                assert!(v.abs() <= vb);
                assert!((grad - grad.dot(u) * u).length() <= gb);
            }
            let (min, max) = sampled_range(&plain, lmax);
            assert!(max <= vb && -min <= vb);
            // The rigorous bounds hold on directions far denser than the samples'.
            let (g, r) = rigorous_bounds(&plain, lmax, (min, max));
            for _ in 0..20000 {
                let u = random_dir(&mut seed);
                let (v, grad) = plain_value_gradient(&plain, lmax, u);
                assert!(v <= r);
                assert!((grad - grad.dot(u) * u).length() <= g, "{lmax}");
            }
        }
    }

    /// The covering radius holds: no random direction is farther from every sample and its
    /// opposite; the samples are half the icosphere's vertices, their opposites the other half.
    #[test]
    fn every_direction_is_within_the_cover_of_a_sample() {
        let mut seed = 19;
        for (lmax, level) in [(8, 4), (12, 5)] {
            let s = sphere_for(lmax);
            let all: Vec<DVec3> = icosphere(level)
                .vertices
                .iter()
                .map(|v| DVec3::from(v.position.map(f64::from)).normalize())
                .collect();
            assert_eq!(2 * s.directions.len(), all.len());
            for d in s.directions.iter().step_by(7) {
                let opposite = all
                    .iter()
                    .map(|a| (*a + *d).length())
                    .fold(f64::MAX, f64::min);
                let twin = s
                    .directions
                    .iter()
                    .map(|a| (*a + *d).length())
                    .fold(f64::MAX, f64::min);
                assert!(opposite < 1e-12 && twin > 1e-3, "{d}: {opposite} {twin}");
            }
            for _ in 0..300 {
                let u = random_dir(&mut seed);
                let nearest = s
                    .directions
                    .iter()
                    .map(|d| d.dot(u).abs().clamp(-1.0, 1.0).acos())
                    .fold(f64::INFINITY, f64::min);
                assert!(nearest <= s.cover, "{nearest} {}", s.cover);
            }
            assert!(s.cover < 0.05 && s.cover > 0.005, "{}", s.cover);
        }
    }
}
