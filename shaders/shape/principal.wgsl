// Principal-stress bars and their arrowheads, the shape interface of common.wgsl (each an
// instance of its own, src/shape/principal.rs): a bar is the capped circular cylinder
// |x| <= 1, y² + z² <= 1 of its parameter space (the local frame scaled by the radii; the slab
// test of slab.wgsl), a head the finite cone x in [−1, 1], √(y² + z²) <= (1 − x)/2 (base at
// x = −1, apex at x = 1). Both lie in that cylinder, whose quad and screen box they share.
// shape.x is 1 for a head, 0 for a bar. Twin: src/twin/principal.rs.

// shape word 0 of a head.
const PRINCIPAL_HEAD: u32 = 1u;
// No infinities in WGSL: bounds beyond any ray parameter.
const PRINCIPAL_FAR: f32 = 3.0e38;

fn shape_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

fn shape_of(g: Glyph, ii: u32) -> Solid {
    let head = select(0.0, 1.0, load_shape_words(ii).x == PRINCIPAL_HEAD);
    return Solid(g.radii, vec3<f32>(1.7320508, 1.2247449, 1.2247449), vec4<f32>(head, 0.0, 0.0, 0.0));
}

fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    var r = 1.0;
    if shape.x != 0.0 {
        r = 0.5 * (1.0 - p.x);
    }
    return abs(p.x) <= 1.0 && dot(p.yz, p.yz) <= r * r;
}

// Both roots of a t² + 2 b t + c = 0 with disc = b² − a c >= 0, ascending, as q/a and c/q.
fn cone_roots(a: f32, b: f32, c: f32, disc: f32) -> vec2<f32> {
    let q = -(b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
    var r1 = 0.0;
    var r2 = 0.0;
    if q != 0.0 {
        r1 = q / a;
        r2 = c / q;
    }
    return vec2<f32>(min(r1, r2), max(r1, r2));
}

// The stretch of o + t v inside the head: (t_in, 1 if it enters through the base, t_out, 1 if
// it leaves through the base); discards on a miss. Cone::span in src/shape/principal.rs.
fn cone_span(o: vec3<f32>, v: vec3<f32>) -> vec4<f32> {
    // The nappe √(y² + z²) <= q, q = (1 − x)/2 >= 0: F = y² + z² − q² <= 0.
    let qa = 0.5 * (1.0 - o.x);
    let qb = -0.5 * v.x;
    let a = dot(v.yz, v.yz) - qb * qb;
    let b = dot(o.yz, v.yz) - qa * qb;
    let c = dot(o.yz, o.yz) - qa * qa;
    // Where q >= 0.
    var q_span = vec2<f32>(-PRINCIPAL_FAR, PRINCIPAL_FAR);
    if qb > 0.0 {
        q_span.x = -qa / qb;
    } else if qb < 0.0 {
        q_span.y = -qa / qb;
    } else if qa < 0.0 {
        discard;
    }
    var f_span = vec2<f32>(-PRINCIPAL_FAR, PRINCIPAL_FAR);
    if a == 0.0 {
        if b == 0.0 {
            if c > 0.0 {
                discard;
            }
        } else if b > 0.0 {
            f_span.y = -c / (2.0 * b);
        } else {
            f_span.x = -c / (2.0 * b);
        }
    } else {
        let disc = b * b - a * c;
        if !(disc >= 0.0) {
            if a > 0.0 {
                discard;
            }
        } else {
            let t = cone_roots(a, b, c, disc);
            if a > 0.0 {
                f_span = t;
            } else if qb < 0.0 {
                f_span.y = t.x;
            } else {
                f_span.x = t.y;
            }
        }
    }
    let side = vec2<f32>(max(f_span.x, q_span.x), min(f_span.y, q_span.y));
    var base = vec2<f32>(-PRINCIPAL_FAR, PRINCIPAL_FAR);
    if v.x != 0.0 {
        let t = (-1.0 - o.x) / v.x;
        if v.x > 0.0 {
            base.x = t;
        } else {
            base.y = t;
        }
    } else if o.x < -1.0 {
        discard;
    }
    let t_in = max(side.x, base.x);
    let t_out = min(side.y, base.y);
    if !(t_in <= t_out) {
        discard;
    }
    return vec4<f32>(t_in, select(0.0, 1.0, base.x >= side.x), t_out, select(0.0, 1.0, base.y <= side.y));
}

// The head's outward normal (parameter space) at p, on the base or the side.
fn cone_normal(p: vec3<f32>, base: bool) -> vec3<f32> {
    if base {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    return vec3<f32>(0.5 * (1.0 - p.x), 2.0 * p.y, 2.0 * p.z);
}

// A bar's (t, normal) of a slab crossing (t, surface): a cap's axial normal or the side's.
fn bar_hit(o: vec3<f32>, v: vec3<f32>, s: vec2<f32>) -> vec4<f32> {
    let p = o + s.x * v;
    var n = vec3<f32>(s.y, 0.0, 0.0);
    if s.y == 0.0 {
        n = vec3<f32>(0.0, p.y, p.z);
    }
    return vec4<f32>(s.x, n);
}

fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    if shape.x != 0.0 {
        let s = cone_span(o, v);
        return vec4<f32>(s.x, cone_normal(o + s.x * v, s.y != 0.0));
    }
    return bar_hit(o, v, slab(o, v));
}

// The box of the cylinder that holds bars and heads (the union of its end discs' boxes).
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let w = o[0] * g.radii.x;
    let u = o[1] * g.radii.y;
    let v = o[2] * g.radii.z;
    let b1 = quadric_box(u, v, vec3<f32>(0.0), g.centre - w);
    let b2 = quadric_box(u, v, vec3<f32>(0.0), g.centre + w);
    return hull_box(b1, b2);
}

// The entry if it lies in front of the ray's start, else (orthographic start inside) the exit.
fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let o = (*r).o_t;
    let v = (*r).v_t;
    if shape.x != 0.0 {
        let s = cone_span(o, v);
        var t = s.xy;
        if !((*r).t0 + t.x > 0.0) {
            t = s.zw;
            if !((*r).t0 + t.x > 0.0) {
                discard;
            }
        }
        return vec4<f32>(t.x, cone_normal(o + t.x * v, t.y != 0.0));
    }
    let span = slab_span(o, v);
    var s = span.xy;
    if !((*r).t0 + s.x > 0.0) {
        s = span.zw;
        if !((*r).t0 + s.x > 0.0) {
            discard;
        }
    }
    return bar_hit(o, v, s);
}

// The prism's point; a head narrows it towards x = 1, the apex (its side normal, ∇F ∝
// (1, 2 cos θ, 2 sin θ), from the prism's radial one; the base keeps its axial normal).
fn shape_mesh_point(p: vec3<f32>, n: vec3<f32>, g: Glyph, solid: Solid) -> MeshPoint {
    if solid.shape.x == 0.0 {
        return MeshPoint(p * g.radii, n / g.radii);
    }
    let q = vec3<f32>(p.x, p.yz * (0.5 * (1.0 - p.x)));
    var m = n;
    if n.x == 0.0 {
        m = vec3<f32>(0.5, n.yz);
    }
    return MeshPoint(q * g.radii, m / g.radii);
}

fn shape_box_half(g: Glyph, solid: Solid) -> vec3<f32> {
    return g.radii;
}

// One colour per glyph (only ODF glyphs colour their pixels by direction).
fn shape_tint(dir: vec3<f32>, local: vec3<f32>, shape: vec4<f32>, base: vec3<f32>) -> vec3<f32> {
    return base;
}
