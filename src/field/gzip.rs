//! Gzip data inflated within a budget and checked to its end.
//!
//! A gzip stream is inflated as the reader takes its bytes, never held whole, and:
//! - no further than a budget fixed before anything is inflated: [`INFLATE_RATIO`] times the
//!   compressed bytes, and at least [`INFLATE_FLOOR`] (deflate itself cannot pass about 1032
//!   times). A header asking for more is refused at once; so is a stream that goes on inflating
//!   past the budget after the data the header asked for;
//! - to the end of its last member ([`Gunzip::finish`]), so that flate2 checks every member's
//!   CRC-32 and size, and bytes after the last member that are not another member are refused.
//!
//! flate2 does the inflating and the checks; this module only counts and bounds.

use std::io::{BufReader, Read};

use flate2::bufread::MultiGzDecoder;

use crate::error::LoadErrorKind;

/// Deflate cannot expand data more than about 1032 times.
const DEFLATE_MAX_RATIO: u64 = 1032;

/// Gzip data may inflate to this many times its compressed size …
pub const INFLATE_RATIO: u64 = 64;

/// … and always to this many bytes (64 MiB): small, very compressible files (masks) stay
/// readable, and no file inflates beyond what it could fill at this ratio or this size.
pub const INFLATE_FLOOR: u64 = 64 << 20;

/// Whether `b` starts like gzip data.
pub fn is_gzip(b: &[u8]) -> bool {
    b.starts_with(&[0x1f, 0x8b])
}

/// The inflated bytes of gzip data, read on demand within the budget.
pub struct Gunzip<'a> {
    dec: MultiGzDecoder<BufReader<Box<dyn Read + 'a>>>,
    /// Bytes inflated so far.
    out: u64,
    compressed: u64,
    limit: u64,
    what: String,
}

impl<'a> Gunzip<'a> {
    /// The gzip data `compressed` bytes long that `src` reads; `what` names it in errors.
    pub fn new(src: Box<dyn Read + 'a>, compressed: u64, what: impl Into<String>) -> Self {
        let limit = compressed
            .saturating_mul(INFLATE_RATIO)
            .max(INFLATE_FLOOR)
            .min(compressed.saturating_mul(DEFLATE_MAX_RATIO));
        Self {
            dec: MultiGzDecoder::new(BufReader::with_capacity(1 << 16, src)),
            out: 0,
            compressed,
            limit,
            what: what.into(),
        }
    }

    /// Refuse, before inflating, a `total` of inflated bytes the budget does not allow.
    pub fn need(&self, total: u64) -> Result<(), LoadErrorKind> {
        if total <= self.limit {
            return Ok(());
        }
        let n = self.compressed;
        Err(LoadErrorKind::Malformed(
            if total > n.saturating_mul(DEFLATE_MAX_RATIO) {
                format!(
                    "{} needs {total} bytes, more than {n} gzip-compressed bytes can hold",
                    self.what
                )
            } else {
                format!(
                    "{} needs {total} bytes, more than the {INFLATE_RATIO}× budget of its {n} \
                     gzip-compressed bytes (at least 64 MiB) allows; gunzip the file to read it",
                    self.what
                )
            },
        ))
    }

    fn corrupt(&self, e: std::io::Error) -> LoadErrorKind {
        LoadErrorKind::Malformed(format!(
            "{}: gzip data is corrupt or truncated ({e})",
            self.what
        ))
    }

    /// Fill `buf` as far as the data goes: the bytes read (fewer than `buf.len()` only at the
    /// end of the data).
    pub fn fill(&mut self, buf: &mut [u8]) -> Result<usize, LoadErrorKind> {
        let mut got = 0;
        while got < buf.len() {
            match self.dec.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.corrupt(e)),
            }
        }
        self.out += got as u64;
        if self.out > self.limit {
            return Err(self.over());
        }
        Ok(got)
    }

    fn over(&self) -> LoadErrorKind {
        LoadErrorKind::Malformed(format!(
            "{}: the gzip data inflates to more than {} bytes, the budget of its {} compressed \
             bytes; gunzip the file to read it",
            self.what, self.limit, self.compressed
        ))
    }

    /// Skip `n` inflated bytes: how many there were (fewer only at the end of the data).
    pub fn skip(&mut self, mut n: u64) -> Result<u64, LoadErrorKind> {
        let mut buf = vec![0u8; 1 << 16];
        let mut skipped = 0;
        while n > 0 {
            let want = n.min(buf.len() as u64) as usize;
            let got = self.fill(&mut buf[..want])?;
            skipped += got as u64;
            n -= got as u64;
            if got < want {
                break;
            }
        }
        Ok(skipped)
    }

    /// Bytes inflated so far.
    pub fn inflated(&self) -> u64 {
        self.out
    }

    /// Inflate what is left, within the budget, so that every member's CRC-32 and size are
    /// checked and anything after the last member is refused.
    pub fn finish(mut self) -> Result<(), LoadErrorKind> {
        self.skip(u64::MAX)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write as _;

    use super::*;

    fn gz(data: &[u8]) -> Vec<u8> {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    fn of(b: &[u8]) -> Gunzip<'_> {
        Gunzip::new(Box::new(b), b.len() as u64, "the data")
    }

    fn read_all(b: &[u8]) -> Result<Vec<u8>, LoadErrorKind> {
        let mut g = of(b);
        let mut out = vec![0u8; 1 << 20];
        let n = g.fill(&mut out)?;
        out.truncate(n);
        g.finish()?;
        Ok(out)
    }

    #[test]
    fn members_are_read_in_turn_and_checked_to_their_end() {
        let data: Vec<u8> = (0..5000u32).flat_map(|x| x.to_le_bytes()).collect();
        let two = [gz(&data[..7000]), gz(&data[7000..])].concat();
        assert_eq!(read_all(&two).unwrap(), data);
        // One byte of the CRC-32, then one of the size, changed: refused.
        for back in [8, 3] {
            let mut bad = gz(&data);
            let at = bad.len() - back;
            bad[at] ^= 0x10;
            let e = read_all(&bad).unwrap_err().to_string();
            assert!(e.contains("gzip data is corrupt or truncated"), "{e}");
        }
        // Bytes after the last member that are not a member.
        let e = read_all(&[gz(&data), b"garbage".to_vec()].concat())
            .unwrap_err()
            .to_string();
        assert!(e.contains("gzip data is corrupt or truncated"), "{e}");
        // Cut before the trailer.
        let whole = gz(&data);
        assert!(read_all(&whole[..whole.len() - 4]).is_err());
    }

    #[test]
    fn the_budget_is_checked_before_and_while_inflating() {
        let zeros = gz(&vec![0u8; 8 << 20]);
        let g = of(&zeros);
        // Eight MiB of zeros compress about 1000 times: within the 64 MiB floor.
        assert!(g.need(8 << 20).is_ok());
        let e = g.need(u64::MAX).unwrap_err().to_string();
        assert!(e.contains("more than"), "{e}");
        // The same stream said to be 1000 bytes long allows 1000 × 1032 at most.
        let g = Gunzip::new(Box::new(&zeros[..]), 1000, "the data");
        assert!(g.need(2_000_000).is_err());
        let mut g = Gunzip::new(Box::new(&zeros[..]), 1000, "the data");
        let e = g.skip(u64::MAX).unwrap_err().to_string();
        assert!(e.contains("inflates to more than 1032000 bytes"), "{e}");
    }
}
