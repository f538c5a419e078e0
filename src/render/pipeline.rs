//! Pipeline state every glyph method shares: one bind group (camera + glyph instances), the same
//! targets, depth test and no culling (impostor winding depends on the view).

use crate::render::context::GpuContext;
use crate::render::targets::{AUX_FORMAT, COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT};

/// Which fragment outputs a pipeline writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Variant {
    /// Write the ray-cast depth (`frag_depth`); otherwise the proxy's own depth stands.
    pub depth_correction: bool,
    /// Also write the aux target (view normal, view z) for accuracy checks.
    pub aux: bool,
}

impl Variant {
    pub const ALL: [Variant; 4] = [
        Variant {
            depth_correction: true,
            aux: false,
        },
        Variant {
            depth_correction: true,
            aux: true,
        },
        Variant {
            depth_correction: false,
            aux: false,
        },
        Variant {
            depth_correction: false,
            aux: true,
        },
    ];

    /// The fragment entry point of this variant (same names in every method's shader).
    pub fn fragment_entry(self) -> &'static str {
        match (self.depth_correction, self.aux) {
            (true, false) => "fs_depth",
            (true, true) => "fs_depth_aux",
            (false, false) => "fs_flat",
            (false, true) => "fs_flat_aux",
        }
    }

    pub fn index(self) -> usize {
        usize::from(self.depth_correction) * 2 + usize::from(self.aux)
    }
}

/// The bind group layout of every glyph shader: @binding(0) camera, @binding(1) glyphs.
pub fn glyph_bind_group_layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("glyphs"),
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
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        })
}

/// A render pipeline for one method and variant (no vertex buffers, no culling).
pub fn glyph_pipeline(
    ctx: &GpuContext,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    label: &str,
    topology: wgpu::PrimitiveTopology,
    variant: Variant,
) -> wgpu::RenderPipeline {
    glyph_pipeline_with(
        ctx,
        layout,
        module,
        label,
        topology,
        variant,
        &VertexInput::default(),
    )
}

/// Vertex buffers and face culling of methods that draw real geometry (the triangle meshes).
#[derive(Debug, Clone, Default)]
pub struct VertexInput<'a> {
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Only for closed, outward-wound (counter-clockwise) meshes.
    pub cull_mode: Option<wgpu::Face>,
}

/// [`glyph_pipeline`] with vertex buffers and optional culling.
pub fn glyph_pipeline_with(
    ctx: &GpuContext,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    label: &str,
    topology: wgpu::PrimitiveTopology,
    variant: Variant,
    input: &VertexInput<'_>,
) -> wgpu::RenderPipeline {
    let mut targets = vec![
        Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Some(wgpu::ColorTargetState {
            format: ID_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
    ];
    if variant.aux {
        targets.push(Some(wgpu::ColorTargetState {
            format: AUX_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }));
    }
    ctx.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: input.buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology,
                cull_mode: input.cull_mode,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(variant.fragment_entry()),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
}

/// One pipeline per output variant (indexed by [`Variant::index`]) for a method's shader.
pub fn variant_pipelines(
    ctx: &GpuContext,
    layout: &wgpu::PipelineLayout,
    source: crate::render::shaders::ShaderSource,
    topology: wgpu::PrimitiveTopology,
) -> Vec<wgpu::RenderPipeline> {
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(source.name()),
            source: wgpu::ShaderSource::Wgsl(source.text().into()),
        });
    let mut pipelines: Vec<Option<wgpu::RenderPipeline>> = vec![None, None, None, None];
    for v in Variant::ALL {
        pipelines[v.index()] = Some(glyph_pipeline(
            ctx,
            layout,
            &module,
            source.name(),
            topology,
            v,
        ));
    }
    pipelines.into_iter().flatten().collect()
}
