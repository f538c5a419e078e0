//! What the viewer asks of the platform it runs on, and what the platform asks of it: a
//! [`Host`] keeps figures and hears what the view shows; a [`Remote`] carries commands from
//! outside the window (the page's file input, drops on the page, `?url=` and `?figure=`).

use std::sync::{Arc, Mutex};

use crate::staging::Source;
use crate::viewer::screenshot::Image;

/// Where a figure goes and who hears what the view shows.
pub trait Host {
    /// Keep a rendered figure the panel named `path`: the desktop writes the PNG there (whole
    /// or not at all), the page shows it as an image to download. The text says what was done,
    /// for the panel; an error is one line.
    fn save_figure(&self, image: &Image, path: &str) -> Result<String, String>;

    /// What the view shows, each time it changes (the page mirrors it into its elements, where
    /// people and tests read it).
    fn report(&self, _report: &Report) {}
}

/// What the view shows, as text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// After the first frame of loaded data: `64000 glyphs · 12.3 ms/frame · WebGPU: <adapter> ·
    /// opened in 0.41 s (read 0.02 s, eigen 0.03 s)` (`60 of 600 glyphs` when the selection keeps
    /// fewer than the data has; opened: from reading to this first status).
    pub status: Option<String>,
    /// The glyph under the pointer, as the tooltip shows it.
    pub pick: Option<String>,
    /// The last error line (a file that did not read, a GPU error).
    pub error: Option<String>,
    /// Something is loading.
    pub loading: bool,
}

/// A command from outside the window.
#[derive(Debug, Clone)]
pub enum Command {
    /// Open this data (replacing what is shown once it has read).
    Open(Source),
    /// Open files handed over as bytes (the page's file input, a drop, `?url=`), by name: the
    /// one that names the others is read ([`crate::viewer::loader::main_file`]), and the others
    /// are what it names (a `.nhdr`'s data file, an eigen set's members, a sidecar).
    OpenFiles(Vec<(String, Vec<u8>)>),
    /// Lay a scalar volume under the slices, as `view --underlay FILE` does, its files handed
    /// over as for [`Command::OpenFiles`] (the page's underlay input).
    Underlay(Vec<(String, Vec<u8>)>),
    /// Render a figure of this many pixels as `render` frames one by default, and keep it
    /// (through [`Host::save_figure`]) as `name`.
    Figure { size: (u32, u32), name: String },
    /// Draw with these figure effects (the panel's; the page's `?effects=`).
    Effects(crate::effects::Effects),
}

/// Commands queued for the app, which takes them at its next frame (woken by the push).
#[derive(Clone, Default)]
pub struct Remote {
    queue: Arc<Mutex<Vec<Command>>>,
    wake: Arc<Mutex<Option<egui::Context>>>,
}

impl std::fmt::Debug for Remote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Remote").finish_non_exhaustive()
    }
}

impl Remote {
    pub fn push(&self, command: Command) {
        self.queue
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(command);
        if let Some(ctx) = &*self.wake.lock().unwrap_or_else(|e| e.into_inner()) {
            ctx.request_repaint();
        }
    }

    /// The app's side: who to wake, then the commands in the order they came.
    pub(crate) fn attach(&self, ctx: &egui::Context) {
        *self.wake.lock().unwrap_or_else(|e| e.into_inner()) = Some(ctx.clone());
    }

    pub(crate) fn take(&self) -> Vec<Command> {
        std::mem::take(&mut *self.queue.lock().unwrap_or_else(|e| e.into_inner()))
    }
}
