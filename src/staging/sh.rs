//! Staging a file of SH series (fibre ODFs): read, then its ODF glyphs on the planes the
//! selection asks for, seen face-on when one plane is shown.

use std::path::Path;

use glam::DVec3;
use web_time::Instant;

use super::{Built, FaceOn, Recipe, StageError, Staged, Timings, ms};
use crate::field::Inputs;
use crate::glyph::{ColorScheme, GlyphSet};
use crate::progress::{Progress, stage as run_stage};
use crate::scene::Scene;
use crate::scene::underlay;
use crate::select::{Plane, Selection, SelectionError, Slicing};
use crate::shape::odf::OdfColoring;

/// [`stage`] for a file of SH series: read, then [`build_sh`].
pub(super) fn stage_sh(
    inputs: &Inputs,
    path: &Path,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Staged, StageError> {
    let mut timings = Timings::default();
    let t = Instant::now();
    let field = run_stage(progress, "reading SH series", None, || {
        crate::field::read_sh_field_from(inputs, path, &recipe.read)
    })?;
    timings.load = ms(t);
    timings.peak_rss_after[0] = crate::mem::peak_rss_bytes();
    let t = Instant::now();
    let built = build_sh(&field, &crate::error::escape_path(path), recipe, progress)?;
    timings.scene = ms(t);
    timings.peak_rss_after[2] = crate::mem::peak_rss_bytes();
    let n = built.scene.instances.len();
    Ok(Staged {
        glyphs_selected: n,
        glyphs_clamped: 0,
        glyphs_valid: n,
        face: built.face,
        frame_centre: built.frame_centre,
        frame_radius: built.frame_radius,
        frame_half: built.frame_half,
        style: built.style,
        scene: built.scene,
        timings,
        read: inputs.paths_read(),
    })
}

/// The scene of ODF glyphs ([`crate::scene::odf`]) of `field` (called `name` in errors) on the
/// lattice planes the selection asks for (with none, the middle axial one where `middle_slice`
/// says so, as for DTI), seen face-on when one plane is shown. Only `--slice` selects: FA,
/// stride, ROI and mask are the tensors' ([`Selection::check`] refused none of them here, so
/// they are refused now). The scene's instances name their voxel (`glyph`), and `selected`
/// lists those voxels.
pub fn build_sh(
    field: &crate::field::ShField,
    name: &str,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Built, StageError> {
    let of = |error: StageError| StageError::Of {
        name: name.to_string(),
        error: Box::new(error),
    };
    let sel = &recipe.selection;
    let rest = Selection {
        slicing: Slicing::Whole,
        ..sel.clone()
    };
    if !rest.is_everything() || recipe.underlay.is_some() {
        return Err(of(StageError::Selection(SelectionError(
            "a file of SH series is selected by --slice only (--fa-*, --stride, --roi, \
             --mask and --underlay are for tensors)"
                .into(),
        ))));
    }
    let d = field.dims;
    let planes = sel.slicing.planes().or_else(|| {
        recipe.middle_slice.then(|| {
            vec![Plane {
                axis: 2,
                index: d[2] / 2,
            }]
        })
    });
    if let Some(p) = planes
        .iter()
        .flatten()
        .find(|p| p.index >= d[p.axis.min(2)])
    {
        return Err(of(StageError::Selection(SelectionError(format!(
            "--slice {p}: the lattice is {}x{}x{}",
            d[0], d[1], d[2]
        )))));
    }
    // An ODF is coloured per pixel (direction, amplitude) or by one colour; the tensors'
    // colourings have nothing to read in a series.
    let mut style = recipe.style.clone();
    let coloring = match style.color {
        ColorScheme::Auto | ColorScheme::Dec => {
            style.color = ColorScheme::Dec;
            OdfColoring::Direction
        }
        ColorScheme::Amplitude => OdfColoring::Amplitude,
        ColorScheme::Solid => OdfColoring::Base,
        other => {
            return Err(of(StageError::Selection(SelectionError(format!(
                "--color {other}: a file of SH series is coloured by dec, amplitude or solid"
            )))));
        }
    };
    let [r, g, b] = style.solid_color;
    let opts = crate::scene::odf::OdfOptions {
        planes: planes.clone(),
        normalize: recipe.odf_normalize.unwrap_or_default(),
        coloring,
        color: [r, g, b, 255],
        ..Default::default()
    };
    let scene = run_stage(progress, "scene", None, || {
        crate::scene::odf::odf_scene(field, &opts)
    });
    if scene.instances.is_empty() {
        return Err(of(StageError::EmptySelection {
            asked: planes.map_or("the whole lattice".into(), |p| {
                p.iter()
                    .map(|p| p.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            }),
            valid: 0,
        }));
    }
    let face = match opts.planes.as_deref() {
        Some([plane]) => sh_face_on(field, *plane, &scene),
        _ => None,
    };
    Ok(Built {
        selected: scene.instances.iter().map(|i| i.glyph as usize).collect(),
        glyphs_clamped: 0,
        glyphs_valid: scene.instances.len(),
        face,
        frame_centre: scene.centre,
        frame_radius: scene.radius,
        frame_half: scene.half,
        style: style.resolve(&GlyphSet::default(), 1.0),
        scene,
    })
}

/// How to see lattice plane `plane` of an SH field face-on, framing `scene` (its ODF glyphs);
/// `None` without an affine or for a degenerate one. `render` and `report` frame ODF slices
/// with it alike.
pub fn sh_face_on(field: &crate::field::ShField, plane: Plane, scene: &Scene) -> Option<FaceOn> {
    let m = field.frame.voxel_to_world?;
    let steps = std::array::from_fn(|c| DVec3::new(m[0][c], m[1][c], m[2][c]));
    let toward = underlay::face_on_steps(steps, plane)?;
    Some(FaceOn {
        toward,
        centre: scene.centre,
        radius: scene.radius,
        half: scene.half,
    })
}
