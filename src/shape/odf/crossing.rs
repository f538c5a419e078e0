//! Where a ray first meets an ODF glyph r~ = max(f~, 0) in its parameter space (the unit ball):
//! two algorithms, the one every back end draws with and the one that checks it.
//!
//! **In the ray's plane** ([`plane_crossing`]; odf.wgsl's `odf_first` in f32, the reference in
//! f64). Peters, Patel, Usher and Johnson (VMV 2023) restrict the series to the plane of the ray
//! and the glyph's centre; this is their construction in the angle of that plane rather than in
//! the ray's parameter. With e₁ the ray's direction, b e₂ its point nearest the centre and φ the
//! angle of a point q = s e₁ + b e₂ from e₁ (s = b cot φ, |q| = b / sin φ, φ falling from π to 0
//! along the ray), the series on the plane's great circle is g(φ) = f~(cos φ e₁ + sin φ e₂), a
//! trigonometric polynomial with the even frequencies 0, 2, …, L of a series of degree L (f~ is
//! even). Its L + 1 coefficients come from L + 1 values at φᵢ = iπ/(L+1) by a discrete Fourier
//! transform (exact for such a polynomial: the fixed inverse Vandermonde matrix of Peters et al.,
//! here the DFT's). The surface is where |q| = g(φ), i.e. where
//!
//! H(φ) = g(φ) sin φ − b
//!
//! changes sign (H > 0 inside; where f~ < 0, H < −b, so negative lobes are not drawn). H is a
//! trigonometric polynomial of degree L + 1 whatever the lobes look like: a thin lobe is thin in
//! space, not in φ, so the cost of finding its crossing does not grow as the lobe thins. The
//! crossing nearest the ray's start is found by steps that cannot pass it: with K₂ = |a₀| +
//! Σⱼ (4j² + 1)(|aⱼ| + |bⱼ|) bounding |H″| (g's coefficients aⱼ, bⱼ), a step δ from a point where
//! |H| = a and |H| falls at rate p along the ray keeps the sign while −a + pδ + K₂δ²/2 < 0, so the
//! step is δ = 2a / (p + √(p² + 2K₂a)): Newton's step where the crossing is near and simple
//! (converging to it quadratically from the outside), √(2a/K₂) at a graze, large where H moves
//! away from 0. Steps are at least `eps` (rad): two crossings closer than that in φ enclose a
//! bump of H no higher than K₂·eps²/8, which is what can be stepped over (2⁻¹⁵ rad on the GPU:
//! below the rounding of H in f32). The bracketed crossing is refined by Newton's method kept
//! inside the bracket, and the point is returned as r u with r = f~(u) at the crossing's
//! direction u, so that it lies on the surface even where φ is rounded (near φ = π, b cot φ
//! would amplify φ's rounding by r²/b). A ray through the centre (b = 0) meets the glyph at
//! ±f~(e₁).
//!
//! **By safe steps along the ray** ([`first_crossing`], f64, the independent check the tests
//! hold the plane's crossing to): along the ray inside the unit ball, h(s) = r~(u(s)) − |q(s)|
//! changes sign at the surface. h is Lipschitz along the ray with K = 1 + G·b/m², b the ray's
//! distance from the centre and m a lower bound of |q| over the step, so a step of |h|/K cannot
//! pass a crossing; steps are at least `eps`, so a lobe thinner than `eps` along the ray can be
//! stepped over, and the first sign change is bisected to the precision of the arithmetic. Its
//! cost grows as lobes thin and as rays pass near the centre (steps of |h|/K shrink with m²):
//! that is why the back ends no longer use it.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

/// The first crossing of the ray `o + s d` (parameter space, `d` unit) with r~ = max(f~, 0)
/// at s > `s_min`, by the module doc's marcher: (s, outward normal, not unit). `f` gives f~
/// and the gradient of its extension at a unit u; `g` bounds |∇_S f~|.
pub fn first_crossing(
    f: &dyn Fn(DVec3) -> (f64, DVec3),
    o: DVec3,
    d: DVec3,
    g: f64,
    s_min: f64,
    eps: f64,
    max_steps: usize,
) -> Option<(f64, DVec3)> {
    // The unit ball, from the point of the line nearest the centre (nothing cancels).
    let sc = -o.dot(d);
    let near = o + sc * d;
    let b2 = near.length_squared();
    if b2.is_nan() || b2 >= 1.0 {
        return None;
    }
    let b = b2.sqrt();
    let half = (1.0 - b2).sqrt();
    let (s0, s1) = (sc - half, sc + half);
    let mut s = s0.max(s_min);
    if s >= s1 {
        return None;
    }
    let h = |s: f64| -> f64 {
        let q = near + (s - sc) * d;
        let n = q.length();
        if n == 0.0 {
            return f(d).0.max(0.0);
        }
        f(q / n).0.max(0.0) - n
    };
    let mut hv = h(s);
    // On the ball (no glyph point lies beyond it) the ray starts outside: h ≥ 0 there is a
    // glyph touching its ball (a ball of a tensor profile is its own bound), met at once.
    let on_ball = s == s0;
    if on_ball && hv >= 0.0 {
        return Some((s, normal_at(f, near + (s - sc) * d)));
    }
    let inside = !on_ball && hv > 0.0;
    let mut steps = 0;
    while s < s1 && steps < max_steps {
        steps += 1;
        let q = near + (s - sc) * d;
        let a = hv.abs();
        // Lipschitz bound over the step: |q| ≥ max(b, |q(s)| − Δ).
        let k = |m: f64| {
            1.0 + if m > 0.0 {
                g * b / (m * m)
            } else {
                f64::INFINITY
            }
        };
        let d0 = a / k(q.length());
        let step = (a / k(b.max(q.length() - d0))).max(eps);
        let s_next = (s + step).min(s1);
        let h_next = h(s_next);
        if (h_next > 0.0) != inside {
            let (mut lo, mut hi) = (s, s_next);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if (h(mid) > 0.0) == inside {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let sh = if inside { lo } else { hi };
            let q = near + (sh - sc) * d;
            return Some((sh, normal_at(f, q)));
        }
        if s_next >= s1 {
            break;
        }
        s = s_next;
        hv = h_next;
    }
    None
}

/// The outward normal (not unit) of r~ = f~ at the surface point q: r u − ∇_S f~, which is the
/// gradient of |q| − f~(q/|q|) times |q| (no division by a radius that may be 0).
pub fn normal_at(f: &dyn Fn(DVec3) -> (f64, DVec3), q: DVec3) -> DVec3 {
    let n = q.length();
    if n == 0.0 {
        return DVec3::Z;
    }
    let u = q / n;
    let (v, grad) = f(u);
    let tangential = grad - grad.dot(u) * u;
    v.max(0.0) * u - tangential
}

/// g(φ) = a₀ + Σⱼ aⱼ cos 2jφ + bⱼ sin 2jφ (j = 1 … L/2): a series of degree L on a great circle
/// ([module doc](self)).
#[derive(Debug, Clone)]
pub struct CircleSeries {
    /// (aⱼ, bⱼ) for j = 0 … L/2 (b₀ = 0).
    pub coefficients: Vec<(f64, f64)>,
}

impl CircleSeries {
    /// The series of degree `l` (even) whose values at φᵢ = iπ/(L+1), i = 0 … L, are
    /// `samples`: the DFT of the samples as a function of 2φ.
    pub fn from_samples(samples: &[f64]) -> Self {
        let n = samples.len();
        let nf = n as f64;
        let coefficients = (0..=(n - 1) / 2)
            .map(|j| {
                let (mut a, mut b) = (0.0, 0.0);
                for (i, &g) in samples.iter().enumerate() {
                    // 2j φᵢ = 2π (j i mod N) / N: the angle reduced before the sine.
                    let theta = 2.0 * PI * ((j * i) % n) as f64 / nf;
                    a += g * theta.cos();
                    b += g * theta.sin();
                }
                let w = if j == 0 { 1.0 / nf } else { 2.0 / nf };
                (a * w, b * w)
            })
            .collect();
        Self { coefficients }
    }

    /// g(φ) and g′(φ).
    pub fn value_slope(&self, phi: f64) -> (f64, f64) {
        let (s2, c2) = (2.0 * phi).sin_cos();
        let (mut c, mut s) = (1.0, 0.0);
        let (mut g, mut gp) = (0.0, 0.0);
        for (j, &(a, b)) in self.coefficients.iter().enumerate() {
            if j > 0 {
                (c, s) = (c * c2 - s * s2, s * c2 + c * s2);
            }
            let jf = 2.0 * j as f64;
            g += a * c + b * s;
            gp += jf * (b * c - a * s);
        }
        (g, gp)
    }

    /// Σⱼ |aⱼ| + |bⱼ| ≥ |g|.
    pub fn bound(&self) -> f64 {
        self.coefficients
            .iter()
            .map(|&(a, b)| a.abs() + b.abs())
            .sum()
    }

    /// K₂ ≥ |H″| for H = g sin φ − b.
    pub fn curvature_bound(&self) -> f64 {
        self.coefficients
            .iter()
            .enumerate()
            .map(|(j, &(a, b))| (4.0 * (j * j) as f64 + 1.0) * (a.abs() + b.abs()))
            .sum()
    }
}

/// The crossing of the ray `o + s d` (parameter space, `d` unit) with r~ = max(f~, 0), f~ a
/// series of degree `degree`, nearest its start at s > `s_min`, in the ray's plane ([module
/// doc](self)): (s, outward normal, not unit). `f` gives f~ and the gradient of its extension
/// at a unit u; `eps` is the smallest step in φ (rad).
pub fn plane_crossing(
    f: &dyn Fn(DVec3) -> (f64, DVec3),
    degree: u32,
    o: DVec3,
    d: DVec3,
    s_min: f64,
    eps: f64,
) -> Option<(f64, DVec3)> {
    let sc = -o.dot(d);
    let near = o + sc * d;
    let b2 = near.length_squared();
    if b2.is_nan() || b2 >= 1.0 {
        return None;
    }
    let b = b2.sqrt();
    let half = (1.0 - b2).sqrt();
    let (s0, s1) = (sc - half, sc + half);
    let start = s0.max(s_min);
    if start >= s1 {
        return None;
    }
    // On the ball (no glyph point lies beyond it) the ray starts outside: H ≥ 0 there is a
    // glyph touching its ball (a ball of a tensor profile is its own bound), met at once.
    let on_ball = start == s0;
    if b == 0.0 {
        // Through the centre: the glyph spans ±r along the ray.
        let r = f(d).0.max(0.0);
        let x = start - sc;
        let s = if r > 0.0 && (x < -r || (on_ball && x <= -r)) {
            -r
        } else if r > 0.0 && x < r {
            r
        } else {
            return None;
        };
        return Some((sc + s, normal_at(f, near + s * d)));
    }
    let (e1, e2) = (d, near / b);
    let n = degree as usize + 1;
    let samples: Vec<f64> = (0..n)
        .map(|i| {
            let (sn, cs) = (PI * i as f64 / n as f64).sin_cos();
            f(cs * e1 + sn * e2).0
        })
        .collect();
    let g = CircleSeries::from_samples(&samples);
    // No point of the circle's series reaches b: the ray misses.
    if g.bound() < b {
        return None;
    }
    let k2 = g.curvature_bound();
    // The ray in two halves, each by the angle θ ∈ (0, π/2] of its points from the ray's axis
    // on that half's side (−e₁ before the point nearest the centre, m = −1, θ rising; e₁ after
    // it, m = 1, θ falling), so that θ keeps its relative precision where sin θ is small: there
    // g(φ) = g(mθ) (g has period π) and sin φ = sin θ.
    let big_h = |m: f64, th: f64| {
        let (v, slope) = g.value_slope(m * th);
        let (sn, cs) = th.sin_cos();
        (v * sn - b, m * slope * sn + v * cs)
    };
    let (x0, x1) = (start - sc, s1 - sc);
    let angle = |x: f64| b.atan2(x.abs());
    let mut inside = None;
    let mut first = true;
    for m in [-1.0, 1.0] {
        let (from, to) = if m < 0.0 {
            if x0 >= 0.0 {
                continue;
            }
            (angle(x0), if x1 < 0.0 { angle(x1) } else { FRAC_PI_2 })
        } else {
            if x1 <= 0.0 {
                continue;
            }
            (if x0 > 0.0 { angle(x0) } else { FRAC_PI_2 }, angle(x1))
        };
        // θ moves by −m along the ray.
        let sigma = -m;
        let mut th = from;
        let (mut h, mut hp) = big_h(m, th);
        let inside = *inside.get_or_insert(!on_ball && h > 0.0);
        if first && on_ball && h >= 0.0 {
            return Some((start, normal_at(f, near + x0 * d)));
        }
        first = false;
        loop {
            // |H| = a, falling at rate p along the ray.
            let a = h.abs();
            let p = if inside { -sigma * hp } else { sigma * hp };
            let root = (p * p + 2.0 * k2 * a).sqrt();
            let step = if p + root > 0.0 {
                2.0 * a / (p + root)
            } else {
                0.0
            };
            let next = th + sigma * step.max(eps);
            let next = if sigma > 0.0 {
                next.min(to)
            } else {
                next.max(to)
            };
            let (hn, hpn) = big_h(m, next);
            if (hn > 0.0) != inside {
                let th = refine(&|x| big_h(m, x), th, next, inside);
                let (sn, cs) = th.sin_cos();
                let u = cs * m * e1 + sn * e2;
                let x = m * f(u).0.max(0.0) * cs;
                return Some((sc + x, normal_at(f, near + x * d)));
            }
            if next == to {
                break;
            }
            (th, h, hp) = (next, hn, hpn);
        }
    }
    None
}

/// The crossing of `h` (value, slope) between `kept`, where its sign is `inside`'s, and `flipped`,
/// where it is not, by Newton's method kept inside the bracket, else bisection: the end on the
/// flipped side once the bracket is as small as the arithmetic allows.
fn refine(h: &dyn Fn(f64) -> (f64, f64), kept: f64, flipped: f64, inside: bool) -> f64 {
    let (mut kept, mut flipped) = (kept, flipped);
    let mut x = flipped;
    for _ in 0..100 {
        let (hx, slope) = h(x);
        if (hx > 0.0) == inside {
            kept = x;
        } else {
            flipped = x;
        }
        let (lo, hi) = (kept.min(flipped), kept.max(flipped));
        let newton = x - hx / slope;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next == x || hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
        x = next;
    }
    flipped
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::ShBasis;
    use crate::shape::odf::test_util::{lcg, random_dir};
    use crate::shape::odf::{
        Profile, REFERENCE_EPS, SeriesForm, plain_of, plain_value_gradient, series_bounds,
    };

    /// Brute force: the first sign change of h along the ray on a grid of 200,000 steps, then
    /// bisection. Independent of the marcher's step rule.
    fn brute(p: &Profile, o: DVec3, d: DVec3) -> Option<f64> {
        let sc = -o.dot(d);
        let b2 = (o + sc * d).length_squared();
        if b2 >= 1.0 {
            return None;
        }
        let half = (1.0 - b2).sqrt();
        let (s0, s1) = ((sc - half).max(0.0), sc + half);
        let h = |s: f64| {
            let q = o + s * d;
            p.value(q.normalize()).max(0.0) - q.length()
        };
        let inside = h(s0) > 0.0;
        let n = 200_000;
        let mut prev = s0;
        for i in 1..=n {
            let s = s0 + (s1 - s0) * f64::from(i) / f64::from(n);
            if (h(s) > 0.0) != inside {
                let (mut lo, mut hi) = (prev, s);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (h(mid) > 0.0) == inside {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            prev = s;
        }
        None
    }

    /// G, a bound of |∇_S f~|, for the marcher.
    fn gradient_bound(p: &Profile) -> f64 {
        match p {
            Profile::Quadratic(a) => a[0] - a[2],
            Profile::Series {
                lmax,
                form: SeriesForm::Plain,
                coefficients,
                ..
            } => series_bounds(coefficients, *lmax).1,
            // Bernstein: |∇_S f| ≤ L max |f| ≤ L Σ |p_abc|.
            Profile::Series {
                lmax, coefficients, ..
            } => f64::from(*lmax) * coefficients.iter().map(|c| c.abs()).sum::<f64>(),
        }
    }

    /// A tensor profile and random lmax-8 series (positive, as a CSD fit's lobes) in the unit
    /// ball.
    fn test_profiles(seed: &mut u64) -> Vec<Profile> {
        let mut profiles = vec![Profile::Quadratic([1.0, 0.3, 0.05])];
        for _ in 0..3 {
            let n = crate::sh::count_of_lmax(8).unwrap();
            let mut c: Vec<f64> = (0..n).map(|_| 0.3 * lcg(seed)).collect();
            c[0] = 1.5;
            let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
            let (vb, _) = series_bounds(&plain, 8);
            let plain: Vec<f64> = plain.iter().map(|v| v / vb).collect();
            profiles.push(Profile::Series {
                lmax: 8,
                form: SeriesForm::Plain,
                coefficients: plain,
                rotation: glam::DMat3::IDENTITY,
            });
        }
        profiles
    }

    /// Both algorithms find the brute-force crossing on [`test_profiles`], to the bisection's
    /// precision; the normal is the gradient of |q| − r~(q/|q|).
    #[test]
    fn crossings_match_brute_force() {
        type Method = fn(&Profile, DVec3, DVec3) -> Option<(f64, DVec3)>;
        let marcher: Method = |p, o, d| {
            let f = |u: DVec3| p.value_gradient(u);
            first_crossing(&f, o, d, gradient_bound(p), 0.0, REFERENCE_EPS, usize::MAX)
        };
        let plane: Method = |p, o, d| {
            let f = |u: DVec3| p.value_gradient(u);
            plane_crossing(&f, p.degree(), o, d, 0.0, 1e-12)
        };
        use rayon::prelude::*;
        let mut seed = 3;
        let profiles = test_profiles(&mut seed);
        for method in [marcher, plane] {
            // Each profile's rays from a seed of its own, the profiles in parallel (the brute
            // march is this test's time).
            let (hits, misses) = profiles
                .par_iter()
                .enumerate()
                .map(|(k, p)| {
                    let mut seed = 3 + 1000 * k as u64;
                    let (mut hits, mut misses) = (0, 0);
                    for _ in 0..150 {
                        let o = random_dir(&mut seed) * 3.0;
                        let target = random_dir(&mut seed) * 0.6 * lcg(&mut seed).abs();
                        let d = (target - o).normalize();
                        let got = method(p, o, d);
                        let want = brute(p, o, d);
                        match (got, want) {
                            (Some((s, n)), Some(w)) => {
                                hits += 1;
                                assert!((s - w).abs() < 1e-9, "{s} {w}");
                                assert_normal(p, o + s * d, n);
                            }
                            (None, None) => misses += 1,
                            (got, want) => panic!("{got:?} against {want:?}"),
                        }
                    }
                    (hits, misses)
                })
                .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
            assert!(hits > 100 && misses > 20, "{hits} {misses}");
        }
    }

    /// `n` is the gradient of F(q) = |q| − r~(q/|q|) at q, by central differences.
    fn assert_normal(p: &Profile, q: DVec3, n: DVec3) {
        let big_f = |q: DVec3| q.length() - p.value(q.normalize()).max(0.0);
        let e = 1e-6;
        let fd = DVec3::new(
            big_f(q + DVec3::X * e) - big_f(q - DVec3::X * e),
            big_f(q + DVec3::Y * e) - big_f(q - DVec3::Y * e),
            big_f(q + DVec3::Z * e) - big_f(q - DVec3::Z * e),
        );
        let angle = n.normalize().dot(fd.normalize()).clamp(-1.0, 1.0).acos();
        assert!(angle.to_degrees() < 1e-3, "{}", angle.to_degrees());
    }

    /// The plain coefficients of Σ wᵢ δ(nᵢ) truncated at `lmax`, scaled into the unit ball: the
    /// sharpest lobes a series of that order has (stability case 14's).
    fn fibres(lmax: u32, fibres: &[(DVec3, f64)]) -> Profile {
        let mut ev = crate::sh::ShEval::new(lmax, ShBasis::Tournier07).unwrap();
        let n = crate::sh::count_of_lmax(lmax).unwrap();
        let (mut sum, mut row) = (vec![0.0; n], vec![0.0; n]);
        for &(dir, w) in fibres {
            ev.row(dir.normalize().to_array(), &mut row);
            for (s, r) in sum.iter_mut().zip(&row) {
                *s += w * r;
            }
        }
        let plain = plain_of(&sum, ShBasis::Tournier07, 1.0).unwrap();
        let (vb, _) = series_bounds(&plain, lmax);
        let plain: Vec<f64> = plain.iter().map(|v| v / vb).collect();
        // The form the GPU and the reference hold it in.
        let form = SeriesForm::for_lmax(lmax);
        Profile::Series {
            lmax,
            form,
            coefficients: form.coefficients(&plain, lmax),
            rotation: glam::DMat3::IDENTITY,
        }
    }

    /// On the sharpest lobes up to lmax 12 (one, two and three fibres, and a second fibre at
    /// 1e-3 of the first), from outside and from inside (a start past the ball's entry), the
    /// plane's crossing is the marcher's with steps of 1e-9 of the radius: the same rays hit,
    /// at the same point, with the same normal; its steps stay few however thin the lobes.
    #[test]
    fn plane_crossing_is_the_fine_marchers_on_sharp_lobes() {
        use rayon::prelude::*;
        let third = glam::DQuat::from_axis_angle(DVec3::Z, 120f64.to_radians());
        let (x, y) = (DVec3::X, DVec3::Y);
        let fibres_of = [
            vec![(DVec3::new(0.2, 0.3, 1.0), 1.0)],
            vec![(x, 1.0), (y, 1.0)],
            vec![(x, 1.0), (third * x, 1.0), (third * third * x, 1.0)],
            vec![(x, 1.0), (DVec3::new(0.34, 0.94, 0.0), 1e-3)],
        ];
        // Every ray of every case in parallel (the fine march, steps of 1e-9 near the sharpest
        // lobes, is this test's time; one ray at lmax 12 can take a second), each case's rays
        // drawn from a seed of its own. 300 rays a case, 150 at lmax 12, whose march costs 30
        // to 100 times lmax 8's.
        let rays: Vec<(u32, usize, DVec3, DVec3, f64)> = [4, 8, 12]
            .into_iter()
            .flat_map(|lmax| (0..fibres_of.len()).map(move |f| (lmax, f)))
            .enumerate()
            .flat_map(|(c, (lmax, f))| {
                let mut seed = 23 + 1000 * c as u64;
                let n = if lmax == 12 { 150 } else { 300 };
                (0..n)
                    .map(|k| {
                        let o = random_dir(&mut seed) * 3.0;
                        // Aimed near the centre, where lobes are thinnest and the ringing is.
                        let target = random_dir(&mut seed) * 0.05 * lcg(&mut seed).abs();
                        let s_min = if k % 3 == 0 {
                            3.0 - 0.2 * lcg(&mut seed).abs()
                        } else {
                            0.0
                        };
                        (lmax, f, o, (target - o).normalize(), s_min)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        let profiles: Vec<Vec<Profile>> = [4, 8, 12]
            .iter()
            .map(|&lmax| fibres_of.iter().map(|f| fibres(lmax, f)).collect())
            .collect();
        let hits: usize = rays
            .par_iter()
            .map(|&(lmax, fibre, o, d, s_min)| {
                let p = &profiles[(lmax / 4 - 1) as usize][fibre];
                let f = |u: DVec3| p.value_gradient(u);
                let want = first_crossing(&f, o, d, gradient_bound(p), s_min, 1e-9, usize::MAX);
                let got = plane_crossing(&f, p.degree(), o, d, s_min, 1e-12);
                match (got, want) {
                    (Some((s, n)), Some((w, nw))) => {
                        assert!((s - w).abs() < 1e-8, "lmax {lmax}: {s} {w}");
                        let angle = n.normalize().dot(nw.normalize()).clamp(-1.0, 1.0);
                        assert!(angle.acos().to_degrees() < 1e-4, "lmax {lmax}");
                        1
                    }
                    (None, None) => 0,
                    (got, want) => panic!("lmax {lmax}: {got:?} against {want:?}"),
                }
            })
            .sum();
        assert!(hits > 1000, "{hits}");
    }

    /// A ray through the centre meets the glyph at ∓f~(d), from outside and from inside, and so
    /// does a ray passing 1e-16 … 1e-6 from it (where an angle measured from one end of the ray
    /// would have lost sin φ's relative precision: it met the ball instead).
    #[test]
    fn a_ray_through_the_centre_meets_the_glyph_along_it() {
        let p = Profile::Quadratic([0.9, 0.3, 0.2]);
        let f = |u: DVec3| p.value_gradient(u);
        for offset in [0.0, 1e-16, 1e-13, 1e-10, 1e-6] {
            let o = DVec3::new(-3.0, offset, 0.5 * offset);
            let (s, n) = plane_crossing(&f, 2, o, DVec3::X, 0.0, 1e-12).unwrap();
            assert!((s - 2.1).abs() < 1e-9, "{offset}: {s}");
            assert!(n.normalize().dot(-DVec3::X) > 0.999_999);
            let (s, _) = plane_crossing(&f, 2, o, DVec3::X, 3.0, 1e-12).unwrap();
            assert!((s - 3.9).abs() < 1e-9, "{offset}: {s}");
        }
    }

    /// A ball's own profile is its bounding ball: every ray meets it where it enters (the
    /// entry's h = 1 − |q| rounds to either sign; it is not taken for being inside).
    #[test]
    fn a_glyph_filling_its_ball_is_met_on_entry() {
        let p = Profile::Quadratic([1.0; 3]);
        let f = |u: DVec3| p.value_gradient(u);
        let mut seed = 5;
        for _ in 0..2000 {
            let o = random_dir(&mut seed) * 3.0;
            let d = (random_dir(&mut seed) * 0.9 * lcg(&mut seed).abs() - o).normalize();
            let sc = -o.dot(d);
            let want = sc - (1.0 - (o + sc * d).length_squared()).sqrt();
            for (s, n) in [
                first_crossing(&f, o, d, 0.0, 0.0, REFERENCE_EPS, usize::MAX).unwrap(),
                plane_crossing(&f, 2, o, d, 0.0, 1e-12).unwrap(),
            ] {
                assert!((s - want).abs() < 1e-12, "{s} {want}");
                assert!((n.normalize() - (o + s * d)).length() < 1e-9);
            }
        }
    }

    /// lmax 0: a ball of radius c₀Y₀⁰, exactly.
    #[test]
    fn lmax_zero_is_a_ball() {
        let y00 = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
        let plain = vec![0.5 / y00];
        let f = |u: DVec3| plain_value_gradient(&plain, 0, u);
        let o = DVec3::new(0.1, 0.2, -3.0);
        let want = 3.0 - (0.25f64 - 0.05).sqrt();
        for (s, n) in [
            first_crossing(&f, o, DVec3::Z, 0.0, 0.0, 1e-7, usize::MAX).unwrap(),
            plane_crossing(&f, 0, o, DVec3::Z, 0.0, 1e-12).unwrap(),
        ] {
            assert!((s - want).abs() < 1e-12, "{s} {want}");
            assert!((n.normalize() - DVec3::new(0.1, 0.2, -(0.2f64).sqrt()) / 0.5).length() < 1e-9);
        }
    }
}
