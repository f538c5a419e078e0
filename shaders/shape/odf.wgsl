// ODF glyphs, the shape interface of common.wgsl: the radial surface r(u) = max(f(u), 0) in
// parameter space p~ = Oᵀ (p − c) / R, where it lies in the unit ball (R: the largest radius).
// f is a tensor's profile Σ aᵢ uᵢ² (aᵢ = rᵢ / R) or a spherical-harmonic series in the plain
// basis, read from the chunk's shape buffer past its per-glyph words (src/shape/odf.rs derives
// both, the bounds and the marcher; the upload in src/render/scene_buffers.rs lays the buffer
// out). Twin: src/twin/odf.rs; the f64 marcher: shape::odf::first_crossing.
//
// The shape vector: x = 0 (profile) or 4 (series), plus the colouring (0 the instance's colour,
// 1 direction, 2 amplitude: word 1's flags, OdfColoring in src/shape/odf.rs); a profile then
// holds (a₁, a₂, a₃), a series (its first word's index, G, lmax).

// The marcher's smallest step (GPU_EPS in src/shape/odf.rs) and its step cap.
const ODF_EPS: f32 = 0.00012207031;
const ODF_STEPS: u32 = 1024u;
// The over-relaxation of the marcher's steps (1.5 took 29 % fewer evaluations than 1 on the
// test fits, 1.8 and 1.95 more: their fall-backs cost what they save).
const ODF_RELAX: f32 = 1.5;

fn shape_radius(radii: vec3<f32>) -> f32 {
    return max(radii.x, max(radii.y, radii.z));
}

fn shape_of(g: Glyph, ii: u32) -> Solid {
    let w = load_shape_words(ii);
    let big = shape_radius(g.radii);
    // Direction wins over amplitude, as OdfColoring::of_flags.
    let colour = select(f32(w.y & 2u), 1.0, (w.y & 1u) != 0u);
    var shape = vec4<f32>(colour, g.radii / big);
    if w.x != 0u {
        shape = vec4<f32>(4.0 + colour, f32(w.x), bitcast<f32>(shapes[w.x].x), f32((w.y >> 8u) & 0xffu));
    }
    return Solid(vec3<f32>(big), vec3<f32>(1.0), shape);
}

// Float k of the series whose first word is `start` (k = 0: G; then the coefficients).
fn odf_word(start: u32, k: u32) -> f32 {
    return bitcast<f32>(shapes[start + (k >> 1u)][k & 1u]);
}

// G: a bound of |∇_S r~| on the sphere.
fn odf_gradient_bound(shape: vec4<f32>) -> f32 {
    if shape.x < 3.5 {
        return max(shape.y, max(shape.z, shape.w)) - min(shape.y, min(shape.z, shape.w));
    }
    return shape.z;
}

// f~(u) (x) and the gradient of its polynomial extension (yzw), u unit: the plain series
// (plain_value_gradient in src/shape/odf.rs, term by term).
fn odf_eval(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
    if shape.x < 3.5 {
        let a = shape.yzw;
        return vec4<f32>(dot(a * u, u), 2.0 * a * u);
    }
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

// h = r~(q/|q|) − |q| at the point near + s d: positive inside.
fn odf_h(near: vec3<f32>, d: vec3<f32>, s: f32, shape: vec4<f32>) -> f32 {
    let q = near + s * d;
    let n = length(q);
    if n == 0.0 {
        return max(odf_eval(d, shape, false).x, 0.0);
    }
    return max(odf_eval(q / n, shape, false).x, 0.0) - n;
}

// The outward normal (not unit) at surface point q: r u − ∇_S f~ (normal_at in odf.rs).
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

// The first crossing of o + t v at t > t_min (first_crossing in src/shape/odf.rs): safe steps
// of |h|/K, at least ODF_EPS, inside the unit ball; the first sign change bisected.
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
    var s = max(-half, t_min * vl - sc);
    if !(s < half) {
        return res;
    }
    let g = odf_gradient_bound(shape);
    var hv = odf_h(near, d, s, shape);
    // On the ball the ray starts outside; h ≥ 0 there is the glyph touching its ball (first_crossing).
    let on_ball = s == -half;
    if on_ball && hv >= 0.0 {
        res.hit = true;
        res.t = (s + sc) / vl;
        res.n = odf_normal(near + s * d, shape);
        return res;
    }
    let inside = !on_ball && hv > 0.0;
    for (var i = 0u; i < ODF_STEPS; i++) {
        // Over-relaxed (Keinert et al. 2014, "Enhanced Sphere Tracing"): a step of ODF_RELAX
        // safe radii, kept only where the new point's own safe radius reaches back over the
        // part the old one did not cover; else the plain step. Either way no crossing is passed.
        let r = odf_safe(near, d, s, abs(hv), b, g);
        var sn = min(s + max(ODF_RELAX * r, ODF_EPS), half);
        var hn = odf_h(near, d, sn, shape);
        if ODF_RELAX * r > ODF_EPS && sn - odf_safe(near, d, sn, abs(hn), b, g) > s + r {
            sn = min(s + max(r, ODF_EPS), half);
            hn = odf_h(near, d, sn, shape);
        }
        if (hn > 0.0) != inside {
            // Bisected to 2⁻²² of the radius (the depth bound is 1e-4 of it).
            var lo = s;
            var hi = sn;
            for (var k = 0u; k < 32u && hi - lo > 2.4e-7; k++) {
                let mid = 0.5 * (lo + hi);
                if (odf_h(near, d, mid, shape) > 0.0) == inside {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let sh = select(hi, lo, inside);
            res.hit = true;
            res.t = (sh + sc) / vl;
            res.n = odf_normal(near + sh * d, shape);
            return res;
        }
        if sn >= half {
            break;
        }
        s = sn;
        hv = hn;
    }
    return res;
}

// The safe radius at near + s d where |h| = a: a step of it cannot reach the surface, since h
// changes by at most 1 + G·b/m² per unit of ray, m ≥ max(b, |q| − step) a lower bound of |q|
// over the step (first_crossing in src/shape/odf.rs).
fn odf_safe(near: vec3<f32>, d: vec3<f32>, s: f32, a: f32, b: f32, g: f32) -> f32 {
    let qn = length(near + s * d);
    let d0 = a / (1.0 + g * b / max(qn * qn, 1e-30));
    let m = max(b, qn - d0);
    return a / (1.0 + g * b / max(m * m, 1e-30));
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

// The bounding ball's box.
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let r = solid.scale.x;
    var b = quadric_box(o[0] * r, o[1] * r, o[2] * r, g.centre);
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
    return solid.scale;
}

// The amplitude colouring's scale: 1 for a profile, the series' word past its coefficients.
fn odf_amplitude_scale(shape: vec4<f32>) -> f32 {
    if shape.x < 3.5 {
        return 1.0;
    }
    let lmax = u32(shape.w);
    return odf_word(u32(shape.y), 1u + (lmax + 1u) * (lmax + 2u) / 2u);
}

// Coloured by direction, the hit's direction `dir` from the centre (world), as mrview's DEC; or
// by amplitude, viridis at r~ in that direction (`local`: the same point in the glyph's axes)
// times the scale. The twin: Odf::tint in src/shape/odf.rs.
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
