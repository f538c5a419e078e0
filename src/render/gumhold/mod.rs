//! Gumhold's method: long-lived pipelines (per output variant and proxy) that draw a 4-vertex
//! (quad), 8-vertex (octagon) or 3-vertex (triangle) strip per glyph instance, with no vertex
//! buffer. Ellipsoids use the glyph's own silhouette quad (optionally moved to its nearest plane:
//! conservative depth); every other kind the quad of its bounding ellipsoid (`shape_of`: a
//! cylinder's minimal ellipsoid, a capsule's circumscribed cylinder's, the ball holding a
//! superquadric). Kinds whose capabilities say so are also built once per glyph by the compute
//! prepass, with splats ([`prepass`]). The f64 twin of the shaders is
//! [`crate::twin::gumhold_ellipsoid`].

pub mod frames;
pub mod occlusion;
pub mod prepass;

use crate::render::context::GpuContext;
use crate::render::drawer::{Drawer, FrameRecording, record_chunks};
use crate::render::pipeline::{GlyphLayouts, Variant};
use crate::render::scene_buffers::{ChunkBuffers, Needs, SceneBuffers};
use crate::render::shaders::{MethodShader, ShaderSource};
use crate::render::strip::StripRenderer;
use crate::request::{FrameRequest, GlyphKind, Proxy};
use prepass::{
    PrepassBuffers, PrepassCache, PrepassPipelines, frame_buffer_layout, glyph_list_layout,
};

/// The prepass buffers the shadow map's pass keeps (a type of its own for the scene's state).
struct LightPrepass(PrepassBuffers);

/// The eye's or the light's prepass buffers.
enum Prepass {
    Eye(std::sync::Arc<PrepassBuffers>),
    Light(std::sync::Arc<LightPrepass>),
}

impl std::ops::Deref for Prepass {
    type Target = PrepassBuffers;
    fn deref(&self) -> &PrepassBuffers {
        match self {
            Prepass::Eye(p) => p,
            Prepass::Light(p) => &p.0,
        }
    }
}

pub struct GumholdRenderer {
    strips: StripRenderer,
    /// The compute prepass and splats (ellipsoids and superquadrics).
    prepass: Option<PrepassCache>,
    /// Occlusion culling's passes, with the prepass.
    occlusion: Option<occlusion::OcclusionPass>,
}

impl GumholdRenderer {
    /// Gumhold's pipelines for `glyph`: the ellipsoid's exact quad, or the kind's bounding
    /// ellipsoid's; the prepass where the kind takes it ([`crate::shape::Capabilities`]).
    pub fn new(ctx: &GpuContext, layouts: &GlyphLayouts, glyph: GlyphKind) -> Self {
        let source = ShaderSource::new(MethodShader::Gumhold, glyph);
        let prepass = glyph.caps().prepass && ctx.prepass_fits();
        // What vs_frames reads per instance: the ellipsoid's frames, another kind's glyph list.
        let instance_input = prepass.then(|| {
            if glyph == GlyphKind::Ellipsoid {
                frame_buffer_layout()
            } else {
                glyph_list_layout()
            }
        });
        Self {
            strips: StripRenderer::new(ctx, layouts, source, instance_input),
            prepass: prepass.then(|| PrepassCache::new(ctx, &layouts.group)),
            occlusion: prepass.then(|| occlusion::OcclusionPass::new(ctx, &layouts.group)),
        }
    }

    /// The prepass pipelines when `req` asks for the prepass and this glyph has it, for a chunk
    /// whose glyphs need `needs`.
    fn prepass_pipelines(
        &self,
        req: &FrameRequest,
        variant: Variant,
        needs: Needs,
    ) -> Option<PrepassPipelines> {
        if !req.uses_prepass() {
            return None;
        }
        let cache = self.prepass.as_ref()?;
        Some(cache.pipelines(&self.strips, variant, req.proxy(), needs))
    }

    /// The scene's prepass buffers, made on the first frame drawn with the prepass; the key
    /// light's shadow map (`light`) has its own, so that neither pass re-sizes the other's
    /// per-pixel buffers every frame.
    fn prepass_buffers(
        &self,
        ctx: &GpuContext,
        buffers: &SceneBuffers,
        light: bool,
    ) -> Option<Prepass> {
        let cache = self.prepass.as_ref()?;
        let make = || {
            let counts: Vec<u32> = buffers.chunks.iter().map(|c| c.count).collect();
            // The key light's map is drawn unculled.
            let bricks = buffers.bricks.as_ref().filter(|_| !light);
            PrepassBuffers::new(ctx, &cache.layouts, &counts, bricks)
        };
        Some(if light {
            Prepass::Light(buffers.method_state(|| LightPrepass(make())))
        } else {
            Prepass::Eye(buffers.method_state(make))
        })
    }
}

impl Drawer for GumholdRenderer {
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        chunk: &ChunkBuffers,
    ) {
        // The request's configuration gives the solids no conservative proxy.
        self.strips.draw(pass, variant, proxy, chunk);
    }

    fn render_passes(&self, ctx: &GpuContext, buffers: &SceneBuffers, req: &FrameRequest) -> u32 {
        if !req.uses_prepass() {
            return 1;
        }
        self.prepass_buffers(ctx, buffers, false)
            .map_or(1, |p| (p.slices.len() as u32).max(1))
    }

    /// Without the prepass, one pass over the chunks; with it, per slice of the scene a compute
    /// pass (frames, splats) and a render pass drawing the kept frames and resolving the splats.
    fn record(&self, frame: &FrameRecording<'_>, encoder: &mut wgpu::CommandEncoder) {
        let prepass = frame
            .req
            .uses_prepass()
            .then(|| self.prepass_buffers(frame.ctx, frame.buffers, frame.light))
            .flatten();
        let Some(prepass) = prepass else {
            return record_chunks(self, frame, encoder);
        };
        let req = frame.req;
        let views = frame.views;
        let splats = req.splat_pixels() > 0;
        let bricks = frame.buffers.bricks.as_ref().filter(|_| !frame.light);
        let draws = prepass.frame_slices(
            &frame.ctx.queue,
            bricks,
            frame.camera,
            frame.buffers.origin(),
        );
        prepass.write_params(&frame.ctx.queue, req.splat_pixels(), &draws);
        if draws.is_empty() {
            views.begin_pass(
                encoder,
                req.background,
                frame.first,
                frame.pass_timestamps(true, true),
            );
            return;
        }
        let last = draws.len() - 1;
        for (j, slice) in draws.iter().enumerate() {
            let buffers = &frame.buffers.chunks[prepass.slices[slice.k].chunk];
            let pipelines = self
                .prepass_pipelines(req, frame.variant(), buffers.needs)
                .expect("a glyph with prepass buffers has its pipelines");
            let chunk = frame.group(buffers);
            if slice.bricks {
                let pass = self.occlusion.as_ref().expect("made with the prepass");
                prepass.record_culling(encoder, pass, chunk, &views.depth, slice, views.size);
            }
            let compute_stamp = frame
                .timestamps
                .filter(|_| j == 0 && frame.first)
                .map(|set| wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: None,
                });
            prepass.record_compute(
                encoder,
                &pipelines,
                chunk,
                slice,
                views.size,
                splats,
                compute_stamp,
            );
            let mut pass = views.begin_pass(
                encoder,
                req.background,
                j == 0 && frame.first,
                frame.pass_timestamps(false, j == last),
            );
            if let Some(set) = frame.stats {
                pass.begin_pipeline_statistics_query(set, frame.query + j as u32);
            }
            pass.set_bind_group(0, chunk, &[]);
            prepass.draw(&mut pass, &pipelines, splats);
            if frame.stats.is_some() {
                pass.end_pipeline_statistics_query();
            }
        }
    }
}
