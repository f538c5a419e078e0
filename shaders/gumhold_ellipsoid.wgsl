// Gumhold's ellipsoid glyph: one perspective-correct silhouette quad per glyph, built here from
// the vertex and instance index, and the incremental ray–ellipsoid intersection per fragment.
// Math and names: shared/math/gumhold-ellipsoid.md. Composed as common.wgsl + this + outputs.wgsl.

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // (q~x, q~y): the corner signs, interpolated.
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
}

// E² at or below this counts as "eye inside or on the glyph": the glyph is culled (documented).
const EYE_INSIDE_E2: f32 = 1.00001;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VsOut {
    var out: VsOut;
    let g = glyphs[ii];
    let o = quat_to_mat3(g.rotation);
    let ot = transpose(o);
    let rinv = 1.0 / g.radii;
    let sx = select(-1.0, 1.0, (vi & 1u) != 0u);
    let sy = select(-1.0, 1.0, (vi & 2u) != 0u);

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
            // Outside the clip volume (z < 0): all four corners are clipped away.
            out.position = vec4<f32>(0.0, 0.0, -2.0, 1.0);
            return out;
        }
        let e = sqrt(e2);
        z_hat = -e_t / e;
        m_t = e_t / e2;
        r_t = sqrt((e2 - 1.0) / e2);
        out.u = 1.0 / e;
    }
    let xy = orthonormal_pair(z_hat);
    let vt_quad = m_t + r_t * (sx * xy[0] + sy * xy[1]);
    let v = g.centre + o * ((ot * vt_quad) * g.radii);
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    out.q = vec2<f32>(sx, sy);
    out.vt_quad = vt_quad;
    if is_ortho() {
        out.vt_ray = z_hat;
    } else {
        out.vt_ray = vt_quad + z_hat / out.u;
    }
    out.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
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
fn ray_cast(in: VsOut) -> Hit {
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
    hit.depth = in.position.z + delta_depth;
    return hit;
}
