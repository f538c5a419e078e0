// Capsule glyphs, the shape interface of common.wgsl, after cylinder-capsule.md §4–§5: the
// segment of half-length h along the frame's first column swept by a ball of radius R
// (capsule_of). Capsule space (the parameter space): the glyph's local frame scaled by R, where
// the solid is every point within 1 of the segment |x| <= h on the x axis; a uniform scale, so
// normals need no inverse transpose. Gumhold's quad is that of the minimal ellipsoid of the
// circumscribed cylinder of half-length h + R and radius R: √3 (h + R) along the axis, √(3/2) R
// across. Twin: src/twin/capsule.rs.

// The capsule of a glyph's radii: (H, R) with R = (r.y + r.z)/2 and the segment's half-length
// max(r.x − R, 0) as H in units of R. Mirrored by shape::capsule::capsule_of.
fn capsule_of(r: vec3<f32>) -> vec2<f32> {
    let radius = 0.5 * (r.y + r.z);
    return vec2<f32>(max(r.x - radius, 0.0) / radius, radius);
}

// Outward normal at p (capsule space; unit on the surface): from the nearest segment point.
fn capsule_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    return p - vec3<f32>(clamp(p.x, -h, h), 0.0, 0.0);
}

fn capsule_contains(p: vec3<f32>, h: f32) -> bool {
    let n = capsule_normal(p, h);
    return dot(n, n) <= 1.0;
}

// Both roots of a t² + 2 b t + c = 0 with disc = b² − a c >= 0, ascending, as q/a and c/q.
fn capsule_roots(a: f32, b: f32, c: f32, disc: f32) -> vec2<f32> {
    let q = -(b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
    var r1 = 0.0;
    var r2 = 0.0;
    if q != 0.0 {
        r1 = q / a;
        r2 = c / q;
    }
    return vec2<f32>(min(r1, r2), max(r1, r2));
}

// The crossing belonging to root t of the infinite cylinder (the entry when `entry`, else the
// exit): t itself where it lies along the segment, else the matching root of the ball at the
// end it lies beyond (the end's flat disc lies inside that ball). Discards on a miss.
fn capsule_crossing(o: vec3<f32>, v: vec3<f32>, h: f32, t: f32, entry: bool) -> f32 {
    let s = o.x + t * v.x;
    if abs(s) <= h {
        return t;
    }
    return capsule_ball(o - vec3<f32>(select(-h, h, s > 0.0), 0.0, 0.0), v, entry);
}

// The entry (or exit) of o + t v through the unit ball at the origin (o relative to the
// ball's centre); discards on a miss.
fn capsule_ball(ok: vec3<f32>, v: vec3<f32>, entry: bool) -> f32 {
    let a = dot(v, v);
    let b = dot(ok, v);
    let c = dot(ok, ok) - 1.0;
    let disc = b * b - a * c;
    if !(disc >= 0.0) {
        discard;
    }
    let r = capsule_roots(a, b, c, disc);
    return select(r.y, r.x, entry);
}

// The side's roots (the infinite cylinder |yz| = 1), ±1e30 for a ray along the axis inside
// it; discards on a miss (both balls lie inside the infinite cylinder).
fn capsule_side(o: vec3<f32>, v: vec3<f32>) -> vec2<f32> {
    var side = vec2<f32>(-1e30, 1e30);
    let a = dot(v.yz, v.yz);
    let b = dot(o.yz, v.yz);
    let c = dot(o.yz, o.yz) - 1.0;
    if a > 0.0 {
        let disc = b * b - a * c;
        if !(disc >= 0.0) {
            discard;
        }
        side = capsule_roots(a, b, c, disc);
    } else if c > 0.0 {
        discard;
    }
    return side;
}

// Entry and exit (t_in, t_out) of the capsule along o + t v (capsule space); discards on a miss.
fn capsule_span(o: vec3<f32>, v: vec3<f32>, h: f32) -> vec2<f32> {
    let side = capsule_side(o, v);
    return vec2<f32>(capsule_crossing(o, v, h, side.x, true), capsule_crossing(o, v, h, side.y, false));
}

// THIN_EXACT: a capsule k thin is h = k radii long in capsule space, where f32 holds a point
// near an end to ~2⁻²⁴·k of the radius, and the ray's slide to the axis and the end's
// x − h both cancel. Here the slide is taken in double-f32 (thin_o_lo, thin_v_lo), and the
// solve runs from the slid origin relative to the end it lies towards (end = ±h): the side's
// roots, the end ball's, and whether a point lies along the segment are then exact to f32's
// own rounding; only a ray crossing to the far end (nearly along the axis) sees that end's
// 2h in f32.
struct CapsuleThin {
    // How far the origin slid along v, the slid origin relative to the end, and the end.
    s: f32,
    o: vec3<f32>,
    end: f32,
    // Entry and exit from the slid origin.
    span: vec2<f32>,
}

fn capsule_cast_thin(o: vec3<f32>, v: vec3<f32>, h_df: vec2<f32>) -> CapsuleThin {
    var c: CapsuleThin;
    let h = h_df.x;
    c.s = capsule_slide(o, v, h);
    df_begin();
    let px = df_add(vec2<f32>(o.x, thin_o_lo.x), df_mul_f(vec2<f32>(v.x, thin_v_lo.x), c.s));
    let py = df_add(vec2<f32>(o.y, thin_o_lo.y), df_mul_f(vec2<f32>(v.y, thin_v_lo.y), c.s));
    let pz = df_add(vec2<f32>(o.z, thin_o_lo.z), df_mul_f(vec2<f32>(v.z, thin_v_lo.z), c.s));
    let side = select(-1.0, 1.0, px.x >= 0.0);
    c.end = side * h;
    let rx = df_add(px, -side * h_df);
    c.o = vec3<f32>(rx.x + rx.y, py.x + py.y, pz.x + pz.y);
    c.span = capsule_span_rel(c.o, v, h, c.end);
    return c;
}

// capsule_normal of the point end + p.
fn capsule_normal_rel(p: vec3<f32>, h: f32, end: f32) -> vec3<f32> {
    // The segment's nearest point less the end: clamp(end + x, −h, h) − end, exactly.
    let lo = select(0.0, -2.0 * h, end > 0.0);
    let hi = select(2.0 * h, 0.0, end > 0.0);
    return p - vec3<f32>(clamp(p.x, lo, hi), 0.0, 0.0);
}

// capsule_crossing from an origin relative to the end `end`.
fn capsule_crossing_rel(o: vec3<f32>, v: vec3<f32>, h: f32, end: f32, t: f32, entry: bool) -> f32 {
    let x = o.x + t * v.x;
    let lo = select(0.0, -2.0 * h, end > 0.0);
    let hi = select(2.0 * h, 0.0, end > 0.0);
    if x >= lo && x <= hi {
        return t;
    }
    // Beyond this end (x on its outer side) or the other (2h away).
    var ok = o;
    if (end > 0.0) != (x > hi) {
        ok.x += select(2.0 * h, -2.0 * h, end < 0.0);
    }
    return capsule_ball(ok, v, entry);
}

// capsule_span from an origin relative to the end `end`.
fn capsule_span_rel(o: vec3<f32>, v: vec3<f32>, h: f32, end: f32) -> vec2<f32> {
    let side = capsule_side(o, v);
    return vec2<f32>(capsule_crossing_rel(o, v, h, end, side.x, true), capsule_crossing_rel(o, v, h, end, side.y, false));
}

fn shape_radius(radii: vec3<f32>) -> f32 {
    return bounding_radius(radii);
}

// Scale R, the shape's x the segment's half-length h in units of R.
// THIN_EXACT: the shape's y is what f32 left of h (capsule_thin_h).
fn shape_of(g: Glyph, ii: u32) -> Solid {
    let cap = capsule_of(g.radii);
    var h = vec2<f32>(cap.x, 0.0);
    if THIN_EXACT {
        h = capsule_thin_h(g.radii, cap.y);
    }
    return Solid(vec3<f32>(cap.y), vec3<f32>(1.7320508 * (h.x + 1.0), 1.2247449, 1.2247449), vec4<f32>(h, 0.0, 0.0));
}

// h = (r.x − R)/R in double-f32: rounded to f32, h moves each end by ~2⁻²⁴·r.x, which a
// capsule k thin sees as 2⁻²⁴·k of its radius (the reference's f64 h does not).
fn capsule_thin_h(r: vec3<f32>, radius: f32) -> vec2<f32> {
    if !(r.x > radius) {
        return vec2<f32>(0.0);
    }
    df_begin();
    return df_div(two_sum(r.x, -radius), vec2<f32>(radius, 0.0));
}

fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return capsule_contains(p, shape.x);
}

// Solved from the ray point nearest the axis (capsule_slide), as shape_cast does: Gumhold's rays
// start on the bounding ellipsoid's quad or, orthographic, at the ray point nearest the centre,
// up to h + 1 radii along the axis from where a needle's ray passes it (72° normal p99 on
// k = 1e4 needles seen orthographically before).
fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let h = shape.x;
    if THIN_EXACT {
        let c = capsule_cast_thin(o, v, shape.xy);
        let t = c.span.x;
        return vec4<f32>(c.s + t, capsule_normal_rel(c.o + t * v, h, c.end));
    }
    let s = capsule_slide(o, v, h);
    let o2 = o + s * v;
    let t = capsule_span(o2, v, h).x;
    return vec4<f32>(s + t, capsule_normal(o2 + t * v, h));
}

// How far along v the ray point nearest the axis lies from o (β ≈ 0 for the side: there
// |o~.yz|² − 1 keeps its 1 in f32); where that point lies beyond an end ball's reach
// (|x| > h + 1), the point nearest that ball's centre instead (never far: clamping x along a
// ray nearly across the axis would slide it by ~1/v.x, and Gumhold's quad, unlike Sigg's box,
// has such rays beyond the ends); 0 for rays along the axis.
fn capsule_slide(o: vec3<f32>, v: vec3<f32>, h: f32) -> f32 {
    let a = dot(v.yz, v.yz);
    if !(a > 0.0) {
        return 0.0;
    }
    let s = -dot(o.yz, v.yz) / a;
    let x = o.x + s * v.x;
    if abs(x) > h + 1.0 {
        let end = vec3<f32>(select(-h, h, x > 0.0), 0.0, 0.0);
        return -dot(o - end, v) / dot(v, v);
    }
    return s;
}

// The union of the two end balls' eq. 5 boxes, exact in front of the camera plane.
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let h = solid.shape.x;
    let r = solid.scale.x;
    let w = o[0] * (h * r);
    let b1 = quadric_box(o[0] * r, o[1] * r, o[2] * r, g.centre - w);
    let b2 = quadric_box(o[0] * r, o[1] * r, o[2] * r, g.centre + w);
    return hull_box(b1, b2);
}

// The ray's origin (the ray point nearest the centre) can lie h + 1 radii from where the ray
// passes a long capsule's axis: there |o~.yz|² − 1 loses the 1 in f32. It slides as
// capsule_slide says (β ≈ 0 for the side; never far). Then the entry if it lies
// in front of the ray's start, else (orthographic start inside the glyph) the exit, as the
// reference does.
fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let h = shape.x;
    if THIN_EXACT {
        let c = capsule_cast_thin((*r).o_t, (*r).v_t, shape.xy);
        (*r).off += c.s * (*r).d;
        (*r).t0 += c.s;
        (*r).o_t = c.o + vec3<f32>(c.end, 0.0, 0.0);
        var t = c.span.x;
        if !((*r).t0 + t > 0.0) {
            t = c.span.y;
            if !((*r).t0 + t > 0.0) {
                discard;
            }
        }
        return vec4<f32>(t, capsule_normal_rel(c.o + t * (*r).v_t, h, c.end));
    }
    let s = capsule_slide((*r).o_t, (*r).v_t, h);
    (*r).off += s * (*r).d;
    (*r).t0 += s;
    (*r).o_t += s * (*r).v_t;
    let span = capsule_span((*r).o_t, (*r).v_t, h);
    var t = span.x;
    if !((*r).t0 + t > 0.0) {
        t = span.y;
        if !((*r).t0 + t > 0.0) {
            discard;
        }
    }
    return vec4<f32>(t, capsule_normal((*r).o_t + t * (*r).v_t, h));
}

// The unit capsule's point is its end (x = ±1) plus the unit normal: placed at
// h sign(p.x) x + R n.
fn shape_mesh_point(p: vec3<f32>, n: vec3<f32>, g: Glyph, solid: Solid) -> MeshPoint {
    let h = solid.shape.x;
    let r = solid.scale.x;
    return MeshPoint(vec3<f32>(sign(p.x) * h * r, 0.0, 0.0) + r * n, n);
}

// [−1, 1]³ scaled to (h + R, R, R).
fn shape_box_half(g: Glyph, solid: Solid) -> vec3<f32> {
    let h = solid.shape.x;
    let r = solid.scale.x;
    return vec3<f32>((h + 1.0) * r, r, r);
}

// One colour per glyph (only ODF glyphs colour their pixels by direction).
fn shape_tint(dir: vec3<f32>, local: vec3<f32>, shape: vec4<f32>, base: vec3<f32>) -> vec3<f32> {
    return base;
}
