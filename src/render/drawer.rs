//! The one thing a method gives the renderer: a [`Drawer`] that records a frame's passes. The
//! frame loop ([`crate::render::GpuRenderer`]) knows no method; a method with passes of its own
//! (Gumhold's compute prepass and splats) records them here. A scene of two kinds (an
//! [`crate::scene::Overlay`]) is drawn by [`Layered`]: each kind's drawer in turn into the same
//! targets, the first clearing them, so that depth decides between any two glyphs.

use crate::camera::Camera;
use crate::render::context::GpuContext;
use crate::render::pipeline::Variant;
use crate::render::scene_buffers::{ChunkBuffers, SceneBuffers};
use crate::render::targets::TargetViews;
use crate::request::{FrameRequest, GlyphKind, Proxy};
use std::sync::Arc;

/// Everything a drawer records one frame with.
pub struct FrameRecording<'a> {
    pub ctx: &'a GpuContext,
    /// The camera the frame is drawn from (the key light's for the shadow map).
    pub camera: &'a Camera,
    pub buffers: &'a SceneBuffers,
    pub req: &'a FrameRequest,
    /// The targets; the first pass clears them.
    pub views: &'a TargetViews,
    /// One pipeline-statistics query per render pass ([`Drawer::render_passes`]), if counted.
    pub stats: Option<&'a wgpu::QuerySet>,
    /// Index 0 at the frame's start and 1 at its end, if timed.
    pub timestamps: Option<&'a wgpu::QuerySet>,
    /// Drawn from the key light (the shadow map): the chunks' light groups, and whatever a
    /// method keeps per scene kept apart from the eye's.
    pub light: bool,
    /// The kind drawn: the chunks of this kind.
    pub kind: GlyphKind,
    /// The first drawing into the targets: it clears them and writes the begin timestamp.
    pub first: bool,
    /// The last: it writes the end timestamp.
    pub last: bool,
    /// The pipeline-statistics query of this recording's first render pass.
    pub query: u32,
}

impl<'a> FrameRecording<'a> {
    /// A recording of a whole frame of `buffers`' own kind (the first and last drawing, queries
    /// from 0).
    pub fn new(
        ctx: &'a GpuContext,
        camera: &'a Camera,
        buffers: &'a SceneBuffers,
        req: &'a FrameRequest,
        views: &'a TargetViews,
    ) -> Self {
        Self {
            ctx,
            camera,
            buffers,
            req,
            views,
            stats: None,
            timestamps: None,
            light: false,
            kind: buffers.kind,
            first: true,
            last: true,
            query: 0,
        }
    }

    /// The chunks of this recording's kind.
    pub fn chunks(&self) -> impl Iterator<Item = &'a ChunkBuffers> + use<'a, '_> {
        self.buffers
            .chunks
            .iter()
            .filter(|c| c.kind == self.kind && c.count > 0)
    }

    /// The bind group 0 of a chunk for this recording's camera.
    pub fn group<'b>(&self, chunk: &'b ChunkBuffers) -> &'b wgpu::BindGroup {
        if self.light {
            &chunk.light_bind_group
        } else {
            &chunk.bind_group
        }
    }

    /// The outputs this recording's pipelines write ([`Variant::of_pass`]).
    pub fn variant(&self) -> Variant {
        Variant::of_pass(self.req, self.light)
    }

    /// Timestamp writes of a render pass that begins and/or ends this recording (the frame's
    /// where the recording is its first or last drawing).
    pub fn pass_timestamps(
        &self,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (begin, end) = (begin && self.first, end && self.last);
        self.timestamps
            .filter(|_| begin || end)
            .map(|set| wgpu::RenderPassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: begin.then_some(0),
                end_of_pass_write_index: end.then_some(1),
            })
    }
}

/// A GPU method's long-lived pipelines for one glyph shape.
pub trait Drawer: Send + Sync {
    /// Record the draw of the glyph instances of `chunk`; bind group 0 (camera, the chunk, its
    /// uniform) is already set.
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        chunk: &ChunkBuffers,
    );

    /// Render passes one frame of `req` takes (each gets one pipeline-statistics query).
    /// Drawn in a [`Layered`] frame, `req` is the layer's own and takes no prepass.
    fn render_passes(
        &self,
        _ctx: &GpuContext,
        _buffers: &SceneBuffers,
        _req: &FrameRequest,
    ) -> u32 {
        1
    }

    /// Record one frame into `frame.views` (cleared first): by default one render pass drawing
    /// every chunk with [`Drawer::draw`].
    fn record(&self, frame: &FrameRecording<'_>, encoder: &mut wgpu::CommandEncoder) {
        record_chunks(self, frame, encoder);
    }
}

/// One render pass drawing every chunk of the scene with `drawer`.
pub fn record_chunks<D: Drawer + ?Sized>(
    drawer: &D,
    frame: &FrameRecording<'_>,
    encoder: &mut wgpu::CommandEncoder,
) {
    let req = frame.req;
    let mut pass = frame.views.begin_pass(
        encoder,
        req.background,
        frame.first,
        frame.pass_timestamps(true, true),
    );
    if let Some(set) = frame.stats {
        pass.begin_pipeline_statistics_query(set, frame.query);
    }
    for c in frame.chunks() {
        pass.set_bind_group(0, frame.group(c), &[]);
        drawer.draw(&mut pass, frame.variant(), req.proxy(), c);
    }
    if frame.stats.is_some() {
        pass.end_pipeline_statistics_query();
    }
}

/// The drawers of a scene of several kinds, each drawing its own chunks in turn into the same
/// targets: the first clears them, the rest draw over with the depth test, so that depth decides
/// between glyphs of different kinds as between any two. Each draws with the request made for its
/// kind ([`FrameRequest::for_kind`]) and without Gumhold's prepass, whose per-scene buffers and
/// bricks are a one-kind scene's.
pub struct Layered {
    pub layers: Vec<(GlyphKind, Arc<dyn Drawer>)>,
}

impl Layered {
    fn layer_request(req: &FrameRequest, kind: GlyphKind) -> FrameRequest {
        let mut req = req.for_kind(kind);
        req.method = req.method.without_prepass();
        req
    }
}

impl Drawer for Layered {
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        chunk: &ChunkBuffers,
    ) {
        if let Some((_, d)) = self.layers.iter().find(|(k, _)| *k == chunk.kind) {
            d.draw(pass, variant, proxy, chunk);
        }
    }

    fn render_passes(&self, ctx: &GpuContext, buffers: &SceneBuffers, req: &FrameRequest) -> u32 {
        self.layers
            .iter()
            .map(|(k, d)| d.render_passes(ctx, buffers, &Self::layer_request(req, *k)))
            .sum()
    }

    fn record(&self, frame: &FrameRecording<'_>, encoder: &mut wgpu::CommandEncoder) {
        let mut query = frame.query;
        let last = self.layers.len().saturating_sub(1);
        for (i, (kind, drawer)) in self.layers.iter().enumerate() {
            let req = Self::layer_request(frame.req, *kind);
            let layer = FrameRecording {
                req: &req,
                kind: *kind,
                first: frame.first && i == 0,
                last: frame.last && i == last,
                query,
                ..*frame
            };
            drawer.record(&layer, encoder);
            query += drawer.render_passes(frame.ctx, frame.buffers, &req);
        }
    }
}
