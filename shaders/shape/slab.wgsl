// The slab test of a capped cylinder in its parameter space, |x| <= 1, y² + z² <= 1
// (sigg-quadric.md §7): the cylinder kind's and the principal-stress bars'. Composed after
// common.wgsl, before the kind's shape file.

// Entry and exit of the capped cylinder along o + t v (sigg-quadric.md §7):
// (t_in, surface_in, t_out, surface_out) with surface 0 = side, ±1 = cap; discards on a miss.
fn slab_span(o: vec3<f32>, v: vec3<f32>) -> vec4<f32> {
    var side_in = -1e30;
    var side_out = 1e30;
    let a = dot(v.yz, v.yz);
    let b = dot(o.yz, v.yz);
    let c = dot(o.yz, o.yz) - 1.0;
    if a > 0.0 {
        let disc = b * b - a * c;
        if disc < 0.0 {
            discard;
        }
        // Stable roots q/a and c/q.
        let q = -(b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
        var r1 = q / a;
        var r2 = r1;
        if q != 0.0 {
            r2 = c / q;
        }
        side_in = min(r1, r2);
        side_out = max(r1, r2);
    } else if c > 0.0 {
        discard;
    }
    var cap_in = -1e30;
    var cap_out = 1e30;
    if v.x != 0.0 {
        let t1 = (-1.0 - o.x) / v.x;
        let t2 = (1.0 - o.x) / v.x;
        cap_in = min(t1, t2);
        cap_out = max(t1, t2);
    } else if abs(o.x) > 1.0 {
        discard;
    }
    let t_in = max(side_in, cap_in);
    let t_out = min(side_out, cap_out);
    if t_in > t_out {
        discard;
    }
    var surface_in = 0.0;
    if cap_in > side_in {
        surface_in = sign(o.x + t_in * v.x);
    }
    var surface_out = 0.0;
    if cap_out < side_out {
        surface_out = sign(o.x + t_out * v.x);
    }
    return vec4<f32>(t_in, surface_in, t_out, surface_out);
}

// Entry only: (t, surface).
fn slab(o: vec3<f32>, v: vec3<f32>) -> vec2<f32> {
    return slab_span(o, v).xy;
}
