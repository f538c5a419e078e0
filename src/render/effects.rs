//! Figure effects on the GPU (Sigg et al. 2006, §4): the glyph methods write the geometry buffer
//! (unlit base colour, id, view normal in the aux target, exact ray-cast depth: 20 bytes a
//! pixel with the octahedral normal of [`AuxTarget::Normal`] where nothing reads the aux target
//! back, 28 with the accuracy check's), and after them
//! and the underlay
//! 1. with shadows, the method draws the scene again from the key light into a shadow map, with
//!    the same ray casting in its depth-only variant ([`crate::render::pipeline::Variant`]'s
//!    `shadow`), so the map holds the glyphs' ray-cast depth and ids and not their proxies';
//! 2. the colour target is copied out as the base colour;
//! 3. one full-screen pass (`shaders/composite.wgsl`) shades every covered pixel once, with the
//!    outline filter and percentage-closer filtered shadows, and writes each pixel's lit
//!    fraction and outline state to a small target the accuracy check reads back. In a
//!    penumbra it casts the exact shadow ray against the glyphs the map names there, with the
//!    scene's own shape code: the pass is composed per glyph kind and binds the glyph group.
//!
//! The per-size textures are kept between frames (the viewer draws many at one size).

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use bytemuck::{Pod, Zeroable};

use crate::camera::{Camera, Projection};
use crate::effects::ao::DensityVolume;
use crate::effects::{Effects, KEY_SHARE, light, outline};
use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::drawer::{Drawer, FrameRecording};
use crate::render::pipeline::glyphs_and;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::{COMMON, SCREEN_BOX};
use crate::render::targets::{COLOR_FORMAT, DEPTH_FORMAT, TargetViews, Targets};
use crate::request::{AuxTarget, FrameRequest, GlyphKind, UnderlayView};

pub const SHADER: &str = include_str!("../../shaders/effects/composite.wgsl");

/// The composite pass for glyphs of `kind`: common.wgsl, the screen box and the kind's shape
/// files, then composite.wgsl. WGSL has no exceptions, so the shape code's `discard`s (a
/// glyph method's miss ends the fragment) become `shadow_missed = true` here: a miss ends one
/// shadow ray, not the pixel, and the ray is cast by the very code that draws the glyph.
pub fn composite_source(kind: GlyphKind) -> String {
    let mut shape = vec![COMMON, SCREEN_BOX];
    shape.extend(kind.shape().wgsl());
    let shape = shape
        .join("\n")
        .replace("discard;", "shadow_missed = true;");
    format!("{shape}\n{SHADER}")
}

/// Why shadows are refused over a scene of two kinds (peaks over ODFs).
pub const SHADOWS_OF_ONE_KIND: &str =
    "--shadows are drawn over glyphs of one kind: not with --peaks over ODFs";

/// Each pixel's lit fraction (r) and outline state (g).
pub const EFFECTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The full-screen pass's uniform. Keep in sync with `Effects` in shaders/composite.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct EffectsUniform {
    pub inv_proj: [[f32; 4]; 4],
    pub view_to_light: [[f32; 4]; 4],
    pub key: [f32; 4],
    pub lighting: [f32; 4],
    pub outline: [f32; 4],
    pub edges: [f32; 4],
    pub viewport: [f32; 4],
    pub params: [u32; 4],
    pub view_to_world: [[f32; 4]; 4],
    pub key_world: [f32; 4],
    pub ao: [f32; 4],
    pub volume_lo: [f32; 4],
    pub volume_scale: [f32; 4],
}

pub const EFFECTS_UNIFORM_SIZE: usize = 352;
const _: () = assert!(std::mem::size_of::<EffectsUniform>() == EFFECTS_UNIFORM_SIZE);

const FLAG_ORTHO: u32 = 1;
const FLAG_ADAPTIVE: u32 = 2;
const FLAG_OUTLINES: u32 = 4;
const FLAG_SHADOWS: u32 = 8;
const FLAG_EXACT: u32 = 16;
const FLAG_AO: u32 = 32;

/// Shadow lookups compare one texel's depth nearer (more where the surface slopes away from the
/// light, see composite.wgsl), for glyphs that touch. A glyph's own texels never shadow it (the
/// map keeps ids), so no offset along the normal is needed: measured on grid40, an offset of 1.5
/// texels moved shadow edges enough to triple the mismatch against the exact shadows.
const DEPTH_BIAS_TEXELS: f64 = 1.0;

impl EffectsUniform {
    /// The uniform of a frame of `camera` (and the key light's `light` camera, with shadows;
    /// `exact`: the pass binds every glyph, so penumbrae are re-tested by exact shadow rays;
    /// `volume`: the scene's ambient-occlusion volume, its mip levels and its unit, the mean
    /// largest radius).
    pub fn new(
        camera: &Camera,
        light: Option<&Camera>,
        origin: glam::DVec3,
        req: &FrameRequest,
        exact: bool,
        volume: (&DensityVolume, f64),
    ) -> Self {
        let fx = &req.effects;
        let m = |m: glam::DMat4| m.as_mat4().to_cols_array_2d();
        let mut flags = 0;
        if camera.is_ortho() {
            flags |= FLAG_ORTHO;
        }
        let mut key = [0.0; 4];
        let mut edges = [
            outline::NORMAL_EDGE as f32,
            outline::DEPTH_EDGE as f32,
            0.0,
            0.0,
        ];
        let mut params = [0, 1, 0, 0];
        let mut view_to_light = [[0.0; 4]; 4];
        let mut key_world = [0.0; 4];
        if let (Some(s), Some(light)) = (&fx.shadows, light) {
            flags |= FLAG_SHADOWS;
            if exact {
                flags |= FLAG_EXACT;
            }
            let w = light::world_direction(camera, s);
            key_world = [w.x as f32, w.y as f32, w.z as f32, 0.0];
            if s.adaptive {
                flags |= FLAG_ADAPTIVE;
            }
            let l = light::view_direction(s.light).unwrap_or(glam::DVec3::Z);
            key = [l.x as f32, l.y as f32, l.z as f32, KEY_SHARE as f32];
            let extent = match light.projection {
                Projection::Orthographic { height } => height,
                Projection::Perspective { .. } => 0.0,
            };
            let texel = extent / f64::from(light.height.max(1));
            edges[3] = (DEPTH_BIAS_TEXELS * texel / (light.far - light.near).max(1e-30)) as f32;
            params[1] = light.width;
            params[2] = s.pcf_radius;
            view_to_light = m(light::view_to_light_clip(camera, light, origin));
        }
        let mut outline = [0.0; 4];
        if let Some(o) = &fx.outlines {
            flags |= FLAG_OUTLINES;
            outline = [
                o.color[0],
                o.color[1],
                o.color[2],
                o.strength.clamp(0.0, 1.0),
            ];
            params[0] = o.width.max(1);
        }
        let (v, unit) = volume;
        let mut ao = [0.0; 4];
        if let Some(a) = &fx.ao {
            flags |= FLAG_AO;
            let reach = f64::from(a.reach) * unit;
            ao = [
                a.strength.clamp(0.0, 1.0),
                reach as f32,
                a.reach,
                (v.levels.len().max(1) - 1) as f32,
            ];
        }
        let size = v.cell * glam::UVec3::from_array(v.dims).as_dvec3();
        let scale = size.recip();
        params[3] = flags;
        let l = &req.lighting;
        Self {
            inv_proj: m(camera.projection_matrix().inverse()),
            view_to_light,
            key,
            lighting: [l.ambient, l.diffuse, l.specular, l.shininess],
            outline,
            edges,
            viewport: [
                camera.width as f32,
                camera.height as f32,
                1.0 / camera.width as f32,
                1.0 / camera.height as f32,
            ],
            params,
            view_to_world: m(camera.view(origin).inverse()),
            key_world,
            ao,
            volume_lo: [
                v.lo.x as f32,
                v.lo.y as f32,
                v.lo.z as f32,
                v.cell.min_element() as f32,
            ],
            volume_scale: [scale.x as f32, scale.y as f32, scale.z as f32, 0.0],
        }
    }
}

/// The textures of one image size and shadow map size, kept between frames.
pub(crate) struct EffectsTextures {
    size: (u32, u32),
    map_size: Option<u32>,
    albedo: wgpu::Texture,
    albedo_view: wgpu::TextureView,
    /// Each pixel's lit fraction and outline state.
    pub(crate) out: wgpu::Texture,
    out_view: wgpu::TextureView,
    shadow: Option<(Targets, TargetViews)>,
    uniform: wgpu::Buffer,
}

/// The composite pipelines (one per glyph kind, built on first use) and the textures of the
/// last size drawn; long-lived in the renderer.
pub struct EffectsPipeline {
    layout: wgpu::BindGroupLayout,
    glyph_group: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// Keyed by the kind and the effects built in (outlines, shadows, ambient occlusion).
    pipelines: Mutex<HashMap<(GlyphKind, [bool; 4]), wgpu::RenderPipeline>>,
    textures: Mutex<Option<Arc<EffectsTextures>>>,
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

impl EffectsPipeline {
    /// `glyph_group`: the glyph methods' group 0, which the pass binds for its shadow rays.
    pub fn new(ctx: &GpuContext, glyph_group: &wgpu::BindGroupLayout) -> Self {
        use wgpu::TextureSampleType as T;
        let layout = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("composite"),
                entries: &[
                    crate::render::pipeline::buffer_entry(
                        0,
                        wgpu::ShaderStages::FRAGMENT,
                        wgpu::BufferBindingType::Uniform,
                    ),
                    texture_entry(1, T::Float { filterable: false }),
                    texture_entry(2, T::Uint),
                    texture_entry(3, T::Float { filterable: false }),
                    texture_entry(4, T::Depth),
                    texture_entry(5, T::Depth),
                    texture_entry(6, T::Uint),
                    wgpu::BindGroupLayoutEntry {
                        binding: 7,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            sample_type: T::Float { filterable: true },
                            view_dimension: wgpu::TextureViewDimension::D3,
                            multisampled: false,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 8,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                        count: None,
                    },
                ],
            });
        let sampler = ctx.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("ambient occlusion volume"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Self {
            layout,
            glyph_group: glyph_group.clone(),
            sampler,
            pipelines: Mutex::new(HashMap::new()),
            textures: Mutex::new(None),
        }
    }

    /// The pass for `kind`'s glyphs, the effects `fx` and the aux target `aux` (whose normals
    /// are octahedral when it holds nothing else).
    fn pipeline(
        &self,
        ctx: &GpuContext,
        kind: GlyphKind,
        fx: &Effects,
        aux: AuxTarget,
    ) -> wgpu::RenderPipeline {
        let built = [
            fx.outlines.is_some(),
            fx.shadows.is_some(),
            fx.ao.is_some(),
            aux == AuxTarget::Normal,
        ];
        let constants: Vec<(&str, f64)> = ["OUTLINES", "SHADOWS", "AO", "OCTAHEDRAL_NORMALS"]
            .into_iter()
            .zip(built)
            .map(|(name, on)| (name, f64::from(u8::from(on))))
            .collect();
        let mut map = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        map.entry((kind, built))
            .or_insert_with(|| {
                let device = &ctx.device;
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("composite.wgsl"),
                    source: wgpu::ShaderSource::Wgsl(composite_source(kind).into()),
                });
                let layout = glyphs_and(device, "composite", &self.glyph_group, &self.layout);
                ctx.pipelines.render(&wgpu::RenderPipelineDescriptor {
                    label: Some("composite"),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_full"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    primitive: Default::default(),
                    // The full-screen triangle lies on the far plane, tested against the
                    // glyphs' depth, read only: pixels no glyph or slice covered fail the test
                    // before the shader runs. On a CPU rasteriser a shader that discards still
                    // costs its whole body per pixel: this pass took 12 ms at 1024x768 with
                    // nothing drawn.
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(false),
                        depth_compare: Some(wgpu::CompareFunction::Greater),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_composite"),
                        compilation_options: wgpu::PipelineCompilationOptions {
                            constants: &constants,
                            ..Default::default()
                        },
                        targets: &[Some(COLOR_FORMAT.into()), Some(EFFECTS_FORMAT.into())],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            })
            .clone()
    }

    /// The textures for `size` and `map_size`, made anew when either changed.
    fn textures(
        &self,
        ctx: &GpuContext,
        size: (u32, u32),
        map_size: Option<u32>,
    ) -> Result<Arc<EffectsTextures>, RenderError> {
        let mut slot = self.textures.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = slot
            .as_ref()
            .filter(|t| t.size == size && t.map_size == map_size)
        {
            return Ok(Arc::clone(t));
        }
        let make = |label, usage| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: COLOR_FORMAT,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as U;
        let albedo = make("base colour", U::COPY_DST | U::TEXTURE_BINDING);
        let out = make("effects", U::RENDER_ATTACHMENT | U::COPY_SRC);
        let shadow = match map_size {
            Some(s) => {
                let t = Targets::new(ctx, s, s, AuxTarget::None)?;
                let v = TargetViews::new(&t);
                Some((t, v))
            }
            None => None,
        };
        let uniform = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("effects"),
            size: EFFECTS_UNIFORM_SIZE as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let t = Arc::new(EffectsTextures {
            size,
            map_size,
            albedo_view: albedo.create_view(&Default::default()),
            albedo,
            out_view: out.create_view(&Default::default()),
            out,
            shadow,
            uniform,
        });
        *slot = Some(Arc::clone(&t));
        Ok(t)
    }

    /// Record the shadow map (if asked), the copy of the base colours and the full-screen pass
    /// over what the method and the underlay drew into `views`. Returns the textures, whose
    /// `out` holds the per-pixel effects once the work is done.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        ctx: &GpuContext,
        buffers: &SceneBuffers,
        drawer: &dyn Drawer,
        camera: &Camera,
        req: &FrameRequest,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Arc<EffectsTextures>, RenderError> {
        let Some(aux) = views.aux.as_ref() else {
            return Err(RenderError::Gpu(
                "deferred shading needs the aux target for its normals".into(),
            ));
        };
        let fx: &Effects = &req.effects;
        // The composite pass re-tests penumbrae against the glyph the shadow map names with its
        // kind's own intersection, compiled in: one kind a pass.
        if fx.shadows.is_some() && buffers.kinds.len() > 1 {
            return Err(RenderError::Unsupported(SHADOWS_OF_ONE_KIND.into()));
        }
        let light = fx.shadows.as_ref().map(|s| {
            let (centre, half) = buffers.bounds();
            light::shadow_camera(camera, centre, half, s, buffers.ao_volume.unit)
        });
        let textures = self.textures(ctx, views.size, light.map(|l| l.width))?;
        if let (Some(light), Some((_, shadow_views))) = (&light, &textures.shadow) {
            // The method's own passes (Gumhold's prepass and splats too) from the light, with
            // its colours unused and no early depth test (vetted for the eye's camera only).
            let mut light_req = ctx.within_limits(
                &FrameRequest {
                    aux: false,
                    effects: Effects::default(),
                    underlay: UnderlayView {
                        shown: false,
                        ..req.underlay
                    },
                    ..*req
                },
                light,
            );
            light_req.method.set_early_depth(false);
            buffers.write_light_uniform(&ctx.queue, light, &light_req);
            drawer.record(
                &FrameRecording {
                    light: true,
                    ..FrameRecording::new(ctx, light, buffers, &light_req, shadow_views)
                },
                encoder,
            );
        }
        // One chunk holds every glyph the map can name; a scene split into chunks keeps the
        // filter's answer.
        let exact = buffers.chunks.len() == 1;
        let uniform = EffectsUniform::new(
            camera,
            light.as_ref(),
            buffers.origin(),
            req,
            exact,
            (&buffers.ao_volume.volume, buffers.ao_volume.unit),
        );
        ctx.queue
            .write_buffer(&textures.uniform, 0, bytemuck::bytes_of(&uniform));
        let (w, h) = views.size;
        encoder.copy_texture_to_texture(
            views.color_texture.as_image_copy(),
            textures.albedo.as_image_copy(),
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        let (shadow_depth, shadow_ids) = match &textures.shadow {
            Some((_, v)) => (&v.depth, &v.id),
            // Not read without shadows; any textures of the kinds fill the bindings.
            None => (&views.depth, &views.id),
        };
        let entry = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: textures.uniform.as_entire_binding(),
                },
                entry(1, &textures.albedo_view),
                entry(2, &views.id),
                entry(3, aux),
                entry(4, &views.depth),
                entry(5, shadow_depth),
                entry(6, shadow_ids),
                entry(7, &buffers.ao_volume.view),
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        });
        let attach = |view, load| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("composite"),
            color_attachments: &[
                attach(views.color_view(), wgpu::LoadOp::Load),
                attach(
                    &textures.out_view,
                    wgpu::LoadOp::Clear(wgpu::Color {
                        r: 1.0,
                        g: 0.0,
                        b: 1.0,
                        a: 0.0,
                    }),
                ),
            ],
            // Read only: the shader samples the same depth (binding 4).
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &views.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline(ctx, buffers.kind, fx, req.aux_target()));
        pass.set_bind_group(0, &buffers.chunks[0].bind_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.draw(0..3, 0..1);
        drop(pass);
        Ok(textures)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_validates_and_its_uniform_matches() {
        for &kind in GlyphKind::VALUES {
            if let Err(e) = crate::render::shaders::validate(&composite_source(kind)) {
                panic!("composite.wgsl for {kind} does not validate:\n{e}");
            }
        }
        let module =
            crate::render::shaders::parse(&composite_source(GlyphKind::Ellipsoid)).expect("parses");
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Effects"))
            .expect("struct Effects");
        let wgpu::naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("Effects is not a struct");
        };
        use std::mem::offset_of;
        let rust = [
            ("inv_proj", offset_of!(EffectsUniform, inv_proj)),
            ("view_to_light", offset_of!(EffectsUniform, view_to_light)),
            ("key", offset_of!(EffectsUniform, key)),
            ("lighting", offset_of!(EffectsUniform, lighting)),
            ("outline", offset_of!(EffectsUniform, outline)),
            ("edges", offset_of!(EffectsUniform, edges)),
            ("viewport", offset_of!(EffectsUniform, viewport)),
            ("params", offset_of!(EffectsUniform, params)),
            ("view_to_world", offset_of!(EffectsUniform, view_to_world)),
            ("key_world", offset_of!(EffectsUniform, key_world)),
            ("ao", offset_of!(EffectsUniform, ao)),
            ("volume_lo", offset_of!(EffectsUniform, volume_lo)),
            ("volume_scale", offset_of!(EffectsUniform, volume_scale)),
        ];
        let wgsl: Vec<(String, usize)> = members
            .iter()
            .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
            .collect();
        let rust: Vec<(String, usize)> = rust.iter().map(|(n, o)| (n.to_string(), *o)).collect();
        assert_eq!(wgsl, rust);
        assert_eq!(*span as usize, EFFECTS_UNIFORM_SIZE);
    }
}
