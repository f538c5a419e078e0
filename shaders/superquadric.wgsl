// A plain finder (a 256-step march, then bisection), to be replaced by the guaranteed one of
// docs/superquadric.md §6; no guarantee against thin crossings.
struct SqHit { s: f32, n: vec3<f32>, hit: bool }
fn sq_gauge(p: vec3<f32>, e: vec3<f32>) -> f32 {
    let a = abs(p);
    if a.z >= 1.0 { return 2.0; }
    let rb = pow(1.0 - pow(a.z, 2.0 / e.y), e.y / 2.0);
    let rc = pow(1.0 - pow(a.z, 2.0 / e.z), e.z / 2.0);
    let u = a.x / rb; let w = a.y / rc;
    return pow(pow(u, 2.0 / e.x) + pow(w, 2.0 / e.x), e.x / 2.0);
}
fn sq_contains(p: vec3<f32>, e: vec3<f32>) -> bool { return sq_gauge(p, e) <= 1.0; }
fn sq_first(o: vec3<f32>, v: vec3<f32>, e: vec3<f32>, s_min: f32) -> SqHit {
    var h: SqHit;
    var s_in = s_min; var s_out = 3.0e38;
    for (var k = 0; k < 3; k++) {
        if v[k] != 0.0 {
            let s1 = (-1.0 - o[k]) / v[k]; let s2 = (1.0 - o[k]) / v[k];
            s_in = max(s_in, min(s1, s2)); s_out = min(s_out, max(s1, s2));
        } else if abs(o[k]) > 1.0 { return h; }
    }
    if s_in >= s_out { return h; }
    let n = 256;
    var prev = s_in;
    let inside0 = sq_contains(o + s_in * v, e);
    for (var i = 1; i <= n; i++) {
        let s = s_in + (s_out - s_in) * f32(i) / f32(n);
        if sq_contains(o + s * v, e) != inside0 {
            var lo = prev; var hi = s;
            for (var j = 0; j < 24; j++) {
                let m = 0.5 * (lo + hi);
                if sq_contains(o + m * v, e) != inside0 { hi = m; } else { lo = m; }
            }
            h.s = 0.5 * (lo + hi); h.hit = true;
            let p = o + h.s * v;
            let d = 1e-3;
            h.n = normalize(vec3<f32>(
                sq_gauge(p + vec3<f32>(d, 0.0, 0.0), e) - sq_gauge(p - vec3<f32>(d, 0.0, 0.0), e),
                sq_gauge(p + vec3<f32>(0.0, d, 0.0), e) - sq_gauge(p - vec3<f32>(0.0, d, 0.0), e),
                sq_gauge(p + vec3<f32>(0.0, 0.0, d), e) - sq_gauge(p - vec3<f32>(0.0, 0.0, d), e)));
            return h;
        }
        prev = s;
    }
    return h;
}

// bounding_scale in src/glyph/superquadric.rs: the radius (local unit coordinates) of the
// smallest ball about the centre holding the solid of exponents e.
fn sq_bound(e: vec3<f32>) -> f32 {
    let beta = min(e.y, e.z);
    let m = max(exp2(1.0 - e.x), 1.0);
    var s2 = m;
    if beta < 1.0 {
        let k = 1.0 - beta;
        s2 = m * pow(1.0 + pow(m, -1.0 / k), k);
    }
    return min(sqrt(s2), 1.7320508);
}
