//! Pipeline state every glyph method shares: one bind group (camera + glyph instances), the same
//! targets, depth test and no culling (impostor winding depends on the view).

use crate::render::context::GpuContext;
use crate::render::pipeline_cache::Pipelines;
use crate::render::targets::{COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT, aux_format};
use crate::request::AuxTarget;

/// Which fragment outputs a pipeline writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Variant {
    /// Write the ray-cast depth (`frag_depth`); otherwise the proxy's own depth stands.
    pub depth_correction: bool,
    /// What the aux target gets, if there is one.
    pub aux: AuxTarget,
    /// The key light's shadow map: only the glyph id and depth are written (the colour target
    /// is masked), so the shaders never compute a colour the map would not keep.
    pub shadow: bool,
}

impl Variant {
    /// Pipelines per method and proxy: the eye's six ([`Self::index`] 0–5) and the shadow
    /// map's two.
    pub const COUNT: usize = 8;

    /// The fragment entry point of this variant (same names in every method's shader).
    pub fn fragment_entry(self) -> &'static str {
        match (self.shadow, self.depth_correction, self.aux) {
            (true, true, _) => "fs_shadow",
            (true, false, _) => "fs_shadow_flat",
            (false, true, AuxTarget::None) => "fs_depth",
            (false, true, AuxTarget::Checked) => "fs_depth_aux",
            (false, true, AuxTarget::Normal) => "fs_depth_normal",
            (false, false, AuxTarget::None) => "fs_flat",
            (false, false, AuxTarget::Checked) => "fs_flat_aux",
            (false, false, AuxTarget::Normal) => "fs_flat_normal",
        }
    }

    /// The outputs `req` needs.
    pub fn of(req: &crate::request::FrameRequest) -> Self {
        Self {
            depth_correction: req.depth_correction(),
            aux: req.aux_target(),
            shadow: false,
        }
    }

    /// The outputs of `req` drawn into the key light's shadow map (`light`), else `req`'s own.
    pub fn of_pass(req: &crate::request::FrameRequest, light: bool) -> Self {
        if light {
            Self {
                depth_correction: req.depth_correction(),
                aux: AuxTarget::None,
                shadow: true,
            }
        } else {
            Self::of(req)
        }
    }

    /// Index in `0..COUNT`.
    pub fn index(self) -> usize {
        let aux = match self.aux {
            AuxTarget::None => 0,
            AuxTarget::Checked => 1,
            AuxTarget::Normal => 2,
        };
        if self.shadow {
            6 + usize::from(self.depth_correction)
        } else {
            usize::from(self.depth_correction) * 3 + aux
        }
    }
}

/// A bind group layout entry for a buffer (uniform or storage) without dynamic offsets.
pub fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bind group layout of every glyph shader: @binding(0) camera, @binding(1) glyphs (one
/// chunk), @binding(2) the chunk's base instance and culling parameters, @binding(3) the chunk's
/// superquadric exponents (one unused word pair for scenes of other glyphs). Compute stages see it
/// too (the `--prepass` reads the glyphs there).
pub fn glyph_bind_group_layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
    let all = wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE);
    // The chunk is a storage buffer: see flag_index in shaders/common.wgsl.
    let read = wgpu::BufferBindingType::Storage { read_only: true };
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("glyphs"),
            entries: &[
                buffer_entry(0, all, wgpu::BufferBindingType::Uniform),
                buffer_entry(1, all, read),
                buffer_entry(2, all, read),
                buffer_entry(3, all, read),
            ],
        })
}

/// A pipeline layout of the glyph group (group 0: camera, chunk, its parameters) and the
/// pass's own `group` (group 1): every pass that reads the glyphs beside its own buffers.
pub fn glyphs_and(
    device: &wgpu::Device,
    label: &str,
    glyphs: &wgpu::BindGroupLayout,
    group: &wgpu::BindGroupLayout,
) -> wgpu::PipelineLayout {
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(glyphs), Some(group)],
        immediate_size: 0,
    })
}

/// The layouts every glyph pipeline is built with.
pub struct GlyphLayouts {
    /// Group 0: camera, one chunk of instances, the chunk's parameters, its exponents.
    pub group: wgpu::BindGroupLayout,
    /// A pipeline layout of group 0 alone.
    pub pipeline: wgpu::PipelineLayout,
}

impl GlyphLayouts {
    pub fn new(ctx: &GpuContext) -> Self {
        let group = glyph_bind_group_layout(ctx);
        let pipeline = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("glyphs"),
                bind_group_layouts: &[Some(&group)],
                immediate_size: 0,
            });
        Self { group, pipeline }
    }
}

/// What besides the shader and variant a glyph pipeline needs: vertex buffers and face culling
/// (the triangle meshes), values for the shader's `override` constants (the ray casters).
#[derive(Debug, Clone, Default)]
pub struct PipelineInput<'a> {
    /// The vertex entry point (`vs_main` when `None`).
    pub vertex_entry: Option<&'a str>,
    /// The fragment entry point (the variant's when `None`).
    pub fragment_entry: Option<&'a str>,
    pub topology: Option<wgpu::PrimitiveTopology>,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Only for closed, outward-wound (counter-clockwise) meshes.
    pub cull_mode: Option<wgpu::Face>,
    pub constants: &'a [(&'a str, f64)],
}

/// A render pipeline for one method and output variant.
pub fn glyph_pipeline(
    pipelines: &Pipelines,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    label: &str,
    topology: wgpu::PrimitiveTopology,
    variant: Variant,
    input: &PipelineInput<'_>,
) -> wgpu::RenderPipeline {
    let options = wgpu::PipelineCompilationOptions {
        constants: input.constants,
        ..Default::default()
    };
    // The shadow map's pass keeps the targets (one render pass layout) but not the colour: its
    // fragment entry points have no colour output, which a masked target allows.
    let color_mask = if variant.shadow {
        wgpu::ColorWrites::empty()
    } else {
        wgpu::ColorWrites::ALL
    };
    let mut targets = vec![
        Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: color_mask,
        }),
        Some(wgpu::ColorTargetState {
            format: ID_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
    ];
    if let Some(format) = aux_format(variant.aux) {
        targets.push(Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }));
    }
    pipelines.render(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(input.vertex_entry.unwrap_or("vs_main")),
            compilation_options: options.clone(),
            buffers: input.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: input.topology.unwrap_or(topology),
            cull_mode: input.cull_mode,
            ..Default::default()
        },
        depth_stencil: Some(depth_test()),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(input.fragment_entry.unwrap_or(variant.fragment_entry())),
            compilation_options: options,
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The depth test every pass drawing into the targets uses: nearer wins, and is written.
pub(crate) fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}
