//! A NIfTI-1 file's voxel data: checked against the bytes present, inflated no further than the
//! header's dimensions need, and read with `scl_slope` and `scl_inter` applied.

use std::borrow::Cow;

use nifti::NiftiHeader;

use super::header::{Header, MIN_OFFSET, Res, field, gunzip};
use crate::field::number::Scalar;

impl Header {
    /// The voxel data of the file whose bytes are `bytes`, checked against the bytes present
    /// (inflated no further than the header's dimensions need).
    pub(crate) fn voxels<'a>(&self, bytes: &'a [u8]) -> Res<Voxels<'a>> {
        let (h, shape) = (&self.h, &self.shape);
        let offset = (h.vox_offset.is_finite() && h.vox_offset >= 0.0)
            .then_some(h.vox_offset as u64)
            .ok_or_else(|| {
                field(
                    "vox_offset",
                    format!("{} is not a byte offset", h.vox_offset),
                )
            })?
            .max(MIN_OFFSET);
        let width = shape.width as u64;
        let data_len = (shape.voxels as u64)
            .checked_mul(shape.components as u64)
            .and_then(|n| n.checked_mul(width))
            .ok_or_else(|| field("dim", "the dimensions overflow"))?;
        let needed = offset
            .checked_add(data_len)
            .ok_or_else(|| field("vox_offset", "the data end overflows"))?;
        let data: Cow<[u8]> = if self.gz {
            Cow::Owned(gunzip(bytes, needed, "the voxel data")?)
        } else {
            Cow::Borrowed(bytes)
        };
        if (data.len() as u64) < needed {
            return Err(field(
                "dim",
                format!(
                    "the header's dimensions and vox_offset need {needed} bytes{}, the file holds {}",
                    if self.gz { " uncompressed" } else { "" },
                    data.len()
                ),
            ));
        }
        let (slope, inter) = scaling(h);
        Ok(Voxels {
            data,
            start: offset as usize,
            width: shape.width,
            voxels: shape.voxels,
            ty: shape.ty,
            big: h.endianness == nifti::Endianness::Big,
            slope,
            inter,
        })
    }
}

/// A NIfTI-1 file's voxel values: `components` volumes one after the other, x fastest.
pub(crate) struct Voxels<'a> {
    /// The file (inflated), holding the values from `start` on.
    data: Cow<'a, [u8]>,
    start: usize,
    width: usize,
    voxels: usize,
    ty: Scalar,
    big: bool,
    slope: f64,
    inter: f64,
}

impl Voxels<'_> {
    /// Value `c` of voxel `v`, scaled by `scl_slope` and `scl_inter`.
    pub(crate) fn get(&self, c: usize, v: usize) -> f64 {
        let at = self.start + (c * self.voxels + v) * self.width;
        self.ty.read(&self.data[at..at + self.width], self.big) * self.slope + self.inter
    }
}

/// `scl_slope` and `scl_inter`; a slope of 0 (or not finite) means "no scaling", per the
/// standard.
fn scaling(h: &NiftiHeader) -> (f64, f64) {
    let s = h.scl_slope as f64;
    if s != 0.0 && s.is_finite() {
        let i = h.scl_inter as f64;
        (s, if i.is_finite() { i } else { 0.0 })
    } else {
        (1.0, 0.0)
    }
}
