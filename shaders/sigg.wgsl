// Sigg et al.'s method (shared part): one screen-space bounding box per glyph from the projected
// conic (Sigg eq. 5), drawn as an instanced 4-vertex strip at its NDC corners, and a per-pixel
// ray rebuilt from @builtin(position) and the camera, solved in parameter space with a
// glyph-near origin. Math: shared/math/sigg-quadric.md §2, §4, §7. The box is mirrored in f64
// by src/render/sigg_math.rs. Composed as common.wgsl + this + sigg_<glyph>.wgsl + outputs.wgsl.
// The fragment stage works in view space, its rays taken from the whole image's centre and
// pixel scale (a tile's projection is off-centre).

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The box point in view space (at the proxy depth): the flat variants' view z.
    @location(0) v_view: vec3<f32>,
    @location(1) @interpolate(flat) id: u32,
    @location(2) @interpolate(flat) color: u32,
    // The glyph centre in view space.
    @location(3) @interpolate(flat) c_view: vec3<f32>,
    // Rows of A = diag(1/r) Oᵀ R_viewᵀ (view to the glyph's parameter space); Aᵀ maps
    // parameter-space normals to view space.
    @location(4) @interpolate(flat) a0: vec3<f32>,
    @location(5) @interpolate(flat) a1: vec3<f32>,
    @location(6) @interpolate(flat) a2: vec3<f32>,
    // Shape parameters of the glyph kind (capsules: x, the segment's half-length in units of R;
    // superquadrics: the exponents α, β, c and the bounding ball's radius).
    @location(7) @interpolate(flat) shape: vec4<f32>,
}

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

fn view_rotation() -> mat3x3<f32> {
    return mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
}

// The flat per-glyph varyings.
fn glyph_varyings(out: ptr<function, VsOut>, g: Glyph, o: mat3x3<f32>, id: u32) {
    let rv = view_rotation();
    (*out).id = id;
    (*out).color = g.color;
    (*out).c_view = (camera.view * vec4<f32>(g.centre, 1.0)).xyz;
    (*out).a0 = rv * o[0] / g.radii.x;
    (*out).a1 = rv * o[1] / g.radii.y;
    (*out).a2 = rv * o[2] / g.radii.z;
}

// Corner vi of the strip ((−,−), (+,−), (−,+), (+,+)) of the box, or of the whole viewport at
// the near plane; position and view-space point. Corners are clamped to the viewport.
fn emit_corner(out: ptr<function, VsOut>, vi: u32, b: SiggBox) {
    let k = vec2<bool>((vi & 1u) != 0u, (vi & 2u) != 0u);
    var ndc = vec3<f32>(select(vec2<f32>(-1.0), vec2<f32>(1.0), k), 0.0);
    if b.kind == PROXY_BOX {
        ndc = vec3<f32>(clamp(select(b.lo, b.hi, k), vec2<f32>(-1.0), vec2<f32>(1.0)), clamp(b.z, 0.0, 1.0));
    }
    (*out).position = vec4<f32>(ndc, 1.0);
    let h = camera.inv_view_proj * vec4<f32>(ndc, 1.0);
    (*out).v_view = (camera.view * vec4<f32>(h.xyz / h.w, 1.0)).xyz;
}

// Outside the clip volume (z < 0): all four corners are clipped away.
fn culled() -> VsOut {
    var out: VsOut;
    out.position = vec4<f32>(0.0, 0.0, -2.0, 1.0);
    return out;
}

// The fragment's ray (glyph_pixel_ray in common.wgsl, shared with Gumhold's orthographic solids).
fn pixel_ray(in: VsOut) -> ParamRay {
    return glyph_pixel_ray(in.position.xy, in.c_view, transpose(mat3x3<f32>(in.a0, in.a1, in.a2)));
}

// Shade the hit at t' along the ray from the glyph-near origin with parameter-space normal n_t;
// depth from the hit point (standard Z).
fn finish(in: VsOut, r: ParamRay, tp: f32, n_t: vec3<f32>) -> Hit {
    let p_view = in.c_view + r.off + tp * r.d;
    let n_view = normalize(mat3x3<f32>(in.a0, in.a1, in.a2) * n_t);
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_rel = (r.off + tp * r.d).z;
    hit.z_proxy_rel = in.v_view.z - in.c_view.z;
    hit.depth = view_depth(p_view.z);
    return hit;
}
