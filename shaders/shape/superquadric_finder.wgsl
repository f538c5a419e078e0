// The superquadric ray–surface root finder (docs/book/src/developer/superquadric-derivation.md
// §6), functions only; composed after common.wgsl. Mirrored line by line in f32 by
// src/twin/superquadric.rs, whose tests judge it against the exact f64 reference
// (src/reference/superquadric.rs).
//
// Local unit coordinates: the solid is |z| <= 1, (|x|/R_β(z))^(2/α) + (|y|/R_c(z))^(2/α) <= 1,
// R_e(z) = (1 − |z|^(2/e))^(e/2), with exponents e = (α, β, c) in (0, 5]; it lies in [−1, 1]³.
// Two finders:
//
// - Convex glyphs (α <= 2, β <= 2, c = β): Newton on g(s) − 1, g(s) = G(o + s v) the norm
//   G = N_β(N_α(|x|, |y|), |z|), from the box entry. g is convex along the ray, so a Newton step
//   from where g > 1 lands at or before the first root (the tangent lies below g): the iterates
//   climb to the root, quadratically for a transversal crossing, linearly at tangency, and
//   g' >= 0 while g > 1 proves a miss. From inside, the same backwards from the box exit. Any
//   subgradient keeps this, so the kinks of G on the mirror planes (components 0) are safe.
// - Other glyphs (pinched β > 2, α > 2 or c ≠ β): the gauge is non-decreasing in |x|, |y|, |z|,
//   so over a stretch of ray it is bounded by its values at the smallest and largest absolute
//   coordinates. Branch and bound, depth-first and left to right over the halvings of the span,
//   without a stack: every skipped stretch is certified empty, so the first surviving one holds
//   the first crossing. At SQ_BRACKET width a sign change across the node is finished by a
//   safeguarded secant.
//
// Powers go through exp2(q log2 x) with x <= 1; log2 0 is never taken (select gives the limit)
// and no infinity is formed (WGSL lets implementations assume there are none). Exponents are
// floored at SQ_EXP_MIN, so 2/e <= 2e30 and (2/e) log2 x stays finite.

// Newton iterations (convex). Transversal crossings take 1–6, a tangent ray about 20. At the cap:
// entry → miss (the iterates are still before any root: a pixel-thin sliver at tangency is
// dropped); exit → the last iterate (between the exit and the box exit).
const SQ_NEWTON_MAX: u32 = 24u;
// Gauge evaluations of the branch and bound (non-convex): one per node, two more per look for a
// sign change. Transversal crossings take 10–40; a ray skimming the surface at clearance δ keeps
// about 1/δ nodes per unit length alive (first-order bounds). At the cap everything before the
// current node is certified; the rest of the ray is then sampled (SQ_SAMPLES, SQ_GROWTH,
// SQ_PARTS) and the first sign change refined, no longer certified.
const SQ_BOUND_MAX: u32 = 128u;
// Tolerance along the ray in local unit coordinates (the box is [−1, 1]³): Newton stops when its
// step is shorter, the branch and bound when its node is narrower.
const SQ_TOL: f32 = 4e-6;
// The tolerance is at least this multiple of |s| (two f32 ulps), so steps stay resolvable.
const SQ_ULP: f32 = 2.4e-7;
// Depth of the branch and bound's tree (grid points s_a + i w exact for i < 2^24); the
// tolerance is reached first (span / tol <= 2√3 / SQ_TOL < 2^20).
const SQ_DEPTH_MAX: u32 = 24u;
// Node width (local units along the ray) at which a sign change across the node is refined by the
// secant: its crossing, the first unless the ray crosses the surface more than once within it.
const SQ_BRACKET: f32 = 1e-3;
// At the cap: at most SQ_SAMPLES samples of the rest of the ray, the steps growing from the node's
// width by SQ_GROWTH to at most 1/SQ_PARTS of the rest.
const SQ_SAMPLES: u32 = 40u;
const SQ_GROWTH: f32 = 1.5;
const SQ_PARTS: f32 = 16.0;
// Gauge evaluations of the secant.
const SQ_SECANT_MAX: u32 = 16u;
// Slack of the bound tests (units of the gauge): its f32 rounding.
const SQ_MARGIN: f32 = 1e-6;
// Exponents are at least this.
const SQ_EXP_MIN: f32 = 1e-30;
// Arguments of log2 are at least this (a normal f32).
const SQ_TINY: f32 = 1e-37;
// The gauge where the profile has closed ("certainly outside"); the slab test's open end.
const SQ_BIG: f32 = 1e30;
// The log of a derivative that is exactly 0 (only ever summed, never multiplied).
const SQ_NEG: f32 = -1e36;
// Ray components below this are 0 to the slab test.
const SQ_V_MIN: f32 = 1e-30;

// First crossing of the ray o + s v (local unit coordinates; v need not be unit) with s >= s_min:
// the entry, or, when o + s_min v is inside the solid, the exit. hit = false: no crossing (miss).
// n: unit direction of the inside–outside function's gradient (local; map with the inverse
// transpose).
struct SqHit {
    s: f32,
    n: vec3<f32>,
    hit: bool,
}

// x^y for 0 <= x <= 1, y > 0 (0^y = 0).
fn sq_pow(x: f32, y: f32) -> f32 {
    return select(exp2(y * log2(max(x, SQ_TINY))), 0.0, x <= 0.0);
}

// (N, log2 ∂N/∂a, log2 ∂N/∂b) of N_e(a, b) = (a^(2/e) + b^(2/e))^(e/2), a, b >= 0 (SQ_NEG for a
// derivative of 0); N = hi (1 + r)^(1/p), r = (lo/hi)^p <= 1: no overflow for p = 2/e <= 2e30.
fn sq_pnorm_log(a: f32, b: f32, e: f32) -> vec3<f32> {
    let hi = max(a, b);
    let lo = min(a, b);
    if hi <= 0.0 {
        return vec3<f32>(0.0, SQ_NEG, SQ_NEG);
    }
    let p = 2.0 / max(e, SQ_EXP_MIN);
    let l = log2(max(lo / hi, SQ_TINY));
    let r = select(exp2(p * l), 0.0, lo <= 0.0);
    // No log1p in WGSL: the absolute error of log2(1 + r), an ulp of 1, is divided by p >= 0.4.
    let k = log2(1.0 + r);
    let n = hi * exp2(k / p);
    // (hi/N)^(p−1) = (1 + r)^(1/p − 1); (lo/N)^(p−1) = (lo/hi)^(p−1) (hi/N)^(p−1).
    let g_hi = k * (1.0 / p - 1.0);
    let g_lo = select((p - 1.0) * l + g_hi, SQ_NEG, lo <= 0.0);
    if a >= b {
        return vec3<f32>(n, g_hi, g_lo);
    }
    return vec3<f32>(n, g_lo, g_hi);
}

// N_e(a, b) alone.
fn sq_pnorm(a: f32, b: f32, e: f32) -> f32 {
    let hi = max(a, b);
    let lo = min(a, b);
    if hi <= 0.0 {
        return 0.0;
    }
    let p = 2.0 / max(e, SQ_EXP_MIN);
    let r = sq_pow(lo / hi, p);
    return hi * exp2(log2(1.0 + r) / p);
}

// R_e(z) = (1 − z^(2/e))^(e/2), 0 <= z <= 1 (R(0) = 1, R(1) = 0). 1 − z^q cancels next to the
// tips (no expm1): an ulp of 1, which moves the surface there by about that much along z.
fn sq_profile(z: f32, e: f32) -> f32 {
    let q = 2.0 / max(e, SQ_EXP_MIN);
    let rest = 1.0 - sq_pow(z, q);
    return select(exp2(log2(max(rest, SQ_TINY)) / q), 0.0, rest <= 0.0);
}

// (G, log2 ∂G/∂a) of Barr's norm G = N_β(N_α(|x|, |y|), |z|) at absolute coordinates a.
fn sq_norm_log(a: vec3<f32>, e: vec3<f32>) -> vec4<f32> {
    let n1 = sq_pnorm_log(a.x, a.y, e.x);
    let n2 = sq_pnorm_log(n1.x, a.z, e.y);
    return vec4<f32>(n2.x, n2.y + n1.y, n2.y + n1.z, n2.z);
}

// (N, ∂N/∂a, ∂N/∂b) of N_e(a, b) for e <= 2 (p = 2/e >= 1, the convex case), a, b >= 0, the
// derivatives without logs of their own: with r = (lo/hi)^p, (hi/N)^p = 1/(1 + r), so
// ∂N/∂hi = (hi/N)^(p−1) = (N/hi)/(1 + r) in [1/2, 1], and ∂N/∂lo = (lo/hi)^(p−1) ∂N/∂hi =
// (r/(lo/hi)) ∂N/∂hi <= 1 (lo/hi clamped as r is). Four transcendentals, as N alone.
fn sq_pnorm_grad(a: f32, b: f32, e: f32) -> vec3<f32> {
    let hi = max(a, b);
    let lo = min(a, b);
    if hi <= 0.0 {
        return vec3<f32>(0.0, 0.0, 0.0);
    }
    let p = 2.0 / max(e, SQ_EXP_MIN);
    let ratio = max(lo / hi, SQ_TINY);
    let r = select(exp2(p * log2(ratio)), 0.0, lo <= 0.0);
    let grow = exp2(log2(1.0 + r) / p);
    let d_hi = grow / (1.0 + r);
    let d_lo = (r / ratio) * d_hi;
    if a >= b {
        return vec3<f32>(hi * grow, d_hi, d_lo);
    }
    return vec3<f32>(hi * grow, d_lo, d_hi);
}

// (G, ∇G) of Barr's norm at absolute coordinates a, convex glyphs: 8 transcendentals.
fn sq_norm_grad(a: vec3<f32>, e: vec3<f32>) -> vec4<f32> {
    let n1 = sq_pnorm_grad(a.x, a.y, e.x);
    let n2 = sq_pnorm_grad(n1.x, a.z, e.y);
    return vec4<f32>(n2.x, n2.y * n1.y, n2.y * n1.z, n2.z);
}

// Inside–outside function of absolute coordinates, <= 1 exactly on the solid and non-decreasing
// in each argument: G when c = β (no profile, no cancellation at the tips), else
// H = N_α(|x|/R_β(z), |y|/R_c(z)) (SQ_BIG where |z| >= 1 off the axis). Without SQ_GENERAL every
// glyph is convex (c = β): the test folds away, and with it H, which a CPU device would otherwise
// run under a mask (the eye test of every glyph).
fn sq_gauge(a: vec3<f32>, e: vec3<f32>) -> f32 {
    if !SQ_GENERAL || e.z == e.y {
        return sq_pnorm(sq_pnorm(a.x, a.y, e.x), a.z, e.y);
    }
    if a.z >= 1.0 {
        return select(SQ_BIG, 1.0, a.z == 1.0 && a.x == 0.0 && a.y == 0.0);
    }
    // a / R with 0 / 0 = 0 on the axis, at most SQ_BIG where the profile has closed.
    let u = min(a.x / max(sq_profile(a.z, e.y), SQ_TINY), SQ_BIG);
    let w = min(a.y / max(sq_profile(a.z, e.z), SQ_TINY), SQ_BIG);
    return sq_pnorm(u, w, e.x);
}

// The point p (local unit coordinates) is in the solid.
fn sq_contains(p: vec3<f32>, e: vec3<f32>) -> bool {
    return sq_gauge(abs(p), e) <= 1.0;
}

// Convex solid, G a norm.
fn sq_convex(e: vec3<f32>) -> bool {
    return e.x <= 2.0 && e.y <= 2.0 && e.z == e.y;
}

// log2(2^a + 2^b).
fn sq_log_add(a: f32, b: f32) -> f32 {
    let hi = max(a, b);
    let lo = min(a, b);
    return hi + log2(1.0 + exp2(lo - hi));
}

// Logs of the components of ∇H at absolute coordinates a (c ≠ β;
// docs/book/src/developer/superquadric-derivation.md §4):
// ∂H/∂x = A/R_β, ∂H/∂y = B/R_c, ∂H/∂|z| = A u (|z|/R_β)^(2/β − 1)/R_β + B w (|z|/R_c)^(2/c − 1)/R_c.
// At the poles and where the profile has closed (tips) the axis.
fn sq_gauge_grad_log(a: vec3<f32>, e: vec3<f32>) -> vec3<f32> {
    let pole = vec3<f32>(SQ_NEG, SQ_NEG, 0.0);
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
    let qb = 2.0 / max(e.y, SQ_EXP_MIN) - 1.0;
    let qc = 2.0 / max(e.z, SQ_EXP_MIN) - 1.0;
    let lz_b = select(
        h.y + log2(max(u, SQ_TINY)) + qb * log2(max(a.z / rb, SQ_TINY)) - lrb,
        SQ_NEG,
        a.x <= 0.0 || a.z <= 0.0,
    );
    let lz_c = select(
        h.z + log2(max(w, SQ_TINY)) + qc * log2(max(a.z / rc, SQ_TINY)) - lrc,
        SQ_NEG,
        a.y <= 0.0 || a.z <= 0.0,
    );
    return vec3<f32>(lx, ly, sq_log_add(lz_b, lz_c));
}

// n normalised, or +z where it is 0 (only at the centre, never on the surface).
fn sq_unit(n: vec3<f32>) -> vec3<f32> {
    if dot(n, n) <= 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return normalize(n);
}

// Unit direction of the gauge's gradient at q, never zero or NaN: logs scaled by the largest (no
// over- or underflow for 2/β = 2e20); a coordinate exactly 0 gives a component 0 (the
// mirror-symmetric limit, also at ridges and tips).
fn sq_normal(q: vec3<f32>, e: vec3<f32>) -> vec3<f32> {
    let a = abs(q);
    var l: vec3<f32>;
    if e.z == e.y {
        let g = sq_norm_log(a, e);
        l = g.yzw;
    } else {
        l = sq_gauge_grad_log(a, e);
    }
    let m = max(l.x, max(l.y, l.z));
    return sq_unit(sign(q) * exp2(l - vec3<f32>(m)));
}

// The convex finder on [s_a, s_b]: the entry forward from s_a, or, when s_a is the ray's start
// (may_start_inside) and lies in the solid, the exit backward from s_b. The normal is the gradient at the last point evaluated (the hit, or within tol of it).
fn sq_newton(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_a: f32, s_b: f32, tol: f32, may_start_inside: bool) -> SqHit {
    var inside = false;
    var dir = 1.0;
    var s_far = s_b;
    var s = s_a;
    // ∇G at the last point evaluated (ratios <= 1 to powers >= 0; |∇G| >= G/|q| > 0).
    var grad = vec3<f32>(0.0, 0.0, 1.0);
    for (var k = 0u; k < SQ_NEWTON_MAX; k++) {
        let q = o + s * v;
        let g = sq_norm_grad(abs(q), e);
        grad = sign(q) * g.yzw;
        // On or in the solid: a box face on the surface, or rounding a hair past the root.
        if g.x <= 1.0 {
            // The ray starts in the solid (its first point is the ray's own start): the exit,
            // backwards from the far end. Testing here costs no evaluation of its own.
            if k == 0u && may_start_inside {
                inside = true;
                dir = -1.0;
                s_far = s_a;
                s = s_b;
                continue;
            }
            return SqHit(s, sq_unit(grad), true);
        }
        // A subgradient of g along the ray.
        let slope = dot(grad, v);
        // g > 1 and not decreasing towards the far end: no root ahead (from inside: rounding at
        // the box exit, where the surface is).
        if dir * slope >= 0.0 {
            return SqHit(s, sq_unit(grad), inside);
        }
        let step = (1.0 - g.x) / slope;
        // Beyond the far end: the tangent, below g, stays above 1 over the box.
        if dir * (s + step - s_far) >= 0.0 {
            return SqHit(s_far, sq_unit(grad), inside);
        }
        s += step;
        if abs(step) <= tol {
            return SqHit(s, sq_unit(grad), true);
        }
    }
    // Cap: the entry is a miss; the exit the last iterate.
    return SqHit(s, sq_unit(grad), inside);
}

// (h − 1)/(h + 1): the sign of h − 1, bounded where H shoots up at closing profiles.
fn sq_excess(h: f32) -> f32 {
    return (h - 1.0) / (h + 1.0);
}

// The crossing in [lo, hi] across which f = sq_excess(gauge) changes sign (fl, fh its values at
// the ends): regula falsi with the Illinois modification, never leaving the bracket. Stops when
// |f| is below the gauge's rounding, the bracket below tol, or after SQ_SECANT_MAX evaluations.
fn sq_secant(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, lo0: f32, hi0: f32, fl0: f32, fh0: f32, tol: f32) -> f32 {
    var lo = lo0;
    var hi = hi0;
    var fl = fl0;
    var fh = fh0;
    let out_lo = fl0 > 0.0;
    // Which end moved last: 1 lo, −1 hi, 0 none yet.
    var side = 0;
    var s = 0.5 * (lo + hi);
    for (var k = 0u; k < SQ_SECANT_MAX; k++) {
        if hi - lo <= tol {
            break;
        }
        s = clamp(hi - fh * (hi - lo) / (fh - fl), lo, hi);
        let f = sq_excess(sq_gauge(abs(o + s * v), e));
        if abs(f) <= 0.5 * SQ_MARGIN {
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
    return s;
}

// The branch and bound on [s_a, s_b]: the first possibly-inside point (entry) or (inside) the
// first possibly-outside point (exit); (s, 1) found, (_, 0) none. Node i at depth d is
// [s_a + i w, s_a + (i + 1) w], w = span / 2^d; a node that may hold the surface is split (left
// child next), one certified empty is skipped for its right sibling, or for a right child the
// right sibling of its nearest ancestor that is a left child. Adjacent nodes share the rounding
// of their common grid point, so the skipped nodes cover [s_a, lo] without gaps.
fn sq_search(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_a: f32, s_b: f32, tol: f32, inside: bool) -> vec2<f32> {
    var w = s_b - s_a;
    let wb = SQ_BRACKET / length(v);
    var i = 0u;
    var d = 0u;
    // Gauge evaluations so far (one per node, two more per look for a sign change).
    var evals = 0u;
    while evals < SQ_BOUND_MAX {
        evals += 1u;
        let lo = s_a + f32(i) * w;
        let hi = s_a + f32(i + 1u) * w;
        let q_lo = o + lo * v;
        let q_hi = o + hi * v;
        // Range of |q_k| over the node: from 0 where q_k changes sign.
        let a_max = max(abs(q_lo), abs(q_hi));
        let cross = q_lo * q_hi <= vec3<f32>(0.0);
        let a_min = select(min(abs(q_lo), abs(q_hi)), vec3<f32>(0.0), cross);
        var possible: bool;
        if inside {
            possible = sq_gauge(a_max, e) >= 1.0 - SQ_MARGIN;
        } else {
            possible = sq_gauge(a_min, e) <= 1.0 + SQ_MARGIN;
        }
        if possible {
            // The first node at most SQ_BRACKET wide: a sign change across it → the secant.
            if w <= wb && (2.0 * w > wb || d == 0u) {
                evals += 2u;
                let fl = sq_excess(sq_gauge(abs(q_lo), e));
                let fh = sq_excess(sq_gauge(abs(q_hi), e));
                // The sought side already at lo: only where lo = s_a (a box face on the surface).
                if (fl > 0.0) == inside {
                    return vec2<f32>(lo, 1.0);
                }
                if (fh > 0.0) == inside {
                    return vec2<f32>(sq_secant(o, v, e, lo, hi, fl, fh, tol), 1.0);
                }
            }
            if w <= tol || d >= SQ_DEPTH_MAX {
                return vec2<f32>(0.5 * (lo + hi), 1.0);
            }
            w *= 0.5;
            i *= 2u;
            d += 1u;
        } else {
            i += 1u;
            while d > 0u && (i & 1u) == 0u {
                i >>= 1u;
                d -= 1u;
                w *= 2.0;
            }
            if d == 0u {
                // The whole span is certified: no crossing (from inside: the box exit).
                return vec2<f32>(s_b, select(0.0, 1.0, inside));
            }
        }
    }
    // Cap: everything before lo is certified. The rest sampled, steps growing from the node's
    // width by SQ_GROWTH up to 1/SQ_PARTS of the rest, and the first change to the sought side
    // (inside for an entry, outside for an exit) refined (not certified).
    let lo = s_a + f32(i) * w;
    let coarse = (s_b - lo) / SQ_PARTS;
    var step = min(w, coarse);
    var s0 = lo;
    var f0 = sq_excess(sq_gauge(abs(o + s0 * v), e));
    if (f0 > 0.0) == inside {
        return vec2<f32>(s0, 1.0);
    }
    for (var k = 0u; k < SQ_SAMPLES; k++) {
        let s1 = min(s0 + step, s_b);
        let f1 = sq_excess(sq_gauge(abs(o + s1 * v), e));
        if (f1 > 0.0) == inside {
            return vec2<f32>(sq_secant(o, v, e, s0, s1, f0, f1, tol), 1.0);
        }
        if s1 >= s_b {
            break;
        }
        s0 = s1;
        f0 = f1;
        step = min(step * SQ_GROWTH, coarse);
    }
    // No change: an entry misses, an exit leaves through the box.
    return vec2<f32>(s_b, select(0.0, 1.0, inside));
}

// Whether the pipeline may meet non-convex glyphs (pinched or c ≠ β: indefinite tensors). The
// renderer sets it per chunk of glyphs; false removes their search from the shader, which a CPU
// device such as lavapipe would otherwise run under a mask for every fragment.
override SQ_GENERAL: bool = true;

// A hair beyond the solid's farthest point, so that f32 rounding cannot put the surface outside
// the ball (BOUND_MARGIN in src/glyph/superquadric.rs).
const SQ_BOUND_MARGIN: f32 = 1.0001;

// bounding_scale in src/glyph/superquadric.rs (times SQ_BOUND_MARGIN): the radius, in local unit
// coordinates, of a ball about the centre holding the solid of exponents e (1 for an ellipsoid,
// √2 for a cylinder, √3 for a box).
fn sq_bound(e: vec3<f32>) -> f32 {
    let beta = min(e.y, e.z);
    let m = max(exp2(1.0 - e.x), 1.0);
    var s2 = m;
    if beta < 1.0 {
        let k = 1.0 - beta;
        s2 = m * exp2(k * log2(1.0 + exp2(-log2(m) / k)));
    }
    return min(sqrt(s2), 1.7320508) * SQ_BOUND_MARGIN;
}

// First crossing of o + s v with s >= s_min (see SqHit); `bound` is sq_bound(e) (computed once
// per glyph by the caller). The caller should put o next to the glyph (as the reference does):
// the tolerance grows with |s| (SQ_ULP).
fn sq_first(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_min: f32, bound: f32) -> SqHit {
    return sq_first_within(o, v, e, s_min, bound, 0.0);
}

// sq_first with the convex finder stopping at steps up to tol_min (local units), for callers
// that only order hits: a transversal crossing is still found to about tol_min² (Newton
// converges quadratically from the outside, so the iterate stays before it), and a ray that
// misses by a clearance δ is taken for a hit only where δ is below about tol_min² (its steps
// stay above √δ). The search of the other glyphs keeps its tolerance.
fn sq_first_within(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_min: f32, bound: f32, tol_min: f32) -> SqHit {
    let span = sq_clip(o, v, s_min, bound);
    if span.z == 0.0 {
        return SqHit(0.0, vec3<f32>(0.0, 0.0, 1.0), false);
    }
    return sq_first_in(o, v, e, s_min, span.xy, tol_min);
}

// The stretch (s_in, s_out, 1) of o + s v with s >= s_min inside the unit box and inside the
// ball of radius `bound` about the centre, or (0, 0, 0) when there is none: a ray past them
// misses without an evaluation, and a search starts next to the surface.
fn sq_clip(o: vec3<f32>, v: vec3<f32>, s_min: f32, bound: f32) -> vec3<f32> {
    let none = vec3<f32>(0.0);
    // Slab-clip to the unit box and to s >= s_min.
    let ok = abs(v) >= vec3<f32>(SQ_V_MIN);
    if any(!ok & (abs(o) > vec3<f32>(1.0))) {
        return none;
    }
    let vs = select(vec3<f32>(1.0), v, ok);
    let s1 = (vec3<f32>(-1.0) - o) / vs;
    let s2 = (vec3<f32>(1.0) - o) / vs;
    let near = select(vec3<f32>(-SQ_BIG), min(s1, s2), ok);
    let far = select(vec3<f32>(SQ_BIG), max(s1, s2), ok);
    var s_in = max(s_min, max(near.x, max(near.y, near.z)));
    var s_out = min(far.x, min(far.y, far.z));
    if !(s_in < s_out && s_out < SQ_BIG) {
        return none;
    }
    // The ball, by the stable roots of the quadratic.
    let qa = dot(v, v);
    let qb = dot(o, v);
    let qc = dot(o, o) - bound * bound;
    let disc = qb * qb - qa * qc;
    if !(disc >= 0.0) {
        return none;
    }
    let q = -(qb + select(-1.0, 1.0, qb >= 0.0) * sqrt(disc));
    var r1 = q / qa;
    var r2 = r1;
    if q != 0.0 {
        r2 = qc / q;
    }
    s_in = max(s_in, min(r1, r2));
    s_out = min(s_out, max(r1, r2));
    if !(s_in < s_out) {
        return none;
    }
    return vec3<f32>(s_in, s_out, 1.0);
}

// sq_first_within on a stretch `span` = (s_in, s_out) of the ray that holds its first crossing
// (sq_clip's, or one known to hold it); where s_in is s_min that point may be inside the solid.
fn sq_first_in(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_min: f32, span: vec2<f32>, tol_min: f32) -> SqHit {
    let miss = SqHit(0.0, vec3<f32>(0.0, 0.0, 1.0), false);
    let s_in = span.x;
    let s_out = span.y;
    let tol = max(SQ_TOL / length(v), SQ_ULP * max(abs(s_in), abs(s_out)));
    // Where the span starts at the ray's start, that point may be inside the solid: then the
    // first crossing is the exit.
    let start = s_in == s_min;
    if !SQ_GENERAL || sq_convex(e) {
        let h = sq_newton(o, v, e, s_in, s_out, max(tol, tol_min / length(v)), start);
        if h.hit {
            return h;
        }
        return miss;
    }
    var inside = false;
    if start {
        inside = sq_contains(o + s_in * v, e);
    }
    let r = sq_search(o, v, e, s_in, s_out, tol, inside);
    if r.y == 0.0 {
        return miss;
    }
    return SqHit(r.x, sq_normal(o + r.x * v, e), true);
}
