//! NIfTI-1 files of fibre peaks: MRtrix's `sh2peaks` output converted to NIfTI (3 values a peak
//! along the fourth axis, the direction scaled by its amplitude, NaN where a voxel has fewer;
//! `descrip` says MRtrix wrote it, and its directions are in scanner axes) and DIPY's
//! (`peaks_dirs`: unit directions in the voxel axes, zero where there is none, 3 values a peak
//! along the fourth axis as DIPY's workflows save them, or `X×Y×Z×N×3` as `peak_dirs` is held;
//! the amplitudes in `peaks_values`, `X×Y×Z×N`, beside it).
//!
//! Neither header says it holds peaks: a file of 9 volumes is three peaks or a full 3×3 tensor,
//! one of 15 five peaks or an lmax-4 SH series. `--holds peaks` says so (a 5-D `X×Y×Z×N×3`
//! file needs no word: nothing else is laid out so), and the tensor reader refuses a 4-D file of
//! 9 volumes that nothing names ([`super::nine_volumes`]).

use std::path::{Path, PathBuf};

use super::header::{Res, Values, field, read_head};
use crate::field::frame::{FrameInfo, TensorFrame, rows4, tensor_rotation};
use crate::field::inputs::{Input, Inputs};
use crate::field::options::ReadOptions;
use crate::field::peaks::PeakField;
use crate::field::sh_field;

/// What deciding whether a NIfTI file holds peaks needs of it (its header only): values per
/// voxel, and whether they are laid out as DIPY's `X×Y×Z×N×3`.
pub(crate) fn kind_probe(input: &Input) -> Res<(usize, bool)> {
    let head = read_head(input, Values::Peaks, |_| Ok(()))?;
    Ok((head.shape.components, head.shape.peak_axis))
}

/// Read the peaks of `input`: directions turned into world (RAS) axes from the frame
/// `opts.tensor_frame` names, by default scanner axes for MRtrix's files and the voxel axes for
/// the others (DIPY's).
pub(crate) fn read_peaks(input: &Input, opts: &ReadOptions) -> Res<PeakField> {
    let head = read_head(input, Values::Peaks, |n| {
        if n % 3 != 0 {
            return Err(field(
                "dim",
                format!("{n} values per voxel: peaks take 3 each"),
            ));
        }
        Ok(())
    })?;
    let shape = &head.shape;
    let per_voxel = shape.components / 3;
    let voxels = shape.voxels;
    let writer = super::sh_writer(&head.h);
    let frame = sh_field::direction_frame(writer, opts.tensor_frame);
    let (a, source) = head.affine()?;
    let linear = a.fixed_view::<3, 3>(0, 0).into_owned();
    let rotation = tensor_rotation(frame, &linear);
    if rotation.is_none() && frame != TensorFrame::World {
        return Err(field(
            source,
            "the voxel-to-world matrix is singular or not finite: no rotation to take voxel-axis \
             directions to world",
        ));
    }
    // Volume after volume as the file stores them (allocated once the data is known to hold
    // them: a header's dimensions alone allocate nothing), then gathered peak by peak.
    let raw = head.values(input, |x| x as f32)?;
    let peak_axis = shape.peak_axis;
    let volume = |p: usize, k: usize| {
        if peak_axis {
            p + per_voxel * k
        } else {
            3 * p + k
        }
    };
    let mut vectors: Vec<[f32; 3]> = (0..voxels * per_voxel)
        .map(|i| {
            let (v, p) = (i / per_voxel, i % per_voxel);
            std::array::from_fn(|k| raw[volume(p, k) * voxels + v])
        })
        .collect();
    drop(raw);
    if let Some(r) = rotation {
        for x in &mut vectors {
            let w = r * nalgebra::Vector3::from(x.map(f64::from));
            *x = [w.x as f32, w.y as f32, w.z as f32];
        }
    }
    Ok(PeakField {
        format: "nifti".into(),
        dims: shape.dims,
        per_voxel,
        vectors,
        frame: FrameInfo {
            tensor_frame: frame,
            world: "RAS".into(),
            voxel_to_world: Some(rows4(&a)),
            source: source.into(),
        },
    })
}

/// Scale `peaks`' unit directions by their amplitudes in `values` (DIPY's `peaks_values`: one
/// value a peak along the fourth axis, on the directions' lattice).
pub(crate) fn scale_by(peaks: &mut PeakField, values: &Input) -> Res<()> {
    let per_voxel = peaks.per_voxel;
    let head = read_head(values, Values::Series, |n| {
        if n != per_voxel {
            return Err(field(
                "dim",
                format!("{n} values per voxel beside {per_voxel} peaks a voxel: one a peak"),
            ));
        }
        Ok(())
    })?;
    if head.dims() != peaks.dims {
        return Err(field(
            "dim",
            format!(
                "a {:?} lattice beside the directions' {:?}",
                head.dims(),
                peaks.dims
            ),
        ));
    }
    let amplitudes = head.values(values, |x| x as f32)?;
    let voxels = peaks.voxels();
    for (i, d) in peaks.vectors.iter_mut().enumerate() {
        let a = amplitudes[(i % per_voxel) * voxels + i / per_voxel];
        *d = d.map(|c| c * a);
    }
    Ok(())
}

/// DIPY's amplitudes beside its directions: the file named as `path` with its last `dirs` made
/// `values` (`peaks_dirs.nii.gz` → `peaks_values.nii.gz`, as its workflows name them), where
/// there is one.
pub(crate) fn values_beside(inputs: &Inputs, path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?.to_str()?;
    let at = name.rfind("dirs")?;
    let values = path.with_file_name(format!("{}values{}", &name[..at], &name[at + 4..]));
    inputs.exists(&values).then_some(values)
}
