//! Tensor fields and scalar volumes handed over in memory rather than read from a file (the
//! Python package's numpy arrays): a lattice placed by a voxel-to-world matrix, built exactly as
//! the NIfTI reader builds its fields (so an array and the same numbers saved as NIfTI give the
//! same field), or tensors at given world positions, as a VTK point set.
//!
//! Errors name the argument (`affine`, `positions`, `tensors`) and say what is wrong, in one
//! line.

use nalgebra::Matrix4;

use super::frame::{Layout, TensorFrame, Why};
use super::order::ComponentOrder;
use super::scalar::{self, ScalarVolume};
use super::tensor_field::{Location, TensorArrayInfo, TensorField};
use crate::error::LoadErrorKind;

/// How the numbers of one tensor are laid out: six unique components in an order, or nine
/// (row-major 3x3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Components {
    Six(ComponentOrder),
    Nine,
}

impl Components {
    /// Values per tensor.
    pub fn len(self) -> usize {
        match self {
            Components::Six(_) => 6,
            Components::Nine => 9,
        }
    }

    /// Always false: a tensor has values.
    pub fn is_empty(self) -> bool {
        false
    }

    /// The row-major 3x3 tensor of one tensor's values (`c.len() == self.len()`).
    pub fn expand(self, c: &[f64]) -> [f64; 9] {
        match self {
            Components::Six(order) => order.expand(c),
            Components::Nine => std::array::from_fn(|i| c[i]),
        }
    }

    fn layout(self) -> Layout {
        match self {
            // Given by the caller, as `--order` is.
            Components::Six(order) => Layout::six(order, Why::Flag),
            Components::Nine => Layout::full(),
        }
    }
}

fn error(what: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: what.to_string(),
        message: message.into(),
    }
}

/// The voxel-to-world matrix of a lattice given in memory, checked: finite, last row
/// `0 0 0 1`, and invertible (its voxels must have a place in the world).
pub fn checked_affine(rows: [[f64; 4]; 4]) -> Result<Matrix4<f64>, LoadErrorKind> {
    if !rows.iter().flatten().all(|x| x.is_finite()) {
        return Err(error("affine", "holds a number that is not finite"));
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(error(
            "affine",
            format!(
                "the last row is {:?}; a voxel-to-world matrix ends in 0, 0, 0, 1",
                rows[3]
            ),
        ));
    }
    let a = Matrix4::from_fn(|i, j| rows[i][j]);
    let det = a.fixed_view::<3, 3>(0, 0).determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(error(
            "affine",
            "the voxel-to-world matrix is singular: the voxels have no place in the world",
        ));
    }
    Ok(a)
}

/// A field of `dims` voxels (`tensors` in NIfTI's order, x fastest, each as [`Components`]
/// says) placed by the voxel-to-world matrix `affine`, its tensors in `frame` (default
/// `voxel`, as NIfTI files): the field the NIfTI reader makes of the same numbers.
pub fn lattice(
    dims: [usize; 3],
    affine: [[f64; 4]; 4],
    components: Components,
    values: &[f64],
    frame: Option<TensorFrame>,
) -> Result<TensorField, LoadErrorKind> {
    let n = dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
    let c = components.len();
    if n.and_then(|n| n.checked_mul(c)) != Some(values.len()) {
        return Err(error(
            "tensors",
            format!(
                "{} values for {dims:?} voxels of {c} components",
                values.len()
            ),
        ));
    }
    let a = checked_affine(affine)?;
    let tensors = super::Tensors::F64(
        values
            .chunks_exact(c)
            .map(|t| components.expand(t))
            .collect(),
    );
    let array = TensorArrayInfo {
        name: "array".into(),
        components: c,
        location: Location::Point,
    };
    let opts = super::ReadOptions {
        tensor_frame: frame,
        ..Default::default()
    };
    let mut field = super::nifti::lattice_field(
        dims,
        (a, "affine"),
        &opts,
        tensors,
        array,
        components.layout(),
    )?;
    field.format = "array".into();
    Ok(field)
}

/// A field of tensors (each as [`Components`] says) at world `positions`, as a VTK point set
/// holds them: no lattice, tensors in world axes.
pub fn points(
    positions: Vec<[f64; 3]>,
    components: Components,
    values: &[f64],
) -> Result<TensorField, LoadErrorKind> {
    let c = components.len();
    if positions.len().checked_mul(c) != Some(values.len()) {
        return Err(error(
            "positions",
            format!(
                "{} positions for {} tensors: give one (x, y, z) per tensor",
                positions.len(),
                values.len() / c
            ),
        ));
    }
    if !positions.iter().flatten().all(|x| x.is_finite()) {
        return Err(error("positions", "hold a number that is not finite"));
    }
    let tensors = values
        .chunks_exact(c)
        .map(|t| components.expand(t))
        .collect();
    let mut field = TensorField::from_points(positions, tensors);
    field.format = "array".into();
    field.array = TensorArrayInfo {
        name: "array".into(),
        components: c,
        location: Location::Point,
    };
    field.meta.layout = Some(components.layout());
    Ok(field)
}

/// A scalar volume of `dims` voxels (x fastest) placed by `affine`, as for `--mask` and
/// `--underlay` files.
pub fn scalar_volume(
    dims: [usize; 3],
    values: Vec<f32>,
    affine: [[f64; 4]; 4],
) -> Result<ScalarVolume, LoadErrorKind> {
    if dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d)) != Some(values.len()) {
        return Err(error(
            "volume",
            format!("{} values for {dims:?} voxels", values.len()),
        ));
    }
    checked_affine(affine)?;
    scalar::checked(dims, values, affine, "affine")
}

#[cfg(test)]
mod tests {
    use super::*;

    const EYE: [[f64; 4]; 4] = [
        [2.0, 0.0, 0.0, -3.0],
        [0.0, 2.0, 0.0, 1.0],
        [0.0, 0.0, 2.0, 0.5],
        [0.0, 0.0, 0.0, 1.0],
    ];

    #[test]
    fn a_lattice_is_placed_by_its_affine_and_expanded_by_its_order() {
        let c = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let values: Vec<f64> = (0..8).flat_map(|_| c).collect();
        let f = lattice(
            [2, 2, 2],
            EYE,
            Components::Six(ComponentOrder::Fsl),
            &values,
            None,
        )
        .unwrap();
        assert_eq!(f.len(), 8);
        assert_eq!(f.position(1), [-1.0, 1.0, 0.5]);
        assert_eq!(f.position(2), [-3.0, 3.0, 0.5]);
        assert_eq!(f.tensor(0), ComponentOrder::Fsl.expand(&c));
        assert_eq!(f.spacing, Some(2.0));
        assert_eq!(f.format, "array");
    }

    #[test]
    fn bad_affines_and_counts_are_refused_with_their_name() {
        let values = vec![1.0; 9];
        let flat = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let e = lattice([1, 1, 1], flat, Components::Nine, &values, None).unwrap_err();
        assert!(e.to_string().contains("'affine'"), "{e}");
        assert!(e.to_string().contains("singular"), "{e}");
        let mut nan = EYE;
        nan[0][0] = f64::NAN;
        assert!(lattice([1, 1, 1], nan, Components::Nine, &values, None).is_err());
        let e = lattice([2, 1, 1], EYE, Components::Nine, &values, None).unwrap_err();
        assert!(e.to_string().contains("'tensors'"), "{e}");
        let e = points(vec![[0.0; 3]; 2], Components::Nine, &values).unwrap_err();
        assert!(e.to_string().contains("'positions'"), "{e}");
    }
}
