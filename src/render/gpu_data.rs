//! Structs shared with the shaders. Each is `#[repr(C)]` + Pod and has a WGSL twin in
//! `shaders/common.wgsl`; `tests::sizes_match_wgsl` checks their sizes against naga's layout.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};

use crate::camera::Camera;

/// One glyph instance: minimal per-glyph data, everything else is derived in the vertex shader.
/// Keep in sync with `GpuGlyph` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuGlyph {
    /// Centre relative to the scene origin.
    pub centre: [f32; 3],
    /// RGBA8 (R in the lowest byte), as `unpack4x8unorm` reads it.
    pub color: u32,
    /// Unit quaternion (x, y, z, w) of the eigenvector frame.
    pub rotation: [f32; 4],
    /// Semi-axes along the frame's columns.
    pub radii: [f32; 3],
    /// Index into the CPU glyph list.
    pub glyph: u32,
}

pub const GPU_GLYPH_SIZE: usize = 48;
const _: () = assert!(std::mem::size_of::<GpuGlyph>() == GPU_GLYPH_SIZE);

impl GpuGlyph {
    pub fn pack_color(rgba: [u8; 4]) -> u32 {
        u32::from_le_bytes(rgba)
    }

    pub fn color_rgba(&self) -> [u8; 4] {
        self.color.to_le_bytes()
    }
}

/// Blinn-Phong headlight parameters: one set for every method and the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.3,
            shininess: 24.0,
        }
    }
}

/// Per-frame camera and lighting. Keep in sync with `Camera` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct CameraUniform {
    pub view_proj: [[f32; 4]; 4],
    pub view: [[f32; 4]; 4],
    /// Inverse of view_proj (formed in f64).
    pub inv_view_proj: [[f32; 4]; 4],
    /// xyz: eye relative to the scene origin; w: 1 orthographic, 0 perspective.
    pub eye: [f32; 4],
    /// xyz: unit view direction.
    pub forward: [f32; 4],
    /// B = P[2][3], P[2][2], near, far.
    pub depth: [f32; 4],
    /// width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
    /// ambient, diffuse, specular, shininess.
    pub light: [f32; 4],
}

pub const CAMERA_UNIFORM_SIZE: usize = 272;
const _: () = assert!(std::mem::size_of::<CameraUniform>() == CAMERA_UNIFORM_SIZE);

impl CameraUniform {
    /// Matrices are formed in f64 relative to `origin` and only then rounded to f32.
    pub fn new(camera: &Camera, origin: DVec3, lighting: &Lighting) -> Self {
        let view = camera.view(origin);
        let proj = camera.projection_matrix();
        let eye = camera.eye - origin;
        let f = camera.forward();
        let m = |m: DMat4| m.as_mat4().to_cols_array_2d();
        Self {
            view_proj: m(proj * view),
            inv_view_proj: m((proj * view).inverse()),
            view: m(view),
            eye: [
                eye.x as f32,
                eye.y as f32,
                eye.z as f32,
                if camera.is_ortho() { 1.0 } else { 0.0 },
            ],
            forward: [f.x as f32, f.y as f32, f.z as f32, 0.0],
            depth: [
                proj.w_axis.z as f32,
                proj.z_axis.z as f32,
                camera.near as f32,
                camera.far as f32,
            ],
            viewport: [
                camera.width as f32,
                camera.height as f32,
                1.0 / camera.width as f32,
                1.0 / camera.height as f32,
            ],
            light: [
                lighting.ambient,
                lighting.diffuse,
                lighting.specular,
                lighting.shininess,
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders;

    /// The WGSL struct named `name` in `module`, and its size per naga's layout rules.
    fn wgsl_size(module: &wgpu::naga::Module, name: &str) -> u32 {
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name} not in WGSL"));
        match &ty.inner {
            wgpu::naga::TypeInner::Struct { span, .. } => *span,
            other => panic!("{name} is not a struct: {other:?}"),
        }
    }

    #[test]
    fn sizes_match_wgsl() {
        let module = shaders::parse(shaders::COMMON).expect("common.wgsl parses");
        assert_eq!(wgsl_size(&module, "GpuGlyph") as usize, GPU_GLYPH_SIZE);
        assert_eq!(wgsl_size(&module, "Camera") as usize, CAMERA_UNIFORM_SIZE);
    }
}
