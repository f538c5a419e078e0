//! The orthonormalised associated Legendre functions Λ_l^m(θ) (no Condon–Shortley phase), their
//! θ-derivatives and Λ_l^m / sin θ, by the standard three-term recurrences (module doc, §2).

use std::f64::consts::PI;

/// Λ_l^m, dΛ_l^m/dθ and (for m ≥ 1) Λ_l^m / sin θ at one θ, for 0 ≤ m ≤ l ≤ lmax, each at
/// [`tri`]`(l, m)`.
#[derive(Debug, Clone)]
pub(crate) struct Legendre {
    pub(crate) lmax: u32,
    pub(crate) p: Vec<f64>,
    pub(crate) dp: Vec<f64>,
    /// Λ_l^m / sin θ for m ≥ 1 (0 at m = 0): finite at the poles, where the φ-part of the
    /// gradient needs it.
    pub(crate) p_over_s: Vec<f64>,
}

/// The place of (l, m), 0 ≤ m ≤ l, in the triangle.
pub(crate) fn tri(l: u32, m: u32) -> usize {
    let l = l as usize;
    l * (l + 1) / 2 + m as usize
}

impl Legendre {
    pub(crate) fn new(lmax: u32) -> Self {
        let n = tri(lmax + 1, 0);
        Legendre {
            lmax,
            p: vec![0.0; n],
            dp: vec![0.0; n],
            p_over_s: vec![0.0; n],
        }
    }

    /// Every function at the polar angle whose cosine is `z` and sine `s` (s ≥ 0,
    /// z² + s² = 1; `s` given rather than derived, so that it keeps its digits near the poles).
    pub(crate) fn at(&mut self, z: f64, s: f64) {
        let lmax = self.lmax;
        // R_l^m = Λ_l^m / s for m ≥ 1, and Λ_l^0 itself for m = 0: one linear recurrence in l
        // per m, so dividing the seed by s divides the whole column.
        let mut diag = 1.0 / (4.0 * PI).sqrt(); // Λ_m^m / s^m (the s-free part)
        let mut s_pow = 1.0; // s^(m-1) for m ≥ 1
        for m in 0..=lmax {
            if m >= 1 {
                let mf = m as f64;
                diag *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
                if m >= 2 {
                    s_pow *= s;
                }
            }
            // Column values of R (m ≥ 1) or Λ (m = 0), l = m, m + 1, …
            let seed = if m == 0 { diag } else { diag * s_pow };
            let store = |me: &mut Self, l: u32, r: f64| {
                let i = tri(l, m);
                if m == 0 {
                    me.p[i] = r;
                } else {
                    me.p_over_s[i] = r;
                    me.p[i] = r * s;
                }
            };
            store(self, m, seed);
            if m == lmax {
                break;
            }
            let mf = m as f64;
            let mut prev2 = seed;
            let mut prev = (2.0 * mf + 3.0).sqrt() * z * seed;
            store(self, m + 1, prev);
            for l in m + 2..=lmax {
                let (lf, l1) = (l as f64, (l - 1) as f64);
                let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                let b = ((l1 * l1 - mf * mf) / (4.0 * l1 * l1 - 1.0)).sqrt();
                let next = a * (z * prev - b * prev2);
                store(self, l, next);
                prev2 = prev;
                prev = next;
            }
        }
        // dΛ_l^m/dθ = ½ [√((l+m)(l−m+1)) Λ_l^(m−1) − √((l−m)(l+m+1)) Λ_l^(m+1)], and
        // −√(l(l+1)) Λ_l^1 at m = 0: the ladder operators on the complex harmonics.
        for l in 0..=lmax {
            let lf = l as f64;
            for m in 0..=l {
                let mf = m as f64;
                let up = if m < l {
                    ((lf - mf) * (lf + mf + 1.0)).sqrt() * self.p[tri(l, m + 1)]
                } else {
                    0.0
                };
                self.dp[tri(l, m)] = if m == 0 {
                    -up
                } else {
                    0.5 * (((lf + mf) * (lf - mf + 1.0)).sqrt() * self.p[tri(l, m - 1)] - up)
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Λ_l^m by the explicit sum of P_l^m with factorials in f64 (fine to l = 8), the closed
    /// form the recurrence must match.
    fn explicit(l: u32, m: u32, x: f64) -> f64 {
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        // Rodrigues: P_l^m(x) = (1−x²)^(m/2) d^m/dx^m P_l(x), P_l(x) = Σ_k (−1)^k (2l−2k)! /
        // (2^l k! (l−k)! (l−2k)!) x^(l−2k).
        let mut d = 0.0;
        for k in 0..=l / 2 {
            let p = l - 2 * k;
            if p < m {
                continue;
            }
            let c = (-1f64).powi(k as i32) * fact(2 * l - 2 * k)
                / (2f64.powi(l as i32) * fact(k) * fact(l - k) * fact(l - 2 * k));
            d += c * fact(p) / fact(p - m) * x.powi((p - m) as i32);
        }
        let norm = ((2 * l + 1) as f64 / (4.0 * PI) * fact(l - m) / fact(l + m)).sqrt();
        norm * (1.0 - x * x).powf(m as f64 / 2.0) * d
    }

    #[test]
    fn the_recurrence_matches_the_explicit_polynomials() {
        let mut leg = Legendre::new(8);
        for theta in [0.0, 1e-3, 0.3, 1.0, PI / 2.0, 2.2, 3.1, PI] {
            leg.at(f64::cos(theta), f64::sin(theta));
            for l in 0..=8 {
                for m in 0..=l {
                    let want = explicit(l, m, theta.cos());
                    let got = leg.p[tri(l, m)];
                    assert!(
                        (got - want).abs() < 1e-12,
                        "l {l} m {m} θ {theta}: {got} {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn derivatives_and_quotients_match_finite_differences() {
        let lmax = 12;
        let (mut a, mut b, mut c) = (
            Legendre::new(lmax),
            Legendre::new(lmax),
            Legendre::new(lmax),
        );
        let h = 1e-6;
        for theta in [0.2, 0.9, 1.7, 2.9] {
            a.at(f64::cos(theta), f64::sin(theta));
            b.at(f64::cos(theta + h), f64::sin(theta + h));
            c.at(f64::cos(theta - h), f64::sin(theta - h));
            for i in 0..tri(lmax + 1, 0) {
                let fd = (b.p[i] - c.p[i]) / (2.0 * h);
                assert!(
                    (a.dp[i] - fd).abs() < 1e-7,
                    "{i} θ {theta}: {} {fd}",
                    a.dp[i]
                );
            }
            for l in 1..=lmax {
                for m in 1..=l {
                    let i = tri(l, m);
                    let want = a.p[i] / theta.sin();
                    assert!((a.p_over_s[i] - want).abs() < 1e-12 * want.abs().max(1.0));
                }
            }
        }
    }

    #[test]
    fn high_orders_stay_finite_and_bounded_at_the_poles_and_the_equator() {
        let mut leg = Legendre::new(30);
        for (z, s) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0)] {
            leg.at(z, s);
            for l in 0..=30u32 {
                // |Λ_l^m| ≤ √((2l+1)/4π): the addition theorem at one point.
                let bound = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * (1.0 + 1e-12);
                for m in 0..=l {
                    let v = leg.p[tri(l, m)];
                    assert!(v.is_finite() && v.abs() <= bound, "l {l} m {m}: {v}");
                }
            }
        }
    }
}
