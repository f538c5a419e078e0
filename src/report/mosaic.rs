//! One figure of a report: a row of slices of one orientation (axial, coronal or sagittal),
//! each glyphs over the FA underlay in DEC colours with the anatomical directions at its edges
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
use super::lattice::{lattice_box, position_in, slice_place};
use crate::backend::{Backend, StageFailed};
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

/// The labels' text height, in pixels, whatever the tiles' size.
pub(super) const LABEL_PX: f32 = 16.0;
/// The inset's outline on the overview and around the inset: a colour the DEC glyphs (scaled
/// by FA, shaded) and the grey underlay do not reach.
pub const OUTLINE: [f64; 3] = [0.0, 1.0, 1.0];
/// Slices per row.
pub const SLICES: usize = 5;
/// The legend panel's width, in pixels.
pub(super) const LEGEND_WIDTH: u32 = 200;
pub(super) const BLACK: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error(transparent)]
    Stage(#[from] StageError),
    #[error(transparent)]
    Render(#[from] StageFailed),
    #[error(transparent)]
    Zoom(#[from] inset::OutsideLattice),
}

/// A figure, RGBA8, and what it shows.
pub struct Mosaic {
    pub width: u32,
    pub height: u32,
    /// The overview tiles' side, in pixels.
    pub tile: u32,
    pub rgba: Vec<u8>,
    /// The lattice axis sliced (0: i, 1: j, 2: k) and the slices, in order.
    pub lattice_axis: usize,
    pub slices: Vec<usize>,
    /// Glyphs drawn, over all overview tiles.
    pub glyphs_drawn: usize,
    /// Pixels per voxel in the overview tiles (of the shorter voxel step across the slices).
    pub overview_px_per_voxel: f64,
    /// The zoomed inset, when the row has a slice.
    pub inset: Option<InsetInfo>,
    /// Wall-clock time to build and draw the row.
    pub ms: f64,
    /// Why the FA underlay could not be drawn, if it could not.
    pub underlay_missing: Option<UnderlayError>,
}

/// The style of every report figure: DEC colours, every glyph the same size (as `render`
/// shows DTI files).
pub(crate) fn style() -> GlyphStyle {
    GlyphStyle {
        color: ColorScheme::Dec,
        size_by: SizeBy::None,
        ..GlyphStyle::default()
    }
}

/// What a figure's inset shows and how.
#[derive(Debug, Clone, PartialEq)]
pub struct InsetInfo {
    pub region: Region,
    /// What the region was chosen by where none was asked for: where this sums highest on
    /// the middle slice (`FA`, an ODF map's fibre density); `None`: as asked.
    pub chosen_by: Option<&'static str>,
    /// The world range of its voxel centres along x, y and z.
    pub world: [[f64; 2]; 3],
    pub px_per_voxel: f64,
    pub glyphs_drawn: usize,
    /// Where it lies in the figure: its left edge and its side, in pixels.
    pub x0: u32,
    pub side: u32,
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
/// one frame, its underlay (if any) in `window`; the frame and the glyphs drawn (those in view,
/// not culled).
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
    let v = scene.visibility(camera, req.cull, req.min_pixel_radius);
    let glyphs_drawn =
        scene.instances.len() - v.eye_inside - v.behind_camera - v.degenerate - v.culled;
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

/// Copy `frame` into the figure at (`x0`, 0).
pub(super) fn blit(rgba: &mut [u8], width: u32, frame: &Frame, x0: u32) {
    let row_bytes = (frame.width * 4) as usize;
    for row in 0..frame.height {
        let src = &frame.color[row as usize * row_bytes..][..row_bytes];
        let at = ((row * width + x0) * 4) as usize;
        rgba[at..at + row_bytes].copy_from_slice(src);
    }
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
    let tile = options.tile;
    let axis = lattice_axis(field, dims, orientation.world_axis);
    let mut slices = slices(set, dims, axis, SLICES);
    let region = inset_region(set, dims, axis, &slices, options.zoom)?;
    with_inset_slice(&mut slices, region.as_ref());
    let lattice = lattice_box(field, dims);
    let at = position_in(field, dims);
    let inset_side = region.map_or(0, |r| inset::side(&at, dims, &r));
    let tiles = slices.len() as u32;
    let (width, height) = (
        tiles * tile + inset_side + LEGEND_WIDTH,
        tile.max(inset_side),
    );
    let mut rgba = vec![0u8; (width * height * 4) as usize];
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let mut drawn = 0;
    let mut window = None;
    let mut underlay_missing = None;
    let mut overview_px_per_voxel = f64::NAN;
    let mut outline = None;
    let pen = Pen::new(LABEL_PX);
    for (n, &index) in slices.iter().enumerate() {
        let plane = Plane { axis, index };
        let Some(d) = draw_slice(
            field,
            set,
            plane,
            None,
            &mut underlay_missing,
            backend,
            progress,
            |toward, face| tile_camera(lattice, toward, face.centre, tile),
        )?
        else {
            continue;
        };
        drawn += d.glyphs_drawn;
        window = window.or(d.window);
        overview_px_per_voxel = inset::px_per_voxel(&at, dims, axis, &d.camera);
        let x0 = n as u32 * tile;
        blit(&mut rgba, width, &d.frame, x0);
        if region.is_some_and(|r| r.slice() == index) {
            outline = Some((x0, d.camera));
        }
        if let Some(pen) = &pen {
            let mut canvas = Canvas {
                rgba: &mut rgba,
                w: i64::from(width),
                h: i64::from(height),
            };
            let [top, bottom] = slice_place(field, dims, axis, index, orientation, anatomical);
            label_tile(
                &mut canvas,
                pen,
                (x0, tile),
                (d.camera.forward(), d.camera.up),
                anatomical,
                [top.as_str(), bottom.as_str()],
            );
        }
    }
    let mut canvas = Canvas {
        rgba: &mut rgba,
        w: i64::from(width),
        h: i64::from(height),
    };
    let x_inset = tiles * tile;
    let placed = Placed {
        region,
        outline,
        x0: x_inset,
        side: inset_side,
    };
    let chosen_by = options.zoom.is_none().then_some("FA");
    let inset_info = place_inset(
        &mut canvas,
        pen.as_ref(),
        &at,
        dims,
        placed,
        anatomical,
        |r| {
            let d = draw_inset(field, set, dims, r, window, backend, progress)?;
            Ok(d.map(|d| (d.frame, d.camera, d.glyphs_drawn)))
        },
    )?
    .map(|i| InsetInfo { chosen_by, ..i });
    if let Some(pen) = &pen {
        legend(
            &mut canvas,
            pen,
            (x_inset + inset_side, height),
            orientation,
            anatomical,
            window,
            overview_px_per_voxel,
            inset_info.is_some(),
        );
    }
    Ok(Mosaic {
        width,
        height,
        tile,
        rgba,
        lattice_axis: axis,
        slices,
        glyphs_drawn: drawn,
        overview_px_per_voxel,
        inset: inset_info,
        ms: staging::ms(t),
        underlay_missing,
    })
}

/// Put the inset's slice among the overview's (its outline is drawn there): the nearest of
/// them gives way to it.
pub(super) fn with_inset_slice(slices: &mut [usize], region: Option<&Region>) {
    if let Some(r) = region
        && !slices.contains(&r.slice())
        && let Some(near) = slices.iter_mut().min_by_key(|s| s.abs_diff(r.slice()))
    {
        *near = r.slice();
        slices.sort_unstable();
    }
}

/// Where a figure's inset goes: its region (none: no inset), the overview tile that shows its
/// slice (left edge and camera) if one does, and its square's left edge and side in the figure.
pub(super) struct Placed {
    pub region: Option<Region>,
    pub outline: Option<(u32, Camera)>,
    pub x0: u32,
    pub side: u32,
}

/// The inset's part of a figure, the same for tensor and ODF rows: the region outlined on its
/// slice where the affine puts its voxels, the inset's frame (`draw` of the region: frame,
/// camera, glyphs; `None` where it holds none) copied into its square, boxed and labelled.
/// Its [`InsetInfo::chosen_by`] is `None` (as asked); the caller says otherwise.
pub(super) fn place_inset(
    canvas: &mut Canvas<'_>,
    pen: Option<&Pen<'_>>,
    at: inset::At<'_>,
    dims: [usize; 3],
    placed: Placed,
    anatomical: bool,
    draw: impl FnOnce(&Region) -> Result<Option<(Frame, Camera, usize)>, FigureError>,
) -> Result<Option<InsetInfo>, FigureError> {
    let Placed {
        region,
        outline,
        x0,
        side,
    } = placed;
    let Some(r) = region else {
        return Ok(None);
    };
    let drawn = draw(&r)?;
    if let Some((tile_x0, camera)) = &outline {
        let c = inset::corners(at, dims, &r).map(|p| {
            let [x, y] = inset::to_pixel(camera, p);
            [x + f64::from(*tile_x0), y]
        });
        for k in 0..4 {
            canvas.line(c[k], c[(k + 1) % 4], 2.0, OUTLINE);
        }
    }
    let width = canvas.w as u32;
    let (px_per_voxel, glyphs_drawn) = match &drawn {
        Some((frame, camera, glyphs)) => {
            blit(canvas.rgba, width, frame, x0);
            (inset::px_per_voxel(at, dims, r.axis, camera), *glyphs)
        }
        None => (f64::NAN, 0),
    };
    let (x, s) = (i64::from(x0), i64::from(side));
    for (x, y, w, h) in [
        (x, 0, s, 2),
        (x, s - 2, s, 2),
        (x, 0, 2, s),
        (x + s - 2, 0, 2, s),
    ] {
        canvas.rect(x, y, w, h, OUTLINE);
    }
    if let (Some(pen), Some((_, camera, _))) = (pen, &drawn) {
        // The region's voxels and world range are the page's caption: short lines here,
        // clear of the edge letters.
        let top = format!("inset {}={}", ["i", "j", "k"][r.axis], r.slice());
        let bottom = format!("{px_per_voxel:.1} px/voxel");
        label_tile(
            canvas,
            pen,
            (x0, side),
            (camera.forward(), camera.up),
            anatomical,
            [top.as_str(), bottom.as_str()],
        );
    }
    Ok(Some(InsetInfo {
        region: r,
        chosen_by: None,
        world: inset::world_range(at, dims, &r),
        px_per_voxel,
        glyphs_drawn,
        x0,
        side,
    }))
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

/// White text with a black rim, readable on glyphs and on the underlay.
pub(super) fn text(canvas: &mut Canvas<'_>, pen: &Pen<'_>, x: f64, y: f64, s: &str, c: [f64; 3]) {
    for (dx, dy) in [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0)] {
        pen.draw(canvas, x + dx, y + dy, s, [0.0; 3]);
    }
    pen.draw(canvas, x, y, s, c);
}

/// The labels of the square tile at `x0` of side `side`: the world directions at its edges
/// (for a camera looking along `forward` with `up`) and `place`'s two lines at its top and
/// bottom left.
pub(super) fn label_tile(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    (x0, side): (u32, u32),
    (forward, up): (DVec3, DVec3),
    anatomical: bool,
    place: [&str; 2],
) {
    let [left, right, top, bottom] = edge_labels(forward, up, anatomical);
    let (x0, side_px) = (f64::from(x0), f64::from(side));
    let lh = pen.line_height();
    let yellow = [1.0, 0.9, 0.3];
    let mid = (side_px - lh) / 2.0;
    text(canvas, pen, x0 + 3.0, mid, left, yellow);
    text(
        canvas,
        pen,
        x0 + side_px - pen.width(right) - 3.0,
        mid,
        right,
        yellow,
    );
    text(
        canvas,
        pen,
        x0 + (side_px - pen.width(top)) / 2.0,
        2.0,
        top,
        yellow,
    );
    let bottom_y = side_px - lh - 2.0;
    text(
        canvas,
        pen,
        x0 + (side_px - pen.width(bottom)) / 2.0,
        bottom_y,
        bottom,
        yellow,
    );
    text(canvas, pen, x0 + 3.0, 2.0, place[0], [1.0; 3]);
    text(canvas, pen, x0 + 3.0, bottom_y, place[1], [1.0; 3]);
    // A thin rule between tiles.
    canvas.rect(
        x0 as i64 + i64::from(side) - 1,
        0,
        1,
        i64::from(side),
        [0.25; 3],
    );
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
