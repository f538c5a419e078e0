//! A report figure's layout, whatever the field kind: a row of face-on slice tiles, each drawn
//! by the kind ([`Row`]) and labelled here with its slice and the anatomical directions at its
//! edges, then the zoomed inset (drawn by the kind, placed and outlined on its slice here),
//! then the kind's legend panel. The tensor rows ([`super::mosaic`]) and the ODF rows
//! ([`super::odf`]) differ only in what their tiles, inset and legend draw; what a figure is
//! ([`Mosaic`], [`InsetInfo`]) and the drawing both share (labels, the inset's outline) are here.

use glam::DVec3;
use web_time::Instant;

use super::inset::{self, At, Region};
use super::lattice::{self, Orientation, edge_labels};
use crate::backend::StageFailed;
use crate::camera::Camera;
use crate::frame::Frame;
use crate::legend::raster::{Canvas, Pen};
use crate::scene::underlay::UnderlayError;
use crate::select::Plane;
use crate::staging::{self, StageError};

/// A drawn square: its frame, the camera it was drawn with and the glyphs drawn (those in
/// view).
pub(super) type Drawn = (Frame, Camera, usize);

/// What a field kind draws in a row of a report figure.
pub(super) trait Row {
    /// Slice `plane` drawn face-on in a square of `tile` pixels; `None` where the slice draws
    /// nothing. `inset`: the inset's region, when it lies on this slice.
    fn tile(
        &mut self,
        plane: Plane,
        tile: u32,
        inset: Option<&Region>,
    ) -> Result<Option<Drawn>, FigureError>;

    /// The inset's region drawn face-on in a square of `side` pixels (after every tile);
    /// `None` where it holds no glyph.
    fn inset(&mut self, region: &Region, side: u32) -> Result<Option<Drawn>, FigureError>;

    /// The sticks of peaks drawn over the inset's glyphs, where the kind draws them (ODFs).
    fn inset_peaks(&self) -> Option<usize> {
        None
    }

    /// The legend panel at (`x0`, 0), `height` tall: what the glyphs are and their colour key,
    /// the tiles' pixels per voxel, and the inset's key when there is one.
    fn legend(
        &self,
        canvas: &mut Canvas<'_>,
        pen: &Pen<'_>,
        at: (u32, u32),
        px_per_voxel: f64,
        inset: bool,
    );
}

/// Where a row is cut: the lattice (its voxels' world positions and size), the axis sliced, the
/// slices chosen, the inset's region, how the row is seen and labelled.
pub(super) struct Plan<'a> {
    pub at: At<'a>,
    pub dims: [usize; 3],
    pub axis: usize,
    pub slices: Vec<usize>,
    pub region: Option<Region>,
    pub orientation: Orientation,
    pub anatomical: bool,
    /// The tiles' side, in pixels.
    pub tile: u32,
    /// What the inset's region was chosen by where none was asked for
    /// ([`InsetInfo::chosen_by`]).
    pub chosen_by: Option<&'static str>,
}

/// Draw the figure `plan` cuts with `row`'s tiles, inset and legend; `started`: when the row's
/// work began (its [`Mosaic::ms`]).
pub(super) fn compose(
    plan: Plan<'_>,
    row: &mut dyn Row,
    started: Instant,
) -> Result<Mosaic, FigureError> {
    let Plan {
        at,
        dims,
        axis,
        mut slices,
        region,
        orientation,
        anatomical,
        tile,
        chosen_by,
    } = plan;
    with_inset_slice(&mut slices, region.as_ref());
    let inset_side = region.map_or(0, |r| inset::side(at, dims, &r));
    let tiles = slices.len() as u32;
    let (width, height) = (
        tiles * tile + inset_side + LEGEND_WIDTH,
        tile.max(inset_side),
    );
    let mut rgba = vec![0u8; (width * height * 4) as usize];
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let pen = Pen::new(LABEL_PX);
    let mut drawn = 0;
    let mut px_per_voxel = f64::NAN;
    let mut outline = None;
    for (n, &index) in slices.iter().enumerate() {
        let here = region.as_ref().filter(|r| r.slice() == index);
        let Some((frame, camera, glyphs)) = row.tile(Plane { axis, index }, tile, here)? else {
            continue;
        };
        drawn += glyphs;
        px_per_voxel = inset::px_per_voxel(at, dims, axis, &camera);
        let x0 = n as u32 * tile;
        blit(&mut rgba, width, &frame, x0);
        if let Some(pen) = &pen {
            let mut canvas = Canvas {
                rgba: &mut rgba,
                w: i64::from(width),
                h: i64::from(height),
            };
            let [top, bottom] = lattice::slice_place(at, axis, index, orientation, anatomical);
            label_tile(
                &mut canvas,
                pen,
                (x0, tile),
                (camera.forward(), camera.up),
                anatomical,
                [top.as_str(), bottom.as_str()],
            );
        }
        if here.is_some() {
            outline = Some((x0, camera));
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
    let inset_info = place_inset(
        &mut canvas,
        pen.as_ref(),
        at,
        dims,
        placed,
        anatomical,
        |r| row.inset(r, inset_side),
    )?
    .map(|i| InsetInfo {
        chosen_by,
        peaks: row.inset_peaks(),
        ..i
    });
    if let Some(pen) = &pen {
        row.legend(
            &mut canvas,
            pen,
            (x_inset + inset_side, height),
            px_per_voxel,
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
        overview_px_per_voxel: px_per_voxel,
        inset: inset_info,
        ms: staging::ms(started),
        underlay_missing: None,
    })
}

/// The labels' text height, in pixels, whatever the tiles' size.
pub(super) const LABEL_PX: f32 = 16.0;

/// The inset's outline on the overview and around the inset: a colour the DEC glyphs (scaled
/// by FA, shaded) and the grey underlay do not reach.
pub const OUTLINE: [f64; 3] = [0.0, 1.0, 1.0];

/// The legend panel's width, in pixels.
pub(super) const LEGEND_WIDTH: u32 = 200;

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
    /// The sticks of peaks drawn over its glyphs, if its kind draws them.
    pub peaks: Option<usize>,
    /// Where it lies in the figure: its left edge and its side, in pixels.
    pub x0: u32,
    pub side: u32,
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
        peaks: None,
        x0,
        side,
    }))
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
