//! Embed tensorglyph's renderer in an egui/eframe app of your own: a window with an azimuth
//! slider and the demo field in a 3D view, drawn by the same renderer as
//! `tensorglyph render` into a texture egui shows. `--frames N` closes the window after N
//! frames (for a scripted check under Xvfb).
//!
//! ```sh
//! cargo run --example egui_embed
//! ```

use tensorglyph::viewer::view3d::View3d;
use tensorglyph::{
    Camera, Demo, FrameRequest, Framing, GpuContext, GpuRenderer, Method, Preset, Recipe, Silent,
    Source, Staged, stage,
};

struct App {
    gpu: GpuRenderer,
    render_state: eframe::egui_wgpu::RenderState,
    view: View3d,
    staged: Staged,
    azimuth: f64,
    frames_left: Option<u32>,
}

impl App {
    fn new(cc: &eframe::CreationContext<'_>, frames: Option<u32>) -> Result<Self, String> {
        // Share eframe's device: the renderer draws into textures egui can show.
        let rs = cc.wgpu_render_state.clone().ok_or("eframe without wgpu")?;
        let ctx = GpuContext::from_device(&rs.adapter, rs.device.clone(), rs.queue.clone());
        let gpu = GpuRenderer::new(ctx).map_err(|e| e.to_string())?;
        let staged = stage(&Source::Demo(Demo { n: 10 }), &Recipe::default(), &Silent)
            .map_err(|e| e.to_string())?;
        let mut view = View3d::default();
        view.set_scene(&gpu, &staged.scene)
            .map_err(|e| e.to_string())?;
        Ok(Self {
            gpu,
            render_state: rs,
            view,
            staged,
            azimuth: 0.0,
            frames_left: frames,
        })
    }
}

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        egui::Panel::top("controls").show(ui, |ui| {
            ui.add(egui::Slider::new(&mut self.azimuth, -180.0..=180.0).text("azimuth"));
        });
        egui::CentralPanel::default().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let ppp = ctx.pixels_per_point();
            let (w, h) = (
                ((rect.width() * ppp) as u32).max(1),
                ((rect.height() * ppp) as u32).max(1),
            );
            let req = FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT);
            let mut renderer = self.render_state.renderer.write();
            if self
                .view
                .resize(&self.gpu, &mut renderer, (w, h), req.aux_target(), false)
                .is_err()
            {
                return;
            }
            drop(renderer);
            let framing = Framing {
                azimuth: self.azimuth,
                ..Framing::default()
            };
            let s = &self.staged;
            let camera = Camera::frame(&framing, s.frame_centre, s.frame_radius, w, h);
            if self.view.draw(&self.gpu, &camera, &req).is_ok()
                && let Some(tex) = self.view.texture
            {
                let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
                ui.painter().image(tex, rect, uv, egui::Color32::WHITE);
            }
        });
        if let Some(n) = &mut self.frames_left {
            *n = n.saturating_sub(1);
            if *n == 0 {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            ctx.request_repaint();
        }
    }
}

fn main() -> eframe::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let frames = args
        .iter()
        .position(|a| a == "--frames")
        .and_then(|i| args.get(i + 1)?.parse().ok());
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default().with_inner_size([800.0, 600.0]),
        ..Default::default()
    };
    eframe::run_native(
        "tensorglyph in egui",
        options,
        Box::new(move |cc| Ok(Box::new(App::new(cc, frames)?))),
    )
}
