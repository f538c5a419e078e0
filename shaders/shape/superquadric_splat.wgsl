// The compute prepass and splats (prepass.wgsl) for superquadrics on Gumhold's quad: composed
// after gumhold_solid.wgsl. cs_frames keeps the drawn glyphs' instance indices (4 bytes each;
// vs_frames rebuilds the quad from the instance, as vs_main does). A splat's pixels are ray cast
// as Sigg's fragments are (glyph_pixel_ray in common.wgsl): nothing interpolated, nothing large
// cancelling.

@group(1) @binding(1) var<storage, read_write> frames_out: array<u32>;

// The compute passes only order the splats' hits (the splat tiles' draw casts each pixel's
// winner again at full accuracy): the convex finder may stop at steps this long (sq_first_within),
// which leaves the hit within about its square.
const SQ_SPLAT_TOL: f32 = 1e-3;

@vertex
fn vs_frames(@builtin(vertex_index) vi: u32, @location(0) ii: u32) -> VsOut {
    return solid_vertex(vi, ii);
}

@compute @workgroup_size(64)
fn cs_frames(@builtin(global_invocation_id) gid: vec3<u32>) {
    let ii = prepass_glyph(gid.x);
    if ii == 0xffffffffu {
        return;
    }
    let g = load_glyph(ii);
    let o = quat_to_mat3(g.rotation);
    let solid = shape_of(g, ii);
    let q = solid_quad(g, o, solid);
    if !q.drawn {
        return;
    }
    if slice.splat_max > 0u && !q.near {
        let px = sq_splat_pixels(q);
        if splat_sized(px) {
            // A glyph covering no pixel centre has nothing to draw.
            if sq_splat(g, o, solid, ii + 1u, px, false) {
                splat_noted(ii, px);
            }
            return;
        }
    }
    frames_out[atomicAdd(&draw_args.instance_count, 1u)] = ii;
}

// The pixels whose centres the quad may cover.
fn sq_splat_pixels(q: SolidQuad) -> vec4<i32> {
    var clips: array<vec4<f32>, 4>;
    for (var k = 0u; k < 4u; k++) {
        let s = corner_signs(k);
        clips[k] = camera.view_proj * vec4<f32>(q.m + s.x * q.x + s.y * q.y, 1.0);
    }
    return splat_pixel_rect(clips);
}

// Splat glyph ii's pixels again (cs_splat_ids): the same functions on the same glyph, bit for
// bit the hits cs_frames had.
fn splat_glyph(ii: u32, second: bool) {
    let g = load_glyph(ii);
    let o = quat_to_mat3(g.rotation);
    let solid = shape_of(g, ii);
    sq_splat(g, o, solid, ii + 1u, sq_splat_pixels(solid_quad(g, o, solid)), second);
}

// Ray cast a splat's pixels px and keep its hits (splat_put) under `id`; whether any pixel was
// hit. Only the pixels whose rays may meet the ball holding the glyph (sq_row) are cast, and of
// them only those where no hit already kept is nearer than the glyph can be (the atomics only
// bring hits nearer, so a pixel skipped could not have been won).
fn sq_splat(g: Glyph, o: mat3x3<f32>, solid: Solid, id: u32, px: vec4<i32>, second: bool) -> bool {
    let s = sq_pixels_of(g, o, solid);
    let near_key = depth_key(max(-sq_near_z(s, o, solid), 0.0));
    var any = false;
    let rows = sq_rows(s, px.y, px.x);
    var y = px.y;
    var span = sq_row(rows, y, px.z);
    var x = span.x;
    loop {
        // To the next pixel to cast. Skipping is cheap and casting dear: lanes that skip run on
        // to their next cast here instead of idling while the others cast.
        loop {
            if x > span.y {
                y++;
                if y > px.w {
                    break;
                }
                span = sq_row(rows, y, px.z);
                x = span.x;
                continue;
            }
            if !splat_nearer(pixel_index(x, y), near_key) {
                break;
            }
            x++;
        }
        if y > px.w {
            break;
        }
        let hit = sq_pixel_hit(s, vec2<f32>(f32(x) + 0.5, f32(y) + 0.5), SQ_SPLAT_TOL);
        if !hit.miss {
            splat_put(pixel_index(x, y), sq_key_distance(s, hit), id, second);
            any = true;
        }
        x++;
    }
    return any;
}

// What a superquadric splat's depth key orders by (depth_key's argument): the hit's distance
// along the view axis, −z, not its depth. Both order alike, but the splat tiles' draw recovers the
// crossing from the key, and an f32 depth holds a point far from the near plane to only a few
// 1e-4 of the glyph's size, where −z holds it to 6e-8 of the distance.
fn sq_key_distance(s: SqPixels, hit: Hit) -> f32 {
    return -(s.c_view.z + hit.z_rel);
}

// The largest view z of the glyph (its nearest point; the view looks along −z): the nearer of
// the box's nearest corner and the ball's front, moved towards the eye by a hair more than the
// rounding of the centre's z.
fn sq_near_z(s: SqPixels, o: mat3x3<f32>, solid: Solid) -> f32 {
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let axes = rv * o;
    let box_reach = dot(abs(vec3<f32>(axes[0].z, axes[1].z, axes[2].z)), solid.scale);
    let ball_reach = s.shape.w * max(solid.scale.x, max(solid.scale.y, solid.scale.z));
    return s.c_view.z + min(box_reach, ball_reach) * 1.0001 + 1e-6 * abs(s.c_view.z);
}

// What a glyph's pixels need, once per glyph.
struct SqPixels {
    // The centre in view space, its centre ray's pixel px0 and o(px0) (centre_ray).
    c_view: vec3<f32>,
    px0: vec2<f32>,
    o0: vec2<f32>,
    // View space from parameter space for normals, R_view O diag(1/radii); its transpose maps
    // view-space offsets into parameter space.
    n: mat3x3<f32>,
    // Exponents and bounding ball (Solid.shape).
    shape: vec4<f32>,
    color: u32,
    // THIN_EXACT: the centre ray's and nᵀ's residuals.
    res: Residuals,
}

fn sq_pixels_of(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SqPixels {
    var s: SqPixels;
    let cr = centre_ray(g.centre);
    s.c_view = cr.c_view;
    s.px0 = cr.px0;
    s.o0 = cr.o0;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    s.n = rv * mat3x3<f32>(o[0] / solid.scale.x, o[1] / solid.scale.y, o[2] / solid.scale.z);
    s.shape = solid.shape;
    s.color = g.color;
    s.res = no_residuals();
    if THIN_EXACT {
        let m = param_map(g.rotation, solid.scale);
        s.n = mat3x3<f32>(m.r0, m.r1, m.r2);
        s.res = Residuals(cr.lo, map_lo(m));
    }
    return s;
}

// The rows of a splat's pixels whose rays may meet the ball holding the glyph (radius shape.w in
// parameter space; splat_span, sq_first deciding each pixel): the line through P with direction
// D meets it where |P × D|² <= w² |D|². P and D are affine in the pixel's x and y (perspective: P
// the eye, D the pixel's direction; orthographic: P the pixel's point, D the view direction), so
// in row y0 + t that is the quadratic a x² + b x + c <= 0 in x with b affine and c quadratic in t:
// their coefficients are formed once per glyph, a row costs three multiply-adds and its roots.
// P × D is formed next to the glyph (the eye's distance scales its rounding by 1e-7 only), so the
// roots are good to a small part of a pixel.
struct SqRows {
    // a; b's coefficients (1, t); c's (1, t, t²).
    a: f32,
    b: vec2<f32>,
    c: vec3<f32>,
    // The first row and the first column (x counts from it).
    y0: i32,
    x0: i32,
}

fn sq_rows(s: SqPixels, y0: i32, x0: i32) -> SqRows {
    let m = transpose(s.n);
    let xy = pixel_view_xy(vec2<f32>(f32(x0) + 0.5, f32(y0) + 0.5));
    // Parameter-space steps of one pixel along x and down y.
    let step_x = m * vec3<f32>(1.0 / camera.pixels.x, 0.0, 0.0);
    let step_y = m * vec3<f32>(0.0, -1.0 / camera.pixels.x, 0.0);
    // P × D = w + t dw + x wx and D = d + t dd + x dx.
    var w: vec3<f32>;
    var dw: vec3<f32>;
    var wx: vec3<f32>;
    var d: vec3<f32>;
    var dd = vec3<f32>(0.0);
    var dx = vec3<f32>(0.0);
    if is_ortho() {
        d = m * vec3<f32>(0.0, 0.0, -1.0);
        w = cross(m * vec3<f32>(xy - s.c_view.xy, 0.0), d);
        dw = cross(step_y, d);
        wx = cross(step_x, d);
    } else {
        let p = m * -s.c_view;
        d = m * vec3<f32>(xy, -1.0);
        dd = step_y;
        dx = step_x;
        w = cross(p, d);
        dw = cross(p, dd);
        wx = cross(p, dx);
    }
    let r2 = s.shape.w * s.shape.w;
    var rows: SqRows;
    rows.a = dot(wx, wx) - r2 * dot(dx, dx);
    rows.b = 2.0 * vec2<f32>(dot(w, wx) - r2 * dot(d, dx), dot(dw, wx) - r2 * dot(dd, dx));
    rows.c = vec3<f32>(dot(w, w) - r2 * dot(d, d), 2.0 * (dot(w, dw) - r2 * dot(d, dd)), dot(dw, dw) - r2 * dot(dd, dd));
    rows.y0 = y0;
    rows.x0 = x0;
    return rows;
}

// The pixels of row y within [rows.x0, x1] whose rays may meet the ball (sq_rows).
fn sq_row(rows: SqRows, y: i32, x1: i32) -> vec2<i32> {
    let t = f32(y - rows.y0);
    let c = rows.c.x + t * (rows.c.y + t * rows.c.z);
    return splat_span(vec3<f32>(rows.a, rows.b.x + t * rows.b.y, c), rows.x0, x1);
}

// The glyph's hit on the ray through pixel centre px (framebuffer coordinates), or a miss.
fn sq_pixel_hit(s: SqPixels, px: vec2<f32>, tol_min: f32) -> Hit {
    let r = glyph_pixel_ray(px, s.c_view, s.px0, s.o0, transpose(s.n), s.res);
    // From the eye; orthographic rays are clipped by the depth range.
    let h = sq_first_within(r.o_t, r.v_t, s.shape.xyz, select(-r.t0, -3.0e38, is_ortho()), s.shape.w, tol_min);
    if !h.hit {
        var hit: Hit;
        hit.miss = true;
        return hit;
    }
    return sq_hit_at(s, r, h.s, h.n);
}

// The hit at ray r's point t with local normal n (the gauge's gradient).
fn sq_hit_at(s: SqPixels, r: ParamRay, t: f32, n: vec3<f32>) -> Hit {
    var hit: Hit;
    hit.miss = true;
    let rel = r.off + t * r.d;
    let p_view = s.c_view + rel;
    hit.depth = view_depth(p_view.z);
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(hit.depth >= 0.0 && hit.depth <= 1.0) {
        return hit;
    }
    hit.miss = false;
    hit.n_view = normalize(s.n * n);
    hit.color = vec4<f32>(shade(unpack4x8unorm(s.color).rgb, hit.n_view, p_view), 1.0);
    hit.z_rel = rel.z;
    return hit;
}

// The splat's hit at pixel centre px (prepass.wgsl's splat_at), from the key the compute pass
// kept there (sq_key_distance): the finder at full tolerance, on the short stretch of the ray
// around the crossing the compute pass found, recovered from the key.
fn splat_hit(ii: u32, px: vec2<f32>, key: u32) -> Hit {
    var hit: Hit;
    hit.miss = true;
    // No key: a discarded pixel, which a CPU device may still run (a helper invocation).
    if key == 0u {
        return hit;
    }
    let g = load_glyph(ii);
    let s = sq_pixels_of(g, quat_to_mat3(g.rotation), shape_of(g, ii));
    let r = glyph_pixel_ray(px, s.c_view, s.px0, s.o0, transpose(s.n), s.res);
    // View z from the key, then the ray's t.
    let z = -bitcast<f32>(0xffffffffu - key);
    let t = (z - s.c_view.z - r.off.z) / r.d.z;
    // The crossing lies within rounding of t: z to half an ulp (z − c_view.z is then exact), the
    // rest to a few ulps of its terms; δ before it the ray is outside, and from there the finder
    // converges as from the box entry, in about two evaluations. The compute pass's crossing was
    // before the true one by at most its tolerance (a nearly grazing ray).
    let delta = 2.4e-7 * (abs(z) + abs(r.off.z) + abs(t * r.d.z)) / abs(r.d.z);
    let span = vec2<f32>(t - delta, t + delta + 2.0 * SQ_SPLAT_TOL / length(r.v_t));
    if !(span.x < span.y) {
        return hit;
    }
    let h = sq_first_in(r.o_t, r.v_t, s.shape.xyz, -3.0e38, span, 0.0);
    if !h.hit {
        return hit;
    }
    return sq_hit_at(s, r, h.s, h.n);
}

// The shadow map's depth of a splat pixel: the compute pass's key is a view distance (not a
// depth, as the ellipsoid's is), found to the convex finder's tolerance: before the true
// crossing by at most 1e-3 of the glyph's parameter space, far inside the map's depth bias.
fn splat_shadow_depth(ii: u32, px: vec2<f32>, key: u32) -> f32 {
    return view_depth(-key_depth(key));
}
