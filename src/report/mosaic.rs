//! A tensor figure of a report (laid out as every row is, `row`): a row of slices of
//! one orientation (axial, coronal or sagittal), each glyphs over the FA underlay in DEC colours with the anatomical directions at its edges
//! and its slice named, then a zoomed inset of one region of one of them (outlined in cyan on
//! its slice; [`super::inset`]), and a legend panel (the DEC key, the underlay's grey scale,
//! the overview's pixels per voxel) beside the row, all drawn into the image so that the PNG
//! reads alone.
//!
//! Every tile is built from the field and glyphs the report read and decomposed once
//! ([`crate::staging::build`]) and drawn with the run's one back end; tiles of a row share the
//! whole field's framing, so they are drawn at one scale.

use glam::DVec3;
use web_time::Instant;

use super::Options;
use super::inset::{self, Region, ZoomRegion};
pub use super::lattice::{ORIENTATIONS, Orientation, edge_labels, lattice_axis, slices};
use super::lattice::{lattice_box, position_in};
use super::row::{self, LEGEND_WIDTH};
pub use super::row::{FigureError, InsetInfo, Mosaic, OUTLINE};
use crate::backend::Backend;
use crate::camera::{Camera, Framing};
use crate::effects::Effects;
use crate::field::TensorField;
use crate::frame::Frame;
use crate::glyph::{ColorScheme, GlyphSet, GlyphStyle, SizeBy};
use crate::legend::raster::{Canvas, Pen};
use crate::progress::Progress;
use crate::request::{FrameRequest, GlyphKind, Method, Preset, UnderlayView};
use crate::scene::UnderlaySource;
use crate::scene::underlay::UnderlayError;
use crate::select::{Plane, Selection, Slicing};
use crate::staging::{self, FaceOn, Recipe, StageError, Timings, field_spacing};
use crate::tensor::measure::Measure;

/// Slices per row.
pub const SLICES: usize = 5;
pub(super) const BLACK: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// The style of every report figure: DEC colours, every glyph the same size (as `render`
/// shows DTI files).
pub(crate) fn style() -> GlyphStyle {
    GlyphStyle {
        color: ColorScheme::Dec,
        size_by: SizeBy::None,
        ..GlyphStyle::default()
    }
}

/// One slice drawn face-on: its frame, the camera, the underlay's window and the glyphs drawn.
pub struct Drawn {
    pub frame: Frame,
    pub camera: Camera,
    pub window: Option<[f32; 2]>,
    pub glyphs_drawn: usize,
}

/// Draw slice `plane` of `set` face-on with the camera `frame_it` makes of how the slice is seen
/// (view direction and up) and its scene; the FA underlay in `window` (its own when `None`).
/// `None` when the slice has nothing to draw.
#[allow(clippy::too_many_arguments)]
fn draw_slice(
    field: &TensorField,
    set: &GlyphSet,
    plane: Plane,
    window: Option<[f32; 2]>,
    underlay_missing: &mut Option<UnderlayError>,
    backend: &Backend,
    progress: &dyn Progress,
    frame_it: impl FnOnce((DVec3, DVec3), &FaceOn) -> Camera,
) -> Result<Option<Drawn>, FigureError> {
    if set.glyphs.is_empty() {
        return Ok(None);
    }
    let spacing = field_spacing(field);
    let recipe = Recipe {
        style: style(),
        selection: Selection {
            slicing: Slicing::Planes(vec![plane]),
            ..Selection::default()
        },
        glyph: GlyphKind::default(),
        underlay: Some(UnderlaySource::Measure(Measure::Fa)),
        ..Recipe::default()
    };
    let built = match staging::build(field, set, spacing.clone(), &recipe, None, progress) {
        // A lattice whose planes are not evenly spaced (rectilinear data) has no image to put
        // under its glyphs: the glyphs alone, as the page says.
        Err(StageError::Underlay(why)) => {
            *underlay_missing = Some(why);
            let recipe = Recipe {
                underlay: None,
                ..recipe
            };
            staging::build(field, set, spacing, &recipe, None, progress)?
        }
        built => built?,
    };
    let Some(face) = built.face else {
        return Ok(None);
    };
    let camera = frame_it(face.toward, &face);
    let mut scene = built.scene;
    let window = window.or(scene.underlay.as_ref().map(|u| u.window));
    let (frame, glyphs_drawn) = draw_scene(&mut scene, &camera, window, backend, progress)?;
    Ok(Some(Drawn {
        frame,
        camera,
        window: scene.underlay.as_ref().and(window),
        glyphs_drawn,
    }))
}

/// Draw `scene` (sorted front to back for the splats) as every report tile is drawn: on black,
/// one frame, its underlay (if any) in `window`; the frame and the glyphs drawn (those of the
/// scene's own kind in view, not culled: not the sticks over ODFs).
pub(super) fn draw_scene(
    scene: &mut crate::scene::Scene,
    camera: &Camera,
    window: Option<[f32; 2]>,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<(Frame, usize), FigureError> {
    scene.sort_front_to_back(camera);
    let req = backend.adapt(
        FrameRequest {
            background: BLACK,
            frames: 1,
            underlay: UnderlayView {
                shown: true,
                window,
            },
            effects: Effects::default().resolved(),
            ..FrameRequest::preset(Method::Gumhold, true, Preset::Splat)
        },
        scene,
        camera,
    );
    let frame = backend.render(scene, camera, &req, &mut Timings::default(), progress)?;
    // The scene's own kind's glyphs (not the sticks over ODFs).
    let own = scene.parts()[0].1.clone();
    let n = own.len();
    let v = scene.visibility_of(own, camera, req.cull, req.min_pixel_radius);
    let glyphs_drawn = n - v.eye_inside - v.behind_camera - v.degenerate - v.culled;
    Ok((frame, glyphs_drawn))
}

/// Draw `region`'s glyphs (and nothing else of the slice) face-on in the inset's square, under
/// the FA underlay in `window` (the overview's, so that its greys are the overview's).
pub fn draw_inset(
    field: &TensorField,
    set: &GlyphSet,
    dims: [usize; 3],
    region: &Region,
    window: Option<[f32; 2]>,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<Option<Drawn>, FigureError> {
    let at = position_in(field, dims);
    let side = inset::side(&at, dims, region);
    let plane = Plane {
        axis: region.axis,
        index: region.slice(),
    };
    draw_slice(
        field,
        &inset::glyphs_in(set, dims, region),
        plane,
        window,
        &mut None,
        backend,
        progress,
        |toward, _| inset::camera(&at, dims, region, toward, side),
    )
}

/// The region the inset of the row along lattice `axis` shows: the one asked for, or the
/// square of [`inset::DEFAULT_SIZE`] voxels of the middle slice where FA is highest.
pub fn inset_region(
    set: &GlyphSet,
    dims: [usize; 3],
    axis: usize,
    slices: &[usize],
    zoom: Option<ZoomRegion>,
) -> Result<Option<Region>, FigureError> {
    Ok(match zoom {
        Some(z) => Some(inset::given(z, dims, axis)?),
        None => slices
            .get(slices.len() / 2)
            .map(|&s| inset::brightest(set, dims, axis, s, inset::DEFAULT_SIZE)),
    })
}

/// Draw the figure of `orientation`: `field` (its geometry) and `set`, its glyphs, in
/// `options.tile`-pixel tiles, with the inset beside them.
#[allow(clippy::too_many_arguments)]
pub fn render(
    field: &TensorField,
    set: &GlyphSet,
    dims: [usize; 3],
    orientation: Orientation,
    anatomical: bool,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<Mosaic, FigureError> {
    let t = Instant::now();
    let axis = lattice_axis(field, dims, orientation.world_axis);
    let slices = slices(set, dims, axis, SLICES);
    let region = inset_region(set, dims, axis, &slices, options.zoom)?;
    let at = position_in(field, dims);
    let mut row = TensorRow {
        field,
        set,
        dims,
        lattice: lattice_box(field, dims),
        orientation,
        anatomical,
        window: None,
        underlay_missing: None,
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
        chosen_by: options.zoom.is_none().then_some("FA"),
    };
    let mosaic = row::compose(plan, &mut row, t)?;
    Ok(Mosaic {
        underlay_missing: row.underlay_missing,
        ..mosaic
    })
}

/// A tensor row: glyphs over the FA underlay (the first tile's window for the inset and the
/// legend), DEC colours.
struct TensorRow<'a> {
    field: &'a TensorField,
    set: &'a GlyphSet,
    dims: [usize; 3],
    lattice: (DVec3, DVec3),
    orientation: Orientation,
    anatomical: bool,
    window: Option<[f32; 2]>,
    underlay_missing: Option<UnderlayError>,
    backend: &'a Backend,
    progress: &'a dyn Progress,
}

impl row::Row for TensorRow<'_> {
    fn tile(
        &mut self,
        plane: Plane,
        tile: u32,
        _inset: Option<&Region>,
    ) -> Result<Option<row::Drawn>, FigureError> {
        let lattice = self.lattice;
        let d = draw_slice(
            self.field,
            self.set,
            plane,
            None,
            &mut self.underlay_missing,
            self.backend,
            self.progress,
            |toward, face| tile_camera(lattice, toward, face.centre, tile),
        )?;
        Ok(d.map(|d| {
            self.window = self.window.or(d.window);
            (d.frame, d.camera, d.glyphs_drawn)
        }))
    }

    fn inset(&mut self, region: &Region, _side: u32) -> Result<Option<row::Drawn>, FigureError> {
        let (field, set, dims) = (self.field, self.set, self.dims);
        let d = draw_inset(
            field,
            set,
            dims,
            region,
            self.window,
            self.backend,
            self.progress,
        )?;
        Ok(d.map(|d| (d.frame, d.camera, d.glyphs_drawn)))
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
            self.anatomical,
            self.window,
            px_per_voxel,
            inset,
        );
    }
}

/// The camera of an overview tile of `tile` pixels showing the slice seen along `toward` whose
/// glyphs are centred at `centre`: the lattice's box moved onto this slice, seen without
/// perspective, so that every tile of a row is at one scale.
pub(super) fn tile_camera(
    lattice: (DVec3, DVec3),
    toward: (DVec3, DVec3),
    centre: DVec3,
    tile: u32,
) -> Camera {
    let normal = toward.0;
    let centre = lattice.0 + normal * normal.dot(centre - lattice.0);
    let framing = Framing {
        toward: Some(toward),
        ortho: true,
        // Room at the edges for the labels.
        zoom: 0.8,
        ..Framing::default()
    };
    Camera::frame_box(&framing, centre, lattice.1, tile, tile)
}

/// The legend panel at `x0`, `height` tall: the row's name, the DEC key, the underlay's grey
/// scale and the overview's pixels per voxel.
#[allow(clippy::too_many_arguments)]
fn legend(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    (x0, height): (u32, u32),
    orientation: Orientation,
    anatomical: bool,
    window: Option<[f32; 2]>,
    px_per_voxel: f64,
    inset: bool,
) {
    let (x, w) = (f64::from(x0) + 10.0, f64::from(LEGEND_WIDTH) - 20.0);
    canvas.rect(
        i64::from(x0),
        0,
        i64::from(LEGEND_WIDTH),
        i64::from(height),
        [0.12; 3],
    );
    let lh = pen.line_height();
    let ink = [1.0; 3];
    let mut y = 6.0;
    pen.draw(canvas, x, y, orientation.name, ink);
    y += lh * 1.3;
    y = direction_key(canvas, pen, (x, y), "colour = |e1| × FA", anatomical);
    y += lh * 0.3;
    let [lo, hi] = window.unwrap_or([0.0, 1.0]);
    pen.draw(canvas, x, y, "underlay: FA", ink);
    y += lh;
    let bar_h = lh * 0.7;
    for k in 0..w as i64 {
        let g = k as f64 / (w - 1.0);
        canvas.rect(x as i64 + k, y as i64, 1, bar_h as i64, [g; 3]);
    }
    y += bar_h + 2.0;
    let (a, b) = (format!("{lo:.2}"), format!("{hi:.2}"));
    pen.draw(canvas, x, y, &a, ink);
    pen.draw(canvas, x + w - pen.width(&b), y, &b, ink);
    y += lh * 1.3;
    if px_per_voxel.is_finite() {
        let line = format!("tiles: {px_per_voxel:.1} px/voxel");
        pen.draw(canvas, x, y, &line, ink);
        y += lh;
    }
    if inset {
        inset_key(canvas, pen, x, y, bar_h);
    }
}

/// The direction colour key at (`x`, `y`), tensor and ODF rows alike: `title`, then a swatch
/// for each world axis (R–L, A–P, S–I, or x, y, z off an anatomical world); returns where the
/// next line goes.
pub(super) fn direction_key(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    (x, y): (f64, f64),
    title: &str,
    anatomical: bool,
) -> f64 {
    let (lh, ink) = (pen.line_height(), [1.0; 3]);
    pen.draw(canvas, x, y, title, ink);
    let mut y = y + lh;
    let names = if anatomical {
        ["R–L", "A–P", "S–I"]
    } else {
        ["x", "y", "z"]
    };
    let swatch = lh * 0.7;
    for (k, name) in names.into_iter().enumerate() {
        let mut c = [0.0; 3];
        c[k] = 1.0;
        canvas.rect(
            x as i64,
            (y + (lh - swatch) / 2.0) as i64,
            swatch as i64,
            swatch as i64,
            c,
        );
        pen.draw(canvas, x + swatch + 6.0, y, name, ink);
        y += lh;
    }
    y
}

/// The legend's key to the inset's outline at (`x`, `y`), its swatch `side` pixels.
pub(super) fn inset_key(canvas: &mut Canvas<'_>, pen: &Pen<'_>, x: f64, y: f64, side: f64) {
    let lh = pen.line_height();
    canvas.rect(
        x as i64,
        (y + (lh - side) / 2.0) as i64,
        side as i64,
        side as i64,
        OUTLINE,
    );
    pen.draw(canvas, x + side + 6.0, y, "the inset's region", [1.0; 3]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ViewPreset;

    #[test]
    fn edges_name_the_world_directions_the_views_show() {
        // Neurological convention, as the views are defined: the subject's right on the right.
        let (f, u) = ViewPreset::Axial.direction_up();
        assert_eq!(edge_labels(f, u, true), ["L", "R", "A", "P"]);
        let (f, u) = ViewPreset::Coronal.direction_up();
        assert_eq!(edge_labels(f, u, true), ["L", "R", "S", "I"]);
        let (f, u) = ViewPreset::Sagittal.direction_up();
        assert_eq!(edge_labels(f, u, true), ["A", "P", "S", "I"]);
        assert_eq!(edge_labels(f, u, false), ["+y", "−y", "+z", "−z"]);
    }
}
