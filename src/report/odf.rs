//! One ODF figure of a report: a row of slices of one orientation of a field of SH series
//! (fibre ODFs), each slice's ODF glyphs drawn face-on as `render` draws a file of SH series
//! ([`crate::scene::odf`], framed by [`staging::sh_face_on`]) on black, with the anatomical
//! directions at its edges, its slice named, and a legend panel beside the row.
//!
//! The tiles are the tensor rows' ([`super::mosaic`]): the same slice choice (up to
//! [`mosaic::SLICES`] through the voxels that hold a series), the same framing (every tile of a
//! row at one scale), labels and back end. There is no FA underlay (an SH series has none) and
//! no zoomed inset yet: each ODF slice costs its scene (every voxel's ODF sampled for its size
//! and bounds: about 30 µs a voxel in the release build since the sampling became a table's dot
//! products) and a ray-marched frame (the dearer part on a CPU rasteriser), and an inset would
//! add both again for every row.

use glam::DVec3;
use web_time::Instant;

use super::lattice;
use super::mosaic::{self, FigureError, Mosaic, Orientation};
use crate::backend::Backend;
use crate::camera::{Camera, ViewPreset};
use crate::field::ShField;
use crate::legend::raster::{Canvas, Pen};
use crate::progress::Progress;
use crate::scene::odf::{OdfNormalize, OdfOptions, odf_scene};
use crate::select::Plane;
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

/// Draw the ODF figure of `orientation` of `field` (`held`: [`held`] of it), in `tile`-pixel
/// tiles, each voxel's ODF normalised as `normalize` says.
#[allow(clippy::too_many_arguments)]
pub fn render(
    field: &ShField,
    held: &[bool],
    orientation: Orientation,
    anatomical: bool,
    normalize: OdfNormalize,
    tile: u32,
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
    let lattice = lattice::lattice_box_of(&at, dims);
    let tiles = slices.len() as u32;
    let (width, height) = (tiles * tile + mosaic::LEGEND_WIDTH, tile);
    let mut rgba = vec![0u8; (width * height * 4) as usize];
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let pen = Pen::new(mosaic::LABEL_PX);
    let step = steps(field);
    let across: Vec<usize> = (0..3).filter(|&a| a != axis && dims[a] > 1).collect();
    let mut drawn = 0;
    let mut px_per_voxel = f64::NAN;
    for (n, &index) in slices.iter().enumerate() {
        let plane = Plane { axis, index };
        let opts = OdfOptions {
            planes: Some(vec![plane]),
            normalize,
            ..OdfOptions::default()
        };
        let mut scene = odf_scene(field, &opts);
        if scene.instances.is_empty() {
            continue;
        }
        let toward = staging::sh_face_on(field, plane, &scene)
            .map_or_else(|| preset_view(orientation), |f| f.toward);
        let camera: Camera = mosaic::tile_camera(lattice, toward, scene.centre, tile);
        let (frame, glyphs) = mosaic::draw_scene(&mut scene, &camera, None, backend, progress)?;
        drawn += glyphs;
        px_per_voxel = across
            .iter()
            .map(|&a| step[a] * camera.pixels_per_unit())
            .fold(f64::INFINITY, f64::min);
        let x0 = n as u32 * tile;
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
    if let Some(pen) = &pen {
        let mut canvas = Canvas {
            rgba: &mut rgba,
            w: i64::from(width),
            h: i64::from(height),
        };
        legend(
            &mut canvas,
            pen,
            (tiles * tile, height),
            orientation,
            field,
            normalize,
            anatomical,
            px_per_voxel,
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
        inset: None,
        ms: staging::ms(t),
        underlay_missing: None,
    })
}

/// The legend panel at `x0`, `height` tall: the row's name, what the glyphs are (lmax, basis,
/// normalisation), the direction colour key and the tiles' pixels per voxel.
#[allow(clippy::too_many_arguments)]
fn legend(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    (x0, height): (u32, u32),
    orientation: Orientation,
    field: &ShField,
    normalize: OdfNormalize,
    anatomical: bool,
    px_per_voxel: f64,
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
    line(canvas, &mut y, "colour = direction");
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
    y += lh * 0.3;
    if px_per_voxel.is_finite() {
        line(
            canvas,
            &mut y,
            &format!("tiles: {px_per_voxel:.1} px/voxel"),
        );
    }
}
