//! Loading off the UI thread: read the file (or make the demo field), then eigendecompose, on a
//! worker thread, with progress the panel can show. A failure (including a panic in a reader)
//! comes back as an error message; the data on screen stays.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::thread::JoinHandle;

use indicatif::ProgressBar;

use crate::field::TensorField;
use crate::field::vtk::ReadOptions;
use crate::glyph::{GlyphSet, derive_glyphs};
use crate::load::{Source, field_spacing};

/// A loaded field and its glyphs.
pub struct Loaded {
    pub source: Source,
    pub field: Arc<TensorField>,
    pub set: Arc<GlyphSet>,
    /// What `--scale auto` fits glyphs to.
    pub spacing: f64,
    /// The box around the glyph centres `[x0, y0, z0, x1, y1, z1]` (the ROI control's default).
    pub bounds: [f64; 6],
}

impl Loaded {
    pub fn name(&self) -> String {
        source_name(&self.source)
    }
}

pub fn source_name(source: &Source) -> String {
    match source {
        Source::File(p) => p.display().to_string(),
        Source::Demo(d) => format!("demo {d}"),
    }
}

/// Reading and deriving, synchronously (the worker's job; tests call it directly).
pub fn load_now(
    source: &Source,
    opts: &ReadOptions,
    progress: Option<&ProgressBar>,
) -> Result<Loaded, String> {
    let field = source.load(opts).map_err(|e| e.to_string())?;
    if field.is_empty() {
        return Err(format!("{}: no tensors", source_name(source)));
    }
    if let Some(pb) = progress {
        pb.set_message("eigendecomposition");
        pb.set_length(field.len() as u64);
        pb.set_position(0);
    }
    let set = derive_glyphs(&field, progress);
    if set.glyphs.is_empty() {
        return Err(format!(
            "{}: no valid tensors ({} skipped)",
            source_name(source),
            field.len()
        ));
    }
    let spacing = field_spacing(&field);
    let bounds = crate::select::centre_bounds(&set);
    Ok(Loaded {
        source: source.clone(),
        field: Arc::new(field),
        set: Arc::new(set),
        spacing,
        bounds,
    })
}

/// A load under way.
pub struct Loading {
    pub source: Source,
    progress: ProgressBar,
    rx: Receiver<Result<Loaded, String>>,
    handle: Option<JoinHandle<()>>,
}

impl Loading {
    /// Start loading on a worker thread; `wake` is called when it is done (to repaint).
    pub fn start(source: Source, opts: ReadOptions, wake: impl Fn() + Send + 'static) -> Self {
        let progress = ProgressBar::hidden();
        progress.set_message("reading");
        let (tx, rx) = channel();
        let pb = progress.clone();
        let src = source.clone();
        let handle = std::thread::Builder::new()
            .name("tensorglyph-load".into())
            .spawn(move || {
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    load_now(&src, &opts, Some(&pb))
                }))
                .unwrap_or_else(|panic| {
                    let msg = panic
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| panic.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "unknown error".into());
                    Err(format!("{}: reading failed: {msg}", source_name(&src)))
                });
                let _ = tx.send(result);
                wake();
            })
            .expect("spawning the loader thread");
        Self {
            source,
            progress,
            rx,
            handle: Some(handle),
        }
    }

    /// (stage, done fraction if known).
    pub fn progress(&self) -> (String, Option<f32>) {
        let msg = self.progress.message();
        let frac = self
            .progress
            .length()
            .filter(|&n| n > 0)
            .map(|n| self.progress.position() as f32 / n as f32);
        (msg, frac)
    }

    /// The result, once there is one.
    pub fn poll(&mut self) -> Option<Result<Loaded, String>> {
        match self.rx.try_recv() {
            Ok(r) => {
                if let Some(h) = self.handle.take() {
                    let _ = h.join();
                }
                Some(r)
            }
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(format!(
                "{}: the loader stopped",
                source_name(&self.source)
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::Demo;

    #[test]
    fn loads_the_demo_off_thread_and_reports_bad_files() {
        let mut l = Loading::start(Source::Demo(Demo { n: 5 }), ReadOptions::default(), || {});
        let loaded = loop {
            if let Some(r) = l.poll() {
                break r.unwrap();
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        assert_eq!(loaded.set.glyphs.len(), 125);
        assert!(loaded.spacing > 0.0);

        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.vtk");
        std::fs::write(&bad, b"not a vtk file").unwrap();
        let mut l = Loading::start(Source::File(bad), ReadOptions::default(), || {});
        let err = loop {
            if let Some(r) = l.poll() {
                break r.err().expect("a bad file is an error");
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        assert!(err.contains("bad.vtk"), "{err}");
    }
}
