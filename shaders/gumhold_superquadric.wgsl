// Superquadric glyphs on Gumhold's quad (gumhold_solid.wgsl): parameter space is the local frame
// (third column the symmetry axis) scaled by the radii, where the solid lies in the unit box;
// the quad is that of the smallest ball about the centre holding the solid (sq_bound: 1 for an
// ellipsoid, √2 for a cylinder, at most √3, the box's corner). The first crossing is found by
// superquadric.wgsl (docs/book/src/developer/superquadric-derivation.md §6). Composed as
// common.wgsl + superquadric.wgsl + this + gumhold_solid.wgsl + outputs.wgsl.

struct Solid {
    scale: vec3<f32>,
    bound: vec3<f32>,
    // The exponents (α, β, c) and the bounding ball's radius.
    shape: vec4<f32>,
}

// The unit box's corner: no superquadric reaches beyond it.
fn solid_radius(radii: vec3<f32>) -> f32 {
    return length(radii);
}

fn solid_of(g: Glyph, ii: u32) -> Solid {
    let e = load_exponents(ii);
    let bound = sq_bound(e);
    return Solid(g.radii, vec3<f32>(bound), vec4<f32>(e, bound));
}

fn solid_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return sq_contains(p, shape.xyz);
}

fn solid_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let h = sq_first(o, v, shape.xyz, t_min, shape.w);
    if !h.hit {
        discard;
    }
    return vec4<f32>(h.s, h.n);
}
