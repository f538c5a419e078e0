//! A scene's ambient-occlusion volume on the GPU, owned by the scene's buffers
//! ([`crate::render::scene_buffers`]) and read by the composite pass
//! ([`crate::render::effects`]): below both, so that neither imports the other for it.

use crate::effects::ao::{AmbientOcclusion, DensityVolume};
use crate::render::context::GpuContext;
use crate::scene::Scene;

/// A scene's ambient-occlusion volume on the GPU: built when the scene is uploaded (one pass
/// over the glyphs; at most 64³ cells of 2 bytes and their mips), whether or not a frame asks
/// for occlusion, so turning `--ao` on in the viewer costs nothing.
pub(crate) struct AoVolume {
    pub(crate) volume: DensityVolume,
    /// The volume's unit: the scene's mean largest glyph radius.
    pub(crate) unit: f64,
    _texture: wgpu::Texture,
    pub(crate) view: wgpu::TextureView,
}

impl AoVolume {
    pub(crate) fn upload(ctx: &GpuContext, scene: &Scene) -> Self {
        let unit = crate::effects::ao::reach(
            scene,
            &AmbientOcclusion {
                reach: 1.0,
                ..AmbientOcclusion::default()
            },
        );
        let mut volume = DensityVolume::build(scene, unit);
        let [w, h, d] = volume.dims;
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ambient occlusion volume"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: d,
            },
            mip_level_count: volume.levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let mut dims = [w, h, d];
        for (level, values) in volume.levels.iter().enumerate() {
            let bits: Vec<u16> = values
                .iter()
                .map(|&v| half::f16::from_f32(v).to_bits())
                .collect();
            ctx.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&bits),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(2 * dims[0]),
                    rows_per_image: Some(dims[1]),
                },
                wgpu::Extent3d {
                    width: dims[0],
                    height: dims[1],
                    depth_or_array_layers: dims[2],
                },
            );
            dims = dims.map(|x| (x / 2).max(1));
        }
        // The texture holds the values; the uniform needs only the levels' count.
        volume.levels.iter_mut().for_each(Vec::clear);
        Self {
            volume,
            unit,
            view: texture.create_view(&Default::default()),
            _texture: texture,
        }
    }
}
