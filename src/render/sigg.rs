//! Sigg et al.'s method: per glyph an instanced 4-vertex strip at the NDC corners of the
//! screen-space bounding box of the glyph (its kind's `shape_box`: for quadrics Sigg eq. 5), with
//! no vertex buffer; the fragment stage rebuilds the pixel's ray from its window position. Glyphs crossing the camera plane cover the viewport; glyphs behind
//! it or around the eye are culled. The box math has an f64 twin in [`crate::twin::sigg`].

use crate::render::context::GpuContext;
use crate::render::drawer::Drawer;
use crate::render::pipeline::{GlyphLayouts, Variant};
use crate::render::scene_buffers::ChunkBuffers;
use crate::render::shaders::{MethodShader, ShaderSource};
use crate::render::strip::StripRenderer;
use crate::request::{GlyphKind, Proxy};

pub struct SiggRenderer(StripRenderer);

impl SiggRenderer {
    pub fn new(ctx: &GpuContext, layouts: &GlyphLayouts, glyph: GlyphKind) -> Self {
        let source = ShaderSource::new(MethodShader::Sigg, glyph);
        Self(StripRenderer::new(ctx, layouts, source, None))
    }
}

impl Drawer for SiggRenderer {
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        _proxy: Proxy,
        chunk: &ChunkBuffers,
    ) {
        // The screen-space box is already tight: no proxy options apply.
        self.0.draw(pass, variant, Proxy::BASELINE, chunk);
    }
}
