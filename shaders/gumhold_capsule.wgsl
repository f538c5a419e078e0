// Capsule glyphs on Gumhold's quad (gumhold_solid.wgsl): the segment of half-length h along the
// frame's first column swept by a ball of radius R (capsule_of in capsule.wgsl); parameter space
// is the local frame scaled by R, bounded by the minimal ellipsoid of the circumscribed cylinder
// of half-length h + R and radius R (cylinder-capsule.md §5): √3 (h + R) along the axis,
// √(3/2) R across. Composed as common.wgsl + capsule.wgsl + this + gumhold_solid.wgsl +
// outputs.wgsl.

struct Solid {
    scale: vec3<f32>,
    bound: vec3<f32>,
    // x: the segment's half-length in units of R.
    shape: vec4<f32>,
}

fn solid_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

fn solid_of(g: Glyph, ii: u32) -> Solid {
    let cap = capsule_of(g.radii);
    let h = cap.x;
    return Solid(vec3<f32>(cap.y), vec3<f32>(1.7320508 * (h + 1.0), 1.2247449, 1.2247449), vec4<f32>(h, 0.0, 0.0, 0.0));
}

fn solid_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return capsule_contains(p, shape.x);
}

fn solid_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let h = shape.x;
    let t = capsule_span(o, v, h).x;
    return vec4<f32>(t, capsule_normal(o + t * v, h));
}
