//! What the view shows, told to the host (the page's status, pick and error elements).

use super::ViewerApp;
use crate::viewer::Report;
use crate::viewer::picking::PickInfo;

impl ViewerApp {
    /// Tell the host what the view shows, when that changed.
    pub(super) fn report(&mut self, ctx: &egui::Context) {
        let frame = self.view.frame_time();
        let shown =
            matches!((&self.built, self.drawn_generation), (Some(b), Some(g)) if g == b.generation);
        if let (true, Some(_), Some(data)) = (shown, frame, &mut self.data) {
            let t = &mut data.timings;
            t.first_frame_ms
                .get_or_insert_with(|| crate::staging::ms(t.started));
        }
        let status = match (&self.data, &self.built, self.drawn_generation) {
            (Some(data), Some(built), Some(g)) if g == built.generation => {
                if frame.is_none() {
                    // The browser reports the frame's time a little later.
                    ctx.request_repaint_after(std::time::Duration::from_millis(10));
                }
                frame.map(|f| {
                    let (shown, total) = (built.selected.len(), data.total);
                    let glyphs = if shown == total {
                        format!("{total} glyphs")
                    } else {
                        format!("{shown} of {total} glyphs")
                    };
                    let t = &data.timings;
                    format!(
                        "{glyphs} · {:.1} ms/frame · {}: {} · opened in {:.2} s (read {:.2} s, eigen {:.2} s)",
                        f.ms,
                        backend_name(&self.gpu.ctx.backend),
                        self.adapter_name(),
                        t.first_frame_ms.unwrap_or(0.0) / 1e3,
                        t.read_ms / 1e3,
                        t.eigen_ms / 1e3,
                    )
                })
            }
            _ => None,
        };
        let report = Report {
            status,
            pick: self.picked.as_ref().map(PickInfo::text),
            error: self.error.clone(),
            loading: self.loading.is_some() || self.figure_job.is_some(),
        };
        if report != self.reported {
            self.host.report(&report);
            self.reported = report;
        }
    }
}

/// How a back end is called where people read it.
fn backend_name(backend: &str) -> &str {
    match backend {
        "browserwebgpu" => "WebGPU",
        "vulkan" => "Vulkan",
        "metal" => "Metal",
        "dx12" => "DirectX 12",
        "gl" => "OpenGL",
        other => other,
    }
}
