//! tensorglyph's viewer in the browser: the wasm entry point (glue only).
//!
//! The viewer is the library's (`tensorglyph::viewer`), the same app as `tensorglyph view`;
//! this crate starts it with eframe's web runner on the page's canvas, hands it what the page
//! opens (files from the file input or a drop, `?url=` fetched by the page, `?demo=`), asks for
//! `?figure=`, and mirrors what the view shows into the page's elements (`#status`, `#pick`,
//! `#error`, `<img id="figure">`). `web/index.html` is the page; `web/build.sh` builds both.
//!
//! On other targets the crate is empty, so the workspace's native builds pass over it.

#![cfg(target_arch = "wasm32")]

mod page;

use std::cell::RefCell;
use std::sync::{Arc, Mutex};

use tensorglyph::staging::{Demo, Source};
use tensorglyph::viewer::{self, Command, Host, Remote, Report, screenshot::Image};
use wasm_bindgen::prelude::*;

/// The running viewer, as the page holds it.
#[wasm_bindgen]
pub struct WebHandle {
    runner: eframe::WebRunner,
    remote: Remote,
    /// Files handed over by [`Self::add_file`], opened together by [`Self::open_files`].
    files: RefCell<Vec<(String, Vec<u8>)>>,
}

#[wasm_bindgen]
impl WebHandle {
    /// A viewer not yet started (installs the panic handler that logs to the console).
    #[wasm_bindgen(constructor)]
    #[allow(clippy::new_without_default)]
    pub fn new() -> Self {
        let _ = eframe::WebLogger::init(log::LevelFilter::Warn);
        Self {
            runner: eframe::WebRunner::new(),
            remote: Remote::default(),
            files: RefCell::default(),
        }
    }

    /// Start the viewer on `canvas`. An error (no WebGPU adapter, a device that cannot be
    /// opened) is the page's to show.
    /// `adapter` names the adapter (WebGPU gives wgpu no name: the page has its vendor and
    /// architecture).
    pub async fn start(
        &self,
        canvas: web_sys::HtmlCanvasElement,
        adapter: String,
    ) -> Result<(), JsValue> {
        let options = eframe::WebOptions {
            wgpu_options: viewer::wgpu_configuration(),
            ..Default::default()
        };
        let remote = self.remote.clone();
        self.runner
            .start(
                canvas,
                options,
                Box::new(move |cc| {
                    let opts = viewer::Options {
                        remote,
                        adopt_defaults: true,
                        adapter_label: Some(adapter),
                        ..Default::default()
                    };
                    let outcome = Arc::new(Mutex::new(viewer::Outcome::default()));
                    let app = viewer::app::ViewerApp::new(cc, opts, outcome, Box::new(Page))
                        .map_err(|e| e.to_string())?;
                    Ok(Box::new(app))
                }),
            )
            .await
    }

    /// Open a built-in field: `grid40` or `grid:N`. A bad name is the error line `?demo=` shows.
    pub fn open_demo(&self, name: &str) -> Result<(), JsValue> {
        let demo: Demo = name.parse().map_err(|e: String| JsValue::from_str(&e))?;
        self.remote.push(Command::Open(Source::Demo(demo)));
        Ok(())
    }

    /// Hand over a file the visitor opened (the file input, a drop, `?url=`): its name and its
    /// bytes, which never leave the page.
    pub fn add_file(&self, name: String, bytes: Vec<u8>) {
        self.files.borrow_mut().push((name, bytes));
    }

    /// Open the files handed over since the last call, together: a `.nhdr` with its data file,
    /// the six files of an FSL eigen set, a NIfTI file with its BEP016 sidecar. A file that
    /// does not read gets its error line in `#error`; what is shown stays.
    pub fn open_files(&self) -> Result<(), JsValue> {
        self.remote.push(Command::OpenFiles(self.take_files()?));
        Ok(())
    }

    /// Lay the scalar volume in the files handed over since the last call under the slices
    /// (`tensorglyph view --underlay FILE`), for what is shown and what is opened next.
    pub fn open_underlay(&self) -> Result<(), JsValue> {
        self.remote.push(Command::Underlay(self.take_files()?));
        Ok(())
    }

    /// Render a figure of `size` (`WxH`) as `tensorglyph render --size WxH` frames one by
    /// default, once the data shows, and put it into `<img id="figure">`.
    pub fn figure(&self, size: &str) -> Result<(), JsValue> {
        let size = tensorglyph::frame::parse_size(size)
            .map_err(|e| JsValue::from_str(&format!("figure: {e}")))?;
        self.remote.push(Command::Figure {
            size,
            name: "tensorglyph.png".into(),
        });
        Ok(())
    }

    /// Draw with the figure effects named (`outlines,shadows,ao`, each at its defaults), in
    /// the view and in figures, as the panel's figure section sets them.
    pub fn effects(&self, names: &str) -> Result<(), JsValue> {
        let effects = tensorglyph::effects::Effects::from_names(names)
            .map_err(|e| JsValue::from_str(&format!("effects: {e}")))?;
        self.remote.push(Command::Effects(effects));
        Ok(())
    }

    /// The panic message, if the viewer stopped on one.
    pub fn panic_message(&self) -> Option<String> {
        self.runner.panic_summary().map(|p| p.message())
    }
}

impl WebHandle {
    /// The files handed over since the last call.
    fn take_files(&self) -> Result<Vec<(String, Vec<u8>)>, JsValue> {
        let files = std::mem::take(&mut *self.files.borrow_mut());
        if files.is_empty() {
            return Err(JsValue::from_str("no file to open"));
        }
        Ok(files)
    }
}

/// The page: figures become an image to download, the view's report its elements' text.
struct Page;

impl Host for Page {
    fn save_figure(&self, image: &Image, path: &str) -> Result<String, String> {
        let png = image.png().map_err(|e| format!("screenshot failed: {e}"))?;
        let name = std::path::Path::new(path)
            .file_name()
            .map_or("tensorglyph.png".into(), |n| {
                n.to_string_lossy().into_owned()
            });
        page::show_figure(&png, &name).map_err(|e| format!("screenshot failed: {e}"))?;
        Ok(format!(
            "figure {}x{} below the view ({name})",
            image.width, image.height
        ))
    }

    fn report(&self, report: &Report) {
        page::set_text("status", report.status.as_deref().unwrap_or(""));
        page::set_text("pick", report.pick.as_deref().unwrap_or(""));
        page::set_text("error", report.error.as_deref().unwrap_or(""));
        page::set_busy(report.loading);
    }
}
