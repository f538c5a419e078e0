//! Staging a file of fibre peaks ([`crate::field::PeakField`]): read, then each peak on the
//! planes the selection asks for as a stick through its voxel's centre, along the peak, as long
//! as its amplitude, coloured by its direction (DEC) — drawn by a glyph kind the field kind
//! offers (a cylinder or a capsule: [`crate::field::FieldKind::offers`]), so every method and
//! the exact reference draw it as they draw those.
//!
//! **Length.** `--scale auto` makes the field's largest peak as long as the voxel step (its
//! half-length half the step, as an ODF's largest radius is); `--scale F` gives a half-length
//! of F × the peak's amplitude, in world units. **Width.** A stick's radius is
//! [`STICK_RADIUS`] of the voxel step, whatever its length, as mrview's and FURY's lines are
//! of one width.

use std::path::Path;

use glam::{DMat3, DQuat, DVec3};

use rayon::prelude::*;

use super::{Built, Recipe, StageError, Staged, lattice};
use crate::field::{Inputs, PeakField, ShField};
use crate::glyph::{ColorScheme, GlyphSet, GlyphStyle, Scale};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::scene::odf::{OdfNormalize, series_frame};
use crate::sh::{PeakFinder, PeakOptions};
use crate::shape::{GlyphInstance, GlyphKind};
use crate::tensor::eigen::quat_to_frame;

/// A stick's radius, in voxel steps.
pub const STICK_RADIUS: f64 = 0.06;

/// [`super::stage`] for a file of peaks: read, then [`build_peaks`].
pub(super) fn stage_peaks(
    inputs: &Inputs,
    path: &Path,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Staged, StageError> {
    lattice::stage(
        inputs,
        progress,
        "reading peaks",
        || crate::field::read_peak_field_from(inputs, path, &recipe.read),
        |f| build_peaks(f, &crate::error::escape_path(path), recipe),
    )
}

/// [`super::stage`] for a file of SH series drawn as its peaks (`--glyph peaks`): read, find
/// the peaks of the voxels shown ([`series_peaks`]), then [`build_peaks`].
pub(super) fn stage_series_peaks(
    inputs: &Inputs,
    path: &Path,
    recipe: &Recipe,
    progress: &dyn Progress,
) -> Result<Staged, StageError> {
    let name = crate::error::escape_path(path);
    lattice::stage(
        inputs,
        progress,
        "reading SH series",
        || crate::field::read_sh_field_from(inputs, path, &recipe.read),
        |sh| build_peaks(&series_peaks(sh, &name, recipe)?, &name, recipe),
    )
}

/// The peaks of `sh`'s series (a file called `name`) in the voxels `recipe` shows (its planes;
/// with none, every voxel or the middle axial slice as for its ODFs): each voxel's maxima by
/// [`PeakFinder`] with DIPY's `peaks_from_model` settings ([`PeakOptions::default`]: at least
/// half the voxel's largest, 25° apart, at most 5), in world axes (the series' frame,
/// [`series_frame`]), as long as the ODF there normalised as its glyph would be: `max` (the
/// default) each voxel's largest peak 1, `none` the ODF's value. `minmax` is refused: a peak
/// has no minimum to subtract.
pub fn series_peaks(sh: &ShField, name: &str, recipe: &Recipe) -> Result<PeakField, StageError> {
    let planes = lattice::planes(name, "SH series", sh.dims, recipe)?;
    let shown = |v| lattice::shown(planes.as_deref(), sh.dims, v);
    let found = peaks_where(sh, name, recipe.odf_normalize.unwrap_or_default(), &shown)?;
    let per_voxel = PeakOptions::default().max_peaks;
    let mut vectors = vec![[f32::NAN; 3]; sh.voxels() * per_voxel];
    for (v, peaks) in found {
        vectors[v * per_voxel..][..peaks.len()].copy_from_slice(&peaks);
    }
    Ok(PeakField {
        format: sh.format.clone(),
        dims: sh.dims,
        per_voxel,
        vectors,
        frame: sh.frame.clone(),
    })
}

/// A voxel and its peaks (direction × amplitude, world axes), largest first.
type VoxelPeaks = (usize, Vec<[f32; 3]>);

/// [`series_peaks`] of the voxels `shown` says, normalised as `normalize` says.
fn peaks_where(
    sh: &ShField,
    name: &str,
    normalize: OdfNormalize,
    shown: &(dyn Fn(usize) -> bool + Sync),
) -> Result<Vec<VoxelPeaks>, StageError> {
    let per_voxel_max = match normalize {
        OdfNormalize::Max => true,
        OdfNormalize::None => false,
        OdfNormalize::MinMax => {
            return Err(lattice::refuse(
                name,
                "--odf-normalize minmax: peaks are normalised by max (each voxel's largest) or \
                 none"
                    .into(),
            ));
        }
    };
    let opts = PeakOptions::default();
    let finder = PeakFinder::new(sh.layout.lmax, sh.layout.basis)
        .map_err(|e| lattice::refuse(name, e.to_string()))?;
    let frame = series_frame(sh);
    let count = sh.layout.count;
    // Only the voxels shown, each with its peaks (a lattice-sized list of empty ones would cost
    // a whole brain 30 MB for an inset of 256 voxels).
    let voxels: Vec<usize> = (0..sh.voxels()).filter(|&v| shown(v)).collect();
    Ok(voxels
        .into_par_iter()
        .map_init(
            || (finder.clone(), vec![0.0; count]),
            |(finder, c), v| {
                sh.coefficients_of(v, c);
                let peaks = finder.peaks(c, &opts);
                let top = peaks.first().map_or(1.0, |p| p.value);
                let vectors = peaks
                    .iter()
                    .take(opts.max_peaks)
                    .map(|p| {
                        let a = if per_voxel_max {
                            p.value / top
                        } else {
                            p.value
                        };
                        (frame * DVec3::from(p.direction) * a).as_vec3().to_array()
                    })
                    .collect();
                (v, vectors)
            },
        )
        .collect())
}

/// The scene of sticks (one a peak: the module's doc) of `field` (called `name` in errors),
/// drawn as `recipe.glyph` where the kind offers it (else its first), on the lattice planes
/// the selection asks for (with none, the middle axial one where `middle_slice` says so), seen
/// face-on when one plane is shown. Only `--slice` selects, as for SH series. The instances
/// name their voxel (`glyph`).
pub fn build_peaks(field: &PeakField, name: &str, recipe: &Recipe) -> Result<Built, StageError> {
    let planes = lattice::planes(name, "peaks", field.dims, recipe)?;
    let mut style = recipe.style.clone();
    let solid = stick_colour(&mut style).map_err(|m| lattice::refuse(name, m))?;
    let step = smallest_step(field);
    let per_amplitude = match style.scale {
        Scale::Auto => auto_half_length(field, step),
        Scale::Factor(f) => f,
    };
    let origin = DVec3::from(field.position(0));
    let size = (per_amplitude, STICK_RADIUS * step);
    let shown = (0..field.voxels()).filter(|&v| lattice::shown(planes.as_deref(), field.dims, v));
    let instances = sticks(
        shown.map(|v| (v, field.peaks_of(v))),
        |v| field.position(v),
        origin,
        size,
        solid,
    );
    let scene = sticks_scene(origin, instances, recipe.glyph);
    lattice::built(
        name,
        scene,
        planes.as_deref(),
        field.frame.voxel_to_world,
        style,
    )
}

/// The smallest of the lattice's steps (1 without an affine).
fn smallest_step(field: &PeakField) -> f64 {
    let m = field.frame.voxel_to_world.unwrap_or_default();
    let steps: [DVec3; 3] = std::array::from_fn(|c| DVec3::new(m[0][c], m[1][c], m[2][c]));
    let step = steps
        .iter()
        .map(|s| s.length())
        .filter(|s| s.is_finite() && *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    if step.is_finite() { step } else { 1.0 }
}

/// `--scale auto`'s half-length per unit of amplitude: the field's largest peak half the step
/// long (0 for a field without peaks).
fn auto_half_length(field: &PeakField, step: f64) -> f64 {
    let largest = field.largest();
    if largest > 0.0 {
        0.5 * step / largest
    } else {
        0.0
    }
}

/// A stick for every peak of `voxels` (each a voxel and its peaks, at `position`), about
/// `origin`, `per_amplitude` half-length per unit of amplitude, `radius` wide, coloured `solid`
/// or by direction, each naming its voxel.
fn sticks<P: IntoIterator<Item = [f32; 3]>>(
    voxels: impl Iterator<Item = (usize, P)>,
    position: impl Fn(usize) -> [f64; 3],
    origin: DVec3,
    (per_amplitude, radius): (f64, f64),
    solid: Option<u32>,
) -> Vec<GlyphInstance> {
    let mut instances = Vec::new();
    for (v, peaks) in voxels {
        let centre = DVec3::from(position(v)) - origin;
        for x in peaks {
            let x = glam::Vec3::from(x).as_dvec3();
            let half = x.length() * per_amplitude;
            instances.push(stick(centre, x, half, radius as f32, solid, v as u32));
        }
    }
    instances
}

/// How far the sticks drawn over ODFs (`--peaks`) reach, in lengths of their lobes: a little
/// past each lobe's tip, so that a stick shows beyond the surface it runs inside.
pub const OVER_ODF_REACH: f64 = 1.25;

/// The radius of the sticks drawn over ODFs, in voxel steps: half a lone stick's, as an ODF's
/// lobe is narrower than a voxel.
pub const OVER_ODF_WIDTH: f64 = 0.5 * STICK_RADIUS;

/// The sticks of `sh`'s peaks (the voxels `recipe` shows, [`series_peaks`]) to draw over its
/// ODF glyphs (`--peaks`): each reaching [`OVER_ODF_REACH`] times its lobe (normalised as the
/// ODFs are) and `OVER_ODF_WIDTH` in radius, white over ODFs coloured by direction or
/// amplitude and coloured by direction over solid ones, as cylinders about `origin` (the ODF
/// scene's).
pub fn peaks_over_odfs(
    sh: &ShField,
    name: &str,
    recipe: &Recipe,
    origin: DVec3,
) -> Result<Scene, StageError> {
    let planes = lattice::planes(name, "SH series", sh.dims, recipe)?;
    let shown = |v| lattice::shown(planes.as_deref(), sh.dims, v);
    let over = OverOdfs {
        normalize: recipe.odf_normalize.unwrap_or_default(),
        solid: recipe.style.color == ColorScheme::Solid,
        planes: planes.as_deref(),
    };
    peaks_over_voxels(sh, name, &over, &shown, origin)
}

/// The ODFs sticks are drawn over: how they are normalised and whether they are one colour
/// (`solid`), and the planes they were made on (every voxel without).
pub struct OverOdfs<'p> {
    pub normalize: OdfNormalize,
    pub solid: bool,
    pub planes: Option<&'p [crate::select::Plane]>,
}

/// [`peaks_over_odfs`] of the voxels `shown` says (a report's inset: a region of one of the
/// planes), over the ODFs `over` describes. A stick's lobe is as long as its ODF glyph's: half
/// the lattice step times the peak's value over the voxel's largest (`max`) or over the
/// largest of the planes' ODFs, sampled as their glyphs' scale is (`none`).
pub fn peaks_over_voxels(
    sh: &ShField,
    name: &str,
    over: &OverOdfs<'_>,
    shown: &(dyn Fn(usize) -> bool + Sync),
    origin: DVec3,
) -> Result<Scene, StageError> {
    let found = peaks_where(sh, name, over.normalize, shown)?;
    let step = sh.spacing();
    let full = match over.normalize {
        OdfNormalize::None => crate::scene::odf::sampled_largest(sh, over.planes),
        // Each voxel's values over its largest ([`peaks_where`]; minmax is refused there).
        _ => 1.0,
    };
    let per_amplitude = if full > 0.0 {
        OVER_ODF_REACH * 0.5 * step / full
    } else {
        0.0
    };
    let colour = (!over.solid).then(|| GlyphInstance::pack_color([255, 255, 255, 255]));
    let instances = sticks(
        found.iter().map(|(v, peaks)| (*v, peaks.iter().copied())),
        |v| sh.position(v),
        origin,
        (per_amplitude, OVER_ODF_WIDTH * step),
        colour,
    );
    Ok(Scene::from_instances_as(
        origin,
        instances,
        GlyphKind::Cylinder,
    ))
}

/// How sticks are coloured by `style` (made `dec` where it asks for none): `None`, by their
/// direction; or the solid colour. A tensor's colouring is the message refusing it.
fn stick_colour(style: &mut GlyphStyle) -> Result<Option<u32>, String> {
    match style.color {
        ColorScheme::Auto | ColorScheme::Dec => {
            style.color = ColorScheme::Dec;
            Ok(None)
        }
        ColorScheme::Solid => {
            let [r, g, b] = style.solid_color;
            Ok(Some(GlyphInstance::pack_color([r, g, b, 255])))
        }
        other => Err(format!(
            "--color {other}: sticks (peaks) are coloured by dec or solid"
        )),
    }
}

/// The stick along `x` (of any length) through `centre`, of half-length `half`: a cylinder
/// instance of radius `radius`, coloured `solid` or by its direction (|x|, |y|, |z|), naming
/// `glyph`.
fn stick(
    centre: DVec3,
    x: DVec3,
    half: f64,
    radius: f32,
    solid: Option<u32>,
    glyph: u32,
) -> GlyphInstance {
    let axis = x.normalize();
    let (u, w) = axis.any_orthonormal_pair();
    let rotation = DQuat::from_mat3(&DMat3::from_cols(axis, u, w)).as_quat();
    let colour = solid.unwrap_or_else(|| {
        let c = (axis.abs() * 255.0).round();
        GlyphInstance::pack_color([c.x as u8, c.y as u8, c.z as u8, 255])
    });
    GlyphInstance {
        centre: centre.as_vec3().into(),
        color: colour,
        rotation: rotation.into(),
        radii: [half as f32, radius, radius],
        glyph,
        shape: [0; 2],
    }
}

/// The scene of `instances` (sticks about `origin`) drawn as `glyph` where peaks offer it (a
/// front end has refused another, `FieldKind::glyph`; one that cannot be unasked means theirs).
fn sticks_scene(origin: DVec3, instances: Vec<GlyphInstance>, glyph: GlyphKind) -> Scene {
    let offered = crate::field::FieldKind::Peaks.offers().glyphs;
    let glyph = if offered.contains(&glyph) {
        glyph
    } else {
        offered[0]
    };
    let scene = Scene::from_instances_as(origin, instances, GlyphKind::Cylinder);
    if glyph == GlyphKind::Cylinder {
        scene
    } else {
        scene.drawn_as(glyph)
    }
}

/// The sticks of a tensor field's principal directions (FSL's V1 lines): one a glyph of `set`
/// (those `indices` names, every one without), along its e1 through its centre, half-length
/// FA × half the lattice step `step` under `--scale auto` (F × FA under `--scale F`), coloured
/// as peaks are; a stick's `glyph` is its glyph's place in `indices`, as a tensor scene's.
pub(super) fn tensor_sticks(
    set: &GlyphSet,
    indices: Option<&[usize]>,
    step: f64,
    style: &GlyphStyle,
    glyph: GlyphKind,
) -> Result<Scene, StageError> {
    let mut style = style.clone();
    let solid = stick_colour(&mut style)
        .map_err(|m| StageError::Selection(crate::select::SelectionError(m)))?;
    let per_fa = match style.scale {
        Scale::Auto => 0.5 * step,
        Scale::Factor(f) => f,
    };
    let all: Vec<usize>;
    let chosen = match indices {
        Some(i) => i,
        None => {
            all = (0..set.glyphs.len()).collect();
            &all
        }
    };
    let origin = chosen
        .first()
        .map_or(DVec3::ZERO, |&k| DVec3::from(set.glyphs[k].centre));
    let radius = (STICK_RADIUS * step) as f32;
    let instances = chosen
        .iter()
        .enumerate()
        .filter_map(|(j, &k)| {
            let g = &set.glyphs[k];
            let fa = crate::tensor::shape::fa(g.eigenvalues.map(f64::from));
            let e1 = DVec3::from(quat_to_frame(g.rotation)[0]);
            (fa > 0.0).then(|| {
                stick(
                    DVec3::from(g.centre) - origin,
                    e1,
                    fa * per_fa,
                    radius,
                    solid,
                    j as u32,
                )
            })
        })
        .collect();
    Ok(sticks_scene(origin, instances, glyph))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::frame::{FrameInfo, TensorFrame};
    use crate::tensor::eigen::quat_to_frame;

    /// Two voxels of a 2×1×1 lattice of step 2: one with two peaks, one with none (NaN, as
    /// sh2peaks writes). Each stick lies along its peak through its voxel's centre, half as
    /// long as the step for the largest peak under `--scale auto` and in proportion for the
    /// other, or F × its amplitude under `--scale F`; coloured by its direction.
    #[test]
    fn a_stick_lies_along_its_peak_as_long_as_its_amplitude() {
        let d = glam::DVec3::new(1.0, 2.0, 2.0) / 3.0;
        let field = PeakField {
            format: "mif".into(),
            dims: [2, 1, 1],
            per_voxel: 2,
            vectors: vec![
                (d * 4.0).as_vec3().into(),
                [0.0, 0.0, 1.0],
                [f32::NAN; 3],
                [f32::NAN; 3],
            ],
            frame: FrameInfo {
                tensor_frame: TensorFrame::World,
                world: "RAS".into(),
                voxel_to_world: Some([
                    [2.0, 0.0, 0.0, 10.0],
                    [0.0, 2.0, 0.0, 0.0],
                    [0.0, 0.0, 2.0, 0.0],
                    [0.0, 0.0, 0.0, 1.0],
                ]),
                source: "transform".into(),
            },
        };
        let mut recipe = Recipe::default();
        recipe.style.color = ColorScheme::Auto;
        let built = build_peaks(&field, "p", &recipe).unwrap();
        let s = &built.scene;
        assert_eq!(s.kind, GlyphKind::Cylinder);
        assert_eq!(s.instances.len(), 2);
        assert_eq!(built.selected, [0, 0]);
        let g = &s.instances[0];
        let axis = glam::DVec3::from(quat_to_frame(g.rotation)[0]);
        assert!(axis.cross(d).length() < 1e-5, "{axis}");
        assert!((f64::from(g.radii[0]) - 1.0).abs() < 1e-6, "{:?}", g.radii);
        assert!((f64::from(s.instances[1].radii[0]) - 0.25).abs() < 1e-6);
        assert!((f64::from(g.radii[1]) - STICK_RADIUS * 2.0).abs() < 1e-5);
        assert_eq!(g.color_rgba(), [85, 170, 170, 255]);
        let centre = s.origin + glam::Vec3::from(g.centre).as_dvec3();
        assert!((centre - glam::DVec3::new(10.0, 0.0, 0.0)).length() < 1e-9);
        recipe.style.scale = Scale::Factor(0.1);
        let built = build_peaks(&field, "p", &recipe).unwrap();
        // Radii are stored to 2⁻¹⁷ (`pack_radius`).
        assert!((f64::from(built.scene.instances[0].radii[0]) - 0.4).abs() < 1e-5);
    }
}
