// Triangle-mesh baselines (`mesh:N`, `box`): one shared unit mesh, instanced per glyph. A unit
// point p maps to c + O diag(r) p, a unit normal n to O diag(1/r) n (the inverse transpose);
// the fragment shades the interpolated, renormalised normal per pixel. Depth is the rasterised
// depth of the triangles. Composed as common.wgsl + this + outputs.wgsl; the CPU side is
// src/render/mesh.rs.

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The mesh point in view space.
    @location(0) v_view: vec3<f32>,
    // The interpolated normal in view space (not unit).
    @location(1) n_view: vec3<f32>,
    @location(2) @interpolate(flat) id: u32,
    @location(3) @interpolate(flat) color: u32,
    // View z relative to the glyph's centre, formed from the small offset O diag(r) p.
    @location(4) z_rel: f32,
}

// Which glyph the mesh approximates; MeshRenderer sets it to true for cylinders.
override MESH_CYLINDER: bool = false;
// reference::EYE_INSIDE_E2.
const MESH_EYE_INSIDE_E2: f32 = 1.00001;

@vertex
fn vs_main(
    @location(0) p: vec3<f32>,
    @location(1) n: vec3<f32>,
    @builtin(instance_index) ii: u32,
) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    let o = quat_to_mat3(g.rotation);
    if !drawable(g.radii) || skip_glyph(g.centre, bounding_radius(g.radii)) {
        out.position = CULLED_POSITION;
        return out;
    }
    // The eye inside or on the true glyph: not drawn, as by the impostors and the reference
    // (the inscribed polytope alone would still show it from just inside the surface).
    if !is_ortho() {
        let e_p = (transpose(o) * (camera.eye.xyz - g.centre)) / g.radii;
        let inside_cylinder = abs(e_p.x) <= 1.0 && dot(e_p.yz, e_p.yz) <= 1.0;
        let inside_ellipsoid = !(dot(e_p, e_p) > MESH_EYE_INSIDE_E2);
        if select(inside_ellipsoid, inside_cylinder, MESH_CYLINDER) {
            out.position = CULLED_POSITION;
            return out;
        }
    }
    let v = g.centre + o * (p * g.radii);
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    out.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
    out.z_rel = dot(vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z), o * (p * g.radii));
    // Normalised per vertex so that thin glyphs (tiny radii) interpolate in a sane range.
    out.n_view = normalize(rv * (o * (n / g.radii)));
    out.id = ii + 1u;
    out.color = g.color;
    return out;
}

// Not a ray cast: the rasterised mesh point, shaded.
fn ray_cast(in: VsOut) -> Hit {
    let n_view = normalize(in.n_view);
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, in.v_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = in.z_rel;
    hit.z_proxy_rel = in.z_rel;
    hit.depth = in.position.z;
    return hit;
}
