//! Gumhold's method: long-lived pipelines (per output variant and proxy) that draw a 4-vertex
//! (quad), 8-vertex (octagon) or 3-vertex (triangle) strip per glyph instance, with no vertex
//! buffer. Ellipsoids use
//! the glyph's own silhouette quad (optionally moved to its nearest plane: conservative depth);
//! cylinders the quad of their bounding ellipsoid.

use crate::render::context::GpuContext;
use crate::render::headless::Drawer;
use crate::render::method::GlyphKind;
use std::ops::Range;

use crate::render::pipeline::{Proxy, StripRenderer, Variant};
use crate::render::shaders::ShaderSource;

pub struct GumholdRenderer {
    strips: StripRenderer,
    glyph: GlyphKind,
}

impl GumholdRenderer {
    pub fn new(ctx: &GpuContext, layout: &wgpu::PipelineLayout, glyph: GlyphKind) -> Self {
        let source = match glyph {
            GlyphKind::Ellipsoid => ShaderSource::GumholdEllipsoid,
            GlyphKind::Cylinder => ShaderSource::GumholdCylinder,
        };
        Self {
            strips: StripRenderer::new(ctx, layout, source),
            glyph,
        }
    }
}

impl Drawer for GumholdRenderer {
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        instances: Range<u32>,
    ) {
        // Conservative depth is derived for the ellipsoid's own quad only.
        let proxy = match self.glyph {
            GlyphKind::Ellipsoid => proxy,
            GlyphKind::Cylinder => Proxy {
                conservative: false,
                early_depth: false,
                ..proxy
            },
        };
        self.strips.draw(pass, variant, proxy, instances);
    }
}
