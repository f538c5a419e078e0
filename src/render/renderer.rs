//! The long-lived GPU renderer: the device, the glyph bind group layout every method shares, one
//! cache of drawers (each method's pipelines, built on first use: lavapipe compiles a pipeline in
//! tens of milliseconds), and the frame loop: write the uniforms, let the method's drawer record
//! its passes, submit, time, count and read the targets back. The loop knows no method.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use web_time::Instant;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::Frame;
use crate::render::context::GpuContext;
use crate::render::drawer::{Drawer, FrameRecording, Layered};
use crate::render::effects::{EffectsPipeline, EffectsTextures};
use crate::render::gpu_data::GPU_GLYPH_SIZE;
use crate::render::gumhold::GumholdRenderer;
use crate::render::mesh::MeshRenderer;
use crate::render::pipeline::GlyphLayouts;
use crate::render::query::Queries;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::sigg::SiggRenderer;
use crate::render::targets::{Readback, TargetViews, Targets};
use crate::render::underlay::UnderlayPipeline;
use crate::request::{FrameRequest, GlyphKind, Method};
use crate::scene::Scene;

type DrawerKey = (Method, GlyphKind);

/// Long-lived GPU state: device, shared layouts and every method's pipelines.
pub struct GpuRenderer {
    pub ctx: GpuContext,
    layouts: GlyphLayouts,
    drawers: Mutex<HashMap<DrawerKey, Arc<dyn Drawer>>>,
    underlay: UnderlayPipeline,
    effects: EffectsPipeline,
}

impl GpuRenderer {
    pub fn new(ctx: GpuContext) -> Result<Self, RenderError> {
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let layouts = GlyphLayouts::new(&ctx);
        let underlay = UnderlayPipeline::new(&ctx);
        let effects = EffectsPipeline::new(&ctx, &layouts.group);
        if let Some(e) = ctx.scope_error(scope, "creating the pipeline layout") {
            return Err(RenderError::Gpu(e));
        }
        Ok(Self {
            ctx,
            layouts,
            drawers: Mutex::new(HashMap::new()),
            underlay,
            effects,
        })
    }

    /// The drawer of a method and shape, built on first use.
    fn drawer(&self, method: Method, glyph: GlyphKind) -> Result<Arc<dyn Drawer>, RenderError> {
        let mut map = self.drawers.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(d) = map.get(&(method, glyph)) {
            return Ok(d.clone());
        }
        let scope = self
            .ctx
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let layouts = &self.layouts;
        let drawer: Arc<dyn Drawer> = match method {
            Method::Gumhold => Arc::new(GumholdRenderer::new(&self.ctx, layouts, glyph)),
            Method::Sigg => Arc::new(SiggRenderer::new(&self.ctx, layouts, glyph)),
            Method::Mesh(_) | Method::Box => {
                Arc::new(MeshRenderer::new(&self.ctx, layouts, method, glyph)?)
            }
            Method::Reference => {
                return Err(RenderError::Unsupported(
                    "the reference is a CPU method; use ReferenceScene".into(),
                ));
            }
        };
        let what = format!("creating {method} pipelines for {glyph}");
        if let Some(e) = self.ctx.scope_error(scope, &what) {
            return Err(RenderError::Gpu(e));
        }
        map.insert((method, glyph), drawer.clone());
        Ok(drawer)
    }

    /// What draws an uploaded scene with `method`: its kind's drawer, or for a scene of two
    /// kinds (an overlay) each kind's in turn ([`Layered`]).
    fn scene_drawer(
        &self,
        method: Method,
        buffers: &SceneBuffers,
    ) -> Result<Arc<dyn Drawer>, RenderError> {
        if let [kind] = buffers.kinds[..] {
            return self.drawer(method, kind);
        }
        let layers = buffers
            .kinds
            .iter()
            .map(|&k| Ok((k, self.drawer(method, k)?)))
            .collect::<Result<Vec<_>, RenderError>>()?;
        Ok(Arc::new(Layered { layers }))
    }

    pub fn adapter_name(&self) -> &str {
        &self.ctx.adapter_name
    }

    /// `req` with conservative depth declared to the GPU (`Proxy::early_depth`) where it holds:
    /// a conservative proxy, an adapter with SHADER_EARLY_DEPTH_TEST, and every glyph of
    /// `scene` far enough in front of the near plane for the move.
    pub fn with_early_depth(
        &self,
        req: FrameRequest,
        scene: &Scene,
        camera: &Camera,
    ) -> FrameRequest {
        let mut req = req.for_kind(scene.kind);
        let holds = req.proxy().conservative
            && self.ctx.early_depth_test
            && scene.conservative_depth_holds(camera);
        req.method.set_early_depth(holds);
        req
    }

    /// Render `scene` seen by `camera` with the request's method, as the scene's kind.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        pollster::block_on(self.render_async(scene, camera, req))
    }

    /// [`Self::render`] without blocking (the browser's figures).
    pub async fn render_async(
        &self,
        scene: &Scene,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        let buffers = self.upload(scene)?;
        self.render_uploaded_async(&buffers, camera, req).await
    }

    /// Upload a scene's instances once; the result is drawn by [`Self::encode`] or
    /// [`Self::render_uploaded`] as often as the camera or the request change (the viewer keeps
    /// it while the scene is unchanged).
    pub fn upload(&self, scene: &Scene) -> Result<SceneBuffers, RenderError> {
        self.upload_chunked(scene, self.max_chunk_glyphs())
    }

    /// Glyphs one storage buffer binding can hold on this device.
    pub fn max_chunk_glyphs(&self) -> usize {
        let limits = &self.ctx.limits;
        let bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        (bytes / GPU_GLYPH_SIZE as u64).clamp(1, u64::from(u32::MAX)) as usize
    }

    /// [`Self::upload`] in buffers of at most `chunk` glyphs each.
    pub fn upload_chunked(&self, scene: &Scene, chunk: usize) -> Result<SceneBuffers, RenderError> {
        SceneBuffers::upload(&self.ctx, &self.layouts.group, &self.underlay, scene, chunk)
    }

    /// `req` as this device can draw it at the camera's size: splats keep a 4- or 8-byte key
    /// per pixel in one storage binding, so an image with more pixels than that binding holds
    /// (16.7 M with 64-bit keys on a 128 MiB limit) draws every glyph from the prepass instead.
    pub fn within_limits(&self, req: &FrameRequest, camera: &Camera) -> FrameRequest {
        self.ctx.within_limits(req, camera)
    }

    /// Render instances uploaded by [`Self::upload`] (timing upload and frames apart).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn render_uploaded(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        pollster::block_on(self.render_uploaded_async(buffers, camera, req))
    }

    /// [`Self::render_uploaded`] without blocking.
    pub async fn render_uploaded_async(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        let req = &self.within_limits(&req.for_kind(buffers.kind), camera);
        let targets = Targets::new(&self.ctx, camera.width, camera.height, req.aux_target())?;
        self.render_into(buffers, camera, req, &targets).await
    }

    /// Run `f` (recording and submitting GPU work) inside a validation and an out-of-memory
    /// error scope, popped as soon as it returns: the browser keeps one stack of scopes per
    /// device, which the page's other work (egui) uses between our waits.
    fn scoped<T>(&self, f: impl FnOnce() -> T) -> (T, impl Future<Output = Option<String>>) {
        let device = &self.ctx.device;
        let invalid = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let out = f();
        let (oom, invalid) = (oom.pop(), invalid.pop());
        (out, async move {
            let oom = oom.await;
            let invalid = invalid.await;
            oom.or(invalid).map(|e| e.to_string())
        })
    }

    /// Record one frame of an uploaded scene into `views` (cleared first). The camera uniform is
    /// written through the queue, so it takes effect at the next submit. `timestamps`, when
    /// given, get the frame's begin (index 0) and end (index 1).
    pub fn encode(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<&wgpu::QuerySet>,
    ) -> Result<(), RenderError> {
        let req = &self.within_limits(&req.for_kind(buffers.kind), camera);
        let drawer = self.scene_drawer(req.method.method(), buffers)?;
        buffers.write_uniforms(&self.ctx.queue, camera, req);
        let frame = FrameRecording {
            timestamps,
            ..FrameRecording::new(&self.ctx, camera, buffers, req, views)
        };
        drawer.record(&frame, encoder);
        self.record_underlay(buffers, req, views, encoder);
        self.record_effects(buffers, drawer.as_ref(), camera, req, views, encoder)?;
        Ok(())
    }

    /// Deferred shading and its effects, after the method's and the underlay's passes.
    fn record_effects(
        &self,
        buffers: &SceneBuffers,
        drawer: &dyn Drawer,
        camera: &Camera,
        req: &FrameRequest,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Option<Arc<EffectsTextures>>, RenderError> {
        if !req.effects.deferred() {
            return Ok(None);
        }
        self.effects
            .record(&self.ctx, buffers, drawer, camera, req, views, encoder)
            .map(Some)
    }

    /// The underlay's pass, after the method's, when the scene has one and it is shown.
    fn record_underlay(
        &self,
        buffers: &SceneBuffers,
        req: &FrameRequest,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        if let (Some(u), true) = (&buffers.underlay, req.underlay.shown) {
            self.underlay.record(&self.ctx, u, views, encoder);
        }
    }

    async fn render_into(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
        targets: &Targets,
    ) -> Result<Frame, RenderError> {
        let ctx = &self.ctx;
        let device = &ctx.device;
        let (drawer, errors) = self.scoped(|| {
            let drawer = self.scene_drawer(req.method.method(), buffers);
            buffers.write_uniforms(&ctx.queue, camera, req);
            drawer
        });
        if let Some(e) = errors.await {
            return Err(RenderError::Gpu(e));
        }
        let drawer = drawer?;
        // Per render pass: [vertex invocations, fragment invocations] (ordered by flag bit).
        let passes = drawer.render_passes(ctx, buffers, req);
        let stats = ctx.pipeline_statistics.then(|| {
            Queries::new(
                device,
                "pipeline statistics",
                wgpu::QueryType::PipelineStatistics(
                    wgpu::PipelineStatisticsTypes::VERTEX_SHADER_INVOCATIONS
                        | wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS,
                ),
                passes,
            )
        });
        let views = TargetViews::new(targets);
        let frames = req.frames.max(1);
        let mut frame_ms = Vec::with_capacity(frames as usize);
        let mut effects = None;
        let mut counts = None;
        for f in 0..frames {
            let ((recorded, start), errors) = self.scoped(|| {
                let mut encoder = device.create_command_encoder(&Default::default());
                let recording = FrameRecording {
                    stats: stats.as_ref().filter(|_| f == 0).map(|s| &s.set),
                    ..FrameRecording::new(ctx, camera, buffers, req, &views)
                };
                drawer.record(&recording, &mut encoder);
                self.record_underlay(buffers, req, &views, &mut encoder);
                let recorded = self.record_effects(
                    buffers,
                    drawer.as_ref(),
                    camera,
                    req,
                    &views,
                    &mut encoder,
                );
                if let (Some(s), true) = (&stats, f == 0) {
                    s.resolve(&mut encoder);
                }
                let start = Instant::now();
                ctx.queue.submit([encoder.finish()]);
                (recorded, start)
            });
            effects = recorded?;
            // The browser's frames are timed by the read-back that follows (Chromium's
            // onSubmittedWorkDone promises can fail where mapping does not).
            #[cfg(not(target_arch = "wasm32"))]
            ctx.wait()?;
            frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
            if let Some(e) = errors.await {
                return Err(RenderError::Gpu(e));
            }
            if let (Some(s), true) = (&stats, f == 0) {
                counts = Some(s.read_async(ctx).await?);
            }
        }
        // The copies out of the targets are a submission of their own, after the timed frames: a
        // frame's time is what drawing it costs, as in the viewer, where nothing is read back
        // (on lavapipe the copies of a 1024x768 frame took 1-3 ms, which had been counted in
        // every one-frame measurement and dominated small scenes).
        let mut encoder = device.create_command_encoder(&Default::default());
        let readbacks = (
            Readback::record(ctx, &mut encoder, &targets.color, 4),
            Readback::record(ctx, &mut encoder, &targets.id, 4),
            targets
                .aux
                .as_ref()
                .filter(|_| req.aux)
                .map(|t| Readback::record(ctx, &mut encoder, t, 16)),
            effects
                .filter(|_| req.aux && req.effects.any())
                .map(|e| Readback::record(ctx, &mut encoder, &e.out, 4)),
        );
        ctx.queue.submit([encoder.finish()]);
        let (color_rb, id_rb, aux_rb, effects_rb) = readbacks;
        let color = color_rb.read_async(ctx).await?;
        let ids: Vec<u32> = bytemuck::pod_collect_to_vec(&id_rb.read_async(ctx).await?);
        let aux = match aux_rb {
            Some(rb) => Some(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(
                &rb.read_async(ctx).await?,
            )),
            None => None,
        };
        let effects = match effects_rb {
            Some(rb) => Some(
                rb.read_async(ctx)
                    .await?
                    .chunks_exact(4)
                    .map(|p| {
                        [
                            f32::from(p[0]) / 255.0,
                            f32::from(p[1]) / 255.0,
                            f32::from(p[2]) / 255.0,
                        ]
                    })
                    .collect(),
            ),
            None => None,
        };
        Ok(Frame {
            width: targets.width,
            height: targets.height,
            color,
            ids,
            aux,
            effects,
            frame_ms,
            fragments: counts
                .as_ref()
                .map(|c: &Vec<u64>| c.iter().skip(1).step_by(2).sum()),
            vertices: counts.as_ref().map(|c| c.iter().step_by(2).sum()),
        })
    }
}
