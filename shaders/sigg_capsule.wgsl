// Sigg et al.'s method for capsule glyphs (the segment of half-length h along the frame's first
// column swept by a ball of radius R, capsule_of in capsule.wgsl): the box is the union of the
// two end balls' eq. 5 boxes (cylinder-capsule.md §5), exact in front of the camera plane; per
// fragment §4 from the glyph-near origin, in capsule space (the varyings are set up with the
// radii (R, R, R), so pixel_ray and finish work there unchanged).
// Composed as common.wgsl + capsule.wgsl + sigg.wgsl + this + outputs.wgsl.

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, bounding_radius(g.radii)) {
        return culled();
    }
    let o = quat_to_mat3(g.rotation);
    let cap = capsule_of(g.radii);
    var ball = g;
    ball.radii = vec3<f32>(cap.y);
    glyph_varyings(&out, ball, o, ii + 1u);
    out.shape = vec4<f32>(cap.x, 0.0, 0.0, 0.0);
    if !is_ortho() {
        let e_c = (transpose(o) * (camera.eye.xyz - g.centre)) / cap.y;
        if capsule_contains(e_c, cap.x) {
            // Eye inside the glyph: not drawn (the reference agrees).
            return culled();
        }
    }
    let w = o[0] * (cap.x * cap.y);
    let b1 = quadric_box(o[0] * cap.y, o[1] * cap.y, o[2] * cap.y, g.centre - w);
    let b2 = quadric_box(o[0] * cap.y, o[1] * cap.y, o[2] * cap.y, g.centre + w);
    let b = hull_box(b1, b2);
    if b.kind == PROXY_CULL {
        return culled();
    }
    emit_corner(&out, vi, b);
    return out;
}

fn ray_cast(in: VsOut) -> Hit {
    var r = pixel_ray(in);
    let h = in.shape.x;
    // pixel_ray's origin is the ray point nearest the centre, which for a long capsule can lie
    // k = h + 1 radii from where the ray passes the axis: there |o~.yz|² − 1 loses the 1 in f32.
    // Slide it to the point nearest the axis (β ≈ 0 for the side), kept within the balls' reach.
    let a = dot(r.v_t.yz, r.v_t.yz);
    if a > 0.0 {
        var s = -dot(r.o_t.yz, r.v_t.yz) / a;
        let x = r.o_t.x + s * r.v_t.x;
        if abs(x) > h + 1.0 && r.v_t.x != 0.0 {
            s = (clamp(x, -h - 1.0, h + 1.0) - r.o_t.x) / r.v_t.x;
        }
        r.off += s * r.d;
        r.t0 += s;
        r.o_t += s * r.v_t;
    }
    let span = capsule_span(r.o_t, r.v_t, h);
    // The entry if it lies in front of the ray's start, else (orthographic start inside the
    // glyph) the exit, as the reference does.
    var t = span.x;
    if !(r.t0 + t > 0.0) {
        t = span.y;
        if !(r.t0 + t > 0.0) {
            discard;
        }
    }
    return finish(in, r, t, capsule_normal(r.o_t + t * r.v_t, h));
}
