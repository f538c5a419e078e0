// Ellipsoid glyphs, the shape interface of common.wgsl: parameter space is the instance frame
// scaled by the radii, where the glyph is the unit ball (sigg-quadric.md §4). Gumhold's method
// draws ellipsoids with their own exact quad (method/gumhold_ellipsoid.wgsl); shape_entry is the
// solids' path for the same ball. Twin: src/twin/ellipsoid.rs.

fn shape_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

fn shape_of(g: Glyph, ii: u32) -> Solid {
    return Solid(g.radii, vec3<f32>(1.0), vec4<f32>(0.0));
}

// E² ≤ EYE_INSIDE_E2, NaN counting as inside.
fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return !(dot(p, p) > EYE_INSIDE_E2);
}

// Both roots of |o + t v|² = 1, ascending, as q/α and γ/q (no cancellation); discards on a miss.
fn ball_roots(o: vec3<f32>, v: vec3<f32>) -> vec2<f32> {
    let alpha = dot(v, v);
    let beta = dot(o, v);
    let gamma = dot(o, o) - 1.0;
    let disc = beta * beta - alpha * gamma;
    if !(disc >= 0.0) {
        discard;
    }
    let q = -(beta + select(-1.0, 1.0, beta >= 0.0) * sqrt(disc));
    var r1 = 0.0;
    var r2 = 0.0;
    if q != 0.0 {
        r1 = q / alpha;
        r2 = gamma / q;
    }
    return vec2<f32>(min(r1, r2), max(r1, r2));
}

fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let t = ball_roots(o, v).x;
    return vec4<f32>(t, o + t * v);
}

// Eq. 5 with T's columns r_i O_i.
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    var b = quadric_box(o[0] * g.radii.x, o[1] * g.radii.y, o[2] * g.radii.z, g.centre);
    if outside_frustum(b) {
        b.kind = PROXY_CULL;
    }
    return b;
}

// The nearer root in front of the ray's start (the farther one only from inside, orthographic).
fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let roots = ball_roots((*r).o_t, (*r).v_t);
    var tp = roots.x;
    if !((*r).t0 + tp > 0.0) {
        tp = roots.y;
        if !((*r).t0 + tp > 0.0) {
            discard;
        }
    }
    return vec4<f32>(tp, (*r).o_t + tp * (*r).v_t);
}

// The icosphere's point on the unit sphere, its normal by the inverse transpose.
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
