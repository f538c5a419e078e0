//! A glyph's proxy frame as the prepass's compute pass writes it and Gumhold's draw reads it
//! ([`GlyphFrame`], 176 bytes), and the per-instance vertex layouts that read frames or the
//! drawn glyphs' indices ([`super::prepass`] owns the passes).

/// One glyph's proxy frame as `cs_frames` writes it and `vs_frames` reads it: the twin of
/// `GlyphFrame` in shaders/gumhold_ellipsoid.wgsl (names and offsets checked against naga's
/// layout in `render::gpu_data`'s tests). WGSL's `vec3<f32>` is 16-aligned: a scalar fills the
/// fourth lane where the shader has one, padding elsewhere.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GlyphFrame {
    pub centre: [f32; 3],
    pub u: f32,
    pub t0: [f32; 3],
    pub move_to: f32,
    pub t1: [f32; 3],
    pub id: u32,
    pub t2: [f32; 3],
    pub color: u32,
    pub m_t: [f32; 3],
    pub tz_x: f32,
    pub x_t: [f32; 3],
    pub tz_y: f32,
    pub y_t: [f32; 3],
    pub tz_z: f32,
    pub ray_t: [f32; 3],
    pub _pad0: f32,
    pub n0: [f32; 3],
    pub _pad1: f32,
    pub n1: [f32; 3],
    pub _pad2: f32,
    pub n2: [f32; 3],
    pub _pad3: f32,
}

/// Bytes of one [`GlyphFrame`].
pub const FRAME_SIZE: usize = std::mem::size_of::<GlyphFrame>();
const _: () = assert!(FRAME_SIZE == 176);

/// [`GlyphFrame`] as the per-instance vertex attributes of `vs_frames` (`FrameInput`, one
/// location each; a `vec4` location reads a `vec3` with the scalar after it).
pub const FRAME_ATTRIBUTES: [wgpu::VertexAttribute; 13] = {
    use std::mem::offset_of;
    use wgpu::VertexFormat::{Float32x3, Float32x4, Uint32};
    let fields = [
        (Float32x4, offset_of!(GlyphFrame, centre)),
        (Float32x4, offset_of!(GlyphFrame, t0)),
        (Float32x3, offset_of!(GlyphFrame, t1)),
        (Uint32, offset_of!(GlyphFrame, id)),
        (Float32x3, offset_of!(GlyphFrame, t2)),
        (Uint32, offset_of!(GlyphFrame, color)),
        (Float32x4, offset_of!(GlyphFrame, m_t)),
        (Float32x4, offset_of!(GlyphFrame, x_t)),
        (Float32x4, offset_of!(GlyphFrame, y_t)),
        (Float32x3, offset_of!(GlyphFrame, ray_t)),
        (Float32x3, offset_of!(GlyphFrame, n0)),
        (Float32x3, offset_of!(GlyphFrame, n1)),
        (Float32x3, offset_of!(GlyphFrame, n2)),
    ];
    // The vec4 reads: each vec3 with its scalar right after it.
    assert!(offset_of!(GlyphFrame, u) == offset_of!(GlyphFrame, centre) + 12);
    assert!(offset_of!(GlyphFrame, move_to) == offset_of!(GlyphFrame, t0) + 12);
    assert!(offset_of!(GlyphFrame, tz_x) == offset_of!(GlyphFrame, m_t) + 12);
    assert!(offset_of!(GlyphFrame, tz_y) == offset_of!(GlyphFrame, x_t) + 12);
    assert!(offset_of!(GlyphFrame, tz_z) == offset_of!(GlyphFrame, y_t) + 12);
    let mut out = [wgpu::VertexAttribute {
        format: Float32x4,
        offset: 0,
        shader_location: 0,
    }; 13];
    let mut i = 0;
    while i < fields.len() {
        out[i] = wgpu::VertexAttribute {
            format: fields[i].0,
            offset: fields[i].1 as u64,
            shader_location: i as u32,
        };
        i += 1;
    }
    out
};

/// The frame buffer as `vs_frames` reads it: one frame per instance.
pub fn frame_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: FRAME_SIZE as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &FRAME_ATTRIBUTES,
    }
}

/// The drawn superquadrics' instance indices (one `u32` per instance, written by their
/// `cs_frames` into the frame buffer) as `vs_frames` reads them.
pub fn glyph_list_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRIBUTES: [wgpu::VertexAttribute; 1] = [wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Uint32,
        offset: 0,
        shader_location: 0,
    }];
    wgpu::VertexBufferLayout {
        array_stride: 4,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRIBUTES,
    }
}
