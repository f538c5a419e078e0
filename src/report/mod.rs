//! Glyph reports for pipelines: per participant of a BIDS derivatives folder (its BEP016 tensor
//! maps and its ODF maps: [`crate::bids`]), or per file (of tensors or of SH series), PNG
//! mosaics (axial, coronal and sagittal rows of slices; a tensor map's each with a zoomed inset
//! where the glyphs' shapes can be read: [`inset`]; an ODF map's rows of ODF glyphs: [`odf`])
//! and one self-contained HTML page stating what was read, assumed and measured.
//!
//! Each map is read and decomposed once, and every figure drawn from that with the caller's one
//! back end. A report is made in memory and then written file by file (each to a temporary
//! file, then renamed), figures first and the page last; if a write fails, what was written of
//! it is removed: a report is whole or absent. A report that fails does not stop the others.

pub mod group;
pub mod inset;
pub mod lattice;
pub mod mosaic;
pub mod odf;
mod odf_map;
pub mod page;
pub mod peaks;
mod row;
pub mod stats;

use std::path::{Path, PathBuf};

use serde::Serialize;
use web_time::Instant;

use crate::backend::Backend;
use crate::bids::{self, FindError};
use crate::error::{LoadError, escape_path};
use crate::field::{FieldKind, Inputs, ReadOptions};
use crate::image_out::{encode_png, write_atomic};
use crate::info::{Skipped, info_report, why_text};
use crate::progress::Progress;
use crate::staging::{self, Source, field_spacing};
use inset::ZoomRegion;
use mosaic::{FigureError, InsetInfo, ORIENTATIONS};
pub use odf_map::{OdfReport, PeakStats};
use stats::Summary;

/// What to report on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Job {
    /// One report per file (any tensor file a reader reads, or a file of SH series), named
    /// after it.
    Files(Vec<PathBuf>),
    /// One report per participant of a BIDS derivatives folder (those of `labels` when it
    /// names some, with or without `sub-`), as a BIDS App's `participant` level.
    Bids { dir: PathBuf, labels: Vec<String> },
}

/// How the figures are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// The overview tiles' side, in pixels ([`inset::check_tile`]).
    pub tile: u32,
    /// The region each row's inset shows (its slices through the voxel asked for); `None`:
    /// where FA is highest on the row's middle slice.
    pub zoom: Option<ZoomRegion>,
    /// The basis of the maps read as SH series (`--sh-basis`); `None`: each file's writer's.
    /// It does not make a tensor map SH: which maps are ODF maps is their count's (or, in a
    /// BIDS folder, their name's) to say.
    pub sh_basis: Option<crate::sh::ShBasis>,
    /// How each voxel's ODF is scaled in the ODF maps' figures (`--odf-normalize`).
    pub odf_normalize: crate::scene::odf::OdfNormalize,
    /// How the ODF maps' glyphs are coloured (`--color`): by direction (DEC, the default) or
    /// by the amplitude through viridis.
    pub odf_color: crate::shape::odf::OdfColoring,
    /// Leave out what differs from run to run (times and memory), so that two runs over the
    /// same data on the same machine write the same bytes (`--reproducible`): a cohort run in
    /// parallel can be checked against a serial one.
    pub reproducible: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            tile: inset::DEFAULT_TILE,
            zoom: None,
            sh_basis: None,
            odf_normalize: crate::scene::odf::OdfNormalize::default(),
            odf_color: crate::shape::odf::OdfColoring::Direction,
            reproducible: false,
        }
    }
}

/// Why no report could be started (a usage error).
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Find(#[from] FindError),
    #[error("no tensor file to report on")]
    NoInput,
    #[error("{0}: two inputs would write the same report (name them apart)")]
    SameName(String),
    #[error(
        "{}: the output folder is the BIDS folder read; write the reports to a folder of their own",
        escape_path(.0)
    )]
    OutputIsInput(PathBuf),
    #[error("{}: cannot write: {source}", escape_path(.path))]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// Why one report failed.
#[derive(Debug, thiserror::Error)]
pub enum UnitError {
    #[error(
        "no BEP016 tensor map (sub-{0}/[ses-*/]dwi/*_model-DTI[_param-tensor]_dwimap.nii[.gz]), \
         no ODF map (*_param-fod_dwimap.nii[.gz], *_param-sh_*, *_param-fod*.mif[.gz] …) and no \
         peaks map (*_param-peaks_dwimap.nii[.gz], *_param-peaks*.mif[.gz])"
    )]
    NoMap(String),
    #[error(
        "{}: named as an ODF map but holds no SH series ({count} values per voxel; SH series \
         have 15, 28, 45, 66, 91 … for lmax 4, 6, 8, 10, 12 …, and 6 are a tensor's)",
        escape_path(.path)
    )]
    NotSh { path: PathBuf, count: usize },
    #[error("{}: no ODF to draw: every voxel's SH series is all zero", escape_path(.0))]
    NoOdf(PathBuf),
    #[error("{}: no peak to draw: every voxel's peaks are NaN or zero", escape_path(.0))]
    NoPeaks(PathBuf),
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(transparent)]
    Figure(#[from] FigureError),
    #[error("{}: not a lattice: a report shows slices of a volume", escape_path(.0))]
    NotLattice(PathBuf),
    #[error("{}: no valid tensor to draw", escape_path(.0))]
    NoValidTensor(PathBuf),
    #[error("{}: cannot write: {source}", escape_path(.path))]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// A report written: its page and figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Written {
    /// `sub-<label>`, or the file's name without its extensions.
    pub name: String,
    pub page: PathBuf,
    pub figures: Vec<PathBuf>,
}

/// A report that failed, and why.
#[derive(Debug)]
pub struct Failed {
    pub name: String,
    pub error: UnitError,
}

/// What a run did.
#[derive(Debug)]
pub struct Outcome {
    pub written: Vec<Written>,
    pub failed: Vec<Failed>,
}

/// What the page says of the run.
pub struct RunInfo {
    pub backend: String,
    pub total_ms: f64,
    pub peak_rss_bytes: Option<u64>,
    /// Whether the page states times and memory ([`Options::reproducible`] leaves them out).
    pub timings: bool,
}

/// One figure, encoded, and what it shows.
pub struct FigureReport {
    pub orientation: &'static str,
    pub file: String,
    pub width: u32,
    pub height: u32,
    pub png: Vec<u8>,
    pub lattice_axis: usize,
    pub slices: Vec<usize>,
    pub glyphs_drawn: usize,
    /// Pixels per voxel in the overview tiles.
    pub overview_px_per_voxel: f64,
    pub inset: Option<InsetInfo>,
    pub ms: f64,
    /// Why the FA underlay is not drawn, if it is not.
    pub underlay_missing: Option<String>,
}

/// One map's part of a report: a tensor map's or an ODF map's.
pub enum Section {
    Tensor(MapReport),
    Odf(OdfReport),
    Peaks(peaks::PeaksReport),
}

impl Section {
    pub fn figures(&self) -> &[FigureReport] {
        match self {
            Section::Tensor(m) => &m.figures,
            Section::Odf(m) => &m.figures,
            Section::Peaks(m) => &m.figures,
        }
    }
}

/// One tensor map's part of a report.
pub struct MapReport {
    pub name: String,
    pub path: String,
    pub session: Option<String>,
    pub format: String,
    /// The component layout and why (`fsl (from the BEP016 sidecar)`).
    pub layout: Option<String>,
    /// The tensors' frame, the world and its source, and the sidecar's `ReferenceAxes`.
    pub frame: Option<String>,
    pub notes: Vec<String>,
    pub units: String,
    /// Whether the world is anatomical (RAS, in millimetres).
    pub anatomical: bool,
    pub dims: [usize; 3],
    pub tensors: usize,
    pub valid: usize,
    pub skipped: Skipped,
    pub clamped: usize,
    pub fa: Option<Summary>,
    pub md: Option<Summary>,
    pub read_ms: f64,
    pub decompose_ms: f64,
    pub figures: Vec<FigureReport>,
}

/// A report to make: its name (the report goes to `<name>.html` and `<name>/figures/` in the
/// output folder) and its maps (with their sessions).
struct Unit {
    name: String,
    maps: Vec<(PathBuf, Option<String>, FieldKind)>,
    /// A participant with no map: its label (the report fails, naming it).
    missing: Option<String>,
}

/// What the back end is, as the page names it.
pub fn backend_name(backend: &Backend) -> String {
    match backend.gpu() {
        None => "the exact CPU reference (no GPU adapter)".into(),
        Some(g) => {
            let name = g.adapter_name();
            if name.contains("llvmpipe") {
                format!("lavapipe, Mesa's Vulkan on the CPU ({name})")
            } else {
                format!("the GPU {name}")
            }
        }
    }
}

/// The file's name without its directory and its extensions (`.nii.gz`, `.nrrd` …).
pub(super) fn file_stem(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    let known = [
        ".nii", ".nrrd", ".nhdr", ".mif", ".mih", ".vtk", ".vti", ".vtr", ".vts", ".vtu", ".vtp",
        ".pvti",
    ];
    let stem = known
        .iter()
        .find_map(|e| name.strip_suffix(e))
        .unwrap_or(name);
    if stem.is_empty() {
        "report".into()
    } else {
        stem.into()
    }
}

fn units(job: &Job) -> Result<Vec<Unit>, ReportError> {
    let units: Vec<Unit> = match job {
        Job::Files(files) => files
            .iter()
            .map(|f| Unit {
                name: file_stem(f),
                // A header probe: a file of SH series is drawn as ODFs, as `render` draws it.
                maps: vec![(
                    f.clone(),
                    None,
                    FieldKind::of_file(&Inputs::file_system(), f, &ReadOptions::default()),
                )],
                missing: None,
            })
            .collect(),
        Job::Bids { dir, labels } => bids::participants(dir, labels)?
            .into_iter()
            .map(|p| Unit {
                name: format!("sub-{}", p.label),
                missing: p.maps.is_empty().then(|| p.label.clone()),
                maps: p
                    .maps
                    .into_iter()
                    .map(|m| (m.path, m.session, m.kind))
                    .collect(),
            })
            .collect(),
    };
    if units.is_empty() {
        return Err(ReportError::NoInput);
    }
    let mut names: Vec<&str> = units.iter().map(|u| u.name.as_str()).collect();
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(ReportError::SameName(w[0].to_string()));
    }
    Ok(units)
}

/// The reports a job asks for, found and checked before anything is drawn (a usage error
/// stops the run before a GPU is set up).
pub struct Plan {
    units: Vec<Unit>,
    /// The BIDS folder read, for a BIDS job.
    bids: Option<PathBuf>,
    options: Options,
}

impl Plan {
    pub fn new(job: &Job) -> Result<Self, ReportError> {
        Ok(Self {
            units: units(job)?,
            bids: match job {
                Job::Bids { dir, .. } => Some(dir.clone()),
                Job::Files(_) => None,
            },
            options: Options::default(),
        })
    }

    /// The plan with its figures drawn as `options` say.
    pub fn with_options(self, options: Options) -> Self {
        Self { options, ..self }
    }

    /// The reports' names, in the order they are made.
    pub fn names(&self) -> Vec<&str> {
        self.units.iter().map(|u| u.name.as_str()).collect()
    }

    /// Make the reports in `out` (created if missing), drawn with `backend`. A BIDS job also
    /// writes `dataset_description.json` (the output is a derivatives dataset).
    pub fn run(
        &self,
        out: &Path,
        backend: &Backend,
        progress: &dyn Progress,
    ) -> Result<Outcome, ReportError> {
        // The reports are a dataset of their own: never among the data they are made of (its
        // dataset_description.json would be replaced).
        if let Some(dir) = &self.bids
            && let (Ok(a), Ok(b)) = (dir.canonicalize(), out.canonicalize())
            && a == b
        {
            return Err(ReportError::OutputIsInput(out.to_path_buf()));
        }
        std::fs::create_dir_all(out).map_err(|source| ReportError::Write {
            path: out.to_path_buf(),
            source,
        })?;
        if self.bids.is_some() {
            write_dataset_description(out)?;
        }
        let mut outcome = Outcome {
            written: Vec::new(),
            failed: Vec::new(),
        };
        let bids = self.bids.is_some();
        for unit in &self.units {
            match report(unit, out, &self.options, backend, progress, bids) {
                Ok(w) => outcome.written.push(w),
                Err(error) => {
                    // The group level lists it with its error; a summary that cannot be
                    // written leaves it "without a report" there, which it is.
                    if bids {
                        let failed = group::ParticipantSummary {
                            name: unit.name.clone(),
                            page: None,
                            error: Some(error.to_string()),
                            maps: Vec::new(),
                        };
                        let _ = group::write_summary(out, &failed, &[]);
                    }
                    outcome.failed.push(Failed {
                        name: unit.name.clone(),
                        error,
                    })
                }
            }
        }
        Ok(outcome)
    }
}

/// Make the reports `job` asks for in `out`: [`Plan::new`], then [`Plan::run`].
pub fn run(
    job: &Job,
    out: &Path,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<Outcome, ReportError> {
    Plan::new(job)?.run(out, backend, progress)
}

/// What BIDS derivatives need: the output is a derivatives dataset of its own.
fn write_dataset_description(out: &Path) -> Result<(), ReportError> {
    let text = serde_json::to_string_pretty(&serde_json::json!({
        "Name": "tensorglyph glyph reports",
        "BIDSVersion": "1.10.0",
        "DatasetType": "derivative",
        "GeneratedBy": [{"Name": "tensorglyph", "Version": env!("CARGO_PKG_VERSION")}],
    }))
    .expect("a JSON value serialises");
    let path = out.join("dataset_description.json");
    write_atomic(&path, &[], |w| {
        use std::io::Write as _;
        writeln!(w, "{text}")
    })
    .map_err(|source| ReportError::Write { path, source })
}

/// One report; with `summary`, the group level's summary of it too ([`group`]), written last.
fn report(
    unit: &Unit,
    out: &Path,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
    summary: bool,
) -> Result<Written, UnitError> {
    let t = Instant::now();
    if let Some(label) = &unit.missing {
        return Err(UnitError::NoMap(label.clone()));
    }
    let mut maps = Vec::new();
    let mut read = Vec::new();
    for (path, session, kind) in &unit.maps {
        let session = session.clone();
        maps.push(match kind {
            FieldKind::Tensors => {
                Section::Tensor(map(path, session, options, backend, progress, &mut read)?)
            }
            FieldKind::Series => Section::Odf(odf_map::map(
                path, session, options, backend, progress, &mut read,
            )?),
            FieldKind::Peaks => Section::Peaks(peaks::map(
                path, session, options, backend, progress, &mut read,
            )?),
        });
    }
    let run = RunInfo {
        backend: backend_name(backend),
        total_ms: staging::ms(t),
        peak_rss_bytes: crate::mem::peak_rss_bytes(),
        timings: !options.reproducible,
    };
    let html = page::html(&unit.name, &maps, &run);
    let folder = out.join(&unit.name).join("figures");
    let page = out.join(format!("{}.html", unit.name));
    let inputs: Vec<&Path> = read.iter().map(PathBuf::as_path).collect();
    let mut written: Vec<PathBuf> = Vec::new();
    let result = (|| {
        std::fs::create_dir_all(&folder).map_err(|source| UnitError::Write {
            path: folder.clone(),
            source,
        })?;
        for f in maps.iter().flat_map(Section::figures) {
            let path = folder.join(&f.file);
            write_bytes(&path, &inputs, &f.png)?;
            written.push(path);
        }
        write_bytes(&page, &inputs, html.as_bytes())?;
        if summary {
            let s = group::summary(&unit.name, &maps);
            group::write_summary(out, &s, &inputs).map_err(|source| {
                let _ = std::fs::remove_file(&page);
                UnitError::Write {
                    path: group::summary_path(out, &unit.name),
                    source,
                }
            })?;
        }
        Ok(())
    })();
    if let Err(e) = result {
        for p in &written {
            let _ = std::fs::remove_file(p);
        }
        return Err(e);
    }
    Ok(Written {
        name: unit.name.clone(),
        page,
        figures: written,
    })
}

fn write_bytes(path: &Path, inputs: &[&Path], bytes: &[u8]) -> Result<(), UnitError> {
    write_atomic(path, inputs, |w| {
        use std::io::Write as _;
        w.write_all(bytes)
    })
    .map_err(|source| UnitError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Read and decompose the map at `path` once, and draw its figures.
fn map(
    path: &Path,
    session: Option<String>,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
    read: &mut Vec<PathBuf>,
) -> Result<MapReport, UnitError> {
    let inputs = Inputs::file_system();
    let t = Instant::now();
    let field = staging::read_from(
        &inputs,
        &Source::File(path.to_path_buf()),
        &ReadOptions::default(),
        progress,
    )?;
    let read_ms = staging::ms(t);
    read.extend(inputs.paths_read());
    let dims = field
        .lattice_dims()
        .ok_or_else(|| UnitError::NotLattice(path.to_path_buf()))?;
    let t = Instant::now();
    let set = staging::decompose(&field, progress);
    // The figures need the positions only.
    let field = field.into_geometry();
    let decompose_ms = staging::ms(t);
    if set.glyphs.is_empty() {
        return Err(UnitError::NoValidTensor(path.to_path_buf()));
    }
    let info = info_report(&field, &set, &[]).expect("no sample asked for");
    let (fa, md) = stats::measures(&set);
    let clamped = stats::clamped(&set, &mosaic::style(), field_spacing(&field));
    let anatomical = field.meta.frame.as_ref().is_some_and(|f| f.world == "RAS");
    let stem = file_stem(path);
    let mut figures = Vec::new();
    for o in ORIENTATIONS {
        let m = mosaic::render(
            &field, &set, dims, o, anatomical, options, backend, progress,
        )?;
        figures.push(figure(path, &stem, o.name, m)?);
    }
    let sidecar_axes = info
        .bep016_sidecar
        .as_ref()
        .and_then(|s| s.reference_axes.clone());
    let units = if info.bep016_sidecar.is_some() {
        "µm²/ms (BEP016 diffusivities)".to_string()
    } else {
        crate::glyph::style::units_in_name(&field.array.name)
            .unwrap_or_else(|| "as stored in the file (it does not say)".into())
    };
    Ok(MapReport {
        name: path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        path: path.display().to_string(),
        session,
        format: info.format.clone(),
        layout: info
            .layout
            .as_ref()
            .map(|l| format!("{} ({})", l.order, why_text(l.why))),
        frame: info.frame.as_ref().map(|f| {
            let axes = sidecar_axes.as_deref().map_or(String::new(), |a| {
                format!(", ReferenceAxes {a} from the BEP016 sidecar")
            });
            format!(
                "tensors in {} axes{axes}; world {} from {}",
                f.tensor_frame.name(),
                f.world,
                f.source
            )
        }),
        notes: info.notes.clone(),
        units,
        anatomical,
        dims,
        tensors: info.tensors,
        valid: info.valid,
        skipped: info.skipped.clone(),
        clamped,
        fa,
        md,
        read_ms,
        decompose_ms,
        figures,
    })
}

/// The figure `m` of the map at `path` (`stem`, its name without extensions), encoded.
pub(super) fn figure(
    path: &Path,
    stem: &str,
    orientation: &'static str,
    m: mosaic::Mosaic,
) -> Result<FigureReport, UnitError> {
    let mut png = Vec::new();
    encode_png(&mut png, m.width, m.height, &m.rgba, None).map_err(|source| UnitError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(FigureReport {
        orientation,
        file: format!("{stem}_{orientation}.png"),
        width: m.width,
        height: m.height,
        png,
        lattice_axis: m.lattice_axis,
        slices: m.slices,
        glyphs_drawn: m.glyphs_drawn,
        overview_px_per_voxel: m.overview_px_per_voxel,
        inset: m.inset,
        ms: m.ms,
        underlay_missing: m.underlay_missing.map(|e| e.to_string()),
    })
}
