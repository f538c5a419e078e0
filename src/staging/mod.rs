//! Staging: source → tensor field → glyphs → selection and style → scene, with the bounds the
//! camera frames. One path for `render`, `demo`, `bench`, the viewer and the examples.
//!
//! [`stage`] runs every stage once, timed, and drops the field and the glyph set as soon as the
//! scene no longer needs them (so peak memory stays near the largest single stage: the
//! eigendecomposition, field and glyphs together). The viewer keeps the field and glyphs to
//! restyle and reselect, and calls [`read`], [`decompose`] and [`build`] itself.

use std::path::{Path, PathBuf};
use web_time::Instant;

use glam::DVec3;
use serde::Serialize;

use crate::error::LoadError;
use crate::field::scalar::ScalarVolume;
use crate::field::{FieldKind, Inputs, ReadOptions};
use crate::field::{Positions, TensorField};
use crate::glyph::style::{Spacing, local_spacing, units_in_name};
use crate::glyph::{GlyphSet, GlyphStyle, ResolvedStyle, derive_glyphs};
use crate::progress::{Progress, stage as run_stage};
use crate::request::GlyphKind;
use crate::scene::Scene;
use crate::scene::underlay::{self, UnderlayError, UnderlaySource, Values};
use crate::select::{Plane, Selection, SelectionError, Slicing};

mod kind;
mod lattice;
mod peaks;
mod sh;
mod source;

pub use kind::Offers;
pub use peaks::{
    OVER_ODF_REACH, OverOdfs, STICK_RADIUS, build_peaks, peaks_over_odfs, peaks_over_voxels,
    series_peaks,
};
pub use sh::{build_sh, sh_face_on};
pub use source::{Demo, InMemory, InMemoryFile, Source};

/// The room `--scale auto` fits glyphs to: a lattice's grid spacing, else each position's own
/// spacing ([`local_spacing`]: the centres of unstructured data, a tetrahedral mesh's cells
/// above all, are too irregular for one distance to fit them all).
pub fn field_spacing(field: &TensorField) -> Spacing {
    match field.spacing.filter(|s| s.is_finite() && *s > 0.0) {
        Some(s) => Spacing::Uniform(s),
        None => match &field.positions {
            Positions::Points(p) => local_spacing(p),
            lattice => local_spacing(&lattice.to_vec()),
        }
        .map_or(Spacing::Uniform(1.0), |h| Spacing::Local(h.into())),
    }
}

/// Why staging stopped.
#[derive(Debug, thiserror::Error)]
pub enum StageError {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(transparent)]
    Selection(#[from] SelectionError),
    #[error("the selection keeps no glyph: {asked} leaves none of the {valid} valid glyphs")]
    EmptySelection { asked: String, valid: usize },
    #[error("no glyph to draw: the field has no valid tensor")]
    NoValidTensor,
    /// One of the above, with the data it is about (the file's path or the field's name).
    #[error("{name}: {error}")]
    Of {
        name: String,
        error: Box<StageError>,
    },
    #[error(transparent)]
    Underlay(#[from] UnderlayError),
}

/// What a scene is made of, besides its source.
#[derive(Debug, Clone, Default)]
pub struct Recipe {
    pub read: ReadOptions,
    pub style: GlyphStyle,
    pub selection: Selection,
    pub glyph: GlyphKind,
    /// A scalar image under the glyphs of each plane the selection shows (with no plane, the
    /// middle axial one).
    pub underlay: Option<UnderlaySource>,
    /// With no plane asked for, show the middle axial one (DTI data's default).
    pub middle_slice: bool,
    /// The largest side of an underlay image resampled from a volume, in texels: the
    /// rendered image's larger side; `None`: [`underlay::MAX_TEXELS`] (the viewer's window
    /// may grow).
    pub underlay_side: Option<usize>,
    /// How a file of SH series scales each voxel's ODF (`None`: the default,
    /// [`crate::scene::odf::OdfNormalize::Max`]); given for tensors, staging refuses it.
    pub odf_normalize: Option<crate::scene::odf::OdfNormalize>,
    /// The field drawn as the sticks of its peaks (`--glyph peaks`), as a peaks file is: a file
    /// of SH series its maxima, found in each shown voxel ([`peaks::series_peaks`]); a tensor
    /// field its glyphs' principal directions (`peaks::tensor_sticks`).
    pub peaks: bool,
    /// A file of SH series drawn as its ODF glyphs with the sticks of their peaks over them
    /// (`--peaks`: [`peaks::peaks_over_odfs`], a [`crate::scene::Overlay`]).
    pub peaks_over: bool,
}

impl Recipe {
    /// The selection drawn: with an underlay or `middle_slice` and no plane asked for, the
    /// middle z plane of the lattice (the middle axial slice of a volume in RAS order).
    pub fn selection_for(&self, field: &TensorField) -> Selection {
        let mut sel = self.selection.clone();
        if (self.underlay.is_some() || self.middle_slice)
            && sel.slicing == Slicing::Whole
            && let Some(d) = field.lattice_dims()
        {
            sel.slicing = Slicing::Planes(vec![Plane {
                axis: 2,
                index: d[2] / 2,
            }]);
        }
        sel
    }
}

/// The scalar volume an underlay file names, or the one handed over (a measure comes from the
/// glyphs: `None`).
pub fn read_underlay(source: &Option<UnderlaySource>) -> Result<Option<ScalarVolume>, LoadError> {
    read_underlay_from(&Inputs::file_system(), source)
}

/// [`read_underlay`], a file read from `inputs`.
pub fn read_underlay_from(
    inputs: &Inputs,
    source: &Option<UnderlaySource>,
) -> Result<Option<ScalarVolume>, LoadError> {
    match source {
        Some(UnderlaySource::File(path)) => {
            crate::field::read_scalar_volume_from(inputs, path).map(Some)
        }
        Some(UnderlaySource::Volume(v)) => Ok(Some((*v.volume).clone())),
        _ => Ok(None),
    }
}

/// The underlay of `built`'s planes, added to its scene, with the frame grown to hold it.
fn add_underlay(
    built: &mut Built,
    field: &TensorField,
    set: &GlyphSet,
    recipe: &Recipe,
    selection: &Selection,
    volume: Option<&ScalarVolume>,
) -> Result<(), StageError> {
    let Some(source) = &recipe.underlay else {
        return Ok(());
    };
    let values = match (source, volume) {
        (UnderlaySource::Measure(m), _) => Values::Measure(*m),
        (UnderlaySource::File(_) | UnderlaySource::Volume(_), Some(v)) => Values::Volume(v),
        (UnderlaySource::File(_) | UnderlaySource::Volume(_), None) => {
            unreachable!("the volume is read first")
        }
    };
    let planes = selection.slicing.planes().ok_or(UnderlayError::NoLattice)?;
    let u = underlay::build(
        field,
        set,
        &values,
        source.to_string(),
        &planes,
        &built.scene,
        recipe.underlay_side.unwrap_or(underlay::MAX_TEXELS),
    )?;
    built.scene.underlay = Some(u);
    // The scene's bounds hold what it draws (near and far planes are fitted to them).
    built.scene.half = holding_underlay(&built.scene, built.scene.centre, built.scene.half);
    built.scene.radius = built.scene.half.length();
    built.frame_half = holding_underlay(&built.scene, built.frame_centre, built.frame_half);
    built.frame_radius = built.frame_half.length();
    Ok(())
}

/// The half extents `half` of a box at `centre` grown to hold the scene's underlay images
/// wherever they are placed (up to `behind` off their plane).
fn holding_underlay(scene: &Scene, centre: DVec3, half: DVec3) -> DVec3 {
    let planes = scene.underlay.iter().flat_map(|u| &u.planes);
    planes.fold(half, |h, p| {
        let g = p.geometry;
        [
            g.corner,
            g.corner + g.u,
            g.corner + g.v,
            g.corner + g.u + g.v,
        ]
        .iter()
        .fold(h, |h, c| {
            h.max((*c - centre).abs() + DVec3::splat(g.behind))
        })
    })
}

/// Wall-clock milliseconds of each stage.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timings {
    /// Reading the file or generating the demo field.
    pub load: f64,
    /// Eigendecomposition of every tensor (`derive_glyphs`).
    pub eigen: f64,
    /// Selection, style and `Scene::build` (and the whole field's bounds when a selection is
    /// drawn).
    pub scene: f64,
    /// Uploading the instances to the GPU (0 for the CPU reference).
    pub upload: f64,
    /// The first frame: targets, pipelines, draw and read-back.
    pub first_frame: f64,
    /// Peak resident set size (VmHWM) after each stage, in the order of [`Self::stages`].
    #[serde(skip)]
    pub peak_rss_after: [Option<u64>; 5],
}

impl Timings {
    /// (stage name, ms) in pipeline order.
    pub fn stages(&self) -> [(&'static str, f64); 5] {
        [
            ("load", self.load),
            ("eigen", self.eigen),
            ("scene", self.scene),
            ("upload", self.upload),
            ("first_frame", self.first_frame),
        ]
    }

    /// "after load … ms, …": the stages that ran, and the peak memory so far, on one line.
    pub fn describe(&self) -> String {
        let ran: Vec<String> = self
            .stages()
            .iter()
            .filter(|(_, ms)| *ms > 0.0)
            .map(|(name, ms)| format!("{name} {ms:.0} ms"))
            .collect();
        let peak = crate::mem::peak_rss_bytes().map_or(String::new(), |b| {
            format!(", peak RSS {:.0} MiB", b as f64 / 1048576.0)
        });
        format!("after {}{peak}", ran.join(", "))
    }
}

pub(crate) fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// A scene, the bounds the camera frames, and what it took.
pub struct Staged {
    pub scene: Scene,
    /// Bounding box (`frame_centre ± frame_half`) and sphere of the whole field (every valid
    /// glyph), which the camera frames so a selection is drawn in place.
    pub frame_centre: DVec3,
    pub frame_radius: f64,
    pub frame_half: DVec3,
    /// Valid tensors (glyphs before the selection).
    pub glyphs_valid: usize,
    /// Glyphs the selection kept (the scene's instances).
    pub glyphs_selected: usize,
    /// Of those, glyphs `--scale auto` scaled down to the size of the robust largest one.
    pub glyphs_clamped: usize,
    /// With one slice shown: how to see it face-on.
    pub face: Option<FaceOn>,
    /// The style with the field's numbers fixed (for the legend).
    pub style: ResolvedStyle,
    pub timings: Timings,
    /// Every file read (the field's, with its detached data, pieces or set, and the
    /// underlay's): no output may replace one.
    pub read: Vec<PathBuf>,
}

/// One lattice slice seen face-on: the view's (direction, up) and the bounding box and sphere
/// of the slice's glyphs and underlay, to frame it closely.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceOn {
    pub toward: (DVec3, DVec3),
    pub centre: DVec3,
    pub radius: f64,
    pub half: DVec3,
}

/// Read the file (or make the demo field).
pub fn read(
    source: &Source,
    opts: &ReadOptions,
    progress: &dyn Progress,
) -> Result<TensorField, LoadError> {
    read_from(&Inputs::file_system(), source, opts, progress)
}

/// [`read`], a file read from `inputs` (which record the files read).
pub fn read_from(
    inputs: &Inputs,
    source: &Source,
    opts: &ReadOptions,
    progress: &dyn Progress,
) -> Result<TensorField, LoadError> {
    let field = run_stage(progress, "reading", None, || source.load_from(inputs, opts))?;
    for note in &field.meta.notes {
        progress.notice(&format!(
            "{}: {note}",
            crate::error::escape_path(std::path::Path::new(&source.name()))
        ));
    }
    Ok(field)
}

/// Eigendecompose every tensor.
pub fn decompose(field: &TensorField, progress: &dyn Progress) -> GlyphSet {
    run_stage(
        progress,
        "eigendecomposition",
        Some(field.len() as u64),
        || derive_glyphs(field, progress),
    )
}

/// Every stage once: read, decompose, select, style and build; the field's tensors are freed
/// once decomposed, the rest of the field and the glyphs when this returns.
pub fn stage(
    source: &Source,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Staged, StageError> {
    recipe.selection.check()?;
    let kind = source.kind(&recipe.read);
    if recipe.peaks_over && (kind != FieldKind::Series || recipe.peaks) {
        let why = if recipe.peaks {
            "--glyph peaks draws the peaks alone"
        } else if kind == FieldKind::Peaks {
            "a file of peaks is drawn as its sticks alone"
        } else {
            "tensors have no ODFs (--glyph peaks draws their principal directions)"
        };
        return Err(StageError::Selection(SelectionError(format!(
            "{}: --peaks draws the peaks of SH series over their ODF glyphs; {why}",
            crate::error::escape_path(Path::new(&source.name()))
        ))));
    }
    match source {
        Source::File(path) if kind == FieldKind::Series && recipe.peaks => {
            return peaks::stage_series_peaks(&Inputs::file_system(), path, recipe, progress);
        }
        Source::Bytes(b) if kind == FieldKind::Series && recipe.peaks => {
            let (inputs, path) = b.inputs();
            return peaks::stage_series_peaks(&inputs, &path, recipe, progress);
        }
        Source::File(path) if kind == FieldKind::Series => {
            return sh::stage_sh(&Inputs::file_system(), path, recipe, progress);
        }
        Source::Bytes(b) if kind == FieldKind::Series => {
            let (inputs, path) = b.inputs();
            return sh::stage_sh(&inputs, &path, recipe, progress);
        }
        Source::File(path) if kind == FieldKind::Peaks => {
            return peaks::stage_peaks(&Inputs::file_system(), path, recipe, progress);
        }
        Source::Bytes(b) if kind == FieldKind::Peaks => {
            let (inputs, path) = b.inputs();
            return peaks::stage_peaks(&inputs, &path, recipe, progress);
        }
        _ => {}
    }
    if recipe.odf_normalize.is_some() && !kind.offers().normalize {
        return Err(StageError::Selection(SelectionError(format!(
            "{}: --odf-normalize applies to files of SH series (fibre ODFs), not to tensors",
            crate::error::escape_path(Path::new(&source.name()))
        ))));
    }
    let mut timings = Timings::default();

    let inputs = Inputs::file_system();
    let t = Instant::now();
    let field = read_from(&inputs, source, &recipe.read, progress)?;
    timings.load = ms(t);
    timings.peak_rss_after[0] = crate::mem::peak_rss_bytes();
    // Lattice checks before the long part.
    recipe.selection.check_field(&field)?;

    let t = Instant::now();
    let set = decompose(&field, progress);
    let field = field.into_geometry();
    timings.eigen = ms(t);
    timings.peak_rss_after[1] = crate::mem::peak_rss_bytes();

    let t = Instant::now();
    let volume = read_underlay_from(&inputs, &recipe.underlay)?;
    let built = build(
        &field,
        &set,
        field_spacing(&field),
        recipe,
        volume.as_ref(),
        progress,
    )
    .map_err(|e| match e {
        // Nothing to draw is about the data: say which.
        e @ (StageError::EmptySelection { .. } | StageError::NoValidTensor) => StageError::Of {
            name: crate::error::escape_path(std::path::Path::new(&source.name())),
            error: Box::new(e),
        },
        e => e,
    })?;
    drop(field);
    drop(set);
    timings.scene = ms(t);
    timings.peak_rss_after[2] = crate::mem::peak_rss_bytes();
    Ok(Staged::of(built, timings, &inputs))
}

/// A scene built from a field and glyphs that stay (the viewer's).
pub struct Built {
    pub scene: Scene,
    /// Instances `--scale auto` scaled down to the robust largest size.
    pub glyphs_clamped: usize,
    /// Glyph k of the scene (its instances' `glyph`) is glyph `selected[k]` of the set.
    pub selected: Vec<usize>,
    /// Bounding box (`frame_centre ± frame_half`) and sphere of the whole field.
    pub frame_centre: DVec3,
    pub frame_radius: f64,
    pub frame_half: DVec3,
    pub glyphs_valid: usize,
    /// With one slice shown: how to see it face-on.
    pub face: Option<FaceOn>,
    /// The style with the field's numbers fixed (for the legend).
    pub style: ResolvedStyle,
}

impl Built {
    fn whole((scene, clamped): (Scene, usize), valid: usize, style: ResolvedStyle) -> Self {
        Self {
            style,
            glyphs_clamped: clamped,
            frame_centre: scene.centre,
            frame_radius: scene.radius,
            frame_half: scene.half,
            selected: (0..valid).collect(),
            glyphs_valid: valid,
            face: None,
            scene,
        }
    }

    fn selected(
        (scene, clamped): (Scene, usize),
        (c, half): (DVec3, DVec3),
        valid: usize,
        selected: Vec<usize>,
        style: ResolvedStyle,
    ) -> Self {
        Self {
            style,
            scene,
            glyphs_clamped: clamped,
            selected,
            frame_centre: c,
            frame_radius: half.length(),
            frame_half: half,
            glyphs_valid: valid,
            face: None,
        }
    }
}

/// Select, style and build from a field and its glyphs, keeping both; `volume` is the
/// underlay file's, read by [`read_underlay`].
pub fn build(
    field: &TensorField,
    set: &GlyphSet,
    spacing: impl Into<Spacing>,
    recipe: &Recipe,
    volume: Option<&ScalarVolume>,
    progress: &dyn Progress,
) -> Result<Built, StageError> {
    let mut resolved = recipe.style.resolve(set, spacing);
    if resolved.units.is_none() {
        resolved.units = units_in_name(&field.array.name);
    }
    let selection = recipe.selection_for(field);
    let indices = select(field, set, &selection)?;
    let mut built = if recipe.peaks {
        let step = field
            .spacing
            .filter(|s| s.is_finite() && *s > 0.0)
            .ok_or_else(|| {
                StageError::Selection(SelectionError(
                "--glyph peaks: the sticks of tensors need a lattice (they are a fraction of its \
                 step long)"
                    .into(),
            ))
            })?;
        let scene =
            peaks::tensor_sticks(set, indices.as_deref(), step, &recipe.style, recipe.glyph)?;
        let bounds = whole_field_bounds(set, &resolved, recipe.glyph, progress);
        let selected = indices.unwrap_or_else(|| (0..set.glyphs.len()).collect());
        Built::selected((scene, 0), bounds, set.glyphs.len(), selected, resolved)
    } else {
        match indices {
            None => Built::whole(
                build_scene(set, &resolved, recipe.glyph, progress),
                set.glyphs.len(),
                resolved,
            ),
            Some(indices) => {
                let bounds = whole_field_bounds(set, &resolved, recipe.glyph, progress);
                let subset = Selection::subset(set, &indices);
                let scene = build_scene(&subset, &resolved, recipe.glyph, progress);
                Built::selected(scene, bounds, set.glyphs.len(), indices, resolved)
            }
        }
    };
    add_underlay(&mut built, field, set, recipe, &selection, volume)?;
    built.face = face_on(&built, field, &selection);
    Ok(built)
}

/// How to see the one slice `selection` shows face-on, framing its glyphs and underlay.
fn face_on(built: &Built, field: &TensorField, selection: &Selection) -> Option<FaceOn> {
    let planes = selection.slicing.planes()?;
    let [plane] = planes.as_slice() else {
        return None;
    };
    let toward = underlay::face_on(field, *plane)?;
    let scene = &built.scene;
    Some(FaceOn {
        toward,
        centre: scene.centre,
        radius: scene.radius,
        half: scene.half,
    })
}

/// The glyphs `selection` keeps (`None`: all of them); an error when it keeps none or there is
/// none to keep.
fn select(
    field: &TensorField,
    set: &GlyphSet,
    selection: &Selection,
) -> Result<Option<Vec<usize>>, StageError> {
    let valid = set.glyphs.len();
    let indices = (!selection.is_everything()).then(|| selection.select(field, set));
    if indices.as_ref().is_some_and(|i| i.is_empty()) {
        return Err(StageError::EmptySelection {
            asked: selection.describe(),
            valid,
        });
    }
    if valid == 0 {
        return Err(StageError::NoValidTensor);
    }
    Ok(indices)
}

/// The scene of `set`, and how many of its glyphs the style clamps.
fn build_scene(
    set: &GlyphSet,
    style: &ResolvedStyle,
    glyph: GlyphKind,
    progress: &dyn Progress,
) -> (Scene, usize) {
    use rayon::prelude::*;
    let scene = run_stage(progress, "scene", Some(set.glyphs.len() as u64), || {
        Scene::build_with_progress(set, style, glyph, progress)
    });
    let clamped = set.glyphs.par_iter().filter(|g| style.clamps(g)).count();
    (scene, clamped)
}

/// The whole field's bounding sphere, without building its scene.
fn whole_field_bounds(
    set: &GlyphSet,
    style: &ResolvedStyle,
    glyph: GlyphKind,
    progress: &dyn Progress,
) -> (DVec3, DVec3) {
    run_stage(progress, "bounds of the whole field", None, || {
        Scene::bounding_box(set, style, glyph)
    })
}
