//! Loading off the UI thread: read the file (or make the demo field), then eigendecompose, on a
//! worker thread, with progress the panel can show. A failure (including a panic in a reader)
//! comes back as an error message; the data on screen stays.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use crate::field::ReadOptions;
use crate::field::TensorField;
use crate::field::scalar::ScalarVolume;
use crate::glyph::GlyphSet;
use crate::progress::Progress;
use crate::scene::UnderlaySource;
use crate::staging::{Source, decompose, field_spacing, read, read_underlay};

/// A loaded field and its glyphs.
pub struct Loaded {
    pub source: Source,
    pub field: Arc<TensorField>,
    pub set: Arc<GlyphSet>,
    /// What `--scale auto` fits glyphs to.
    pub spacing: crate::glyph::style::Spacing,
    /// The box around the glyph centres `[x0, y0, z0, x1, y1, z1]` (the ROI control's default).
    pub bounds: [f64; 6],
    /// The underlay file's volume, when one was given.
    pub underlay: Option<Arc<ScalarVolume>>,
}

impl Loaded {
    pub fn name(&self) -> String {
        self.source.name()
    }
}

/// Reading and deriving, synchronously (the worker's job; tests call it directly).
pub fn load_now(
    source: &Source,
    opts: &ReadOptions,
    underlay: &Option<UnderlaySource>,
    progress: &dyn Progress,
) -> Result<Loaded, String> {
    let field = read(source, opts, progress).map_err(|e| e.to_string())?;
    let underlay = read_underlay(underlay).map_err(|e| e.to_string())?;
    if field.is_empty() {
        return Err(format!("{}: no tensors", source.name()));
    }
    let set = decompose(&field, progress);
    if set.glyphs.is_empty() {
        return Err(format!(
            "{}: no valid tensors ({} skipped)",
            source.name(),
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
        underlay: underlay.map(Arc::new),
    })
}

/// Progress the worker reports and the panel reads.
#[derive(Default)]
struct SharedProgress {
    stage: Mutex<String>,
    items: AtomicU64,
    done: AtomicU64,
}

impl Progress for SharedProgress {
    fn begin(&self, stage: &str, items: Option<u64>) {
        *self.stage.lock().unwrap_or_else(|e| e.into_inner()) = stage.to_string();
        self.items.store(items.unwrap_or(0), Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
    }

    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
}

/// A load under way.
pub struct Loading {
    pub source: Source,
    progress: Arc<SharedProgress>,
    rx: Receiver<Result<Loaded, String>>,
    handle: Option<JoinHandle<()>>,
}

impl Loading {
    /// Start loading on a worker thread (the tensors, and the underlay's file if it names one);
    /// `wake` is called when it is done (to repaint).
    pub fn start(
        source: Source,
        opts: ReadOptions,
        underlay: Option<UnderlaySource>,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let progress = Arc::new(SharedProgress::default());
        progress.begin("reading", None);
        let (tx, rx) = channel();
        let pb = progress.clone();
        let src = source.clone();
        let handle = std::thread::Builder::new()
            .name("tensorglyph-load".into())
            .spawn(move || {
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    load_now(&src, &opts, &underlay, pb.as_ref())
                }))
                .unwrap_or_else(|panic| {
                    let msg = panic
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| panic.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "unknown error".into());
                    Err(format!("{}: reading failed: {msg}", src.name()))
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
        let p = &self.progress;
        let stage = p.stage.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let items = p.items.load(Ordering::Relaxed);
        let frac = (items > 0).then(|| p.done.load(Ordering::Relaxed) as f32 / items as f32);
        (stage, frac)
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
            Err(TryRecvError::Disconnected) => {
                Some(Err(format!("{}: the loader stopped", self.source.name())))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::staging::Demo;

    #[test]
    fn loads_the_demo_off_thread_and_reports_bad_files() {
        let mut l = Loading::start(
            Source::Demo(Demo { n: 5 }),
            ReadOptions::default(),
            None,
            || {},
        );
        let loaded = loop {
            if let Some(r) = l.poll() {
                break r.unwrap();
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        assert_eq!(loaded.set.glyphs.len(), 125);
        assert!(loaded.spacing.typical() > 0.0);

        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.vtk");
        std::fs::write(&bad, b"not a vtk file").unwrap();
        let mut l = Loading::start(Source::File(bad), ReadOptions::default(), None, || {});
        let err = loop {
            if let Some(r) = l.poll() {
                break r.err().expect("a bad file is an error");
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        assert!(err.contains("bad.vtk"), "{err}");
    }
}
