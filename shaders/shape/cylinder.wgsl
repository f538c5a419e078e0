// Capped elliptic cylinder glyphs, the shape interface of common.wgsl: the axis is the frame's
// first column with half-length radii.x, the cross-section has semi-axes radii.y, radii.z;
// parameter space is the local frame scaled by the radii, where the solid is |p~x| <= 1,
// p~y² + p~z² <= 1, bounded by its minimal ellipsoid (√3 along the axis, √(3/2) across) and
// entered through the slab test (sigg-quadric.md §7). Twin: src/twin/cylinder.rs.

fn shape_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

fn shape_of(g: Glyph, ii: u32) -> Solid {
    return Solid(g.radii, vec3<f32>(1.7320508, 1.2247449, 1.2247449), vec4<f32>(0.0));
}

fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return abs(p.x) <= 1.0 && dot(p.yz, p.yz) <= 1.0;
}

// (t, local normal) where the ray o + t v enters: a cap (axial normal) or the side.
fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let s = slab(o, v);
    let p = o + s.x * v;
    var n = vec3<f32>(s.y, 0.0, 0.0);
    if s.y == 0.0 {
        n = vec3<f32>(0.0, p.y, p.z);
    }
    return vec4<f32>(s.x, n);
}

// The union of the two end discs' eq. 5 boxes (T_cap = [[u, v, 0, c ± w], [0, 0, 0, 1]]), exact
// in front of the camera plane.
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let w = o[0] * g.radii.x;
    let u = o[1] * g.radii.y;
    let v = o[2] * g.radii.z;
    let b1 = quadric_box(u, v, vec3<f32>(0.0), g.centre - w);
    let b2 = quadric_box(u, v, vec3<f32>(0.0), g.centre + w);
    return hull_box(b1, b2);
}

// The entry if it lies in front of the ray's start, else (orthographic start inside the glyph)
// the exit, as the reference does.
fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let span = slab_span((*r).o_t, (*r).v_t);
    var s = span.xy;
    if !((*r).t0 + s.x > 0.0) {
        s = span.zw;
        if !((*r).t0 + s.x > 0.0) {
            discard;
        }
    }
    let p_t = (*r).o_t + s.x * (*r).v_t;
    var n_t = vec3<f32>(s.y, 0.0, 0.0);
    if s.y == 0.0 {
        n_t = vec3<f32>(0.0, p_t.y, p_t.z);
    }
    return vec4<f32>(s.x, n_t);
}

// The prism's point (axis x, |x| <= 1, the unit circle across), its normal by the inverse
// transpose.
fn shape_mesh_point(p: vec3<f32>, n: vec3<f32>, g: Glyph, solid: Solid) -> MeshPoint {
    return MeshPoint(p * g.radii, n / g.radii);
}

fn shape_box_half(g: Glyph, solid: Solid) -> vec3<f32> {
    return g.radii;
}

// One colour per glyph (only ODF glyphs colour their pixels by direction).
fn shape_tint(dir: vec3<f32>, local: vec3<f32>, shape: vec4<f32>, base: vec3<f32>) -> vec3<f32> {
    return base;
}
