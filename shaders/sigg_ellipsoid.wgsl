// Sigg et al.'s method for ellipsoid glyphs: the box of eq. 5 with T's columns r_i O_i, and the
// stable parameter-space roots of sigg-quadric.md §4 per fragment. Composed as common.wgsl +
// sigg.wgsl + this + outputs.wgsl.

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
        let e_t = (transpose(o) * (camera.eye.xyz - g.centre)) / g.radii;
        if !(dot(e_t, e_t) > EYE_INSIDE_E2) {
            return culled();
        }
    }
    let b = quadric_box(o[0] * g.radii.x, o[1] * g.radii.y, o[2] * g.radii.z, g.centre);
    if b.kind == PROXY_CULL || outside_frustum(b) {
        return culled();
    }
    emit_corner(&out, vi, b);
    return out;
}

fn ray_cast(in: VsOut) -> Hit {
    let r = pixel_ray(in);
    let alpha = dot(r.v_t, r.v_t);
    let beta = dot(r.o_t, r.v_t);
    let gamma = dot(r.o_t, r.o_t) - 1.0;
    let disc = beta * beta - alpha * gamma;
    if !(disc >= 0.0) {
        discard;
    }
    // Stable roots q/α and γ/q; the nearer one in front of the origin (the farther one only
    // from inside, orthographic).
    let q = -(beta + select(-1.0, 1.0, beta >= 0.0) * sqrt(disc));
    var r1 = 0.0;
    var r2 = 0.0;
    if q != 0.0 {
        r1 = q / alpha;
        r2 = gamma / q;
    }
    var tp = min(r1, r2);
    if !(r.t0 + tp > 0.0) {
        tp = max(r1, r2);
        if !(r.t0 + tp > 0.0) {
            discard;
        }
    }
    return finish(in, r, tp, r.o_t + tp * r.v_t);
}
