// Gumhold's method for every kind but the ellipsoid (whose exact quad is gumhold_ellipsoid.wgsl):
// the glyph ray cast on Gumhold's quad of a bounding ellipsoid (cylinder-capsule.md §5), in the
// glyph's local parameter space p~ = diag(1/scale) Oᵀ (p − c). The quad only chooses the
// fragments: each casts its own pixel's ray (ray_cast). When the eye is inside the bounding
// ellipsoid but outside the solid (near a cap), the proxy becomes the whole near plane. The
// kind's shape file (the interface in common.wgsl's `Solid`) gives the bounding sphere
// (`shape_radius`), the scale, bounding ellipsoid and parameters (`shape_of`), the eye test
// (`shape_contains`) and the entry (`shape_entry`: t and local normal, discarding on a miss).

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The proxy point V in parameter space: the flat variants' view z (they keep its depth).
    @location(0) o_t: vec3<f32>,
    @location(3) @interpolate(flat) id: u32,
    @location(4) @interpolate(flat) color: u32,
    // Columns of N = R_view O diag(1/scale): view normal = N n~.
    @location(5) @interpolate(flat) n0: vec3<f32>,
    @location(6) @interpolate(flat) n1: vec3<f32>,
    @location(7) @interpolate(flat) n2: vec3<f32>,
    // Row 2 of R_view O diag(scale): the hit's view z relative to the centre is tz · p~.
    @location(8) @interpolate(flat) tz: vec3<f32>,
    // The shape's parameters (a capsule's segment half-length in units of its radius; a
    // superquadric's exponents and bounding ball).
    @location(9) @interpolate(flat) shape: vec4<f32>,
    // The glyph centre in view space: the rays' reference point.
    @location(10) @interpolate(flat) c_view: vec3<f32>,
    // The centre ray's pixel px0 and o(px0) (centre_ray in common.wgsl).
    @location(12) @interpolate(flat) px0_o0: vec4<f32>,
    // THIN_EXACT: the residuals of the centre ray (CentreRay.lo) and of N's columns.
    @location(1) @interpolate(flat) lo: vec3<f32>,
    @location(2) @interpolate(flat) n0_lo: vec3<f32>,
    @location(11) @interpolate(flat) n1_lo: vec3<f32>,
    @location(13) @interpolate(flat) n2_lo: vec3<f32>,
}

// The quad of a glyph's bounding ellipsoid (g, its rotation o, shape_of): corner s at
// m + s.x x + s.y y (world), or (near) the whole near plane; not `drawn` when the glyph is
// degenerate, culled or holds the eye.
struct SolidQuad {
    drawn: bool,
    near: bool,
    m: vec3<f32>,
    x: vec3<f32>,
    y: vec3<f32>,
}

fn solid_quad(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SolidQuad {
    var q: SolidQuad;
    if !drawable(g.radii) || skip_glyph(g.centre, shape_radius(g.radii)) {
        return q;
    }
    let ot = transpose(o);
    // World offsets from the bounding ellipsoid's parameter space.
    let t = o * mat3x3<f32>(vec3<f32>(solid.bound.x * solid.scale.x, 0.0, 0.0), vec3<f32>(0.0, solid.bound.y * solid.scale.y, 0.0), vec3<f32>(0.0, 0.0, solid.bound.z * solid.scale.z));
    var z_hat: vec3<f32>;
    var radius = 1.0;
    q.m = g.centre;
    if is_ortho() {
        // Gumhold's orthographic quad of the bounding ellipsoid (m~ = 0, r~ = 1).
        z_hat = normalize((ot * camera.forward.xyz) / solid.scale / solid.bound);
    } else {
        let e_c = (ot * (camera.eye.xyz - g.centre)) / solid.scale;
        if shape_contains(e_c, solid.shape) {
            // Eye inside the glyph: not drawn (as for ellipsoids; the reference agrees).
            return q;
        }
        let e_b = e_c / solid.bound;
        let e2 = dot(e_b, e_b);
        if !(e2 > EYE_INSIDE_E2) {
            q.drawn = true;
            q.near = true;
            return q;
        }
        let e = sqrt(e2);
        z_hat = -e_b / e;
        q.m += t * (e_b / e2);
        radius = sqrt((e2 - 1.0) / e2);
        // The quad's plane lies on the eye's side of the bounding ellipsoid's silhouette: in
        // front of the near plane while the glyph reaches beyond it, the quad would be clipped
        // away whole, and a non-convex glyph's parts behind the near plane (seen past parts in
        // front of it, as the reference sees them) with it. The near-plane proxy draws them.
        let f = camera.forward.xyz;
        let near = camera.depth.z;
        if dot(q.m - camera.eye.xyz, f) < near && dot(g.centre - camera.eye.xyz, f) + shape_radius(g.radii) > near {
            q.drawn = true;
            q.near = true;
            return q;
        }
    }
    let xy = orthonormal_pair(z_hat);
    q.x = t * (radius * xy[0]);
    q.y = t * (radius * xy[1]);
    q.drawn = true;
    return q;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    return solid_vertex(vi, ii);
}

// Vertex vi of glyph ii's proxy.
fn solid_vertex(vi: u32, ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    let o = quat_to_mat3(g.rotation);
    let solid = shape_of(g, ii);
    let q = solid_quad(g, o, solid);
    if !q.drawn {
        out.position = CULLED_POSITION;
        return out;
    }
    let ot = transpose(o);
    let sc = solid.scale;
    let s = proxy_corner(vi) * margin_growth(g.centre, q.x, q.y);
    var v = q.m + s.x * q.x + s.y * q.y;
    if q.near {
        v = near_plane_point(near_plane_ndc(vi));
    }
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    if q.near {
        // Exactly on the near plane: a round trip through the inverse could land in front of it.
        out.position = vec4<f32>(near_plane_ndc(vi), 0.0, 1.0);
    }
    out.o_t = (ot * (v - g.centre)) / sc;
    out.id = ii + 1u;
    out.color = g.color;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let n = rv * mat3x3<f32>(o[0] / sc.x, o[1] / sc.y, o[2] / sc.z);
    out.n0 = n[0];
    out.n1 = n[1];
    out.n2 = n[2];
    let r2 = vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z);
    out.tz = (ot * r2) * sc;
    out.shape = solid.shape;
    let cr = centre_ray(g.centre);
    out.c_view = cr.c_view;
    out.px0_o0 = vec4<f32>(cr.px0, cr.o0);
    if THIN_EXACT {
        // N's columns are A's rows (parameter space from view space is Nᵀ).
        let m = param_map(g.rotation, sc);
        out.n0 = m.r0;
        out.n1 = m.r1;
        out.n2 = m.r2;
        out.n0_lo = m.l0;
        out.n1_lo = m.l1;
        out.n2_lo = m.l2;
        out.lo = cr.lo;
    }
    return out;
}

// Every fragment casts its own pixel's ray from a glyph-near origin (glyph_pixel_ray, as
// Sigg's): nothing interpolated, and the pixel's offset from the centre's ray formed in
// double-f32 once per glyph (centre_ray). Rays through the interpolated quad point V were only
// as exact as an attribute plane rounded over the whole screen: grid40's cylinders had depth p99
// 8.8e-5 of the radius that way, 6.5e-7 this way. Perspective rays take what lies in front of
// the eye, orthographic ones the whole line (the depth range clips them).
fn ray_cast(in: VsOut) -> Hit {
    let n = mat3x3<f32>(in.n0, in.n1, in.n2);
    // Parameter space from view space is Nᵀ.
    let res = Residuals(in.lo, transpose(mat3x3<f32>(in.n0_lo, in.n1_lo, in.n2_lo)));
    let r = glyph_pixel_ray(in.position.xy, in.c_view, in.px0_o0.xy, in.px0_o0.zw, transpose(n), res);
    let o_t = r.o_t;
    let v_t = r.v_t;
    let entry = shape_entry(o_t, v_t, in.shape, select(-r.t0, -3.0e38, is_ortho()));
    let t = entry.x;
    var hit: Hit;
    if !(is_ortho() || r.t0 + t > 0.0) {
        discard;
    }
    let off = r.off + t * r.d;
    let p_view = in.c_view + off;
    hit.z_rel = off.z;
    // From the hit's view z: the quad's rasterised depth belongs to V, not to this ray's origin.
    hit.depth = view_depth(p_view.z);
    let n_view = normalize(n * entry.yzw);
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let local = o_t + t * v_t;
    let base = shape_tint(transpose(rv) * (n * local), local, in.shape, unpack4x8unorm(in.color).rgb);
    hit.color = vec4<f32>(shade(base, n_view, p_view), 1.0);
    hit.n_view = n_view;
    // The flat variants leave the quad's depth, so the proxy's z stays V's.
    hit.z_proxy_rel = dot(in.tz, in.o_t);
    return hit;
}
