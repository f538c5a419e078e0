//! One ODF figure of a report: a row of slices of one orientation of a field of SH series
//! (fibre ODFs), each slice's ODF glyphs drawn face-on as `render` draws a file of SH series
//! ([`crate::scene::odf`], framed by [`staging::sh_face_on`]) on black, with the anatomical
//! directions at its edges, its slice named, and a legend panel beside the row.
//!
//! The tiles are the tensor rows' ([`super::mosaic`]): the same slice choice (up to
//! [`mosaic::SLICES`] through the voxels that hold a series), the same framing (every tile of a
//! row at one scale), labels, back end and zoomed inset ([`super::inset`]: a square of one slice
//! at ≥ 8 pixels per voxel, outlined on its slice). There is no FA underlay (an SH series has
//! none). The inset's region is the one `--zoom-region` asks for or, by default, the square of
//! the middle slice where the fibre density (each ODF's l = 0 coefficient, MRtrix's AFD, the
//! same in every basis read) sums highest: white matter. Its glyphs are those of the overview's
//! scene of that slice, so a glyph has the same size in both (with `--odf-normalize none` too),
//! and the scene is built once.

use glam::DVec3;
use web_time::Instant;

use super::Options;
use super::inset;
use super::lattice;
use super::mosaic::{self, FigureError, Mosaic, Orientation, Placed};
use crate::backend::Backend;
use crate::camera::{Camera, ViewPreset};
use crate::field::ShField;
use crate::legend::raster::{Canvas, Pen};
use crate::progress::Progress;
use crate::request::GlyphKind;
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

/// The length of one voxel step along each lattice axis, in world units.
fn steps(field: &ShField) -> [f64; 3] {
    let at = position(field);
    let origin = at([0; 3]);
    std::array::from_fn(|a| {
        let mut c = [0; 3];
        c[a] = 1;
        (at(c) - origin).length()
    })
}

/// The orientation's view direction and up for a field whose affine gives no face-on view.
fn preset_view(orientation: Orientation) -> (DVec3, DVec3) {
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
fn scene_in(scene: &Scene, dims: [usize; 3], region: &inset::Region) -> Scene {
    let kept = scene
        .instances
        .iter()
        .filter(|g| region.contains(crate::select::lattice_coords(g.glyph as usize, dims)))
        .copied()
        .collect();
    let mut s = Scene::from_instances_as(scene.origin, kept, GlyphKind::Odf);
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
    let (tile, zoom, normalize) = (options.tile, options.zoom, options.odf_normalize);
    let dims = field.dims;
    let at = position(field);
    let axis = lattice::lattice_axis_of(&at, dims, orientation.world_axis);
    let mut count = vec![0usize; dims[axis]];
    for (v, _) in held.iter().enumerate().filter(|(_, h)| **h) {
        count[crate::select::lattice_coords(v, dims)[axis]] += 1;
    }
    let mut slices = lattice::slices_of(&count, mosaic::SLICES);
    let region = match zoom {
        Some(z) => Some(inset::given(z, dims, axis)?),
        None => slices.get(slices.len() / 2).map(|&s| {
            let values = density(field, held, axis, s);
            inset::brightest_of(values, dims, axis, s, inset::DEFAULT_SIZE)
        }),
    };
    mosaic::with_inset_slice(&mut slices, region.as_ref());
    let inset_side = region.map_or(0, |r| inset::side(&at, dims, &r));
    let lattice = lattice::lattice_box_of(&at, dims);
    let tiles = slices.len() as u32;
    let (width, height) = (
        tiles * tile + inset_side + mosaic::LEGEND_WIDTH,
        tile.max(inset_side),
    );
    let mut rgba = vec![0u8; (width * height * 4) as usize];
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let pen = Pen::new(mosaic::LABEL_PX);
    let step = steps(field);
    let across: Vec<usize> = (0..3).filter(|&a| a != axis && dims[a] > 1).collect();
    let mut drawn = 0;
    let mut px_per_voxel = f64::NAN;
    // The inset's glyphs (cut from its slice's scene), the way that slice is seen, and where
    // its tile is.
    let mut cut = None;
    let mut outline = None;
    for (n, &index) in slices.iter().enumerate() {
        let plane = Plane { axis, index };
        let opts = OdfOptions {
            planes: Some(vec![plane]),
            normalize,
            coloring: options.odf_color,
            ..OdfOptions::default()
        };
        let mut scene = odf_scene(field, &opts);
        if scene.instances.is_empty() {
            continue;
        }
        let toward = staging::sh_face_on(field, plane, &scene)
            .map_or_else(|| preset_view(orientation), |f| f.toward);
        let camera: Camera = mosaic::tile_camera(lattice, toward, scene.centre, tile);
        let x0 = n as u32 * tile;
        if let Some(r) = region.filter(|r| r.slice() == index) {
            cut = Some((scene_in(&scene, dims, &r), toward));
            outline = Some((x0, camera));
        }
        let (frame, glyphs) = mosaic::draw_scene(&mut scene, &camera, None, backend, progress)?;
        drawn += glyphs;
        px_per_voxel = across
            .iter()
            .map(|&a| step[a] * camera.pixels_per_unit())
            .fold(f64::INFINITY, f64::min);
        mosaic::blit(&mut rgba, width, &frame, x0);
        if let Some(pen) = &pen {
            let mut canvas = Canvas {
                rgba: &mut rgba,
                w: i64::from(width),
                h: i64::from(height),
            };
            let [top, bottom] = lattice::slice_place_of(&at, axis, index, orientation, anatomical);
            mosaic::label_tile(
                &mut canvas,
                pen,
                (x0, tile),
                (camera.forward(), camera.up),
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
    let chosen_by = zoom.is_none().then_some("the fibre density (l = 0)");
    let inset_info = mosaic::place_inset(
        &mut canvas,
        pen.as_ref(),
        &at,
        dims,
        placed,
        anatomical,
        |r| {
            let Some((mut scene, toward)) = cut.filter(|(s, _)| !s.instances.is_empty()) else {
                return Ok(None);
            };
            let camera = inset::camera(&at, dims, r, toward, inset_side);
            let (frame, glyphs) = mosaic::draw_scene(&mut scene, &camera, None, backend, progress)?;
            Ok(Some((frame, camera, glyphs)))
        },
    )?
    .map(|i| mosaic::InsetInfo { chosen_by, ..i });
    if let Some(pen) = &pen {
        legend(
            &mut canvas,
            pen,
            (x_inset + inset_side, height),
            orientation,
            field,
            (normalize, options.odf_color),
            anatomical,
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
        ms: staging::ms(t),
        underlay_missing: None,
    })
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
    let w = mosaic::LEGEND_WIDTH;
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
    }
}
