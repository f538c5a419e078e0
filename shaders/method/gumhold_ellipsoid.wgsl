// Gumhold's ellipsoid glyph: one perspective-correct silhouette quad per glyph, built here from
// the vertex and instance index, and the incremental ray–ellipsoid intersection per fragment.
// Math and names: shared/math/gumhold-ellipsoid.md. Composed as common.wgsl + this + outputs.wgsl.

// With CONSERVATIVE_DEPTH the proxy's vertices are moved along their eye rays onto the glyph's
// nearest view plane by a factor s_k (1 otherwise). The screen positions stay, but perspective
// interpolation then weighs vertex k by 1/(s_k w_k): so every varying below except `s` is sent
// multiplied by s_k and divided by the interpolated `s` per fragment, which restores the
// interpolation over the original quad exactly.
struct VsOut {
    @builtin(position) position: vec4<f32>,
    // Packed into few locations: rasterisers set up and store every location of every triangle.
    // xy: (q~x, q~y), the proxy corner in the unit circle's plane; zw: clip (z, w) of the quad
    // point (before any move): its depth is z / w.
    @location(0) q_zw: vec4<f32>,
    // xyz: V~, the quad point in parameter space; w: the move factor s_k (see above).
    @location(1) vt_quad_s: vec4<f32>,
    // xyz: v~ = V~ − e~ (perspective) or z^ (orthographic), the ray in parameter space; w: the
    // quad point's view x.
    @location(2) vt_ray_vx: vec4<f32>,
    // The quad point's view (y, z).
    @location(3) v_yz: vec2<f32>,
    // Columns of N = R_view T⁻¹ (the view-space normal is N p~) with, in w: u~ = 1/E
    // (perspective) or 1/|d~| (orthographic); the colour's bits; tz.x.
    @location(4) @interpolate(flat) n0_u: vec4<f32>,
    @location(5) @interpolate(flat) n1_color: vec4<u32>,
    @location(6) @interpolate(flat) n2_tzx: vec4<f32>,
    // Row 2 of R_view T: the hit's view z relative to the centre is tz · p~; this holds (y, z).
    @location(7) @interpolate(flat) tz_yz: vec2<f32>,
    @location(8) @interpolate(flat) id: u32,
}

// Everything a glyph's proxy vertices need, computed once per glyph: by each vertex in vs_main,
// or by cs_frames into `frames` for vs_frames (--prepass). 176 bytes (FRAME_SIZE in
// src/render/prepass.rs).
struct GlyphFrame {
    centre: vec3<f32>,
    // u~ = 1/E (perspective) or 1/|d~| (orthographic).
    u: f32,
    // Columns of T = O diag(r) Oᵀ: world offsets from parameter space.
    t0: vec3<f32>,
    // CONSERVATIVE_DEPTH: the view distance the proxy moves to (0: it stays).
    move_to: f32,
    t1: vec3<f32>,
    id: u32,
    t2: vec3<f32>,
    color: u32,
    // The quad: V~ = m~ + q~x x_t + q~y y_t (x_t, y_t: r~ times the orthonormal pair).
    m_t: vec3<f32>,
    tz_x: f32,
    x_t: vec3<f32>,
    tz_y: f32,
    y_t: vec3<f32>,
    tz_z: f32,
    // v~ = V~ + ray_t (perspective: ray_t = −e~) or v~ = ray_t = z^ (orthographic).
    ray_t: vec3<f32>,
    // Columns of N = R_view T⁻¹.
    n0: vec3<f32>,
    n1: vec3<f32>,
    n2: vec3<f32>,
}

// The glyph's frame, or false in `ok` when it is not drawn (degenerate, culled, eye inside).
struct FrameOrSkip {
    frame: GlyphFrame,
    ok: bool,
}

fn glyph_frame(ii: u32) -> FrameOrSkip {
    var out: FrameOrSkip;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, bounding_radius(g.radii)) {
        return out;
    }
    let o = quat_to_mat3(g.rotation);
    let ot = transpose(o);
    let rinv = 1.0 / g.radii;
    var f: GlyphFrame;
    var z_hat: vec3<f32>;
    var m_t = vec3<f32>(0.0);
    var r_t = 1.0;
    if is_ortho() {
        let d_t = o * ((ot * camera.forward.xyz) * rinv);
        let len = length(d_t);
        z_hat = d_t / len;
        f.u = 1.0 / len;
        f.ray_t = z_hat;
    } else {
        let e_t = o * ((ot * (camera.eye.xyz - g.centre)) * rinv);
        let e2 = dot(e_t, e_t);
        if !(e2 > EYE_INSIDE_E2) {
            return out;
        }
        let e = sqrt(e2);
        z_hat = -e_t / e;
        m_t = e_t / e2;
        r_t = sqrt((e2 - 1.0) / e2);
        f.u = 1.0 / e;
        f.ray_t = z_hat / f.u;
    }
    let xy = orthonormal_pair(z_hat);
    f.centre = g.centre;
    f.m_t = m_t;
    f.x_t = r_t * xy[0];
    f.y_t = r_t * xy[1];
    let t = o * mat3x3<f32>(ot[0] * g.radii, ot[1] * g.radii, ot[2] * g.radii);
    f.t0 = t[0];
    f.t1 = t[1];
    f.t2 = t[2];
    f.move_to = 0.0;
    if CONSERVATIVE_DEPTH {
        // Nearest view distance of the ellipsoid: centre's minus its support |diag(r) Oᵀ f|.
        let fwd = camera.forward.xyz;
        let d_c = dot(g.centre - camera.eye.xyz, fwd);
        let d_min = d_c - length(g.radii * (ot * fwd));
        let r_max = max(g.radii.x, max(g.radii.y, g.radii.z));
        if is_ortho() && d_min > camera.depth.z {
            f.move_to = d_min;
        } else if !is_ortho() && d_c - 1.5 * r_max > camera.depth.z {
            // Every proxy vertex lies within 1.5 r_max of the centre (|V~|² ≤ 1/E² + r~²|q~|²
            // ≤ 2), so all are in front of the near plane and can be scaled about the eye.
            f.move_to = max(d_min, camera.depth.z);
        }
    }
    f.id = ii + 1u;
    f.color = g.color;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let n = rv * o * mat3x3<f32>(ot[0] * rinv, ot[1] * rinv, ot[2] * rinv);
    f.n0 = n[0];
    f.n1 = n[1];
    f.n2 = n[2];
    let r2 = vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z);
    let tz = o * ((ot * r2) * g.radii);
    f.tz_x = tz.x;
    f.tz_y = tz.y;
    f.tz_z = tz.z;
    out.frame = f;
    out.ok = true;
    return out;
}

// Proxy vertex `s` (a corner of the polygon around the unit circle) of a glyph.
fn proxy_vertex(f: GlyphFrame, s: vec2<f32>) -> VsOut {
    var out: VsOut;
    let vt_quad = f.m_t + s.x * f.x_t + s.y * f.y_t;
    let v = f.centre + mat3x3<f32>(f.t0, f.t1, f.t2) * vt_quad;
    let clip = camera.view_proj * vec4<f32>(v, 1.0);
    out.position = clip;
    var k = 1.0;
    if CONSERVATIVE_DEPTH && f.move_to > 0.0 {
        let fwd = camera.forward.xyz;
        if is_ortho() {
            out.position = camera.view_proj * vec4<f32>(v + (f.move_to - dot(v - camera.eye.xyz, fwd)) * fwd, 1.0);
        } else {
            k = f.move_to / dot(v - camera.eye.xyz, fwd);
            out.position = camera.view_proj * vec4<f32>(camera.eye.xyz + k * (v - camera.eye.xyz), 1.0);
        }
    }
    var vt_ray = f.ray_t;
    if !is_ortho() {
        vt_ray = vt_quad + f.ray_t;
    }
    let v_view = k * (camera.view * vec4<f32>(v, 1.0)).xyz;
    out.q_zw = vec4<f32>(k * s, k * clip.zw);
    out.vt_quad_s = vec4<f32>(k * vt_quad, k);
    out.vt_ray_vx = vec4<f32>(k * vt_ray, v_view.x);
    out.v_yz = v_view.yz;
    out.id = f.id;
    out.n0_u = vec4<f32>(f.n0, f.u);
    out.n1_color = vec4<u32>(bitcast<vec3<u32>>(f.n1), f.color);
    out.n2_tzx = vec4<f32>(f.n2, f.tz_x);
    out.tz_yz = vec2<f32>(f.tz_y, f.tz_z);
    return out;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    let f = glyph_frame(ii);
    if !f.ok {
        var out: VsOut;
        out.position = CULLED_POSITION;
        return out;
    }
    return proxy_vertex(f.frame, proxy_corner(vi));
}

// --prepass: cs_frames writes the frames of the glyphs that are drawn, compacted, and counts
// them into draw-indirect arguments (prepass.wgsl); vs_frames draws them.
@group(1) @binding(1) var<storage, read_write> frames_out: array<GlyphFrame>;

@compute @workgroup_size(64)
fn cs_frames(@builtin(global_invocation_id) gid: vec3<u32>) {
    let ii = prepass_glyph(gid.x);
    if ii == 0xffffffffu {
        return;
    }
    let f = glyph_frame(ii);
    if !f.ok {
        return;
    }
    if slice.splat_max > 0u {
        let px = splat_pixels(f.frame);
        if splat_sized(px) {
            // A glyph covering no pixel centre has nothing to draw.
            if splat_frame(f.frame, px, false) {
                splat_noted(ii, px);
            }
            return;
        }
    }
    frames_out[atomicAdd(&draw_args.instance_count, 1u)] = f.frame;
}

// Splat glyph ii's pixels again (cs_splat_ids): the same function on the same glyph, bit for bit
// the frame cs_frames had.
fn splat_glyph(ii: u32, second: bool) {
    let f = glyph_frame(ii).frame;
    splat_frame(f, splat_pixels(f), second);
}

// Ray cast a splat's pixels px and keep its hits (splat_put); whether any pixel was hit.
fn splat_frame(f: GlyphFrame, px: vec4<i32>, second: bool) -> bool {
    var any = false;
    let setup = splat_setup(f);
    for (var y = px.y; y <= px.w; y++) {
        let span = splat_row(setup, y, px.x, px.z);
        for (var x = span.x; x <= span.y; x++) {
            let depth = splat_depth(setup, splat_q(setup, vec2<f32>(f32(x) + 0.5, f32(y) + 0.5)));
            if depth >= 0.0 {
                splat_put(pixel_index(x, y), depth, f.id, second);
                any = true;
            }
        }
    }
    return any;
}

// The splat's hit at pixel centre px (prepass.wgsl's splat_at), cast again from the glyph's
// frame: the closed form costs less than starting from the kept depth key would save.
fn splat_hit(ii: u32, px: vec2<f32>, key: u32) -> Hit {
    return pixel_hit(glyph_frame(ii).frame, px);
}

// A GlyphFrame read as per-instance vertex attributes (vertex fetch is the fast path on
// lavapipe; storage-buffer reads there are per-lane gathers). Layout: FRAME_ATTRIBUTES in
// src/render/prepass.rs.
struct FrameInput {
    @location(0) centre_u: vec4<f32>,
    @location(1) t0_move: vec4<f32>,
    @location(2) t1: vec3<f32>,
    @location(3) id: u32,
    @location(4) t2: vec3<f32>,
    @location(5) color: u32,
    @location(6) m_t_tzx: vec4<f32>,
    @location(7) x_t_tzy: vec4<f32>,
    @location(8) y_t_tzz: vec4<f32>,
    @location(9) ray_t: vec3<f32>,
    @location(10) n0: vec3<f32>,
    @location(11) n1: vec3<f32>,
    @location(12) n2: vec3<f32>,
}

@vertex
fn vs_frames(@builtin(vertex_index) vi: u32, in: FrameInput) -> VsOut {
    var f: GlyphFrame;
    f.centre = in.centre_u.xyz;
    f.u = in.centre_u.w;
    f.t0 = in.t0_move.xyz;
    f.move_to = in.t0_move.w;
    f.t1 = in.t1;
    f.id = in.id;
    f.t2 = in.t2;
    f.color = in.color;
    f.m_t = in.m_t_tzx.xyz;
    f.tz_x = in.m_t_tzx.w;
    f.x_t = in.x_t_tzy.xyz;
    f.tz_y = in.x_t_tzy.w;
    f.y_t = in.y_t_tzz.xyz;
    f.tz_z = in.y_t_tzz.w;
    f.ray_t = in.ray_t;
    f.n0 = in.n0;
    f.n1 = in.n1;
    f.n2 = in.n2;
    return proxy_vertex(f, proxy_corner(vi));
}

// The interpolated quad point, unpacked (and, with CONSERVATIVE_DEPTH, moved back).
struct Unpacked {
    q: vec2<f32>,
    zw: vec2<f32>,
    vt_quad: vec3<f32>,
    vt_ray: vec3<f32>,
    v_view: vec3<f32>,
    u: f32,
}

// The front intersection of the pixel's ray, or discard.
fn ray_cast(packed: VsOut) -> Hit {
    var in: Unpacked;
    in.q = packed.q_zw.xy;
    in.zw = packed.q_zw.zw;
    in.vt_quad = packed.vt_quad_s.xyz;
    in.vt_ray = packed.vt_ray_vx.xyz;
    in.v_view = vec3<f32>(packed.vt_ray_vx.w, packed.v_yz);
    in.u = packed.n0_u.w;
    if CONSERVATIVE_DEPTH {
        let inv = 1.0 / packed.vt_quad_s.w;
        in.q *= inv;
        in.vt_quad *= inv;
        in.vt_ray *= inv;
        in.v_view *= inv;
    }
    let n = mat3x3<f32>(packed.n0_u.xyz, bitcast<vec3<f32>>(packed.n1_color.xyz), packed.n2_tzx.xyz);
    let tz = vec3<f32>(packed.n2_tzx.w, packed.tz_yz);
    let hit = hit_at(in, n, tz, packed.n1_color.w);
    if hit.miss {
        discard;
    }
    return hit;
}

// The front intersection of the ray through quad point `in` (miss: the ray passes the glyph).
// N = R_view T⁻¹ gives the view normal N p~; tz · p~ the hit's view z relative to the centre.
fn hit_at(in: Unpacked, n: mat3x3<f32>, tz: vec3<f32>, color: u32) -> Hit {
    var hit: Hit;
    let q2 = dot(in.q, in.q);
    if q2 > 1.0 {
        hit.miss = true;
        return hit;
    }
    let alpha = sqrt(1.0 - q2);
    var kappa: f32;
    var p_view: vec3<f32>;
    if is_ortho() {
        // p = V + τ d with τ = −α/|d~|; the view depth grows by α/|d~|.
        kappa = alpha;
        p_view = in.v_view + vec3<f32>(0.0, 0.0, alpha * in.u);
    } else {
        // κ = 1 − λ = β/(1 + β): no cancellation for distant glyphs.
        let beta = in.u * alpha;
        kappa = beta / (1.0 + beta);
        p_view = (1.0 - kappa) * in.v_view;
    }
    let p_t = in.vt_quad - kappa * in.vt_ray;
    let n_view = normalize(n * p_t);
    hit.color = vec4<f32>(shade(unpack4x8unorm(color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = dot(tz, p_t);
    hit.z_proxy_rel = dot(tz, in.vt_quad);
    hit.depth = hit_depth(alpha, in.zw, in.v_view.z, in.u);
    return hit;
}

// The depth of the hit on the ray through a quad point with clip (z, w) `zw` and view z `z_view`,
// α = √(1 − |q~|²).
fn hit_depth(alpha: f32, zw: vec2<f32>, z_view: f32, u: f32) -> f32 {
    if is_ortho() {
        // p = V + τ d with τ = −α/|d~|; the view depth grows by α/|d~|.
        return zw.x / zw.y + camera.depth.y * alpha * u;
    }
    return zw.x / zw.y + u * alpha * camera.depth.x / (-z_view);
}

// --splat: glyphs whose proxy spans few pixels are ray cast per pixel in compute, not drawn.
// cs_frames finds each splat glyph's nearest hit per pixel and which glyph made it (one 64-bit
// atomic max, or a 32-bit one on depth and a second pass for the id: splat64.wgsl,
// splat32.wgsl), and a quad per 16-pixel tile they touch (vs_splat_tile + fs_splat*) shades them,
// depth-tested against the drawn glyphs.

// A glyph's quad coordinates q~ and depth as functions of the pixel: everything per glyph that
// the per-pixel loops need, so a pixel costs a few dozen operations.
struct SplatSetup {
    // q~(px) = t(px) (o.x ux + o.y uy) with o = xy(px) + off0, xy(px) the pixel's view-space
    // offset at distance 1 (perspective) or 0 (orthographic), t = (1 − E²)/(g · (xy, −1))
    // (orthographic: g = (0, 0, −1), 1 − E² = 1, so t = 1).
    ux: vec2<f32>,
    uy: vec2<f32>,
    off0: vec2<f32>,
    g: vec3<f32>,
    one_minus_e2: f32,
    // Clip (z, w) and view z of the quad point, affine in q~.
    zw0: vec2<f32>,
    zwx: vec2<f32>,
    zwy: vec2<f32>,
    vz: vec3<f32>,
    u: f32,
}

fn splat_setup(f: GlyphFrame) -> SplatSetup {
    var s: SplatSetup;
    let rv_t = transpose(mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz));
    // Parameter space from view space: T⁻¹ R_viewᵀ = R_viewᵀ N R_viewᵀ.
    let m = rv_t * (mat3x3<f32>(f.n0, f.n1, f.n2) * rv_t);
    let r2 = dot(f.x_t, f.x_t);
    s.ux = vec2<f32>(dot(m[0], f.x_t), dot(m[0], f.y_t)) / r2;
    s.uy = vec2<f32>(dot(m[1], f.x_t), dot(m[1], f.y_t)) / r2;
    let c_v = (camera.view * vec4<f32>(f.centre, 1.0)).xyz;
    if is_ortho() {
        // The ray from (x, y, 0) in view space along the view direction keeps q~ while it
        // moves: take it level with the centre (in-plane offsets only, nothing to cancel).
        s.off0 = -c_v.xy;
        // t = 1.
        s.g = vec3<f32>(0.0, 0.0, -1.0);
        s.one_minus_e2 = 1.0;
    } else {
        // The ray e~ + t d~ meets the eye's polar plane e~ · p~ = 1 at t = (1 − E²)/(e~ · d~).
        // e~ and m~ both lie on the quad's axis, the eye's ray to the centre, so the in-plane
        // offset is t times that of the pixel ray's offset from the centre's ray, taken alone
        // (the whole d~, mostly along the axis, would cancel badly).
        s.off0 = c_v.xy / c_v.z;
        let e_t = -f.ray_t;
        s.g = transpose(m) * e_t;
        s.one_minus_e2 = 1.0 - dot(e_t, e_t);
    }
    let t = mat3x3<f32>(f.t0, f.t1, f.t2);
    let clip0 = camera.view_proj * vec4<f32>(f.centre + t * f.m_t, 1.0);
    let clipx = camera.view_proj * vec4<f32>(t * f.x_t, 0.0);
    let clipy = camera.view_proj * vec4<f32>(t * f.y_t, 0.0);
    s.zw0 = clip0.zw;
    s.zwx = clipx.zw;
    s.zwy = clipy.zw;
    let row2 = vec4<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z, camera.view[3].z);
    s.vz = vec3<f32>(dot(row2, vec4<f32>(f.centre + t * f.m_t, 1.0)), dot(row2.xyz, t * f.x_t), dot(row2.xyz, t * f.y_t));
    s.u = f.u;
    return s;
}

// q~ at pixel centre `px` (framebuffer coordinates).
fn splat_q(s: SplatSetup, px: vec2<f32>) -> vec2<f32> {
    let xy = pixel_view_xy(px);
    let o = xy + s.off0;
    return (s.one_minus_e2 / (dot(s.g.xy, xy) - s.g.z)) * (o.x * s.ux + o.y * s.uy);
}

// The pixels of row y within [x0, x1] whose centres may see the glyph: |q~| ≤ 1 is
// (1 − E²)² |L|² ≤ D² with L = o.x ux + o.y uy and D = g · (xy, −1) both affine in the pixel's x,
// a quadratic inequality in x (splat_span; the depth test decides each pixel).
fn splat_row(s: SplatSetup, y: i32, x0: i32, x1: i32) -> vec2<i32> {
    let start = vec2<f32>(f32(x0) + 0.5, f32(y) + 0.5);
    let xy = pixel_view_xy(start);
    let o = xy + s.off0;
    let k = s.one_minus_e2;
    let l0 = k * (o.x * s.ux + o.y * s.uy);
    let lx = k * s.ux / camera.pixels.x;
    let d0 = dot(s.g.xy, xy) - s.g.z;
    let dx = s.g.x / camera.pixels.x;
    return splat_span(vec3<f32>(dot(lx, lx) - dx * dx, 2.0 * (dot(l0, lx) - d0 * dx), dot(l0, l0) - d0 * d0), x0, x1);
}

// The hit's depth at quad coordinates q (-1: no hit).
fn splat_depth(s: SplatSetup, q: vec2<f32>) -> f32 {
    let q2 = dot(q, q);
    if q2 > 1.0 {
        return -1.0;
    }
    let zw = s.zw0 + q.x * s.zwx + q.y * s.zwy;
    let depth = hit_depth(sqrt(1.0 - q2), zw, s.vz.x + q.x * s.vz.y + q.y * s.vz.z, s.u);
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(depth >= 0.0 && depth <= 1.0) {
        return -1.0;
    }
    return depth;
}

// The quad point that pixel centre `px` sees, formed as the vertex stage forms it.
fn pixel_quad_point(f: GlyphFrame, px: vec2<f32>) -> Unpacked {
    var in: Unpacked;
    in.q = splat_q(splat_setup(f), px);
    let vt = f.m_t + in.q.x * f.x_t + in.q.y * f.y_t;
    in.vt_quad = vt;
    in.vt_ray = f.ray_t;
    if !is_ortho() {
        in.vt_ray = vt + f.ray_t;
    }
    let v = f.centre + mat3x3<f32>(f.t0, f.t1, f.t2) * vt;
    in.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
    in.zw = (camera.view_proj * vec4<f32>(v, 1.0)).zw;
    in.u = f.u;
    return in;
}

fn pixel_hit(f: GlyphFrame, px: vec2<f32>) -> Hit {
    let tz = vec3<f32>(f.tz_x, f.tz_y, f.tz_z);
    var hit = hit_at(pixel_quad_point(f, px), mat3x3<f32>(f.n0, f.n1, f.n2), tz, f.color);
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(hit.depth >= 0.0 && hit.depth <= 1.0) {
        hit.miss = true;
    }
    return hit;
}

// The pixels (first and last, inclusive) whose centres a glyph's proxy may cover, or none.
fn splat_pixels(f: GlyphFrame) -> vec4<i32> {
    var clips: array<vec4<f32>, 4>;
    for (var k = 0u; k < 4u; k++) {
        let s = corner_signs(k);
        let v = f.centre + mat3x3<f32>(f.t0, f.t1, f.t2) * (f.m_t + s.x * f.x_t + s.y * f.y_t);
        clips[k] = camera.view_proj * vec4<f32>(v, 1.0);
    }
    return splat_pixel_rect(clips);
}
