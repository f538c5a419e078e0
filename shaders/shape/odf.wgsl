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

// The smallest step in the ray plane's angle (GPU_STEP in src/shape/odf/mod.rs) and the step
// cap. A great circle's series has at most 16 (a, b) pairs (OdfCircle): lmax ≤ 30 (MAX_LMAX in
// src/sh).
const ODF_STEP: f32 = 3.0517578e-5;
const ODF_STEPS: u32 = 256u;
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
    if ODF_GENERAL && shape.x < 3.5 {
        return mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    }
    return quat_to_mat3(vec4<f32>(odf_tail(shape, 1u), odf_tail(shape, 2u), odf_tail(shape, 3u), odf_tail(shape, 4u)));
}

// f~(u) (x) and the gradient of its polynomial extension (yzw), u unit in the glyph's axes
// (Profile::value_gradient in src/shape/odf/mod.rs).
fn odf_eval(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
    if ODF_GENERAL && shape.x < 3.5 {
        let a = shape.yzw;
        return vec4<f32>(dot(a * u, u), 2.0 * a * u);
    }
    let rot = odf_rotation(shape);
    let e = odf_series(rot * u, shape, want_grad);
    return vec4<f32>(e.x, transpose(rot) * e.yzw);
}

// The largest lmax whose series a payload holds as monomials (MAX_MONOMIAL_LMAX in
// src/shape/odf/monomial.rs); above it, plain coefficients.
const ODF_MONOMIAL_LMAX: u32 = 12u;

// Whether the pipeline draws glyphs past the monomial series: tensors' profiles and series of
// lmax > 12 (Shape::general_override; a chunk of monomial series only sets it false). lavapipe
// runs every branch of a shader, the lanes' results masked, so the paths no glyph of a chunk
// takes cost each fragment the same as the one it takes: without them, the slab of 10,000 lmax-8
// ODFs draws about 15 % faster.
override ODF_GENERAL: bool = true;

// The series at unit u in its own axes and its gradient there, in the form its payload holds.
fn odf_series(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
    let lmax = u32(shape.w);
    if !ODF_GENERAL || lmax <= ODF_MONOMIAL_LMAX {
        if want_grad {
            return odf_monomial_gradient(u, u32(shape.y), lmax);
        }
        return vec4<f32>(odf_monomial(u, u32(shape.y), lmax), 0.0, 0.0, 0.0);
    }
    return odf_plain(u, shape, want_grad);
}

// The homogeneous polynomial Σ p_abc x^a y^b z^c (a + b + c = L) whose coefficients follow G
// at `start` (monomial_value in src/shape/odf/monomial.rs): Horner's rule in x over the rows
// a = L … 0, each row a binary form in y and z by Horner's rule in y with z's powers.
fn odf_monomial(u: vec3<f32>, start: u32, lmax: u32) -> f32 {
    var f = 0.0;
    for (var i = 0u; i <= lmax; i++) {
        let a = lmax - i;
        let row = 1u + a * (2u * lmax + 3u - a) / 2u;
        var h = odf_word(start, row + i);
        var zp = 1.0;
        for (var b = i; b > 0u; b--) {
            zp *= u.z;
            h = h * u.y + odf_word(start, row + b - 1u) * zp;
        }
        f = f * u.x + h;
    }
    return f;
}

// The points cos ψ d + sin ψ e of four angles (their cosines c and sines s), as their x, y
// and z components.
fn odf_circle_points(c: vec4<f32>, s: vec4<f32>, d: vec3<f32>, e: vec3<f32>) -> mat3x4<f32> {
    return mat3x4<f32>(c * d.x + s * e.x, c * d.y + s * e.y, c * d.z + s * e.z);
}

// odf_monomial at the n ≤ 13 points cos ψᵢ d + sin ψᵢ e, ψᵢ = iπ/n, of a great circle, as
// odf_dft4's four vectors: Horner's rule run on all of them at once, so that each coefficient is
// read once (reading them dominated the crossing's set-up: L + 1 passes cost 10x the rest of the
// frame). Points 0–7 go two vectors, point 8 alone and, where `wide` (n > 9), points 9–12 a third
// vector: every lane evaluated is a point used at lmax 8 and 12. `wide` is a constant at each
// call, so the driver folds the other case away: lavapipe runs both sides of a branch, and
// a fourth vector at lmax 8 cost 7 of the 16 points evaluated.
fn odf_circle_monomials(d: vec3<f32>, e: vec3<f32>, start: u32, lmax: u32, n: u32, wide: bool) -> array<vec4<f32>, 4> {
    // cos ψᵢ and sin ψᵢ by powers of e^(iπ/n), four to a vector.
    let w = odf_powers16(vec2<f32>(cos(ODF_PI / f32(n)), sin(ODF_PI / f32(n))));
    let p0 = odf_circle_points(w[0], w[1], d, e);
    let p1 = odf_circle_points(w[2], w[3], d, e);
    let p8 = odf_circle_points(w[4], w[5], d, e);
    let pw = odf_circle_points(vec4<f32>(w[4].yzw, w[6].x), vec4<f32>(w[5].yzw, w[7].x), d, e);
    let x0 = p0[0];
    let y0 = p0[1];
    let z0 = p0[2];
    let x1 = p1[0];
    let y1 = p1[1];
    let z1 = p1[2];
    let x8 = p8[0].x;
    let y8 = p8[1].x;
    let z8 = p8[2].x;
    let xw = pw[0];
    let yw = pw[1];
    let zw = pw[2];
    var f0 = vec4<f32>(0.0);
    var f1 = vec4<f32>(0.0);
    var f8 = 0.0;
    var fw = vec4<f32>(0.0);
    for (var i = 0u; i <= lmax; i++) {
        let a = lmax - i;
        let row = 1u + a * (2u * lmax + 3u - a) / 2u;
        let top = odf_word(start, row + i);
        var h0 = vec4<f32>(top);
        var h1 = h0;
        var h8 = top;
        var hw = h0;
        var p0 = vec4<f32>(1.0);
        var p1 = p0;
        var p8 = 1.0;
        var pw = p0;
        for (var b = i; b > 0u; b--) {
            let w = odf_word(start, row + b - 1u);
            p0 *= z0;
            p1 *= z1;
            p8 *= z8;
            h0 = h0 * y0 + w * p0;
            h1 = h1 * y1 + w * p1;
            h8 = h8 * y8 + w * p8;
            if wide {
                pw *= zw;
                hw = hw * yw + w * pw;
            }
        }
        f0 = f0 * x0 + h0;
        f1 = f1 * x1 + h1;
        f8 = f8 * x8 + h8;
        if wide {
            fw = fw * xw + hw;
        }
    }
    return array<vec4<f32>, 4>(f0, f1, vec4<f32>(f8, fw.xyz), vec4<f32>(fw.w, 0.0, 0.0, 0.0));
}

// The great circle's series g(φ) = Σⱼ aⱼ cos 2jφ + bⱼ sin 2jφ, j < 16, four terms to a vector
// (aⱼ in a[j/4] lane j%4): held in registers, since an array indexed at run time costs lavapipe a
// gather at every read.
struct OdfCircle {
    a0: vec4<f32>,
    a1: vec4<f32>,
    a2: vec4<f32>,
    a3: vec4<f32>,
    b0: vec4<f32>,
    b1: vec4<f32>,
    b2: vec4<f32>,
    b3: vec4<f32>,
}

// (cos jθ, sin jθ) for j = 0…3 of e^(iθ) = z, as two vectors, and z⁴.
fn odf_powers(z: vec2<f32>) -> array<vec4<f32>, 3> {
    let z2 = vec2<f32>(z.x * z.x - z.y * z.y, 2.0 * z.x * z.y);
    let z3 = vec2<f32>(z2.x * z.x - z2.y * z.y, z2.x * z.y + z2.y * z.x);
    let z4 = vec2<f32>(z2.x * z2.x - z2.y * z2.y, 2.0 * z2.x * z2.y);
    return array<vec4<f32>, 3>(vec4<f32>(1.0, z.x, z2.x, z3.x), vec4<f32>(0.0, z.y, z2.y, z3.y), vec4<f32>(z4, 0.0, 0.0));
}

// (cos jθ, sin jθ) for j = 0…15 of e^(iθ) = z: cos of j = 4k…4k+3 at [2k], sin at [2k + 1].
fn odf_powers16(z: vec2<f32>) -> array<vec4<f32>, 8> {
    let p = odf_powers(z);
    let z4 = p[2].xy;
    let c1 = p[0] * z4.x - p[1] * z4.y;
    let s1 = p[1] * z4.x + p[0] * z4.y;
    let c2 = c1 * z4.x - s1 * z4.y;
    let s2 = s1 * z4.x + c1 * z4.y;
    let c3 = c2 * z4.x - s2 * z4.y;
    let s3 = s2 * z4.x + c2 * z4.y;
    return array<vec4<f32>, 8>(p[0], p[1], c1, s1, c2, s2, c3, s3);
}

// Adds g (cos jθ, sin jθ) to every term j: one value's share of the transform.
fn odf_circle_add(c: ptr<function, OdfCircle>, g: f32, theta: f32) {
    let p = odf_powers16(vec2<f32>(cos(theta), sin(theta)));
    (*c).a0 += g * p[0];
    (*c).b0 += g * p[1];
    (*c).a1 += g * p[2];
    (*c).b1 += g * p[3];
    (*c).a2 += g * p[4];
    (*c).b2 += g * p[5];
    (*c).a3 += g * p[6];
    (*c).b3 += g * p[7];
}

// The transform Σᵢ gᵢ (cos jθᵢ, sin jθᵢ), θᵢ = 2iπ/n, of the n ≤ 16 values `v` (four to a
// vector), for j < terms ≤ 8: the angles' powers kept four to a vector, each term placed in its
// lane by a select (no value indexed at run time).
fn odf_dft4(v: array<vec4<f32>, 4>, n: u32, terms: u32) -> OdfCircle {
    let r = odf_powers16(vec2<f32>(cos(2.0 * ODF_PI / f32(n)), sin(2.0 * ODF_PI / f32(n))));
    let rc0 = r[0];
    let rs0 = r[1];
    let rc1 = r[2];
    let rs1 = r[3];
    let rc2 = r[4];
    let rs2 = r[5];
    let rc3 = r[6];
    let rs3 = r[7];
    let lane = vec4<f32>(0.0, 1.0, 2.0, 3.0);
    let nf = f32(n);
    let v0 = select(vec4<f32>(0.0), v[0], lane < vec4<f32>(nf));
    let v1 = select(vec4<f32>(0.0), v[1], lane + 4.0 < vec4<f32>(nf));
    let v2 = select(vec4<f32>(0.0), v[2], lane + 8.0 < vec4<f32>(nf));
    let v3 = select(vec4<f32>(0.0), v[3], lane + 12.0 < vec4<f32>(nf));
    var pc0 = vec4<f32>(1.0);
    var ps0 = vec4<f32>(0.0);
    var pc1 = pc0;
    var ps1 = ps0;
    var pc2 = pc0;
    var ps2 = ps0;
    var pc3 = pc0;
    var ps3 = ps0;
    var c: OdfCircle;
    for (var j = 0u; j < min(terms, 8u); j++) {
        let aj = dot(v0, pc0) + dot(v1, pc1) + dot(v2, pc2) + dot(v3, pc3);
        let bj = dot(v0, ps0) + dot(v1, ps1) + dot(v2, ps2) + dot(v3, ps3);
        let jf = vec4<f32>(f32(j));
        c.a0 = select(c.a0, vec4<f32>(aj), lane == jf);
        c.b0 = select(c.b0, vec4<f32>(bj), lane == jf);
        c.a1 = select(c.a1, vec4<f32>(aj), lane + 4.0 == jf);
        c.b1 = select(c.b1, vec4<f32>(bj), lane + 4.0 == jf);
        let c0 = pc0 * rc0 - ps0 * rs0;
        ps0 = ps0 * rc0 + pc0 * rs0;
        pc0 = c0;
        let c1 = pc1 * rc1 - ps1 * rs1;
        ps1 = ps1 * rc1 + pc1 * rs1;
        pc1 = c1;
        let c2 = pc2 * rc2 - ps2 * rs2;
        ps2 = ps2 * rc2 + pc2 * rs2;
        pc2 = c2;
        let c3 = pc3 * rc3 - ps3 * rs3;
        ps3 = ps3 * rc3 + pc3 * rs3;
        pc3 = c3;
    }
    return c;
}

// odf_monomial with the polynomial's gradient carried along (monomial_value_gradient).
fn odf_monomial_gradient(u: vec3<f32>, start: u32, lmax: u32) -> vec4<f32> {
    var f = vec4<f32>(0.0);
    for (var i = 0u; i <= lmax; i++) {
        let a = lmax - i;
        let row = 1u + a * (2u * lmax + 3u - a) / 2u;
        var h = odf_word(start, row + i);
        var hy = 0.0;
        var hz = 0.0;
        var zp = 1.0;
        var zpz = 0.0;
        for (var b = i; b > 0u; b--) {
            let p = odf_word(start, row + b - 1u);
            zpz = zpz * u.z + zp;
            zp *= u.z;
            hy = hy * u.y + h;
            hz = hz * u.y + p * zpz;
            h = h * u.y + p * zp;
        }
        f = vec4<f32>(f.x * u.x + h, f.y * u.x + f.x, f.z * u.x + hy, f.w * u.x + hz);
    }
    return f;
}

// The plain series at unit u in its own axes and its gradient there (plain_value_gradient in
// src/shape/odf/series.rs, term by term).
fn odf_plain(u: vec3<f32>, shape: vec4<f32>, want_grad: bool) -> vec4<f32> {
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
    if ODF_GENERAL && shape.x < 3.5 {
        return 2u;
    }
    return u32(shape.w);
}

// g(φ) and g′(φ) of the great circle's series (CircleSeries::value_slope in
// src/shape/odf/crossing.rs), from cos φ and sin φ; terms past `terms` are zero.
// `wide` (terms past 8, lmax ≥ 16) is a constant at each call, as in odf_circle_monomials.
fn odf_circle(c: ptr<function, OdfCircle>, terms: u32, wide: bool, cs: vec2<f32>) -> vec2<f32> {
    let p = odf_powers(vec2<f32>(cs.x * cs.x - cs.y * cs.y, 2.0 * cs.x * cs.y));
    let z4 = p[2].xy;
    var pc = p[0];
    var ps = p[1];
    // d/dφ of cos 2jφ is −2j sin 2jφ.
    var j2 = vec4<f32>(0.0, 2.0, 4.0, 6.0);
    var g = dot((*c).a0, pc) + dot((*c).b0, ps);
    var gp = dot((*c).b0 * j2, pc) - dot((*c).a0 * j2, ps);
    if terms > 4u {
        let t = pc * z4.x - ps * z4.y;
        ps = ps * z4.x + pc * z4.y;
        pc = t;
        j2 += 8.0;
        g += dot((*c).a1, pc) + dot((*c).b1, ps);
        gp += dot((*c).b1 * j2, pc) - dot((*c).a1 * j2, ps);
    }
    if wide && terms > 8u {
        var t = pc * z4.x - ps * z4.y;
        ps = ps * z4.x + pc * z4.y;
        pc = t;
        j2 += 8.0;
        g += dot((*c).a2, pc) + dot((*c).b2, ps);
        gp += dot((*c).b2 * j2, pc) - dot((*c).a2 * j2, ps);
        t = pc * z4.x - ps * z4.y;
        ps = ps * z4.x + pc * z4.y;
        pc = t;
        j2 += 8.0;
        g += dot((*c).a3, pc) + dot((*c).b3, ps);
        gp += dot((*c).b3 * j2, pc) - dot((*c).a3 * j2, ps);
    }
    return vec2<f32>(g, gp);
}

// H = g(mθ) sin θ − b and its slope in θ, at the angle θ from the ray's axis on the side m
// (plane_crossing's halves in src/shape/odf/crossing.rs).
fn odf_big_h(c: ptr<function, OdfCircle>, terms: u32, wide: bool, m: f32, th: f32, b: f32) -> vec2<f32> {
    let cs = vec2<f32>(cos(th), sin(th));
    let g = odf_circle(c, terms, wide, vec2<f32>(cs.x, m * cs.y));
    return vec2<f32>(g.x * cs.y - b, m * g.y * cs.y + g.x * cs.x);
}

// The march of odf_first along its ray's two halves over (first, last): the crossing's angle θ
// and side m (0: none; 2: the ray enters the glyph where it enters its proxy); k2 bounds H's
// second derivative (odf_first). `wide` is a constant at each call (odf_circle).
fn odf_march(c: ptr<function, OdfCircle>, terms: u32, wide: bool, k2: f32, b: f32, first: f32, last: f32, on_proxy: bool) -> vec2<f32> {
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
        var h = odf_big_h(c, terms, wide, m, th, b);
        if !started {
            started = true;
            if on_proxy && h.x >= 0.0 {
                return vec2<f32>(0.0, 2.0);
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
            let hn = odf_big_h(c, terms, wide, m, next, b);
            if (hn.x > 0.0) != inside {
                // Newton's method in the bracket, else bisection; the end on the flipped side.
                var kept = th;
                var flipped = next;
                var x = next;
                for (var k = 0u; k < 24u; k++) {
                    let hx = odf_big_h(c, terms, wide, m, x, b);
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
    return vec2<f32>(th_hit, m_hit);
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
    if !ODF_GENERAL || shape.x > 3.5 {
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
    var c: OdfCircle;
    let rot = odf_rotation(shape);
    let ds = rot * d;
    let e2s = rot * e2;
    if !ODF_GENERAL || (shape.x > 3.5 && u32(shape.w) <= ODF_MONOMIAL_LMAX) {
        // Monomials: every value in one pass over the coefficients, each read once.
        var v: array<vec4<f32>, 4>;
        if n > 9u {
            v = odf_circle_monomials(ds, e2s, u32(shape.y), u32(shape.w), n, true);
        } else {
            v = odf_circle_monomials(ds, e2s, u32(shape.y), u32(shape.w), n, false);
        }
        c = odf_dft4(v, n, terms);
    } else {
        for (var i = 0u; i < n; i++) {
            let psi = ODF_PI * f32(i) / f32(n);
            let us = cos(psi) * ds + sin(psi) * e2s;
            var g = 0.0;
            if ODF_GENERAL && shape.x < 3.5 {
                g = odf_eval(us, shape, false).x;
            } else {
                g = odf_series(us, shape, false).x;
            }
            odf_circle_add(&c, g, 2.0 * psi);
        }
    }
    // Scaled (a₀ by 1/n, the rest by 2/n) and cut to `terms`; K₂ = Σ (4j² + 1)(|aⱼ| + |bⱼ|).
    let lane = vec4<f32>(0.0, 1.0, 2.0, 3.0);
    let tf = vec4<f32>(f32(terms));
    let two = 2.0 / f32(n);
    let s0 = select(vec4<f32>(0.0), select(vec4<f32>(two), vec4<f32>(1.0 / f32(n), two, two, two), lane == vec4<f32>(0.0)), lane < tf);
    let s1 = select(vec4<f32>(0.0), vec4<f32>(two), lane + 4.0 < tf);
    let s2 = select(vec4<f32>(0.0), vec4<f32>(two), lane + 8.0 < tf);
    let s3 = select(vec4<f32>(0.0), vec4<f32>(two), lane + 12.0 < tf);
    c = OdfCircle(c.a0 * s0, c.a1 * s1, c.a2 * s2, c.a3 * s3, c.b0 * s0, c.b1 * s1, c.b2 * s2, c.b3 * s3);
    let m0 = abs(c.a0) + abs(c.b0);
    let m1 = abs(c.a1) + abs(c.b1);
    let m2 = abs(c.a2) + abs(c.b2);
    let m3 = abs(c.a3) + abs(c.b3);
    let k = 4.0 * lane * lane + 1.0;
    let k2 = dot(k, m0) + dot(k + 32.0 * lane + 64.0, m1) + dot(k + 64.0 * lane + 256.0, m2) + dot(k + 96.0 * lane + 576.0, m3);
    // No point of the circle's series reaches b: the ray misses.
    if dot(vec4<f32>(1.0), m0 + m1 + m2 + m3) < b {
        return res;
    }
    // Entering the ball or the ellipsoid, which hold the glyph.
    let on_proxy = first > start || on_ball;
    var hit: vec2<f32>;
    if ODF_GENERAL && terms > 8u {
        hit = odf_march(&c, terms, true, k2, b, first, last, on_proxy);
    } else {
        hit = odf_march(&c, terms, false, k2, b, first, last, on_proxy);
    }
    if hit.y == 2.0 {
        res.hit = true;
        res.t = (first + sc) / vl;
        res.n = odf_normal(near + first * d, shape);
        return res;
    }
    let th_hit = hit.x;
    let m_hit = hit.y;
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
    if ODF_GENERAL && shape.x < 3.5 {
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
