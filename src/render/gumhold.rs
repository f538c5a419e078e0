//! Gumhold's method: long-lived pipelines (per output variant and proxy) that draw a 4-vertex
//! (quad), 8-vertex (octagon) or 3-vertex (triangle) strip per glyph instance, with no vertex
//! buffer. Ellipsoids use the glyph's own silhouette quad (optionally moved to its nearest plane:
//! conservative depth, and optionally built once per glyph by the `--prepass`); cylinders the
//! quad of their bounding ellipsoid.

use crate::render::context::GpuContext;
use crate::render::headless::Drawer;
use crate::render::method::GlyphKind;
use std::ops::Range;

use crate::render::pipeline::{Proxy, StripRenderer, Variant};
use crate::render::prepass::{PrepassLayouts, PrepassPipelines};
use crate::render::shaders::ShaderSource;

pub struct GumholdRenderer {
    strips: StripRenderer,
    glyph: GlyphKind,
}

impl GumholdRenderer {
    /// `prepass`: the `--prepass` layouts (used by ellipsoids only).
    pub fn new(
        ctx: &GpuContext,
        layout: &wgpu::PipelineLayout,
        glyph: GlyphKind,
        prepass: &PrepassLayouts,
    ) -> Self {
        let (source, prepass) = match glyph {
            GlyphKind::Ellipsoid => (ShaderSource::GumholdEllipsoid, Some(prepass.clone())),
            GlyphKind::Cylinder => (ShaderSource::GumholdCylinder, None),
        };
        Self {
            strips: StripRenderer::new(ctx, layout, source, prepass),
            glyph,
        }
    }
}

impl GumholdRenderer {
    /// Conservative depth is derived for the ellipsoid's own quad only.
    fn supported(&self, proxy: Proxy) -> Proxy {
        match self.glyph {
            GlyphKind::Ellipsoid => proxy,
            GlyphKind::Cylinder => Proxy {
                conservative: false,
                early_depth: false,
                ..proxy
            },
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
        self.strips
            .draw(pass, variant, self.supported(proxy), instances);
    }

    fn prepass_pipelines(&self, variant: Variant, proxy: Proxy) -> Option<PrepassPipelines> {
        self.strips
            .prepass_pipelines(variant, self.supported(proxy))
    }
}
