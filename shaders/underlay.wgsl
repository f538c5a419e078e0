// The underlay: a greyscale image on a plane, drawn after the glyphs with the depth test, so
// the glyphs in front of it stay (src/scene/underlay.rs places it behind its plane's glyphs).
// Keep `Underlay` in sync with UnderlayUniform in src/render/gpu_data.rs.

struct Underlay {
    // Clip space from world relative to the scene origin.
    view_proj: mat4x4<f32>,
    // xyz: the image's corner at texel coordinates (0, 0), relative to the scene origin, as
    // placed for this camera.
    corner: vec4<f32>,
    // xyz: the image's edges along its columns (u) and rows (v).
    u: vec4<f32>,
    v: vec4<f32>,
    // x, y: texels along u and v.
    size: vec4<u32>,
    // x: the value drawn black, y: the value drawn white.
    window: vec4<f32>,
}

@group(0) @binding(0) var<uniform> underlay: Underlay;
@group(0) @binding(1) var values: texture_2d<f32>;

struct VsOut {
    @builtin(position) position: vec4<f32>,
    // Image coordinates in [0, 1]².
    @location(0) st: vec2<f32>,
}

@vertex
fn vs_underlay(@builtin(vertex_index) vertex: u32) -> VsOut {
    // A triangle strip over the image: (0, 0), (1, 0), (0, 1), (1, 1).
    let st = vec2<f32>(f32(vertex & 1u), f32(vertex >> 1u));
    let p = underlay.corner.xyz + st.x * underlay.u.xyz + st.y * underlay.v.xyz;
    return VsOut(underlay.view_proj * vec4<f32>(p, 1.0), st);
}

struct Out {
    @location(0) color: vec4<f32>,
    // Not a glyph: the id target says background.
    @location(1) id: u32,
}

@fragment
fn fs_underlay(in: VsOut) -> Out {
    let size = underlay.size.xy;
    let texel = min(vec2<u32>(max(in.st, vec2<f32>(0.0)) * vec2<f32>(size)), size - 1u);
    let value = textureLoad(values, texel, 0).r;
    // NaN marks texels with nothing to show (checked on the bits: NaN compares are not kept).
    if (bitcast<u32>(value) & 0x7fffffffu) > 0x7f800000u {
        discard;
    }
    let lo = underlay.window.x;
    let hi = underlay.window.y;
    var g = select(0.0, 1.0, value >= hi);
    if hi > lo {
        g = clamp((value - lo) / (hi - lo), 0.0, 1.0);
    }
    return Out(vec4<f32>(g, g, g, 1.0), 0u);
}
