//! Figures: the panel's "Save figure" (the view's camera) and `?figure=` (the framing `render`
//! gives by default), rendered through `render`'s path and handed to the host.

use super::ViewerApp;
use crate::camera::Camera;
use crate::error::RenderError;
use crate::glyph::style::ResolvedStyle;
use crate::request::FrameRequest;
use crate::viewer::pending::Pending;
use crate::viewer::screenshot::{Figure, Image, parse_size, render_figure};

/// A figure being rendered, and the name it is kept as.
pub(super) struct FigureJob {
    name: String,
    result: Pending<Result<Image, RenderError>>,
}

impl ViewerApp {
    /// The 3D view as a figure, through `render`'s own path, kept by the host (a file on the
    /// desktop, an image in the page).
    pub(super) fn screenshot(&mut self, ctx: &egui::Context) {
        let (Some(built), Some(nav)) = (&self.built, &self.nav) else {
            self.status = Some("nothing to save yet".into());
            return;
        };
        let size = if self.panel.screenshot_window_size {
            // The whole frame's targets (a draft on screen is coarser).
            let n = self.settings.ssaa.max(1);
            self.view
                .size()
                .map(|_| (self.pixels.0 * n, self.pixels.1 * n))
        } else {
            parse_size(&self.panel.screenshot_size)
        };
        let Some(size) = size else {
            self.status = Some(format!(
                "screenshot size '{}' is not WxH",
                self.panel.screenshot_size
            ));
            return;
        };
        let ssaa = self.panel.figure_ssaa.clamp(1, 4);
        let camera = nav.camera(size.0, size.1);
        let mut req = self.settings.request(ssaa);
        if self.panel.figure_transparent {
            req.background[3] = 0.0;
        }
        let legend = self
            .panel
            .figure_legend
            .then(|| (built.style.clone(), built.clamped, self.anatomical()));
        let name = self.panel.screenshot_path.trim().to_string();
        self.start_figure(ctx, camera, req, size, ssaa, legend, name);
    }

    /// A figure as `render` makes one by default: its framing, its request (early depth where
    /// it holds), one sample per pixel, no legend.
    pub(super) fn render_figure(&mut self, ctx: &egui::Context, size: (u32, u32), name: String) {
        let Some(built) = &self.built else { return };
        let (framing, centre, half) = built.render_framing;
        let camera = Camera::frame_box(&framing, centre, half, size.0, size.1);
        let req = self
            .gpu
            .with_early_depth(self.settings.request(1), &built.scene, &camera);
        self.start_figure(ctx, camera, req, size, 1, None, name);
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn start_figure(
        &mut self,
        ctx: &egui::Context,
        camera: Camera,
        req: FrameRequest,
        size: (u32, u32),
        ssaa: u32,
        legend: Option<(ResolvedStyle, usize, bool)>,
        name: String,
    ) {
        let Some(built) = &self.built else { return };
        let (gpu, scene) = (self.gpu.clone(), built.scene.clone());
        let work = async move {
            let figure = Figure {
                size,
                ssaa,
                legend: legend.as_ref().map(|(s, c, a)| (s, *c, *a)),
            };
            render_figure(&gpu, &scene, &camera, &req, &figure).await
        };
        self.status = Some(format!("rendering a {}x{} figure…", size.0, size.1));
        self.figure_job = Some(FigureJob {
            name,
            result: Pending::spawn(work, ctx),
        });
    }

    /// Hand a finished figure to the host.
    pub(super) fn poll_figure(&mut self) {
        let Some(job) = &self.figure_job else { return };
        let Some(result) = job.result.take() else {
            return;
        };
        let job = self.figure_job.take().expect("checked above");
        let saved = result
            .map_err(|e| format!("screenshot failed: {e:#}"))
            .and_then(|image| self.host.save_figure(&image, &job.name));
        match saved {
            Ok(done) => self.status = Some(done),
            // The panel's status shows it, and the error line the page mirrors.
            Err(e) => {
                self.status = Some(e.clone());
                self.error = Some(e);
            }
        }
    }
}
