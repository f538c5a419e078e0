// Solid glyphs (cylinders, capsules) ray cast on Gumhold's quad of a bounding ellipsoid
// (cylinder-capsule.md §5), in the glyph's local parameter space p~ = diag(1/scale) Oᵀ (p − c).
// The ray starts at the quad point V, next to the glyph: p = V + t v with v = V − e, in front of
// the eye for t > −1. When the eye is inside the bounding ellipsoid but outside the solid (near
// a cap), the proxy becomes the whole near plane. Orthographic rays are instead formed from the
// fragment's position (glyph_pixel_ray, as Sigg's method does): V interpolated across the quad
// is only as exact as an attribute plane rounded over the whole screen, and at the rims that
// error moves the nearly tangent ray's hit by more than the depth bound (perspective rays stay
// within it). The shape's own file, composed before this one, gives `solid_radius` (a bounding
// sphere's radius), `solid_of` (scale, bounding ellipsoid, shape parameter), `solid_contains` and
// `solid_entry` (entry t and local normal, discarding on a miss).

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The proxy point V in parameter space.
    @location(0) o_t: vec3<f32>,
    // The ray through V in parameter space, diag(1/scale) Oᵀ (V − e) (perspective only).
    @location(1) v_t: vec3<f32>,
    // V in view space.
    @location(2) v_view: vec3<f32>,
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
    // The glyph centre in view space: the orthographic ray's reference point.
    @location(10) @interpolate(flat) c_view: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    if !drawable(g.radii) || skip_glyph(g.centre, solid_radius(g.radii)) {
        out.position = CULLED_POSITION;
        return out;
    }
    let o = quat_to_mat3(g.rotation);
    let ot = transpose(o);
    let solid = solid_of(g, ii);
    let sc = solid.scale;
    let bound = solid.bound;
    let s = proxy_corner(vi);
    let e_c = (ot * (camera.eye.xyz - g.centre)) / sc;

    var v: vec3<f32>;
    var near = false;
    if is_ortho() {
        // Gumhold's orthographic quad of the bounding ellipsoid (m~ = 0, r~ = 1).
        let d_b = (ot * camera.forward.xyz) / sc / bound;
        let z_hat = normalize(d_b);
        let xy = orthonormal_pair(z_hat);
        v = g.centre + o * ((s.x * xy[0] + s.y * xy[1]) * bound * sc);
    } else {
        if solid_contains(e_c, solid.shape) {
            // Eye inside the glyph: not drawn (as for ellipsoids; the reference agrees).
            out.position = vec4<f32>(0.0, 0.0, -2.0, 1.0);
            return out;
        }
        let e_b = e_c / bound;
        let e2 = dot(e_b, e_b);
        if e2 > EYE_INSIDE_E2 {
            let e = sqrt(e2);
            let z_hat = -e_b / e;
            let xy = orthonormal_pair(z_hat);
            let vt = e_b / e2 + sqrt((e2 - 1.0) / e2) * (s.x * xy[0] + s.y * xy[1]);
            v = g.centre + o * (vt * bound * sc);
        } else {
            near = true;
            v = near_plane_point(near_plane_ndc(vi));
        }
    }
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    if near {
        // Exactly on the near plane: a round trip through the inverse could land in front of it.
        out.position = vec4<f32>(near_plane_ndc(vi), 0.0, 1.0);
    }
    out.o_t = (ot * (v - g.centre)) / sc;
    if !is_ortho() {
        out.v_t = (ot * (v - camera.eye.xyz)) / sc;
    }
    out.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
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
    out.c_view = (camera.view * vec4<f32>(g.centre, 1.0)).xyz;
    return out;
}

fn ray_cast(in: VsOut) -> Hit {
    if is_ortho() {
        return ray_cast_ortho(in);
    }
    // From the eye (t = −1).
    let entry = solid_entry(in.o_t, in.v_t, in.shape, -1.0);
    let t = entry.x;
    // t > −1 is in front of the eye; t < 0 is in front of the proxy.
    if t <= -1.0 {
        discard;
    }
    let p_view = (1.0 + t) * in.v_view;
    let delta_depth = -(t / (1.0 + t)) * camera.depth.x / (-in.v_view.z);
    let p_t = in.o_t + t * in.v_t;
    let n_t = entry.yzw;
    let n_view = normalize(in.n0 * n_t.x + in.n1 * n_t.y + in.n2 * n_t.z);
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = dot(in.tz, p_t);
    hit.z_proxy_rel = dot(in.tz, in.o_t);
    hit.depth = in.position.z + delta_depth;
    return hit;
}

fn ray_cast_ortho(in: VsOut) -> Hit {
    // Parameter space from view space is Nᵀ.
    let n = mat3x3<f32>(in.n0, in.n1, in.n2);
    let r = glyph_pixel_ray(in.position.xy, in.c_view, transpose(n));
    // The whole line: orthographic rays are clipped by the depth range.
    let entry = solid_entry(r.o_t, r.v_t, in.shape, -3.0e38);
    let t = entry.x;
    let off = r.off + t * r.d;
    let p_view = in.c_view + off;
    let n_view = normalize(n * entry.yzw);
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = off.z;
    // The flat variants leave the quad's depth, so the proxy's z stays V's.
    hit.z_proxy_rel = dot(in.tz, in.o_t);
    // From the hit's view z: the quad's rasterised depth belongs to V, not to this ray's origin.
    hit.depth = view_depth(p_view.z);
    return hit;
}
