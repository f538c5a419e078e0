// Triangle-mesh baselines (`mesh:N`, `box`): one shared unit mesh, instanced per glyph. A unit
// point p maps to c + O diag(r) p, a unit normal n to O diag(1/r) n (the inverse transpose);
// the fragment shades the interpolated, renormalised normal per pixel. Depth is the rasterised
// depth of the triangles. Superquadrics first map the unit grid's point through the glyph's
// exponents (superquadric_mesh.wgsl). Composed as common.wgsl + capsule.wgsl +
// superquadric_mesh.wgsl + this + outputs.wgsl; the CPU side is src/render/mesh.rs.

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
// Capsules (MeshRenderer): 1 for the unit capsule, whose point p is its end (x = ±1) plus the
// unit normal n, placed at h sign(p.x) x + R n with the glyph's capsule_of (h, R); 2 for the
// capsule's box, [−1, 1]³ scaled to (h + R, R, R).
override MESH_CAPSULE: u32 = 0u;
// Superquadrics (MeshRenderer): 1 for the θ × φ grid on the unit sphere, each direction mapped
// to the glyph's surface by sqm_vertex with its exponents (local z the symmetry axis); 2 for
// the box [−1, 1]³ scaled by the radii, which holds every superquadric. Both cull by the box's
// corner, length(radii), and test the eye against the glyph's own inside–outside function.
override MESH_SUPERQUADRIC: u32 = 0u;
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
    let superquadric = MESH_SUPERQUADRIC != 0u;
    let radius = select(bounding_radius(g.radii), length(g.radii), superquadric);
    if !drawable(g.radii) || skip_glyph(g.centre, radius) {
        out.position = CULLED_POSITION;
        return out;
    }
    // A superquadric's exponents (α, β, c), floored where 2/e must stay finite
    // (pack_exponents stores ≥ 1e-30).
    var e = vec3<f32>(1.0);
    if superquadric {
        e = max(load_exponents(ii), vec3<f32>(1e-30));
    }
    // The eye inside or on the true glyph: not drawn, as by the impostors and the reference
    // (the inscribed polytope alone would still show it from just inside the surface).
    let cap = capsule_of(g.radii);
    if !is_ortho() {
        let e_p = (transpose(o) * (camera.eye.xyz - g.centre)) / g.radii;
        let inside_cylinder = abs(e_p.x) <= 1.0 && dot(e_p.yz, e_p.yz) <= 1.0;
        let inside_ellipsoid = !(dot(e_p, e_p) > MESH_EYE_INSIDE_E2);
        let inside_capsule = capsule_contains((transpose(o) * (camera.eye.xyz - g.centre)) / cap.y, cap.x);
        var inside = select(select(inside_ellipsoid, inside_cylinder, MESH_CYLINDER), inside_capsule, MESH_CAPSULE != 0u);
        if superquadric {
            // As the reference (Superquadric::contains) and the ray casters: H ≤ 1.
            inside = sqm_gauge(e_p, e) <= 1.0;
        }
        if inside {
            out.position = CULLED_POSITION;
            return out;
        }
    }
    // The point and normal in the glyph's frame.
    var local = p * g.radii;
    var n_local = n / g.radii;
    if MESH_CAPSULE == 1u {
        local = vec3<f32>(sign(p.x) * cap.x * cap.y, 0.0, 0.0) + cap.y * n;
        n_local = n;
    } else if MESH_CAPSULE == 2u {
        let b = vec3<f32>((cap.x + 1.0) * cap.y, cap.y, cap.y);
        local = p * b;
        n_local = n / b;
    } else if MESH_SUPERQUADRIC == 1u {
        let s = sqm_vertex(p, e);
        local = s.p * g.radii;
        n_local = s.n / g.radii;
    }
    let v = g.centre + o * local;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    out.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
    out.z_rel = dot(vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z), o * local);
    // Normalised per vertex so that thin glyphs (tiny radii) interpolate in a sane range.
    out.n_view = normalize(rv * (o * n_local));
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
