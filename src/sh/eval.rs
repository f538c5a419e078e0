//! f(u) = Σ c_j Y_j(u) and its gradient on the sphere, for one basis and lmax (module doc, §3).

use super::basis::{ShBasis, ShError, Trig, count_of_lmax, degrees, lmax_of_count};
use super::legendre::{Legendre, tri};

/// Evaluates SH series of one basis and lmax, keeping its scratch between calls (the peak
/// finder evaluates thousands of directions per voxel).
#[derive(Debug, Clone)]
pub struct ShEval {
    basis: ShBasis,
    lmax: u32,
    leg: Legendre,
    /// cos(mφ), sin(mφ) for m = 0..=lmax.
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// Per coefficient: (l, |m|, trig, sign · w), w = √2 for m ≠ 0.
    terms: Vec<(u32, u32, Trig, f64)>,
}

/// Where a direction is, in the terms the series needs.
struct Polar {
    z: f64,
    s: f64,
    cos_phi: f64,
    sin_phi: f64,
}

/// `u` normalised, as (cos θ, sin θ, cos φ, sin φ); φ = 0 on the axis (any φ is the same
/// point there, and the gradient's frame is then the limit along φ = 0). `None` for a zero or
/// non-finite vector.
fn polar(u: [f64; 3]) -> Option<Polar> {
    let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    let r = u[0].hypot(u[1]);
    let (cos_phi, sin_phi) = if r > 0.0 {
        (u[0] / r, u[1] / r)
    } else {
        (1.0, 0.0)
    };
    Some(Polar {
        z: u[2] / n,
        s: r / n,
        cos_phi,
        sin_phi,
    })
}

impl ShEval {
    /// An evaluator of lmax `lmax` series in `basis`.
    pub fn new(lmax: u32, basis: ShBasis) -> Result<Self, ShError> {
        count_of_lmax(lmax)?;
        let terms = degrees(lmax)
            .map(|(l, m)| {
                let (trig, sign) = basis.term(m);
                let w = if m == 0 {
                    1.0
                } else {
                    std::f64::consts::SQRT_2
                };
                (l, m.unsigned_abs(), trig, sign * w)
            })
            .collect();
        Ok(ShEval {
            basis,
            lmax,
            leg: Legendre::new(lmax),
            cos: vec![0.0; lmax as usize + 1],
            sin: vec![0.0; lmax as usize + 1],
            terms,
        })
    }

    /// The evaluator for `count` coefficients.
    pub fn for_count(count: usize, basis: ShBasis) -> Result<Self, ShError> {
        Self::new(lmax_of_count(count)?, basis)
    }

    pub fn basis(&self) -> ShBasis {
        self.basis
    }

    pub fn lmax(&self) -> u32 {
        self.lmax
    }

    /// Coefficients per series.
    pub fn count(&self) -> usize {
        self.terms.len()
    }

    fn prepare(&mut self, u: [f64; 3]) -> Option<Polar> {
        let p = polar(u)?;
        self.leg.at(p.z, p.s);
        // cos(mφ) + i sin(mφ) by repeated multiplication: exact at m = 0, 1 and off by a few
        // ulps at m = 30.
        let (mut c, mut s) = (1.0, 0.0);
        for m in 0..=self.lmax as usize {
            self.cos[m] = c;
            self.sin[m] = s;
            (c, s) = (c * p.cos_phi - s * p.sin_phi, s * p.cos_phi + c * p.sin_phi);
        }
        Some(p)
    }

    /// The value of every basis function at `u` (any non-zero length), in coefficient order,
    /// into `out`; NaN for a zero or non-finite `u`.
    pub fn row(&mut self, u: [f64; 3], out: &mut [f64]) {
        if self.prepare(u).is_none() {
            out.fill(f64::NAN);
            return;
        }
        for (o, &(l, m, trig, k)) in out.iter_mut().zip(&self.terms) {
            let p = self.leg.p[tri(l, m)];
            *o = k
                * p
                * match trig {
                    Trig::One => 1.0,
                    Trig::Cos => self.cos[m as usize],
                    Trig::Sin => self.sin[m as usize],
                };
        }
    }

    /// f(u) for the coefficients `c` ([`Self::count`] of them); NaN for a zero or non-finite
    /// `u`.
    pub fn value(&mut self, c: &[f64], u: [f64; 3]) -> f64 {
        if self.prepare(u).is_none() {
            return f64::NAN;
        }
        self.terms
            .iter()
            .zip(c)
            .map(|(&(l, m, trig, k), &cj)| {
                let p = self.leg.p[tri(l, m)];
                cj * k
                    * p
                    * match trig {
                        Trig::One => 1.0,
                        Trig::Cos => self.cos[m as usize],
                        Trig::Sin => self.sin[m as usize],
                    }
            })
            .sum()
    }

    /// f(u) and its gradient on the unit sphere at û (the tangent vector ∂f/∂θ ê_θ +
    /// (1/sin θ) ∂f/∂φ ê_φ, orthogonal to û): the direction of steepest ascent of f along the
    /// sphere, and ∇F − (û·∇F) û for the extension F(x) = f(x/|x|).
    pub fn value_gradient(&mut self, c: &[f64], u: [f64; 3]) -> (f64, [f64; 3]) {
        let Some(p) = self.prepare(u) else {
            return (f64::NAN, [f64::NAN; 3]);
        };
        let (mut f, mut ft, mut fp) = (0.0, 0.0, 0.0);
        for (&(l, m, trig, k), &cj) in self.terms.iter().zip(c) {
            let i = tri(l, m);
            let (a, da) = match trig {
                Trig::One => (1.0, 0.0),
                // d/dφ cos(mφ) = −m sin(mφ), d/dφ sin(mφ) = m cos(mφ).
                Trig::Cos => (self.cos[m as usize], -(m as f64) * self.sin[m as usize]),
                Trig::Sin => (self.sin[m as usize], m as f64 * self.cos[m as usize]),
            };
            let w = cj * k;
            f += w * self.leg.p[i] * a;
            ft += w * self.leg.dp[i] * a;
            fp += w * self.leg.p_over_s[i] * da;
        }
        let e_theta = [p.z * p.cos_phi, p.z * p.sin_phi, -p.s];
        let e_phi = [-p.sin_phi, p.cos_phi, 0.0];
        (f, std::array::from_fn(|i| ft * e_theta[i] + fp * e_phi[i]))
    }
}

/// f(u) for the coefficients `c` in `basis` (their count gives lmax).
pub fn value(c: &[f64], basis: ShBasis, u: [f64; 3]) -> Result<f64, ShError> {
    Ok(ShEval::for_count(c.len(), basis)?.value(c, u))
}

#[cfg(test)]
mod tests {
    use super::super::basis::{convert, index};
    use super::*;
    use std::f64::consts::PI;

    fn dir(theta: f64, phi: f64) -> [f64; 3] {
        [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ]
    }

    fn unit(j: usize, n: usize) -> Vec<f64> {
        let mut c = vec![0.0; n];
        c[j] = 1.0;
        c
    }

    #[test]
    fn y00_and_the_order_2_functions_have_their_closed_forms() {
        let y00 = 1.0 / (2.0 * PI.sqrt());
        // The real l = 2 harmonics, orthonormal: √(15/4π) xz, √(15/4π) yz, √(15/16π)(x²−y²),
        // √(15/4π) xy, √(5/16π)(3z²−1).
        let k = (15.0 / (4.0 * PI)).sqrt();
        let k2 = (15.0 / (16.0 * PI)).sqrt();
        let k0 = (5.0 / (16.0 * PI)).sqrt();
        for b in ShBasis::VALUES {
            let mut e = ShEval::new(2, *b).unwrap();
            for (t, p) in [(0.3, 0.4), (1.2, -2.0), (2.9, 5.0), (0.0, 0.0), (PI, 0.0)] {
                let u = dir(t, p);
                let [x, y, z] = u;
                assert!((e.value(&unit(0, 6), u) - y00).abs() < 1e-15);
                assert!(
                    (e.value(&unit(index(2, 0), 6), u) - k0 * (3.0 * z * z - 1.0)).abs() < 1e-14
                );
                // Which signed function each m holds: the module doc's table.
                let want = |m: i32| match (b, m) {
                    (ShBasis::Tournier07, 1) => -k * x * z,
                    (ShBasis::Tournier07, -1) => -k * y * z,
                    (ShBasis::Tournier07, 2) => k2 * (x * x - y * y),
                    (ShBasis::Tournier07, -2) => k * x * y,
                    (_, 1) => -k * y * z,
                    (_, 2) => k * x * y,
                    (ShBasis::Descoteaux07, -1) => k * x * z,
                    (ShBasis::Descoteaux07Legacy, -1) => -k * x * z,
                    (_, -2) => k2 * (x * x - y * y),
                    _ => unreachable!(),
                };
                for m in [-2, -1, 1, 2] {
                    let got = e.value(&unit(index(2, m), 6), u);
                    assert!((got - want(m)).abs() < 1e-14, "{b} m {m} at {u:?}: {got}");
                }
            }
        }
    }

    /// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n).
    fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
                let mut dp = 0.0;
                for _ in 0..100 {
                    let (mut p0, mut p1) = (1.0, x);
                    for k in 2..=n {
                        let kf = k as f64;
                        (p0, p1) = (p1, ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf);
                    }
                    dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                    let dx = p1 / dp;
                    x -= dx;
                    if dx.abs() < 1e-16 {
                        break;
                    }
                }
                (x, 2.0 / ((1.0 - x * x) * dp * dp))
            })
            .collect()
    }

    #[test]
    fn every_basis_is_orthonormal_by_exact_quadrature() {
        // Gauss–Legendre in cos θ times a uniform rule in φ integrates products of degree ≤ 24
        // exactly: 13 × 26 nodes suffice for lmax 12.
        let lmax = 12;
        let n = count_of_lmax(lmax).unwrap();
        let gl = gauss_legendre(13);
        let nphi = 26;
        for b in ShBasis::VALUES {
            let mut e = ShEval::new(lmax, *b).unwrap();
            let mut gram = vec![0.0; n * n];
            let mut row = vec![0.0; n];
            for &(z, w) in &gl {
                for k in 0..nphi {
                    let phi = 2.0 * PI * k as f64 / nphi as f64;
                    let s = (1.0 - z * z).sqrt();
                    e.row([s * phi.cos(), s * phi.sin(), z], &mut row);
                    let wk = w * 2.0 * PI / nphi as f64;
                    for i in 0..n {
                        for j in 0..n {
                            gram[i * n + j] += wk * row[i] * row[j];
                        }
                    }
                }
            }
            for i in 0..n {
                for j in 0..n {
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((gram[i * n + j] - want).abs() < 1e-12, "{b} {i} {j}");
                }
            }
        }
    }

    #[test]
    fn converted_coefficients_are_the_same_function() {
        let c: Vec<f64> = (0..91).map(|i| ((i * 7 % 13) as f64 - 6.0) / 7.0).collect();
        for &a in ShBasis::VALUES {
            let mut ea = ShEval::new(12, a).unwrap();
            for &b in ShBasis::VALUES {
                let cb = convert(&c, a, b).unwrap();
                let mut eb = ShEval::new(12, b).unwrap();
                for (t, p) in [(0.3, 0.4), (1.2, -2.0), (2.9, 5.0), (0.0, 0.0)] {
                    let (fa, fb) = (ea.value(&c, dir(t, p)), eb.value(&cb, dir(t, p)));
                    assert!((fa - fb).abs() < 1e-13, "{a} → {b}: {fa} {fb}");
                }
            }
        }
    }

    #[test]
    fn the_gradient_is_the_derivative_along_the_sphere_poles_included() {
        let c: Vec<f64> = (0..91)
            .map(|i| (i as f64 * 1.3).cos() / (1.0 + i as f64))
            .collect();
        let h = 1e-6;
        for &b in ShBasis::VALUES {
            let mut e = ShEval::new(12, b).unwrap();
            for u in [
                dir(0.7, 0.2),
                dir(2.0, -1.0),
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
                dir(1e-9, 2.0),
                [0.0, 0.0, 3.0],
            ] {
                let (_, g) = e.value_gradient(&c, u);
                let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                let uh = u.map(|x| x / n);
                assert!((0..3).map(|i| g[i] * uh[i]).sum::<f64>().abs() < 1e-12);
                // Along two tangent directions t: (f(exp(h t)) − f(exp(−h t))) / 2h = g·t.
                let a = if uh[2].abs() < 0.9 {
                    [0.0, 0.0, 1.0]
                } else {
                    [1.0, 0.0, 0.0]
                };
                let t1 = normal(cross(uh, a));
                let t2 = cross(uh, t1);
                for t in [t1, t2] {
                    let at = |s: f64| std::array::from_fn(|i| uh[i] * s.cos() + t[i] * s.sin());
                    let fd = (e.value(&c, at(h)) - e.value(&c, at(-h))) / (2.0 * h);
                    let gt: f64 = (0..3).map(|i| g[i] * t[i]).sum();
                    assert!((fd - gt).abs() < 1e-7, "{b} at {u:?}: {fd} {gt}");
                }
            }
            assert!(e.value(&c, [0.0; 3]).is_nan());
            assert!(e.value(&c, [f64::NAN, 0.0, 1.0]).is_nan());
        }
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn normal(a: [f64; 3]) -> [f64; 3] {
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|x| x / n)
    }
}
