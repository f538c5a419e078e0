//! Gumhold's ellipsoid method: a long-lived set of pipelines (one per output variant) that draws
//! 4-vertex strips, one instance per glyph, with no vertex buffer.

use crate::render::context::GpuContext;
use crate::render::pipeline::{Variant, glyph_pipeline};
use crate::render::shaders::ShaderSource;

pub struct GumholdRenderer {
    pipelines: Vec<wgpu::RenderPipeline>,
}

impl GumholdRenderer {
    pub fn new(ctx: &GpuContext, layout: &wgpu::PipelineLayout) -> Self {
        let text = ShaderSource::GumholdEllipsoid.text();
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(ShaderSource::GumholdEllipsoid.name()),
                source: wgpu::ShaderSource::Wgsl(text.into()),
            });
        let mut pipelines: Vec<Option<wgpu::RenderPipeline>> = vec![None, None, None, None];
        for v in Variant::ALL {
            pipelines[v.index()] = Some(glyph_pipeline(
                ctx,
                layout,
                &module,
                "gumhold ellipsoid",
                wgpu::PrimitiveTopology::TriangleStrip,
                v,
            ));
        }
        Self {
            pipelines: pipelines.into_iter().flatten().collect(),
        }
    }

    /// Record the draw: the bind group (camera + glyphs) must already be set.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, variant: Variant, instances: u32) {
        pass.set_pipeline(&self.pipelines[variant.index()]);
        pass.draw(0..4, 0..instances);
    }

    /// Vertex-shader invocations a draw of `instances` glyphs makes.
    pub fn vertices_per_instance() -> u32 {
        4
    }
}
