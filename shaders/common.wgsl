// Shared by every glyph method: camera, per-glyph data, lighting and fragment outputs.
// Keep the structs in sync with src/render/gpu_data.rs (sizes are checked by a unit test).

struct Camera {
    view_proj: mat4x4<f32>,
    view: mat4x4<f32>,
    // World (relative to the scene origin) from clip space: rays for viewport-covering proxies.
    inv_view_proj: mat4x4<f32>,
    // xyz: eye relative to the scene origin; w: 1 for orthographic, 0 for perspective.
    eye: vec4<f32>,
    // xyz: unit view direction (world); w unused.
    forward: vec4<f32>,
    // x: B = P[2][3], y: P[2][2], z: near, w: far.
    depth: vec4<f32>,
    // x, y: viewport size in pixels; z, w: their reciprocals.
    viewport: vec4<f32>,
    // x: ambient, y: diffuse, z: specular, w: shininess (Blinn-Phong headlight).
    light: vec4<f32>,
    // Clip planes (left, right, bottom, top, near, far): inward unit normal and offset, relative
    // to the scene origin (Camera::frustum_planes).
    frustum: array<vec4<f32>, 6>,
    // x: pixels per world unit at view distance 1 (orthographic: at any distance); y, z: the
    // whole image's centre (the principal point) in this viewport's pixels, off-centre for a tile;
    // w: 1 when shading is deferred (the colour target gets the unlit base colour, see
    // composite.wgsl).
    pixels: vec4<f32>,
    // Rows 0..3 of `view` (columns 0..4) less their f32 rounding: the view transform in
    // double-f32 with `view` (centre_ray).
    view_lo: array<vec4<f32>, 3>,
    // pixels.x and its reciprocal, each in double-f32: (hi, lo, hi, lo).
    pixel_scale: vec4<f32>,
}

// One glyph as stored: 32 bytes (layout in src/render/gpu_data.rs). Read it with load_glyph.
struct GpuGlyph {
    centre: vec3<f32>,
    // Radius i as a 24-bit float (bits 8..32) and colour channel i (bits 0..8).
    radius_rgb0: u32,
    radius_rgb1: u32,
    radius_rgb2: u32,
    // The rotation quaternion, "smallest three" at 20 bits.
    rotation0: u32,
    rotation1: u32,
}

// Which instances this draw's glyph buffer holds (large scenes are split into chunks within
// the adapter's buffer limits).
struct Chunk {
    // instance_index of the buffer's first glyph.
    base: u32,
    // Pixels: glyphs whose projected bounding sphere is smaller are not drawn (0: all drawn).
    min_pixel_radius: f32,
    // 1: cull glyphs outside the view frustum in the vertex stage.
    cull: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> glyphs: array<GpuGlyph>;
@group(0) @binding(2) var<storage, read> chunk: Chunk;
// Superquadric exponents (α, β, c), 21 bits each (pack_exponents in src/glyph/superquadric.rs),
// one pair of words per glyph of the chunk. Bound for every method, read by superquadrics only.
@group(0) @binding(3) var<storage, read> shapes: array<vec2<u32>>;

// A glyph decoded.
struct Glyph {
    // Centre relative to the scene origin.
    centre: vec3<f32>,
    // RGBA8, unpack4x8unorm.
    color: u32,
    // Unit quaternion (x, y, z, w) of the eigenvector frame O.
    rotation: vec4<f32>,
    // Semi-axes along O's columns; T = O diag(radii) Oᵀ.
    radii: vec3<f32>,
}

// Radii spanning more than this make a glyph thin (src/shape/geometry.rs THIN_RATIO): its
// quaternion is decoded exactly as the CPU decodes it (quat_largest), and its chunk is drawn
// with THIN_EXACT. The default --min-radius (0.01) keeps every glyph at or under it.
const THIN_RATIO: f32 = 100.0;

// 1.5 · 2⁻²⁰: one step of a stored quaternion component, (n − 2¹⁹) · QUAT_STEP, exact in f32
// (src/shape/geometry.rs QUAT_STEP; the reference casts the same decoded glyph).
const QUAT_STEP: f32 = 1.4305115e-6;

fn load_glyph(instance: u32) -> Glyph {
    let s = glyphs[instance - chunk.base];
    var g: Glyph;
    g.centre = s.centre;
    g.radii = vec3<f32>(
        bitcast<f32>((s.radius_rgb0 >> 8u) << 7u),
        bitcast<f32>((s.radius_rgb1 >> 8u) << 7u),
        bitcast<f32>((s.radius_rgb2 >> 8u) << 7u),
    );
    g.color = (s.radius_rgb0 & 0xffu) | ((s.radius_rgb1 & 0xffu) << 8u)
        | ((s.radius_rgb2 & 0xffu) << 16u) | 0xff000000u;
    let a = f32(i32(s.rotation0 & 0xfffffu) - 524288) * QUAT_STEP;
    let b = f32(i32((s.rotation0 >> 20u) | ((s.rotation1 & 0xffu) << 12u)) - 524288) * QUAT_STEP;
    let c = f32(i32((s.rotation1 >> 8u) & 0xfffffu) - 524288) * QUAT_STEP;
    // Exact, as the CPU has it, where a glyph is thin enough to show the difference; elsewhere
    // f32 (within an ulp of it).
    var big = sqrt(max(1.0 - (a * a + b * b + c * c), 0.0));
    let rmax = max(g.radii.x, max(g.radii.y, g.radii.z));
    if rmax > THIN_RATIO * min(g.radii.x, min(g.radii.y, g.radii.z)) {
        big = quat_largest(a, b, c);
    }
    switch (s.rotation1 >> 28u) & 3u {
        case 0u: { g.rotation = vec4<f32>(big, a, b, c); }
        case 1u: { g.rotation = vec4<f32>(a, big, b, c); }
        case 2u: { g.rotation = vec4<f32>(a, b, big, c); }
        default: { g.rotation = vec4<f32>(a, b, c, big); }
    }
    return g;
}

// √(1 − a² − b² − c²) rounded to f32 from double-f32 (a, b, c exact), as the CPU forms it in f64
// (unpack_rotation in src/shape/geometry.rs): both sides then hold the same quaternion, to which
// a thin glyph is sensitive (an ulp of it turns a glyph by 6e-8 rad, which a needle of k = 1e5
// turns into 0.3° of normal at its rim).
fn quat_largest(a: f32, b: f32, c: f32) -> f32 {
    df_begin();
    let x = df_add(vec2<f32>(1.0, 0.0), -df_add(df_add(two_prod(a, a), two_prod(b, b)), two_prod(c, c)));
    if !(x.x > 0.0) {
        return 0.0;
    }
    let r = sqrt(x.x);
    // One Newton step on the double-f32 residual.
    return r + df_add(x, -two_prod(r, r)).x / (2.0 * r);
}

// The shape interface. Every kind's file, shaders/shape/<kind>.wgsl, defines these functions,
// which every method calls (Gumhold's solids, Sigg's boxes, the meshes):
//
//   shape_radius(radii) -> f32         radius of a sphere about the centre holding the glyph
//                                      (the vertex stages cull with it)
//   shape_of(g, ii) -> Solid           the glyph's parameter space and parameters
//   shape_contains(p, shape) -> bool   p (parameter space) is in the glyph: the eye rule
//   shape_entry(o, v, shape, t_min) -> vec4<f32>
//                                      Gumhold's solids: (t, parameter-space normal) where the
//                                      ray o + t v enters, discarding on a miss
//   shape_box(g, o, solid) -> SiggBox  Sigg's screen box (shaders/shape/screen_box.wgsl),
//                                      PROXY_CULL outside the frustum
//   shape_cast(r, shape) -> vec4<f32>  Sigg: (t, normal) of the first crossing in front of the
//                                      ray's start (r may be moved along itself), or discard
//   shape_mesh_point(p, n, g, solid) -> MeshPoint
//                                      mesh:N: a unit-mesh vertex placed in the glyph's frame
//   shape_box_half(g, solid) -> vec3<f32>
//                                      box: the half sizes of the box drawn for the glyph
//
// Twins: src/twin/<kind>.rs; the exact geometry: src/shape/<kind>.rs.

// A glyph in its parameter space p~ = diag(1/scale) Oᵀ (p − c).
struct Solid {
    scale: vec3<f32>,
    // Semi-axes of the ellipsoid (parameter space) whose quad Gumhold's method draws.
    bound: vec3<f32>,
    // The kind's parameters (a capsule's segment half-length in units of its radius; a
    // superquadric's exponents and bounding ball).
    shape: vec4<f32>,
}

// A mesh vertex in the glyph's frame (not yet rotated) and its normal there (not unit).
struct MeshPoint {
    local: vec3<f32>,
    n_local: vec3<f32>,
}

// The kind's two parameter words of instance `instance` (GlyphInstance::shape).
fn load_shape_words(instance: u32) -> vec2<u32> {
    return shapes[instance - chunk.base];
}

// The exponents (α, β, c) of superquadric instance `instance` (unpack_exponents in
// src/glyph/superquadric.rs).
fn load_exponents(instance: u32) -> vec3<f32> {
    let w = shapes[instance - chunk.base];
    let a = w.x & 0x1fffffu;
    let b = (w.x >> 21u) | ((w.y & 0x3ffu) << 11u);
    let c = (w.y >> 10u) & 0x1fffffu;
    return vec3<f32>(bitcast<f32>(a << 10u), bitcast<f32>(b << 10u), bitcast<f32>(c << 10u));
}

// E² (the eye in an ellipsoid's parameter space, squared) at or below this counts as "eye
// inside or on the ellipsoid": the ellipsoid glyphs are culled there, as by the reference
// (reference::EYE_INSIDE_E2); Gumhold's cylinders then draw on the near plane.
const EYE_INSIDE_E2: f32 = 1.00001;

// The camera's flags are read at an index the shader compiler cannot know. Mesa's lavapipe (the
// CI's Vulkan, 22.x) inlines uniform-buffer words that alone decide an `if` and, when that
// removes much code, optimises the shader again at every bind: on a close view of 27 glyphs that
// was 4.4 of 6.6 ms per frame for ellipsoids and 7.5 of 16 for superquadrics. A word read at a
// computed offset is not inlined (chunk and slice are storage buffers for the same reason);
// tests::no_if_decided_by_uniform_words_alone in src/render/shaders.rs keeps it so. The index
// is 3 for every camera (eye.w is 0 or 1).
fn flag_index() -> u32 {
    return 3u + u32(camera.eye.w > 2.0);
}

fn is_ortho() -> bool {
    return camera.eye[flag_index()] > 0.5;
}

// Shading is deferred (composite.wgsl lights the pixels).
fn shading_deferred() -> bool {
    return camera.pixels[flag_index()] > 0.5;
}

// A glyph is drawn only if every radius is finite and at least this fraction of the largest
// (2⁻²⁴: thinner than f32 resolves at the glyph's own scale, T⁻¹ is meaningless). NaN fails
// every comparison, so NaN radii are not drawn either. Mirrored by reference::drawable_radii.
const MIN_RADIUS_RATIO: f32 = 5.9604645e-8;

fn drawable(r: vec3<f32>) -> bool {
    let rmax = max(r.x, max(r.y, r.z));
    let rmin = min(r.x, min(r.y, r.z));
    return rmin > 0.0 && rmin >= rmax * MIN_RADIUS_RATIO && rmax <= 3.0e38;
}

// How far a proxy reaches beyond the silhouette it touches (Gumhold's ellipsoid quad, Sigg's
// boxes), in pixels: a rasteriser may place the edges up to that much inside (SwiftShader got
// 0.12 % of grid40's glyph pixels wrong at the touching points, none with 1/8 px); the
// fragments outside are discarded.
const PROXY_MARGIN_PX: f32 = 0.125;

// Outside the clip volume (z < 0): every corner of a culled glyph is clipped away.
const CULLED_POSITION: vec4<f32> = vec4<f32>(0.0, 0.0, -2.0, 1.0);

// The factors on a proxy quad's half axes x, y (world) about a glyph centred at c that widen it
// by PROXY_MARGIN_PX on each side: its half widths measured in pixels on the view plane
// through the centre. A quad thinner than a pixel (a needle's) otherwise covers pixel centres
// at the rasteriser's whim (SwiftShader drew 0 of 28 pixels of k = 1e5 needles' Gumhold
// cylinders).
fn margin_growth(c: vec3<f32>, x: vec3<f32>, y: vec3<f32>) -> vec2<f32> {
    var w = 1.0;
    if !is_ortho() {
        w = max(dot(c - camera.eye.xyz, camera.forward.xyz), 1e-30);
    }
    let hx = length((camera.view * vec4<f32>(x, 0.0)).xy) * camera.pixels.x / w;
    let hy = length((camera.view * vec4<f32>(y, 0.0)).xy) * camera.pixels.x / w;
    return 1.0 + PROXY_MARGIN_PX / max(vec2<f32>(hx, hy), vec2<f32>(1e-30));
}

fn quat_to_mat3(q: vec4<f32>) -> mat3x3<f32> {
    let x2 = q.x + q.x;
    let y2 = q.y + q.y;
    let z2 = q.z + q.z;
    let xx = q.x * x2;
    let xy = q.x * y2;
    let xz = q.x * z2;
    let yy = q.y * y2;
    let yz = q.y * z2;
    let zz = q.z * z2;
    let wx = q.w * x2;
    let wy = q.w * y2;
    let wz = q.w * z2;
    return mat3x3<f32>(
        vec3<f32>(1.0 - (yy + zz), xy + wz, xz - wy),
        vec3<f32>(xy - wz, 1.0 - (xx + zz), yz + wx),
        vec3<f32>(xz + wy, yz - wx, 1.0 - (xx + yy)),
    );
}

// Orthonormal pair (x, y) with x × y = z (Duff et al. 2017; glam's any_orthonormal_pair).
fn orthonormal_pair(z: vec3<f32>) -> array<vec3<f32>, 2> {
    let s = select(-1.0, 1.0, z.z >= 0.0);
    let a = -1.0 / (s + z.z);
    let b = z.x * z.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + s * z.x * z.x * a, s * b, -s * z.x),
        vec3<f32>(b, s + z.y * z.y * a, -z.y),
    );
}

// The corner signs (s_x, s_y) ∈ {−1, 1}² of strip vertex k (0..3, strip order (-,-), (+,-),
// (-,+), (+,+)).
fn corner_signs(k: u32) -> vec2<f32> {
    return vec2<f32>(select(-1.0, 1.0, (k & 1u) != 0u), select(-1.0, 1.0, (k & 2u) != 0u));
}

// Vertices of the ray casters' proxy polygon around the unit circle (gumhold-ellipsoid.md §10):
// 4 (Gumhold's quad), 8 (the circumscribed octagon: 1.05 of the circle's area instead of 4/π)
// or 3 (the circumscribed triangle: one triangle to set up instead of two, 1.65 of the area).
override PROXY_VERTICES: u32 = 4u;
// Gumhold ellipsoids: place the proxy on the glyph's nearest view plane, so the rasterised depth
// never exceeds the ray-cast depth (conservative depth; lets early depth tests reject).
override CONSERVATIVE_DEPTH: bool = false;

// Octagon strip order (gumhold-ellipsoid.md §10): 0, 1, 7, 2, 6, 3, 5, 4.
const OCTAGON_STRIP: array<u32, 8> = array<u32, 8>(0u, 1u, 7u, 2u, 6u, 3u, 5u, 4u);
// sec(π/8): the octagon's vertices circumscribe the unit circle.
const SEC_PI_8: f32 = 1.0823922;

// Vertex vi of the proxy polygon around the unit circle (a triangle strip).
fn proxy_corner(vi: u32) -> vec2<f32> {
    if PROXY_VERTICES == 3u {
        // At radius 2 = 1/cos(π/3), from the top, 120° apart.
        let theta = 1.5707963 + f32(vi) * 2.0943951;
        return 2.0 * vec2<f32>(cos(theta), sin(theta));
    }
    if PROXY_VERTICES == 8u {
        let theta = (f32(OCTAGON_STRIP[vi & 7u]) * 2.0 + 1.0) * 0.39269908;
        return SEC_PI_8 * vec2<f32>(cos(theta), sin(theta));
    }
    return corner_signs(vi);
}

// NDC (x, y) of vertex vi of a proxy covering the whole viewport on the near plane, for glyphs
// the eye is too close to: the viewport's corners, or √2 × the octagon or triangle (which then
// contains the square [−1, 1]²).
fn near_plane_ndc(vi: u32) -> vec2<f32> {
    if PROXY_VERTICES != 4u {
        return proxy_corner(vi) * 1.4142135;
    }
    return corner_signs(vi);
}

// The world point (relative to the scene origin) of an NDC point on the near plane.
fn near_plane_point(ndc: vec2<f32>) -> vec3<f32> {
    let h = camera.inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
    return h.xyz / h.w;
}

// Double-f32 arithmetic: a value is hi + lo (vec2: x = hi, y = lo), ~2⁻⁴⁸ relative, for the
// few per-glyph numbers that f32 cannot hold (centre_ray). Nothing in SPIR-V keeps a compiler
// from simplifying these formulas (naga marks nothing NoContraction or exact): products split
// their factors by masking bits, not by Dekker's 4097 · a, so every partial product is exact and
// fusing a · b + c into fma changes nothing; sums pass through `opaque`, since lavapipe's NIR
// folds (a + b) − a into b, which turns every error term into 0. tests/gpu/double_f32.rs checks
// the arithmetic on the device against f64.

// A 0 the compiler cannot know: df_begin sets it from the camera (eye.w is 0 or 1, read at a
// computed index), once per invocation, before any double-f32 arithmetic.
var<private> df_salt: u32;

fn df_begin() {
    df_salt = u32(camera.eye[flag_index()] > 2.0);
}

// x, through df_salt.
fn opaque(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) ^ df_salt);
}

fn df_split(a: f32) -> vec2<f32> {
    // 12 significant bits each: products of halves are exact in f32.
    let hi = bitcast<f32>(bitcast<u32>(a) & 0xfffff000u);
    return vec2<f32>(hi, a - hi);
}

fn two_sum(a: f32, b: f32) -> vec2<f32> {
    let s = opaque(a + b);
    let bb = opaque(s - a);
    return vec2<f32>(s, (a - (s - bb)) + (b - bb));
}

// |a| ≥ |b| (or a = 0).
fn quick_two_sum(a: f32, b: f32) -> vec2<f32> {
    let s = opaque(a + b);
    return vec2<f32>(s, b - (s - a));
}

fn two_prod(a: f32, b: f32) -> vec2<f32> {
    let p = a * b;
    let x = df_split(a);
    let y = df_split(b);
    return vec2<f32>(p, ((x.x * y.x - p) + x.x * y.y + x.y * y.x) + x.y * y.y);
}

fn df_add(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let s = two_sum(a.x, b.x);
    return quick_two_sum(s.x, s.y + (a.y + b.y));
}

fn df_mul_f(a: vec2<f32>, b: f32) -> vec2<f32> {
    let p = two_prod(a.x, b);
    return quick_two_sum(p.x, p.y + a.y * b);
}

fn df_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let p = two_prod(a.x, b.x);
    return quick_two_sum(p.x, p.y + (a.x * b.y + a.y * b.x));
}

fn df_div(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let q1 = a.x / b.x;
    let r = df_add(a, -df_mul_f(b, q1));
    return quick_two_sum(q1, r.x / b.x);
}

// Where a glyph's centre lies for the rays of its pixels. A pixel's offset from the centre's
// ray, o(px) (pixel_offset), is a small difference of two large numbers, the pixel's view
// direction and the centre's, each ~|xy| (up to ~0.5 at the image's edge): f32 rounds each to
// ~2⁻²⁴·|xy|, a lateral error of 2⁻²⁴·|xy|·D at the glyph's distance D, which a glyph of
// radius r sees as 2⁻²⁴·|xy|·D/r of itself (grid40: depth p99 5e-5; needles: normals ~0.3°).
// Here it is formed once per glyph in double-f32 for one pixel centre px0 next to the centre's
// projection, where it is ≤ ~1 px and f32 holds it to 2⁻²⁴ of itself; every other pixel adds
// its exact integer distance from px0.
struct CentreRay {
    // The centre in view space (the double-f32 transform, rounded).
    c_view: vec3<f32>,
    // A pixel centre (framebuffer coordinates) and o(px0).
    px0: vec2<f32>,
    o0: vec2<f32>,
    // What rounding left of the centre's view z and of o(px0)'s x and y (thin_pixel_ray).
    lo: vec3<f32>,
}

// Row i of the view transform applied to c, in double-f32: hi and lo are the row's four
// entries (rotation, then translation) and what f32 left of them. Written out, not looped:
// lavapipe keeps a run-time-indexed local array in memory.
fn view_row(hi: vec4<f32>, lo: vec4<f32>, c: vec3<f32>) -> vec2<f32> {
    var acc = vec2<f32>(hi.w, lo.w);
    acc = df_add(acc, df_mul_f(vec2<f32>(hi.x, lo.x), c.x));
    acc = df_add(acc, df_mul_f(vec2<f32>(hi.y, lo.y), c.y));
    return df_add(acc, df_mul_f(vec2<f32>(hi.z, lo.z), c.z));
}

fn centre_ray(c: vec3<f32>) -> CentreRay {
    df_begin();
    let v = camera.view;
    let cx = view_row(vec4<f32>(v[0].x, v[1].x, v[2].x, v[3].x), camera.view_lo[0], c);
    let cy = view_row(vec4<f32>(v[0].y, v[1].y, v[2].y, v[3].y), camera.view_lo[1], c);
    let cz = view_row(vec4<f32>(v[0].z, v[1].z, v[2].z, v[3].z), camera.view_lo[2], c);
    var r: CentreRay;
    r.c_view = vec3<f32>(cx.x + cx.y, cy.x + cy.y, cz.x + cz.y);
    // The centre's view (x, y): at view distance 1 (perspective) or as it is (orthographic).
    var ax = cx;
    var ay = cy;
    if !is_ortho() {
        if !(cz.x < 0.0) {
            // Behind the eye's plane: any px0 is exact, the principal point will do.
            r.px0 = camera.pixels.yz;
            r.o0 = pixel_view_xy(r.px0) - r.c_view.xy / -r.c_view.z;
            return r;
        }
        ax = df_div(cx, -cz);
        ay = df_div(cy, -cz);
    }
    let f = camera.pixels.x;
    let proj = vec2<f32>(camera.pixels.y + f * ax.x, camera.pixels.z - f * ay.x);
    // df_add's results are normalised: hi + lo rounds to hi, so lo is all rounding left.
    r.lo.x = cz.y;
    // Clamped so px − px0 stays exact for every pixel of any viewport.
    r.px0 = clamp(floor(proj), vec2<f32>(-16384.0), vec2<f32>(16384.0)) + 0.5;
    let inv_f = camera.pixel_scale.zw;
    let ox = df_add(df_mul_f(inv_f, r.px0.x - camera.pixels.y), -ax);
    let oy = df_add(df_mul_f(inv_f, camera.pixels.z - r.px0.y), -ay);
    r.o0 = vec2<f32>(ox.x + ox.y, oy.x + oy.y);
    r.lo = vec3<f32>(r.lo.x, ox.y, oy.y);
    return r;
}

// o(px): the pixel's view (x, y) less the centre's, at view distance 1 (perspective: the
// pixel's ray direction (xy, −1) less the centre's c/(−c.z)) or in view units (orthographic).
fn pixel_offset(px: vec2<f32>, px0: vec2<f32>, o0: vec2<f32>) -> vec2<f32> {
    let d = px - px0;
    return o0 + vec2<f32>(d.x, -d.y) * camera.pixel_scale.z;
}

// The pixel's view-space (x, y) (at view distance 1 when perspective), for a framebuffer
// position px: measured from the whole image's centre, so a tile's off-centre pixels get their
// own rays.
fn pixel_view_xy(px: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(px.x - camera.pixels.y, camera.pixels.z - px.y) / camera.pixels.x;
}

// A pixel's ray towards one glyph, with the glyph-near origin of sigg-quadric.md §4 first taken
// where the ray crosses the plane z_view = c_view.z: the offset from the centre is formed from
// the pixel's position in screen space, so nothing cancels however far the glyph is (unlike
// eye + t d − c in world space, or a point interpolated across the screen).
struct ParamRay {
    // Origin offset from the centre (view space) and unit direction (view space).
    off: vec3<f32>,
    d: vec3<f32>,
    // The same in parameter space.
    o_t: vec3<f32>,
    v_t: vec3<f32>,
    // Distance from the ray's start (eye, or the camera plane when orthographic) to the origin.
    t0: f32,
}

// The ray of the pixel at framebuffer position px towards the glyph centred at c_view (view
// space; px0, o0: its centre_ray), whose parameter space is a · view space
// (a = diag(1/scale) Oᵀ R_viewᵀ).
fn glyph_pixel_ray(px: vec2<f32>, c_view: vec3<f32>, px0: vec2<f32>, o0: vec2<f32>, a: mat3x3<f32>, res: Residuals) -> ParamRay {
    if THIN_EXACT {
        return thin_pixel_ray(px, c_view, px0, o0, a, res);
    }
    let o = pixel_offset(px, px0, o0);
    var r: ParamRay;
    if is_ortho() {
        r.off = vec3<f32>(o, 0.0);
        r.d = vec3<f32>(0.0, 0.0, -1.0);
        r.t0 = -c_view.z;
    } else {
        let dv = vec3<f32>(pixel_view_xy(px), -1.0);
        let len = length(dv);
        r.off = vec3<f32>(-c_view.z * o, 0.0);
        r.d = dv / len;
        r.t0 = -c_view.z * len;
    }
    r.v_t = a * r.d;
    // Then slide it to the ray point closest to the centre in parameter space (β ≈ 0): for
    // thin glyphs this keeps |o~| ~ 1, so β² − αγ does not cancel near the silhouette.
    let s = -dot(a * r.off, r.v_t) / dot(r.v_t, r.v_t);
    r.off += s * r.d;
    r.t0 += s;
    r.o_t = a * r.off;
    return r;
}

// Thin glyphs. A glyph k = r_max/r_min thin sees f32's rounding of every number its rays are
// made of (the pixel's offset, the map A into parameter space, the glyph-near origin) ~k times
// magnified across its thin axes: needles at k = 1e5 had normals off by degrees. Chunks holding
// a glyph thinner than THIN_RATIO are drawn with THIN_EXACT (an override set per pipeline, so
// other chunks run none of it, which matters on CPU rasterisers that run both sides of every
// branch): A in double-f32 once per glyph (param_map), and each pixel's ray through it in
// double-f32 (thin_pixel_ray), down to the parameter-space origin, which is then O(1) and
// exact to f32's own rounding.
override THIN_EXACT: bool = false;

// What thin_pixel_ray needs beyond glyph_pixel_ray's f32 arguments: the residuals of the
// centre's view z and o(px0) (CentreRay.lo) and of A (a_lo, A's layout).
struct Residuals {
    lo: vec3<f32>,
    a_lo: mat3x3<f32>,
}

fn no_residuals() -> Residuals {
    return Residuals(vec3<f32>(0.0), mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)));
}

// A vector of three double-f32 numbers.
struct DfVec3 {
    x: vec2<f32>,
    y: vec2<f32>,
    z: vec2<f32>,
}

fn df_dot(a: DfVec3, b: DfVec3) -> vec2<f32> {
    return df_add(df_add(df_mul(a.x, b.x), df_mul(a.y, b.y)), df_mul(a.z, b.z));
}

// 2ab, exactly.
fn twice_prod(a: f32, b: f32) -> vec2<f32> {
    return 2.0 * two_prod(a, b);
}

// A = diag(1/scale) Oᵀ R_viewᵀ (view to parameter space) in double-f32: rows hi (r0..r2) and
// what f32 left of them (l0..l2). O is quat_to_mat3(q) term by term, as the reference forms it
// in f64 (quat_to_mat3_unnormalised).
struct ParamMap {
    r0: vec3<f32>,
    r1: vec3<f32>,
    r2: vec3<f32>,
    l0: vec3<f32>,
    l1: vec3<f32>,
    l2: vec3<f32>,
}

// Row i of A: the frame's column o_i against R_view's rows, over scale_i.
fn map_row(o: DfVec3, v0: DfVec3, v1: DfVec3, v2: DfVec3, k: f32) -> array<vec3<f32>, 2> {
    let x = df_mul_f(df_dot(o, v0), k);
    let y = df_mul_f(df_dot(o, v1), k);
    let z = df_mul_f(df_dot(o, v2), k);
    return array<vec3<f32>, 2>(vec3<f32>(x.x, y.x, z.x), vec3<f32>(x.y, y.y, z.y));
}

fn view_row_df(i: u32) -> DfVec3 {
    let v = camera.view;
    let lo = camera.view_lo[i];
    return DfVec3(vec2<f32>(v[0][i], lo.x), vec2<f32>(v[1][i], lo.y), vec2<f32>(v[2][i], lo.z));
}

fn param_map(q: vec4<f32>, scale: vec3<f32>) -> ParamMap {
    df_begin();
    let xx = twice_prod(q.x, q.x);
    let yy = twice_prod(q.y, q.y);
    let zz = twice_prod(q.z, q.z);
    let xy = twice_prod(q.x, q.y);
    let xz = twice_prod(q.x, q.z);
    let yz = twice_prod(q.y, q.z);
    let wx = twice_prod(q.w, q.x);
    let wy = twice_prod(q.w, q.y);
    let wz = twice_prod(q.w, q.z);
    let one = vec2<f32>(1.0, 0.0);
    let o0 = DfVec3(df_add(one, -df_add(yy, zz)), df_add(xy, wz), df_add(xz, -wy));
    let o1 = DfVec3(df_add(xy, -wz), df_add(one, -df_add(xx, zz)), df_add(yz, wx));
    let o2 = DfVec3(df_add(xz, wy), df_add(yz, -wx), df_add(one, -df_add(xx, yy)));
    let v0 = view_row_df(0u);
    let v1 = view_row_df(1u);
    let v2 = view_row_df(2u);
    let a0 = map_row(o0, v0, v1, v2, 1.0 / scale.x);
    let a1 = map_row(o1, v0, v1, v2, 1.0 / scale.y);
    let a2 = map_row(o2, v0, v1, v2, 1.0 / scale.z);
    return ParamMap(a0[0], a1[0], a2[0], a0[1], a1[1], a2[1]);
}

// A's rows hi and lo as glyph_pixel_ray takes them (a, res.a_lo).
fn map_hi(m: ParamMap) -> mat3x3<f32> {
    return transpose(mat3x3<f32>(m.r0, m.r1, m.r2));
}

fn map_lo(m: ParamMap) -> mat3x3<f32> {
    return transpose(mat3x3<f32>(m.l0, m.l1, m.l2));
}

// Row i of A·x in double-f32, A = a + a_lo, x's components double-f32.
fn map_apply(a: mat3x3<f32>, a_lo: mat3x3<f32>, i: u32, x: DfVec3) -> vec2<f32> {
    let row = DfVec3(vec2<f32>(a[0][i], a_lo[0][i]), vec2<f32>(a[1][i], a_lo[1][i]), vec2<f32>(a[2][i], a_lo[2][i]));
    return df_dot(row, x);
}

// What rounding left of thin_pixel_ray's o_t and v_t (o_t + thin_o_lo, v_t + thin_v_lo are its
// double-f32 values), for shapes whose own solve moves the origin far along the ray (capsules:
// capsule_cast_thin); set by every thin_pixel_ray.
var<private> thin_o_lo: vec3<f32>;
var<private> thin_v_lo: vec3<f32>;

// glyph_pixel_ray in double-f32 up to the glyph-near origin in parameter space: the pixel's
// offset o(px) (its exact integer distance from px0 over f, 1/f in double-f32), the ray's
// point level with the centre, −c_z o (c_z double-f32), the pixel's direction (xy, −1), both
// mapped by A, and the slide along the ray: the origin comes out O(1) and within an f32 ulp.
fn thin_pixel_ray(px: vec2<f32>, c_view: vec3<f32>, px0: vec2<f32>, o0: vec2<f32>, a: mat3x3<f32>, res: Residuals) -> ParamRay {
    df_begin();
    let inv_f = camera.pixel_scale.zw;
    let d = px - px0;
    let ox = df_add(vec2<f32>(o0.x, res.lo.y), df_mul_f(inv_f, d.x));
    let oy = df_add(vec2<f32>(o0.y, res.lo.z), df_mul_f(inv_f, -d.y));
    let zero = vec2<f32>(0.0);
    var off = DfVec3(ox, oy, zero);
    var dv = DfVec3(zero, zero, vec2<f32>(-1.0, 0.0));
    var r: ParamRay;
    var len = 1.0;
    r.t0 = -c_view.z;
    if !is_ortho() {
        let cz = vec2<f32>(-c_view.z, -res.lo.x);
        off = DfVec3(df_mul(cz, ox), df_mul(cz, oy), zero);
        dv.x = df_mul_f(inv_f, px.x - camera.pixels.y);
        dv.y = df_mul_f(inv_f, camera.pixels.z - px.y);
        len = length(vec3<f32>(dv.x.x, dv.y.x, -1.0));
        r.t0 = -c_view.z * len;
    }
    let a_lo = res.a_lo;
    let o_0 = map_apply(a, a_lo, 0u, off);
    let o_1 = map_apply(a, a_lo, 1u, off);
    let o_2 = map_apply(a, a_lo, 2u, off);
    let v_0 = map_apply(a, a_lo, 0u, dv);
    let v_1 = map_apply(a, a_lo, 1u, dv);
    let v_2 = map_apply(a, a_lo, 2u, dv);
    let vh = vec3<f32>(v_0.x, v_1.x, v_2.x);
    // The slide (in units of dv): only its rounding of the origin along the ray, harmless,
    // is f32's; the sum that cancels is double-f32.
    let s = -dot(vec3<f32>(o_0.x, o_1.x, o_2.x), vh) / dot(vh, vh);
    let p0 = df_add(o_0, df_mul_f(v_0, s));
    let p1 = df_add(o_1, df_mul_f(v_1, s));
    let p2 = df_add(o_2, df_mul_f(v_2, s));
    // Normalised double-f32 sums: hi + lo rounds to hi.
    r.o_t = vec3<f32>(p0.x, p1.x, p2.x);
    thin_o_lo = vec3<f32>(p0.y, p1.y, p2.y);
    let dir = vec3<f32>(dv.x.x, dv.y.x, -1.0);
    r.d = dir / len;
    r.v_t = vh / len;
    // v_t's residual: (v' − v_t len) / len, v_t len exactly.
    let e0 = df_add(v_0, -two_prod(r.v_t.x, len));
    let e1 = df_add(v_1, -two_prod(r.v_t.y, len));
    let e2 = df_add(v_2, -two_prod(r.v_t.z, len));
    thin_v_lo = vec3<f32>(e0.x, e1.x, e2.x) / len;
    r.off = vec3<f32>(off.x.x, off.y.x, 0.0) + s * dir;
    r.t0 += s * len;
    return r;
}

// The NDC depth (standard Z) of view z.
fn view_depth(z: f32) -> f32 {
    if is_ortho() {
        return camera.depth.y * z + camera.depth.x;
    }
    // (P22 z + B) / (−z) = B / d − P22 with d = −z.
    return camera.depth.x / -z - camera.depth.y;
}

// Radius of a sphere around a glyph drawn as an ellipsoid or as a capped cylinder (axis
// radii.x): √(r_axis² + r_cross²) ≥ the largest radius.
fn bounding_radius(r: vec3<f32>) -> f32 {
    return length(vec2<f32>(r.x, max(r.y, r.z)));
}

// True when a glyph inside the sphere (centre c, radius r) is not drawn: with chunk.cull, when
// it is outside a frustum plane (the near plane included: wholly in front of it); and when it is
// projected smaller than chunk.min_pixel_radius. Mirrored in f64 by Scene::visibility.
fn skip_glyph(c: vec3<f32>, r: f32) -> bool {
    if chunk.cull != 0u {
        for (var i = 0u; i < 6u; i++) {
            let p = camera.frustum[i];
            if dot(p.xyz, c) + p.w < -r {
                return true;
            }
        }
    }
    if chunk.min_pixel_radius <= 0.0 {
        return false;
    }
    var w = 1.0;
    if !is_ortho() {
        w = max(dot(c - camera.eye.xyz, camera.forward.xyz), 1e-30);
    }
    return r * camera.pixels.x / w < chunk.min_pixel_radius;
}

// Blinn-Phong with a headlight: the light sits at the eye, so L = H = direction to the eye.
// Mirrored in f64 by src/reference/shading.rs.
fn shade(base: vec3<f32>, n_view: vec3<f32>, p_view: vec3<f32>) -> vec3<f32> {
    if shading_deferred() {
        return base;
    }
    var l = vec3<f32>(0.0, 0.0, 1.0);
    if !is_ortho() {
        l = normalize(-p_view);
    }
    let nl = max(dot(n_view, l), 0.0);
    let spec = pow(nl, camera.light.w);
    return clamp(base * (camera.light.x + camera.light.y * nl) + vec3<f32>(camera.light.z * spec), vec3<f32>(0.0), vec3<f32>(1.0));
}

// What a ray-cast fragment found.
struct Hit {
    color: vec4<f32>,
    n_view: vec3<f32>,
    // View z of the hit minus view z of the glyph's centre, formed next to the glyph: the
    // accuracy check compares it with the reference (an absolute view z of a distant glyph is
    // not even representable in f32 to the bounds checked).
    z_rel: f32,
    // The same for the proxy point, which the flat variants leave in the depth buffer.
    z_proxy_rel: f32,
    depth: f32,
    // The ray passes the glyph (functions that cannot discard report it).
    miss: bool,
    // The glyph's id, where the hit does not come with it.
    id: u32,
}

// Colour + glyph id, depth written.
struct OutDepth {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @builtin(frag_depth) depth: f32,
}

// Colour + glyph id + (view normal, view z) for accuracy checks, depth written.
struct OutDepthAux {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @location(2) aux: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// Colour + glyph id + the view normal alone (octahedral, oct_encode), depth written: deferred
// shading's G-buffer where nothing reads the aux target back (8 bytes a pixel, not 16).
struct OutDepthNormal {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @location(2) normal: vec2<f32>,
    @builtin(frag_depth) depth: f32,
}

// The octahedral map of a unit vector onto [-1, 1]² (Cigolle et al. 2014, "A survey of
// efficient representations for independent unit vectors"), kept in f32: its error is the
// rounding of the division and the fold, not a quantisation.
fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z >= 0.0 {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - abs(e.x) - abs(e.y);
    // The lower hemisphere's fold, undone: its points moved away from the axes by -z.
    let t = max(-z, 0.0);
    let xy = e - select(vec2<f32>(-t), vec2<f32>(t), e >= vec2<f32>(0.0));
    return normalize(vec3<f32>(xy, z));
}

// Without depth correction the rasterised depth of the proxy geometry stands.
struct OutFlat {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
}

// The shadow map: glyph id and depth only (the colour target is masked).
struct OutShadow {
    @location(1) id: u32,
    @builtin(frag_depth) depth: f32,
}

struct OutShadowFlat {
    @location(1) id: u32,
}

struct OutFlatAux {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @location(2) aux: vec4<f32>,
}

struct OutFlatNormal {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @location(2) normal: vec2<f32>,
}
