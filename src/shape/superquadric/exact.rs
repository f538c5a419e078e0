//! Exact f64 ray–superquadric intersection (docs/book/src/developer/superquadric-derivation.md
//! §4), the judge of the GPU's superquadric glyphs.
//!
//! Two certified searches, neither of which samples the ray and so neither of which can step over
//! a thin crossing (a sharp γ = 10 corner nicked by a ray, a grazing ray):
//!
//! - Convex glyphs (α, β ≤ 2 and c = β: all of Kindlmann's): Barr's function is a norm, convex
//!   along the ray, so the solid meets the ray in one interval around the norm's minimum;
//!   bisection on the sign of the monotone slope finds the minimum, bisection on the norm the
//!   crossing.
//! - Pinched and Schultz–Kindlmann `c ≠ β` glyphs: the inside–outside function is monotone in
//!   `|x|`, `|y|`, `|z|`, so its range over a stretch of ray is bounded by its values at the
//!   stretch's smallest and largest absolute coordinates; branch and bound on those bounds, left
//!   to right, certifies every discarded stretch free of the solid, down to machine width.
//!
//! Fixed-step marches and Newton iterations, what a shader can afford, give no such guarantee,
//! and a reference must not share the method it judges. Hand-written, as no crate offers
//! superquadrics, let alone a certified first root.

use glam::{DMat3, DVec3};

use crate::glyph::superquadric::{SuperquadricShape, gauge, pnorm, profile};
use crate::shape::RayHit;

/// The slack of the bound tests, in units of the inside–outside function: a few ulps of its
/// rounding, so that no stretch is discarded on rounding alone.
const MARGIN: f64 = 16.0 * f64::EPSILON;
/// Bound evaluations per search of a non-convex glyph. A transversal crossing takes a few per
/// halving (≈ 55 halvings to machine width); a ray at angle θ to the surface keeps about
/// `1/cos θ` stretches alive per halving, as the bounds are first order. At the cap the
/// leftmost stretch still alive is taken as the hit: everything before it is certified empty,
/// so it is a tangency resolved to that stretch's width.
pub const MAX_BOUND_EVALS: usize = 1 << 20;
use crate::glyph::superquadric::EXPONENT_MIN;

/// A superquadric glyph in world space: the solid of [`SuperquadricShape`] in local unit
/// coordinates, scaled by `radii`, turned into `frame`, at `centre`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Superquadric {
    pub centre: DVec3,
    /// World directions of local x, y, z (orthonormal; either handedness, the solid is
    /// mirror-symmetric).
    pub frame: DMat3,
    /// Semi-axes along local x, y, z (positive).
    pub radii: DVec3,
    pub alpha: f64,
    pub beta: f64,
    /// Schultz–Kindlmann's `c`: the profile exponent in the local y–z plane.
    pub beta_y: f64,
}

impl Superquadric {
    /// A glyph from its eigenvector frame `O = [e1 e2 e3]`, its radii in frame order and the
    /// shape the mapping gave it.
    pub fn from_shape(
        centre: DVec3,
        eigen_frame: DMat3,
        frame_radii: DVec3,
        shape: &SuperquadricShape,
    ) -> Self {
        let [i, j, k] = shape.axes;
        let r = frame_radii.to_array();
        Superquadric {
            centre,
            frame: DMat3::from_cols(eigen_frame.col(i), eigen_frame.col(j), eigen_frame.col(k)),
            radii: DVec3::new(r[i], r[j], r[k]),
            alpha: shape.alpha,
            beta: shape.beta,
            beta_y: shape.c,
        }
    }

    /// The superquadric an instance's geometry is drawn as (`--glyph superquadric`: the frame
    /// and radii already in local order, the exponents as stored).
    pub fn of(geo: &crate::shape::GlyphGeometry) -> Self {
        Superquadric {
            centre: geo.centre,
            frame: geo.frame,
            radii: geo.radii,
            alpha: geo.exponents.x,
            beta: geo.exponents.y,
            beta_y: geo.exponents.z,
        }
    }

    /// To local unit coordinates (a vector, not a point).
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        (self.frame.transpose() * v) / self.radii
    }

    /// Half-extents of the world-space bounding box of the local unit box, which holds the solid.
    pub fn half_extents(&self) -> DVec3 {
        self.frame.x_axis.abs() * self.radii.x
            + self.frame.y_axis.abs() * self.radii.y
            + self.frame.z_axis.abs() * self.radii.z
    }

    pub fn contains(&self, p: DVec3) -> bool {
        let q = self.to_local(p - self.centre).abs();
        self.gauge(q.x, q.y, q.z) <= 1.0
    }

    /// Inside–outside function of absolute local coordinates: ≤ 1 exactly on the solid,
    /// non-decreasing in each argument, `N_α(|x| / R_β(z), |y| / R_c(z))`.
    pub fn gauge(&self, ax: f64, ay: f64, az: f64) -> f64 {
        gauge([self.alpha, self.beta, self.beta_y], [ax, ay, az])
    }

    /// Bounds of [`Self::gauge`] over `q0 + s v`, `s ∈ [a, b]`.
    fn bounds(&self, q0: DVec3, v: DVec3, a: f64, b: f64) -> (f64, f64) {
        let (x0, x1) = abs_range(q0.x, v.x, a, b);
        let (y0, y1) = abs_range(q0.y, v.y, a, b);
        let (z0, z1) = abs_range(q0.z, v.z, a, b);
        (self.gauge(x0, y0, z0), self.gauge(x1, y1, z1))
    }

    /// First `s` in `[a, b]` at which the ray is possibly inside (`inside`) or possibly outside
    /// (`!inside`), to machine width: every stretch before it is certified the other way.
    fn first(&self, q0: DVec3, v: DVec3, a: f64, b: f64, inside: bool) -> Option<f64> {
        let tol = 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(b - a);
        // Depth-first, left child on top; at most one pending right sibling per level.
        let mut stack = [(0.0, 0.0); 128];
        stack[0] = (a, b);
        let mut len = 1;
        let mut evals = 0;
        while len > 0 {
            len -= 1;
            let (lo, hi) = stack[len];
            evals += 1;
            let (gmin, gmax) = self.bounds(q0, v, lo, hi);
            let possible = if inside {
                gmin <= 1.0 + MARGIN
            } else {
                gmax.is_nan() || gmax > 1.0 - MARGIN
            };
            if !possible {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            if hi - lo <= tol
                || mid <= lo
                || mid >= hi
                || len + 2 > stack.len()
                || evals >= MAX_BOUND_EVALS
            {
                return Some(mid);
            }
            stack[len] = (mid, hi);
            stack[len + 1] = (lo, mid);
            len += 2;
        }
        None
    }

    /// Barr's solid with α, β ≤ 2: a convex solid, and its gauge
    /// `G = N_β(N_α(|x|, |y|), |z|)` a norm, convex along every ray.
    pub fn is_convex(&self) -> bool {
        self.alpha <= 2.0 && self.beta <= 2.0 && self.beta_y == self.beta
    }

    /// The norm `G` of a convex glyph: 1 on the surface, positively homogeneous.
    fn norm(&self, q: DVec3) -> f64 {
        let q = q.abs();
        pnorm(pnorm(q.x, q.y, self.alpha), q.z, self.beta)
    }

    /// `∇G`, each component in `[−1, 1]` (ratios ≤ 1 raised to powers ≥ 0), so no overflow.
    fn norm_gradient(&self, q: DVec3) -> DVec3 {
        let a = q.abs();
        let n_xy = pnorm(a.x, a.y, self.alpha);
        let g = pnorm(n_xy, a.z, self.beta);
        if g == 0.0 {
            return DVec3::ZERO;
        }
        let p1 = 2.0 / self.alpha.max(EXPONENT_MIN) - 1.0;
        let q1 = 2.0 / self.beta.max(EXPONENT_MIN) - 1.0;
        let ratio = |num: f64, den: f64, e: f64| {
            if num == 0.0 {
                0.0
            } else {
                (num / den).min(1.0).powf(e)
            }
        };
        let outer = ratio(n_xy, g, q1);
        DVec3::new(
            q.x.signum() * outer * ratio(a.x, n_xy, p1),
            q.y.signum() * outer * ratio(a.y, n_xy, p1),
            q.z.signum() * ratio(a.z, g, q1),
        )
    }

    /// First crossing in `[a, b]` for a convex glyph. Along the ray `g(s) = G(q(s))` is convex,
    /// so the solid meets the ray in one interval around the minimum of `g`; `g'` is
    /// non-decreasing, so bisection on its sign finds the minimum, and on each side of it
    /// `g − 1` changes sign at most once, so bisection finds the crossing. Nothing is sampled:
    /// a crossing however short (a nicked corner, a grazing ray) lies around the minimum.
    fn first_convex(&self, q0: DVec3, v: DVec3, a: f64, b: f64, from_inside: bool) -> Option<f64> {
        let g = |s: f64| self.norm(q0 + v * s);
        let slope = |s: f64| self.norm_gradient(q0 + v * s).dot(v);
        let tol = 4.0 * f64::EPSILON * a.abs().max(b.abs()).max(b - a);
        // Bisect keeping pred(lo) false and pred(hi) true.
        let bisect = |mut lo: f64, mut hi: f64, pred: &dyn Fn(f64) -> bool| {
            loop {
                let mid = 0.5 * (lo + hi);
                if hi - lo <= tol || mid <= lo || mid >= hi {
                    return mid;
                }
                if pred(mid) { hi = mid } else { lo = mid }
            }
        };
        let s_min = if slope(a) >= 0.0 {
            a
        } else if slope(b) <= 0.0 {
            b
        } else {
            bisect(a, b, &|s| slope(s) >= 0.0)
        };
        if from_inside {
            let lo = a.max(s_min);
            if g(b) <= 1.0 {
                return Some(b);
            }
            return Some(bisect(lo, b, &|s| g(s) > 1.0));
        }
        if g(s_min) > 1.0 {
            return None;
        }
        if g(a) <= 1.0 {
            return Some(a);
        }
        Some(bisect(a, s_min, &|s| g(s) <= 1.0))
    }

    /// First crossing of the surface by `o + t d` (d unit) with `t > 0`: the entry, or from
    /// inside the solid the exit, with the unit outward normal.
    pub fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        // The glyph-near origin, as for the ellipsoid: nothing cancels for distant glyphs.
        let t0 = (self.centre - o).dot(d);
        let q0 = self.to_local((o - self.centre) + d * t0);
        let v = self.to_local(d);
        if !(q0.is_finite() && v.is_finite() && t0.is_finite()) {
            return None;
        }
        let (mut s_in, mut s_out) = (-t0, f64::INFINITY);
        // The box faces the ray enters and leaves by (none where the ray starts inside).
        let (mut k_in, mut k_out) = (None, None);
        for k in 0..3 {
            if v[k] != 0.0 {
                let s1 = (-1.0 - q0[k]) / v[k];
                let s2 = (1.0 - q0[k]) / v[k];
                if s1.min(s2) > s_in {
                    (s_in, k_in) = (s1.min(s2), Some(k));
                }
                if s1.max(s2) < s_out {
                    (s_out, k_out) = (s1.max(s2), Some(k));
                }
            } else if q0[k].abs() > 1.0 {
                return None;
            }
        }
        if s_in >= s_out {
            return None;
        }
        let start = (q0 + v * s_in).abs();
        let from_inside = self.gauge(start.x, start.y, start.z) <= 1.0 && s_in == -t0;
        let s = if self.is_convex() {
            self.first_convex(q0, v, s_in, s_out, from_inside)?
        } else {
            match self.first(q0, v, s_in, s_out, !from_inside) {
                Some(s) => s,
                // From inside, a stretch certified inside up to the box exit leaves there: a
                // flat cap lying on the box face (rounding can put the face a hair inside).
                None if from_inside => s_out,
                None => return None,
            }
        };
        if t0 + s <= 0.0 {
            return None;
        }
        let q = q0 + v * s;
        // A convex glyph's norm G has the solid's normal everywhere on it, flat caps included;
        // H jumps from below 1 to ∞ across a near-box's cap (R_β(z) stays 1 up to the face), so
        // its gradient there points along the cap instead of across it.
        let local = if self.is_convex() {
            let n = self.norm_gradient(q);
            if n == DVec3::ZERO {
                self.local_gradient(q)
            } else {
                n
            }
        } else {
            // A hit on the box face it entered or leaves by is a flat cap's (sharp exponents keep
            // the profiles at 1 up to the face, the gauge jumps from below 1 to ∞ across it): the
            // face is the surface there, whatever the gauge's gradient just inside says.
            let tol = 8.0 * f64::EPSILON * s_in.abs().max(s_out.abs()).max(s_out - s_in);
            let face = |k: Option<usize>, at: f64| k.filter(|_| (s - at).abs() <= tol);
            let axis = |k: usize, sign: f64| {
                let mut n = DVec3::ZERO;
                n[k] = sign;
                n
            };
            if let Some(k) = face(k_in, s_in) {
                axis(k, -v[k].signum())
            } else if let Some(k) = face(k_out, s_out) {
                axis(k, v[k].signum())
            } else {
                self.local_gradient(q)
            }
        };
        let normal = (self.frame * (local / self.radii)).normalize();
        Some(RayHit { t: t0 + s, normal })
    }

    /// Direction of the gradient of the gauge at local point `q` (not normalised; never zero or
    /// NaN). Where a coordinate is exactly 0 its component is 0, the mirror-symmetric limit
    /// (also at the pinched shapes' ridges and tips, where no gradient exists). Magnitudes
    /// are combined in logarithms: with exponents like `2/β = 2e20` the factors over- and
    /// underflow although their ratios do not.
    pub fn local_gradient(&self, q: DVec3) -> DVec3 {
        let (ax, ay, az) = (q.x.abs(), q.y.abs(), q.z.abs());
        let sign = |c: f64| if c == 0.0 { 0.0 } else { c.signum() };
        let pole = DVec3::new(0.0, 0.0, q.z.signum());
        if ax == 0.0 && ay == 0.0 {
            return pole;
        }
        let (rb, rc) = (profile(az, self.beta), profile(az, self.beta_y));
        if az >= 1.0 || rb == 0.0 || rc == 0.0 {
            return pole;
        }
        let (u, w) = (ax / rb, ay / rc);
        let h = pnorm(u, w, self.alpha);
        let p1 = 2.0 / self.alpha.max(EXPONENT_MIN) - 1.0;
        // ∂H/∂u and ∂H/∂w, in [0, 1] for α ≤ 2.
        let la = if ax == 0.0 {
            f64::NEG_INFINITY
        } else {
            p1 * (u / h).ln()
        };
        let lb = if ay == 0.0 {
            f64::NEG_INFINITY
        } else {
            p1 * (w / h).ln()
        };
        let lx = la - rb.ln();
        let ly = lb - rc.ln();
        // ∂u/∂|z| = u (|z|/R_β)^(2/β − 1) / R_β, and likewise for w.
        let lz = if az == 0.0 {
            f64::NEG_INFINITY
        } else {
            let qb = 2.0 / self.beta.max(EXPONENT_MIN) - 1.0;
            let qc = 2.0 / self.beta_y.max(EXPONENT_MIN) - 1.0;
            let z1 = la + u.ln() + qb * (az / rb).ln() - rb.ln();
            let z2 = lb + w.ln() + qc * (az / rc).ln() - rc.ln();
            log_add(z1, z2)
        };
        let m = lx.max(ly).max(lz);
        if !m.is_finite() {
            // Not reachable on the surface (one of ∂H/∂u, ∂H/∂w is at least 1/2); keep a
            // direction anyway.
            let a = q.abs();
            return if a.x >= a.y && a.x >= a.z {
                DVec3::new(q.x.signum(), 0.0, 0.0)
            } else if a.y >= a.z {
                DVec3::new(0.0, q.y.signum(), 0.0)
            } else {
                pole
            };
        }
        let e = |l: f64| {
            if l == f64::NEG_INFINITY {
                0.0
            } else {
                (l - m).exp()
            }
        };
        DVec3::new(sign(q.x) * e(lx), sign(q.y) * e(ly), sign(q.z) * e(lz))
    }
}

/// `ln(e^a + e^b)` without overflow.
fn log_add(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    if lo == f64::NEG_INFINITY || hi == f64::INFINITY {
        return hi;
    }
    hi + (lo - hi).exp().ln_1p()
}

/// Range of `|q0 + s v|` over `s ∈ [a, b]`: at the ends, or 0 where it changes sign.
fn abs_range(q0: f64, v: f64, a: f64, b: f64) -> (f64, f64) {
    let (ea, eb) = (q0 + a * v, q0 + b * v);
    let hi = ea.abs().max(eb.abs());
    if (ea <= 0.0 && eb >= 0.0) || (ea >= 0.0 && eb <= 0.0) {
        (0.0, hi)
    } else {
        (ea.abs().min(eb.abs()), hi)
    }
}

#[cfg(test)]
pub(crate) mod tests;
