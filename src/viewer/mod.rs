//! The interactive viewer: one for the desktop (`tensorglyph view`: eframe's native runner,
//! winit + egui on the renderer's wgpu) and the browser (web/: eframe's web runner on WebGPU).
//!
//! The 3D view draws into its own long-lived colour / id / depth targets with the same
//! [`GpuRenderer`](crate::render::GpuRenderer) as `render`, and only when something changed;
//! egui shows the colour target next to the side panel.
//!
//! Shared: the app (`app`: data, scene, panels, camera, picking, slices, underlay, figures),
//! and everything it calls. Per platform, and only this: the window's glue (`native::run` here,
//! the web crate's runner there), file access (paths read by a loader thread on the desktop;
//! bytes handed over by the page, read at once, in `loader`), where a figure goes and who hears
//! what the view shows (a [`Host`]), and waiting on the GPU (`pending`: at once on the desktop,
//! on the page's event loop in the browser).

pub mod app;
pub mod draft;
pub mod host;
pub mod loader;
#[cfg(not(target_arch = "wasm32"))]
mod native;
pub mod navigation;
pub mod panel;
pub mod pending;
pub mod picking;
pub mod screenshot;
pub mod state;
pub mod triad;
pub mod view3d;

use std::path::PathBuf;

use std::sync::Arc;

use crate::camera::Framing;
use crate::field::vtk::ReadOptions;
use crate::render::context::WANTED_FEATURES;
use crate::staging::Source;
pub use host::{Command, Host, Remote, Report};
#[cfg(not(target_arch = "wasm32"))]
pub use native::run;
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
    /// Commands from outside the window (the page's file input, `?url=`, `?figure=`).
    pub remote: Remote,
    /// Each opened source brings its kind of data's defaults (colours, background, the
    /// middle slice face-on for DTI): the page, which has no command line.
    pub adopt_defaults: bool,
    /// What to call the adapter when the back end gives no name (WebGPU hides it; the page
    /// has its vendor and architecture).
    pub adapter_label: Option<String>,
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

/// How eframe opens the device the viewer and egui share, on the desktop and in the browser:
/// timestamps and pipeline statistics where the adapter has them, and its full limits (the
/// largest storage buffers and textures it allows, which WebGPU otherwise caps low).
pub fn wgpu_configuration() -> eframe::egui_wgpu::WgpuConfiguration {
    let mut wgpu_options = eframe::egui_wgpu::WgpuConfiguration::default();
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut wgpu_options.wgpu_setup {
        create.device_descriptor = Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
            label: Some("tensorglyph viewer"),
            required_features: adapter.features() & WANTED_FEATURES,
            required_limits: adapter.limits(),
            ..Default::default()
        });
    }
    wgpu_options
}
