// Sigg et al.'s method for capped elliptic cylinder glyphs (axis = the frame's first column,
// half-length radii.x, cross-section semi-axes radii.y, radii.z): the box is the union of the
// two end discs' eq. 5 boxes (T_cap = [[u, v, 0, c ± w], [0, 0, 0, 1]]), exact in front of the
// camera plane; per fragment the slab method of sigg-quadric.md §7 from the glyph-near origin.
// Composed as common.wgsl + cylinder_slab.wgsl + sigg.wgsl + this + outputs.wgsl.

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, bounding_radius(g.radii)) {
        return culled();
    }
    let o = quat_to_mat3(g.rotation);
    glyph_varyings(&out, g, o, ii + 1u);
    if !is_ortho() {
        let e_c = (transpose(o) * (camera.eye.xyz - g.centre)) / g.radii;
        if abs(e_c.x) <= 1.0 && dot(e_c.yz, e_c.yz) <= 1.0 {
            // Eye inside the glyph: not drawn (the reference agrees).
            return culled();
        }
    }
    let w = o[0] * g.radii.x;
    let u = o[1] * g.radii.y;
    let v = o[2] * g.radii.z;
    let b1 = quadric_box(u, v, vec3<f32>(0.0), g.centre - w);
    let b2 = quadric_box(u, v, vec3<f32>(0.0), g.centre + w);
    let b = hull_box(b1, b2);
    if b.kind == PROXY_CULL {
        return culled();
    }
    emit_corner(&out, vi, b);
    return out;
}

fn ray_cast(in: VsOut) -> Hit {
    let r = pixel_ray(in);
    let span = slab_span(r.o_t, r.v_t);
    // The entry if it lies in front of the ray's start, else (orthographic start inside the
    // glyph) the exit, as the reference does.
    var s = span.xy;
    if !(r.t0 + s.x > 0.0) {
        s = span.zw;
        if !(r.t0 + s.x > 0.0) {
            discard;
        }
    }
    let p_t = r.o_t + s.x * r.v_t;
    var n_t = vec3<f32>(s.y, 0.0, 0.0);
    if s.y == 0.0 {
        n_t = vec3<f32>(0.0, p_t.y, p_t.z);
    }
    return finish(in, r, s.x, n_t);
}
