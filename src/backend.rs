//! The back end a frame is rendered with: the GPU renderer, or the exact f64 reference (asked
//! for, or the fallback when no GPU adapter exists). One choice for `render`, `demo`, the bench
//! and the examples.

use web_time::Instant;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::Frame;
use crate::progress::Progress;
use crate::reference::ReferenceScene;
use crate::render::{GpuContext, GpuRenderer};
use crate::request::{FrameRequest, Method, MethodConfig};
use crate::scene::Scene;
use crate::staging::{Timings, ms};

/// What renders the frames.
pub enum Backend {
    Gpu(Box<GpuRenderer>),
    Reference,
}

/// Why a GPU stage failed, with what ran before it.
#[derive(Debug, thiserror::Error)]
#[error("stopped at {stage} {ran}: {error}")]
pub struct StageFailed {
    pub stage: &'static str,
    /// The stages that ran before, with their times ([`Timings::describe`]).
    pub ran: String,
    pub error: RenderError,
}

impl Backend {
    /// The back end for `method`: the reference for [`Method::Reference`], else the GPU, or the
    /// reference when there is no adapter (the `bool` says a fallback happened).
    pub fn for_method(method: Method) -> Result<(Self, bool), RenderError> {
        if !method.is_gpu() {
            return Ok((Backend::Reference, false));
        }
        match GpuContext::new() {
            Ok(ctx) => Ok((Backend::Gpu(Box::new(GpuRenderer::new(ctx)?)), false)),
            Err(RenderError::NoAdapter) => Ok((Backend::Reference, true)),
            Err(e) => Err(e),
        }
    }

    /// The GPU renderer, if this is one.
    pub fn gpu(&self) -> Option<&GpuRenderer> {
        match self {
            Backend::Gpu(g) => Some(g),
            Backend::Reference => None,
        }
    }

    /// `req` as this back end draws it: the reference draws the exact glyphs whatever method
    /// was asked; the GPU declares conservative depth where it holds for `scene`.
    pub fn adapt(&self, req: FrameRequest, scene: &Scene, camera: &Camera) -> FrameRequest {
        match self {
            Backend::Gpu(gpu) => gpu.with_early_depth(req, scene, camera),
            Backend::Reference => FrameRequest {
                method: MethodConfig::Reference,
                ..req
            },
        }
    }

    /// Draw `req.frames` frames of `scene`, timing the upload and the first frame on their own
    /// (`timings`); the frame times of the result are those of the other frames if there are
    /// any, else the first frame's.
    pub fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        req: &FrameRequest,
        timings: &mut Timings,
        progress: &dyn Progress,
    ) -> Result<Frame, StageFailed> {
        crate::frame::check_size(camera.width, camera.height).map_err(|error| StageFailed {
            stage: "first frame",
            ran: timings.describe(),
            error,
        })?;
        match self {
            Backend::Gpu(gpu) => render_gpu(gpu, scene, camera, req, timings, progress),
            Backend::Reference => Ok(render_reference(scene, camera, req, timings, progress)),
        }
    }
}

/// Upload `scene` to `gpu`, timing it (`timings.upload`) and its peak memory, as the upload
/// stage of [`Backend::render`] (and of tiled images, which upload once for all tiles).
pub(crate) fn upload_timed(
    gpu: &GpuRenderer,
    scene: &Scene,
    timings: &mut Timings,
    progress: &dyn Progress,
) -> Result<crate::render::SceneBuffers, RenderError> {
    progress.begin(
        &format!("uploading {} instances", scene.instances.len()),
        None,
    );
    let t = Instant::now();
    let uploaded = gpu.upload(scene);
    timings.upload = ms(t);
    timings.peak_rss_after[3] = crate::mem::peak_rss_bytes();
    uploaded
}

/// Upload `scene` and draw `req.frames` frames on `gpu`, timed as [`Backend::render`] says.
pub fn render_gpu(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    timings: &mut Timings,
    progress: &dyn Progress,
) -> Result<Frame, StageFailed> {
    let failed = |stage, timings: &Timings, error| StageFailed {
        stage,
        ran: timings.describe(),
        error,
    };
    let buffers =
        upload_timed(gpu, scene, timings, progress).map_err(|e| failed("upload", timings, e))?;
    progress.begin("first frame", None);
    let first_req = FrameRequest { frames: 1, ..*req };
    let t = Instant::now();
    let first = gpu.render_uploaded(&buffers, camera, &first_req);
    timings.first_frame = ms(t);
    timings.peak_rss_after[4] = crate::mem::peak_rss_bytes();
    let mut frame = first.map_err(|e| failed("first frame", timings, e))?;
    if req.frames > 1 {
        progress.begin(&format!("{} more frames", req.frames - 1), None);
        let rest = FrameRequest {
            frames: req.frames - 1,
            ..*req
        };
        frame = gpu
            .render_uploaded(&buffers, camera, &rest)
            .map_err(|e| failed("frames", timings, e))?;
    }
    progress.end();
    Ok(frame)
}

/// The exact CPU reference, timed like [`render_gpu`] (no upload).
fn render_reference(
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    timings: &mut Timings,
    progress: &dyn Progress,
) -> Frame {
    progress.begin("reference frame", None);
    let t = Instant::now();
    let rs = ReferenceScene::new(scene, camera);
    let mut frame = rs.render(req);
    timings.upload = 0.0;
    timings.first_frame = ms(t);
    timings.peak_rss_after[3] = timings.peak_rss_after[2];
    timings.peak_rss_after[4] = crate::mem::peak_rss_bytes();
    if req.frames > 1 {
        frame.frame_ms.clear();
        for _ in 1..req.frames {
            frame.frame_ms.extend(rs.render(req).frame_ms);
        }
    }
    progress.end();
    frame
}
