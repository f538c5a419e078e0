// Sigg et al.'s method (shared part): one screen-space bounding box per glyph from the projected
// conic (Sigg eq. 5), drawn as an instanced 4-vertex strip at its NDC corners, and a per-pixel
// ray rebuilt from @builtin(position) and the camera, solved in parameter space with a
// glyph-near origin. Math: shared/math/sigg-quadric.md §2, §4, §7. Mirrored in f64 by
// src/render/sigg_math.rs. Composed as common.wgsl + this + sigg_<glyph>.wgsl + outputs.wgsl.

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // The box point in view space (at the proxy depth): the flat variants' view z.
    @location(0) v_view: vec3<f32>,
    @location(1) @interpolate(flat) id: u32,
    @location(2) @interpolate(flat) color: u32,
    @location(3) @interpolate(flat) centre: vec3<f32>,
    // Rows of A = diag(1/r) Oᵀ (world to the glyph's parameter space); Aᵀ maps normals back.
    @location(4) @interpolate(flat) a0: vec3<f32>,
    @location(5) @interpolate(flat) a1: vec3<f32>,
    @location(6) @interpolate(flat) a2: vec3<f32>,
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
    let r4 = vec4<f32>(mu.w, mv.w, mw.w, mc.w);
    let r44 = ddot(r4, r4);
    var b: SiggBox;
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

// The flat per-glyph varyings.
fn glyph_varyings(out: ptr<function, VsOut>, g: GpuGlyph, o: mat3x3<f32>, id: u32) {
    (*out).id = id;
    (*out).color = g.color;
    (*out).centre = g.centre;
    (*out).a0 = o[0] / g.radii.x;
    (*out).a1 = o[1] / g.radii.y;
    (*out).a2 = o[2] / g.radii.z;
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

struct PixelRay {
    // Perspective: the eye; orthographic: the pixel's point on the camera plane (view z = 0).
    o: vec3<f32>,
    // Unit direction.
    d: vec3<f32>,
}

// The pixel's ray from its window position (pixel centres at +0.5). Perspective: the direction
// is the line where the NDC planes x = const and y = const (rows of P View) meet.
fn pixel_ray(frag: vec4<f32>) -> PixelRay {
    let ndc = vec2<f32>(2.0 * frag.x * camera.viewport.z - 1.0, 1.0 - 2.0 * frag.y * camera.viewport.w);
    let f = camera.forward.xyz;
    if is_ortho() {
        let h = camera.inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
        return PixelRay(h.xyz / h.w - camera.depth.z * f, f);
    }
    let vp = camera.view_proj;
    let r4 = vec3<f32>(vp[0].w, vp[1].w, vp[2].w);
    let n1 = vec3<f32>(vp[0].x, vp[1].x, vp[2].x) - ndc.x * r4;
    let n2 = vec3<f32>(vp[0].y, vp[1].y, vp[2].y) - ndc.y * r4;
    let d = normalize(cross(n1, n2));
    return PixelRay(camera.eye.xyz, select(d, -d, dot(d, f) < 0.0));
}

// The glyph-near origin of §4: the ray point closest to the centre, in parameter space, and the
// ray direction there; t0 is its distance along the ray.
struct ParamRay {
    o_t: vec3<f32>,
    v_t: vec3<f32>,
    t0: f32,
}

fn to_param(in: VsOut, ray: PixelRay) -> ParamRay {
    let a = transpose(mat3x3<f32>(in.a0, in.a1, in.a2));
    let t0 = dot(in.centre - ray.o, ray.d);
    return ParamRay(a * ((ray.o - in.centre) + t0 * ray.d), a * ray.d, t0);
}

// Shade the hit at distance t along the ray with parameter-space normal n_t; depth from the
// hit point (standard Z).
fn finish(in: VsOut, ray: PixelRay, t: f32, n_t: vec3<f32>) -> Hit {
    let rv = mat3x3<f32>(camera.view[0].xyz, camera.view[1].xyz, camera.view[2].xyz);
    var p_view: vec3<f32>;
    var depth: f32;
    if is_ortho() {
        // The origin lies on the camera plane: view z = −t.
        p_view = vec3<f32>((camera.view * vec4<f32>(ray.o, 1.0)).xy, -t);
        depth = camera.depth.y * p_view.z + camera.depth.x;
    } else {
        p_view = t * (rv * ray.d);
        // (P22 z + B) / (−z) = B / d − P22 with d = −z.
        depth = camera.depth.x / -p_view.z - camera.depth.y;
    }
    let n_view = normalize(rv * (mat3x3<f32>(in.a0, in.a1, in.a2) * n_t));
    var hit: Hit;
    hit.color = vec4<f32>(shade(unpack4x8unorm(in.color).rgb, n_view, p_view), 1.0);
    hit.n_view = n_view;
    hit.z_view = p_view.z;
    hit.depth = depth;
    return hit;
}
