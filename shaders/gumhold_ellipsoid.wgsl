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
    // (q~x, q~y): the proxy corner in the unit circle's plane, interpolated.
    @location(0) q: vec2<f32>,
    // V~: the quad point in parameter space.
    @location(1) vt_quad: vec3<f32>,
    // v~ = V~ − e~ (perspective) or z^ (orthographic): the ray in parameter space.
    @location(2) vt_ray: vec3<f32>,
    // The quad point in view space.
    @location(3) v_view: vec3<f32>,
    // u~ = 1/E (perspective) or 1/|d~| (orthographic).
    @location(4) @interpolate(flat) u: f32,
    @location(5) @interpolate(flat) id: u32,
    @location(6) @interpolate(flat) color: u32,
    // Columns of N = R_view T⁻¹: the view-space normal is N p~.
    @location(7) @interpolate(flat) n0: vec3<f32>,
    @location(8) @interpolate(flat) n1: vec3<f32>,
    @location(9) @interpolate(flat) n2: vec3<f32>,
    // Row 2 of R_view T: the hit's view z relative to the centre is tz · p~.
    @location(10) @interpolate(flat) tz: vec3<f32>,
    // Clip (z, w) of the quad point (before any move): its depth is z / w.
    @location(11) zw: vec2<f32>,
    // The move factor s_k (see above).
    @location(12) s: f32,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    let r_max = max(g.radii.x, max(g.radii.y, g.radii.z));
    if !drawable(g.radii) || skip_glyph(g.centre, bounding_radius(g.radii)) {
        out.position = CULLED_POSITION;
        return out;
    }
    let o = quat_to_mat3(g.rotation);
    let ot = transpose(o);
    let rinv = 1.0 / g.radii;
    let s = proxy_corner(vi);

    var z_hat: vec3<f32>;
    var m_t = vec3<f32>(0.0);
    var r_t = 1.0;
    if is_ortho() {
        let d_t = o * ((ot * camera.forward.xyz) * rinv);
        let len = length(d_t);
        z_hat = d_t / len;
        out.u = 1.0 / len;
    } else {
        let e_t = o * ((ot * (camera.eye.xyz - g.centre)) * rinv);
        let e2 = dot(e_t, e_t);
        if !(e2 > EYE_INSIDE_E2) {
            out.position = CULLED_POSITION;
            return out;
        }
        let e = sqrt(e2);
        z_hat = -e_t / e;
        m_t = e_t / e2;
        r_t = sqrt((e2 - 1.0) / e2);
        out.u = 1.0 / e;
    }
    let xy = orthonormal_pair(z_hat);
    let vt_quad = m_t + r_t * (s.x * xy[0] + s.y * xy[1]);
    let v = g.centre + o * ((ot * vt_quad) * g.radii);
    let clip = camera.view_proj * vec4<f32>(v, 1.0);
    var k = 1.0;
    if CONSERVATIVE_DEPTH {
        // Nearest view distance of the ellipsoid: centre's minus its support |diag(r) Oᵀ f|.
        let f = camera.forward.xyz;
        let d_c = dot(g.centre - camera.eye.xyz, f);
        let d_min = d_c - length(g.radii * (ot * f));
        if is_ortho() && d_min > camera.depth.z {
            out.position = camera.view_proj * vec4<f32>(v + (d_min - dot(v - camera.eye.xyz, f)) * f, 1.0);
        } else if !is_ortho() && d_c - 1.5 * r_max > camera.depth.z {
            // Every proxy vertex lies within 1.5 r_max of the centre (|V~|² ≤ 1/E² + r~²|q~|²
            // ≤ 2), so all are in front of the near plane and can be scaled about the eye.
            k = max(d_min, camera.depth.z) / dot(v - camera.eye.xyz, f);
            out.position = camera.view_proj * vec4<f32>(camera.eye.xyz + k * (v - camera.eye.xyz), 1.0);
        } else {
            out.position = clip;
        }
    } else {
        out.position = clip;
    }
    out.s = k;
    out.zw = k * clip.zw;
    out.q = k * s;
    out.vt_quad = k * vt_quad;
    if is_ortho() {
        out.vt_ray = k * z_hat;
    } else {
        out.vt_ray = k * (vt_quad + z_hat / out.u);
    }
    out.v_view = k * (camera.view * vec4<f32>(v, 1.0)).xyz;
    out.id = ii + 1u;
    out.color = g.color;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    let n = rv * o * mat3x3<f32>(ot[0] * rinv, ot[1] * rinv, ot[2] * rinv);
    out.n0 = n[0];
    out.n1 = n[1];
    out.n2 = n[2];
    let r2 = vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z);
    out.tz = o * ((ot * r2) * g.radii);
    return out;
}

// The front intersection of the pixel's ray, or discard.
fn ray_cast(in_moved: VsOut) -> Hit {
    var in = in_moved;
    if CONSERVATIVE_DEPTH {
        let inv = 1.0 / in.s;
        in.q *= inv;
        in.vt_quad *= inv;
        in.vt_ray *= inv;
        in.v_view *= inv;
    }
    let q2 = dot(in.q, in.q);
    if q2 > 1.0 {
        discard;
    }
    let alpha = sqrt(1.0 - q2);
    var kappa: f32;
    var p_view: vec3<f32>;
    var delta_depth: f32;
    if is_ortho() {
        // p = V + τ d with τ = −α/|d~|; the view depth grows by α/|d~|.
        kappa = alpha;
        p_view = in.v_view + vec3<f32>(0.0, 0.0, alpha * in.u);
        delta_depth = camera.depth.y * alpha * in.u;
    } else {
        // κ = 1 − λ = β/(1 + β): no cancellation for distant glyphs.
        let beta = in.u * alpha;
        kappa = beta / (1.0 + beta);
        p_view = (1.0 - kappa) * in.v_view;
        delta_depth = beta * camera.depth.x / (-in.v_view.z);
    }
    let p_t = in.vt_quad - kappa * in.vt_ray;
    let n_view = normalize(in.n0 * p_t.x + in.n1 * p_t.y + in.n2 * p_t.z);
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = dot(in.tz, p_t);
    hit.z_proxy_rel = dot(in.tz, in.vt_quad);
    hit.depth = in.zw.x / in.zw.y + delta_depth;
    return hit;
}
