// Sigg et al.'s method for superquadric glyphs: the solid lies in its local unit box (third
// column the symmetry axis, half-sizes the radii) and in the ellipsoid of semi-axes s·radii
// (s = sq_bound: 1 for an ellipsoid, √2 for a cylinder, √3 for a cube), so the screen box is the
// intersection of the hull of the box's eight projected corners and the ellipsoid's eq. 5 box
// (both exact in front of the camera plane; the first is tighter for boxy glyphs, the second for
// round ones), and a frustum plane is missed when it misses all eight corners. Per fragment the first crossing from the glyph-near origin by
// superquadric.wgsl (docs/book/src/developer/superquadric-derivation.md §6).
// Composed as common.wgsl + superquadric.wgsl + sigg.wgsl + this + outputs.wgsl.

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, length(g.radii)) {
        return culled();
    }
    let o = quat_to_mat3(g.rotation);
    let e = load_exponents(ii);
    let bound = sq_bound(e);
    glyph_varyings(&out, g, o, ii + 1u);
    out.shape = vec4<f32>(e, bound);
    if !is_ortho() {
        let e_t = (transpose(o) * (camera.eye.xyz - g.centre)) / g.radii;
        if sq_contains(e_t, e) {
            // Eye inside the glyph: not drawn (the reference agrees).
            return culled();
        }
    }
    let mc = camera.view_proj * vec4<f32>(g.centre, 1.0);
    let mu = camera.view_proj * vec4<f32>(o[0] * g.radii.x, 0.0);
    let mv = camera.view_proj * vec4<f32>(o[1] * g.radii.y, 0.0);
    let mw = camera.view_proj * vec4<f32>(o[2] * g.radii.z, 0.0);
    var b: SiggBox;
    b.reach_a = vec3<f32>(
        box_reach(mc.w + mc.x, mu.w + mu.x, mv.w + mv.x, mw.w + mw.x),
        box_reach(mc.w - mc.x, mu.w - mu.x, mv.w - mv.x, mw.w - mw.x),
        box_reach(mc.w + mc.y, mu.w + mu.y, mv.w + mv.y, mw.w + mw.y),
    );
    b.reach_b = vec3<f32>(
        box_reach(mc.w - mc.y, mu.w - mu.y, mv.w - mv.y, mw.w - mw.y),
        box_reach(mc.z, mu.z, mv.z, mw.z),
        box_reach(mc.w - mc.z, mu.w - mu.z, mv.w - mv.z, mw.w - mw.z),
    );
    if outside_frustum(b) {
        return culled();
    }
    var lo = vec2<f32>(3.0e38);
    var hi = vec2<f32>(-3.0e38);
    var in_front = 0u;
    for (var k = 0u; k < 8u; k++) {
        let s = vec3<f32>(
            select(-1.0, 1.0, (k & 1u) != 0u),
            select(-1.0, 1.0, (k & 2u) != 0u),
            select(-1.0, 1.0, (k & 4u) != 0u),
        );
        let p = mc + s.x * mu + s.y * mv + s.z * mw;
        if p.w > 0.0 {
            in_front += 1u;
            lo = min(lo, p.xy / p.w);
            hi = max(hi, p.xy / p.w);
        }
    }
    if in_front == 0u {
        return culled();
    }
    if in_front == 8u {
        let q = quadric_box(o[0] * (bound * g.radii.x), o[1] * (bound * g.radii.y), o[2] * (bound * g.radii.z), g.centre);
        b.kind = PROXY_BOX;
        b.lo = lo;
        b.hi = hi;
        if q.kind == PROXY_BOX {
            b.lo = max(lo, q.lo);
            b.hi = min(hi, q.hi);
        }
        b.z = clamp(mc.z / mc.w, 0.0, 1.0);
    } else {
        // The box crosses the camera plane.
        b.kind = PROXY_VIEWPORT;
    }
    emit_corner(&out, vi, b);
    return out;
}

// max over s ∈ [−1, 1]³ of c + s·(u, v, w).
fn box_reach(c: f32, u: f32, v: f32, w: f32) -> f32 {
    return c + abs(u) + abs(v) + abs(w);
}

fn ray_cast(in: VsOut) -> Hit {
    let r = pixel_ray(in);
    // The first crossing in front of the ray's start (eye, or the orthographic camera plane).
    let h = sq_first(r.o_t, r.v_t, in.shape.xyz, -r.t0, in.shape.w);
    if !h.hit {
        discard;
    }
    return finish(in, r, h.s, h.n);
}
