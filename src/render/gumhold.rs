//! Gumhold's method: a long-lived set of pipelines (one per output variant) that draws 4-vertex
//! strips, one instance per glyph, with no vertex buffer. Ellipsoids use the glyph's own
//! silhouette quad; cylinders the quad of their bounding ellipsoid.

use crate::render::context::GpuContext;
use crate::render::headless::Drawer;
use crate::render::method::GlyphKind;
use crate::render::pipeline::{Variant, variant_pipelines};
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
        Self {
            pipelines: variant_pipelines(
                ctx,
                layout,
                source,
                wgpu::PrimitiveTopology::TriangleStrip,
            ),
        }
    }
}

impl Drawer for GumholdRenderer {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, variant: Variant, instances: u32) {
        pass.set_pipeline(&self.pipelines[variant.index()]);
        pass.draw(0..4, 0..instances);
    }
}
