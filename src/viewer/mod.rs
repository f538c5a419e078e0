//! `tensorglyph view`: an interactive window (eframe: winit + egui on the renderer's wgpu).
//!
//! The 3D view draws into its own long-lived colour / id / depth targets with the same
//! [`GpuRenderer`](crate::render::GpuRenderer) as `render`, and only when something changed;
//! egui shows the colour target next to the side panel. Loading runs on a worker thread.

pub mod app;
pub mod loader;
pub mod navigation;
pub mod panel;
pub mod picking;
pub mod screenshot;
pub mod state;
pub mod triad;
pub mod view3d;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use crate::camera::Framing;
use crate::field::vtk::ReadOptions;
use crate::render::context::WANTED_FEATURES;
use crate::staging::Source;
use state::Settings;

/// How the viewer starts.
#[derive(Debug, Clone, Default)]
pub struct Options {
    pub source: Option<Source>,
    pub read: ReadOptions,
    pub settings: Settings,
    /// The camera options of the first view (`view --view`, `--zoom`, `--ortho`, …).
    pub framing: Framing,
    /// When the first scene shows one slice, see it face-on and close (DTI data).
    pub face_slice: bool,
    /// The first data opens on its middle axial slice (DTI data with no `--slice`).
    pub middle_slice: bool,
    /// Window size in points.
    pub size: (u32, u32),
    /// Scripted mode: render `frames` frames, write a screenshot of the whole window, exit.
    pub screenshot: Option<PathBuf>,
    pub frames: u32,
}

/// How a run ended (scripted mode reports its error here).
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    pub error: Option<String>,
}

/// Why the viewer stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    #[error("cannot open the viewer window: {0}")]
    Window(String),
    /// A scripted run that failed (loading, or writing the screenshot).
    #[error("{0}")]
    Scripted(String),
    #[error(transparent)]
    Render(#[from] crate::error::RenderError),
}

/// Open the window and run until it is closed.
pub fn run(opts: Options) -> Result<(), ViewerError> {
    let (w, h) = if opts.size.0 > 0 && opts.size.1 > 0 {
        opts.size
    } else {
        (1280, 800)
    };
    let mut wgpu_options = eframe::egui_wgpu::WgpuConfiguration::default();
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut wgpu_options.wgpu_setup {
        // Timestamps and pipeline statistics where the adapter has them, and its full limits.
        create.device_descriptor = Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
            label: Some("tensorglyph viewer"),
            required_features: adapter.features() & WANTED_FEATURES,
            required_limits: adapter.limits(),
            ..Default::default()
        });
    }
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("tensorglyph")
            .with_inner_size([w as f32, h as f32])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options,
        ..Default::default()
    };
    let outcome = Arc::new(Mutex::new(Outcome::default()));
    let out = outcome.clone();
    eframe::run_native(
        "tensorglyph",
        native,
        Box::new(move |cc| {
            let app = app::ViewerApp::new(cc, opts, out).map_err(|e| format!("{e:#}"))?;
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
