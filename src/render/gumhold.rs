//! Gumhold's method: a long-lived set of pipelines (one per output variant) that draws 4-vertex
//! strips, one instance per glyph, with no vertex buffer. Ellipsoids use the glyph's own
//! silhouette quad; cylinders the quad of their bounding ellipsoid.

use crate::render::context::GpuContext;
use crate::render::headless::Drawer;
use crate::render::method::GlyphKind;
use crate::render::pipeline::{Variant, glyph_pipeline};
use crate::render::shaders::ShaderSource;

pub struct GumholdRenderer {
    pipelines: Vec<wgpu::RenderPipeline>,
}

impl GumholdRenderer {
    pub fn new(ctx: &GpuContext, layout: &wgpu::PipelineLayout, glyph: GlyphKind) -> Self {
        let source = match glyph {
            GlyphKind::Ellipsoid => ShaderSource::GumholdEllipsoid,
            GlyphKind::Cylinder => ShaderSource::GumholdCylinder,
        };
        let text = source.text();
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(source.name()),
                source: wgpu::ShaderSource::Wgsl(text.into()),
            });
        let mut pipelines: Vec<Option<wgpu::RenderPipeline>> = vec![None, None, None, None];
        for v in Variant::ALL {
            pipelines[v.index()] = Some(glyph_pipeline(
                ctx,
                layout,
                &module,
                source.name(),
                wgpu::PrimitiveTopology::TriangleStrip,
                v,
            ));
        }
        Self {
            pipelines: pipelines.into_iter().flatten().collect(),
        }
    }
}

impl Drawer for GumholdRenderer {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, variant: Variant, instances: u32) {
        pass.set_pipeline(&self.pipelines[variant.index()]);
        pass.draw(0..4, 0..instances);
    }
}
