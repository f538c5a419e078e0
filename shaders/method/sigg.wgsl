// Sigg et al.'s method: one screen-space bounding box per glyph, the kind's `shape_box` (Sigg
// eq. 5 for quadrics; shaders/shape/screen_box.wgsl), drawn as an instanced 4-vertex strip at
// its NDC corners, and a per-pixel ray rebuilt from @builtin(position) and the camera, solved in
// the kind's parameter space (`shape_cast`) from a glyph-near origin. Math:
// shared/math/sigg-quadric.md §2, §4, §7. Twin of the vertex stage: src/twin/sigg.rs. Composed
// as common.wgsl + shape/screen_box.wgsl + the kind's shape file(s) + this + outputs.wgsl.
// The fragment stage works in view space, its rays taken from the whole image's centre and
// pixel scale (a tile's projection is off-centre).

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The box point in view space (at the proxy depth): the flat variants' view z.
    @location(0) v_view: vec3<f32>,
    @location(1) @interpolate(flat) id: u32,
    @location(2) @interpolate(flat) color: u32,
    // The glyph centre in view space.
    @location(3) @interpolate(flat) c_view: vec3<f32>,
    // Rows of A = diag(1/scale) Oᵀ R_viewᵀ (view to the glyph's parameter space, `shape_of`'s
    // scale); Aᵀ maps parameter-space normals to view space.
    @location(4) @interpolate(flat) a0: vec3<f32>,
    @location(5) @interpolate(flat) a1: vec3<f32>,
    @location(6) @interpolate(flat) a2: vec3<f32>,
    // Shape parameters of the glyph kind (capsules: x, the segment's half-length in units of R;
    // superquadrics: the exponents α, β, c and the bounding ball's radius).
    @location(7) @interpolate(flat) shape: vec4<f32>,
    // The centre ray's pixel px0 and o(px0) (centre_ray in common.wgsl).
    @location(8) @interpolate(flat) px0_o0: vec4<f32>,
    // THIN_EXACT: the residuals of the centre ray (CentreRay.lo) and of A's rows.
    @location(9) @interpolate(flat) lo: vec3<f32>,
    @location(10) @interpolate(flat) a0_lo: vec3<f32>,
    @location(11) @interpolate(flat) a1_lo: vec3<f32>,
    @location(12) @interpolate(flat) a2_lo: vec3<f32>,
}

// The flat per-glyph varyings of glyph g with frame o and parameter-space scale `scale`.
fn glyph_varyings(out: ptr<function, VsOut>, g: Glyph, o: mat3x3<f32>, scale: vec3<f32>, id: u32) {
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    (*out).id = id;
    (*out).color = g.color;
    let cr = centre_ray(g.centre);
    (*out).c_view = cr.c_view;
    (*out).px0_o0 = vec4<f32>(cr.px0, cr.o0);
    (*out).a0 = rv * o[0] / scale.x;
    (*out).a1 = rv * o[1] / scale.y;
    (*out).a2 = rv * o[2] / scale.z;
    if THIN_EXACT {
        let m = param_map(g.rotation, scale);
        (*out).a0 = m.r0;
        (*out).a1 = m.r1;
        (*out).a2 = m.r2;
        (*out).a0_lo = m.l0;
        (*out).a1_lo = m.l1;
        (*out).a2_lo = m.l2;
        (*out).lo = cr.lo;
    }
}

// Corner vi of the strip ((−,−), (+,−), (−,+), (+,+)) of the box, or of the whole viewport at
// the near plane; position and view-space point. The box is widened by PROXY_MARGIN_PX and
// clamped to the viewport.
fn emit_corner(out: ptr<function, VsOut>, vi: u32, b: SiggBox) {
    let k = vec2<bool>((vi & 1u) != 0u, (vi & 2u) != 0u);
    var ndc = vec3<f32>(select(vec2<f32>(-1.0), vec2<f32>(1.0), k), 0.0);
    if b.kind == PROXY_BOX {
        let margin = 2.0 * PROXY_MARGIN_PX * camera.viewport.zw;
        ndc = vec3<f32>(clamp(select(b.lo - margin, b.hi + margin, k), vec2<f32>(-1.0), vec2<f32>(1.0)), clamp(b.z, 0.0, 1.0));
    }
    (*out).position = vec4<f32>(ndc, 1.0);
    let h = camera.inv_view_proj * vec4<f32>(ndc, 1.0);
    (*out).v_view = (camera.view * vec4<f32>(h.xyz / h.w, 1.0)).xyz;
}

// Outside the clip volume (z < 0): all four corners are clipped away.
fn culled() -> VsOut {
    var out: VsOut;
    out.position = vec4<f32>(0.0, 0.0, -2.0, 1.0);
    return out;
}

// The fragment's ray (glyph_pixel_ray in common.wgsl, shared with Gumhold's orthographic solids).
fn pixel_ray(in: VsOut) -> ParamRay {
    let res = Residuals(in.lo, transpose(mat3x3<f32>(in.a0_lo, in.a1_lo, in.a2_lo)));
    return glyph_pixel_ray(in.position.xy, in.c_view, in.px0_o0.xy, in.px0_o0.zw, transpose(mat3x3<f32>(in.a0, in.a1, in.a2)), res);
}

// Shade the hit at t' along the ray from the glyph-near origin with parameter-space normal n_t;
// depth from the hit point (standard Z).
fn finish(in: VsOut, r: ParamRay, tp: f32, n_t: vec3<f32>) -> Hit {
    let p_view = in.c_view + r.off + tp * r.d;
    let n_view = normalize(mat3x3<f32>(in.a0, in.a1, in.a2) * n_t);
    var hit: Hit;
    let a = mat3x3<f32>(in.a0, in.a1, in.a2);
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let local = r.o_t + tp * r.v_t;
    let base = shape_tint(transpose(rv) * (a * local), local, in.shape, unpack4x8unorm(in.color).rgb);
    hit.color = vec4<f32>(shade(base, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = (r.off + tp * r.d).z;
    hit.z_proxy_rel = in.v_view.z - in.c_view.z;
    hit.depth = view_depth(p_view.z);
    return hit;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, shape_radius(g.radii)) {
        return culled();
    }
    let o = quat_to_mat3(g.rotation);
    let solid = shape_of(g, ii);
    glyph_varyings(&out, g, o, solid.scale, ii + 1u);
    out.shape = solid.shape;
    if !is_ortho() {
        let e_t = (transpose(o) * (camera.eye.xyz - g.centre)) / solid.scale;
        if shape_contains(e_t, solid.shape) {
            // Eye inside the glyph: not drawn (the reference agrees).
            return culled();
        }
    }
    let b = shape_box(g, o, solid);
    if b.kind == PROXY_CULL {
        return culled();
    }
    emit_corner(&out, vi, b);
    return out;
}

fn ray_cast(in: VsOut) -> Hit {
    var r = pixel_ray(in);
    let h = shape_cast(&r, in.shape);
    return finish(in, r, h.x, h.yzw);
}
