//! Off-screen frames: upload a scene, draw it with one method, time it, count its fragments and
//! read the targets back.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::gpu_data::{CameraUniform, ChunkUniform, GPU_GLYPH_SIZE, GpuGlyph, Lighting};
use crate::render::gumhold::GumholdRenderer;
use crate::render::mesh::MeshRenderer;
use crate::render::method::{GlyphKind, Method};
use crate::render::pipeline::{Proxy, Variant, glyph_bind_group_layout};
use crate::render::prepass::{PrepassBuffers, PrepassLayouts, PrepassPipelines};
use crate::render::query::Queries;
use crate::render::sigg::SiggRenderer;
use crate::render::targets::{Readback, Targets};

use crate::scene::{GlyphInstance, Scene};

/// What to draw and what to read back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRequest {
    pub method: Method,
    pub glyph: GlyphKind,
    pub depth_correction: bool,
    /// Read back view normals and view z (for `--reference-check`).
    pub aux: bool,
    /// Linear RGBA in [0, 1].
    pub background: [f64; 4],
    /// Frames to render and time (the targets of the last one are read back).
    pub frames: u32,
    pub lighting: Lighting,
    /// How the ray casters bound each glyph.
    pub proxy: Proxy,
    /// Cull glyphs outside the view frustum (or wholly in front of the near plane) in the
    /// vertex stage. Off by default: on lavapipe a culled glyph still costs its vertex
    /// invocations and measured no faster (README, "Doing less work").
    pub cull: bool,
    /// Skip glyphs whose projected bounding sphere has a radius below this many pixels (0: none).
    pub min_pixel_radius: f32,
    /// Gumhold ellipsoids: build each glyph's proxy frame once in a compute pass and draw only
    /// the glyphs it keeps (src/render/prepass.rs); other methods ignore it.
    pub prepass: bool,
    /// Gumhold ellipsoids with depth correction: glyphs whose proxy spans at most this many
    /// pixels across are ray cast per pixel in compute instead of drawn (0: none; implies the
    /// prepass).
    pub splat: u32,
}

impl FrameRequest {
    /// `render`'s default way of drawing (issue 7): culled, with splats up to
    /// [`crate::render::DEFAULT_SPLAT`] px from the compute prepass. [`FrameRequest::default`]
    /// is the path before it (a quad drawn for every glyph), which `render --baseline` runs.
    pub fn with_render_path(self) -> Self {
        Self {
            cull: true,
            splat: crate::render::DEFAULT_SPLAT,
            ..self
        }
    }

    /// Whether frames come from the compute prepass.
    pub fn uses_prepass(&self) -> bool {
        self.prepass || self.splat > 0
    }

    /// The splat size in effect: splats write the ray-cast depth, so none without depth
    /// correction.
    pub fn splat_pixels(&self) -> u32 {
        if self.depth_correction { self.splat } else { 0 }
    }

    /// The fragment outputs this request needs.
    pub fn variant(&self) -> Variant {
        Variant {
            depth_correction: self.depth_correction,
            aux: self.aux,
        }
    }

    /// Declare conservative depth to the GPU (`Proxy::early_depth`) where it holds: a
    /// conservative proxy, an adapter with SHADER_EARLY_DEPTH_TEST, and every glyph of `scene`
    /// far enough in front of the near plane for the move.
    pub fn with_early_depth(self, gpu: &GpuRenderer, scene: &Scene, camera: &Camera) -> Self {
        let mut req = self;
        req.proxy.early_depth = req.proxy.conservative
            && gpu.ctx.early_depth_test
            && scene.conservative_depth_holds(camera);
        req
    }
}

impl Default for FrameRequest {
    fn default() -> Self {
        Self {
            method: Method::Gumhold,
            glyph: GlyphKind::Ellipsoid,
            depth_correction: true,
            aux: false,
            background: [1.0, 1.0, 1.0, 1.0],
            frames: 1,
            lighting: Lighting::default(),
            proxy: Proxy::default(),
            cull: false,
            min_pixel_radius: 0.0,
            prepass: false,
            splat: 0,
        }
    }
}

/// A rendered frame, as the GPU or the reference produced it.
#[derive(Debug, Clone, Default)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, row-major from the top-left.
    pub color: Vec<u8>,
    /// Instance index + 1 of the front-most glyph, 0 for background.
    pub ids: Vec<u32>,
    /// View-space normal and the view z of the hit relative to its glyph's centre, per pixel
    /// (where `ids` is non-zero).
    pub aux: Option<Vec<[f32; 4]>>,
    /// Wall-clock time of each frame, submit to completion.
    pub frame_ms: Vec<f64>,
    /// Fragment-shader invocations of one frame (pipeline statistics), where available.
    pub fragments: Option<u64>,
    /// Vertex-shader invocations of one frame.
    pub vertices: Option<u64>,
}

impl Frame {
    pub fn median_ms(&self) -> f64 {
        let mut t = self.frame_ms.clone();
        t.sort_by(f64::total_cmp);
        if t.is_empty() { 0.0 } else { t[t.len() / 2] }
    }

    pub fn covered_pixels(&self) -> usize {
        self.ids.iter().filter(|&&i| i != 0).count()
    }

    /// Glyphs that show in at least one pixel.
    pub fn visible_glyphs(&self) -> usize {
        let mut ids: Vec<u32> = self.ids.iter().copied().filter(|&i| i != 0).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }
}

/// A GPU method's long-lived pipelines for one glyph shape.
pub trait Drawer: Send + Sync {
    /// Record the draw of the glyph instances `instances` (instance_index values); bind group 0
    /// (camera, the chunk holding them, its uniform) is already set.
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        instances: std::ops::Range<u32>,
    );

    /// The `--prepass` pipelines, for drawers that have them.
    fn prepass_pipelines(&self, _variant: Variant, _proxy: Proxy) -> Option<PrepassPipelines> {
        None
    }
}

type DrawerKey = (Method, GlyphKind);

/// Long-lived GPU state: device, shared layout and every method's pipelines (built on first use:
/// lavapipe compiles a pipeline in tens of milliseconds).
pub struct GpuRenderer {
    pub ctx: GpuContext,
    bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    prepass_layouts: PrepassLayouts,
    drawers: Mutex<HashMap<DrawerKey, Arc<dyn Drawer>>>,
}

impl GpuRenderer {
    pub fn new(ctx: GpuContext) -> Result<Self, RenderError> {
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bind_group_layout = glyph_bind_group_layout(&ctx);
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("glyphs"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
        let prepass_layouts = PrepassLayouts::new(&ctx, &bind_group_layout);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Gpu(format!(
                "creating the pipeline layout: {e}"
            )));
        }
        Ok(Self {
            ctx,
            bind_group_layout,
            pipeline_layout: layout,
            prepass_layouts,
            drawers: Mutex::new(HashMap::new()),
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
        let layout = &self.pipeline_layout;
        let drawer: Arc<dyn Drawer> = match (method, glyph) {
            (Method::Gumhold, glyph) => Arc::new(GumholdRenderer::new(
                &self.ctx,
                layout,
                glyph,
                &self.prepass_layouts,
            )),
            (Method::Sigg, glyph) => Arc::new(SiggRenderer::new(&self.ctx, layout, glyph)),
            (Method::Mesh(_) | Method::Box, glyph) => Arc::new(
                MeshRenderer::new(&self.ctx, layout, method, glyph).expect("a mesh method"),
            ),
            (Method::Reference, _) => {
                return Err(RenderError::Unsupported(
                    "the reference is a CPU method; use ReferenceScene".into(),
                ));
            }
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Gpu(format!(
                "creating {method} pipelines for {glyph}: {e}"
            )));
        }
        map.insert((method, glyph), drawer.clone());
        Ok(drawer)
    }

    pub fn adapter_name(&self) -> &str {
        &self.ctx.adapter_name
    }

    /// Render `scene` seen by `camera` with the request's method and glyph shape.
    pub fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        let buffers = self.upload(scene)?;
        self.render_uploaded(&buffers, camera, req)
    }

    /// Render instances uploaded by [`Self::upload`] (timing upload and frames apart).
    pub fn render_uploaded(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<Frame, RenderError> {
        let ctx = &self.ctx;
        let targets = Targets::new(ctx, camera.width, camera.height, req.aux)?;
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let result = self.render_into(buffers, camera, req, &targets);
        let oom = pollster::block_on(oom.pop());
        let invalid = pollster::block_on(scope.pop());
        if let Some(e) = oom.or(invalid) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        result
    }

    /// Upload a scene's instances once; the result is drawn by [`Self::encode`] as often as the
    /// camera or the request change (the viewer keeps it while the scene is unchanged).
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

    /// [`Self::upload`] in buffers of at most `chunk` glyphs each. The instances are packed
    /// straight into each buffer's mapping (no second copy of the scene on the CPU).
    pub fn upload_chunked(&self, scene: &Scene, chunk: usize) -> Result<SceneBuffers, RenderError> {
        let device = &self.ctx.device;
        let chunk = chunk.max(1);
        if scene.instances.len() > u32::MAX as usize - 1 {
            return Err(RenderError::Unsupported(format!(
                "{} glyphs: at most {} can be drawn",
                scene.instances.len(),
                u32::MAX - 1
            )));
        }
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let camera_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("camera"),
            size: std::mem::size_of::<CameraUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // A binding may not be empty: an empty scene gets one chunk with an unused instance.
        let pieces: Vec<&[GlyphInstance]> = if scene.instances.is_empty() {
            vec![&[]]
        } else {
            scene.instances.chunks(chunk).collect()
        };
        let mut chunks = Vec::with_capacity(pieces.len());
        let mut base = 0u32;
        for piece in pieces {
            chunks.push(self.upload_chunk(piece, base, &camera_buffer)?);
            base += piece.len() as u32;
        }
        let oom = pollster::block_on(oom.pop());
        let invalid = pollster::block_on(scope.pop());
        if let Some(e) = oom.or(invalid) {
            return Err(RenderError::Gpu(format!(
                "uploading {} glyph instances: {e}",
                scene.instances.len()
            )));
        }
        Ok(SceneBuffers {
            origin: scene.origin,
            count: base,
            camera_buffer,
            chunks,
            prepass: OnceLock::new(),
        })
    }

    /// One chunk: a storage buffer of `piece` packed straight into its mapping, its uniform and
    /// its bind group.
    fn upload_chunk(
        &self,
        piece: &[GlyphInstance],
        base: u32,
        camera_buffer: &wgpu::Buffer,
    ) -> Result<ChunkBuffers, RenderError> {
        use rayon::prelude::*;
        let device = &self.ctx.device;
        let glyphs = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("glyph instances"),
            size: (piece.len().max(1) * GPU_GLYPH_SIZE) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: true,
        });
        {
            let mut view = glyphs
                .slice(..)
                .get_mapped_range_mut()
                .map_err(|e| RenderError::Gpu(format!("mapping a glyph buffer for upload: {e}")))?;
            // The mapping is write-only: pack in blocks (in parallel) and copy each in.
            const BLOCK: usize = 1 << 16;
            let mut packed: Vec<GpuGlyph> = Vec::with_capacity(BLOCK.min(piece.len()));
            for (k, block) in piece.chunks(BLOCK).enumerate() {
                block
                    .par_iter()
                    .map(GpuGlyph::pack)
                    .collect_into_vec(&mut packed);
                let at = k * BLOCK * GPU_GLYPH_SIZE;
                view.slice(at..at + block.len() * GPU_GLYPH_SIZE)
                    .copy_from_slice(bytemuck::cast_slice(&packed));
            }
        }
        glyphs.unmap();
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("chunk"),
            size: std::mem::size_of::<ChunkUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("glyphs"),
            layout: &self.bind_group_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: camera_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: glyphs.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: uniform.as_entire_binding(),
                },
            ],
        });
        let count = piece.len() as u32;
        Ok(ChunkBuffers {
            base,
            count,
            _glyphs: glyphs,
            uniform,
            bind_group,
        })
    }

    /// Write the camera and chunk uniforms of a frame (through the queue: they take effect at
    /// the next submit).
    fn write_uniforms(&self, buffers: &SceneBuffers, camera: &Camera, req: &FrameRequest) {
        let queue = &self.ctx.queue;
        let uniform = CameraUniform::new(camera, buffers.origin, &req.lighting);
        queue.write_buffer(&buffers.camera_buffer, 0, bytemuck::bytes_of(&uniform));
        for c in &buffers.chunks {
            let u = ChunkUniform {
                base: c.base,
                min_pixel_radius: req.min_pixel_radius,
                cull: u32::from(req.cull),
                _pad: 0,
            };
            queue.write_buffer(&c.uniform, 0, bytemuck::bytes_of(&u));
        }
    }

    /// The prepass pipelines when `req` asks for the prepass and the drawer has it.
    fn prepass_for(drawer: &dyn Drawer, req: &FrameRequest) -> Option<PrepassPipelines> {
        if !req.uses_prepass() {
            return None;
        }
        drawer.prepass_pipelines(req.variant(), req.proxy)
    }

    fn prepass_buffers<'b>(&self, buffers: &'b SceneBuffers) -> &'b PrepassBuffers {
        buffers.prepass.get_or_init(|| {
            let counts: Vec<u32> = buffers.chunks.iter().map(|c| c.count).collect();
            PrepassBuffers::new(&self.ctx, &self.prepass_layouts, &counts)
        })
    }

    /// Render passes one frame of `req` takes: one, or one per prepass slice.
    fn render_passes(
        &self,
        drawer: &dyn Drawer,
        buffers: &SceneBuffers,
        req: &FrameRequest,
    ) -> u32 {
        match Self::prepass_for(drawer, req) {
            Some(_) => (self.prepass_buffers(buffers).slices.len() as u32).max(1),
            None => 1,
        }
    }

    /// Record one frame of an uploaded scene into `views` (cleared first): one render pass
    /// drawing every chunk or, with the prepass, a compute pass and a render pass per slice.
    /// `stats` gets one pipeline-statistics query per render pass ([`Self::render_passes`]);
    /// `timestamps` gets index 0 at the frame's start and 1 at its end.
    #[allow(clippy::too_many_arguments)]
    fn record_frame(
        &self,
        drawer: &dyn Drawer,
        buffers: &SceneBuffers,
        req: &FrameRequest,
        views: &TargetViews,
        encoder: &mut wgpu::CommandEncoder,
        stats: Option<&wgpu::QuerySet>,
        timestamps: Option<&wgpu::QuerySet>,
    ) {
        let variant = req.variant();
        let stamp = |begin: bool, end: bool| {
            timestamps.map(|set| wgpu::RenderPassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: begin.then_some(0),
                end_of_pass_write_index: end.then_some(1),
            })
        };
        let Some(pipelines) = Self::prepass_for(drawer, req) else {
            let mut pass = views.begin_pass(encoder, req.background, true, stamp(true, true));
            if let Some(set) = stats {
                pass.begin_pipeline_statistics_query(set, 0);
            }
            for c in buffers.chunks.iter().filter(|c| c.count > 0) {
                pass.set_bind_group(0, &c.bind_group, &[]);
                drawer.draw(&mut pass, variant, req.proxy, c.base..c.base + c.count);
            }
            if stats.is_some() {
                pass.end_pipeline_statistics_query();
            }
            return;
        };
        let prepass = self.prepass_buffers(buffers);
        let splats = req.splat_pixels() > 0;
        prepass.write_uniforms(&self.ctx.queue, req.splat_pixels());
        if prepass.slices.is_empty() {
            views.begin_pass(encoder, req.background, true, stamp(true, true));
            return;
        }
        let last = prepass.slices.len() - 1;
        for (k, slice) in prepass.slices.iter().enumerate() {
            let chunk = &buffers.chunks[slice.chunk].bind_group;
            let compute_stamp =
                timestamps
                    .filter(|_| k == 0)
                    .map(|set| wgpu::ComputePassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: None,
                    });
            prepass.record_compute(
                encoder,
                &pipelines,
                chunk,
                k,
                views.size,
                splats,
                compute_stamp,
            );
            let mut pass =
                views.begin_pass(encoder, req.background, k == 0, stamp(false, k == last));
            if let Some(set) = stats {
                pass.begin_pipeline_statistics_query(set, k as u32);
            }
            pass.set_bind_group(0, chunk, &[]);
            prepass.draw(&mut pass, &pipelines, splats);
            if stats.is_some() {
                pass.end_pipeline_statistics_query();
            }
        }
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
        let drawer = self.drawer(req.method, req.glyph)?;
        self.write_uniforms(buffers, camera, req);
        self.record_frame(
            drawer.as_ref(),
            buffers,
            req,
            views,
            encoder,
            None,
            timestamps,
        );
        Ok(())
    }

    fn render_into(
        &self,
        buffers: &SceneBuffers,
        camera: &Camera,
        req: &FrameRequest,
        targets: &Targets,
    ) -> Result<Frame, RenderError> {
        let ctx = &self.ctx;
        let device = &ctx.device;
        let drawer = self.drawer(req.method, req.glyph)?;
        self.write_uniforms(buffers, camera, req);
        // [vertex invocations, fragment invocations] (ordered by flag bit).
        // Per render pass: [vertex invocations, fragment invocations] (ordered by flag bit).
        let passes = self.render_passes(drawer.as_ref(), buffers, req);
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
        let mut readbacks = None;
        let mut counts = None;
        for f in 0..frames {
            let last = f + 1 == frames;
            let mut encoder = device.create_command_encoder(&Default::default());
            let frame_stats = stats.as_ref().filter(|_| f == 0).map(|s| &s.set);
            self.record_frame(
                drawer.as_ref(),
                buffers,
                req,
                &views,
                &mut encoder,
                frame_stats,
                None,
            );
            if let (Some(s), true) = (&stats, f == 0) {
                s.resolve(&mut encoder);
            }
            if last {
                readbacks = Some((
                    Readback::record(ctx, &mut encoder, &targets.color, 4),
                    Readback::record(ctx, &mut encoder, &targets.id, 4),
                    targets
                        .aux
                        .as_ref()
                        .map(|t| Readback::record(ctx, &mut encoder, t, 16)),
                ));
            }
            let start = Instant::now();
            ctx.queue.submit([encoder.finish()]);
            ctx.wait()?;
            frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
            if let (Some(s), true) = (&stats, f == 0) {
                counts = Some(s.read(ctx)?);
            }
        }
        let (color_rb, id_rb, aux_rb) = readbacks.expect("at least one frame");
        let color = color_rb.read(ctx)?;
        let ids: Vec<u32> = bytemuck::pod_collect_to_vec(&id_rb.read(ctx)?);
        let aux = match aux_rb {
            Some(rb) => Some(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&rb.read(ctx)?)),
            None => None,
        };
        Ok(Frame {
            width: targets.width,
            height: targets.height,
            color,
            ids,
            aux,
            frame_ms,
            fragments: counts
                .as_ref()
                .map(|c: &Vec<u64>| c.iter().skip(1).step_by(2).sum()),
            vertices: counts.as_ref().map(|c| c.iter().step_by(2).sum()),
        })
    }
}

/// A scene's instances and camera uniform on the GPU, bound for drawing.
pub struct SceneBuffers {
    origin: glam::DVec3,
    count: u32,
    camera_buffer: wgpu::Buffer,
    chunks: Vec<ChunkBuffers>,
    /// Made on the first frame drawn with the prepass.
    prepass: OnceLock<PrepassBuffers>,
}

/// One storage buffer of packed instances and its uniform, bound as group 0.
struct ChunkBuffers {
    base: u32,
    count: u32,
    _glyphs: wgpu::Buffer,
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl SceneBuffers {
    /// Number of glyph instances drawn.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Number of storage buffers the instances were split into.
    pub fn chunks(&self) -> usize {
        self.chunks.len()
    }
}

/// Views of a [`Targets`]' textures, as a render pass attaches them.
pub struct TargetViews {
    /// Width and height in pixels.
    size: (u32, u32),
    color: wgpu::TextureView,
    id: wgpu::TextureView,
    aux: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

impl TargetViews {
    pub fn new(t: &Targets) -> Self {
        let v = |t: &wgpu::Texture| t.create_view(&Default::default());
        Self {
            size: (t.width, t.height),
            color: v(&t.color),
            id: v(&t.id),
            aux: t.aux.as_ref().map(v),
            depth: v(&t.depth),
        }
    }

    /// A pass over the targets, cleared first when `clear` (else drawing over what is there).
    fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        background: [f64; 4],
        clear: bool,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        let load = |c| {
            if clear {
                wgpu::LoadOp::Clear(c)
            } else {
                wgpu::LoadOp::Load
            }
        };
        let attach = |c: wgpu::Color, view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: load(c),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let [r, g, b, a] = background;
        let mut attachments = vec![
            attach(wgpu::Color { r, g, b, a }, &self.color),
            attach(wgpu::Color::TRANSPARENT, &self.id),
        ];
        if let Some(aux) = &self.aux {
            attachments.push(attach(wgpu::Color::TRANSPARENT, aux));
        }
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("glyphs"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: if clear {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}
