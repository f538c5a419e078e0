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
}

struct GpuGlyph {
    // Centre relative to the scene origin.
    centre: vec3<f32>,
    // RGBA8, unpack4x8unorm.
    color: u32,
    // Unit quaternion (x, y, z, w) of the eigenvector frame O.
    rotation: vec4<f32>,
    // Semi-axes along O's columns; T = O diag(radii) Oᵀ.
    radii: vec3<f32>,
    // Index into the CPU glyph list (picking).
    glyph: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> glyphs: array<GpuGlyph>;

fn is_ortho() -> bool {
    return camera.eye.w > 0.5;
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

// Corner k (0..3, strip order (-,-), (+,-), (-,+), (+,+)) of the near plane in world space,
// with its NDC: a proxy that covers the whole viewport, for glyphs the eye is too close to.
fn near_plane_corner(k: u32) -> vec3<f32> {
    let ndc = vec2<f32>(select(-1.0, 1.0, (k & 1u) != 0u), select(-1.0, 1.0, (k & 2u) != 0u));
    let h = camera.inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
    return h.xyz / h.w;
}

// Blinn-Phong with a headlight: the light sits at the eye, so L = H = direction to the eye.
// Mirrored in f64 by src/reference/shading.rs.
fn shade(base: vec3<f32>, n_view: vec3<f32>, p_view: vec3<f32>) -> vec3<f32> {
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

// Without depth correction the rasterised depth of the proxy geometry stands.
struct OutFlat {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
}

struct OutFlatAux {
    @location(0) color: vec4<f32>,
    @location(1) id: u32,
    @location(2) aux: vec4<f32>,
}
