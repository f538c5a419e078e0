//! Staging a file of SH series (fibre ODFs): read, then its ODF glyphs on the planes the
//! selection asks for, seen face-on when one plane is shown.

use std::path::Path;

use super::{Built, FaceOn, Recipe, StageError, Staged, lattice};
use crate::field::Inputs;
use crate::glyph::ColorScheme;
use crate::progress::{Progress, stage as run_stage};
use crate::scene::Scene;
use crate::select::Plane;
use crate::shape::odf::OdfColoring;

/// [`stage`] for a file of SH series: read, then [`build_sh`].
pub(super) fn stage_sh(
    inputs: &Inputs,
    path: &Path,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Staged, StageError> {
    lattice::stage(
        inputs,
        progress,
        "reading SH series",
        || crate::field::read_sh_field_from(inputs, path, &recipe.read),
        |f| build_sh(f, &crate::error::escape_path(path), recipe, progress),
    )
}

/// The scene of ODF glyphs ([`crate::scene::odf`]) of `field` (called `name` in errors) on the
/// lattice planes the selection asks for (`lattice::planes`: `--slice` only; with none, the
/// middle axial one where `middle_slice` says so, as for DTI), seen face-on when one plane is
/// shown. The scene's instances name their voxel (`glyph`), and `selected` lists those voxels.
/// With `recipe.peaks_over`, the sticks of the voxels' peaks are drawn over the ODFs.
pub fn build_sh(
    field: &crate::field::ShField,
    name: &str,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Built, StageError> {
    let planes = lattice::planes(name, "SH series", field.dims, recipe)?;
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
            return Err(lattice::refuse(
                name,
                format!(
                    "--color {other}: a file of SH series is coloured by dec, amplitude or solid"
                ),
            ));
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
    let mut scene = run_stage(progress, "scene", None, || {
        crate::scene::odf::odf_scene(field, &opts)
    });
    if recipe.peaks_over {
        let sticks = run_stage(progress, "peaks", None, || {
            super::peaks_over_odfs(field, name, recipe, scene.origin)
        })?;
        scene = scene.with_overlay(sticks);
    }
    lattice::built(
        name,
        scene,
        opts.planes.as_deref(),
        field.frame.voxel_to_world,
        style,
    )
}

/// How to see lattice plane `plane` of an SH field face-on, framing `scene` (its ODF glyphs);
/// `None` without an affine or for a degenerate one. `render` and `report` frame ODF slices
/// with it alike.
pub fn sh_face_on(field: &crate::field::ShField, plane: Plane, scene: &Scene) -> Option<FaceOn> {
    lattice::face_on(field.frame.voxel_to_world, plane, scene)
}
