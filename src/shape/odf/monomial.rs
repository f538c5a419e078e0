//! The series as a homogeneous polynomial in x, y, z: r~(u) = Σ p_abc x^a y^b z^c over
//! a + b + c = L, which equals the plain series on the unit sphere (each term of degree l < L
//! times (x² + y² + z²)^((L − l)/2)). There are as many such monomials as even-order SH
//! coefficients up to L ((L + 1)(L + 2)/2), so a glyph's payload keeps its size; the GPU
//! evaluates them by Horner's rule in a few dozen multiply–adds where the plain series' recurrence
//! costs two square roots a term. That evaluation is the per-fragment set-up of the crossing
//! (L + 1 values on the ray plane's great circle), so it sets what an exact ODF costs.
//!
//! **Order**: a = 0 … L, then b = 0 … L − a (c = L − a − b); [`monomial_index`].
//!
//! **Conditioning.** Monomial coefficients grow with L and cancel on the sphere: the rounding
//! error of an f32 evaluation is about 2⁻²⁴ Σ |p_abc| |x^a y^b z^c|, which the tests bound
//! relative to the series' largest value ([`MAX_MONOMIAL_LMAX`] is where that stays small);
//! above it the GPU evaluates the plain series.

use std::sync::OnceLock;

use glam::DVec3;

use crate::sh::count_of_lmax;

/// The largest lmax whose series the GPU evaluates as monomials (module doc).
pub const MAX_MONOMIAL_LMAX: u32 = 12;

/// How a payload holds a series: the monomials (lmax ≤ [`MAX_MONOMIAL_LMAX`]) or, above, the
/// plain coefficients ([`super::plain_value`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesForm {
    Plain,
    Monomial,
}

impl SeriesForm {
    pub fn for_lmax(lmax: u32) -> Self {
        // An SH series' lmax is even; an odd one is not a series the payload holds.
        if lmax <= MAX_MONOMIAL_LMAX && lmax.is_multiple_of(2) {
            SeriesForm::Monomial
        } else {
            SeriesForm::Plain
        }
    }

    /// The coefficients of this form of the series whose plain coefficients are `plain`.
    pub fn coefficients(self, plain: &[f64], lmax: u32) -> Vec<f64> {
        match self {
            SeriesForm::Plain => plain.to_vec(),
            SeriesForm::Monomial => monomials_of(plain, lmax).unwrap_or_else(|| plain.to_vec()),
        }
    }

    /// The series of these `coefficients` at unit `u` and the gradient of its polynomial
    /// extension.
    pub fn value_gradient(self, coefficients: &[f64], lmax: u32, u: DVec3) -> (f64, DVec3) {
        match self {
            SeriesForm::Plain => super::plain_value_gradient(coefficients, lmax, u),
            SeriesForm::Monomial => monomial_value_gradient(coefficients, lmax, u),
        }
    }

    pub fn value(self, coefficients: &[f64], lmax: u32, u: DVec3) -> f64 {
        match self {
            SeriesForm::Plain => super::plain_value(coefficients, lmax, u),
            SeriesForm::Monomial => monomial_value(coefficients, lmax, u),
        }
    }
}

/// The position of x^a y^b z^(L−a−b) in the order of the module doc.
pub fn monomial_index(lmax: u32, a: u32, b: u32) -> usize {
    // Rows a' < a hold L − a' + 1 entries each.
    let (l, a, b) = (lmax as usize, a as usize, b as usize);
    a * (l + 1) - a * (a.saturating_sub(1)) / 2 + b
}

/// A polynomial in x, y, z as a dense cube of coefficients [a][b][c] (each power ≤ n).
#[derive(Clone)]
struct Poly {
    n: usize,
    c: Vec<f64>,
}

impl Poly {
    fn zero(n: usize) -> Self {
        Self {
            n,
            c: vec![0.0; (n + 1).pow(3)],
        }
    }

    fn at(&self, a: usize, b: usize, c: usize) -> usize {
        (a * (self.n + 1) + b) * (self.n + 1) + c
    }

    fn constant(n: usize, v: f64) -> Self {
        let mut p = Self::zero(n);
        p.c[0] = v;
        p
    }

    /// This times x (axis 0), y (1) or z (2); powers past n are dropped (none are reached).
    fn times(&self, axis: usize) -> Self {
        let n = self.n;
        let mut out = Self::zero(n);
        for a in 0..=n {
            for b in 0..=n {
                for c in 0..=n {
                    let v = self.c[self.at(a, b, c)];
                    if v == 0.0 {
                        continue;
                    }
                    let (a2, b2, c2) = match axis {
                        0 => (a + 1, b, c),
                        1 => (a, b + 1, c),
                        _ => (a, b, c + 1),
                    };
                    if a2.max(b2).max(c2) <= n {
                        let k = out.at(a2, b2, c2);
                        out.c[k] += v;
                    }
                }
            }
        }
        out
    }

    /// This times x² + y² + z².
    fn times_r2(&self) -> Self {
        let mut out = self.times(0).times(0);
        out.add(1.0, &self.times(1).times(1));
        out.add(1.0, &self.times(2).times(2));
        out
    }

    fn add(&mut self, k: f64, other: &Self) {
        self.c
            .iter_mut()
            .zip(&other.c)
            .for_each(|(s, o)| *s += k * o);
    }

    fn scaled(&self, k: f64) -> Self {
        Self {
            n: self.n,
            c: self.c.iter().map(|v| k * v).collect(),
        }
    }
}

/// The matrix taking plain coefficients (lmax, [`super::plain_value`]'s order) to monomial
/// coefficients: column j is plain basis function j as a homogeneous polynomial of degree lmax,
/// stored row-major (count × count). Made once per even lmax ≤ [`MAX_MONOMIAL_LMAX`].
pub fn plain_to_monomial(lmax: u32) -> Option<&'static [f64]> {
    const KEPT: usize = (MAX_MONOMIAL_LMAX / 2 + 1) as usize;
    static TABLES: [OnceLock<Vec<f64>>; KEPT] = [const { OnceLock::new() }; KEPT];
    if SeriesForm::for_lmax(lmax) != SeriesForm::Monomial {
        return None;
    }
    let count = count_of_lmax(lmax).ok()?;
    Some(TABLES[(lmax / 2) as usize].get_or_init(|| {
        let columns = plain_basis_polynomials(lmax);
        let mut m = vec![0.0; count * count];
        for (j, poly) in columns.iter().enumerate() {
            for a in 0..=lmax {
                for b in 0..=lmax - a {
                    let c = lmax - a - b;
                    let v = poly.c[poly.at(a as usize, b as usize, c as usize)];
                    m[monomial_index(lmax, a, b) * count + j] = v;
                }
            }
        }
        m
    }))
}

/// Each plain basis function (the recurrence of `plain_basis` in series.rs, on polynomials),
/// homogenised to degree lmax.
fn plain_basis_polynomials(lmax: u32) -> Vec<Poly> {
    let n = lmax as usize;
    let count = count_of_lmax(lmax).unwrap_or(0);
    let mut out = vec![Poly::zero(n); count];
    let (mut c, mut s) = (Poly::constant(n, 1.0), Poly::zero(n));
    let mut seed = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    for m in 0..=lmax {
        let mf = f64::from(m);
        if m > 0 {
            seed *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            // (c + i s)(x + i y)
            let mut cn = c.times(0);
            cn.add(-1.0, &s.times(1));
            let mut sn = s.times(0);
            sn.add(1.0, &c.times(1));
            (c, s) = (cn, sn);
        }
        let (mut q2, mut q1) = (Poly::zero(n), Poly::constant(n, seed));
        for l in m..=lmax {
            if l > m {
                let lf = f64::from(l);
                let q0 = if l == m + 1 {
                    q1.times(2).scaled((2.0 * mf + 3.0).sqrt())
                } else {
                    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                    let bb = (((lf - 1.0) * (lf - 1.0) - mf * mf)
                        / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0))
                        .sqrt();
                    let mut q0 = q1.times(2);
                    q0.add(-bb, &q2.times_r2());
                    q0.scaled(a)
                };
                (q2, q1) = (q1, q0);
            }
            if l % 2 != 0 {
                continue;
            }
            let base = (l * (l + 1) / 2) as usize;
            let lift = |p: Poly| {
                let mut p = p;
                for _ in 0..(lmax - l) / 2 {
                    p = p.times_r2();
                }
                p
            };
            out[base + m as usize] = lift(mul(&q1, &c));
            if m > 0 {
                out[base - m as usize] = lift(mul(&q1, &s));
            }
        }
    }
    out
}

fn mul(p: &Poly, q: &Poly) -> Poly {
    let n = p.n;
    let mut out = Poly::zero(n);
    for a in 0..=n {
        for b in 0..=n {
            for c in 0..=n {
                let v = p.c[p.at(a, b, c)];
                if v == 0.0 {
                    continue;
                }
                for a2 in 0..=n - a {
                    for b2 in 0..=n - b {
                        for c2 in 0..=n - c {
                            let w = q.c[q.at(a2, b2, c2)];
                            if w != 0.0 {
                                let k = out.at(a + a2, b + b2, c + c2);
                                out.c[k] += v * w;
                            }
                        }
                    }
                }
            }
        }
    }
    out
}

/// The monomial coefficients of a series given by its plain coefficients; `None` above
/// [`MAX_MONOMIAL_LMAX`].
pub fn monomials_of(plain: &[f64], lmax: u32) -> Option<Vec<f64>> {
    let m = plain_to_monomial(lmax)?;
    let n = plain.len();
    (m.len() == n * n).then(|| {
        m.chunks_exact(n)
            .map(|row| row.iter().zip(plain).map(|(a, b)| a * b).sum())
            .collect()
    })
}

/// The homogeneous polynomial at `u` and its gradient, by odf.wgsl's `odf_monomial_gradient`
/// scheme in f64: Horner's rule in x over the rows a = L … 0, each row a binary form in y and z
/// by Horner's rule in y with z's powers, derivatives carried along.
pub fn monomial_value_gradient(p: &[f64], lmax: u32, u: DVec3) -> (f64, DVec3) {
    let (x, y, z) = (u.x, u.y, u.z);
    let (mut f, mut fx, mut fy, mut fz) = (0.0, 0.0, 0.0, 0.0);
    for a in (0..=lmax).rev() {
        let row = monomial_index(lmax, a, 0);
        let n = (lmax - a) as usize;
        let (mut h, mut hy, mut hz) = (p[row + n], 0.0, 0.0);
        let (mut zp, mut zpz) = (1.0, 0.0);
        for b in (0..n).rev() {
            zpz = zpz * z + zp;
            zp *= z;
            hy = hy * y + h;
            hz = hz * y + p[row + b] * zpz;
            h = h * y + p[row + b] * zp;
        }
        fx = fx * x + f;
        fy = fy * x + hy;
        fz = fz * x + hz;
        f = f * x + h;
    }
    (f, DVec3::new(fx, fy, fz))
}

/// The homogeneous polynomial at `u` (odf.wgsl's `odf_monomial`).
pub fn monomial_value(p: &[f64], lmax: u32, u: DVec3) -> f64 {
    let (x, y, z) = (u.x, u.y, u.z);
    let mut f = 0.0;
    for a in (0..=lmax).rev() {
        let row = monomial_index(lmax, a, 0);
        let n = (lmax - a) as usize;
        let (mut h, mut zp) = (p[row + n], 1.0);
        for b in (0..n).rev() {
            zp *= z;
            h = h * y + p[row + b] * zp;
        }
        f = f * x + h;
    }
    f
}

/// Σ |p_abc x^a y^b z^c| at `u`: what an f32 evaluation's rounding error is proportional to.
pub fn monomial_magnitude(p: &[f64], lmax: u32, u: DVec3) -> f64 {
    let l = lmax as i32;
    let mut s = 0.0;
    let mut k = 0;
    for a in 0..=l {
        for b in 0..=l - a {
            let c = l - a - b;
            s += (p[k] * u.x.powi(a) * u.y.powi(b) * u.z.powi(c)).abs();
            k += 1;
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::{ShBasis, ShEval};
    use crate::shape::odf::test_util::{lcg, random_dir};
    use crate::shape::odf::{plain_of, plain_value_gradient};

    /// odf.wgsl decides the form by the same bound.
    #[test]
    fn the_shader_takes_monomials_to_the_same_lmax() {
        let line = format!("const ODF_MONOMIAL_LMAX: u32 = {MAX_MONOMIAL_LMAX}u;");
        assert!(crate::shape::odf::WGSL.contains(&line), "{line}");
    }

    #[test]
    fn the_index_walks_the_order() {
        for lmax in [0, 2, 8, 12] {
            let mut k = 0;
            for a in 0..=lmax {
                for b in 0..=lmax - a {
                    assert_eq!(monomial_index(lmax, a, b), k);
                    k += 1;
                }
            }
            assert_eq!(k, count_of_lmax(lmax).unwrap());
        }
    }

    /// The monomials equal the plain series and its tangential gradient on the sphere, for
    /// random series and the sharpest lobes each order has; and the rounding an f32 Horner
    /// evaluation makes stays small against the series' largest value.
    #[test]
    fn monomials_are_the_plain_series_on_the_sphere() {
        let mut seed = 7;
        let x = DVec3::new(0.3, 0.9, -0.2).normalize();
        for lmax in (0..=MAX_MONOMIAL_LMAX).step_by(2) {
            let n = count_of_lmax(lmax).unwrap();
            let mut random: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            random[0] = 2.0;
            let mut delta = vec![0.0; n];
            ShEval::new(lmax, ShBasis::Tournier07)
                .unwrap()
                .row(x.to_array(), &mut delta);
            for c in [random, delta] {
                let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
                let mono = monomials_of(&plain, lmax).unwrap();
                let mut largest = 0.0f64;
                let mut worst = 0.0f64;
                let mut magnitude = 0.0f64;
                for _ in 0..2000 {
                    let u = random_dir(&mut seed);
                    let (f, g) = plain_value_gradient(&plain, lmax, u);
                    let (fm, gm) = monomial_value_gradient(&mono, lmax, u);
                    assert_eq!(fm, monomial_value(&mono, lmax, u));
                    let tangential = |g: DVec3| g - g.dot(u) * u;
                    largest = largest.max(f.abs());
                    worst = worst
                        .max((f - fm).abs())
                        .max((tangential(g) - tangential(gm)).length() / f64::from(lmax.max(1)));
                    magnitude = magnitude.max(monomial_magnitude(&mono, lmax, u));
                }
                assert!(
                    worst <= 1e-11 * largest,
                    "lmax {lmax}: {worst} of {largest}"
                );
                // Measured: at most 7.0 (lmax 8) and 13.9 (lmax 12), so f32 rounding stays
                // near 1e-6 of the largest value.
                assert!(
                    magnitude <= 16.0 * largest,
                    "lmax {lmax}: {magnitude} of {largest}"
                );
            }
        }
    }
}
