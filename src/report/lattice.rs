//! Where a report's slices are: which lattice axis an orientation's slices run along, the
//! lattice's box in the world, which slices to show, and the names of directions and slices
//! drawn on the tiles. For tensor fields (their positions) and SH fields (an affine) alike.

use glam::DVec3;

use crate::field::TensorField;
use crate::glyph::GlyphSet;
use crate::legend::axis_labels;
use crate::select::lattice_coords;

/// A row's orientation: its name and the world axis (x, y, z) its slices are normal to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Orientation {
    pub name: &'static str,
    pub world_axis: usize,
}

/// The three rows of a map's report.
pub const ORIENTATIONS: [Orientation; 3] = [
    Orientation {
        name: "axial",
        world_axis: 2,
    },
    Orientation {
        name: "coronal",
        world_axis: 1,
    },
    Orientation {
        name: "sagittal",
        world_axis: 0,
    },
];

/// The lattice axis whose steps run most nearly along world axis `world`: the axis whose
/// slices are this orientation's, whatever order the voxels are stored in.
pub fn lattice_axis(field: &TensorField, dims: [usize; 3], world: usize) -> usize {
    lattice_axis_of(position_in(field, dims), dims, world)
}

/// The world position of lattice voxel (i, j, k) of `field`.
pub(super) fn position_in(
    field: &TensorField,
    dims: [usize; 3],
) -> impl Fn([usize; 3]) -> DVec3 + '_ {
    move |c| DVec3::from(field.position(c[0] + dims[0] * (c[1] + dims[1] * c[2])))
}

/// [`lattice_axis`] of any lattice, its voxels' world positions given by `at` (an SH field
/// has an affine, not a list of positions).
pub(super) fn lattice_axis_of(
    at: impl Fn([usize; 3]) -> DVec3,
    dims: [usize; 3],
    world: usize,
) -> usize {
    let origin = at([0, 0, 0]);
    (0..3)
        .max_by(|&a, &b| {
            let along = |axis: usize| {
                if dims[axis] < 2 {
                    return -1.0;
                }
                let mut c = [0; 3];
                c[axis] = 1;
                let step = (at(c) - origin).normalize_or_zero();
                step[world].abs()
            };
            along(a).total_cmp(&along(b))
        })
        .unwrap_or(world)
}

/// The box (centre, half extents) of the lattice's voxels, corners to corners.
pub(super) fn lattice_box(field: &TensorField, dims: [usize; 3]) -> (DVec3, DVec3) {
    lattice_box_of(position_in(field, dims), dims)
}

/// [`lattice_box`] of a lattice whose voxels' world positions `at` gives.
pub(super) fn lattice_box_of(at: impl Fn([usize; 3]) -> DVec3, dims: [usize; 3]) -> (DVec3, DVec3) {
    let corners: Vec<DVec3> = (0..8)
        .map(|k| at([0, 1, 2].map(|a| if k >> a & 1 == 1 { dims[a] - 1 } else { 0 })))
        .collect();
    let lo = corners.iter().fold(DVec3::INFINITY, |m, c| m.min(*c));
    let hi = corners.iter().fold(DVec3::NEG_INFINITY, |m, c| m.max(*c));
    // Half a voxel beyond the centres of the outer ones.
    let step = (0..3)
        .filter(|&a| dims[a] > 1)
        .map(|a| {
            let mut c = [0; 3];
            c[a] = 1;
            (at(c) - at([0; 3])).length()
        })
        .fold(0.0, f64::max);
    ((lo + hi) / 2.0, (hi - lo) / 2.0 + DVec3::splat(step / 2.0))
}

/// Up to `n` slices along lattice `axis`, evenly spaced through the part of the volume that
/// holds valid tensors (its first and last slices, often nearly empty, left out), each moved
/// to the nearest slice with a valid tensor.
pub fn slices(set: &GlyphSet, dims: [usize; 3], axis: usize, n: usize) -> Vec<usize> {
    let mut count = vec![0usize; dims[axis]];
    for g in &set.glyphs {
        count[lattice_coords(g.index as usize, dims)[axis]] += 1;
    }
    slices_of(&count, n)
}

/// [`slices`] of the slices whose glyph counts are `count`, one per slice.
pub(super) fn slices_of(count: &[usize], n: usize) -> Vec<usize> {
    let held: Vec<usize> = (0..count.len()).filter(|&i| count[i] > 0).collect();
    let (Some(&lo), Some(&hi)) = (held.first(), held.last()) else {
        return Vec::new();
    };
    if hi - lo < n {
        return held.into_iter().take(n).collect();
    }
    let mut out: Vec<usize> = (1..=n)
        .map(|j| {
            let target = lo as f64 + (hi - lo) as f64 * j as f64 / (n + 1) as f64;
            *held
                .iter()
                .min_by(|a, b| {
                    (**a as f64 - target)
                        .abs()
                        .total_cmp(&(**b as f64 - target).abs())
                })
                .expect("held is not empty")
        })
        .collect();
    out.dedup();
    out
}

/// The label of world direction `d`: the axis it mostly runs along, by its sign.
fn direction_label(d: DVec3, anatomical: bool) -> &'static str {
    let a = d.abs().max_position();
    axis_labels(anatomical)[a][usize::from(d[a] < 0.0)]
}

/// The labels at a tile's (left, right, top, bottom) edges for a camera looking along
/// `forward` with `up`: where the world's directions point on screen.
pub fn edge_labels(forward: DVec3, up: DVec3, anatomical: bool) -> [&'static str; 4] {
    let right = forward.cross(up).normalize();
    let up = right.cross(forward).normalize();
    [-right, right, up, -up].map(|d| direction_label(d, anatomical))
}

/// A slice's name: its lattice index, and where it is in the world along the row's axis (the
/// lattice's voxels' world positions given by `at`).
pub(super) fn slice_place(
    at: impl Fn([usize; 3]) -> DVec3,
    axis: usize,
    index: usize,
    orientation: Orientation,
    anatomical: bool,
) -> [String; 2] {
    let mut c = [0; 3];
    c[axis] = index;
    let p = at(c);
    let w = orientation.world_axis;
    let unit = if anatomical { " mm" } else { "" };
    [
        format!("{}={index}", ["i", "j", "k"][axis]),
        format!("{}={:.1}{unit}", ["x", "y", "z"][w], p[w]),
    ]
}
