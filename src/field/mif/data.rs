//! An MRtrix image's values: found (after the header, in the inflated stream of a `.mif.gz`,
//! or in a detached data file), checked to be all there before anything is allocated for
//! them, then read in the order they are stored and each handed to its voxel and volume as
//! `layout` places it.

use std::io::Read as _;
use std::path::Path;

use super::header::{DataFile, Header, Res, field};
use crate::error::LoadErrorKind;
use crate::field::inputs::{Input, Inputs};

/// Bytes decoded at a time.
const BLOCK: usize = 1 << 16;

/// Where the values are, known to hold all of them.
pub(super) struct Values<'a> {
    input: Source<'a>,
    start: u64,
    gz: bool,
    len: u64,
}

enum Source<'a> {
    Header(&'a Input<'a>),
    Detached(Input<'a>),
}

impl<'a> Source<'a> {
    fn input(&self) -> &Input<'a> {
        match self {
            Source::Header(i) => i,
            Source::Detached(i) => i,
        }
    }
}

/// The values of the image `h` (whose header is the file `input`, at `path` among `inputs`):
/// refused unless the file holds every byte `dim` and `datatype` need from the offset `file`
/// gives. A `.mif.gz` is inflated to its end for this (within its budget, every member's
/// CRC-32 checked), so that nothing is allocated for values a short stream does not hold.
pub(super) fn locate<'a>(
    inputs: &'a Inputs,
    path: &Path,
    input: &'a Input<'a>,
    h: &Header,
) -> Res<Values<'a>> {
    let voxels = h
        .dims()
        .iter()
        .try_fold(1usize, |a, &x| a.checked_mul(x))
        .ok_or_else(|| field("dim", "the dimensions overflow"))?;
    let len = (voxels as u64)
        .checked_mul(h.per_voxel()? as u64)
        .and_then(|n| n.checked_mul(h.ty.size() as u64))
        .ok_or_else(|| field("dim", "the dimensions overflow"))?;
    let (source, start, what) = match &h.data {
        DataFile::Same(offset) => (Source::Header(input), *offset, None),
        DataFile::Detached(name, offset) => {
            let d = Inputs::detached(path, name).map_err(|e| field("file", e))?;
            let detached = inputs
                .open(&d.path)
                .map_err(|e| field("file", format!("{}: {e}", d.shown)))?;
            (Source::Detached(detached), *offset, Some(d.shown))
        }
    };
    let needed = start
        .checked_add(len)
        .ok_or_else(|| field("file", "the data's end overflows"))?;
    let short = |holds: u64| {
        field(
            "dim",
            format!(
                "dim and datatype need {len} bytes of data from byte {start}, {} holds {}{}",
                what.as_deref().unwrap_or("the file"),
                holds.saturating_sub(start),
                if h.gz { " (uncompressed)" } else { "" },
            ),
        )
    };
    let file = source.input();
    if h.gz {
        let mut g = file.gunzip(0, "the image data")?;
        g.need(needed)?;
        g.skip(u64::MAX)?;
        if g.inflated() < needed {
            return Err(short(g.inflated()));
        }
    } else if file.len() < needed {
        return Err(short(file.len()));
    }
    Ok(Values {
        input: source,
        start,
        gz: h.gz,
        len,
    })
}

impl Values<'_> {
    /// Hand every value to `put(c, v, value)`: value `c` (the index over the axes past the
    /// third, the fourth fastest) of voxel `v` (x fastest), `scaling` applied.
    pub(super) fn each(&self, h: &Header, mut put: impl FnMut(usize, usize, f64)) -> Res<()> {
        let width = h.ty.size();
        let (offset, scale) = h.scaling;
        let mut at = Odometer::new(h);
        let mut buf = vec![0u8; BLOCK - BLOCK % width];
        let mut take = |bytes: &[u8]| {
            for b in bytes.chunks_exact(width) {
                let (c, v) = at.here();
                put(c, v, offset + scale * h.ty.read(b, h.big));
                at.step();
            }
        };
        let input = self.input.input();
        let mut left = self.len;
        if self.gz {
            // Known to be all there ([`locate`] inflated it once).
            let mut g = input.gunzip(0, "the image data")?;
            g.skip(self.start)?;
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                let got = g.fill(&mut buf[..want])?;
                if got < want {
                    return Err(LoadErrorKind::Malformed(
                        "the gzip stream changed while it was read".into(),
                    ));
                }
                take(&buf[..want]);
                left -= want as u64;
            }
        } else {
            let mut r = input.reader_at(self.start)?;
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                r.read_exact(&mut buf[..want]).map_err(LoadErrorKind::Io)?;
                take(&buf[..want]);
                left -= want as u64;
            }
        }
        Ok(())
    }
}

/// The place of the next stored value: the axes counted in the order of storage (`layout`'s
/// ranks), each forwards or backwards, and the voxel and volume indices that place gives.
struct Odometer {
    /// Per axis in the order of storage: its size, and how one step along it moves the voxel
    /// index (spatial axes) or the volume index (the others), signed.
    axes: Vec<(usize, bool, i64)>,
    /// Steps taken along each axis, in the order of storage.
    count: Vec<usize>,
    v: i64,
    c: i64,
}

impl Odometer {
    fn new(h: &Header) -> Self {
        let mut weight = vec![0i64; h.axes.len()];
        let (mut wv, mut wc) = (1i64, 1i64);
        for (i, a) in h.axes.iter().enumerate() {
            let w = if i < 3 { &mut wv } else { &mut wc };
            weight[i] = *w;
            // Products of sizes the data was checked to hold: no overflow.
            *w = w.saturating_mul(a.size as i64);
        }
        let mut order: Vec<usize> = (0..h.axes.len()).collect();
        order.sort_by_key(|&i| h.axes[i].rank);
        let (mut v, mut c) = (0i64, 0i64);
        let axes = order
            .iter()
            .map(|&i| {
                let a = h.axes[i];
                // A reversed axis starts at its last index and steps back.
                let first = if a.reversed {
                    (a.size as i64 - 1) * weight[i]
                } else {
                    0
                };
                if i < 3 {
                    v += first;
                } else {
                    c += first;
                }
                let step = if a.reversed { -weight[i] } else { weight[i] };
                (a.size, i < 3, step)
            })
            .collect();
        Self {
            count: vec![0; order.len()],
            axes,
            v,
            c,
        }
    }

    fn here(&self) -> (usize, usize) {
        (self.c as usize, self.v as usize)
    }

    fn step(&mut self) {
        for (k, &(size, spatial, step)) in self.axes.iter().enumerate() {
            let idx = if spatial { &mut self.v } else { &mut self.c };
            self.count[k] += 1;
            if self.count[k] < size {
                *idx += step;
                return;
            }
            self.count[k] = 0;
            *idx -= step * (size as i64 - 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::header::parse;
    use super::*;

    /// The (volume, voxel) of each stored value of a header's image, in storage order.
    fn places(lines: &str) -> Vec<(usize, usize)> {
        let text = format!("mrtrix image\n{lines}datatype: UInt8\nfile: . 200\nEND\n");
        let h = parse(text.as_bytes(), false).unwrap();
        let n = h.dims().iter().product::<usize>() * h.per_voxel().unwrap();
        let mut o = Odometer::new(&h);
        (0..n)
            .map(|_| {
                let p = o.here();
                o.step();
                p
            })
            .collect()
    }

    #[test]
    fn layout_places_values_as_mrtrix_documents() {
        // dim 3,2 stored x fastest: voxels in order.
        assert_eq!(
            places("dim: 3,2\nvox: 1,1\nlayout: +0,+1\n"),
            [(0, 0), (0, 1), (0, 2), (0, 3), (0, 4), (0, 5)]
        );
        // x reversed: each row from its last voxel.
        assert_eq!(
            places("dim: 3,2\nvox: 1,1\nlayout: -0,+1\n"),
            [(0, 2), (0, 1), (0, 0), (0, 5), (0, 4), (0, 3)]
        );
        // y fastest and reversed, then x: MRtrix's documented `+1,-0` reading.
        assert_eq!(
            places("dim: 3,2\nvox: 1,1\nlayout: +1,-0\n"),
            [(0, 3), (0, 0), (0, 4), (0, 1), (0, 5), (0, 2)]
        );
        // Volumes contiguous (MRtrix's 2,3,4,1): a voxel's values together.
        assert_eq!(
            places("dim: 2,1,1,3\nvox: 1,1,1,nan\nlayout: +1,+2,+3,+0\n"),
            [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]
        );
        // Volumes reversed and slowest.
        assert_eq!(
            places("dim: 2,1,1,2\nvox: 1,1,1,nan\nlayout: +0,+1,+2,-3\n"),
            [(1, 0), (1, 1), (0, 0), (0, 1)]
        );
    }
}
