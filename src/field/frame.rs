//! Voxel-to-world geometry shared by the NIfTI and NRRD readers, and what a field says about
//! its layout and frames (reported by `info`).
//! (Each format's conventions for users: docs/book/src/user-guide/dti.md.)
//!
//! No tensor file says whether its tensors are in the voxel axes or in world axes, so the
//! reader is told ([`TensorFrame`], with a default per format) and records what it used.

use nalgebra::{Matrix3, Matrix4, Vector3};
use serde::Serialize;

use super::order::ComponentOrder;

/// The axes the stored tensors are expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TensorFrame {
    /// The voxel (index) axes: rotated into world by the rotation-or-reflection part of the
    /// voxel-to-world matrix (FSL `dtifit` with a negative-determinant matrix, DIPY).
    Voxel,
    /// As `voxel`, with FSL's x-flip where the matrix has a positive determinant (FSL's bvec
    /// convention, which `dtifit`'s tensors inherit).
    Fsl,
    /// World axes already (MRtrix, NRRD after its measurement frame).
    World,
}

crate::names::named_values!(TensorFrame {
    Voxel => "voxel",
    Fsl => "fsl",
    World => "world",
});

/// Where the component order came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Why {
    /// The file says (NIfTI intent code or 9 volumes, NRRD `kinds`, VTK's 9 components).
    File,
    /// `--order`.
    Flag,
    /// The documented default for the format.
    Default,
    /// The files' names (FSL's eigen set `_L1`..`_V3`).
    Names,
    /// A BEP016 map's JSON sidecar.
    Sidecar,
}

/// How the components were laid out.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Layout {
    /// `fsl`, `mrtrix`, `nifti`, `vtk` or `full` (nine components, row-major).
    pub order: String,
    pub why: Why,
}

impl Layout {
    pub fn six(order: ComponentOrder, why: Why) -> Self {
        Layout {
            order: order.name().to_string(),
            why,
        }
    }

    pub fn full() -> Self {
        Layout {
            order: "full".into(),
            why: Why::File,
        }
    }
}

/// The frames a field was read in.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameInfo {
    pub tensor_frame: TensorFrame,
    /// The world convention positions and tensors are given in (`RAS` for NIfTI and for NRRD
    /// after conversion; `VTK` for VTK files, whose world is whatever the writer used).
    pub world: String,
    /// Rows of the 4x4 voxel-to-world matrix, for NIfTI and NRRD (left out of the JSON for VTK
    /// files, whose lattice is given by origin, spacing and direction instead).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub voxel_to_world: Option<[[f64; 4]; 4]>,
    /// `sform`, `qform`, `pixdim`, `space directions` or `VTK`.
    pub source: String,
}

impl FrameInfo {
    /// The voxel-to-world matrix, the identity where there is none.
    fn matrix(&self) -> [[f64; 4]; 4] {
        self.voxel_to_world.unwrap_or([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
    }

    /// The world position of voxel `v` (x fastest) of a `dims` lattice placed by this frame.
    pub fn voxel_position(&self, dims: [usize; 3], v: usize) -> [f64; 3] {
        let d = dims;
        let ijk = [v % d[0], v / d[0] % d[1], v / d[0] / d[1]].map(|x| x as f64);
        let m = self.voxel_to_world.unwrap_or_default();
        std::array::from_fn(|r| m[r][0] * ijk[0] + m[r][1] * ijk[1] + m[r][2] * ijk[2] + m[r][3])
    }

    /// The smallest voxel step in world units (1 without a usable voxel-to-world matrix).
    pub fn smallest_step(&self) -> f64 {
        let m = self.matrix();
        let s = (0..3)
            .map(|c| (0..3).map(|r| m[r][c] * m[r][c]).sum::<f64>().sqrt())
            .fold(f64::INFINITY, f64::min);
        if s.is_finite() && s > 0.0 { s } else { 1.0 }
    }
}

/// What a BEP016 map's JSON sidecar said (read by [`super::bep016`]), as `info` reports it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sidecar {
    /// The sidecar's file name (the one read, or the one looked for).
    pub name: String,
    /// `ijk` or `xyz` when the sidecar decided the frame; `None` when the default was used.
    pub reference_axes: Option<String>,
}

/// What a reader knows about the data beyond the tensors.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReadMeta {
    pub layout: Option<Layout>,
    pub frame: Option<FrameInfo>,
    /// Voxels whose confidence (NRRD masked tensors) was below 0.5: stored as zero tensors, so
    /// that the lattice stays whole, and counted here.
    pub masked: usize,
    /// The BEP016 sidecar that decided the tensor frame (or was looked for), for BEP016 maps.
    pub sidecar: Option<Sidecar>,
    /// What the reader assumed that the user should know, one line each (a BEP016 map read
    /// with the default for want of a usable sidecar).
    pub notes: Vec<String>,
}

/// The rotation-or-reflection part of `m` (polar decomposition `m = R S`): `R = U Vᵀ` from the
/// SVD, so scaling and shear are removed and the handedness of `m` is kept.
///
/// `m` is scaled to a largest entry of 1 first: the rotation does not depend on the scale, and
/// voxel sizes of 1e200 (whose determinant overflows to infinity and whose SVD turns NaN) or
/// 1e-120 (whose determinant underflows to 0) are lattices like any other. `None` for a matrix
/// that is not finite, is singular, or whose rotation is not finite.
pub fn polar_rotation(m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let scale = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if !m.iter().all(|x| x.is_finite()) || scale == 0.0 {
        return None;
    }
    let m = m / scale;
    if m.determinant() == 0.0 {
        return None;
    }
    let svd = m.svd(true, true);
    Some(svd.u? * svd.v_t?).filter(|r| r.iter().all(|x| x.is_finite()))
}

/// The matrix that takes tensors stored in `frame` to world axes for a lattice whose
/// voxel-to-world linear part is `m`: `D_world = Q D Qᵀ`. `None` means the identity.
pub fn tensor_rotation(frame: TensorFrame, m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    match frame {
        TensorFrame::World => None,
        TensorFrame::Voxel => polar_rotation(m),
        TensorFrame::Fsl => {
            let r = polar_rotation(m)?;
            // FSL stores its voxel axes radiologically: when the matrix keeps handedness it
            // flips x before rotating (as it does for bvecs).
            if r.determinant() > 0.0 {
                Some(r * Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)))
            } else {
                Some(r)
            }
        }
    }
}

/// Row-major array form of a 3x3 matrix.
pub fn rows3(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// Row-major array form of a 4x4 matrix.
pub fn rows4(m: &Matrix4<f64>) -> [[f64; 4]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// The smallest voxel size of the lattice (length of each column of `m`) along axes with more
/// than one voxel, else along any axis; `None` if none is positive and finite.
pub fn smallest_spacing(m: &Matrix3<f64>, dims: [usize; 3]) -> Option<f64> {
    let size = |a: usize| m.column(a).norm();
    let ok = |s: &f64| *s > 0.0 && s.is_finite();
    let on_axes = (0..3)
        .filter(|&a| dims[a] > 1)
        .map(size)
        .filter(ok)
        .fold(f64::INFINITY, f64::min);
    let any = (0..3).map(size).filter(ok).fold(f64::INFINITY, f64::min);
    let s = if on_axes.is_finite() { on_axes } else { any };
    s.is_finite().then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polar_rotation_removes_scale_and_shear_and_keeps_reflection() {
        let r = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let s = Matrix3::new(2.0, 0.3, 0.0, 0.3, 1.5, 0.0, 0.0, 0.0, 3.0);
        let got = polar_rotation(&(r * s)).unwrap();
        assert!((got - r).abs().max() < 1e-12, "{got}");
        let flip = Matrix3::from_diagonal(&Vector3::new(-2.0, 2.0, 2.0));
        let got = polar_rotation(&flip).unwrap();
        assert!((got.determinant() + 1.0).abs() < 1e-12);
        assert!(polar_rotation(&Matrix3::zeros()).is_none());
    }

    #[test]
    fn fsl_frame_flips_x_only_for_positive_determinants() {
        let pos = Matrix3::from_diagonal(&Vector3::new(2.0, 2.0, 2.0));
        let q = tensor_rotation(TensorFrame::Fsl, &pos).unwrap();
        assert!(
            (q - Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)))
                .abs()
                .max()
                < 1e-12
        );
        let neg = Matrix3::from_diagonal(&Vector3::new(-2.0, 2.0, 2.0));
        let q = tensor_rotation(TensorFrame::Fsl, &neg).unwrap();
        let v = tensor_rotation(TensorFrame::Voxel, &neg).unwrap();
        assert_eq!(q, v);
        assert!(tensor_rotation(TensorFrame::World, &neg).is_none());
    }
}
