//! What the staging of a lattice of voxel glyphs (SH series, peaks) shares: the planes
//! `--slice` asks for, the built scene with its face-on view, and the staged result.

use glam::DVec3;
use web_time::Instant;

use super::{Built, FaceOn, Recipe, StageError, Staged, Timings, ms};
use crate::error::LoadError;
use crate::field::Inputs;
use crate::glyph::{GlyphSet, GlyphStyle};
use crate::scene::Scene;
use crate::scene::underlay;
use crate::select::{Plane, Selection, SelectionError, Slicing};

/// `error` as said of the file `name`.
pub(super) fn of(name: &str, error: StageError) -> StageError {
    StageError::Of {
        name: name.to_string(),
        error: Box::new(error),
    }
}

/// A selection error said of the file `name`.
pub(super) fn refuse(name: &str, message: String) -> StageError {
    of(name, StageError::Selection(SelectionError(message)))
}

/// The lattice planes of a `dims` lattice (of `what`, a file of which is called `name`) the
/// recipe shows: those `--slice` asks for, or with none the middle axial one where
/// `middle_slice` says so (as for DTI), or `None` (every voxel). Only `--slice` selects such a
/// field: FA, stride, ROI, mask and underlay are the tensors' ([`Selection::check`] refused
/// none of them, so they are refused here).
pub(super) fn planes(
    name: &str,
    what: &str,
    dims: [usize; 3],
    recipe: &Recipe,
) -> Result<Option<Vec<Plane>>, StageError> {
    let sel = &recipe.selection;
    let rest = Selection {
        slicing: Slicing::Whole,
        ..sel.clone()
    };
    if !rest.is_everything() || recipe.underlay.is_some() {
        return Err(refuse(
            name,
            format!(
                "a file of {what} is selected by --slice only (--fa-*, --stride, --roi, \
                 --mask and --underlay are for tensors)"
            ),
        ));
    }
    let d = dims;
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
        return Err(refuse(
            name,
            format!("--slice {p}: the lattice is {}x{}x{}", d[0], d[1], d[2]),
        ));
    }
    Ok(planes)
}

/// Whether voxel `v` (x fastest) of a `dims` lattice lies on one of `planes` (every voxel
/// without planes).
pub(super) fn shown(planes: Option<&[Plane]>, dims: [usize; 3], v: usize) -> bool {
    let ijk = [v % dims[0], v / dims[0] % dims[1], v / dims[0] / dims[1]];
    planes.is_none_or(|ps| ps.iter().any(|p| ijk[p.axis.min(2)] == p.index))
}

/// The [`Built`] of a lattice's `scene` (of the file `name`, on `planes`, the lattice's
/// voxel-to-world matrix `m`): empty is an error naming what was asked, one plane is seen
/// face-on, and the instances name their voxel (`glyph`), which `selected` lists.
pub(super) fn built(
    name: &str,
    scene: Scene,
    planes: Option<&[Plane]>,
    m: Option<[[f64; 4]; 4]>,
    style: GlyphStyle,
) -> Result<Built, StageError> {
    if scene.instances.is_empty() {
        return Err(of(
            name,
            StageError::EmptySelection {
                asked: planes.map_or("the whole lattice".into(), |p| {
                    p.iter()
                        .map(|p| p.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                }),
                valid: 0,
            },
        ));
    }
    let face = match planes {
        Some([plane]) => face_on(m, *plane, &scene),
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

/// How to see lattice plane `plane` face-on, framing `scene` (its glyphs), for a lattice whose
/// voxel-to-world matrix is `m`; `None` without one or for a degenerate one.
pub(super) fn face_on(m: Option<[[f64; 4]; 4]>, plane: Plane, scene: &Scene) -> Option<FaceOn> {
    let m = m?;
    let steps = std::array::from_fn(|c| DVec3::new(m[0][c], m[1][c], m[2][c]));
    let toward = underlay::face_on_steps(steps, plane)?;
    Some(FaceOn {
        toward,
        centre: scene.centre,
        radius: scene.radius,
        half: scene.half,
    })
}

/// Stage a lattice field: `read` it (the progress stage called `reading`), then `build` its
/// scene, timing both.
pub(super) fn stage<F>(
    inputs: &Inputs,
    progress: &dyn crate::progress::Progress,
    reading: &str,
    read: impl FnOnce() -> Result<F, LoadError>,
    build: impl FnOnce(&F) -> Result<Built, StageError>,
) -> Result<Staged, StageError> {
    let mut timings = Timings::default();
    let t = Instant::now();
    let field = crate::progress::stage(progress, reading, None, read)?;
    timings.load = ms(t);
    timings.peak_rss_after[0] = crate::mem::peak_rss_bytes();
    let t = Instant::now();
    let built = build(&field)?;
    timings.scene = ms(t);
    timings.peak_rss_after[2] = crate::mem::peak_rss_bytes();
    Ok(Staged::of(built, timings, inputs))
}

impl Staged {
    /// What staging made of `built`, with the time it took and the files `inputs` read.
    pub(super) fn of(built: Built, timings: Timings, inputs: &Inputs) -> Self {
        Staged {
            glyphs_selected: built.selected.len(),
            glyphs_clamped: built.glyphs_clamped,
            glyphs_valid: built.glyphs_valid,
            face: built.face,
            frame_centre: built.frame_centre,
            frame_radius: built.frame_radius,
            frame_half: built.frame_half,
            style: built.style,
            scene: built.scene,
            timings,
            read: inputs.paths_read(),
        }
    }
}
