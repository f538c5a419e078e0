// Capped elliptic cylinder glyphs on Gumhold's quad (gumhold_solid.wgsl): the axis is the frame's
// first column with half-length radii.x, the cross-section has semi-axes radii.y, radii.z;
// parameter space is the local frame scaled by the radii, where the solid is |p~x| <= 1,
// p~y² + p~z² <= 1, bounded by its minimal ellipsoid (√3 along the axis, √(3/2) across).
// Composed as common.wgsl + cylinder_slab.wgsl + this + gumhold_solid.wgsl + outputs.wgsl.

struct Solid {
    scale: vec3<f32>,
    bound: vec3<f32>,
    shape: vec4<f32>,
}

fn solid_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

fn solid_of(g: Glyph, ii: u32) -> Solid {
    return Solid(g.radii, vec3<f32>(1.7320508, 1.2247449, 1.2247449), vec4<f32>(0.0));
}

fn solid_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return abs(p.x) <= 1.0 && dot(p.yz, p.yz) <= 1.0;
}

// (t, local normal) where the ray o + t v enters: a cap (axial normal) or the side.
fn solid_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let s = slab(o, v);
    let p = o + s.x * v;
    var n = vec3<f32>(s.y, 0.0, 0.0);
    if s.y == 0.0 {
        n = vec3<f32>(0.0, p.y, p.z);
    }
    return vec4<f32>(s.x, n);
}
