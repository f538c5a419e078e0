//! One ODF figure of a report: a row of slices of one orientation of a field of SH series
//! (fibre ODFs), each slice's ODF glyphs drawn face-on as `render` draws a file of SH series
//! ([`crate::scene::odf`], framed by [`staging::sh_face_on`]) on black, with the anatomical
//! directions at its edges, its slice named, and a legend panel beside the row.
//!
//! The row is laid out as the tensor rows are (`row`; this module draws its tiles, inset
//! and legend): the same slice choice (up to [`mosaic::SLICES`] through the voxels that hold a
//! series), the same framing (every tile of a row at one scale), labels, back end and zoomed inset ([`super::inset`]: a square of one slice
//! at ≥ 8 pixels per voxel, outlined on its slice). There is no FA underlay (an SH series has
//! none). The inset's region is the one `--zoom-region` asks for or, by default, the square of
//! the middle slice where the fibre density (each ODF's l = 0 coefficient, MRtrix's AFD, the
//! same in every basis read) sums highest: white matter. Its glyphs are those of the overview's
//! scene of that slice, so a glyph has the same size in both (with `--odf-normalize none` too),
//! and the scene is built once; over them, the sticks of their peaks as `render --peaks` draws
//! them (found for the inset's voxels only; none over minmax-normalised ODFs).

use glam::DVec3;
use web_time::Instant;

use super::Options;
use super::inset;
use super::lattice;
use super::mosaic::{self, FigureError, Mosaic, Orientation};
use super::row;
use crate::backend::Backend;
use crate::camera::{Camera, ViewPreset};
use crate::field::ShField;
use crate::legend::raster::{Canvas, Pen};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::scene::odf::{OdfNormalize, OdfOptions, odf_scene};
use crate::select::Plane;
use crate::shape::odf::OdfColoring;
use crate::staging;

/// The world position of voxel (i, j, k) of `field`.
fn position(field: &ShField) -> impl Fn([usize; 3]) -> DVec3 + '_ {
    let d = field.dims;
    move |c| DVec3::from(field.position(c[0] + d[0] * (c[1] + d[1] * c[2])))
}

/// Which voxels hold a series that is not all zero: those [`odf_scene`] draws (a CSD fit
/// writes zeros outside its mask).
pub fn held(field: &ShField) -> Vec<bool> {
    let mut c = vec![0.0; field.layout.count];
    (0..field.voxels())
        .map(|v| {
            field.coefficients_of(v, &mut c);
            c.iter().any(|&x| x != 0.0)
        })
        .collect()
}

/// The orientation's view direction and up for a field whose affine gives no face-on view.
pub(super) fn preset_view(orientation: Orientation) -> (DVec3, DVec3) {
    match orientation.world_axis {
        0 => ViewPreset::Sagittal,
        1 => ViewPreset::Coronal,
        _ => ViewPreset::Axial,
    }
    .direction_up()
}

/// The fibre density of the voxels of slice `slice` along `axis` that hold a series: their
/// l = 0 coefficient (the first of every basis read).
fn density<'a>(
    field: &'a ShField,
    held: &'a [bool],
    axis: usize,
    slice: usize,
) -> impl Iterator<Item = ([usize; 3], f64)> + 'a {
    let mut c = vec![0.0; field.layout.count];
    held.iter().enumerate().filter_map(move |(v, &h)| {
        let ijk = crate::select::lattice_coords(v, field.dims);
        (h && ijk[axis] == slice).then(|| {
            field.coefficients_of(v, &mut c);
            (ijk, c[0])
        })
    })
}

/// The glyphs of `scene` (one slice's) whose voxels lie in `region`, sized as in `scene`.
pub(super) fn scene_in(scene: &Scene, dims: [usize; 3], region: &inset::Region) -> Scene {
    let kept = scene
        .instances
        .iter()
        .filter(|g| region.contains(crate::select::lattice_coords(g.glyph as usize, dims)))
        .copied()
        .collect();
    let mut s = Scene::from_instances_as(scene.origin, kept, scene.kind);
    s.payload = scene.payload.clone();
    s
}

/// Draw the ODF figure of `orientation` of `field` (`held`: [`held`] of it) as `options` say:
/// `tile`-pixel tiles, each voxel's ODF normalised and coloured as `odf_normalize` and
/// `odf_color` say, with the inset of `zoom` (or of where the fibre density is highest) beside
/// them.
pub fn render(
    field: &ShField,
    held: &[bool],
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
    for (v, _) in held.iter().enumerate().filter(|(_, h)| **h) {
        count[crate::select::lattice_coords(v, dims)[axis]] += 1;
    }
    let slices = lattice::slices_of(&count, mosaic::SLICES);
    let region = match options.zoom {
        Some(z) => Some(inset::given(z, dims, axis)?),
        None => slices.get(slices.len() / 2).map(|&s| {
            let values = density(field, held, axis, s);
            inset::brightest_of(values, dims, axis, s, inset::DEFAULT_SIZE)
        }),
    };
    let mut row = OdfRow {
        field,
        at: &at,
        lattice: lattice::lattice_box_of(&at, dims),
        orientation,
        anatomical,
        normalize: options.odf_normalize,
        coloring: options.odf_color,
        cut: None,
        inset_peaks: None,
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
            .then_some("the fibre density (l = 0)"),
    };
    row::compose(plan, &mut row, t)
}

/// An ODF row: each slice's ODF glyphs (no underlay); the inset's glyphs are cut from its
/// slice's scene.
struct OdfRow<'a> {
    field: &'a ShField,
    at: inset::At<'a>,
    lattice: (DVec3, DVec3),
    orientation: Orientation,
    anatomical: bool,
    normalize: OdfNormalize,
    coloring: OdfColoring,
    /// The inset's glyphs (cut from its slice's scene) and the way that slice is seen.
    cut: Option<(Scene, (DVec3, DVec3))>,
    /// The sticks of peaks drawn over the inset's ODFs.
    inset_peaks: Option<usize>,
    backend: &'a Backend,
    progress: &'a dyn Progress,
}

impl OdfRow<'_> {
    /// The sticks of the peaks of `region`'s voxels (on `plane`) to draw over its ODFs, about
    /// `origin`, as `render --peaks` draws them ([`staging::peaks_over_voxels`]); none over
    /// minmax-normalised ODFs, whose lobes are not as long as their peaks' values.
    fn peaks_in(
        &self,
        plane: Plane,
        region: &inset::Region,
        origin: DVec3,
    ) -> Result<Option<Scene>, FigureError> {
        if self.normalize == OdfNormalize::MinMax {
            return Ok(None);
        }
        let dims = self.field.dims;
        let over = staging::OverOdfs {
            normalize: self.normalize,
            solid: self.coloring == OdfColoring::Base,
            planes: Some(&[plane]),
        };
        let shown = |v| region.contains(crate::select::lattice_coords(v, dims));
        let name = &self.field.format;
        Ok(Some(staging::peaks_over_voxels(
            self.field, name, &over, &shown, origin,
        )?))
    }
}

impl row::Row for OdfRow<'_> {
    fn tile(
        &mut self,
        plane: Plane,
        tile: u32,
        inset: Option<&inset::Region>,
    ) -> Result<Option<row::Drawn>, FigureError> {
        let opts = OdfOptions {
            planes: Some(vec![plane]),
            normalize: self.normalize,
            coloring: self.coloring,
            ..OdfOptions::default()
        };
        let mut scene = odf_scene(self.field, &opts);
        if scene.instances.is_empty() {
            return Ok(None);
        }
        let toward = staging::sh_face_on(self.field, plane, &scene)
            .map_or_else(|| preset_view(self.orientation), |f| f.toward);
        let camera: Camera = mosaic::tile_camera(self.lattice, toward, scene.centre, tile);
        if let Some(r) = inset {
            let cut = scene_in(&scene, self.field.dims, r);
            let cut = match self.peaks_in(plane, r, cut.origin)? {
                Some(sticks) => cut.with_overlay(sticks),
                None => cut,
            };
            self.cut = Some((cut, toward));
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
        self.inset_peaks = scene.overlay.map(|o| scene.instances.len() - o.first);
        let camera = inset::camera(self.at, self.field.dims, region, toward, side);
        let (frame, glyphs) =
            mosaic::draw_scene(&mut scene, &camera, None, self.backend, self.progress)?;
        Ok(Some((frame, camera, glyphs)))
    }

    fn inset_peaks(&self) -> Option<usize> {
        self.inset_peaks
    }

    fn legend(
        &self,
        canvas: &mut Canvas<'_>,
        pen: &Pen<'_>,
        at: (u32, u32),
        px_per_voxel: f64,
        inset: bool,
    ) {
        legend(
            canvas,
            pen,
            at,
            self.orientation,
            self.field,
            (self.normalize, self.coloring),
            self.anatomical,
            px_per_voxel,
            inset,
        );
    }
}

/// The legend panel at `x0`, `height` tall: the row's name, what the glyphs are (lmax, basis,
/// normalisation), the colour key (directions, or viridis from 0 to the full radius) and the
/// tiles' pixels per voxel.
#[allow(clippy::too_many_arguments)]
fn legend(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    (x0, height): (u32, u32),
    orientation: Orientation,
    field: &ShField,
    (normalize, coloring): (OdfNormalize, OdfColoring),
    anatomical: bool,
    px_per_voxel: f64,
    inset: bool,
) {
    let w = row::LEGEND_WIDTH;
    let x = f64::from(x0) + 10.0;
    canvas.rect(i64::from(x0), 0, i64::from(w), i64::from(height), [0.12; 3]);
    let lh = pen.line_height();
    let ink = [1.0; 3];
    let mut y = 6.0;
    let line = |canvas: &mut Canvas<'_>, y: &mut f64, s: &str| {
        pen.draw(canvas, x, *y, s, ink);
        *y += lh;
    };
    line(canvas, &mut y, &format!("{} ODFs", orientation.name));
    y += lh * 0.3;
    line(canvas, &mut y, &format!("lmax {}", field.layout.lmax));
    line(canvas, &mut y, field.layout.basis.name());
    line(canvas, &mut y, &format!("normalised: {}", normalize.name()));
    y += lh * 0.3;
    if coloring == OdfColoring::Amplitude {
        line(canvas, &mut y, "colour = amplitude");
        // Viridis from 0 (left) to the full radius (right).
        let (bar_w, bar_h) = (f64::from(w) - 40.0, lh * 0.7);
        for px in 0..bar_w as i64 {
            let c = crate::glyph::colormap::viridis(px as f64 / (bar_w - 1.0));
            canvas.rect(x as i64 + px, y as i64, 1, bar_h as i64, c);
        }
        y += bar_h + 2.0;
        line(canvas, &mut y, "0 … 1 (full radius)");
    } else {
        y = mosaic::direction_key(canvas, pen, (x, y), "colour = direction", anatomical);
    }
    y += lh * 0.3;
    if px_per_voxel.is_finite() {
        line(
            canvas,
            &mut y,
            &format!("tiles: {px_per_voxel:.1} px/voxel"),
        );
    }
    if inset {
        mosaic::inset_key(canvas, pen, x, y, lh * 0.7);
        if normalize != OdfNormalize::MinMax {
            y += lh;
            let sticks = if coloring == OdfColoring::Base {
                "inset: peaks (sticks)"
            } else {
                "inset: peaks (white sticks)"
            };
            line(canvas, &mut y, sticks);
        }
    }
}
