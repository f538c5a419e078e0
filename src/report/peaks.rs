//! A peaks map's part of a report (MRtrix's `sh2peaks` images, DIPY's peaks, [`PeakField`]):
//! the map read once, how many peaks its voxels hold (every voxel: counting is cheap), and three
//! figures of sticks as `render` draws a peaks file ([`staging::build_peaks`]: one stick a peak
//! through its voxel's centre, the map's largest peak one voxel step long, coloured by
//! direction), laid out as the other rows are (`row`): up to [`mosaic::SLICES`] slices
//! through the voxels that hold a peak, face-on, and the zoomed inset of the square of the middle
//! slice where the peaks' amplitudes sum highest (or `--zoom-region`'s), its sticks cut from its
//! slice's scene.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Serialize;
use web_time::Instant;

use super::mosaic::{self, FigureError, Mosaic, ORIENTATIONS, Orientation};
use super::odf::{preset_view, scene_in};
use super::{FigureReport, Options, UnitError, figure, file_stem, inset, lattice, row};
use crate::backend::Backend;
use crate::camera::Camera;
use crate::field::{Inputs, PeakField, ReadOptions};
use crate::legend::raster::{Canvas, Pen};
use crate::progress::{Progress, Silent};
use crate::scene::Scene;
use crate::select::{Plane, Selection, Slicing};
use crate::staging::{self, Recipe};

/// How many peaks the voxels holding any have.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeakCounts {
    /// Voxels holding at least one peak.
    pub held: usize,
    /// Mean peaks per voxel held.
    pub mean: f64,
    /// The share of the voxels held with one peak, two, and three or more.
    pub shares: [f64; 3],
}

impl PeakCounts {
    /// The share of voxels with two peaks or more: crossing (or fanning) fibres.
    pub fn crossing_share(&self) -> f64 {
        self.shares[1] + self.shares[2]
    }

    fn of(field: &PeakField) -> Self {
        let counts: Vec<usize> = (0..field.voxels())
            .map(|v| field.peaks_of(v).count())
            .filter(|&n| n > 0)
            .collect();
        let held = counts.len();
        let mut shares = [0.0; 3];
        for &n in &counts {
            shares[(n - 1).min(2)] += 1.0 / held as f64;
        }
        Self {
            held,
            mean: counts.iter().sum::<usize>() as f64 / held.max(1) as f64,
            shares,
        }
    }
}

/// A peaks map's part of a report.
pub struct PeaksReport {
    pub name: String,
    pub path: String,
    pub session: Option<String>,
    pub format: String,
    /// Peaks a voxel can hold.
    pub per_voxel: usize,
    /// The axes the directions are in, and the world and its source.
    pub frame: String,
    pub anatomical: bool,
    pub dims: [usize; 3],
    pub counts: PeakCounts,
    pub read_ms: f64,
    pub figures: Vec<FigureReport>,
}

/// Read the peaks map at `path` once and draw its figures.
pub(super) fn map(
    path: &Path,
    session: Option<String>,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
    read: &mut Vec<PathBuf>,
) -> Result<PeaksReport, UnitError> {
    let inputs = Inputs::file_system();
    let t = Instant::now();
    // A peaks map's name (BIDS: `param-peaks`) or header said it holds peaks: a NIfTI file of 9
    // volumes is read as three peaks, as `--holds peaks` reads it.
    let opts = ReadOptions {
        holds: Some(crate::field::FieldKind::Peaks),
        ..ReadOptions::default()
    };
    let field = crate::field::read_peak_field_from(&inputs, path, &opts)?;
    let read_ms = staging::ms(t);
    read.extend(inputs.paths_read());
    let counts = PeakCounts::of(&field);
    if counts.held == 0 {
        return Err(UnitError::NoPeaks(path.to_path_buf()));
    }
    let anatomical = field.frame.world == "RAS";
    let name = crate::error::escape_path(path);
    let stem = file_stem(path);
    let mut figures = Vec::new();
    for o in ORIENTATIONS {
        let m = render(&field, &name, o, anatomical, options, backend, progress)?;
        figures.push(figure(path, &stem, o.name, m)?);
    }
    let f = &field.frame;
    Ok(PeaksReport {
        name: path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        path: path.display().to_string(),
        session,
        format: field.format.clone(),
        per_voxel: field.per_voxel,
        frame: format!(
            "directions in {} axes; world {} from {}",
            f.tensor_frame.name(),
            f.world,
            f.source
        ),
        anatomical,
        dims: field.dims,
        counts,
        read_ms,
        figures,
    })
}

/// The world position of voxel (i, j, k) of `field`.
fn position(field: &PeakField) -> impl Fn([usize; 3]) -> DVec3 + '_ {
    let d = field.dims;
    move |c| DVec3::from(field.position(c[0] + d[0] * (c[1] + d[1] * c[2])))
}

/// The figure of `orientation`: `tile`-pixel tiles of sticks, with the inset of `zoom` (or of
/// where the peaks' amplitudes sum highest) beside them.
fn render(
    field: &PeakField,
    name: &str,
    orientation: Orientation,
    anatomical: bool,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<Mosaic, FigureError> {
    let t = Instant::now();
    let dims = field.dims;
    let at = position(field);
    let axis = lattice::lattice_axis_of(&at, dims, orientation.world_axis);
    let mut count = vec![0usize; dims[axis]];
    let mut amplitude = vec![0.0f64; field.voxels()];
    for (v, a) in amplitude.iter_mut().enumerate() {
        *a = field
            .peaks_of(v)
            .map(|x| f64::from(glam::Vec3::from(x).length()))
            .sum();
        if *a > 0.0 {
            count[crate::select::lattice_coords(v, dims)[axis]] += 1;
        }
    }
    let slices = lattice::slices_of(&count, mosaic::SLICES);
    let region = match options.zoom {
        Some(z) => Some(inset::given(z, dims, axis)?),
        None => slices.get(slices.len() / 2).map(|&s| {
            let values = amplitude
                .iter()
                .enumerate()
                .map(|(v, &a)| (crate::select::lattice_coords(v, dims), a));
            inset::brightest_of(values, dims, axis, s, inset::DEFAULT_SIZE)
        }),
    };
    let mut row = PeaksRow {
        field,
        name,
        at: &at,
        lattice: lattice::lattice_box_of(&at, dims),
        orientation,
        anatomical,
        cut: None,
        backend,
        progress,
    };
    let plan = row::Plan {
        at: &at,
        dims,
        axis,
        slices,
        region,
        orientation,
        anatomical,
        tile: options.tile,
        chosen_by: options
            .zoom
            .is_none()
            .then_some("the peaks' summed amplitude"),
    };
    row::compose(plan, &mut row, t)
}

/// A peaks row: each slice's sticks; the inset's are cut from its slice's scene.
struct PeaksRow<'a> {
    field: &'a PeakField,
    name: &'a str,
    at: inset::At<'a>,
    lattice: (DVec3, DVec3),
    orientation: Orientation,
    anatomical: bool,
    /// The inset's sticks (cut from its slice's scene) and the way that slice is seen.
    cut: Option<(Scene, (DVec3, DVec3))>,
    backend: &'a Backend,
    progress: &'a dyn Progress,
}

impl row::Row for PeaksRow<'_> {
    fn tile(
        &mut self,
        plane: Plane,
        tile: u32,
        inset: Option<&inset::Region>,
    ) -> Result<Option<row::Drawn>, FigureError> {
        // The sticks `render FILE --slice PLANE` draws: every stick of the map one scale.
        let recipe = Recipe {
            selection: Selection {
                slicing: Slicing::Planes(vec![plane]),
                ..Selection::default()
            },
            glyph: crate::field::FieldKind::Peaks.offers().glyphs[0],
            style: crate::glyph::GlyphStyle {
                color: crate::glyph::ColorScheme::Dec,
                ..Default::default()
            },
            ..Recipe::default()
        };
        let built = staging::build_peaks(self.field, self.name, &recipe)?;
        let mut scene = built.scene;
        if scene.instances.is_empty() {
            return Ok(None);
        }
        let toward = built
            .face
            .map_or_else(|| preset_view(self.orientation), |f| f.toward);
        let camera: Camera = mosaic::tile_camera(self.lattice, toward, scene.centre, tile);
        if let Some(r) = inset {
            self.cut = Some((scene_in(&scene, self.field.dims, r), toward));
        }
        let (frame, glyphs) =
            mosaic::draw_scene(&mut scene, &camera, None, self.backend, self.progress)?;
        Ok(Some((frame, camera, glyphs)))
    }

    fn inset(
        &mut self,
        region: &inset::Region,
        side: u32,
    ) -> Result<Option<row::Drawn>, FigureError> {
        let Some((mut scene, toward)) = self.cut.take().filter(|(s, _)| !s.instances.is_empty())
        else {
            return Ok(None);
        };
        let camera = inset::camera(self.at, self.field.dims, region, toward, side);
        let (frame, glyphs) = mosaic::draw_scene(&mut scene, &camera, None, self.backend, &Silent)?;
        Ok(Some((frame, camera, glyphs)))
    }

    fn legend(
        &self,
        canvas: &mut Canvas<'_>,
        pen: &Pen<'_>,
        (x0, height): (u32, u32),
        px_per_voxel: f64,
        inset: bool,
    ) {
        let w = row::LEGEND_WIDTH;
        let x = f64::from(x0) + 10.0;
        canvas.rect(i64::from(x0), 0, i64::from(w), i64::from(height), [0.12; 3]);
        let lh = pen.line_height();
        let ink = [1.0; 3];
        let mut y = 6.0;
        let mut line = |canvas: &mut Canvas<'_>, s: &str| {
            pen.draw(canvas, x, y, s, ink);
            y += lh;
        };
        line(canvas, &format!("{} peaks", self.orientation.name));
        line(canvas, &format!("up to {} a voxel", self.field.per_voxel));
        line(canvas, "length: amplitude");
        y += lh * 0.3;
        y = mosaic::direction_key(canvas, pen, (x, y), "colour = direction", self.anatomical);
        y += lh * 0.3;
        if px_per_voxel.is_finite() {
            pen.draw(
                canvas,
                x,
                y,
                &format!("tiles: {px_per_voxel:.1} px/voxel"),
                ink,
            );
            y += lh;
        }
        if inset {
            mosaic::inset_key(canvas, pen, x, y, lh * 0.7);
        }
    }
}
