// The capsule test shared by every capsule method (composed after common.wgsl), after
// cylinder-capsule.md §4. Capsule space: the glyph's local frame (axis = first column) scaled by
// the ball's radius R, where the solid is every point within 1 of the segment |x| <= H on the
// x axis; a uniform scale, so normals need no inverse transpose.

// The capsule of a glyph's radii: (H, R) with R = (r.y + r.z)/2 and the segment's half-length
// max(r.x − R, 0) as H in units of R. Mirrored by scene::capsule_of.
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
    let ok = o - vec3<f32>(select(-h, h, s > 0.0), 0.0, 0.0);
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

// Entry and exit (t_in, t_out) of the capsule along o + t v (capsule space); discards on a miss.
fn capsule_span(o: vec3<f32>, v: vec3<f32>, h: f32) -> vec2<f32> {
    var side = vec2<f32>(-1e30, 1e30);
    let a = dot(v.yz, v.yz);
    let b = dot(o.yz, v.yz);
    let c = dot(o.yz, o.yz) - 1.0;
    if a > 0.0 {
        let disc = b * b - a * c;
        // Both balls lie inside the infinite cylinder.
        if !(disc >= 0.0) {
            discard;
        }
        side = capsule_roots(a, b, c, disc);
    } else if c > 0.0 {
        discard;
    }
    return vec2<f32>(capsule_crossing(o, v, h, side.x, true), capsule_crossing(o, v, h, side.y, false));
}
