//! Structs shared with the shaders. Each is `#[repr(C)]` + Pod and has a WGSL twin in
//! `shaders/common.wgsl`; `tests::sizes_match_wgsl` checks their sizes against naga's layout.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};

use crate::camera::Camera;
use crate::frame::Lighting;
use crate::scene::GlyphInstance;
use crate::shape::geometry::{pack_radius, pack_rotation, unpack_radius, unpack_rotation};

/// One glyph as the GPU reads it: 32 bytes, decoded by `load_glyph` in shaders/common.wgsl.
/// Keep in sync with `GpuGlyph` there.
///
/// - `centre`: f32, relative to the scene origin (as [`GlyphInstance`]).
/// - `radius_rgb[i]`: radius i as an unsigned 24-bit float (f32 without sign and the 7 lowest
///   mantissa bits, rounded to nearest: relative error ≤ 2⁻¹⁷) in bits 8..32, and colour channel
///   i (R, G, B) in bits 0..8. Glyphs no method draws (degenerate radii) get radii 0.
/// - `rotation`: the unit quaternion as "smallest three" ([`pack_rotation`]).
///
/// Scenes hold their instances as stored ([`GlyphInstance::stored`]), so packing them again
/// changes nothing and the reference casts the glyph the GPU reads.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuGlyph {
    pub centre: [f32; 3],
    pub radius_rgb: [u32; 3],
    pub rotation: [u32; 2],
}

pub const GPU_GLYPH_SIZE: usize = 32;
const _: () = assert!(std::mem::size_of::<GpuGlyph>() == GPU_GLYPH_SIZE);

impl GpuGlyph {
    pub fn pack(g: &GlyphInstance) -> Self {
        let radii = if crate::shape::rules::drawable_radii(g.radii) {
            g.radii
        } else {
            [0.0; 3]
        };
        let rgba = g.color.to_le_bytes();
        let radius_rgb = std::array::from_fn(|i| (pack_radius(radii[i]) << 8) | u32::from(rgba[i]));
        Self {
            centre: g.centre,
            radius_rgb,
            rotation: pack_rotation(g.rotation),
        }
    }

    /// The CPU twin of `load_glyph` in common.wgsl.
    pub fn unpack(&self) -> GlyphInstance {
        let radii = self.radius_rgb.map(|w| unpack_radius(w >> 8));
        let [r, g, b] = self.radius_rgb.map(|w| (w & 0xff) as u8);
        GlyphInstance {
            centre: self.centre,
            color: u32::from_le_bytes([r, g, b, 255]),
            rotation: unpack_rotation(self.rotation),
            radii,
            glyph: 0,
            // A separate buffer holds superquadric exponents (`GpuShape`).
            shape: [0; 2],
        }
    }
}

/// Per draw of one chunk of instances. Keep in sync with `Chunk` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ChunkParams {
    /// instance_index of the chunk's first glyph.
    pub base: u32,
    /// Glyphs projected smaller than this many pixels (radius) are not drawn (0: all are).
    pub min_pixel_radius: f32,
    /// 1: frustum culling in the vertex stage.
    pub cull: u32,
    pub _pad: u32,
}

pub const CHUNK_PARAMS_SIZE: usize = 16;
const _: () = assert!(std::mem::size_of::<ChunkParams>() == CHUNK_PARAMS_SIZE);

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
    /// B = `P[2][3]`, `P[2][2]`, near, far.
    pub depth: [f32; 4],
    /// width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
    /// ambient, diffuse, specular, shininess.
    pub light: [f32; 4],
    /// Clip planes (inward unit normal, offset), relative to the scene origin, for culling.
    pub frustum: [[f32; 4]; 6],
    /// x: pixels per world unit at view distance 1 (orthographic: at any distance); y, z: the
    /// whole image's centre in this viewport's pixels (off-centre for a tile); w: 1 when
    /// shading is deferred (the methods write the unlit base colour).
    pub pixels: [f32; 4],
    /// Rows 0..3 of the view matrix (columns 0..4: rotation and translation) less their f32
    /// rounding: with `view`, the view transform in double-f32 (`centre_ray` in common.wgsl).
    pub view_lo: [[f32; 4]; 3],
    /// `pixels.x` and its reciprocal, each in double-f32 (hi, lo, hi, lo).
    pub pixel_scale: [f32; 4],
}

pub const CAMERA_UNIFORM_SIZE: usize = 448;
const _: () = assert!(std::mem::size_of::<CameraUniform>() == CAMERA_UNIFORM_SIZE);

impl CameraUniform {
    /// Matrices are formed in f64 relative to `origin` and only then rounded to f32.
    pub fn new(camera: &Camera, origin: DVec3, lighting: &Lighting) -> Self {
        let view = camera.view(origin);
        let proj = camera.projection_matrix();
        let eye = camera.eye - origin;
        let f = camera.forward();
        let m = |m: DMat4| m.as_mat4().to_cols_array_2d();
        // What f32 leaves of x: x = hi + lo with hi = x as f32.
        let lo = |x: f64| (x - f64::from(x as f32)) as f32;
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
            frustum: camera
                .frustum_planes(origin)
                .map(|p| p.as_vec4().to_array()),
            pixels: {
                let (cx, cy) = camera.image_centre_px();
                [camera.pixels_per_unit() as f32, cx as f32, cy as f32, 0.0]
            },
            view_lo: std::array::from_fn(|i| std::array::from_fn(|j| lo(view.col(j)[i]))),
            pixel_scale: {
                let f = camera.pixels_per_unit();
                [f as f32, lo(f), (1.0 / f) as f32, lo(1.0 / f)]
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders;

    /// The WGSL struct named `name` in `module`: its members (name, byte offset) and its size,
    /// per naga's layout rules.
    fn wgsl_struct(module: &wgpu::naga::Module, name: &str) -> (Vec<(String, u32)>, u32) {
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name} not in WGSL"));
        match &ty.inner {
            wgpu::naga::TypeInner::Struct { members, span } => (
                members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                    .collect(),
                *span,
            ),
            other => panic!("{name} is not a struct: {other:?}"),
        }
    }

    fn wgsl_size(module: &wgpu::naga::Module, name: &str) -> u32 {
        wgsl_struct(module, name).1
    }

    fn instance(rotation: [f32; 4], radii: [f32; 3]) -> GlyphInstance {
        GlyphInstance {
            centre: [1.5, -2.25, 1e6],
            color: u32::from_le_bytes([10, 200, 37, 255]),
            rotation,
            radii,
            glyph: 7,
            shape: [0; 2],
        }
    }

    #[test]
    fn packing_keeps_centre_colour_and_bounds_the_error() {
        use glam::DQuat;
        let mut worst_q = 0.0f64;
        let mut worst_r = 0.0f64;
        // Rotations over all four "largest component" cases and both signs, and radii over
        // many magnitudes.
        for k in 0..2000 {
            let t = f64::from(k);
            let axis = glam::DVec3::new((t * 0.37).sin(), (t * 1.3).cos(), (t * 0.11).sin() + 0.2)
                .normalize();
            let q = DQuat::from_axis_angle(axis, t * 0.0137);
            let q = if k % 2 == 0 { q } else { -q };
            let r = [
                (10f64.powf((t * 0.01).sin() * 3.0)) as f32,
                0.5 + (t * 0.3).cos() as f32 * 0.25,
                1.0e-3 * (1.0 + (k % 7) as f32),
            ];
            let g = instance([q.x as f32, q.y as f32, q.z as f32, q.w as f32], r);
            let u = GpuGlyph::pack(&g).unpack();
            assert_eq!(u.centre, g.centre);
            assert_eq!(u.color_rgba(), g.color_rgba());
            let back = DQuat::from_xyzw(
                u.rotation[0].into(),
                u.rotation[1].into(),
                u.rotation[2].into(),
                u.rotation[3].into(),
            );
            // q and −q are one rotation. The decoded quaternion's length is 1 only to f32
            // rounding (the shader uses it unnormalised, as the CPU twin does): compare the
            // rotation angle between them, and the length apart.
            let angle = 2.0 * (back.dot(q).abs() / back.length()).min(1.0).acos();
            worst_q = worst_q.max(angle);
            assert!((back.length() - 1.0).abs() < 4e-7, "{back:?}");
            for (a, b) in u.radii.iter().zip(r) {
                worst_r = worst_r.max((f64::from(*a) / f64::from(b) - 1.0).abs());
            }
        }
        // 20-bit components (steps of 1.3e-6): rotations agree to a few microradians (the f32
        // input and decode add ~1e-7).
        assert!(worst_q < 6e-6, "quaternion angle error {worst_q} rad");
        assert!(worst_r <= 2f64.powi(-17), "radius error {worst_r}");
    }

    #[test]
    fn glyphs_no_method_draws_are_packed_with_zero_radii() {
        use crate::shape::rules::drawable_radii;
        for radii in [
            [1.0, 0.0, 1.0],
            [1.0, -0.5, 1.0],
            [f32::NAN, 1.0, 1.0],
            [f32::INFINITY, 1.0, 1.0],
            [1.0, 1e-9, 1.0],
        ] {
            let u = GpuGlyph::pack(&instance([0.0, 0.0, 0.0, 1.0], radii)).unpack();
            assert_eq!(u.radii, [0.0; 3], "{radii:?}");
            assert!(!drawable_radii(u.radii));
        }
    }

    /// Every member of the WGSL struct at the offset its Rust twin gives it (`rust` lists the
    /// WGSL member names with the Rust offsets; padding the WGSL leaves implicit is not listed).
    fn assert_offsets(module: &wgpu::naga::Module, name: &str, rust: &[(&str, usize)]) {
        let (wgsl, _) = wgsl_struct(module, name);
        let names: Vec<&str> = wgsl.iter().map(|(n, _)| n.as_str()).collect();
        let listed: Vec<&str> = rust.iter().map(|(n, _)| *n).collect();
        assert_eq!(names, listed, "{name}: members");
        for ((member, w), (_, r)) in wgsl.iter().zip(rust) {
            assert_eq!(*w as usize, *r, "{name}.{member}: offset");
        }
    }

    #[test]
    fn offsets_match_wgsl() {
        use crate::render::gumhold::prepass::GlyphFrame;
        use std::mem::offset_of;
        let module = shaders::parse(shaders::COMMON).expect("common.wgsl parses");
        let g = offset_of!(GpuGlyph, radius_rgb);
        let q = offset_of!(GpuGlyph, rotation);
        assert_offsets(
            &module,
            "GpuGlyph",
            &[
                ("centre", offset_of!(GpuGlyph, centre)),
                ("radius_rgb0", g),
                ("radius_rgb1", g + 4),
                ("radius_rgb2", g + 8),
                ("rotation0", q),
                ("rotation1", q + 4),
            ],
        );
        macro_rules! fields {
            ($ty:ty: $($f:ident),+) => { [$((stringify!($f), offset_of!($ty, $f))),+] };
        }
        assert_offsets(
            &module,
            "Camera",
            &fields!(CameraUniform: view_proj, view, inv_view_proj, eye, forward, depth,
                viewport, light, frustum, pixels, view_lo, pixel_scale),
        );
        assert_offsets(
            &module,
            "Chunk",
            &fields!(ChunkParams: base, min_pixel_radius, cull, _pad),
        );
        let underlay =
            shaders::parse(crate::render::underlay::SHADER).expect("underlay.wgsl parses");
        {
            use crate::render::underlay::UnderlayUniform;
            assert_offsets(
                &underlay,
                "Underlay",
                &fields!(UnderlayUniform: view_proj, corner, u, v, size, window),
            );
        }
        let gumhold = shaders::parse(
            &shaders::ShaderSource::new(
                shaders::MethodShader::Gumhold,
                crate::shape::GlyphKind::Ellipsoid,
            )
            .text(),
        )
        .expect("gumhold_ellipsoid.wgsl parses");
        assert_offsets(
            &gumhold,
            "GlyphFrame",
            &fields!(GlyphFrame: centre, u, t0, move_to, t1, id, t2, color, m_t, tz_x, x_t,
                tz_y, y_t, tz_z, ray_t, n0, n1, n2),
        );
    }

    #[test]
    fn sizes_match_wgsl() {
        let module = shaders::parse(shaders::COMMON).expect("common.wgsl parses");
        assert_eq!(wgsl_size(&module, "GpuGlyph") as usize, GPU_GLYPH_SIZE);
        assert_eq!(wgsl_size(&module, "Camera") as usize, CAMERA_UNIFORM_SIZE);
        assert_eq!(wgsl_size(&module, "Chunk") as usize, CHUNK_PARAMS_SIZE);
        let underlay =
            shaders::parse(crate::render::underlay::SHADER).expect("underlay.wgsl parses");
        assert_eq!(
            wgsl_size(&underlay, "Underlay") as usize,
            crate::render::underlay::UNDERLAY_UNIFORM_SIZE
        );
        let gumhold = shaders::parse(
            &shaders::ShaderSource::new(
                shaders::MethodShader::Gumhold,
                crate::shape::GlyphKind::Ellipsoid,
            )
            .text(),
        )
        .expect("gumhold_ellipsoid.wgsl parses");
        assert_eq!(
            wgsl_size(&gumhold, "GlyphFrame") as usize,
            crate::render::gumhold::prepass::FRAME_SIZE
        );
        assert_eq!(
            u64::from(wgsl_size(&gumhold, "SplatInfo")),
            crate::render::gumhold::prepass::SPLAT_INFO_SIZE
        );
        let tile = gumhold
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some("SPLAT_TILE"))
            .map(|(_, c)| &gumhold.global_expressions[c.init]);
        assert!(
            matches!(
                tile,
                Some(wgpu::naga::Expression::Literal(wgpu::naga::Literal::U32(t)))
                    if *t == crate::render::gumhold::prepass::SPLAT_TILE
            ),
            "{tile:?}"
        );
    }
}
