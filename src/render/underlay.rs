//! The underlay on the GPU: each plane's image as an R32Float texture (values, not grey: the
//! window is a per-frame uniform, so the viewer's window controls redraw without an upload),
//! drawn after the method's passes into the same targets with the depth test. The image is
//! placed per camera by [`PlaneGeometry::placed_corner`], as the reference places it.

use std::sync::OnceLock;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::targets::{COLOR_FORMAT, ID_FORMAT, TargetViews};
use crate::request::UnderlayView;
use crate::scene::underlay::{PlaneGeometry, Underlay};

pub const SHADER: &str = include_str!("../../shaders/underlay.wgsl");

/// One plane's uniform. Keep in sync with `Underlay` in shaders/underlay.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct UnderlayUniform {
    /// Clip space from world relative to the scene origin.
    pub view_proj: [[f32; 4]; 4],
    /// The placed corner relative to the scene origin (w unused).
    pub corner: [f32; 4],
    pub u: [f32; 4],
    pub v: [f32; 4],
    /// Texels along u and v.
    pub size: [u32; 4],
    /// The values drawn black and white.
    pub window: [f32; 4],
}

pub const UNDERLAY_UNIFORM_SIZE: usize = 144;
const _: () = assert!(std::mem::size_of::<UnderlayUniform>() == UNDERLAY_UNIFORM_SIZE);

fn vec4(v: DVec3) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, 0.0]
}

/// The underlay's layout and pipeline (built on first use), long-lived in the renderer.
pub struct UnderlayPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: OnceLock<wgpu::RenderPipeline>,
}

impl UnderlayPipeline {
    pub fn new(ctx: &GpuContext) -> Self {
        let layout = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("underlay"),
                entries: &[
                    wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            sample_type: wgpu::TextureSampleType::Float { filterable: false },
                            view_dimension: wgpu::TextureViewDimension::D2,
                            multisampled: false,
                        },
                        count: None,
                    },
                ],
            });
        Self {
            layout,
            pipeline: OnceLock::new(),
        }
    }

    fn pipeline(&self, ctx: &GpuContext) -> &wgpu::RenderPipeline {
        self.pipeline.get_or_init(|| {
            let device = &ctx.device;
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("underlay.wgsl"),
                source: wgpu::ShaderSource::Wgsl(SHADER.into()),
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("underlay"),
                bind_group_layouts: &[Some(&self.layout)],
                immediate_size: 0,
            });
            ctx.pipelines.render(&wgpu::RenderPipelineDescriptor {
                label: Some("underlay"),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_underlay"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleStrip,
                    ..Default::default()
                },
                depth_stencil: Some(crate::render::pipeline::depth_test()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_underlay"),
                    compilation_options: Default::default(),
                    targets: &[Some(COLOR_FORMAT.into()), Some(ID_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// Record the underlay's pass over what the method drew.
    pub fn record(
        &self,
        ctx: &GpuContext,
        buffers: &UnderlayBuffers,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let pipeline = self.pipeline(ctx);
        let mut pass = views.begin_overlay_pass(encoder);
        pass.set_pipeline(pipeline);
        for p in &buffers.planes {
            pass.set_bind_group(0, &p.bind_group, &[]);
            pass.draw(0..4, 0..1);
        }
    }
}

/// A scene's underlay on the GPU.
pub struct UnderlayBuffers {
    planes: Vec<PlaneBuffers>,
    /// The scene's default window.
    window: [f32; 2],
}

struct PlaneBuffers {
    geometry: PlaneGeometry,
    size: [u32; 2],
    uniform: wgpu::Buffer,
    _texture: wgpu::Texture,
    bind_group: wgpu::BindGroup,
}

impl UnderlayBuffers {
    pub fn upload(
        ctx: &GpuContext,
        pipeline: &UnderlayPipeline,
        underlay: &Underlay,
    ) -> Result<Self, RenderError> {
        let device = &ctx.device;
        let max = ctx.limits.max_texture_dimension_2d;
        let mut planes = Vec::with_capacity(underlay.planes.len());
        for p in &underlay.planes {
            let [w, h] = p.size;
            if w == 0 || h == 0 || w > max || h > max {
                return Err(RenderError::Unsupported(format!(
                    "an underlay image of {w}x{h} texels: this adapter takes at most {max} a side"
                )));
            }
            let size = wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            };
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("underlay"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            ctx.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&p.values),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * w),
                    rows_per_image: Some(h),
                },
                size,
            );
            let uniform = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("underlay"),
                size: UNDERLAY_UNIFORM_SIZE as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let view = texture.create_view(&Default::default());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("underlay"),
                layout: &pipeline.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: uniform.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                ],
            });
            planes.push(PlaneBuffers {
                geometry: p.geometry,
                size: p.size,
                uniform,
                _texture: texture,
                bind_group,
            });
        }
        Ok(Self {
            planes,
            window: underlay.window,
        })
    }

    /// Place every image for `camera` and write the window in effect.
    pub fn write_uniforms(
        &self,
        queue: &wgpu::Queue,
        camera: &Camera,
        origin: DVec3,
        view: &UnderlayView,
    ) {
        let view_proj = (camera.projection_matrix() * camera.view(origin))
            .as_mat4()
            .to_cols_array_2d();
        let [lo, hi] = view.window.unwrap_or(self.window);
        for p in &self.planes {
            let g = &p.geometry;
            let u = UnderlayUniform {
                view_proj,
                corner: vec4(g.placed_corner(camera) - origin),
                u: vec4(g.u),
                v: vec4(g.v),
                size: [p.size[0], p.size[1], 0, 0],
                window: [lo, hi, 0.0, 0.0],
            };
            queue.write_buffer(&p.uniform, 0, bytemuck::bytes_of(&u));
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_shader_validates() {
        if let Err(e) = crate::render::shaders::validate(super::SHADER) {
            panic!("underlay.wgsl does not validate:\n{e}");
        }
    }
}
