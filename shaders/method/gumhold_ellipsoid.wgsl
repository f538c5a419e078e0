// Gumhold's ellipsoid glyph: one perspective-correct silhouette quad per glyph, built here from
// the vertex and instance index, and the ray–ellipsoid intersection per fragment from its pixel.
// Math and names: shared/math/gumhold-ellipsoid.md. Composed as common.wgsl + this + outputs.wgsl.

// Nothing is interpolated: every fragment finds its quad point q~ from its own pixel position
// and the glyph's PixelCast, sent flat. Interpolation precision is not specified (WGSL, Vulkan),
// and the hit is very sensitive to q~ on thin glyphs: SwiftShader's interpolated q~ turned
// grid40's normals by 12° at the 99th percentile (0.0002° now, as lavapipe's).
struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The PixelCast packed: (ux, uy); (o0, g.xy); (g.z, 1 − E², u, view z of the centre);
    // the view normal's columns nx, ny, nz with tzq's components in w.
    @location(0) @interpolate(flat) ux_uy: vec4<f32>,
    @location(1) @interpolate(flat) o0_gxy: vec4<f32>,
    @location(2) @interpolate(flat) gz_k_u_cz: vec4<f32>,
    @location(3) @interpolate(flat) nx_tzx: vec4<f32>,
    @location(4) @interpolate(flat) ny_tzy: vec4<f32>,
    @location(5) @interpolate(flat) nz_tzz: vec4<f32>,
    @location(6) @interpolate(flat) color: u32,
    @location(7) @interpolate(flat) id: u32,
    // The centre ray's pixel px0 (centre_ray in common.wgsl).
    @location(8) @interpolate(flat) px0: vec2<f32>,
    // THIN_EXACT: A's rows and their residuals, and the centre ray's (PixelCast's a, a_lo, lo),
    // packed: (a0, l0.x), (a1, l0.y), (a2, l0.z), (l1, lo.x), (l2, lo.y), lo.z.
    @location(9) @interpolate(flat) a0_l0x: vec4<f32>,
    @location(10) @interpolate(flat) a1_l0y: vec4<f32>,
    @location(11) @interpolate(flat) a2_l0z: vec4<f32>,
    @location(12) @interpolate(flat) l1_lox: vec4<f32>,
    @location(13) @interpolate(flat) l2_loy: vec4<f32>,
    @location(14) @interpolate(flat) loz: f32,
}

// Everything a glyph's proxy vertices need, computed once per glyph: by each vertex in vs_main,
// or by cs_frames into `frames` for vs_frames (--prepass). 176 bytes (FRAME_SIZE in
// src/render/prepass.rs).
struct GlyphFrame {
    centre: vec3<f32>,
    // u~ = 1/E (perspective) or 1/|d~| (orthographic).
    u: f32,
    // Columns of T = O diag(r): world offsets from parameter space, the glyph's principal frame
    // scaled per axis (see glyph_frame).
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
    // Columns of N = R_view O diag(1/r) (normals: T⁻ᵀ = O diag(1/r)).
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
    // Parameter space is the principal frame scaled per axis, p~ = diag(1/r) Oᵀ (p − c), not the
    // symmetric T⁻¹ = O diag(1/r) Oᵀ: rotating back to world axes would add the thin axis's
    // ×k components to the others in f32 and lose where the eye lies across a thin glyph (discs
    // at k = 1e5: depth p99 3e-3 of the radius). Here each component keeps its own relative
    // precision and nothing is mixed after the scaling.
    let o = quat_to_mat3(g.rotation);
    let ot = transpose(o);
    let rinv = 1.0 / g.radii;
    var f: GlyphFrame;
    var z_hat: vec3<f32>;
    var m_t = vec3<f32>(0.0);
    var r_t = 1.0;
    if is_ortho() {
        let d_t = (ot * camera.forward.xyz) * rinv;
        let len = length(d_t);
        z_hat = d_t / len;
        f.u = 1.0 / len;
        f.ray_t = z_hat;
    } else {
        let e_t = (ot * (camera.eye.xyz - g.centre)) * rinv;
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
    let t = mat3x3<f32>(o[0] * g.radii.x, o[1] * g.radii.y, o[2] * g.radii.z);
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
    let n = rv * mat3x3<f32>(o[0] * rinv.x, o[1] * rinv.y, o[2] * rinv.z);
    f.n0 = n[0];
    f.n1 = n[1];
    f.n2 = n[2];
    let r2 = vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z);
    let tz = (ot * r2) * g.radii;
    f.tz_x = tz.x;
    f.tz_y = tz.y;
    f.tz_z = tz.z;
    out.frame = f;
    out.ok = true;
    return out;
}

// The factors on the quad's (x, y) that widen it by PROXY_MARGIN_PX on each side: its half
// widths T x~, T y~ measured in pixels on the view plane through the centre.
fn proxy_growth(f: GlyphFrame) -> vec2<f32> {
    let t = mat3x3<f32>(f.t0, f.t1, f.t2);
    return margin_growth(f.centre, t * f.x_t, t * f.y_t);
}

// Proxy vertex `corner` (a corner of the polygon around the unit circle) of a glyph.
fn proxy_vertex(f: GlyphFrame, corner: vec2<f32>) -> VsOut {
    var out: VsOut;
    let s = corner * proxy_growth(f);
    let v = f.centre + mat3x3<f32>(f.t0, f.t1, f.t2) * (f.m_t + s.x * f.x_t + s.y * f.y_t);
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    if CONSERVATIVE_DEPTH && f.move_to > 0.0 {
        // Along the eye ray, so the screen position stays (nothing is interpolated).
        let fwd = camera.forward.xyz;
        if is_ortho() {
            out.position = camera.view_proj * vec4<f32>(v + (f.move_to - dot(v - camera.eye.xyz, fwd)) * fwd, 1.0);
        } else {
            let k = f.move_to / dot(v - camera.eye.xyz, fwd);
            out.position = camera.view_proj * vec4<f32>(camera.eye.xyz + k * (v - camera.eye.xyz), 1.0);
        }
    }
    let c = pixel_cast(f);
    out.ux_uy = vec4<f32>(c.ux, c.uy);
    out.o0_gxy = vec4<f32>(c.o0, c.g.xy);
    out.px0 = c.px0;
    out.gz_k_u_cz = vec4<f32>(c.g.z, c.one_minus_e2, c.u, c.cz);
    out.nx_tzx = vec4<f32>(c.nx, c.tzq.x);
    out.ny_tzy = vec4<f32>(c.ny, c.tzq.y);
    out.nz_tzz = vec4<f32>(c.nz, c.tzq.z);
    out.color = f.color;
    out.id = f.id;
    if THIN_EXACT {
        let a = transpose(c.a);
        let l = transpose(c.a_lo);
        out.a0_l0x = vec4<f32>(a[0], l[0].x);
        out.a1_l0y = vec4<f32>(a[1], l[0].y);
        out.a2_l0z = vec4<f32>(a[2], l[0].z);
        out.l1_lox = vec4<f32>(l[1], c.lo.x);
        out.l2_loy = vec4<f32>(l[2], c.lo.y);
        out.loz = c.lo.z;
    }
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
    let setup = pixel_cast(f);
    var quad: array<vec2<f32>, 4>;
    if THIN_EXACT {
        quad = quad_polygon(splat_clips(f));
    }
    for (var y = px.y; y <= px.w; y++) {
        var span: vec2<i32>;
        if THIN_EXACT {
            span = polygon_row(quad, y, px.x, px.z);
        } else {
            span = splat_row(setup, y, px.x, px.z);
        }
        for (var x = span.x; x <= span.y; x++) {
            let centre = vec2<f32>(f32(x) + 0.5, f32(y) + 0.5);
            var depth = -1.0;
            if THIN_EXACT {
                let h = thin_hit(setup, centre, 0u);
                if !h.miss && h.depth >= 0.0 && h.depth <= 1.0 {
                    depth = h.depth;
                }
            } else {
                depth = cast_depth(setup, splat_q(setup, centre));
            }
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

// The shadow map's depth of a splat pixel: the compute pass's hit is exact and its key is the
// depth's bits, so no ray is cast again.
fn splat_shadow_depth(ii: u32, px: vec2<f32>, key: u32) -> f32 {
    return key_depth(key);
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

// The front intersection of the pixel's ray, or discard.
fn ray_cast(in: VsOut) -> Hit {
    var c: PixelCast;
    c.ux = in.ux_uy.xy;
    c.uy = in.ux_uy.zw;
    c.o0 = in.o0_gxy.xy;
    c.px0 = in.px0;
    c.g = vec3<f32>(in.o0_gxy.zw, in.gz_k_u_cz.x);
    c.one_minus_e2 = in.gz_k_u_cz.y;
    c.u = in.gz_k_u_cz.z;
    c.cz = in.gz_k_u_cz.w;
    c.nx = in.nx_tzx.xyz;
    c.ny = in.ny_tzy.xyz;
    c.nz = in.nz_tzz.xyz;
    c.tzq = vec3<f32>(in.nx_tzx.w, in.ny_tzy.w, in.nz_tzz.w);
    if THIN_EXACT {
        c.a = transpose(mat3x3<f32>(in.a0_l0x.xyz, in.a1_l0y.xyz, in.a2_l0z.xyz));
        let l0 = vec3<f32>(in.a0_l0x.w, in.a1_l0y.w, in.a2_l0z.w);
        c.a_lo = transpose(mat3x3<f32>(l0, in.l1_lox.xyz, in.l2_loy.xyz));
        c.lo = vec3<f32>(in.l1_lox.w, in.l2_loy.w, in.loz);
    }
    let hit = cast_hit(c, in.position.xy, in.color);
    if hit.miss {
        discard;
    }
    return hit;
}

// The hit's p~ is (q.x x~ + q.y y~ − (u + α) z^)/(1 + uα) with α = √(1 − |q~|²) and u = 1/E
// (perspective: κ = uα/(1 + uα) in p~ = V~ − κ v~, m~ = −u z^, v~ = V~ + z^/u) or 0
// (orthographic: p~ = V~ − α z^): the view normal and the view z relative to the centre are
// linear in it, and nothing cancels.
fn cast_p(c: PixelCast, q: vec2<f32>, alpha: f32) -> vec3<f32> {
    return vec3<f32>(q, -(c.u + alpha));
}

// The hit's view z relative to the glyph's centre.
fn cast_z_rel(c: PixelCast, p: vec3<f32>, alpha: f32) -> f32 {
    return dot(c.tzq, p) / (1.0 + c.u * alpha);
}

// The front intersection of the ray through pixel centre px (miss: the ray passes the glyph).
fn cast_hit(c: PixelCast, px: vec2<f32>, color: u32) -> Hit {
    if THIN_EXACT {
        return thin_hit(c, px, color);
    }
    var hit: Hit;
    let q = splat_q(c, px);
    let q2 = dot(q, q);
    if q2 > 1.0 {
        hit.miss = true;
        return hit;
    }
    let alpha = sqrt(1.0 - q2);
    let p = cast_p(c, q, alpha);
    let n_view = normalize(mat3x3<f32>(c.nx, c.ny, c.nz) * p);
    // The hit lies on the pixel's ray: its direction is all shading needs of it.
    let ray_view = vec3<f32>(pixel_view_xy(px), -1.0);
    hit.color = vec4<f32>(shade(unpack4x8unorm(color).rgb, n_view, ray_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = cast_z_rel(c, p, alpha);
    hit.z_proxy_rel = dot(c.tzq, vec3<f32>(q, -c.u));
    hit.depth = view_depth(c.cz + hit.z_rel);
    return hit;
}

// --splat: glyphs whose proxy spans few pixels are ray cast per pixel in compute, not drawn.
// cs_frames finds each splat glyph's nearest hit per pixel and which glyph made it (one 64-bit
// atomic max, or a 32-bit one on depth and a second pass for the id: splat64.wgsl,
// splat32.wgsl), and a quad per 16-pixel tile they touch (vs_splat_tile + fs_splat*) shades them,
// depth-tested against the drawn glyphs.

// What a pixel's hit needs of a glyph, per glyph: q~ as a function of the pixel (splat_q), and
// what is linear in the hit's p~ (cast_p): so a pixel costs a few dozen operations. The vertex
// stage sends it flat to the fragments; the splats' loops use it directly.
struct PixelCast {
    // q~(px) = t(px) (o.x ux + o.y uy) with o = o(px) of pixel_offset, the pixel's view (x, y)
    // less the centre's (at distance 1 when perspective), t = (1 − E²)/(g · (xy, −1)) with
    // xy(px) the pixel's view-space (x, y) (orthographic: g = (0, 0, −1), 1 − E² = 1, so t = 1).
    ux: vec2<f32>,
    uy: vec2<f32>,
    // The centre ray's pixel and o(px0) (centre_ray).
    o0: vec2<f32>,
    px0: vec2<f32>,
    g: vec3<f32>,
    one_minus_e2: f32,
    // u = 1/E (perspective) or 0 (orthographic), as in cast_p.
    u: f32,
    // The view z of the glyph's centre.
    cz: f32,
    // N x~, N y~, N z^ (N = R_view T⁻ᵀ = R_view O diag(1/r)): the view normal is their
    // combination by cast_p.
    nx: vec3<f32>,
    ny: vec3<f32>,
    nz: vec3<f32>,
    // tz · x~, tz · y~, tz · z^: the view z relative to the centre, likewise.
    tzq: vec3<f32>,
    // THIN_EXACT: A = diag(1/r) Oᵀ R_viewᵀ (view to parameter space) in double-f32, and the
    // centre ray's residuals (param_map, CentreRay.lo), for thin_hit.
    a: mat3x3<f32>,
    a_lo: mat3x3<f32>,
    lo: vec3<f32>,
}

fn pixel_cast(f: GlyphFrame) -> PixelCast {
    var s: PixelCast;
    // Parameter space from view space: T⁻¹ R_viewᵀ = diag(1/r) Oᵀ R_viewᵀ = Nᵀ.
    let n = mat3x3<f32>(f.n0, f.n1, f.n2);
    let m = transpose(n);
    let r2 = dot(f.x_t, f.x_t);
    s.ux = vec2<f32>(dot(m[0], f.x_t), dot(m[0], f.y_t)) / r2;
    s.uy = vec2<f32>(dot(m[1], f.x_t), dot(m[1], f.y_t)) / r2;
    let cr = centre_ray(f.centre);
    let c_v = cr.c_view;
    s.o0 = cr.o0;
    s.px0 = cr.px0;
    var z_hat = f.ray_t;
    if is_ortho() {
        // The ray from (x, y, 0) in view space along the view direction keeps q~ while it
        // moves: take it level with the centre (in-plane offsets only, nothing to cancel).
        // t = 1.
        s.g = vec3<f32>(0.0, 0.0, -1.0);
        s.one_minus_e2 = 1.0;
    } else {
        // The ray e~ + t d~ meets the eye's polar plane e~ · p~ = 1 at t = (1 − E²)/(e~ · d~).
        // e~ and m~ both lie on the quad's axis, the eye's ray to the centre, so the in-plane
        // offset is t times that of the pixel ray's offset from the centre's ray, taken alone
        // (the whole d~, mostly along the axis, would cancel badly).
        let e_t = -f.ray_t;
        s.g = transpose(m) * e_t;
        s.one_minus_e2 = 1.0 - dot(e_t, e_t);
        s.u = f.u;
        z_hat = f.ray_t * f.u;
    }
    s.cz = c_v.z;
    s.nx = n * f.x_t;
    s.ny = n * f.y_t;
    s.nz = n * z_hat;
    let tz = vec3<f32>(f.tz_x, f.tz_y, f.tz_z);
    s.tzq = vec3<f32>(dot(tz, f.x_t), dot(tz, f.y_t), dot(tz, z_hat));
    if THIN_EXACT {
        let g = load_glyph(f.id - 1u);
        let m = param_map(g.rotation, g.radii);
        s.a = map_hi(m);
        s.a_lo = map_lo(m);
        s.lo = cr.lo;
    }
    return s;
}

// q~ at pixel centre `px` (framebuffer coordinates).
fn splat_q(s: PixelCast, px: vec2<f32>) -> vec2<f32> {
    let xy = pixel_view_xy(px);
    let o = pixel_offset(px, s.px0, s.o0);
    return (s.one_minus_e2 / (dot(s.g.xy, xy) - s.g.z)) * (o.x * s.ux + o.y * s.uy);
}

// The pixels of row y within [x0, x1] whose centres may see the glyph: |q~| ≤ 1 is
// (1 − E²)² |L|² ≤ D² with L = o.x ux + o.y uy and D = g · (xy, −1) both affine in the pixel's x,
// a quadratic inequality in x (splat_span; the depth test decides each pixel).
fn splat_row(s: PixelCast, y: i32, x0: i32, x1: i32) -> vec2<i32> {
    let start = vec2<f32>(f32(x0) + 0.5, f32(y) + 0.5);
    let xy = pixel_view_xy(start);
    let o = pixel_offset(start, s.px0, s.o0);
    let k = s.one_minus_e2;
    let l0 = k * (o.x * s.ux + o.y * s.uy);
    let lx = k * s.ux / camera.pixels.x;
    let d0 = dot(s.g.xy, xy) - s.g.z;
    let dx = s.g.x / camera.pixels.x;
    return splat_span(vec3<f32>(dot(lx, lx) - dx * dx, 2.0 * (dot(l0, lx) - d0 * dx), dot(l0, l0) - d0 * d0), x0, x1);
}

// THIN_EXACT: the front intersection of the pixel's ray (thin_pixel_ray in common.wgsl) with
// the unit ball of parameter space, the quad only choosing the pixels: the quad point q~ is a
// map of the pixel formed in f32, which a needle's k magnifies across its section.
fn thin_hit(c: PixelCast, px: vec2<f32>, color: u32) -> Hit {
    var hit: Hit;
    hit.miss = true;
    let r = thin_pixel_ray(px, vec3<f32>(0.0, 0.0, c.cz), c.px0, c.o0, c.a, Residuals(c.lo, c.a_lo));
    let alpha = dot(r.v_t, r.v_t);
    let beta = dot(r.o_t, r.v_t);
    let gamma = dot(r.o_t, r.o_t) - 1.0;
    let disc = beta * beta - alpha * gamma;
    if !(disc >= 0.0) {
        return hit;
    }
    // The nearer root, as q/α or γ/q (no cancellation).
    let qq = -(beta + select(-1.0, 1.0, beta >= 0.0) * sqrt(disc));
    var t = 0.0;
    if qq != 0.0 {
        t = min(qq / alpha, gamma / qq);
    }
    let p_t = r.o_t + t * r.v_t;
    // View-space normals from parameter space are Aᵀ.
    let n_view = normalize(transpose(c.a) * p_t);
    let ray_view = vec3<f32>(pixel_view_xy(px), -1.0);
    hit.miss = false;
    hit.color = vec4<f32>(shade(unpack4x8unorm(color).rgb, n_view, ray_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = (r.off + t * r.d).z;
    hit.z_proxy_rel = dot(c.tzq, vec3<f32>(splat_q(c, px), -c.u));
    hit.depth = view_depth(c.cz + hit.z_rel);
    return hit;
}

// The hit's depth at quad coordinates q (-1: no hit).
fn cast_depth(c: PixelCast, q: vec2<f32>) -> f32 {
    let q2 = dot(q, q);
    if q2 > 1.0 {
        return -1.0;
    }
    let alpha = sqrt(1.0 - q2);
    let depth = view_depth(c.cz + cast_z_rel(c, cast_p(c, q, alpha), alpha));
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(depth >= 0.0 && depth <= 1.0) {
        return -1.0;
    }
    return depth;
}

fn pixel_hit(f: GlyphFrame, px: vec2<f32>) -> Hit {
    var hit = cast_hit(pixel_cast(f), px, f.color);
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(hit.depth >= 0.0 && hit.depth <= 1.0) {
        hit.miss = true;
    }
    return hit;
}

// The pixels (first and last, inclusive) whose centres a glyph's proxy may cover, or none.
fn splat_pixels(f: GlyphFrame) -> vec4<i32> {
    return splat_pixel_rect(splat_clips(f));
}

// The proxy quad's corners as clip positions (strip order); THIN_EXACT: grown as vs_main draws
// it (quad_polygon).
fn splat_clips(f: GlyphFrame) -> array<vec4<f32>, 4> {
    var grow = vec2<f32>(1.0);
    if THIN_EXACT {
        grow = proxy_growth(f);
    }
    var clips: array<vec4<f32>, 4>;
    for (var k = 0u; k < 4u; k++) {
        let s = corner_signs(k) * grow;
        let v = f.centre + mat3x3<f32>(f.t0, f.t1, f.t2) * (f.m_t + s.x * f.x_t + s.y * f.y_t);
        clips[k] = camera.view_proj * vec4<f32>(v, 1.0);
    }
    return clips;
}
