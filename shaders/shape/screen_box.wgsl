// Screen boxes (shared/math/sigg-quadric.md §2): the NDC box of a projected quadric (Sigg et al.
// eq. 5) and of the hull of two, with the frustum planes each one reaches. Every kind's
// `shape_box` (shaders/shape/<kind>.wgsl) is built from these; Sigg's method draws it. Composed
// after common.wgsl in every glyph shader. Twin: src/twin/screen_box.rs.

// How a glyph is drawn.
const PROXY_BOX: u32 = 0u;
// Crosses the camera plane (eq. 5 gives no finite box): cover the viewport.
const PROXY_VIEWPORT: u32 = 1u;
// Entirely behind the camera plane, or the eye is inside: not drawn.
const PROXY_CULL: u32 = 2u;

struct SiggBox {
    // NDC corners (xmin, ymin) and (xmax, ymax).
    lo: vec2<f32>,
    hi: vec2<f32>,
    // NDC depth of the centre (the proxy depth of the flat variants).
    z: f32,
    kind: u32,
    // The largest value over the glyph of the clip-space planes w + x, w − x, w + y (reach_a)
    // and w − y, z, w − z (reach_b): negative = wholly outside that frustum plane.
    reach_a: vec3<f32>,
    reach_b: vec3<f32>,
}

// max over the unit ball of the parameter-space plane n: n.w + |n.xyz|.
fn reach(n: vec4<f32>) -> f32 {
    return n.w + length(n.xyz);
}

// A glyph wholly outside one frustum plane is culled (an addition to Sigg: it keeps glyphs
// beside the eye, which cross the camera plane, from drawing viewport proxies).
fn outside_frustum(b: SiggBox) -> bool {
    return any(b.reach_a < vec3<f32>(0.0)) || any(b.reach_b < vec3<f32>(0.0));
}

// Minkowski product with D = diag(1, 1, 1, −1).
fn ddot(a: vec4<f32>, b: vec4<f32>) -> f32 {
    return dot(a.xyz, b.xyz) - a.w * b.w;
}

// Box of the ellipsoid with variance matrix T = [[u, v, w, c], [0, 0, 0, 1]] (eq. 5 with
// M = P View T). Written around the box centre b0 = r1ᵀDr4 / r4ᵀDr4: with n = r1 − b0 r4 the
// half-width is √(−nᵀDn / r4ᵀDr4), which does not cancel for small or off-centre glyphs.
fn quadric_box(u: vec3<f32>, v: vec3<f32>, w: vec3<f32>, c: vec3<f32>) -> SiggBox {
    let mu = camera.view_proj * vec4<f32>(u, 0.0);
    let mv = camera.view_proj * vec4<f32>(v, 0.0);
    let mw = camera.view_proj * vec4<f32>(w, 0.0);
    let mc = camera.view_proj * vec4<f32>(c, 1.0);
    let r1 = vec4<f32>(mu.x, mv.x, mw.x, mc.x);
    let r2 = vec4<f32>(mu.y, mv.y, mw.y, mc.y);
    let r3 = vec4<f32>(mu.z, mv.z, mw.z, mc.z);
    let r4 = vec4<f32>(mu.w, mv.w, mw.w, mc.w);
    let r44 = ddot(r4, r4);
    var b: SiggBox;
    b.reach_a = vec3<f32>(reach(r4 + r1), reach(r4 - r1), reach(r4 + r2));
    b.reach_b = vec3<f32>(reach(r4 - r2), reach(r3), reach(r4 - r3));
    if !(r44 < 0.0) {
        b.kind = PROXY_VIEWPORT;
        return b;
    }
    if !(mc.w > 0.0) {
        b.kind = PROXY_CULL;
        return b;
    }
    let b0 = vec2<f32>(ddot(r1, r4), ddot(r2, r4)) / r44;
    let n1 = r1 - b0.x * r4;
    let n2 = r2 - b0.y * r4;
    let h = sqrt(max(vec2<f32>(ddot(n1, n1), ddot(n2, n2)) / -r44, vec2<f32>(0.0)));
    b.lo = b0 - h;
    b.hi = b0 + h;
    b.z = mc.z / mc.w;
    b.kind = PROXY_BOX;
    return b;
}

// The box of the hull of a solid's two end pieces (a cylinder's discs, a capsule's balls) from
// theirs: their union where both are boxes, the viewport where one crosses the camera plane or
// they lie on both sides of it, PROXY_CULL where both are culled or the hull lies outside the
// frustum (outside a plane iff both pieces are).
fn hull_box(b1: SiggBox, b2: SiggBox) -> SiggBox {
    var b = b1;
    b.reach_a = max(b1.reach_a, b2.reach_a);
    b.reach_b = max(b1.reach_b, b2.reach_b);
    if outside_frustum(b) || (b1.kind == PROXY_CULL && b2.kind == PROXY_CULL) {
        b.kind = PROXY_CULL;
    } else if b1.kind == PROXY_BOX && b2.kind == PROXY_BOX {
        b.lo = min(b1.lo, b2.lo);
        b.hi = max(b1.hi, b2.hi);
        b.z = clamp(0.5 * (b1.z + b2.z), 0.0, 1.0);
    } else {
        b.kind = PROXY_VIEWPORT;
    }
    return b;
}
