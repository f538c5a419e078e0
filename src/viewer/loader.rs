//! Loading: read the file (or make the demo field), then eigendecompose, with progress the
//! panel can show. On the desktop a worker thread does it off the UI thread. The browser has
//! one thread (threads need a cross-origin isolated page, which a plain static server does not
//! give), so there the load runs inside a frame, once a frame saying "loading" was shown; rayon
//! then runs on that one thread too. A failure comes back as an error message; the data on
//! screen stays.

use std::sync::atomic::{AtomicU64, Ordering};
#[cfg(not(target_arch = "wasm32"))]
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Arc, Mutex};
#[cfg(not(target_arch = "wasm32"))]
use std::thread::JoinHandle;

use rayon::prelude::*;
use web_time::Instant;

use crate::field::scalar::ScalarVolume;
use crate::field::{FieldKind, PeakField, ShField, TensorField};
use crate::field::{Inputs, ReadOptions};
use crate::glyph::GlyphSet;
use crate::progress::Progress;
use crate::scene::UnderlaySource;
use crate::staging::{Source, decompose, field_spacing, read_from, read_underlay};

/// A loaded field and its glyphs.
pub struct Loaded {
    pub source: Source,
    pub field: Arc<TensorField>,
    pub set: Arc<GlyphSet>,
    /// What `--scale auto` fits glyphs to.
    pub spacing: crate::glyph::style::Spacing,
    /// The box around the glyph centres `[x0, y0, z0, x1, y1, z1]` (the ROI control's default).
    pub bounds: [f64; 6],
    /// The series of a file of SH series (fibre ODFs), drawn as ODF glyphs; `field` is then
    /// its lattice without tensors ([`ShField::geometry`]) and `set` is empty.
    pub odf: Option<Arc<ShField>>,
    /// The peaks of a file of fibre peaks, drawn as sticks; `field` is then its lattice without
    /// tensors ([`PeakField::geometry`]) and `set` is empty.
    pub peaks: Option<Arc<PeakField>>,
    /// The underlay file's volume, when one was given.
    pub underlay: Option<Arc<ScalarVolume>>,
    pub timings: LoadTimings,
    /// The glyphs the data holds, shown or not: its valid tensors, or the voxels holding a
    /// series (counted once: the status line says "N of total").
    pub total: usize,
}

/// How long opening took (the page's status says it: one thread reads and decomposes there).
#[derive(Debug, Clone, Copy)]
pub struct LoadTimings {
    /// When reading began.
    pub started: Instant,
    pub read_ms: f64,
    pub eigen_ms: f64,
    /// From `started` to the status of the first frame that shows the data (set by the view).
    pub first_frame_ms: Option<f64>,
}

impl Loaded {
    /// What the file holds.
    pub fn kind(&self) -> FieldKind {
        if self.odf.is_some() {
            FieldKind::Series
        } else if self.peaks.is_some() {
            FieldKind::Peaks
        } else {
            FieldKind::Tensors
        }
    }

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
    load_now_from(&Inputs::file_system(), source, opts, underlay, progress)
}

/// [`load_now`], the tensors read from `inputs` (the page's files, by name).
pub fn load_now_from(
    inputs: &Inputs,
    source: &Source,
    opts: &ReadOptions,
    underlay: &Option<UnderlaySource>,
    progress: &dyn Progress,
) -> Result<Loaded, String> {
    let started = Instant::now();
    let kind = source.kind_in(inputs, opts);
    if let Some(refusal) = kind.viewer_refusal(&source.name()) {
        return Err(refusal);
    }
    if let (FieldKind::Series, Source::File(path)) = (kind, source) {
        return load_sh(inputs, path, source, opts, progress, started);
    }
    if let (FieldKind::Peaks, Source::File(path)) = (kind, source) {
        return load_peaks(inputs, path, source, opts, progress, started);
    }
    let field = read_from(inputs, source, opts, progress).map_err(|e| e.to_string())?;
    let underlay = read_underlay(underlay).map_err(|e| e.to_string())?;
    if field.is_empty() {
        return Err(format!("{}: no tensors", source.name()));
    }
    let read_ms = crate::staging::ms(started);
    let t = Instant::now();
    let set = decompose(&field, progress);
    let eigen_ms = crate::staging::ms(t);
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
        total: set.glyphs.len(),
        set: Arc::new(set),
        spacing,
        bounds,
        odf: None,
        peaks: None,
        underlay: underlay.map(Arc::new),
        timings: LoadTimings {
            started,
            read_ms,
            eigen_ms,
            first_frame_ms: None,
        },
    })
}

/// [`load_now_from`] of a file of SH series: the series and their lattice (an underlay is for
/// tensors: ODF glyphs are drawn without one, as `render` draws them).
fn load_sh(
    inputs: &Inputs,
    path: &std::path::Path,
    source: &Source,
    opts: &ReadOptions,
    progress: &dyn Progress,
    started: Instant,
) -> Result<Loaded, String> {
    let sh = crate::progress::stage(progress, "reading SH series", None, || {
        crate::field::read_sh_field_from(inputs, path, opts)
    })
    .map_err(|e| e.to_string())?;
    let (field, total) = (sh.geometry(), sh.series());
    let read = (started, crate::staging::ms(started));
    Ok(of_lattice(source, field, total, (Some(sh), None), read))
}

/// [`load_now_from`] of a file of fibre peaks: the peaks and their lattice (no underlay, as
/// `render` draws them).
fn load_peaks(
    inputs: &Inputs,
    path: &std::path::Path,
    source: &Source,
    opts: &ReadOptions,
    progress: &dyn Progress,
    started: Instant,
) -> Result<Loaded, String> {
    let peaks = crate::progress::stage(progress, "reading peaks", None, || {
        crate::field::read_peak_field_from(inputs, path, opts)
    })
    .map_err(|e| e.to_string())?;
    let field = peaks.geometry();
    let total = peaks.counts().iter().enumerate().map(|(k, n)| k * n).sum();
    let read = (started, crate::staging::ms(started));
    Ok(of_lattice(source, field, total, (None, Some(peaks)), read))
}

/// What a file of another kind than tensors opens as: its lattice `field` (no tensors, no
/// glyph set, no underlay), `total` glyphs it holds, its series or peaks, and when reading
/// began and how long it took.
fn of_lattice(
    source: &Source,
    field: TensorField,
    total: usize,
    (odf, peaks): (Option<ShField>, Option<PeakField>),
    (started, read_ms): (Instant, f64),
) -> Loaded {
    Loaded {
        source: source.clone(),
        spacing: field_spacing(&field),
        bounds: crate::select::point_bounds(
            (0..field.len()).into_par_iter().map(|i| field.position(i)),
        ),
        field: Arc::new(field),
        set: Arc::new(GlyphSet::default()),
        total,
        odf: odf.map(Arc::new),
        peaks: peaks.map(Arc::new),
        underlay: None,
        timings: LoadTimings {
            started,
            read_ms,
            eigen_ms: 0.0,
            first_frame_ms: None,
        },
    }
}

/// Of files opened together (the page's file input or a drop), the one to read: the one that
/// names the others. A `.nhdr` or `.mih` names its data file and a `.pvti` its pieces; any member of an
/// FSL eigen set names the set; a NIfTI file comes with its BEP016 sidecar (`.json`). So a
/// `.nhdr` or `.pvti` first, else the first that is not a data file, piece or sidecar.
pub fn main_file(names: &[String]) -> Option<&str> {
    let lower = |n: &str| n.to_ascii_lowercase();
    let names_others = |n: &&String| {
        [".nhdr", ".mih", ".pvti"]
            .iter()
            .any(|e| lower(n).ends_with(e))
    };
    let companion = |n: &&String| {
        let n = lower(n);
        [".raw", ".raw.gz", ".dat", ".json", ".bval", ".bvec", ".vti"]
            .iter()
            .any(|e| n.ends_with(e))
    };
    names
        .iter()
        .find(names_others)
        .or_else(|| names.iter().find(|n| !companion(n)))
        .or(names.first())
        .map(String::as_str)
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
    job: Job,
}

#[cfg(not(target_arch = "wasm32"))]
struct Job {
    rx: Receiver<Result<Loaded, String>>,
    handle: Option<JoinHandle<()>>,
}

/// The load, run at the second poll (the first frame shows that it is loading).
#[cfg(target_arch = "wasm32")]
struct Job {
    work: Option<Box<dyn FnOnce() -> Result<Loaded, String>>>,
    shown: bool,
}

impl Loading {
    /// Start loading (the tensors, and the underlay's file if it names one); `wake` is called
    /// when it is done (to repaint).
    pub fn start(
        source: Source,
        inputs: Inputs,
        opts: ReadOptions,
        underlay: Option<UnderlaySource>,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let progress = Arc::new(SharedProgress::default());
        progress.begin("reading", None);
        let pb = progress.clone();
        let src = source.clone();
        let load = move || load_now_from(&inputs, &src, &opts, &underlay, pb.as_ref());
        let name = source.name();
        Self {
            source,
            progress,
            job: Job::start(load, name, wake),
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
        self.job.poll(&self.source)
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl Job {
    /// On a worker thread; a panic in a reader becomes an error naming the source.
    fn start(
        load: impl FnOnce() -> Result<Loaded, String> + Send + 'static,
        name: String,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let (tx, rx) = channel();
        let handle = std::thread::Builder::new()
            .name("tensorglyph-load".into())
            .spawn(move || {
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(load))
                    .unwrap_or_else(|panic| {
                        let msg = panic
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| panic.downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "unknown error".into());
                        Err(format!("{name}: reading failed: {msg}"))
                    });
                let _ = tx.send(result);
                wake();
            })
            .expect("spawning the loader thread");
        Self {
            rx,
            handle: Some(handle),
        }
    }

    fn poll(&mut self, source: &Source) -> Option<Result<Loaded, String>> {
        match self.rx.try_recv() {
            Ok(r) => {
                if let Some(h) = self.handle.take() {
                    let _ = h.join();
                }
                Some(r)
            }
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                Some(Err(format!("{}: the loader stopped", source.name())))
            }
        }
    }
}

#[cfg(target_arch = "wasm32")]
impl Job {
    fn start(
        load: impl FnOnce() -> Result<Loaded, String> + 'static,
        _name: String,
        wake: impl Fn() + 'static,
    ) -> Self {
        wake();
        Self {
            work: Some(Box::new(load)),
            shown: false,
        }
    }

    fn poll(&mut self, _source: &Source) -> Option<Result<Loaded, String>> {
        if !std::mem::replace(&mut self.shown, true) {
            return None;
        }
        self.work.take().map(|work| work())
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
            Inputs::file_system(),
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
        assert_eq!(loaded.total, 125);
        assert!(loaded.spacing.typical() > 0.0);

        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.vtk");
        std::fs::write(&bad, b"not a vtk file").unwrap();
        let mut l = Loading::start(
            Source::File(bad),
            Inputs::file_system(),
            ReadOptions::default(),
            None,
            || {},
        );
        let err = loop {
            if let Some(r) = l.poll() {
                break r.err().expect("a bad file is an error");
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        assert!(err.contains("bad.vtk"), "{err}");
    }

    /// The file `name` of tests/data/sh opened from disk and as the page hands it over (its
    /// bytes under `page_name`): its path and both.
    fn open_both(name: &str, page_name: &str) -> (std::path::PathBuf, [Loaded; 2]) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/sh")
            .join(name);
        let opts = ReadOptions::default();
        let silent = &crate::progress::Silent;
        let from_disk = load_now(&Source::File(path.clone()), &opts, &None, silent).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let from_page = load_now_from(
            &Inputs::named([(page_name.to_string(), bytes)]),
            &Source::File(page_name.into()),
            &opts,
            &None,
            silent,
        )
        .unwrap();
        (path, [from_disk, from_page])
    }

    /// A file of peaks (MRtrix's sh2peaks image, from disk and as the page hands it over)
    /// opens as its lattice and peaks, and the viewer's scene of a slice is `render`'s sticks.
    #[test]
    fn peaks_open_and_build_the_sticks_render_draws() {
        let (path, [from_disk, from_page]) = open_both("sh2peaks_lmax8.mif", "peaks.mif");
        let silent = &crate::progress::Silent;
        for l in [&from_disk, &from_page] {
            assert_eq!(l.kind(), FieldKind::Peaks);
            let p = l.peaks.as_ref().expect("read as peaks");
            assert_eq!((p.dims, p.per_voxel), ([4, 4, 4], 3));
            assert_eq!(l.field.lattice_dims(), Some([4, 4, 4]));
            assert_eq!(l.field.positions.len(), 64);
            assert!(l.set.glyphs.is_empty() && l.field.tensors.is_empty());
            // The status line's total: the peaks (three in each of the 64 voxels).
            assert_eq!(l.total, 192);
        }
        let slice = crate::select::Plane { axis: 2, index: 1 };
        let recipe = crate::staging::Recipe {
            selection: crate::select::Selection {
                slicing: crate::select::Slicing::Planes(vec![slice]),
                ..Default::default()
            },
            glyph: crate::shape::GlyphKind::Capsule,
            style: crate::glyph::GlyphStyle {
                color: crate::glyph::ColorScheme::Dec,
                ..Default::default()
            },
            ..Default::default()
        };
        let viewer =
            crate::staging::build_peaks(from_page.peaks.as_ref().unwrap(), "peaks.mif", &recipe)
                .unwrap();
        let render = crate::staging::stage(&Source::File(path), &recipe, silent).unwrap();
        assert_eq!(viewer.scene.instances.len(), 48);
        assert_eq!(viewer.scene.kind, crate::shape::GlyphKind::Capsule);
        assert_eq!(viewer.scene.instances, render.scene.instances);
        assert_eq!(viewer.face.map(|f| f.toward), render.face.map(|f| f.toward));
    }

    /// A file of SH series (MRtrix's, and the same bytes handed over as the page hands them)
    /// opens as its lattice and series, and the viewer's scene of a slice is `render`'s.
    #[test]
    fn sh_series_open_and_build_the_scene_render_draws() {
        let (path, [from_disk, from_page]) = open_both("mrtrix_lmax8.mif", "lmax8.mif");
        let silent = &crate::progress::Silent;
        for l in [&from_disk, &from_page] {
            let sh = l.odf.as_ref().expect("read as SH series");
            assert_eq!((sh.dims, sh.layout.lmax), ([4, 4, 4], 8));
            assert_eq!(l.field.lattice_dims(), Some([4, 4, 4]));
            assert_eq!(l.field.positions.len(), 64);
            assert!(l.set.glyphs.is_empty() && l.field.tensors.is_empty());
            // The status line's total: the voxels holding a series (all 64 of MRtrix's fit,
            // where sh2peaks finds peaks: expected.json), not the empty tensor set's 0.
            assert_eq!(l.total, 64);
        }
        let slice = crate::select::Plane { axis: 1, index: 2 };
        let recipe = crate::staging::Recipe {
            selection: crate::select::Selection {
                slicing: crate::select::Slicing::Planes(vec![slice]),
                ..Default::default()
            },
            odf_normalize: Some(crate::scene::odf::OdfNormalize::MinMax),
            style: crate::glyph::GlyphStyle {
                color: crate::glyph::ColorScheme::Dec,
                ..Default::default()
            },
            ..Default::default()
        };
        let viewer = crate::staging::build_sh(
            from_page.odf.as_ref().unwrap(),
            "lmax8.mif",
            &recipe,
            silent,
        )
        .unwrap();
        let render = crate::staging::stage(&Source::File(path), &recipe, silent).unwrap();
        assert_eq!(viewer.scene.instances.len(), 16);
        assert_eq!(viewer.scene.instances, render.scene.instances);
        assert_eq!(viewer.scene.payload, render.scene.payload);
        assert_eq!(viewer.face.map(|f| f.toward), render.face.map(|f| f.toward));
        assert_eq!(viewer.selected.len(), 16);
    }

    #[test]
    fn files_opened_together_are_read_through_the_one_that_names_the_others() {
        let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let pick = |n: &[&str]| main_file(&names(n)).map(str::to_string);
        assert_eq!(pick(&["d.raw", "d.nhdr"]).as_deref(), Some("d.nhdr"));
        assert_eq!(pick(&["d.dat", "d.mih"]).as_deref(), Some("d.mih"));
        assert_eq!(
            pick(&["p_0.vti", "p.pvti", "p_1.vti"]).as_deref(),
            Some("p.pvti")
        );
        assert_eq!(
            pick(&["dwi.json", "dwi.nii.gz"]).as_deref(),
            Some("dwi.nii.gz")
        );
        assert_eq!(
            pick(&["f_L1.nii.gz", "f_V1.nii.gz"]).as_deref(),
            Some("f_L1.nii.gz")
        );
        assert_eq!(pick(&["one.vti"]).as_deref(), Some("one.vti"));
        assert_eq!(pick(&[]), None);

        // A detached NRRD handed over as two buffers reads as the files do, in either order.
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dti");
        let want =
            crate::field::read_field(&dir.join("nrrd_detached.nhdr"), &ReadOptions::default())
                .unwrap();
        let files: Vec<(String, Vec<u8>)> = ["nrrd_detached.raw", "nrrd_detached.nhdr"]
            .iter()
            .map(|n| (n.to_string(), std::fs::read(dir.join(n)).unwrap()))
            .collect();
        let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
        let main = main_file(&names).unwrap().to_string();
        let mut l = Loading::start(
            Source::File(main.into()),
            Inputs::named(files),
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
        assert_eq!(loaded.field.len(), want.len());
        assert_eq!(loaded.field.tensors, want.tensors);
        assert_eq!(loaded.field.positions, want.positions);
    }
}
