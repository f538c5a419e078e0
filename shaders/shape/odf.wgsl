// ODF glyphs, the shape interface of common.wgsl: the radial surface r(u) = max(f(u), 0) in
// parameter space p~ = Oᵀ (p − c) / R, where it lies in the unit ball (R: the largest radius;
// a series glyph's O is its own axes and its radii its bounding ellipsoid's semi-axes). f is a
// tensor's profile Σ aᵢ uᵢ² (aᵢ = rᵢ / R) or a spherical-harmonic series in the plain basis,
// read from the chunk's shape buffer past its per-glyph words (src/shape/odf/ derives both,
// the bounds, the ellipsoid and the crossing; the upload in src/render/scene_buffers.rs lays
// the buffer out). Twin: src/twin/odf.rs; the f64 crossing: shape::odf::plane_crossing.
//
// The shape vector: x = 0 (profile) or 4 (series), plus the colouring (0 the instance's colour,
// 1 direction, 2 amplitude: word 1's flags, OdfColoring in src/shape/odf/mod.rs); a profile then
// holds (a₁, a₂, a₃), a series (its first word's index, G, lmax).

// The smallest step in the ray plane's angle (GPU_STEP in src/shape/odf/mod.rs), the step cap,
// and the most (a, b) pairs of a great circle's series: lmax ≤ 30 (MAX_LMAX in src/sh).
const ODF_STEP: f32 = 3.0517578e-5;
const ODF_STEPS: u32 = 256u;
const ODF_TERMS: u32 = 16u;
const ODF_PI: f32 = 3.14159265358979;

fn shape_radius(radii: vec3<f32>) -> f32 {
    return max(radii.x, max(radii.y, radii.z));
}

fn shape_of(g: Glyph, ii: u32) -> Solid {
    let w = load_shape_words(ii);
    let big = shape_radius(g.radii);
    // Direction wins over amplitude, as OdfColoring::of_flags.
    let colour = select(f32(w.y & 2u), 1.0, (w.y & 1u) != 0u);
    var shape = vec4<f32>(colour, g.radii / big);
    var bound = vec3<f32>(1.0);
    if w.x != 0u {
        shape = vec4<f32>(4.0 + colour, f32(w.x), bitcast<f32>(shapes[w.x].x), f32((w.y >> 8u) & 0xffu));
        // A series glyph's radii are its bounding ellipsoid's semi-axes (src/shape/odf/bound.rs).
        bound = g.radii / big;
    }
    return Solid(vec3<f32>(big), bound, shape);
}

// Float k of the series whose first word is `start` (k = 0: G; then the coefficients).
fn odf_word(start: u32, k: u32) -> f32 {
    return bitcast<f32>(shapes[start + (k >> 1u)][k & 1u]);
}

// The words of a series past its coefficients (Payload in src/shape/odf/mod.rs): k = 0 its
// amplitude scale, 1–4 the rotation from the glyph's axes to the series', 5–7 its bounding
// ellipsoid's semi-axes over R.
fn odf_tail(shape: vec4<f32>, k: u32) -> f32 {
    let lmax = u32(shape.w);
    return odf_word(u32(shape.y), 1u + (lmax + 1u) * (lmax + 2u) / 2u + k);
}

// The rotation taking the glyph's axes to its series' (identity for a tensor's profile).
fn odf_rotation(shape: vec4<f32>) -> mat3x3<f32> {
    if shape.x < 3.5 {
        return mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    }
    return quat_to_mat3(vec4<f32>(odf_tail(shape, 1u), odf_tail(shape, 2u), odf_tail(shape, 3u), odf_tail(shape, 4u)));
}

// f~(u) (x) and the gradient of its polynomial extension (yzw), u unit in the glyph's axes
// (Profile::value_gradient in src/shape/odf/mod.rs).
fn odf_eval(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
    if shape.x < 3.5 {
        let a = shape.yzw;
        return vec4<f32>(dot(a * u, u), 2.0 * a * u);
    }
    let rot = odf_rotation(shape);
    let e = odf_series(rot * u, shape, want_grad);
    return vec4<f32>(e.x, transpose(rot) * e.yzw);
}

// The plain series at unit u in its own axes and its gradient there (plain_value_gradient in
// src/shape/odf/series.rs, term by term).
fn odf_series(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
    let start = u32(shape.y);
    let lmax = u32(shape.w);
    var f = 0.0;
    var grad = vec3<f32>(0.0);
    var c = 1.0;
    var s = 0.0;
    var c1 = 0.0;
    var s1 = 0.0;
    // Λ_0^0. The recurrence's constants are computed, not looked up: lavapipe copies a constant
    // array indexed at run time out at every access (a table of them made frames 20x slower).
    var seed = 0.28209479;
    for (var m = 0u; m <= lmax; m++) {
        let mf = f32(m);
        if m > 0u {
            seed *= sqrt((2.0 * mf + 1.0) / (2.0 * mf));
            c1 = c;
            s1 = s;
            let cn = u.x * c - u.y * s;
            s = u.x * s + u.y * c;
            c = cn;
        }
        var q2 = 0.0;
        var d2 = 0.0;
        var q1 = seed;
        var d1 = 0.0;
        for (var l = m; l <= lmax; l++) {
            if l > m {
                let lf = f32(l);
                var a = sqrt(2.0 * mf + 3.0);
                var bb = 0.0;
                if l > m + 1u {
                    a = sqrt((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf));
                    bb = sqrt(((lf - 1.0) * (lf - 1.0) - mf * mf) / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0));
                }
                let q0 = a * (u.z * q1 - bb * q2);
                let d0 = a * (q1 + u.z * d1 - bb * d2);
                q2 = q1;
                d2 = d1;
                q1 = q0;
                d1 = d0;
            }
            if (l & 1u) != 0u {
                continue;
            }
            let base = l * (l + 1u) / 2u;
            let pc = odf_word(start, 1u + base + m);
            f += pc * q1 * c;
            if want_grad {
                grad += pc * vec3<f32>(q1 * mf * c1, -q1 * mf * s1, d1 * c);
            }
            if m > 0u {
                let ps = odf_word(start, 1u + base - m);
                f += ps * q1 * s;
                if want_grad {
                    grad += ps * vec3<f32>(q1 * mf * s1, q1 * mf * c1, d1 * s);
                }
            }
        }
    }
    return vec4<f32>(f, grad);
}

// The outward normal (not unit) at surface point q: r u − ∇_S f~ (normal_at in src/shape/odf/crossing.rs).
fn odf_normal(q: vec3<f32>, shape: vec4<f32>) -> vec3<f32> {
    let n = length(q);
    if n == 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let u = q / n;
    let e = odf_eval(u, shape, true);
    let tangential = e.yzw - dot(e.yzw, u) * u;
    return max(e.x, 0.0) * u - tangential;
}

struct OdfHit {
    hit: bool,
    t: f32,
    n: vec3<f32>,
}

// The series' degree L: 2 for a tensor's profile.
fn odf_degree(shape: vec4<f32>) -> u32 {
    if shape.x < 3.5 {
        return 2u;
    }
    return u32(shape.w);
}

// g(φ) and g′(φ) of the great circle's series (CircleSeries::value_slope in
// src/shape/odf/crossing.rs), from cos φ and sin φ.
fn odf_circle(c: ptr<function, array<vec2<f32>, ODF_TERMS>>, terms: u32, cs: vec2<f32>) -> vec2<f32> {
    let c2 = cs.x * cs.x - cs.y * cs.y;
    let s2 = 2.0 * cs.x * cs.y;
    var w = vec2<f32>(1.0, 0.0);
    var g = 0.0;
    var gp = 0.0;
    for (var j = 0u; j < terms; j++) {
        if j > 0u {
            w = vec2<f32>(w.x * c2 - w.y * s2, w.y * c2 + w.x * s2);
        }
        let ab = (*c)[j];
        g += ab.x * w.x + ab.y * w.y;
        gp += 2.0 * f32(j) * (ab.y * w.x - ab.x * w.y);
    }
    return vec2<f32>(g, gp);
}

// H = g(mθ) sin θ − b and its slope in θ, at the angle θ from the ray's axis on the side m
// (plane_crossing's halves in src/shape/odf/crossing.rs).
fn odf_big_h(c: ptr<function, array<vec2<f32>, ODF_TERMS>>, terms: u32, m: f32, th: f32, b: f32) -> vec2<f32> {
    let cs = vec2<f32>(cos(th), sin(th));
    let g = odf_circle(c, terms, vec2<f32>(cs.x, m * cs.y));
    return vec2<f32>(g.x * cs.y - b, m * g.y * cs.y + g.x * cs.x);
}

// The crossing of o + t v nearest its start at t > t_min, in the ray's plane (plane_crossing in
// src/shape/odf/crossing.rs, whose module doc derives it): the series on the plane's great
// circle from L + 1 values, the sign change of H = g sin φ − b approached by safe steps, refined
// by Newton's method in its bracket, and the point r u on the surface in the crossing's direction.
fn odf_first(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> OdfHit {
    var res: OdfHit;
    let vl = length(v);
    let d = v / vl;
    let sc = -dot(o, d);
    // s is measured from the line's point nearest the centre.
    let near = o + sc * d;
    let b2 = dot(near, near);
    if !(b2 < 1.0) {
        return res;
    }
    let b = sqrt(b2);
    let half = sqrt(1.0 - b2);
    let start = max(-half, t_min * vl - sc);
    if !(start < half) {
        return res;
    }
    let on_ball = start == -half;
    if b < 1e-30 {
        // Through the centre: the glyph spans ±r along the ray.
        let r = max(odf_eval(d, shape, false).x, 0.0);
        var s = r;
        if r > 0.0 && (start < -r || (on_ball && start <= -r)) {
            s = -r;
        } else if !(r > 0.0 && start < r) {
            return res;
        }
        res.hit = true;
        res.t = (s + sc) / vl;
        res.n = odf_normal(s * d, shape);
        return res;
    }
    var first = start;
    var last = half;
    if shape.x > 3.5 {
        // Only where the ray crosses the glyph's bounding ellipsoid (a cheap miss for the rest of
        // its quad or box): the ray scaled by the semi-axes against the unit ball.
        let inv = 1.0 / vec3<f32>(odf_tail(shape, 5u), odf_tail(shape, 6u), odf_tail(shape, 7u));
        let ne = near * inv;
        let de = d * inv;
        let aa = dot(de, de);
        let bb = dot(ne, de);
        let disc = bb * bb - aa * (dot(ne, ne) - 1.0);
        if !(disc > 0.0) {
            return res;
        }
        let q = sqrt(disc);
        first = max(first, (-bb - q) / aa);
        last = min(last, (-bb + q) / aa);
        if !(first < last) {
            return res;
        }
    }
    let e2 = near / b;
    // The great circle's series, in the series' own axes: the DFT of L + 1 values at
    // φᵢ = iπ/(L+1) as a function of 2φ.
    let n = odf_degree(shape) + 1u;
    let terms = (n + 1u) / 2u;
    var c: array<vec2<f32>, ODF_TERMS>;
    let rot = odf_rotation(shape);
    let ds = rot * d;
    let e2s = rot * e2;
    for (var i = 0u; i < n; i++) {
        let psi = ODF_PI * f32(i) / f32(n);
        let us = cos(psi) * ds + sin(psi) * e2s;
        var g = 0.0;
        if shape.x < 3.5 {
            g = odf_eval(us, shape, false).x;
        } else {
            g = odf_series(us, shape, false).x;
        }
        let theta = 2.0 * psi;
        let rot = vec2<f32>(cos(theta), sin(theta));
        var w = vec2<f32>(g, 0.0);
        for (var j = 0u; j < terms; j++) {
            if j > 0u {
                w = vec2<f32>(w.x * rot.x - w.y * rot.y, w.y * rot.x + w.x * rot.y);
            }
            c[j] += w;
        }
    }
    var k2 = 0.0;
    for (var j = 0u; j < terms; j++) {
        c[j] *= select(2.0, 1.0, j == 0u) / f32(n);
        let jf = f32(j);
        k2 += (4.0 * jf * jf + 1.0) * (abs(c[j].x) + abs(c[j].y));
    }
    // No point of the circle's series reaches b: the ray misses.
    if odf_circle_bound(&c, terms) < b {
        return res;
    }
    // Entering the ball or the ellipsoid, which hold the glyph.
    let on_proxy = first > start || on_ball;
    // The ray in two halves, each by the angle θ ∈ (0, π/2] of its points from the ray's axis
    // on that half's side (m = −1 before the point nearest the centre, θ rising; m = 1 after
    // it, θ falling), so that sin θ keeps its relative precision near the axis.
    var inside = false;
    var started = false;
    var th_hit = 0.0;
    var m_hit = 0.0;
    for (var half_i = 0u; half_i < 2u; half_i++) {
        let m = select(1.0, -1.0, half_i == 0u);
        var th0 = 0.0;
        var to = 0.0;
        if half_i == 0u {
            if first >= 0.0 {
                continue;
            }
            th0 = atan2(b, -first);
            to = select(ODF_PI * 0.5, atan2(b, -last), last < 0.0);
        } else {
            if last <= 0.0 {
                continue;
            }
            th0 = select(ODF_PI * 0.5, atan2(b, first), first > 0.0);
            to = atan2(b, last);
        }
        let sigma = -m;
        var th = th0;
        var h = odf_big_h(&c, terms, m, th, b);
        if !started {
            started = true;
            if on_proxy && h.x >= 0.0 {
                res.hit = true;
                res.t = (first + sc) / vl;
                res.n = odf_normal(near + first * d, shape);
                return res;
            }
            inside = !on_proxy && h.x > 0.0;
        }
        for (var i = 0u; i < ODF_STEPS; i++) {
            // |H| = a, falling at rate p along the ray.
            let a = abs(h.x);
            let p = select(sigma * h.y, -sigma * h.y, inside);
            let root = sqrt(p * p + 2.0 * k2 * a);
            var step = 0.0;
            if p + root > 0.0 {
                step = 2.0 * a / (p + root);
            }
            var next = th + sigma * max(step, ODF_STEP);
            next = select(max(next, to), min(next, to), sigma > 0.0);
            let hn = odf_big_h(&c, terms, m, next, b);
            if (hn.x > 0.0) != inside {
                // Newton's method in the bracket, else bisection; the end on the flipped side.
                var kept = th;
                var flipped = next;
                var x = next;
                for (var k = 0u; k < 24u; k++) {
                    let hx = odf_big_h(&c, terms, m, x, b);
                    if (hx.x > 0.0) == inside {
                        kept = x;
                    } else {
                        flipped = x;
                    }
                    let lo = min(kept, flipped);
                    let hi = max(kept, flipped);
                    let newton = x - hx.x / hx.y;
                    var nx = 0.5 * (lo + hi);
                    if newton > lo && newton < hi {
                        nx = newton;
                    }
                    if nx == x || hi - lo <= 2.4e-7 * hi {
                        break;
                    }
                    x = nx;
                }
                th_hit = flipped;
                m_hit = m;
                break;
            }
            if next == to {
                break;
            }
            th = next;
            h = hn;
        }
        if m_hit != 0.0 {
            break;
        }
    }
    if m_hit == 0.0 {
        return res;
    }
    let u = cos(th_hit) * m_hit * d + sin(th_hit) * e2;
    let e = odf_eval(u, shape, true);
    let r = max(e.x, 0.0);
    res.hit = true;
    res.t = (m_hit * r * cos(th_hit) + sc) / vl;
    let tangential = e.yzw - dot(e.yzw, u) * u;
    res.n = r * u - tangential;
    return res;
}

// A bound of g on the whole circle: Σ |aⱼ| + |bⱼ|.
fn odf_circle_bound(c: ptr<function, array<vec2<f32>, ODF_TERMS>>, terms: u32) -> f32 {
    var m = 0.0;
    for (var j = 0u; j < terms; j++) {
        m += abs((*c)[j].x) + abs((*c)[j].y);
    }
    return m;
}

fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    let n = length(p);
    return !(n > max(odf_eval(p / max(n, 1e-30), shape, false).x, 0.0));
}

fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let h = odf_first(o, v, shape, t_min);
    if !h.hit {
        discard;
    }
    return vec4<f32>(h.t, h.n);
}

// The bounding ellipsoid's box (the ball's for a tensor's profile).
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let r = solid.scale * solid.bound;
    var b = quadric_box(o[0] * r.x, o[1] * r.y, o[2] * r.z, g.centre);
    if outside_frustum(b) {
        b.kind = PROXY_CULL;
    }
    return b;
}

fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let h = odf_first((*r).o_t, (*r).v_t, shape, -(*r).t0);
    if !h.hit {
        discard;
    }
    return vec4<f32>(h.t, h.n);
}

// The icosphere's direction p at radius r~(p).
fn shape_mesh_point(p: vec3<f32>, n: vec3<f32>, g: Glyph, solid: Solid) -> MeshPoint {
    let r = max(odf_eval(p, solid.shape, false).x, 0.0);
    return MeshPoint(p * (r * solid.scale.x), odf_normal(p * r, solid.shape));
}

fn shape_box_half(g: Glyph, solid: Solid) -> vec3<f32> {
    return solid.scale * solid.bound;
}

// The amplitude colouring's scale: 1 for a profile, the series' word past its coefficients.
fn odf_amplitude_scale(shape: vec4<f32>) -> f32 {
    if shape.x < 3.5 {
        return 1.0;
    }
    return odf_tail(shape, 0u);
}

// Coloured by direction, the hit's direction `dir` from the centre (world), as mrview's DEC; or
// by amplitude, viridis at r~ in that direction (`local`: the same point in the glyph's axes)
// times the scale. The twin: Odf::tint in src/shape/odf/mod.rs.
fn shape_tint(dir: vec3<f32>, local: vec3<f32>, shape: vec4<f32>, base: vec3<f32>) -> vec3<f32> {
    let mode = u32(shape.x) & 3u;
    let len = length(dir);
    if mode == 0u || !(len > 0.0) {
        return base;
    }
    if mode == 1u {
        return abs(dir) / len;
    }
    let u = local / max(length(local), 1e-30);
    return viridis(max(odf_eval(u, shape, false).x, 0.0) * odf_amplitude_scale(shape));
}
