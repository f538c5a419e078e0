//! A NIfTI-1 file's voxel data: only the bytes the header's dimensions need are read (from
//! `vox_offset` on), gzip data is inflated within its budget and checked to its end, and each
//! value goes, scaled by `scl_slope` and `scl_inter`, straight to where the caller keeps it.

use nifti::NiftiHeader;

use super::header::{Header, MIN_OFFSET, Res, field};
use crate::field::inputs::Input;
use crate::field::number::Scalar;

/// Bytes decoded at a time.
const BLOCK: usize = 1 << 16;

impl Header {
    /// Hand every value of the file `input` to `put(c, v, value)`: value `c` of voxel `v`,
    /// scaled, volume after volume (all voxels of value 0 first), x fastest.
    ///
    /// The data must hold what the header's dimensions and `vox_offset` say, checked before
    /// anything is allocated; no more of the file is read (a gzip stream is inflated to its
    /// end, within its budget, to check it).
    pub(crate) fn each_value(&self, input: &Input, put: impl FnMut(usize, usize, f64)) -> Res<()> {
        self.each_value_sized(input, |_| {}, put)
    }

    /// Every value of the file `input`, in [`Self::each_value`]'s order, as `convert` makes it:
    /// the vector sized once the data is known to hold them (a vector grown value by value would
    /// double its allocation, and hold both, near its end).
    pub(crate) fn values<T>(&self, input: &Input, convert: impl Fn(f64) -> T) -> Res<Vec<T>> {
        let (mut out, count) = (Vec::new(), std::cell::Cell::new(0));
        self.each_value_sized(
            input,
            |n| count.set(n),
            |_, _, x| {
                if out.capacity() == 0 {
                    out.reserve_exact(count.get());
                }
                out.push(convert(x))
            },
        )?;
        Ok(out)
    }

    /// [`Self::each_value`], telling `sized` how many values will come once the data is
    /// known to hold them (before the first).
    fn each_value_sized(
        &self,
        input: &Input,
        sized: impl FnOnce(usize),
        mut put: impl FnMut(usize, usize, f64),
    ) -> Res<()> {
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
        let short = |holds: u64| {
            field(
                "dim",
                format!(
                    "the header's dimensions and vox_offset need {needed} bytes{}, the file holds {holds}",
                    if self.gz { " uncompressed" } else { "" },
                ),
            )
        };
        let (slope, inter) = scaling(h);
        let big = h.endianness == nifti::Endianness::Big;
        let mut sink = Sink {
            ty: shape.ty,
            big,
            slope,
            inter,
            voxels: shape.voxels,
            at: 0,
        };
        let mut buf = vec![0u8; BLOCK - BLOCK % shape.width];
        let mut left = data_len;
        if self.gz {
            let mut g = input.gunzip(0, "the voxel data")?;
            g.need(needed)?;
            if g.skip(offset)? < offset {
                return Err(short(g.inflated()));
            }
            sized(shape.voxels * shape.components);
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                let got = g.fill(&mut buf[..want])?;
                if got < want {
                    return Err(short(g.inflated()));
                }
                sink.take(&buf[..got], &mut put);
                left -= got as u64;
            }
            g.finish()
        } else {
            if input.len() < needed {
                return Err(short(input.len()));
            }
            sized(shape.voxels * shape.components);
            let mut r = input.reader_at(offset)?;
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                r.read_exact(&mut buf[..want])
                    .map_err(crate::error::LoadErrorKind::Io)?;
                sink.take(&buf[..want], &mut put);
                left -= want as u64;
            }
            Ok(())
        }
    }
}

use std::io::Read as _;

/// Where the next value goes.
struct Sink {
    ty: Scalar,
    big: bool,
    slope: f64,
    inter: f64,
    voxels: usize,
    /// Values handed over so far.
    at: usize,
}

impl Sink {
    /// The values in `bytes` (whole elements), handed to `put`.
    fn take(&mut self, bytes: &[u8], put: &mut impl FnMut(usize, usize, f64)) {
        for b in bytes.chunks_exact(self.ty.size()) {
            let (c, v) = (self.at / self.voxels, self.at % self.voxels);
            put(c, v, self.ty.read(b, self.big) * self.slope + self.inter);
            self.at += 1;
        }
    }
}

/// `scl_slope` and `scl_inter`; a slope of 0 (or not finite) means "no scaling", per the
/// standard.
pub(super) fn scaling(h: &NiftiHeader) -> (f64, f64) {
    let s = h.scl_slope as f64;
    if s != 0.0 && s.is_finite() {
        let i = h.scl_inter as f64;
        (s, if i.is_finite() { i } else { 0.0 })
    } else {
        (1.0, 0.0)
    }
}
