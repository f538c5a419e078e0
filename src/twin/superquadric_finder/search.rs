//! The finders of the superquadric twin: the convex Newton search, the branch and bound with its
//! secant, and the first crossing built from them (`sq_newton`, `sq_search`, `sq_secant`,
//! `sq_first*` in shaders/shape/superquadric_finder.wgsl).

use glam::Vec3;

use super::*;

/// `sq_newton`: the convex finder on `[s_a, s_b]`: the entry, forward from `s_a`, or (`inside`)
/// the exit, backward from `s_b`. The normal is the gradient at the last point evaluated, which
/// is the hit or within `tol` of it: no further evaluation.
#[allow(clippy::too_many_arguments)]
fn sq_newton(
    o: Vec3,
    v: Vec3,
    e: Vec3,
    s_a: f32,
    s_b: f32,
    tol: f32,
    may_start_inside: bool,
    cost: &mut SqCost,
) -> SqHit {
    let mut inside = false;
    let mut dir = 1.0;
    let mut s_far = s_b;
    let mut s = s_a;
    // ∇G at the last point evaluated (each component a ratio ≤ 1 to a power ≥ 0, and
    // |∇G| ≥ G/|q| > 0 off the centre).
    let mut grad = Vec3::Z;
    for k in 0..SQ_NEWTON_MAX {
        cost.search += 1;
        let q = o + s * v;
        let g = sq_norm_grad(q.abs(), e);
        grad = sign3(q) * Vec3::new(g[1], g[2], g[3]);
        // On or in the solid: the box face is the surface (flat faces), or rounding took the
        // last step a hair past the root.
        if g[0] <= 1.0 {
            // The ray starts in the solid (its first point is the ray's own start): the exit,
            // backwards from the far end. Testing here costs no evaluation of its own.
            if k == 0 && may_start_inside {
                inside = true;
                dir = -1.0;
                s_far = s_a;
                s = s_b;
                continue;
            }
            return SqHit {
                s,
                n: sq_unit(grad),
                hit: true,
            };
        }
        // A subgradient of g along the ray.
        let slope = grad.dot(v);
        // g > 1 and not decreasing towards the far end: no root ahead (from inside: rounding
        // at the box exit, where the surface is).
        if dir * slope >= 0.0 {
            return SqHit {
                s,
                n: sq_unit(grad),
                hit: inside,
            };
        }
        let step = (1.0 - g[0]) / slope;
        // Beyond the far end of the box: the tangent, below g, stays above 1 over the box.
        if dir * (s + step - s_far) >= 0.0 {
            return SqHit {
                s: s_far,
                n: sq_unit(grad),
                hit: inside,
            };
        }
        s += step;
        if step.abs() <= tol {
            return SqHit {
                s,
                n: sq_unit(grad),
                hit: true,
            };
        }
    }
    // At the cap the entry is a miss; the exit is the last iterate (between the exit and the
    // box exit), with the gradient of the one before.
    cost.capped = true;
    SqHit {
        s,
        n: sq_unit(grad),
        hit: inside,
    }
}

/// `sq_search`: the branch and bound on `[s_a, s_b]`: the first possibly-inside point (entry), or
/// (`inside`) the first possibly-outside point (exit). Returns `(s, hit)`.
///
/// Depth-first over the binary tree of halvings of the span, left child first, without a
/// stack: node `i` at depth `d` is `[s_a + i w, s_a + (i + 1) w]`, `w = span / 2^d`. A node that
/// may hold the surface is split (its left child next); one certified empty is skipped, and the
/// next node is its right sibling, or, for a right child, the right sibling of its nearest
/// ancestor that is a left child. Adjacent nodes share the rounding of their common grid point,
/// so the skipped nodes cover `[s_a, lo]` without gaps.
#[allow(clippy::too_many_arguments)]
fn sq_search(
    o: Vec3,
    v: Vec3,
    e: Vec3,
    s_a: f32,
    s_b: f32,
    tol: f32,
    inside: bool,
    cost: &mut SqCost,
) -> (f32, bool) {
    let mut w = s_b - s_a;
    let wb = SQ_BRACKET / v.length();
    let mut i = 0u32;
    let mut d = 0u32;
    // Gauge evaluations so far (one per node, two more per look for a sign change).
    let mut evals = 0u32;
    while evals < SQ_BOUND_MAX {
        evals += 1;
        cost.search += 1;
        let lo = s_a + i as f32 * w;
        let hi = s_a + (i + 1) as f32 * w;
        let q_lo = o + lo * v;
        let q_hi = o + hi * v;
        // Range of |q_k| over the stretch: from 0 where q_k changes sign.
        let a_max = q_lo.abs().max(q_hi.abs());
        let cross = (q_lo * q_hi).cmple(Vec3::ZERO);
        let a_min = Vec3::select(cross, Vec3::ZERO, q_lo.abs().min(q_hi.abs()));
        let possible = if inside {
            sq_gauge(a_max, e) >= 1.0 - SQ_MARGIN
        } else {
            sq_gauge(a_min, e) <= 1.0 + SQ_MARGIN
        };
        if possible {
            // The first node at most SQ_BRACKET wide: with a sign change across it, finish with
            // the secant (the first crossing, unless the ray crosses the surface more than once
            // within this one node).
            if w <= wb && (2.0 * w > wb || d == 0) {
                evals += 2;
                cost.search += 2;
                let fl = sq_excess(sq_gauge(q_lo.abs(), e));
                let fh = sq_excess(sq_gauge(q_hi.abs(), e));
                // The sought side already at lo: only where lo = s_a (a box face on the
                // surface), as the stretch before any other lo is certified the other way.
                if (fl > 0.0) == inside {
                    return (lo, true);
                }
                if (fh > 0.0) == inside {
                    return (sq_secant(o, v, e, lo, hi, fl, fh, tol, cost), true);
                }
            }
            if w <= tol || d >= SQ_DEPTH_MAX {
                return (0.5 * (lo + hi), true);
            }
            w *= 0.5;
            i *= 2;
            d += 1;
        } else {
            i += 1;
            while d > 0 && (i & 1) == 0 {
                i >>= 1;
                d -= 1;
                w *= 2.0;
            }
            if d == 0 {
                // The whole span is certified: no crossing (from inside: the box exit).
                return (s_b, inside);
            }
        }
    }
    // At the cap (a ray skimming the surface keeps about 1/cos θ nodes per level alive, θ its
    // angle to the surface): everything before `lo` is certified.
    cost.capped = true;
    let lo = s_a + i as f32 * w;
    // The rest of the ray is sampled, at steps growing from the node's width by SQ_GROWTH up to
    // 1/SQ_PARTS of the rest, and the first change to the sought side (inside for an entry,
    // outside for an exit) refined: no longer certified (a sliver between two samples can be
    // missed), but a ray that skims the surface for a while and then crosses it is still drawn.
    let coarse = (s_b - lo) / SQ_PARTS;
    let mut step = w.min(coarse);
    let mut s0 = lo;
    cost.search += 1;
    let mut f0 = sq_excess(sq_gauge((o + s0 * v).abs(), e));
    if (f0 > 0.0) == inside {
        return (s0, true);
    }
    for _ in 0..SQ_SAMPLES {
        let s1 = (s0 + step).min(s_b);
        cost.search += 1;
        let f1 = sq_excess(sq_gauge((o + s1 * v).abs(), e));
        if (f1 > 0.0) == inside {
            return (sq_secant(o, v, e, s0, s1, f0, f1, tol, cost), true);
        }
        if s1 >= s_b {
            break;
        }
        s0 = s1;
        f0 = f1;
        step = (step * SQ_GROWTH).min(coarse);
    }
    // No change: an entry misses, an exit leaves through the box.
    (s_b, inside)
}

/// `sq_excess`: `(h − 1)/(h + 1)`, the sign of `h − 1` in `(−1, 1)`: about `(G − 1)/2` near the
/// surface, and bounded where the gauge `H` shoots up at closing profiles (flat caps, tips), which
/// would stall a secant on `H − 1`.
fn sq_excess(h: f32) -> f32 {
    (h - 1.0) / (h + 1.0)
}

/// `sq_secant`: the crossing in `[lo, hi]` across which `f` = [`sq_excess`] of the gauge changes
/// sign (`fl`, `fh` its values at the ends, one of them `> 0`, the other `≤ 0`). Regula falsi
/// with the Illinois modification (an end kept twice has its value halved, so both ends close
/// in, superlinearly), never leaving the bracket. It stops when `|f|` is below the gauge's
/// rounding, when the bracket is narrower than `tol`, or after [`SQ_SECANT_MAX`] evaluations;
/// the estimate is always inside the bracket.
#[allow(clippy::too_many_arguments)]
fn sq_secant(
    o: Vec3,
    v: Vec3,
    e: Vec3,
    lo0: f32,
    hi0: f32,
    fl0: f32,
    fh0: f32,
    tol: f32,
    cost: &mut SqCost,
) -> f32 {
    let mut lo = lo0;
    let mut hi = hi0;
    let mut fl = fl0;
    let mut fh = fh0;
    let out_lo = fl0 > 0.0;
    // Which end moved last: 1 lo, −1 hi, 0 none yet.
    let mut side = 0;
    let mut s = 0.5 * (lo + hi);
    for _ in 0..SQ_SECANT_MAX {
        if hi - lo <= tol {
            break;
        }
        s = (hi - fh * (hi - lo) / (fh - fl)).clamp(lo, hi);
        cost.search += 1;
        let f = sq_excess(sq_gauge((o + s * v).abs(), e));
        if f.abs() <= 0.5 * SQ_MARGIN {
            break;
        }
        if (f > 0.0) == out_lo {
            lo = s;
            fl = f;
            if side > 0 {
                fh *= 0.5;
            }
            side = 1;
        } else {
            hi = s;
            fh = f;
            if side < 0 {
                fl *= 0.5;
            }
            side = -1;
        }
    }
    s
}

/// [`sq_first`], also reporting its cost.
pub fn sq_first_cost(o: Vec3, v: Vec3, e: Vec3, s_min: f32, bound: f32) -> (SqHit, SqCost) {
    sq_first_within_cost(o, v, e, s_min, bound, 0.0)
}

/// `sq_first_within`, also reporting its cost: [`sq_first`] with the convex finder stopping at
/// steps up to `tol_min` (local units), for callers that only order hits (the superquadric
/// splats' compute passes, whose `SQ_SPLAT_TOL` it is).
pub fn sq_first_within_cost(
    o: Vec3,
    v: Vec3,
    e: Vec3,
    s_min: f32,
    bound: f32,
    tol_min: f32,
) -> (SqHit, SqCost) {
    let mut cost = SqCost::default();
    let Some(span) = sq_clip(o, v, s_min, bound) else {
        return (MISS, cost);
    };
    let hit = sq_first_in(o, v, e, s_min, span, tol_min, &mut cost);
    (hit, cost)
}

/// No crossing.
const MISS: SqHit = SqHit {
    s: 0.0,
    n: Vec3::Z,
    hit: false,
};

/// `sq_clip`: the stretch `(s_in, s_out)` of `o + s v` with `s ≥ s_min` inside the unit box and
/// inside the ball of radius `bound` about the centre, or `None`.
pub fn sq_clip(o: Vec3, v: Vec3, s_min: f32, bound: f32) -> Option<(f32, f32)> {
    // Slab-clip to the unit box and to s ≥ s_min.
    let ok = v.abs().cmpge(Vec3::splat(SQ_V_MIN));
    if (!ok & o.abs().cmpgt(Vec3::ONE)).any() {
        return None;
    }
    let vs = Vec3::select(ok, v, Vec3::ONE);
    let s1 = (Vec3::splat(-1.0) - o) / vs;
    let s2 = (Vec3::ONE - o) / vs;
    let near = Vec3::select(ok, s1.min(s2), Vec3::splat(-SQ_BIG));
    let far = Vec3::select(ok, s1.max(s2), Vec3::splat(SQ_BIG));
    let mut s_in = s_min.max(near.x.max(near.y.max(near.z)));
    let mut s_out = far.x.min(far.y.min(far.z));
    if !(s_in < s_out && s_out < SQ_BIG) {
        return None;
    }
    // The ball, by the stable roots of the quadratic.
    let qa = v.dot(v);
    let qb = o.dot(v);
    let qc = o.dot(o) - bound * bound;
    let disc = qb * qb - qa * qc;
    // `!(disc >= 0.0)` in the shader: NaN misses too.
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let q = -(qb + select(-1.0, 1.0, qb >= 0.0) * disc.sqrt());
    let r1 = q / qa;
    let r2 = if q != 0.0 { qc / q } else { r1 };
    s_in = s_in.max(r1.min(r2));
    s_out = s_out.min(r1.max(r2));
    if s_in.is_nan() || s_out.is_nan() || s_in >= s_out {
        return None;
    }
    Some((s_in, s_out))
}

/// `sq_first_in`: the first crossing on a stretch `(s_in, s_out)` of the ray that holds it
/// ([`sq_clip`]'s, or one known to hold it); where `s_in` is `s_min` that point may be inside.
pub fn sq_first_in(
    o: Vec3,
    v: Vec3,
    e: Vec3,
    s_min: f32,
    (s_in, s_out): (f32, f32),
    tol_min: f32,
    cost: &mut SqCost,
) -> SqHit {
    let tol = (SQ_TOL / v.length()).max(SQ_ULP * s_in.abs().max(s_out.abs()));
    // Where the span starts at the ray's start, that point may be inside the solid: then the
    // first crossing is the exit.
    let start = s_in == s_min;
    if sq_convex(e) {
        let tol = tol.max(tol_min / v.length());
        let h = sq_newton(o, v, e, s_in, s_out, tol, start, cost);
        return if h.hit { h } else { MISS };
    }
    let mut inside = false;
    if start {
        cost.other += 1;
        inside = sq_contains(o + s_in * v, e);
    }
    let (s, hit) = sq_search(o, v, e, s_in, s_out, tol, inside, cost);
    if !hit {
        return MISS;
    }
    cost.other += 1;
    SqHit {
        s,
        n: sq_normal(o + s * v, e),
        hit: true,
    }
}

/// First crossing of the ray `o + s v` (local unit coordinates; `v` need not be unit: the
/// tolerance in `s` is [`SQ_TOL`]` / |v|`) with `s ≥ s_min`: the entry, or, when `o + s_min v` is
/// inside the solid, the exit. `hit = false`: no crossing. The caller should put `o` next to the
/// glyph, as the reference does: the tolerance grows with `|s|` ([`SQ_ULP`]).
pub fn sq_first(o: Vec3, v: Vec3, e: Vec3, s_min: f32) -> SqHit {
    sq_first_cost(o, v, e, s_min, sq_bound(e)).0
}
