//! Which glyphs to show: an FA range, a stride over the lattice, axis-aligned slices, a
//! region-of-interest box and a mask volume.
//!
//! A [`Selection`] maps a field's [`GlyphSet`] to the indices (into `set.glyphs`) of the glyphs
//! to draw; the scene is then built from those glyphs only. Stride and slices use the lattice of
//! structured data ([`TensorField::lattice_dims`], x fastest); unstructured data has no lattice,
//! so there the stride runs over file order and slicing is not available. The ROI box tests the
//! glyph centres in world coordinates, so it works on any data (as ParaView's box clip). The
//! mask is sampled at the glyph centres too, through its own voxel-to-world matrix, so it need
//! not share the tensors' lattice.
//!
//! The same selection is used by the viewer's panel and by the `--fa-min`, `--fa-max`,
//! `--stride`, `--slice`, `--roi` and `--mask` flags of the command line; [`Selection::check`] and
//! [`Selection::check_field`] give the errors for input that cannot be honoured.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec4};
use rayon::prelude::*;

use crate::error::{LoadError, LoadErrorKind, escape_path};
use crate::field::scalar::ScalarVolume;
use crate::field::{Inputs, TensorField, read_scalar_volume_from};
use crate::glyph::GlyphSet;
use crate::tensor::shape;

/// One lattice plane perpendicular to `axis` (0 = x, 1 = y, 2 = z) at lattice `index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Plane {
    pub axis: usize,
    pub index: usize,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl std::fmt::Display for Plane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", AXES[self.axis.min(2)], self.index)
    }
}

impl std::str::FromStr for Plane {
    type Err = String;
    /// `x=I`, `y=J` or `z=K` (lattice indices, from 0).
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("slice '{s}' is not x=I, y=J or z=K (a lattice index from 0)");
        let (a, i) = s.split_once('=').ok_or_else(bad)?;
        let axis = match a.trim().to_ascii_lowercase().as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return Err(bad()),
        };
        let index = i.trim().parse::<usize>().map_err(|_| bad())?;
        Ok(Plane { axis, index })
    }
}

/// Which part of the lattice to show.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Slicing {
    /// Every lattice position.
    #[default]
    Whole,
    /// One plane perpendicular to `axis` (0 = x, 1 = y, 2 = z) at lattice `index`.
    Slice { axis: usize, index: usize },
    /// Three orthogonal planes through the lattice position `at`.
    Orthogonal { at: [usize; 3] },
    /// The union of any set of axis-aligned planes (`--slice x=10 --slice z=5`).
    Planes(Vec<Plane>),
}

impl Slicing {
    /// The planes this slicing keeps (their union), or `None` for the whole lattice.
    pub fn planes(&self) -> Option<Vec<Plane>> {
        match self {
            Slicing::Whole => None,
            Slicing::Slice { axis, index } => Some(vec![Plane {
                axis: (*axis).min(2),
                index: *index,
            }]),
            Slicing::Orthogonal { at } => Some(
                (0..3)
                    .map(|axis| Plane {
                        axis,
                        index: at[axis],
                    })
                    .collect(),
            ),
            Slicing::Planes(p) => Some(p.clone()),
        }
    }
}

/// A selection that cannot be honoured, with what was asked and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct SelectionError(pub String);

/// A mask volume (`--mask FILE`): a glyph is kept when the voxel nearest to its centre holds a
/// non-zero, finite value; glyphs outside the volume (more than half a voxel beyond its outer
/// voxel centres) are dropped.
///
/// The volume is shared ([`Arc`]): a selection is cloned with every change in the viewer, and a
/// mask can be as large as the tensor field. Two masks are equal when they share one volume
/// (pointer equality): a volume is never changed once read, and comparing voxels would cost as
/// much as the volume and call a NaN-holding mask unequal to itself.
#[derive(Clone)]
pub struct Mask {
    path: PathBuf,
    volume: Arc<ScalarVolume>,
    to_voxel: DMat4,
    /// The files the volume was read from (a `.nhdr` and its data file); none when handed over.
    read: Vec<PathBuf>,
}

/// The file and the size, not every voxel: selections are printed in debug messages.
impl std::fmt::Debug for Mask {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mask")
            .field("path", &self.path)
            .field("dims", &self.volume.dims)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Mask {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.volume, &other.volume)
    }
}

impl Mask {
    /// The mask in the scalar volume file `path` (any format
    /// [`read_scalar_volume`](crate::field::read_scalar_volume) reads).
    pub fn read(path: &Path) -> Result<Self, LoadError> {
        let inputs = Inputs::file_system();
        let volume = read_scalar_volume_from(&inputs, path)?;
        let mask = Self::build(path.to_path_buf(), Arc::new(volume))
            .map_err(|e| LoadError::new(path, LoadErrorKind::Other(e)))?;
        Ok(Self {
            read: inputs.paths_read(),
            ..mask
        })
    }

    /// A mask of `volume`; `path` names it in messages. An error when the volume's voxels
    /// cannot be placed (a singular matrix) or its values do not fill its dimensions.
    pub fn new(
        path: impl Into<PathBuf>,
        volume: Arc<ScalarVolume>,
    ) -> Result<Self, SelectionError> {
        let path = path.into();
        let shown = escape_path(&path);
        Self::build(path, volume).map_err(|e| SelectionError(format!("mask {shown}: {e}")))
    }

    fn build(path: PathBuf, volume: Arc<ScalarVolume>) -> Result<Self, String> {
        let want = volume
            .dims
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d));
        if want != Some(volume.values.len()) {
            return Err(format!(
                "{} values for {:?} voxels",
                volume.values.len(),
                volume.dims
            ));
        }
        let to_voxel = volume
            .world_to_voxel()
            .ok_or("the voxel-to-world matrix is singular")?;
        Ok(Self {
            path,
            volume,
            to_voxel,
            read: Vec::new(),
        })
    }

    /// The file the mask was read from, as given.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Every file [`Self::read`] read (the file, and a `.nhdr`'s data file): no output may
    /// replace one.
    pub fn files_read(&self) -> &[PathBuf] {
        &self.read
    }

    pub fn volume(&self) -> &Arc<ScalarVolume> {
        &self.volume
    }

    /// Whether a glyph centred at `world` is kept.
    pub fn keeps(&self, world: [f64; 3]) -> bool {
        let v = (self.to_voxel * DVec4::new(world[0], world[1], world[2], 1.0)).truncate();
        self.volume
            .nearest_voxel(v)
            .map(|ijk| self.volume.at(ijk))
            .is_some_and(|x| x.is_finite() && x != 0.0)
    }
}

/// What to draw of a field.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Inclusive FA range. An upper bound of 1 or more has no effect: FA of positive-definite
    /// tensors is at most 1, and indefinite ones (stress, strain) above 1 are kept with it.
    pub fa_min: f64,
    pub fa_max: f64,
    /// Every `stride`-th lattice position along each axis (1 = all).
    pub stride: usize,
    pub slicing: Slicing,
    /// Region of interest `[x0, y0, z0, x1, y1, z1]`: keep glyphs whose centre (world
    /// coordinates) lies in the box, bounds included.
    pub roi: Option<[f64; 6]>,
    /// Keep glyphs whose centre is in a non-zero, finite voxel of this volume.
    pub mask: Option<Mask>,
    /// Keep glyphs whose largest |σ| is at least this (`--min-stress`; 0 keeps all).
    pub min_stress: f64,
}

impl Default for Selection {
    fn default() -> Self {
        Self {
            fa_min: 0.0,
            fa_max: 1.0,
            stride: 1,
            slicing: Slicing::Whole,
            roi: None,
            mask: None,
            min_stress: 0.0,
        }
    }
}

/// Lattice coordinates (i, j, k) of file-order index `n` on a lattice of `dims` (x fastest).
pub fn lattice_coords(n: usize, dims: [usize; 3]) -> [usize; 3] {
    let [nx, ny, _] = dims.map(|d| d.max(1));
    [n % nx, (n / nx) % ny, n / (nx * ny)]
}

/// The box `[x0, y0, z0, x1, y1, z1]` around the glyph centres (the ROI that keeps every
/// glyph; all zero for an empty set).
pub fn centre_bounds(set: &GlyphSet) -> [f64; 6] {
    point_bounds(set.glyphs.par_iter().map(|g| g.centre))
}

/// The box `[x0, y0, z0, x1, y1, z1]` around `points` (all zero for none).
pub fn point_bounds(points: impl ParallelIterator<Item = [f64; 3]>) -> [f64; 6] {
    // The identity of the fold: every point extends it.
    const EMPTY: [f64; 6] = [
        f64::INFINITY,
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    let b = points
        .fold(
            || EMPTY,
            |mut b, p| {
                for a in 0..3 {
                    b[a] = b[a].min(p[a]);
                    b[a + 3] = b[a + 3].max(p[a]);
                }
                b
            },
        )
        .reduce(
            || EMPTY,
            |mut a, b| {
                for k in 0..3 {
                    a[k] = a[k].min(b[k]);
                    a[k + 3] = a[k + 3].max(b[k + 3]);
                }
                a
            },
        );
    if b == EMPTY { [0.0; 6] } else { b }
}

/// `[x0, y0, z0, x1, y1, z1]` from "x0,y0,z0,x1,y1,z1", checked (finite, x0 ≤ x1 …).
pub fn parse_roi(s: &str) -> Result<[f64; 6], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 6 {
        return Err(format!(
            "ROI '{s}' is not six numbers x0,y0,z0,x1,y1,z1 (got {})",
            parts.len()
        ));
    }
    let mut roi = [0.0; 6];
    for (r, p) in roi.iter_mut().zip(&parts) {
        *r = p
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("ROI '{s}': '{}' is not a finite number", p.trim()))?;
    }
    check_roi(&roi).map_err(|e| e.0)?;
    Ok(roi)
}

fn check_roi(roi: &[f64; 6]) -> Result<(), SelectionError> {
    if roi.iter().any(|v| !v.is_finite()) {
        return Err(SelectionError(format!(
            "ROI {} has a value that is not a finite number",
            fmt_roi(roi)
        )));
    }
    for a in 0..3 {
        if roi[a] > roi[a + 3] {
            return Err(SelectionError(format!(
                "ROI {}: {}0 = {} is greater than {}1 = {}",
                fmt_roi(roi),
                AXES[a],
                roi[a],
                AXES[a],
                roi[a + 3]
            )));
        }
    }
    Ok(())
}

fn fmt_roi(roi: &[f64; 6]) -> String {
    roi.iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

impl Selection {
    /// True when this selection keeps every glyph.
    pub fn is_everything(&self) -> bool {
        self.fa_min <= 0.0
            && self.fa_max >= 1.0
            && self.stride <= 1
            && self.slicing == Slicing::Whole
            && self.roi.is_none()
            && self.mask.is_none()
            && self.min_stress <= 0.0
    }

    /// Errors that do not depend on the data: FA bounds outside [0, 1] or NaN, fa-min above
    /// fa-max, stride 0, an ROI with x0 > x1 (or y, z) or a non-finite bound.
    pub fn check(&self) -> Result<(), SelectionError> {
        for (name, v) in [("--fa-min", self.fa_min), ("--fa-max", self.fa_max)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(SelectionError(format!(
                    "{name} must be a number between 0 and 1, got {v}"
                )));
            }
        }
        if self.fa_min > self.fa_max {
            return Err(SelectionError(format!(
                "--fa-min {} is greater than --fa-max {}",
                self.fa_min, self.fa_max
            )));
        }
        if self.stride == 0 {
            return Err(SelectionError("--stride must be at least 1".into()));
        }
        if let Some(roi) = &self.roi {
            check_roi(roi)?;
        }
        Ok(())
    }

    /// [`Self::check`], plus what depends on the data: slicing needs a lattice, and every
    /// slice index must lie inside it.
    pub fn check_field(&self, field: &TensorField) -> Result<(), SelectionError> {
        self.check()?;
        let Some(planes) = self.slicing.planes() else {
            return Ok(());
        };
        let Some(dims) = field.lattice_dims() else {
            return Err(SelectionError(format!(
                "cannot slice {} ({}): unstructured data has no lattice (use --roi instead)",
                planes
                    .iter()
                    .map(|p| p.to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
                field.dataset.as_str()
            )));
        };
        for p in &planes {
            let axis = p.axis.min(2);
            if p.index >= dims[axis] {
                return Err(SelectionError(format!(
                    "slice {p} is outside the lattice: it has {} × {} × {} positions, so {} runs from 0 to {}",
                    dims[0],
                    dims[1],
                    dims[2],
                    AXES[axis],
                    dims[axis].max(1) - 1
                )));
            }
        }
        Ok(())
    }

    /// The selection in the command line's words, for messages.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if self.fa_min > 0.0 {
            parts.push(format!("--fa-min {}", self.fa_min));
        }
        if self.fa_max < 1.0 {
            parts.push(format!("--fa-max {}", self.fa_max));
        }
        if self.stride > 1 {
            parts.push(format!("--stride {}", self.stride));
        }
        for p in self.slicing.planes().unwrap_or_default() {
            parts.push(format!("--slice {p}"));
        }
        if let Some(roi) = &self.roi {
            parts.push(format!("--roi {}", fmt_roi(roi)));
        }
        if let Some(mask) = &self.mask {
            parts.push(format!("--mask {}", escape_path(mask.path())));
        }
        if self.min_stress > 0.0 {
            parts.push(format!("--min-stress {}", self.min_stress));
        }
        if parts.is_empty() {
            "everything".into()
        } else {
            parts.join(" ")
        }
    }

    /// Indices into `set.glyphs` of the selected glyphs, in order.
    pub fn select(&self, field: &TensorField, set: &GlyphSet) -> Vec<usize> {
        let dims = field.lattice_dims();
        let stride = self.stride.max(1);
        let fa_all = self.fa_min <= 0.0 && self.fa_max >= 1.0;
        let planes = self.slicing.planes();
        let keep = |g: &crate::glyph::Glyph| {
            let n = g.index as usize;
            let lattice_ok = match dims {
                Some(d) => keeps_lattice(planes.as_deref(), lattice_coords(n, d), stride),
                // No lattice: stride over file order; slicing keeps nothing.
                None => planes.is_none() && n.is_multiple_of(stride),
            };
            lattice_ok
                && self
                    .roi
                    .is_none_or(|r| (0..3).all(|a| g.centre[a] >= r[a] && g.centre[a] <= r[a + 3]))
                && self.mask.as_ref().is_none_or(|m| m.keeps(g.centre))
                && (fa_all || {
                    let fa = shape::fa(g.eigenvalues.map(f64::from));
                    fa >= self.fa_min && (self.fa_max >= 1.0 || fa <= self.fa_max)
                })
                && (self.min_stress <= 0.0
                    || g.eigenvalues
                        .iter()
                        .any(|l| f64::from(l.abs()) >= self.min_stress))
        };
        // rayon's collect keeps the order of the input.
        set.glyphs
            .par_iter()
            .enumerate()
            .filter(|(_, g)| keep(g))
            .map(|(k, _)| k)
            .collect()
    }

    /// A subset of `set` holding the selected glyphs; the field statistics stay those of the
    /// whole field, so scale and colours do not change with the selection.
    pub fn subset(set: &GlyphSet, indices: &[usize]) -> GlyphSet {
        GlyphSet {
            glyphs: indices.iter().map(|&k| set.glyphs[k]).collect(),
            stats: set.stats.clone(),
        }
    }
}

/// Whether lattice position `c` is kept by the union of `planes` (all of it when `None`).
fn keeps_lattice(planes: Option<&[Plane]>, c: [usize; 3], stride: usize) -> bool {
    // Stride applies along the axes in a plane, not across it (a slice stays a slice).
    let on_stride = |axes: &[usize]| axes.iter().all(|&a| c[a].is_multiple_of(stride));
    match planes {
        None => on_stride(&[0, 1, 2]),
        Some(planes) => planes.iter().any(|p| {
            let axis = p.axis.min(2);
            c[axis] == p.index && on_stride(&others(axis))
        }),
    }
}

fn others(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::synthetic::grid;
    use crate::glyph::derive_glyphs;

    fn demo(n: usize) -> (TensorField, GlyphSet) {
        let f = grid(n);
        let s = derive_glyphs(&f, &crate::progress::Silent);
        (f, s)
    }

    #[test]
    fn default_keeps_everything() {
        let (f, s) = demo(6);
        assert!(Selection::default().is_everything());
        assert_eq!(Selection::default().select(&f, &s).len(), s.glyphs.len());
    }

    #[test]
    fn stride_and_slices_count_lattice_positions() {
        let (f, s) = demo(6);
        assert_eq!(s.glyphs.len(), 216, "the demo grid has no invalid tensors");
        let sel = |stride, slicing: Slicing| {
            Selection {
                stride,
                slicing,
                ..Selection::default()
            }
            .select(&f, &s)
        };
        assert_eq!(sel(2, Slicing::Whole).len(), 27);
        assert_eq!(sel(1, Slicing::Slice { axis: 2, index: 3 }).len(), 36);
        assert_eq!(sel(2, Slicing::Slice { axis: 0, index: 1 }).len(), 9);
        // Three planes of 36 share 3 lines of 6 and one point: 3·36 − 3·6 + 1.
        assert_eq!(sel(1, Slicing::Orthogonal { at: [2, 2, 2] }).len(), 91);
        for k in sel(1, Slicing::Slice { axis: 1, index: 4 }) {
            let c = lattice_coords(s.glyphs[k].index as usize, [6, 6, 6]);
            assert_eq!(c[1], 4);
        }
        assert!(sel(1, Slicing::Slice { axis: 2, index: 99 }).is_empty());
    }

    #[test]
    fn fa_range_filters_by_anisotropy() {
        let (f, s) = demo(6);
        let sel = Selection {
            fa_min: 0.5,
            fa_max: 1.0,
            ..Selection::default()
        };
        let kept = sel.select(&f, &s);
        assert!(!kept.is_empty() && kept.len() < s.glyphs.len());
        for k in &kept {
            assert!(shape::fa(s.glyphs[*k].eigenvalues.map(f64::from)) >= 0.5);
        }
        let sub = Selection::subset(&s, &kept);
        assert_eq!(sub.glyphs.len(), kept.len());
        assert_eq!(sub.stats, s.stats);
    }

    #[test]
    fn lattice_coordinates_run_x_fastest() {
        assert_eq!(lattice_coords(0, [4, 3, 2]), [0, 0, 0]);
        assert_eq!(lattice_coords(5, [4, 3, 2]), [1, 1, 0]);
        assert_eq!(lattice_coords(23, [4, 3, 2]), [3, 2, 1]);
    }

    #[test]
    fn roi_keeps_centres_in_the_box_bounds_included() {
        // grid:N has its lattice position (i, j, k) at world (i, j, k).
        let (f, s) = demo(8);
        let roi = |r: [f64; 6]| {
            Selection {
                roi: Some(r),
                ..Selection::default()
            }
            .select(&f, &s)
        };
        // Integer bounds are inclusive: 3 × 3 × 3 positions.
        assert_eq!(roi([2.0, 2.0, 2.0, 4.0, 4.0, 4.0]).len(), 27);
        // x ∈ {2, 3, 4}, every y (8), z = 2 only.
        assert_eq!(roi([1.5, -10.0, 2.0, 4.0, 10.0, 2.0]).len(), 3 * 8);
        // A box between lattice planes holds no centre.
        assert!(roi([0.2, 0.0, 0.0, 0.8, 7.0, 7.0]).is_empty());
        for k in roi([0.0, 5.0, 0.0, 7.0, 7.0, 1.0]) {
            let c = s.glyphs[k].centre;
            assert!(c[1] >= 5.0 && c[2] <= 1.0);
        }
        // ROI combines with the lattice selection (intersection): z = 3 plane ∩ x ≤ 1.
        let both = Selection {
            roi: Some([0.0, 0.0, 0.0, 1.0, 7.0, 7.0]),
            slicing: Slicing::Planes(vec![Plane { axis: 2, index: 3 }]),
            ..Selection::default()
        };
        assert_eq!(both.select(&f, &s).len(), 2 * 8);
        assert!(!both.is_everything());
    }

    #[test]
    fn centre_bounds_box_the_lattice() {
        let (_, s) = demo(5);
        assert_eq!(centre_bounds(&s), [0.0, 0.0, 0.0, 4.0, 4.0, 4.0]);
        assert_eq!(centre_bounds(&GlyphSet::default()), [0.0; 6]);
    }

    #[test]
    fn roi_works_without_a_lattice() {
        let (mut f, s) = demo(5);
        f.dims = None;
        let sel = Selection {
            roi: Some([0.0, 0.0, 0.0, 1.0, 1.0, 4.0]),
            ..Selection::default()
        };
        sel.check_field(&f).unwrap();
        assert_eq!(sel.select(&f, &s).len(), 2 * 2 * 5);
    }

    #[test]
    fn any_set_of_planes_keeps_their_union() {
        let (f, s) = demo(8);
        let planes = |p: &[(usize, usize)], stride| {
            Selection {
                stride,
                slicing: Slicing::Planes(
                    p.iter()
                        .map(|&(axis, index)| Plane { axis, index })
                        .collect(),
                ),
                ..Selection::default()
            }
            .select(&f, &s)
            .len()
        };
        // Three planes of 8 × 8: x=1 meets each z plane in a line of 8; z=5 and z=6 are parallel.
        assert_eq!(planes(&[(0, 1), (2, 5), (2, 6)], 1), 3 * 64 - 2 * 8);
        // A repeated plane counts once.
        assert_eq!(planes(&[(1, 4), (1, 4)], 1), 64);
        // Stride 2 runs along each plane: 4 × 4 positions per plane; x=1 keeps only even z, so it
        // shares nothing with z=5 (odd) and z=6 keeps only even x, which x=1 is not.
        assert_eq!(planes(&[(0, 1), (2, 5), (2, 6)], 2), 3 * 16);
        // The viewer's modes are plane sets too.
        let ortho = Selection {
            slicing: Slicing::Orthogonal { at: [2, 3, 4] },
            ..Selection::default()
        };
        assert_eq!(
            ortho.select(&f, &s).len(),
            planes(&[(0, 2), (1, 3), (2, 4)], 1)
        );
        assert_eq!(ortho.select(&f, &s).len(), 3 * 64 - 3 * 8 + 1);
    }

    #[test]
    fn bad_selections_are_errors_that_say_why() {
        let (f, _) = demo(4);
        let err = |sel: Selection| sel.check_field(&f).unwrap_err().0;
        let base = Selection::default();
        assert!(
            err(Selection {
                fa_min: 0.6,
                fa_max: 0.4,
                ..base.clone()
            })
            .contains("--fa-min 0.6 is greater than --fa-max 0.4")
        );
        for v in [1.5, -0.1, f64::NAN] {
            let e = err(Selection {
                fa_min: v,
                ..base.clone()
            });
            assert!(
                e.contains("--fa-min must be a number between 0 and 1"),
                "{e}"
            );
            let e = err(Selection {
                fa_max: v,
                ..base.clone()
            });
            assert!(e.contains("--fa-max"), "{e}");
        }
        assert!(
            err(Selection {
                stride: 0,
                ..base.clone()
            })
            .contains("--stride")
        );
        let e = err(Selection {
            roi: Some([0.0, 3.0, 0.0, 1.0, 2.0, 1.0]),
            ..base.clone()
        });
        assert!(e.contains("y0 = 3 is greater than y1 = 2"), "{e}");
        let e = err(Selection {
            slicing: Slicing::Planes(vec![
                Plane { axis: 0, index: 1 },
                Plane { axis: 2, index: 4 },
            ]),
            ..base.clone()
        });
        assert!(e.contains("slice z=4 is outside the lattice"), "{e}");
        assert!(e.contains("4 × 4 × 4"), "{e}");
        assert!(e.contains("from 0 to 3"), "{e}");
        let mut unstructured = f.clone();
        unstructured.dims = None;
        let e = Selection {
            slicing: Slicing::Slice { axis: 1, index: 0 },
            ..base.clone()
        }
        .check_field(&unstructured)
        .unwrap_err()
        .0;
        assert!(
            e.contains("cannot slice y=0") && e.contains("no lattice"),
            "{e}"
        );
        base.check_field(&unstructured).unwrap();
    }

    #[test]
    fn planes_and_rois_parse_or_say_why_not() {
        assert_eq!("x=10".parse::<Plane>(), Ok(Plane { axis: 0, index: 10 }));
        assert_eq!(" Z = 0 ".parse::<Plane>(), Ok(Plane { axis: 2, index: 0 }));
        for bad in ["w=3", "x", "x=", "x=-1", "z=1.5", "=2", "x=1=2"] {
            let e = bad.parse::<Plane>().unwrap_err();
            assert!(e.contains("is not x=I, y=J or z=K"), "{bad}: {e}");
        }
        assert_eq!(
            parse_roi("-1,0,0.5,2,3,4e0"),
            Ok([-1.0, 0.0, 0.5, 2.0, 3.0, 4.0])
        );
        assert!(parse_roi("0,0,0,1,1").unwrap_err().contains("six numbers"));
        assert!(parse_roi("0,0,0,1,1,nan").unwrap_err().contains("finite"));
        assert!(parse_roi("0,0,0,1,1,x").unwrap_err().contains("'x'"));
        assert!(
            parse_roi("2,0,0,1,1,1")
                .unwrap_err()
                .contains("x0 = 2 is greater than x1 = 1")
        );
    }

    /// A volume of `dims` voxels whose voxel (i, j, k) is at world `origin + size · (i, j, k)`.
    fn volume(
        dims: [usize; 3],
        values: Vec<f32>,
        size: f64,
        origin: [f64; 3],
    ) -> Arc<ScalarVolume> {
        let mut m = [[0.0; 4]; 4];
        for a in 0..3 {
            m[a][a] = size;
            m[a][3] = origin[a];
        }
        m[3][3] = 1.0;
        Arc::new(ScalarVolume {
            dims,
            values,
            voxel_to_world: m,
        })
    }

    fn masked(f: &TensorField, s: &GlyphSet, mask: Mask) -> Vec<[usize; 3]> {
        Selection {
            mask: Some(mask),
            ..Selection::default()
        }
        .select(f, s)
        .into_iter()
        .map(|k| lattice_coords(s.glyphs[k].index as usize, [4, 4, 4]))
        .collect()
    }

    #[test]
    fn mask_on_the_same_lattice_keeps_non_zero_finite_voxels() {
        // grid:4 has lattice position (i, j, k) at world (i, j, k): the mask shares it.
        let (f, s) = demo(4);
        let at = |i: usize, j: usize, k: usize| i + 4 * (j + 4 * k);
        let mut values: Vec<f32> = (0..64)
            .map(|n| {
                let [i, j, k] = lattice_coords(n, [4, 4, 4]);
                ((i + j + k) % 2) as f32
            })
            .collect();
        values[at(1, 0, 0)] = f32::NAN;
        values[at(0, 1, 0)] = f32::INFINITY;
        values[at(0, 0, 0)] = -0.5;
        let mask = Mask::new("same.nii", volume([4, 4, 4], values, 1.0, [0.0; 3])).unwrap();
        let kept = masked(&f, &s, mask);
        let want: Vec<[usize; 3]> = (0..64)
            .map(|n| lattice_coords(n, [4, 4, 4]))
            .filter(|&[i, j, k]| {
                ((i + j + k) % 2 == 1 && [i, j, k] != [1, 0, 0] && [i, j, k] != [0, 1, 0])
                    || [i, j, k] == [0, 0, 0]
            })
            .collect();
        assert_eq!(kept, want);
    }

    #[test]
    fn mask_on_a_coarser_shifted_lattice_uses_its_nearest_voxel() {
        let (f, s) = demo(4);
        // 2 mm voxels centred at 0.5 and 2.5 along y and z: lattice 0, 1 fall in voxel 0
        // and 2, 3 in voxel 1. One voxel along x (centre 0.5): x = 2 is 0.75 voxels out.
        let values = vec![1.0, 0.0, 0.0, 1.0];
        let mask = Mask::new("coarse.nii", volume([1, 2, 2], values, 2.0, [0.5; 3])).unwrap();
        let kept = masked(&f, &s, mask);
        let want: Vec<[usize; 3]> = (0..64)
            .map(|n| lattice_coords(n, [4, 4, 4]))
            .filter(|&[i, j, k]| i < 2 && (j / 2 == k / 2))
            .collect();
        assert_eq!(kept, want);
    }

    #[test]
    fn masks_are_equal_when_they_share_the_volume() {
        let v = volume([1, 1, 1], vec![1.0], 1.0, [0.0; 3]);
        let a = Mask::new("m.nii", v.clone()).unwrap();
        let sel = Selection {
            mask: Some(a.clone()),
            ..Selection::default()
        };
        assert_eq!(sel.clone(), sel);
        assert!(!sel.is_everything());
        assert_eq!(Mask::new("other.nii", v.clone()).unwrap(), a);
        assert_ne!(Mask::new("m.nii", Arc::new((*v).clone())).unwrap(), a);
        let singular = volume([1, 1, 1], vec![1.0], 0.0, [0.0; 3]);
        let e = Mask::new("flat.nii", singular).unwrap_err().0;
        assert!(e.contains("flat.nii") && e.contains("singular"), "{e}");
        let e = Mask::new("short.nii", volume([2, 1, 1], vec![1.0], 1.0, [0.0; 3]))
            .unwrap_err()
            .0;
        assert!(e.contains("1 values for [2, 1, 1] voxels"), "{e}");
    }

    #[test]
    fn describe_names_what_was_asked() {
        let sel = Selection {
            fa_min: 0.9,
            stride: 2,
            slicing: Slicing::Planes(vec![Plane { axis: 0, index: 3 }]),
            roi: Some([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]),
            ..Selection::default()
        };
        assert_eq!(
            sel.describe(),
            "--fa-min 0.9 --stride 2 --slice x=3 --roi 0,0,0,1,1,1"
        );
        let v = volume([1, 1, 1], vec![1.0], 1.0, [0.0; 3]);
        let sel = Selection {
            mask: Some(Mask::new("dir/fa\nmask.nii.gz", v).unwrap()),
            ..sel
        };
        assert!(
            sel.describe().ends_with(" --mask dir/fa\\nmask.nii.gz"),
            "{}",
            sel.describe()
        );
        assert_eq!(Selection::default().describe(), "everything");
    }
}
