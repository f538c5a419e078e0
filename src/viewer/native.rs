//! The desktop's window: eframe's native runner (winit), and figures written to files.

use std::path::Path;
use std::sync::{Arc, Mutex};

use crate::viewer::screenshot::write_png;
use crate::viewer::{Host, Options, Outcome, ViewerError, app};

/// Figures go to the file the panel names, written whole or not at all.
struct Desktop;

impl Host for Desktop {
    fn save_figure(
        &self,
        image: &crate::viewer::screenshot::Image,
        path: &str,
    ) -> Result<String, String> {
        write_png(Path::new(path), image.width, image.height, &image.rgba)
            .map(|()| format!("saved {path} ({}x{})", image.width, image.height))
            .map_err(|e| format!("screenshot failed: {e:#}"))
    }
}

/// Open the window and run until it is closed.
pub fn run(opts: Options) -> Result<(), ViewerError> {
    let (w, h) = if opts.size.0 > 0 && opts.size.1 > 0 {
        opts.size
    } else {
        (1280, 800)
    };
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("tensorglyph")
            .with_inner_size([w as f32, h as f32])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: crate::viewer::wgpu_configuration(),
        ..Default::default()
    };
    let outcome = Arc::new(Mutex::new(Outcome::default()));
    let out = outcome.clone();
    eframe::run_native(
        "tensorglyph",
        native,
        Box::new(move |cc| {
            let app = app::ViewerApp::new(cc, opts, out, Box::new(Desktop))
                .map_err(|e| format!("{e:#}"))?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| ViewerError::Window(e.to_string()))?;
    let outcome = outcome.lock().unwrap_or_else(|e| e.into_inner()).clone();
    match outcome.error {
        Some(e) => Err(ViewerError::Scripted(e)),
        None => Ok(()),
    }
}
