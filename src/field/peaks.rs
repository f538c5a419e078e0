//! Fibre directions per voxel (peaks): [`PeakField`], read from the images MRtrix's `sh2peaks`
//! writes (3 values a peak along the fourth axis: the direction scaled by the ODF's amplitude,
//! NaN where a voxel has fewer peaks), whose header says what it is (`command_history` ends
//! with `sh2peaks`, [`super::FieldKind::of_file`]; the directions in scanner axes, world RAS),
//! and from NIfTI files of peaks: `sh2peaks` output converted, and DIPY's `peaks_dirs` (unit
//! directions in the voxel axes) with the amplitudes of the `peaks_values` file beside it
//! ([`super::nifti::peaks`]; `--holds peaks` says what such a file holds).

use std::path::Path;

use super::frame::{FrameInfo, TensorFrame};
use super::{Inputs, ReadOptions, guard, mif, nifti};
use crate::error::{LoadError, LoadErrorKind};

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
        let d = self.dims;
        let ijk = [v % d[0], v / d[0] % d[1], v / d[0] / d[1]].map(|x| x as f64);
        let m = self.frame.voxel_to_world.unwrap_or_default();
        std::array::from_fn(|r| m[r][0] * ijk[0] + m[r][1] * ijk[1] + m[r][2] * ijk[2] + m[r][3])
    }
}

/// Read the peaks file `path` among `inputs`: an MRtrix image whose header says `sh2peaks` wrote
/// it, or a NIfTI file of peaks (DIPY's `…dirs…` file takes its amplitudes from the `…values…`
/// file of the same name beside it, where there is one).
pub fn read_peak_field_from(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<PeakField, LoadError> {
    if nifti::is_nifti_path(path) {
        let mut field =
            guard::guarded(path, || nifti::peaks::read_peaks(&inputs.open(path)?, opts))?;
        if let Some(values) = values_beside(inputs, path) {
            guard::guarded(&values, || {
                nifti::peaks::scale_by(&mut field, &inputs.open(&values)?)
            })?;
        }
        return Ok(field);
    }
    guard::guarded(path, || {
        if !mif::is_mif_path(path) {
            return Err(LoadErrorKind::Other(
                "peaks are read from MRtrix images that sh2peaks wrote (.mif, .mif.gz, .mih) \
                 and from NIfTI files (.nii, .nii.gz)"
                    .into(),
            ));
        }
        if let Some(f) = opts.tensor_frame.filter(|f| *f != TensorFrame::World) {
            return Err(LoadErrorKind::Other(format!(
                "--tensor-frame {f}: sh2peaks writes its directions in scanner axes (world)"
            )));
        }
        let v = mif::read_volumes(inputs, path)?;
        if v.volumes % 3 != 0 || v.volumes == 0 {
            return Err(LoadErrorKind::Field {
                field: "dim".into(),
                message: format!(
                    "{} values per voxel: peaks take 3 each (sh2peaks writes 3 per peak)",
                    v.volumes
                ),
            });
        }
        let vectors = v
            .values
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Ok(PeakField {
            format: "mif".into(),
            dims: v.dims,
            per_voxel: v.volumes / 3,
            vectors,
            frame: FrameInfo {
                tensor_frame: TensorFrame::World,
                world: "RAS".into(),
                voxel_to_world: Some(v.voxel_to_world),
                source: v.source.into(),
            },
        })
    })
}

/// DIPY's amplitudes beside its directions: the file named as `path` with its last `dirs` made
/// `values` (`peaks_dirs.nii.gz` → `peaks_values.nii.gz`, as its workflows name them), where
/// there is one.
fn values_beside(inputs: &Inputs, path: &Path) -> Option<std::path::PathBuf> {
    let name = path.file_name()?.to_str()?;
    let at = name.rfind("dirs")?;
    let values = path.with_file_name(format!("{}values{}", &name[..at], &name[at + 4..]));
    inputs.exists(&values).then_some(values)
}
