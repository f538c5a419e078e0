//! The 3D view's GPU side: long-lived colour / id / depth targets the size of the view, the
//! scene's buffers, and a frame drawn into them only when asked (the app asks only when
//! something changed). egui shows the colour target as a texture.

use std::sync::{Arc, Mutex};

use web_time::Instant;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::render::query::Queries;
use crate::render::targets::{COLOR_VIEW_SRGB, Targets};
use crate::render::{GpuRenderer, SceneBuffers, TargetViews};
use crate::request::{AuxTarget, FrameRequest};
use crate::scene::Scene;

/// How long the last frame took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameTime {
    pub ms: f64,
    /// Measured with GPU timestamps (else wall clock, submit to completion).
    pub gpu_timestamps: bool,
}

#[derive(Default)]
pub struct View3d {
    pub targets: Option<Targets>,
    views: Option<TargetViews>,
    pub texture: Option<egui::TextureId>,
    buffers: Option<SceneBuffers>,
    timer: Option<GpuTimer>,
    last_frame: Option<FrameTime>,
    /// The time of a frame the browser's queue finished (set from its callback), with the
    /// scene it drew (`scenes` then).
    done: Arc<Mutex<Option<(u64, f64)>>>,
    /// Scenes set so far: a frame time is shown for the scene it drew, never the last one's.
    scenes: u64,
    /// The targets' aux target and the texture's filter, as last made.
    made: (AuxTarget, bool),
}

impl View3d {
    pub fn set_scene(&mut self, gpu: &GpuRenderer, scene: &Scene) -> Result<(), RenderError> {
        self.buffers = None;
        self.scenes += 1;
        self.last_frame = None;
        self.buffers = Some(gpu.upload(scene)?);
        Ok(())
    }

    pub fn size(&self) -> Option<(u32, u32)> {
        self.targets.as_ref().map(|t| (t.width, t.height))
    }

    /// Make the targets `size` (if they are not), with the aux target `aux` (deferred
    /// shading's normals), and show them as an egui texture, filtered linearly if `smooth`: a
    /// texture of 2×2 samples per pixel is then shown box filtered.
    pub fn resize(
        &mut self,
        gpu: &GpuRenderer,
        egui_renderer: &mut eframe::egui_wgpu::Renderer,
        (width, height): (u32, u32),
        aux: AuxTarget,
        smooth: bool,
    ) -> Result<(), RenderError> {
        if self.size() == Some((width, height)) && self.made == (aux, smooth) {
            return Ok(());
        }
        let targets = Targets::new(&gpu.ctx, width, height, aux)?;
        let filter = if smooth {
            wgpu::FilterMode::Linear
        } else {
            wgpu::FilterMode::Nearest
        };
        let view = targets.color.create_view(&wgpu::TextureViewDescriptor {
            format: Some(COLOR_VIEW_SRGB),
            ..Default::default()
        });
        let device = &gpu.ctx.device;
        match self.texture {
            Some(id) => {
                egui_renderer.update_egui_texture_from_wgpu_texture(device, &view, filter, id)
            }
            None => {
                self.texture = Some(egui_renderer.register_native_texture(device, &view, filter))
            }
        }
        self.made = (aux, smooth);
        self.views = Some(TargetViews::new(&targets));
        self.targets = Some(targets);
        Ok(())
    }

    /// Draw a frame into the targets and wait for it (lavapipe draws on the CPU anyway). In the
    /// browser nothing waits: the queue reports the frame's time when it is done, and
    /// [`Self::frame_time`] has it from then on.
    pub fn draw(
        &mut self,
        gpu: &GpuRenderer,
        camera: &Camera,
        req: &FrameRequest,
    ) -> Result<(), RenderError> {
        let (Some(views), Some(buffers)) = (&self.views, &self.buffers) else {
            return Ok(());
        };
        let ctx = &gpu.ctx;
        // GPU timestamps are read back, which only the desktop can wait for.
        if ctx.timestamps && self.timer.is_none() && cfg!(not(target_arch = "wasm32")) {
            self.timer = Some(GpuTimer::new(&ctx.device));
        }
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        let writes = self.timer.as_ref().map(|t| &t.0.set);
        let encoded = gpu.encode(buffers, camera, req, views, &mut encoder, writes);
        if let Some(t) = &self.timer {
            t.resolve(&mut encoder);
        }
        let start = Instant::now();
        ctx.queue.submit([encoder.finish()]);
        #[cfg(target_arch = "wasm32")]
        {
            let (done, scene) = (self.done.clone(), self.scenes);
            ctx.queue.on_submitted_work_done(move || {
                let ms = start.elapsed().as_secs_f64() * 1e3;
                *done.lock().unwrap_or_else(|e| e.into_inner()) = Some((scene, ms));
            });
            if let Some(e) = ctx.scope_error(scope, "drawing the view") {
                return Err(RenderError::Gpu(e));
            }
            encoded
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            ctx.wait()?;
            let wall = start.elapsed().as_secs_f64() * 1e3;
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(RenderError::Gpu(e.to_string()));
            }
            encoded?;
            let gpu_ms = match &self.timer {
                Some(t) => t.read_ms(gpu).ok(),
                None => None,
            };
            self.last_frame = Some(match gpu_ms {
                Some(ms) => FrameTime {
                    ms,
                    gpu_timestamps: true,
                },
                None => FrameTime {
                    ms: wall,
                    gpu_timestamps: false,
                },
            });
            Ok(())
        }
    }

    /// How long the last finished frame took (wall clock from submission to completion, or GPU
    /// timestamps where the desktop has them).
    pub fn frame_time(&mut self) -> Option<FrameTime> {
        let done = self.done.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some((_, ms)) = done.filter(|(scene, _)| *scene == self.scenes) {
            self.last_frame = Some(FrameTime {
                ms,
                gpu_timestamps: false,
            });
        }
        self.last_frame
    }
}

/// Begin/end timestamps of the frame's passes.
struct GpuTimer(Queries);

impl GpuTimer {
    fn new(device: &wgpu::Device) -> Self {
        Self(Queries::new(
            device,
            "frame time",
            wgpu::QueryType::Timestamp,
            2,
        ))
    }

    fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        self.0.resolve(encoder);
    }

    /// Milliseconds between the two timestamps (after the submission completed).
    #[cfg(not(target_arch = "wasm32"))]
    fn read_ms(&self, gpu: &GpuRenderer) -> Result<f64, RenderError> {
        let t = self.0.read(&gpu.ctx)?;
        let period = f64::from(gpu.ctx.queue.get_timestamp_period());
        Ok(t[1].saturating_sub(t[0]) as f64 * period / 1e6)
    }
}
