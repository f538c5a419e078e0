//! Fibre directions per voxel (peaks): [`PeakField`], read from the images MRtrix's `sh2peaks`
//! writes (3 values a peak along the fourth axis: the direction scaled by the ODF's amplitude,
//! NaN where a voxel has fewer peaks), whose header says what it is (`command_history` ends
//! with `sh2peaks`, [`super::FieldKind::of_file`]; the directions in scanner axes, world RAS),
//! and from NIfTI files of peaks: `sh2peaks` output converted, and DIPY's `peaks_dirs` (unit
//! directions in the voxel axes) with the amplitudes of the `peaks_values` file beside it
//! (`nifti::peaks`; `--holds peaks` says what such a file holds). The readers are the
//! formats' ([`super::mif`], `nifti::peaks`); [`super::read_peak_field_from`] picks one.

use super::frame::FrameInfo;
use super::tensor_field::{Location, TensorArrayInfo, TensorField};

/// Up to `per_voxel` fibre directions in each voxel of a lattice.
#[derive(Debug, Clone, PartialEq)]
pub struct PeakField {
    /// `mif`.
    pub format: String,
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// Peaks a voxel can hold (volumes / 3).
    pub per_voxel: usize,
    /// Peak `p` of voxel `v` (x fastest) at `v * per_voxel + p`: the direction scaled by its
    /// amplitude, in world axes (turned there when read from the file's, `frame.tensor_frame`);
    /// NaN or zero where there is none.
    pub vectors: Vec<[f32; 3]>,
    /// The voxel-to-world matrix and the axes the file stored the directions in.
    pub frame: FrameInfo,
}

impl PeakField {
    pub fn voxels(&self) -> usize {
        self.dims.iter().product()
    }

    /// Peak `p` of voxel `v`, `None` where there is none (NaN or of zero length).
    pub fn peak(&self, v: usize, p: usize) -> Option<[f32; 3]> {
        let x = self.vectors[v * self.per_voxel + p];
        let l2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        (l2.is_finite() && l2 > 0.0).then_some(x)
    }

    /// Voxel `v`'s peaks, largest first as their writer stored them.
    pub fn peaks_of(&self, v: usize) -> impl Iterator<Item = [f32; 3]> + '_ {
        (0..self.per_voxel).filter_map(move |p| self.peak(v, p))
    }

    /// How many voxels hold 0, 1, … `per_voxel` peaks.
    pub fn counts(&self) -> Vec<usize> {
        let mut c = vec![0; self.per_voxel + 1];
        for v in 0..self.voxels() {
            c[self.peaks_of(v).count()] += 1;
        }
        c
    }

    /// The largest peak's length (its amplitude), 0 without any.
    pub fn largest(&self) -> f64 {
        (0..self.voxels())
            .flat_map(|v| self.peaks_of(v))
            .map(|x| glam::Vec3::from(x).as_dvec3().length())
            .fold(0.0, f64::max)
    }

    /// The world position of voxel `v`'s centre.
    pub fn position(&self, v: usize) -> [f64; 3] {
        self.frame.voxel_position(self.dims, v)
    }

    /// The smallest voxel step in world units (1 without a usable voxel-to-world matrix).
    pub fn spacing(&self) -> f64 {
        self.frame.smallest_step()
    }

    /// The lattice as a field holding no tensors: what the viewer slices and frames, the
    /// peaks staying here.
    pub fn geometry(&self) -> TensorField {
        let array = TensorArrayInfo {
            name: format!("fibre peaks (up to {} a voxel)", self.per_voxel),
            components: 3 * self.per_voxel,
            location: Location::Point,
        };
        TensorField::lattice_only(&self.format, self.dims, &self.frame, array)
    }
}
