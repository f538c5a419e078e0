// Capsule glyphs on Gumhold's quad (gumhold_solid.wgsl): the segment of half-length h along the
// frame's first column swept by a ball of radius R (capsule_of in capsule.wgsl); parameter space
// is the local frame scaled by R, bounded by the minimal ellipsoid of the circumscribed cylinder
// of half-length h + R and radius R (cylinder-capsule.md §5): √3 (h + R) along the axis,
// √(3/2) R across. Composed as common.wgsl + capsule.wgsl + this + gumhold_solid.wgsl +
// outputs.wgsl.

struct Solid {
    scale: vec3<f32>,
    bound: vec3<f32>,
    // The segment's half-length in units of R.
    shape: f32,
}

fn solid_of(radii: vec3<f32>) -> Solid {
    let cap = capsule_of(radii);
    let h = cap.x;
    return Solid(vec3<f32>(cap.y), vec3<f32>(1.7320508 * (h + 1.0), 1.2247449, 1.2247449), h);
}

fn solid_contains(p: vec3<f32>, h: f32) -> bool {
    return capsule_contains(p, h);
}

fn solid_entry(o: vec3<f32>, v: vec3<f32>, h: f32) -> vec4<f32> {
    let t = capsule_span(o, v, h).x;
    return vec4<f32>(t, capsule_normal(o + t * v, h));
}
