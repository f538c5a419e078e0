// Triangle-mesh baselines (`mesh:N`, `box`): one shared unit mesh, instanced per glyph, each
// vertex placed in the glyph's frame by its kind (shape_mesh_point: for most kinds p maps to
// c + O diag(r) p and a unit normal n to O diag(1/r) n, the inverse transpose); the fragment
// shades the interpolated, renormalised normal per pixel. Depth is the rasterised depth of the
// triangles. Composed as common.wgsl + shape/screen_box.wgsl + the kind's shape file(s) + this +
// outputs.wgsl; the CPU side is src/render/mesh.rs, the unit meshes src/shape/.

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
    // The point's offset from the glyph's centre (world) and the kind's shape vector: the
    // kind's per-pixel colour (shape_tint).
    @location(5) dir: vec3<f32>,
    @location(6) @interpolate(flat) shape: vec4<f32>,
    // The same offset in the glyph's axes.
    @location(7) local: vec3<f32>,
}

// The box baseline (MeshRenderer sets it for `box`): the unit cube scaled by the kind's
// shape_box_half instead of its unit mesh placed by shape_mesh_point.
override MESH_BOX: bool = false;

@vertex
fn vs_main(
    @location(0) p: vec3<f32>,
    @location(1) n: vec3<f32>,
    @builtin(instance_index) ii: u32,
) -> VsOut {
    var out: VsOut;
    let g = load_glyph(ii);
    let o = quat_to_mat3(g.rotation);
    if !drawable(g.radii) || skip_glyph(g.centre, shape_radius(g.radii)) {
        out.position = CULLED_POSITION;
        return out;
    }
    let solid = shape_of(g, ii);
    // The eye inside or on the true glyph: not drawn, as by the impostors and the reference
    // (the inscribed polytope alone would still show it from just inside the surface).
    if !is_ortho() {
        let e_p = (transpose(o) * (camera.eye.xyz - g.centre)) / solid.scale;
        if shape_contains(e_p, solid.shape) {
            out.position = CULLED_POSITION;
            return out;
        }
    }
    // The point and normal in the glyph's frame.
    var m: MeshPoint;
    if MESH_BOX {
        let b = shape_box_half(g, solid);
        m = MeshPoint(p * b, n / b);
    } else {
        m = shape_mesh_point(p, n, g, solid);
    }
    let local = m.local;
    let v = g.centre + o * local;
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    out.position = camera.view_proj * vec4<f32>(v, 1.0);
    out.v_view = (camera.view * vec4<f32>(v, 1.0)).xyz;
    out.z_rel = dot(vec3<f32>(camera.view[0].z, camera.view[1].z, camera.view[2].z), o * local);
    // Normalised per vertex so that thin glyphs (tiny radii) interpolate in a sane range.
    out.n_view = normalize(rv * (o * m.n_local));
    out.id = ii + 1u;
    out.color = g.color;
    out.dir = o * local;
    out.local = local;
    out.shape = solid.shape;
    return out;
}

// Not a ray cast: the rasterised mesh point, shaded.
fn ray_cast(in: VsOut) -> Hit {
    let n_view = normalize(in.n_view);
    var hit: Hit;
    let base = shape_tint(in.dir, in.local, in.shape, unpack4x8unorm(in.color).rgb);
    hit.color = vec4<f32>(shade(base, n_view, in.v_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = in.z_rel;
    hit.z_proxy_rel = in.z_rel;
    hit.depth = in.position.z;
    return hit;
}
