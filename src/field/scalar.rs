//! Scalar volumes: an anatomical image, an FA map or a mask, placed in the same world as the
//! tensor fields (RAS for NIfTI and NRRD), for `--underlay FILE` and `--mask FILE`.
//!
//! A volume is sampled through its own voxel-to-world matrix, so it need not share the tensors'
//! lattice (a 1 mm T1 under 2 mm tensors).
//!
//! [`read_scalar_volume`] reads NIfTI-1, NRRD and VTK image data with the tensor readers' header,
//! geometry and data code, so a volume's world is the one those readers put glyphs in: RAS for
//! NIfTI (sform, qform, pixdim) and NRRD (LPS turned into RAS as for tensors), the writer's own
//! for VTK.
//!
//! This module holds what those readers share, below them: the type, and `checked`, with
//! which each reader makes its volume. [`read_scalar_volume`], which picks the reader by the
//! file's name, is above them, in the `field` module.
//!
//! [`read_scalar_volume`]: crate::field::read_scalar_volume

use glam::{DMat4, DVec3, DVec4};

use crate::error::LoadErrorKind;

/// A volume the readers made, refused when its matrix cannot place voxels in the world
/// (`field` names the header field the matrix came from).
pub(crate) fn checked(
    dims: [usize; 3],
    values: Vec<f32>,
    voxel_to_world: [[f64; 4]; 4],
    field: &str,
) -> Result<ScalarVolume, LoadErrorKind> {
    let v = ScalarVolume {
        dims,
        values,
        voxel_to_world,
    };
    if v.world_to_voxel().is_none() {
        return Err(LoadErrorKind::Field {
            field: field.to_string(),
            message: "the voxel-to-world matrix is singular or not finite: the voxels have no place in the world".into(),
        });
    }
    Ok(v)
}

/// A 3-D scalar image and where its voxels are.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalarVolume {
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// `dims[0] * dims[1] * dims[2]` values, i fastest; NaN where the file has none.
    pub values: Vec<f32>,
    /// Rows of the 4x4 matrix taking (i, j, k, 1) to world (x, y, z, 1): voxel centres.
    pub voxel_to_world: [[f64; 4]; 4],
}

impl ScalarVolume {
    fn matrix(&self) -> DMat4 {
        DMat4::from_cols_array_2d(&self.voxel_to_world).transpose()
    }

    /// The value of voxel (i, j, k).
    pub fn at(&self, [i, j, k]: [usize; 3]) -> f32 {
        self.values[i + self.dims[0] * (j + self.dims[1] * k)]
    }

    /// The matrix taking world points to continuous voxel coordinates; `None` when the
    /// voxel-to-world matrix is singular or not finite.
    pub fn world_to_voxel(&self) -> Option<DMat4> {
        let m = self.matrix();
        let det = m.determinant();
        (det.is_finite() && det != 0.0)
            .then(|| m.inverse())
            .filter(|inv| inv.is_finite())
    }

    /// Continuous voxel coordinates of a world point; `None` for a singular matrix.
    pub fn voxel_of(&self, world: DVec3) -> Option<DVec3> {
        self.world_to_voxel()
            .map(|inv| (inv * DVec4::new(world.x, world.y, world.z, 1.0)).truncate())
    }

    /// The voxel whose centre is nearest to continuous voxel coordinates `v` (ties round up);
    /// `None` outside the volume (more than half a voxel beyond its outer centres).
    pub fn nearest_voxel(&self, v: DVec3) -> Option<[usize; 3]> {
        let mut ijk = [0usize; 3];
        for a in 0..3 {
            let r = (v[a] + 0.5).floor();
            if !(r >= 0.0 && r < self.dims[a] as f64) {
                return None;
            }
            ijk[a] = r as usize;
        }
        Some(ijk)
    }

    /// The value of the voxel whose centre is nearest to `world` (ties round up); `None`
    /// outside the volume (more than half a voxel beyond its outer centres).
    pub fn nearest(&self, world: DVec3) -> Option<f32> {
        self.nearest_voxel(self.voxel_of(world)?)
            .map(|ijk| self.at(ijk))
    }

    /// Trilinear interpolation at `world` (edges clamped to the outer voxel centres); `None`
    /// outside the volume as for [`Self::nearest`]. A NaN neighbour gives NaN.
    pub fn trilinear(&self, world: DVec3) -> Option<f32> {
        let v = self.voxel_of(world)?;
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        let mut f = [0.0f64; 3];
        for a in 0..3 {
            let n = self.dims[a];
            if n == 0 || !(v[a] >= -0.5 && v[a] < n as f64 - 0.5) {
                return None;
            }
            let x = v[a].clamp(0.0, (n - 1) as f64);
            lo[a] = x.floor() as usize;
            hi[a] = (lo[a] + 1).min(n - 1);
            f[a] = x - lo[a] as f64;
        }
        let mut sum = 0.0f64;
        for corner in 0..8 {
            let pick = |a: usize| corner >> a & 1 == 1;
            let ijk = [0, 1, 2].map(|a| if pick(a) { hi[a] } else { lo[a] });
            let w: f64 = (0..3)
                .map(|a| if pick(a) { f[a] } else { 1.0 - f[a] })
                .product();
            if w > 0.0 {
                sum += w * f64::from(self.at(ijk));
            }
        }
        Some(sum as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> ScalarVolume {
        // value = i + 10 j + 100 k on a 3x3x3 lattice, 2 mm voxels, origin (-2, 0, 4).
        let dims = [3, 3, 3];
        let mut values = Vec::new();
        for k in 0..3 {
            for j in 0..3 {
                for i in 0..3 {
                    values.push((i + 10 * j + 100 * k) as f32);
                }
            }
        }
        ScalarVolume {
            dims,
            values,
            voxel_to_world: [
                [2.0, 0.0, 0.0, -2.0],
                [0.0, 2.0, 0.0, 0.0],
                [0.0, 0.0, 2.0, 4.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
        }
    }

    #[test]
    fn nearest_finds_the_voxel_and_nothing_outside() {
        let v = ramp();
        assert_eq!(
            v.nearest(DVec3::new(0.0, 2.0, 8.0)),
            Some(1.0 + 10.0 + 200.0)
        );
        assert_eq!(v.nearest(DVec3::new(-2.9, -0.9, 3.1)), Some(0.0));
        assert_eq!(v.nearest(DVec3::new(-3.1, 0.0, 4.0)), None);
        assert_eq!(v.nearest(DVec3::new(0.0, 5.1, 4.0)), None);
    }

    #[test]
    fn trilinear_reproduces_a_linear_ramp() {
        let v = ramp();
        // Halfway between voxel centres along every axis: the ramp's value there.
        let w = DVec3::new(-1.0, 1.0, 5.0);
        let expect = 0.5 + 10.0 * 0.5 + 100.0 * 0.5;
        assert!((v.trilinear(w).unwrap() - expect).abs() < 1e-5);
        assert_eq!(v.trilinear(DVec3::new(-3.1, 0.0, 4.0)), None);
    }
}
