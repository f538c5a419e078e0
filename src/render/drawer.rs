//! The one thing a method gives the renderer: a [`Drawer`] that records a frame's passes. The
//! frame loop ([`crate::render::GpuRenderer`]) knows no method; a method with passes of its own
//! (Gumhold's compute prepass and splats) records them here.

use crate::camera::Camera;
use crate::render::context::GpuContext;
use crate::render::pipeline::Variant;
use crate::render::scene_buffers::{ChunkBuffers, SceneBuffers};
use crate::render::targets::TargetViews;
use crate::request::{FrameRequest, Proxy};

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
}

impl FrameRecording<'_> {
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

    /// Timestamp writes of a render pass that begins and/or ends the frame.
    pub fn pass_timestamps(
        &self,
        begin: bool,
        end: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.timestamps.map(|set| wgpu::RenderPassTimestampWrites {
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
        true,
        frame.pass_timestamps(true, true),
    );
    if let Some(set) = frame.stats {
        pass.begin_pipeline_statistics_query(set, 0);
    }
    for c in frame.buffers.chunks.iter().filter(|c| c.count > 0) {
        pass.set_bind_group(0, frame.group(c), &[]);
        drawer.draw(&mut pass, frame.variant(), req.proxy(), c);
    }
    if frame.stats.is_some() {
        pass.end_pipeline_statistics_query();
    }
}
