//! The CPU twin of shaders/shape/superquadric_finder.wgsl: the f32 ray–superquadric root finder
//! the GPU's superquadric glyphs call (docs/book/src/developer/superquadric-derivation.md §6), line by line with the shader's
//! names and in the shader's precision, so the tests can judge it against the exact f64
//! intersection (`crate::shape::superquadric::Superquadric`) and the 50-digit worked cases.
//!
//! Local unit coordinates: the solid is `|z| ≤ 1`, `(|x|/R_β(z))^(2/α) + (|y|/R_c(z))^(2/α) ≤ 1`
//! with exponents `e = (α, β, c)` in `(0, 5]`. Two finders, chosen per glyph:
//!
//! - Convex glyphs (α ≤ 2, β ≤ 2, c = β): Newton on `g(s) − 1`, `g(s) = G(o + s v)` the norm
//!   `G = N_β(N_α(|x|, |y|), |z|)`, started at the box entry. `g` is convex along the ray, so
//!   every Newton step from the left (where `g > 1`) lands at or before the first root — a
//!   tangent of a convex function lies below it — and the iterates increase to the root
//!   (quadratically for a transversal crossing, linearly at tangency). A slope `g' ≥ 0` while
//!   `g > 1` proves a miss: `g` only grows from there. From inside, the same from the box exit
//!   backwards finds the exit. Any subgradient will do, so the kinks of `G` on the mirror
//!   planes (where the components are 0) keep the guarantee.
//! - Other glyphs (pinched β > 2, α > 2, or c ≠ β): the gauge is monotone in `|x|, |y|, |z|`,
//!   so its range over a stretch of ray is bounded by its values at the stretch's smallest and
//!   largest absolute coordinates. Branch and bound, depth-first and left to right over the
//!   halvings of the span, without a stack ([`SQ_BOUND_MAX`] nodes): every skipped node is
//!   certified empty, so the first node that survives holds the first crossing. Once a
//!   surviving node is at most [`SQ_BRACKET`] wide and the gauge changes sign across it, a
//!   safeguarded secant (Illinois) finishes; otherwise the halving goes on to [`SQ_TOL`].
//!
//! Every power goes through `exp2(q log2 x)` with ratios `x ≤ 1`; `log2 0` is never taken
//! (`select` gives the limit instead) and no infinity is formed, as WGSL lets implementations
//! assume there are none. The exponents are floored at [`SQ_EXP_MIN`], so `2/e ≤ 2e30`.

use glam::Vec3;

/// Newton iterations of the convex finder. Transversal crossings take 1–6 (1 where a box face is
/// the surface), a tangent ray about
/// `log2(span / tolerance) ≈ 20` (linear convergence at a double root). At the cap the entry
/// search reports a miss (the iterates are still left of any root, so what is dropped is a
/// pixel-thin sliver at tangency); the exit search (eye inside) returns its current iterate,
/// which lies between the exit and the box exit.
pub const SQ_NEWTON_MAX: u32 = 24;
/// Gauge evaluations of the branch and bound (non-convex glyphs): one per node, two more per
/// look for a sign change. Transversal crossings take 10–40; a ray skimming the surface at
/// clearance δ keeps about `1/δ` nodes per unit length alive, as the bounds are first order.
/// At the cap everything before the current node is certified: the search then samples the
/// rest of the ray (at most [`SQ_SAMPLES`] points, steps growing from the node's width by
/// [`SQ_GROWTH`] to 1/[`SQ_PARTS`] of the rest) and refines the first change to the sought side
/// — no longer certified, a sliver between two samples can be missed, but a ray that skims the
/// surface and then crosses it is drawn at its crossing.
pub const SQ_BOUND_MAX: u32 = 128;
/// The finders' tolerance along the ray, in local unit coordinates (the glyph's box is
/// `[−1, 1]³`): Newton stops when its step is shorter, the branch and bound when its stretch is.
pub const SQ_TOL: f32 = 4e-6;
/// The tolerance never goes below this many multiples of `|s|` (two f32 ulps of the ray
/// parameter), so that the steps stay resolvable for a far origin.
pub const SQ_ULP: f32 = 2.4e-7;
/// Depth of the branch and bound's tree: its leaves are at least `span / 2^24`, so the grid
/// points `s_a + i w` are exact multiples (`i < 2^24`). The tolerance is reached first for every
/// ray the slab test passes (`span / tol ≤ 2√3 / SQ_TOL < 2^20`).
pub const SQ_DEPTH_MAX: u32 = 24;
/// Width (local unit coordinates along the ray) at which the branch and bound looks for a sign
/// change across its current node and, if there is one, finishes with the secant. That finds a
/// crossing of the node, the first unless the ray crosses the surface more than once within
/// this one node (a sliver under 1e-3 of the radius): then the depth is off by at most the
/// node's width.
pub const SQ_BRACKET: f32 = 1e-3;
/// At most this many samples of the rest of the ray when the branch and bound reaches its cap:
/// from a node of the deepest width (span / 2^20) about 28 growing steps reach 1/16 of the rest
/// and cover 3/16 of it, and 13 more the end.
pub const SQ_SAMPLES: u32 = 40;
/// Growth of the steps of those samples, from the current node's width...
pub const SQ_GROWTH: f32 = 1.5;
/// ... to at most this fraction of the rest of the ray.
pub const SQ_PARTS: f32 = 16.0;
/// Gauge evaluations of the secant.
pub const SQ_SECANT_MAX: u32 = 16;
/// Slack of the bound tests in units of the gauge: its f32 rounding, so that no stretch is
/// discarded on rounding alone.
pub const SQ_MARGIN: f32 = 1e-6;
/// Exponents below this are raised to it: `2/e` stays finite (≤ 2e30) and so does `(2/e) log2 x`.
pub const SQ_EXP_MIN: f32 = 1e-30;
/// Arguments of `log2` are at least this (a normal f32): `log2` stays finite.
pub const SQ_TINY: f32 = 1e-37;
/// The gauge's value for "certainly outside" (where the profile has closed), and the limit for
/// the slab test's far end.
pub const SQ_BIG: f32 = 1e30;
/// The log of a derivative that is exactly 0 (no product with it is ever formed, only sums, and
/// every other log is below 1e33 in magnitude).
pub const SQ_NEG: f32 = -1e36;
/// Ray components smaller than this are taken as 0 by the slab test (no division overflows).
pub const SQ_V_MIN: f32 = 1e-30;

/// What [`sq_first`] found: `n` is the unit direction of the inside–outside function's gradient
/// in local unit coordinates (map it with the inverse transpose).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SqHit {
    pub s: f32,
    pub n: Vec3,
    pub hit: bool,
}

/// Counts of the twin only (the shader has no counters): gauge evaluations per call, for the
/// cost report. A Newton iteration (the norm and its gradient together) counts as one.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SqCost {
    /// Newton iterations or bound evaluations.
    pub search: u32,
    /// Everything else: the inside test at the start and the normal.
    pub other: u32,
    /// The search stopped at its cap.
    pub capped: bool,
}

// ---------------------------------------------------------------------------------------------
// The shader's transcendental functions. In tests they can be made as inaccurate as Vulkan
// allows (`sloppy`), to check that the finder does not rely on correctly rounded results.

fn exp2(x: f32) -> f32 {
    #[cfg(test)]
    if let Some(err) = sloppy::exp2_err(x) {
        return x.exp2() * (1.0 + err);
    }
    x.exp2()
}

fn log2(x: f32) -> f32 {
    #[cfg(test)]
    if let Some(err) = sloppy::log2_err(x) {
        return x.log2() + err;
    }
    x.log2()
}

/// WGSL's `sign`: 0 at 0.
fn sign(x: f32) -> f32 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

fn sign3(v: Vec3) -> Vec3 {
    Vec3::new(sign(v.x), sign(v.y), sign(v.z))
}

/// WGSL's `select(f, t, cond)`.
fn select(f: f32, t: f32, cond: bool) -> f32 {
    if cond { t } else { f }
}

// ---------------------------------------------------------------------------------------------

/// `sq_pow`: `x^y` for `0 ≤ x ≤ 1`, `y > 0` (`0^y = 0`).
pub fn sq_pow(x: f32, y: f32) -> f32 {
    select(exp2(y * log2(x.max(SQ_TINY))), 0.0, x <= 0.0)
}

/// `sq_pnorm_log`: `N_e(a, b) = (a^(2/e) + b^(2/e))^(e/2)` for `a, b ≥ 0`, with the logs (base 2)
/// of its partial derivatives `∂N/∂a = (a/N)^(2/e − 1)` and `∂N/∂b` ([`SQ_NEG`] for a derivative
/// of 0). Scaled by the larger argument: `N = hi (1 + r)^(1/p)`, `r = (lo/hi)^p ≤ 1`, so nothing
/// overflows for `p = 2/e` up to 2e30, and `N → max(a, b)` as `e → 0`.
pub fn sq_pnorm_log(a: f32, b: f32, e: f32) -> Vec3 {
    let hi = a.max(b);
    let lo = a.min(b);
    if hi <= 0.0 {
        return Vec3::new(0.0, SQ_NEG, SQ_NEG);
    }
    let p = 2.0 / e.max(SQ_EXP_MIN);
    let l = log2((lo / hi).max(SQ_TINY));
    let r = select(exp2(p * l), 0.0, lo <= 0.0);
    // log2(1 + r): no log1p in WGSL; its absolute error (an ulp of 1) is divided by p ≥ 0.4.
    let k = log2(1.0 + r);
    let n = hi * exp2(k / p);
    // (hi/N)^(p−1) = (1 + r)^(1/p − 1); (lo/N)^(p−1) = (lo/hi)^(p−1) (hi/N)^(p−1).
    let g_hi = k * (1.0 / p - 1.0);
    let g_lo = select((p - 1.0) * l + g_hi, SQ_NEG, lo <= 0.0);
    if a >= b {
        Vec3::new(n, g_hi, g_lo)
    } else {
        Vec3::new(n, g_lo, g_hi)
    }
}

/// `sq_pnorm`: `N_e(a, b)` alone.
pub fn sq_pnorm(a: f32, b: f32, e: f32) -> f32 {
    let hi = a.max(b);
    let lo = a.min(b);
    if hi <= 0.0 {
        return 0.0;
    }
    let p = 2.0 / e.max(SQ_EXP_MIN);
    let r = sq_pow(lo / hi, p);
    hi * exp2(log2(1.0 + r) / p)
}

/// `sq_profile`: `R_e(z) = (1 − z^(2/e))^(e/2)` for `0 ≤ z ≤ 1` (`R(0) = 1`, `R(1) = 0`). The
/// difference `1 − z^q` cancels next to the tips (no `expm1` in WGSL); its absolute error, an
/// ulp of 1, moves the surface there by about that much along z.
pub fn sq_profile(z: f32, e: f32) -> f32 {
    let q = 2.0 / e.max(SQ_EXP_MIN);
    let rest = 1.0 - sq_pow(z, q);
    select(exp2(log2(rest.max(SQ_TINY)) / q), 0.0, rest <= 0.0)
}

/// `sq_norm_log`: Barr's norm `G = N_β(N_α(|x|, |y|), |z|)` at absolute coordinates `a`, with the
/// logs of `∂G/∂a` (x, y, z). `G ≤ 1` is the solid when `c = β`; `G` is monotone in each
/// argument for every exponent, and a norm (convex) for α, β ≤ 2.
pub fn sq_norm_log(a: Vec3, e: Vec3) -> [f32; 4] {
    let n1 = sq_pnorm_log(a.x, a.y, e.x);
    let n2 = sq_pnorm_log(n1.x, a.z, e.y);
    [n2.x, n2.y + n1.y, n2.y + n1.z, n2.z]
}

/// `sq_pnorm_grad`: `(N, ∂N/∂a, ∂N/∂b)` of `N_e(a, b)` for `e ≤ 2` (`p = 2/e ≥ 1`, the convex
/// case), the derivatives without logs of their own: with `r = (lo/hi)^p`, `(hi/N)^p = 1/(1 +
/// r)`, so `∂N/∂hi = (hi/N)^(p−1) = (N/hi)/(1 + r)` in `[1/2, 1]` and `∂N/∂lo = (lo/hi)^(p−1)
/// ∂N/∂hi = (r/(lo/hi)) ∂N/∂hi ≤ 1` (`lo/hi` clamped as `r` is). Four transcendentals, as `N`
/// alone.
pub fn sq_pnorm_grad(a: f32, b: f32, e: f32) -> Vec3 {
    let hi = a.max(b);
    let lo = a.min(b);
    if hi <= 0.0 {
        return Vec3::ZERO;
    }
    let p = 2.0 / e.max(SQ_EXP_MIN);
    let ratio = (lo / hi).max(SQ_TINY);
    let r = select(exp2(p * log2(ratio)), 0.0, lo <= 0.0);
    let grow = exp2(log2(1.0 + r) / p);
    let d_hi = grow / (1.0 + r);
    let d_lo = (r / ratio) * d_hi;
    if a >= b {
        Vec3::new(hi * grow, d_hi, d_lo)
    } else {
        Vec3::new(hi * grow, d_lo, d_hi)
    }
}

/// `sq_norm_grad`: `(G, ∇G)` of Barr's norm at absolute coordinates `a`, convex glyphs: 8
/// transcendentals.
pub fn sq_norm_grad(a: Vec3, e: Vec3) -> [f32; 4] {
    let n1 = sq_pnorm_grad(a.x, a.y, e.x);
    let n2 = sq_pnorm_grad(n1.x, a.z, e.y);
    [n2.x, n2.y * n1.y, n2.y * n1.z, n2.z]
}

/// `sq_gauge`: an inside–outside function of absolute local coordinates, ≤ 1 exactly on the
/// solid and non-decreasing in each argument: the norm `G` when `c = β` (no profile, so no
/// cancellation next to the tips), else `H = N_α(|x|/R_β(z), |y|/R_c(z))` ([`SQ_BIG`] where
/// `|z| ≥ 1` off the axis).
pub fn sq_gauge(a: Vec3, e: Vec3) -> f32 {
    if e.z == e.y {
        return sq_pnorm(sq_pnorm(a.x, a.y, e.x), a.z, e.y);
    }
    if a.z >= 1.0 {
        return select(SQ_BIG, 1.0, a.z == 1.0 && a.x == 0.0 && a.y == 0.0);
    }
    // a / R with 0 / 0 = 0 on the axis, and at most SQ_BIG where the profile has closed.
    let u = (a.x / sq_profile(a.z, e.y).max(SQ_TINY)).min(SQ_BIG);
    let w = (a.y / sq_profile(a.z, e.z).max(SQ_TINY)).min(SQ_BIG);
    sq_pnorm(u, w, e.x)
}

/// `sq_contains`: the point `p` (local unit coordinates) is in the solid.
pub fn sq_contains(p: Vec3, e: Vec3) -> bool {
    sq_gauge(p.abs(), e) <= 1.0
}

/// `sq_convex`: Barr's solid is convex and `G` a norm (α ≤ 2, β ≤ 2, c = β).
pub fn sq_convex(e: Vec3) -> bool {
    e.x <= 2.0 && e.y <= 2.0 && e.z == e.y
}

/// `sq_log_add`: `log2(2^a + 2^b)`.
fn sq_log_add(a: f32, b: f32) -> f32 {
    let hi = a.max(b);
    let lo = a.min(b);
    hi + log2(1.0 + exp2(lo - hi))
}

/// `sq_gauge_grad_log`: logs of the components of `∇H` at absolute coordinates `a` for `c ≠ β`
/// (docs/book/src/developer/superquadric-derivation.md §4, as the reference's `local_gradient`): `∂H/∂x = A/R_β`,
/// `∂H/∂y = B/R_c`, `∂H/∂|z| = A u (|z|/R_β)^(2/β − 1)/R_β + B w (|z|/R_c)^(2/c − 1)/R_c`. At the
/// poles and where the profile has closed to below [`SQ_TINY`] (the tips) the normal is the
/// axis.
fn sq_gauge_grad_log(a: Vec3, e: Vec3) -> Vec3 {
    let pole = Vec3::new(SQ_NEG, SQ_NEG, 0.0);
    if a.x <= 0.0 && a.y <= 0.0 {
        return pole;
    }
    let rb = sq_profile(a.z, e.y);
    let rc = sq_profile(a.z, e.z);
    if a.z >= 1.0 || rb <= SQ_TINY || rc <= SQ_TINY {
        return pole;
    }
    let u = a.x / rb;
    let w = a.y / rc;
    let h = sq_pnorm_log(u, w, e.x);
    let lrb = log2(rb);
    let lrc = log2(rc);
    let lx = h.y - lrb;
    let ly = h.z - lrc;
    let qb = 2.0 / e.y.max(SQ_EXP_MIN) - 1.0;
    let qc = 2.0 / e.z.max(SQ_EXP_MIN) - 1.0;
    let lz_b = select(
        h.y + log2(u.max(SQ_TINY)) + qb * log2((a.z / rb).max(SQ_TINY)) - lrb,
        SQ_NEG,
        a.x <= 0.0 || a.z <= 0.0,
    );
    let lz_c = select(
        h.z + log2(w.max(SQ_TINY)) + qc * log2((a.z / rc).max(SQ_TINY)) - lrc,
        SQ_NEG,
        a.y <= 0.0 || a.z <= 0.0,
    );
    Vec3::new(lx, ly, sq_log_add(lz_b, lz_c))
}

/// `sq_unit`: `n` normalised, or the axis `+z` where it is 0 (only at the centre, never on the
/// surface).
fn sq_unit(n: Vec3) -> Vec3 {
    if n.dot(n) <= 0.0 {
        return Vec3::new(0.0, 0.0, 1.0);
    }
    n.normalize()
}

/// `sq_normal`: the unit direction of the gauge's gradient at `q` (local unit coordinates),
/// never zero or NaN. Components are formed as logs and scaled by the largest, so exponents
/// like `2/β = 2e20` neither over- nor underflow the direction. A coordinate that is exactly 0
/// gives a component 0 (the mirror-symmetric limit, also at ridges and tips).
pub fn sq_normal(q: Vec3, e: Vec3) -> Vec3 {
    let a = q.abs();
    let l = if e.z == e.y {
        let g = sq_norm_log(a, e);
        Vec3::new(g[1], g[2], g[3])
    } else {
        sq_gauge_grad_log(a, e)
    };
    let m = l.max_element();
    sq_unit(sign3(q) * Vec3::new(exp2(l.x - m), exp2(l.y - m), exp2(l.z - m)))
}

mod search;

pub use search::{sq_clip, sq_first, sq_first_cost, sq_first_in, sq_first_within_cost};

/// A hair beyond the solid's farthest point (`SQ_BOUND_MARGIN`).
pub const SQ_BOUND_MARGIN: f32 = 1.0001;

/// `sq_bound`: [`crate::glyph::superquadric::bounding_scale`] in f32, times
/// [`SQ_BOUND_MARGIN`]: the radius of a ball about the centre holding the solid, which the
/// shaders compute once per glyph and pass to `sq_first`.
pub fn sq_bound(e: Vec3) -> f32 {
    let beta = e.y.min(e.z);
    let m = exp2(1.0 - e.x).max(1.0);
    let mut s2 = m;
    if beta < 1.0 {
        let k = 1.0 - beta;
        s2 = m * exp2(k * log2(1.0 + exp2(-log2(m) / k)));
    }
    s2.sqrt().min(1.732_050_8) * SQ_BOUND_MARGIN
}

/// Vulkan's precision of `exp2` and `log2` (3 + 2|x| ulp; 3 ulp, or 2⁻²¹ absolute for arguments
/// in [0.5, 2]), as random errors for the tests.
#[cfg(test)]
pub(crate) mod sloppy {
    use std::cell::Cell;

    thread_local! {
        static STATE: Cell<u64> = const { Cell::new(0) };
    }

    /// Runs `f` with inaccurate `exp2`/`log2` (seeded by `seed`, which must not be 0).
    pub fn with<R>(seed: u64, f: impl FnOnce() -> R) -> R {
        STATE.with(|s| s.set(seed | 1));
        let r = f();
        STATE.with(|s| s.set(0));
        r
    }

    /// Uniform in [−1, 1), or None when off.
    fn unit() -> Option<f32> {
        STATE.with(|s| {
            let x = s.get();
            if x == 0 {
                return None;
            }
            let x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            s.set(x | 1);
            Some(((x >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0)
        })
    }

    pub fn exp2_err(x: f32) -> Option<f32> {
        unit().map(|u| u * (3.0 + 2.0 * x.abs().min(1e6)) * f32::EPSILON / 2.0)
    }

    pub fn log2_err(x: f32) -> Option<f32> {
        unit().map(|u| {
            if (0.5..=2.0).contains(&x) {
                u * 2f32.powi(-21)
            } else {
                u * 3.0 * f32::EPSILON / 2.0 * x.log2().abs()
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::superquadric::{Sharpness, superquadric_shape};
    use crate::shape::superquadric::Superquadric;
    use crate::shape::superquadric::exact::tests::{
        Lcg, glyph_of, random_frame, random_glyph, random_ray,
    };
    use crate::test_vectors::superquadric_vectors as vectors;
    use crate::test_vectors::v3;
    use glam::{DMat3, DVec3};
    use proptest::prelude::*;

    const SHADER: &str = include_str!("../../shaders/shape/superquadric_finder.wgsl");

    fn exponents_of(sq: &Superquadric) -> Vec3 {
        Vec3::new(sq.alpha as f32, sq.beta as f32, sq.beta_y as f32)
    }

    /// The twin's answer for a world ray (d unit): t and the world normal.
    #[derive(Debug, Clone, Copy)]
    struct Twin {
        t: f64,
        normal: DVec3,
    }

    /// The world ray in local unit coordinates next to the glyph, in f64 as the reference does
    /// (origin moved to the point nearest the centre), then the f32 twin with s ≥ −t0 (t ≥ 0).
    fn twin(sq: &Superquadric, o: DVec3, d: DVec3) -> (Option<Twin>, SqCost) {
        twin_within(sq, o, d, 0.0)
    }

    /// [`twin`] with the convex finder stopping at steps up to `tol_min` (`sq_first_within`).
    fn twin_within(sq: &Superquadric, o: DVec3, d: DVec3, tol_min: f32) -> (Option<Twin>, SqCost) {
        let t0 = (sq.centre - o).dot(d);
        let q0 = sq.to_local((o - sq.centre) + d * t0);
        let v = sq.to_local(d);
        let e = exponents_of(sq);
        let (h, cost) = sq_first_within_cost(
            q0.as_vec3(),
            v.as_vec3(),
            e,
            (-t0) as f32,
            sq_bound(e),
            tol_min,
        );
        assert!(h.s.is_finite() && h.n.is_finite(), "{h:?}");
        assert!((h.n.length() - 1.0).abs() < 1e-5, "{h:?}");
        if !h.hit {
            return (None, cost);
        }
        let normal = (sq.frame * (h.n.as_dvec3() / sq.radii)).normalize();
        let t = t0 + f64::from(h.s);
        (Some(Twin { t, normal }), cost)
    }

    fn angle_deg(a: DVec3, b: DVec3) -> f64 {
        a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
    }

    /// Every ray case of the 50-digit worked cases. Tolerances: t and the point within 1e-5 of
    /// the glyph size, loosened to 2e-7 / |d·n| for grazing crossings (rounding the ray to f32
    /// moves a crossing at incidence d·n by about an ulp of the coordinates over |d·n|); the
    /// normal within 0.5°.
    #[test]
    fn rays_match_the_vectors() {
        let all = vectors();
        let cases = all["rays"].as_array().unwrap();
        for case in cases {
            let id = case["id"].as_str().unwrap();
            let sq = glyph_of(&case["glyph"]);
            let o = v3(&case["ray"]["origin"]);
            let d = v3(&case["ray"]["dir"]);
            let e = &case["expected"];
            let (hit, _) = twin(&sq, o, d);
            assert_eq!(hit.is_some(), e["hit"].as_bool().unwrap(), "{id}: {hit:?}");
            let Some(hit) = hit else { continue };
            let size = sq.radii.max_element();
            let cos = case["d_dot_n"].as_f64().unwrap().abs();
            let tol = size * 1e-5f64.max(2e-7 / cos);
            let t = e["t"].as_f64().unwrap();
            assert!(
                (hit.t - t).abs() <= tol,
                "{id}: t {} vs {t} ({:e} of the size)",
                hit.t,
                (hit.t - t).abs() / size
            );
            let p = o + d * hit.t;
            assert!((p - v3(&e["point"])).length() <= tol, "{id}: point {p}");
            let n = v3(&e["normal"]);
            assert!(
                angle_deg(hit.normal, n) <= 0.5,
                "{id}: normal {} vs {n}",
                hit.normal
            );
        }
        assert!(cases.len() >= 15, "only {} ray cases", cases.len());
    }

    /// The constants of this twin are the shader's, and every function of the twin is there.
    #[test]
    fn shader_has_the_twins_constants_and_functions() {
        let value = |name: &str| -> String {
            let key = format!("const {name}: ");
            let line = SHADER
                .lines()
                .find(|l| l.starts_with(&key))
                .unwrap_or_else(|| panic!("{name} not in superquadric_finder.wgsl"));
            let rest = &line[key.len()..];
            let v = rest.split('=').nth(1).unwrap().trim();
            v.trim_end_matches(';').trim().to_string()
        };
        let u = |name: &str| -> u32 { value(name).trim_end_matches('u').parse().unwrap() };
        let f = |name: &str| -> f32 { value(name).parse().unwrap() };
        assert_eq!(u("SQ_NEWTON_MAX"), SQ_NEWTON_MAX);
        assert_eq!(u("SQ_BOUND_MAX"), SQ_BOUND_MAX);
        assert_eq!(u("SQ_DEPTH_MAX"), SQ_DEPTH_MAX);
        assert_eq!(u("SQ_SAMPLES"), SQ_SAMPLES);
        assert_eq!(u("SQ_SECANT_MAX"), SQ_SECANT_MAX);
        for (name, x) in [
            ("SQ_TOL", SQ_TOL),
            ("SQ_ULP", SQ_ULP),
            ("SQ_BRACKET", SQ_BRACKET),
            ("SQ_GROWTH", SQ_GROWTH),
            ("SQ_PARTS", SQ_PARTS),
            ("SQ_MARGIN", SQ_MARGIN),
            ("SQ_EXP_MIN", SQ_EXP_MIN),
            ("SQ_TINY", SQ_TINY),
            ("SQ_BIG", SQ_BIG),
            ("SQ_NEG", SQ_NEG),
            ("SQ_V_MIN", SQ_V_MIN),
            ("SQ_BOUND_MARGIN", SQ_BOUND_MARGIN),
        ] {
            assert_eq!(f(name), x, "{name}");
        }
        // No other constant in the shader.
        let consts = SHADER.lines().filter(|l| l.starts_with("const ")).count();
        assert_eq!(consts, 17);
        assert_eq!(
            SQ_BOUND_MARGIN,
            crate::glyph::superquadric::BOUND_MARGIN as f32
        );
        for name in [
            "sq_pow",
            "sq_pnorm_log",
            "sq_pnorm",
            "sq_profile",
            "sq_norm_log",
            "sq_pnorm_grad",
            "sq_norm_grad",
            "sq_bound",
            "sq_gauge",
            "sq_contains",
            "sq_convex",
            "sq_log_add",
            "sq_gauge_grad_log",
            "sq_unit",
            "sq_normal",
            "sq_newton",
            "sq_excess",
            "sq_secant",
            "sq_search",
            "sq_first",
            "sq_first_within",
        ] {
            assert!(SHADER.contains(&format!("\nfn {name}(")), "{name}");
        }
        assert!(
            SHADER.contains("struct SqHit {\n    s: f32,\n    n: vec3<f32>,\n    hit: bool,\n}")
        );
    }

    /// naga parses and validates the shader composed after common.wgsl (as the pipelines will
    /// compose it) and on its own, each with a stub entry point calling the API.
    #[test]
    fn shader_validates() {
        use crate::render::shaders::{COMMON, validate};
        let stub = "
@fragment
fn fs_sq_stub(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let e = vec3<f32>(0.5, 3.0, 2.5);
    let h = sq_first(vec3<f32>(pos.xy * 0.01, -3.0), vec3<f32>(0.0, 0.0, 1.0), e, 0.0, sq_bound(e));
    let inside = sq_contains(vec3<f32>(pos.xy * 0.01, 0.0), vec3<f32>(1.0));
    return vec4<f32>(h.n * h.s, select(0.0, 1.0, h.hit && inside));
}
";
        validate(&format!("{COMMON}\n{SHADER}\n{stub}")).unwrap();
        validate(&format!("{SHADER}\n{stub}")).unwrap();
    }

    /// The classes of random glyphs the twin is judged on.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum Kind {
        /// α, β log-uniform in [1e-6, 2], c = β.
        Convex,
        /// α log-uniform in [1e-6, 2], β = c in (2, 5].
        Pinched,
        /// α log-uniform in [1e-6, 2], β ≠ c independent in (2, 5] (Schultz–Kindlmann's range).
        Mixed,
        /// α log-uniform in [1e-6, 2], β and c independent, log-uniform in [1e-3, 5].
        Wild,
    }

    const KINDS: [Kind; 4] = [Kind::Convex, Kind::Pinched, Kind::Mixed, Kind::Wild];

    fn exponents(rng: &mut Lcg, kind: Kind) -> [f64; 3] {
        let a = rng.log_range(1e-6, 2.0);
        match kind {
            Kind::Convex => {
                let b = rng.log_range(1e-6, 2.0);
                [a, b, b]
            }
            Kind::Pinched => {
                let b = rng.range(2.0, 5.0);
                [a, b, b]
            }
            Kind::Mixed => [a, rng.range(2.0, 5.0), rng.range(2.0, 5.0)],
            Kind::Wild => [a, rng.log_range(1e-3, 5.0), rng.log_range(1e-3, 5.0)],
        }
    }

    /// A ray aimed at a random point of 1.1 × the box, starting 0.5 to 5 plus the box's
    /// half-diagonal before it: mostly outside the glyph, but it may start inside the box, and
    /// now and then inside the solid (then its first crossing is an exit).
    fn near_ray(rng: &mut Lcg, sq: &Superquadric) -> (DVec3, DVec3) {
        let reach = sq.radii.length();
        random_ray(rng, sq, |rng| reach + rng.range(0.5, 5.0))
    }

    /// The reference on the very ray the twin was given (its f32 coordinates in the glyph's
    /// unit frame, the f32 exponents): what is left is the finder's own error. `s` of the first
    /// crossing with s > s_min.
    fn reference_local(o: Vec3, v: Vec3, e: Vec3, s_min: f32) -> Option<f64> {
        let unit = Superquadric {
            centre: DVec3::ZERO,
            frame: DMat3::IDENTITY,
            radii: DVec3::ONE,
            alpha: f64::from(e.x),
            beta: f64::from(e.y),
            beta_y: f64::from(e.z),
        };
        let v = v.as_dvec3();
        let len = v.length();
        let start = o.as_dvec3() + v * f64::from(s_min);
        let h = unit.intersect(start, v / len)?;
        Some(f64::from(s_min) + h.t / len)
    }

    /// The ray's (entry, exit) of the glyph's box, t ≥ 0 (f64).
    fn box_span(sq: &Superquadric, o: DVec3, d: DVec3) -> (f64, f64) {
        let q0 = sq.to_local(o - sq.centre);
        let v = sq.to_local(d);
        let (mut a, mut b) = (0.0f64, f64::INFINITY);
        for k in 0..3 {
            let s1 = (-1.0 - q0[k]) / v[k];
            let s2 = (1.0 - q0[k]) / v[k];
            a = a.max(s1.min(s2));
            b = b.min(s1.max(s2));
        }
        (a, b)
    }

    /// The smallest gauge along the ray within the box (f64, sampled and refined by golden
    /// sections): `1 − m` is how deep a hit goes into the solid, `m − 1` how close a miss
    /// passes — the measure of tangency under which hit and miss may disagree.
    fn min_gauge(sq: &Superquadric, o: DVec3, d: DVec3) -> f64 {
        let t0 = (sq.centre - o).dot(d);
        let q0 = sq.to_local((o - sq.centre) + d * t0);
        let v = sq.to_local(d);
        let (mut a, mut b) = (-t0, f64::INFINITY);
        for k in 0..3 {
            if v[k] != 0.0 {
                let s1 = (-1.0 - q0[k]) / v[k];
                let s2 = (1.0 - q0[k]) / v[k];
                a = a.max(s1.min(s2));
                b = b.min(s1.max(s2));
            } else if q0[k].abs() > 1.0 {
                return f64::INFINITY;
            }
        }
        if a >= b {
            return f64::INFINITY;
        }
        let h = |s: f64| {
            let q = (q0 + v * s).abs();
            sq.gauge(q.x, q.y, q.z)
        };
        const N: usize = 4000;
        let step = (b - a) / N as f64;
        let mut best = (f64::INFINITY, a);
        for k in 0..=N {
            let s = a + step * k as f64;
            let g = h(s);
            if g < best.0 {
                best = (g, s);
            }
        }
        let (mut lo, mut hi) = ((best.1 - step).max(a), (best.1 + step).min(b));
        let r = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (m1, m2) = (hi - r * (hi - lo), lo + r * (hi - lo));
            if h(m1) < h(m2) { hi = m2 } else { lo = m1 }
        }
        best.0.min(h(0.5 * (lo + hi)))
    }

    /// Hit and miss may disagree only where the ray passes the surface within this (in units of
    /// the gauge, `|m − 1|` of [`min_gauge`]): f32 resolves the gauge to about 1e-7.
    const TANGENCY: f64 = 1e-5;

    /// One ray judged against the reference.
    #[derive(Debug, Clone, Copy)]
    struct Judged {
        /// Twin and reference (world ray) agree on hit or miss.
        agree: bool,
        /// Where they do not: the reference's `|m − 1|` (see [`min_gauge`]).
        tangency: f64,
        /// Both hit: |Δt| / half-diagonal against the world ray, the same against the reference
        /// on the twin's own f32 ray (the finder's part), and the angle between the normals (°).
        depth: Option<(f64, f64, f64)>,
        /// The reference's |d·n| at its hit (1 for a miss).
        cos: f64,
        cost: SqCost,
        hit: bool,
    }

    fn judge(sq: &Superquadric, o: DVec3, d: DVec3) -> Judged {
        let want = sq.intersect(o, d);
        let (got, cost) = twin(sq, o, d);
        let agree = want.is_some() == got.is_some();
        let mut j = Judged {
            agree,
            tangency: if agree {
                f64::INFINITY
            } else {
                (min_gauge(sq, o, d) - 1.0).abs()
            },
            depth: None,
            cos: want.map_or(1.0, |w| w.normal.dot(d).abs()),
            cost,
            hit: got.is_some(),
        };
        if let (Some(g), Some(w)) = (got, want) {
            let hd = sq.radii.length();
            let t0 = (sq.centre - o).dot(d);
            let q0 = sq.to_local((o - sq.centre) + d * t0).as_vec3();
            let v = sq.to_local(d).as_vec3();
            let own = reference_local(q0, v, exponents_of(sq), (-t0) as f32)
                .map_or(f64::INFINITY, |s| (t0 + s - g.t).abs() / hd);
            j.depth = Some(((g.t - w.t).abs() / hd, own, angle_deg(g.normal, w.normal)));
        }
        j
    }

    /// The per-ray bounds: no NaN (checked in [`twin`]), hit and miss agree except within
    /// [`TANGENCY`], depth within 1e-4 of the half-diagonal except at grazing incidence
    /// (|d·n| < 1e-3, where f32 rounding of the ray alone moves the crossing by ~1e-7/|d·n|).
    fn check(j: &Judged) -> Result<(), TestCaseError> {
        prop_assert!(j.agree || j.tangency < TANGENCY, "{j:?}");
        if let Some((depth, own, _)) = j.depth {
            prop_assert!(depth <= 1e-4 || j.cos < 1e-3, "{j:?}");
            prop_assert!(own <= 1e-4 || j.cos < 1e-3, "{j:?}");
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Random glyphs of every kind, random rays from outside aimed near them.
        #[test]
        fn agrees_with_the_reference(kind in 0usize..4, seed in any::<u64>()) {
            let mut rng = Lcg(seed);
            let abc = exponents(&mut rng, KINDS[kind]);
            let sq = random_glyph(&mut rng, abc);
            let (o, d) = near_ray(&mut rng, &sq);
            check(&judge(&sq, o, d))?;
        }

        /// Rays along the local axes and in the mirror planes (exact zeros in the powers), with
        /// exponents down to 1e-20 and up to 5: no NaN, the reference's hit and normal.
        #[test]
        fn axis_and_mirror_plane_rays(
            abc in (prop_oneof![Just(1e-20), Just(1e-6), 0.01f64..2.0],
                    prop_oneof![Just(1e-20), Just(1e-6), 0.01f64..5.0],
                    any::<bool>(), 0.01f64..5.0)
                .prop_map(|(a, b, same, c)| [a, b, if same { b } else { c }]),
            k in 0usize..3, off in -1.2f64..1.2, tilt in -0.5f64..0.5,
            sign in any::<bool>(), plane in 0usize..3,
        ) {
            let sq = Superquadric {
                centre: DVec3::ZERO,
                frame: DMat3::IDENTITY,
                radii: DVec3::new(1.0, 0.5, 0.8),
                alpha: abc[0],
                beta: abc[1],
                beta_y: abc[2],
            };
            let mut d = DVec3::ZERO;
            d[k] = if sign { 1.0 } else { -1.0 };
            let mut o = -d * 3.0;
            match plane {
                // Along the axis through the centre.
                0 => {}
                // Parallel to the axis, offset within a mirror plane.
                1 => o[(k + 1) % 3] = off * sq.radii[(k + 1) % 3],
                // Tilted within a mirror plane through the axis.
                _ => {
                    d[(k + 1) % 3] = tilt;
                    d = d.normalize();
                    o = -d * 3.0;
                }
            }
            let j = judge(&sq, o, d);
            check(&j)?;
            if plane == 0 {
                // Straight through the centre: the pole or equator point on axis k.
                let (h, _) = twin(&sq, o, d);
                let h = h.unwrap();
                prop_assert!((h.normal + d).length() < 1e-6, "{h:?}");
                prop_assert!((h.t - (3.0 - sq.radii[k])).abs() < 1e-6, "{h:?}");
            }
            if let Some((_, _, angle)) = j.depth {
                // A mirror plane keeps the normal in it; smooth enough shapes agree closely.
                if abc.iter().all(|&x| (0.05..=2.0).contains(&x)) {
                    prop_assert!(angle < 0.5, "{j:?}");
                }
            }
        }

        /// From inside the solid: the exit, outward, as the reference.
        #[test]
        fn eye_inside_gives_the_exit(kind in 0usize..4, seed in any::<u64>()) {
            let mut rng = Lcg(seed);
            let abc = exponents(&mut rng, KINDS[kind]);
            let sq = random_glyph(&mut rng, abc);
            let o = sq.centre + sq.frame * (DVec3::new(rng.range(-0.3, 0.3),
                rng.range(-0.3, 0.3), rng.range(-0.3, 0.3)) * sq.radii);
            prop_assume!(sq.contains(o));
            let d = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
                .normalize_or(DVec3::X);
            let (h, _) = twin(&sq, o, d);
            if sq.intersect(o, d).is_none() {
                // The reference's branch and bound gives no exit when the ray leaves through a
                // flat cap that lies on the box face (β or c tiny, c ≠ β): rounding puts the
                // box exit a hair inside the solid, so the whole span is certified inside. The
                // exit is then the box exit, which the twin returns.
                let h = h.unwrap();
                let box_exit = box_span(&sq, o, d).1;
                prop_assert!((h.t - box_exit).abs() < 1e-5 * sq.radii.length(), "{h:?} vs {box_exit}");
                return Ok(());
            }
            let j = judge(&sq, o, d);
            check(&j)?;
            if let Some(h) = h {
                prop_assert!(h.normal.dot(d) >= -1e-3, "exit normal faces the ray: {h:?}");
            }
        }
    }

    /// The hit of the f32 ray `o + s v` in the unit frame and the reference's `s` on it.
    fn local(o: [f32; 3], v: [f32; 3], e: [f32; 3], s_min: f32) -> (SqHit, Option<f64>) {
        let (o, v, e) = (Vec3::from(o), Vec3::from(v), Vec3::from(e));
        (sq_first(o, v, e, s_min), reference_local(o, v, e, s_min))
    }

    #[test]
    fn pole_hit_along_the_axis() {
        let (h, want) = local([0.0, 0.0, -3.0], [0.0, 0.0, 1.0], [0.3, 0.4, 0.4], 0.0);
        assert!(
            h.hit && h.s == 2.0 && h.n == Vec3::new(0.0, 0.0, -1.0),
            "{h:?}"
        );
        assert_eq!(want, Some(2.0));
        // Pinched, c ≠ β: the tip.
        let (h, _) = local([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], [1.0, 3.0, 2.5], 0.0);
        assert!(h.hit && (h.s - 2.0).abs() < 1e-5 && h.n == Vec3::Z, "{h:?}");
    }

    #[test]
    fn near_cube_face_along_x() {
        // γ = 10's near-cube (docs §2) and the limit of exponents 1e-20.
        for e in [[0.30794615, 0.08101311, 0.08101311], [1e-20; 3]] {
            let (h, want) = local([-3.0, 0.3, 0.2], [1.0, 0.0, 0.0], e, 0.0);
            let want = want.unwrap();
            assert!(
                h.hit && (f64::from(h.s) - want).abs() < 1e-6,
                "{e:?}: {h:?} vs {want}"
            );
            assert!(h.n.dot(Vec3::NEG_X) > 0.99999, "{e:?}: {h:?}");
        }
        // Straight at a corner of the 1e-20 cube: the corner itself.
        let (h, _) = local([-3.0, -3.0, -3.0], [1.0, 1.0, 1.0], [1e-20; 3], 0.0);
        assert!(h.hit && (h.s - 2.0).abs() < 1e-6, "{h:?}");
    }

    #[test]
    fn grazing_rays_on_the_sphere() {
        for (y, hit) in [(1.0 - 1e-4, true), (1.0 - 1e-6, true), (1.0 + 1e-4, false)] {
            let (h, _) = local([-3.0, y, 0.0], [1.0, 0.0, 0.0], [1.0; 3], 0.0);
            assert_eq!(h.hit, hit, "{y}: {h:?}");
            if hit {
                let want = 3.0 - (1.0 - f64::from(y) * f64::from(y)).sqrt();
                // A tangent crossing is conditioned as √(rounding): f32 gets about 1e-4 of it.
                assert!((f64::from(h.s) - want).abs() < 3e-4, "{y}: {h:?} vs {want}");
            }
        }
        // Exactly tangent: hit or miss, finite either way.
        let (h, _) = local([-3.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0; 3], 0.0);
        assert!(h.s.is_finite() && h.n.is_finite(), "{h:?}");
        // Tangent to a flat face of the 1e-20 cube and the rim of a near-cylinder.
        for e in [[1e-20; 3], [1.0, 1e-20, 1e-20]] {
            let (h, _) = local([-3.0, 0.2, 1.0], [1.0, 0.0, 0.0], e, 0.0);
            assert!(h.s.is_finite() && h.n.is_finite(), "{e:?}: {h:?}");
        }
    }

    #[test]
    fn eye_inside_the_solid_gives_the_exit() {
        for e in [[1.0; 3], [0.5, 0.3, 0.3], [1.0, 3.0, 3.0], [0.2, 2.5, 4.0]] {
            let (h, want) = local([0.0; 3], [1.0, 0.0, 0.0], e, 0.0);
            assert!(h.hit && (h.s - 1.0).abs() < 1e-5, "{e:?}: {h:?}");
            assert!((want.unwrap() - 1.0).abs() < 1e-12, "{e:?}: {want:?}");
            assert!((h.n - Vec3::X).length() < 1e-6, "{e:?}: {h:?}");
        }
    }

    /// From inside a glyph whose flat cap lies on the box face (β, c tiny, c ≠ β) through that
    /// cap: the exit is the box exit. (The reference's branch and bound returns no hit here:
    /// rounding puts its box exit a hair inside the solid, so it certifies the whole span
    /// inside and finds nothing.)
    #[test]
    fn exit_through_a_flat_cap_on_the_box_face() {
        let sq = Superquadric {
            centre: DVec3::new(3.2611083914394126, -3.3193779662707588, -2.4453830404715085),
            frame: DMat3::from_cols(
                DVec3::new(
                    -0.17046407576687916,
                    -0.19504671494013448,
                    -0.9658668530724125,
                ),
                DVec3::new(
                    -0.9317572722800007,
                    0.35080916604784473,
                    0.09360189405214081,
                ),
                DVec3::new(0.3205782032925445, 0.915909224764047, -0.24153655534068985),
            ),
            radii: DVec3::new(0.1004376194362255, 0.18567984442371305, 0.06515918675563614),
            alpha: 0.004700101772210524,
            beta: 0.022349952363801377,
            beta_y: 0.016322249164070476,
        };
        let o = DVec3::new(3.276096060171581, -3.336859280803039, -2.444522456665473);
        let d = DVec3::new(-0.6448591278015953, 0.7487439206982072, 0.1534250517628809);
        assert!(sq.contains(o));
        let (h, _) = twin(&sq, o, d);
        let h = h.unwrap();
        let box_exit = box_span(&sq, o, d).1;
        assert!(
            (h.t - box_exit).abs() < 1e-6 * sq.radii.length(),
            "{h:?} vs {box_exit}"
        );
        // The reference leaves through the box face too.
        let want = sq.intersect(o, d).expect("the exit through the cap");
        assert!((want.t - box_exit).abs() < 1e-12 * sq.radii.length());
        // Outward through the cap: the local +z direction, away from the eye.
        assert!(h.normal.dot(sq.frame.z_axis).abs() > 0.999 && h.normal.dot(d) > 0.0);
    }

    #[test]
    fn eye_in_the_box_outside_a_thorn_gives_the_entry() {
        let e = [1.0, 3.0, 3.0];
        // At z = 0.5 the thorn's radius is (1 − 0.5^(2/3))^(3/2) ≈ 0.2246: (0.5, 0, 0.5) is out.
        assert!(!sq_contains(Vec3::new(0.5, 0.0, 0.5), Vec3::from(e)));
        let (h, want) = local([0.5, 0.0, 0.5], [-1.0, 0.0, 0.0], e, 0.0);
        let r = (1.0 - 0.5f64.powf(2.0 / 3.0)).powf(1.5);
        assert!(
            h.hit && (f64::from(h.s) - (0.5 - r)).abs() < 1e-5,
            "{h:?} vs {r}"
        );
        assert!((want.unwrap() - (0.5 - r)).abs() < 1e-12);
        // Outward at the entry: towards +x and +z.
        assert!(h.n.x > 0.0 && h.n.z > 0.0 && h.n.y == 0.0, "{h:?}");
    }

    #[test]
    fn exponents_1e_20() {
        // Near-cylinder along z: cap near the rim, then the side.
        let e = [1.0, 1e-20, 1e-20];
        let (h, _) = local([0.7, 0.6, 3.0], [0.0, 0.0, -1.0], e, 0.0);
        assert!(h.hit && (h.s - 2.0).abs() < 1e-6 && h.n == Vec3::Z, "{h:?}");
        let (h, _) = local([-3.0, 0.0, 0.5], [1.0, 0.0, 0.0], e, 0.0);
        assert!(h.hit && (h.s - 2.0).abs() < 1e-6 && (h.n - Vec3::NEG_X).length() < 1e-6);
        // Everything 1e-20 with c ≠ β, and a pinched profile with a square section.
        for e in [[1e-20, 1e-20, 3.0], [1e-20, 4.0, 4.0]] {
            let (h, want) = local([-3.0, 0.1, 0.05], [1.0, 0.01, 0.02], e, 0.0);
            assert_eq!(h.hit, want.is_some(), "{e:?}");
            if let Some(want) = want {
                assert!(
                    (f64::from(h.s) - want).abs() < 1e-5,
                    "{e:?}: {h:?} vs {want}"
                );
            }
        }
    }

    #[test]
    fn s_min_behind_and_inside() {
        let e = [0.6, 0.8, 0.8];
        // The origin at the centre, s_min behind the glyph: the back face's entry at s = −1.
        let (h, _) = local([0.0; 3], [1.0, 0.0, 0.0], e, -5.0);
        assert!(h.hit && (h.s + 1.0).abs() < 1e-6, "{h:?}");
        // s_min inside the solid: its exit.
        let (h, _) = local([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0], e, 3.0);
        assert!(h.hit && (h.s - 4.0).abs() < 1e-5, "{h:?}");
        // s_min in the box, outside the solid (near a corner): the entry after it.
        let (h, want) = local([-0.95, -0.95, 0.0], [1.0, 1.0, 0.0], e, 0.0);
        assert!(
            h.hit && (f64::from(h.s) - want.unwrap()).abs() < 1e-5,
            "{h:?}"
        );
        // s_min past the glyph: a miss; and a ray that points away.
        assert!(!local([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0], e, 4.5).0.hit);
        assert!(!local([-3.0, 0.0, 0.0], [-1.0, 0.0, 0.0], e, 0.0).0.hit);
        // v of any length: s scales with 1/|v|.
        for scale in [1e-3f32, 1e3] {
            let (h, _) = local([-3.0, 0.1, 0.0], [scale, 0.0, 0.0], e, 0.0);
            let (h1, _) = local([-3.0, 0.1, 0.0], [1.0, 0.0, 0.0], e, 0.0);
            assert!(
                h.hit && (h.s * scale - h1.s).abs() < 1e-5 * h1.s,
                "{scale}: {h:?}"
            );
        }
        // A zero direction, or one along a face outside the box: misses, no NaN.
        assert!(!local([0.0; 3], [0.0; 3], e, 0.0).0.hit);
        assert!(!local([2.0, 0.0, 0.0], [0.0, 1.0, 0.0], e, 0.0).0.hit);
    }

    fn percentile(v: &mut [f64], p: f64) -> f64 {
        if v.is_empty() {
            return 0.0;
        }
        v.sort_by(f64::total_cmp);
        v[((v.len() - 1) as f64 * p).round() as usize]
    }

    #[derive(Debug, Default)]
    struct Sweep {
        rays: usize,
        hits: usize,
        disagree: usize,
        capped: usize,
        depth: Vec<f64>,
        own: Vec<f64>,
        angle: Vec<f64>,
        /// Gauge evaluations (search + other) of hits and of misses.
        evals_hit: Vec<f64>,
        evals_miss: Vec<f64>,
    }

    impl Sweep {
        fn add(&mut self, j: &Judged) {
            self.rays += 1;
            let evals = f64::from(j.cost.search + j.cost.other);
            if j.hit {
                self.hits += 1;
                self.evals_hit.push(evals);
            } else {
                self.evals_miss.push(evals);
            }
            self.capped += usize::from(j.cost.capped);
            self.disagree += usize::from(!j.agree);
            if let Some((depth, own, angle)) = j.depth {
                self.depth.push(depth);
                self.own.push(own);
                self.angle.push(angle);
            }
        }

        /// Prints the sweep; returns (depth p99, normal p99).
        fn report(&mut self, name: &str) -> (f64, f64) {
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            println!(
                "{name}: {} rays, {} hits, {} disagree (allowed within a tangency of 1e-5), {} at the cap",
                self.rays, self.hits, self.disagree, self.capped
            );
            println!(
                "  gauge evaluations per hit: mean {:.1}, p50 {}, p99 {}, max {}; per miss: mean {:.1}",
                mean(&self.evals_hit),
                percentile(&mut self.evals_hit, 0.5),
                percentile(&mut self.evals_hit, 0.99),
                percentile(&mut self.evals_hit, 1.0),
                mean(&self.evals_miss),
            );
            let row = |what: &str, v: &mut Vec<f64>| {
                let r = (
                    percentile(v, 0.5),
                    percentile(v, 0.99),
                    percentile(v, 0.999),
                    percentile(v, 1.0),
                );
                println!(
                    "  {what}: p50 {:.1e} p99 {:.1e} p99.9 {:.1e} max {:.1e}",
                    r.0, r.1, r.2, r.3
                );
                r.1
            };
            let depth = row("depth error / half-diagonal", &mut self.depth);
            row("  of it the finder's own", &mut self.own);
            let angle = row("normal error (degrees)", &mut self.angle);
            (depth, angle)
        }
    }

    fn sweep_kind(kind: Kind, n: usize, seed: u64) -> Sweep {
        let mut rng = Lcg(seed);
        let mut out = Sweep::default();
        for _ in 0..n {
            let abc = exponents(&mut rng, kind);
            let sq = random_glyph(&mut rng, abc);
            let (o, d) = near_ray(&mut rng, &sq);
            let j = judge(&sq, o, d);
            check(&j).unwrap();
            out.add(&j);
        }
        out
    }

    /// A glyph of random eigenvalues (magnitudes 0.05–1 as radii) through the mapping:
    /// Kindlmann's for definite tensors at γ, Schultz–Kindlmann's for indefinite ones (β_max 3).
    fn mapped_glyph(rng: &mut Lcg, definite: bool, gamma: f64) -> Superquadric {
        let mut ev = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        if !definite {
            ev[0] = -ev[0];
            ev[1] *= if rng.next() < 0.5 { -1.0 } else { 1.0 };
        }
        ev.sort_by(|a, b| b.total_cmp(a));
        let shape = superquadric_shape(
            ev,
            Sharpness {
                gamma,
                beta_max: 3.0,
            },
        );
        let centre = DVec3::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), 0.0);
        let frame = random_frame(rng);
        let radii = DVec3::from(ev.map(f64::abs));
        Superquadric::from_shape(centre, frame, radii, &shape)
    }

    /// The sweep over glyphs from the mapping ([`mapped_glyph`]).
    fn sweep_mapped(definite: bool, gamma: f64, n: usize, seed: u64) -> Sweep {
        let mut rng = Lcg(seed);
        let mut out = Sweep::default();
        for _ in 0..n {
            let sq = mapped_glyph(&mut rng, definite, gamma);
            let (o, d) = near_ray(&mut rng, &sq);
            let j = judge(&sq, o, d);
            check(&j).unwrap();
            out.add(&j);
        }
        out
    }

    /// The cost and accuracy report (`--nocapture`): gauge evaluations per ray (a Newton
    /// iteration, the norm with its gradient, counts as one; the normal's own evaluation counts)
    /// and the errors against the reference, per kind of glyph and for mapped glyphs. The
    /// release bounds are asserted (depth p99 ≤ 1e-4 of the half-diagonal, normal p99 ≤ 0.5°);
    /// the counts are not.
    #[test]
    fn sweep_against_the_reference_and_report() {
        let mut all = Vec::new();
        for (k, kind) in KINDS.into_iter().enumerate() {
            all.push((format!("{kind:?}"), sweep_kind(kind, 20_000, 11 + k as u64)));
        }
        for (name, definite, gamma) in [
            ("Kindlmann γ = 3", true, 3.0),
            ("Kindlmann γ = 10", true, 10.0),
            ("Schultz–Kindlmann (indefinite)", false, 3.0),
        ] {
            all.push((name.to_string(), sweep_mapped(definite, gamma, 20_000, 5)));
        }
        for (name, s) in &mut all {
            let (depth, angle) = s.report(name);
            assert!(
                depth <= 1e-4 && angle <= 0.5,
                "{name}: p99 {depth:e}, {angle}°"
            );
        }
    }

    /// The splats' compute passes (`SQ_SPLAT_TOL` in superquadric_splat.wgsl) only order hits
    /// and choose which pixels have one: against the reference, the loose convex finder agrees
    /// on hit or miss except within a tangency far below a pixel's worth, and its crossing lies
    /// before the reference's (Newton climbs from outside; behind only by the f32 ray's
    /// rounding), by 1e-5 of the half-diagonal at the 99th percentile and 2e-4 at most except at
    /// grazing incidence (near tangency Newton converges linearly). Two glyphs' hits are then
    /// misordered only where their surfaces touch to that. And it saves evaluations.
    #[test]
    fn the_splat_tolerance_orders_hits() {
        let tol_min = splat_constant("SQ_SPLAT_TOL");
        let mut rng = Lcg(77);
        let (mut rays, mut disagree, mut hits) = (0usize, 0usize, 0usize);
        let (mut errs, mut behind) = (Vec::new(), 0.0f64);
        let (mut loose_evals, mut full_evals) = (0u32, 0u32);
        for n in 0..40_000 {
            let sq = splat_test_glyph(&mut rng, n);
            let (o, d) = near_ray(&mut rng, &sq);
            let (loose, cost) = twin_within(&sq, o, d, tol_min);
            let (_, full_cost) = twin(&sq, o, d);
            loose_evals += cost.search + cost.other;
            full_evals += full_cost.search + full_cost.other;
            rays += 1;
            let want = sq.intersect(o, d);
            if want.is_some() != loose.is_some() {
                disagree += 1;
                let tangency = (min_gauge(&sq, o, d) - 1.0).abs();
                assert!(
                    tangency < 1e-5,
                    "{sq:?} {loose:?} {want:?} tangency {tangency:e}"
                );
                continue;
            }
            let (Some(w), Some(loose)) = (want, loose) else {
                continue;
            };
            hits += 1;
            let err = (loose.t - w.t) / sq.radii.length();
            if w.normal.dot(d).abs() >= 1e-3 {
                errs.push(err.abs());
            }
            behind = behind.max(err);
        }
        let p99 = percentile(&mut errs, 0.99);
        let worst = percentile(&mut errs, 1.0);
        println!(
            "splat tolerance {tol_min:e}: {rays} rays, {hits} hits, {disagree} disagree; |Δt| / \
             half-diagonal p99 {p99:.1e} max {worst:.1e} (behind the reference at most \
             {behind:.1e}); gauge evaluations {loose_evals} against {full_evals} at full tolerance"
        );
        assert!(p99 <= 1e-5 && worst <= 2e-4, "{p99:e} {worst:e}");
        // Rounding of the f32 ray puts a crossing a hair behind at most (as at full tolerance).
        assert!(behind <= 1e-5, "{behind:e}");
        assert!(loose_evals < full_evals);
    }

    /// The splat tests' glyph `n`: convex glyphs of every exponent (even `n`), and Kindlmann's
    /// mapped glyphs at γ = 3.
    fn splat_test_glyph(rng: &mut Lcg, n: usize) -> Superquadric {
        if n.is_multiple_of(2) {
            let abc = exponents(rng, Kind::Convex);
            random_glyph(rng, abc)
        } else {
            mapped_glyph(rng, true, 3.0)
        }
    }

    /// A constant of superquadric_splat.wgsl.
    fn splat_constant(name: &str) -> f32 {
        const SPLAT: &str = include_str!("../../shaders/shape/superquadric_splat.wgsl");
        let prefix = format!("const {name}: f32 = ");
        SPLAT
            .lines()
            .find_map(|l| l.strip_prefix(prefix.as_str()))
            .and_then(|l| l.trim_end_matches(';').parse().ok())
            .expect(name)
    }

    /// The splat tiles' draw (`splat_hit` in superquadric_splat.wgsl) does not cast a winning
    /// pixel's ray again: it starts the finder, at full tolerance, on the stretch from δ before
    /// the crossing the compute pass kept (recovered from its key, off by up to the key's
    /// rounding) to δ plus twice `SQ_SPLAT_TOL` after it. A splat's ray starts at the eye,
    /// outside the glyph (a glyph holding the eye is not a splat), so its crossing is an entry.
    /// With the kept crossing moved by up to δ = 3e-4 (a glyph some 5000 of its sizes away), the
    /// crossings are as close to the reference as a full cast's, in fewer evaluations.
    #[test]
    fn the_splat_tiles_restart_at_the_kept_crossing() {
        let splat_tol = splat_constant("SQ_SPLAT_TOL");
        let mut rng = Lcg(78);
        let (mut errs, mut hits) = (Vec::new(), 0usize);
        let (mut tile_evals, mut full_evals) = (0u32, 0u32);
        for n in 0..40_000 {
            let sq = splat_test_glyph(&mut rng, n);
            let (o, d) = near_ray(&mut rng, &sq);
            let t0 = (sq.centre - o).dot(d);
            let q0 = sq.to_local((o - sq.centre) + d * t0).as_vec3();
            let v = sq.to_local(d).as_vec3();
            let e = exponents_of(&sq);
            let s_min = (-t0) as f32;
            let Some(want) = sq.intersect(o, d) else {
                continue;
            };
            if sq_contains(q0 + s_min * v, e) {
                continue;
            }
            let (kept, _) = sq_first_within_cost(q0, v, e, s_min, sq_bound(e), splat_tol);
            if !kept.hit {
                continue;
            }
            full_evals += sq_first_cost(q0, v, e, s_min, sq_bound(e)).1.search;
            let delta = 3e-4 / v.length();
            let key = kept.s + delta * (2.0 * rng.range(0.0, 1.0) as f32 - 1.0);
            let span = (key - delta, key + delta + 2.0 * splat_tol / v.length());
            let mut cost = SqCost::default();
            let h = sq_first_in(q0, v, e, -3.0e38, span, 0.0, &mut cost);
            tile_evals += cost.search;
            assert!(h.hit, "{sq:?} {kept:?} {span:?}");
            hits += 1;
            if want.normal.dot(d).abs() >= 1e-3 {
                errs.push(((t0 + f64::from(h.s)) - want.t).abs() / sq.radii.length());
            }
        }
        let p99 = percentile(&mut errs, 0.99);
        let worst = percentile(&mut errs, 1.0);
        println!(
            "tile restart: {hits} hits; |Δt| / half-diagonal p99 {p99:.1e} max {worst:.1e}; \
             evaluations {tile_evals} against {full_evals} for full casts"
        );
        assert!(p99 <= 1e-5 && worst <= 2e-4, "{p99:e} {worst:e}");
        assert!(tile_evals < full_evals);
    }

    /// The same with `exp2` and `log2` as inaccurate as Vulkan allows: the finder does not rely
    /// on correctly rounded transcendentals.
    #[test]
    fn vulkan_precision_keeps_the_bounds() {
        sloppy::with(0x5eed, || {
            for (k, kind) in KINDS.into_iter().enumerate() {
                let mut s = sweep_kind(kind, 5_000, 101 + k as u64);
                let (depth, angle) = s.report(&format!("{kind:?}, Vulkan-precision exp2/log2"));
                assert!(
                    depth <= 1e-4 && angle <= 0.5,
                    "{kind:?}: p99 {depth:e}, {angle}°"
                );
            }
        });
    }
}
