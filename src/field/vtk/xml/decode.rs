//! Decoding one DataArray: ascii, inline or appended base64, appended raw; uncompressed or
//! compressed blocks; into f64 values.

use std::io::Read;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as B64;

use super::tokenize::{Doc, Tag};
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::vtk::binary::{Scalar, decode_into, parse_ascii, try_vec};
use crate::field::vtk::malformed::{Res, malformed};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Compressor {
    None,
    Zlib,
    Lz4,
    Lzma,
}

/// File-wide decoding settings.
pub(super) struct Ctx<'a> {
    pub b: &'a [u8],
    pub header: usize,
    pub big_endian: bool,
    pub compressor: Compressor,
    pub appended: Option<(usize, bool)>,
}

/// The file-wide decoding settings the `<VTKFile>` root element states, and the dataset type
/// it names.
pub(super) fn header_ctx<'a>(b: &'a [u8], doc: &Doc) -> Res<(Ctx<'a>, String)> {
    let root = doc
        .tags
        .first()
        .filter(|t| t.name == "VTKFile")
        .ok_or_else(|| LoadErrorKind::NotVtk("XML without a <VTKFile> root element".into()))?;
    let header = match root.get("header_type").unwrap_or("UInt32") {
        "UInt32" => 4,
        "UInt64" => 8,
        other => return Err(malformed(format!("header_type '{}'", esc(other)))),
    };
    let big_endian = match root.get("byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => false,
        "BigEndian" => true,
        other => return Err(malformed(format!("byte_order '{}'", esc(other)))),
    };
    let compressor = match root.get("compressor").unwrap_or("") {
        "" => Compressor::None,
        "vtkZLibDataCompressor" => Compressor::Zlib,
        "vtkLZ4DataCompressor" => Compressor::Lz4,
        "vtkLZMADataCompressor" => Compressor::Lzma,
        other => {
            return Err(LoadErrorKind::UnsupportedDataset(format!(
                "compressor '{}'",
                esc(other)
            )));
        }
    };
    let ty = root
        .get("type")
        .ok_or_else(|| malformed("<VTKFile> without a type"))?
        .to_string();
    Ok((
        Ctx {
            b,
            header,
            big_endian,
            compressor,
            appended: doc.appended,
        },
        ty,
    ))
}

/// How many values (or bytes) an array must hold: `min..=max`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Need {
    pub min: usize,
    pub max: usize,
}

impl Need {
    pub fn exactly(n: usize) -> Need {
        Need { min: n, max: n }
    }

    fn bytes(self, size: usize) -> Option<Need> {
        Some(Need {
            min: self.min.checked_mul(size)?,
            max: self.max.checked_mul(size)?,
        })
    }
}

impl std::fmt::Display for Need {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.min == self.max {
            write!(f, "{}", self.min)
        } else {
            write!(f, "{} to {}", self.min, self.max)
        }
    }
}

/// Where encoded bytes come from.
#[derive(Clone, Copy)]
pub(super) enum Src<'a> {
    Raw(&'a [u8]),
    /// Base64 text with the header and the payload encoded as separate chunks (VTK does this
    /// for compressed data).
    B64(&'a [u8]),
    /// Base64 text with header and payload encoded as one stream (VTK does this for
    /// uncompressed data).
    Joint(&'a [u8]),
}

fn b64_len(nbytes: usize) -> usize {
    nbytes.div_ceil(3).saturating_mul(4)
}

fn b64_decode(chars: &[u8], what: &str) -> Res<Vec<u8>> {
    B64.decode(chars)
        .map_err(|e| malformed(format!("{what}: bad base64 data ({e})")))
}

impl Ctx<'_> {
    fn uint(&self, b: &[u8]) -> u64 {
        let mut v = 0u64;
        for k in 0..self.header {
            let byte = if self.big_endian {
                b[k]
            } else {
                b[self.header - 1 - k]
            };
            v = (v << 8) | byte as u64;
        }
        v
    }

    fn to_usize(&self, v: u64, what: &str) -> Res<usize> {
        usize::try_from(v).map_err(|_| malformed(format!("{what}: size {v} too large")))
    }

    /// The decoded (uncompressed) bytes of a binary or appended array, which must hold `need`
    /// bytes. A header claiming another size is refused before anything is inflated or
    /// allocated for it, and no block inflates past its own claim: memory is bounded by what
    /// the data holds and the geometry needs, whichever is less (a geometry that lies about
    /// its size costs nothing either).
    fn bytes(&self, src: Src<'_>, what: &str, need: Need) -> Res<Vec<u8>> {
        let hs = self.header;
        let wrong_size = |claim: &dyn std::fmt::Display, more: bool| {
            malformed(format!(
                "{what}: the data {} {claim} bytes but the array needs {need}",
                if more { "claims" } else { "holds" }
            ))
        };
        let check = |claim: u64| -> Res<()> {
            if claim > need.max as u64 {
                Err(wrong_size(&claim, true))
            } else if claim < need.min as u64 {
                Err(wrong_size(&claim, false))
            } else {
                Ok(())
            }
        };
        // Header and payload, each either raw bytes or a separately encoded base64 chunk.
        let take = |src: &Src<'_>, pos: usize, n: usize, label: &str| -> Res<(Vec<u8>, usize)> {
            match src {
                Src::Raw(b) => {
                    let end = pos
                        .checked_add(n)
                        .filter(|&e| e <= b.len())
                        .ok_or_else(|| {
                            malformed(format!(
                                "{what}: {label} of {n} bytes runs past the end of the file (truncated?)"
                            ))
                        })?;
                    Ok((b[pos..end].to_vec(), end))
                }
                Src::B64(c) => {
                    let len = b64_len(n);
                    let end = pos.checked_add(len).filter(|&e| e <= c.len()).ok_or_else(|| {
                        malformed(format!(
                            "{what}: {label} of {n} bytes runs past the end of the data (truncated?)"
                        ))
                    })?;
                    let mut d = b64_decode(&c[pos..end], what)?;
                    if d.len() < n {
                        return Err(malformed(format!("{what}: short {label}")));
                    }
                    d.truncate(n);
                    Ok((d, end))
                }
                Src::Joint(c) => {
                    let end = pos
                        .checked_add(n)
                        .ok_or_else(|| malformed(format!("{what}: size overflow")))?;
                    let len = b64_len(end);
                    if len > c.len() {
                        return Err(malformed(format!(
                            "{what}: {label} of {n} bytes runs past the end of the data (truncated?)"
                        )));
                    }
                    let d = b64_decode(&c[..len], what)?;
                    if d.len() < end {
                        return Err(malformed(format!("{what}: short {label}")));
                    }
                    Ok((d[pos..end].to_vec(), end))
                }
            }
        };
        if self.compressor == Compressor::None {
            let (h, pos) = take(&src, 0, hs, "header")?;
            let n = self.uint(&h);
            check(n)?;
            let (d, _) = take(&src, pos, n as usize, "data")?;
            return Ok(d);
        }
        let (h3, _) = take(&src, 0, 3 * hs, "compression header")?;
        let (nb64, bs64, lbs64) = (
            self.uint(&h3[..hs]),
            self.uint(&h3[hs..2 * hs]),
            self.uint(&h3[2 * hs..]),
        );
        // Blocks of `bs` bytes, the last one `lbs` (0: a full block).
        let claimed = match nb64 {
            0 => Some(0),
            n => (n - 1)
                .checked_mul(bs64)
                .and_then(|v| v.checked_add(if lbs64 == 0 { bs64 } else { lbs64 })),
        };
        match claimed {
            Some(c) => check(c)?,
            None => return Err(wrong_size(&format!("{nb64} × {bs64}"), true)),
        }
        let nb = self.to_usize(nb64, what)?;
        let bs = self.to_usize(bs64, what)?;
        let lbs = self.to_usize(lbs64, what)?;
        let hlen = nb
            .checked_add(3)
            .and_then(|v| v.checked_mul(hs))
            .ok_or_else(|| malformed(format!("{what}: block count {nb} overflows")))?;
        let avail = match &src {
            Src::Raw(b) => b.len(),
            Src::B64(c) | Src::Joint(c) => c.len() / 4 * 3,
        };
        if hlen > avail {
            return Err(malformed(format!(
                "{what}: {nb} compressed blocks declared but the data is only {avail} bytes (truncated?)"
            )));
        }
        let (h, pos) = take(&src, 0, hlen, "compression header")?;
        let mut csizes = try_vec::<usize>(nb)?;
        for k in 0..nb {
            let at = (3 + k) * hs;
            csizes.push(self.to_usize(self.uint(&h[at..at + hs]), what)?);
        }
        let ctotal = csizes
            .iter()
            .try_fold(0usize, |a, &c| a.checked_add(c))
            .ok_or_else(|| malformed(format!("{what}: compressed sizes overflow")))?;
        let (comp, _) = take(&src, pos, ctotal, "compressed data")?;
        let mut out = Vec::new();
        let mut at = 0;
        for (k, &cs) in csizes.iter().enumerate() {
            let usize_k = if k + 1 == nb && lbs != 0 { lbs } else { bs };
            // A real block cannot expand more than ~1000x (zlib's limit is 1032).
            if usize_k > cs.saturating_mul(1100).saturating_add(1 << 16) {
                return Err(malformed(format!(
                    "{what}: block {k} claims {usize_k} bytes from {cs} compressed bytes"
                )));
            }
            let block = &comp[at..at + cs];
            at += cs;
            let before = out.len();
            out.try_reserve(usize_k)
                .map_err(|_| malformed(format!("{what}: cannot allocate {usize_k} bytes")))?;
            let res = match self.compressor {
                Compressor::Zlib => flate2::read::ZlibDecoder::new(block)
                    .take(usize_k as u64 + 1)
                    .read_to_end(&mut out)
                    .map(|_| ())
                    .map_err(|e| e.to_string()),
                Compressor::Lzma => unxz(block, usize_k as u64 + 1, &mut out),
                Compressor::Lz4 => {
                    out.resize(before + usize_k, 0);
                    lz4_flex::block::decompress_into(block, &mut out[before..])
                        .map(|n| out.truncate(before + n))
                        .map_err(|e| e.to_string())
                }
                Compressor::None => unreachable!("handled above"),
            };
            res.map_err(|e| malformed(format!("{what}: block {k} does not decompress ({e})")))?;
            if out.len() - before != usize_k {
                return Err(malformed(format!(
                    "{what}: block {k} decompresses to {} bytes, expected {usize_k}",
                    out.len() - before
                )));
            }
        }
        Ok(out)
    }

    /// Decode a DataArray into f64 values; the dataset needs `need` of them. Binary data of
    /// another size is refused before it is decoded (see [`Ctx::bytes`]); ascii data (bounded
    /// by its text) of another length is returned for the caller to report with the counts it
    /// knows.
    pub fn values(&self, a: &Tag, what: &str, need: Need) -> Res<Vec<f64>> {
        let ty_name = a.get("type").unwrap_or("");
        let ty = Scalar::from_xml(ty_name).ok_or_else(|| {
            LoadErrorKind::UnsupportedDataset(format!("{what}: data type '{}'", esc(ty_name)))
        })?;
        let need = need
            .bytes(ty.size())
            .ok_or_else(|| malformed(format!("{what}: {need} values overflow")))?;
        let format = a.get("format").unwrap_or("ascii");
        let bytes = match format {
            "ascii" => {
                let text = &self.b[a.text.0..a.text.1];
                let n = text
                    .split(|c| c.is_ascii_whitespace())
                    .filter(|t| !t.is_empty())
                    .count();
                return parse_ascii(text, n, ty, what);
            }
            "binary" => {
                let text: Vec<u8> = self.b[a.text.0..a.text.1]
                    .iter()
                    .copied()
                    .filter(|c| !c.is_ascii_whitespace())
                    .collect();
                self.b64_bytes(&text, what, need)?
            }
            "appended" => {
                let (start, raw) = self.appended.ok_or_else(|| {
                    malformed(format!("{what}: appended array but no AppendedData"))
                })?;
                let off: usize = a
                    .get("offset")
                    .and_then(|o| o.trim().parse().ok())
                    .ok_or_else(|| malformed(format!("{what}: missing or bad offset")))?;
                let from = start
                    .checked_add(off)
                    .filter(|&f| f <= self.b.len())
                    .ok_or_else(|| {
                        malformed(format!("{what}: offset {off} is past the end of the file"))
                    })?;
                let data = &self.b[from..];
                if raw {
                    self.bytes(Src::Raw(data), what, need)?
                } else {
                    let end = data
                        .iter()
                        .position(|&c| {
                            !(c.is_ascii_alphanumeric() || c == b'+' || c == b'/' || c == b'=')
                        })
                        .unwrap_or(data.len());
                    self.b64_bytes(&data[..end], what, need)?
                }
            }
            other => {
                return Err(LoadErrorKind::UnsupportedDataset(format!(
                    "{what}: data format '{}'",
                    esc(other)
                )));
            }
        };
        if bytes.len() % ty.size() != 0 {
            return Err(malformed(format!(
                "{what}: {} bytes is not a whole number of {ty_name} values",
                bytes.len()
            )));
        }
        let mut out = try_vec(bytes.len() / ty.size())?;
        decode_into(&bytes, ty, self.big_endian, &mut out);
        Ok(out)
    }

    /// Decode base64 data, telling separately encoded header chunks (padded, as VTK writes
    /// compressed data) from one joint stream (as VTK writes uncompressed data).
    fn b64_bytes(&self, text: &[u8], what: &str, need: Need) -> Res<Vec<u8>> {
        let hs = self.header;
        let padded_at = |nbytes: usize| text.get(b64_len(nbytes).wrapping_sub(1)) == Some(&b'=');
        match self.compressor {
            Compressor::None => {
                if padded_at(hs) {
                    self.bytes(Src::B64(text), what, need)
                } else {
                    self.bytes(Src::Joint(text), what, need)
                }
            }
            _ => {
                // The first 3 header values (a multiple of 3 bytes) decode alike either way.
                let first = b64_decode(text.get(..4 * hs).unwrap_or(text), what)?;
                if first.len() < 3 * hs {
                    return Err(malformed(format!("{what}: truncated compression header")));
                }
                let nb = self.uint(&first[..hs]);
                let hlen = nb.saturating_add(3).saturating_mul(hs as u64);
                if !hlen.is_multiple_of(3) {
                    let hlen = usize::try_from(hlen).unwrap_or(usize::MAX);
                    if padded_at(hlen) {
                        self.bytes(Src::B64(text), what, need)
                    } else {
                        self.bytes(Src::Joint(text), what, need)
                    }
                } else {
                    self.bytes(Src::B64(text), what, need)
                        .or_else(|e| self.bytes(Src::Joint(text), what, need).map_err(|_| e))
                }
            }
        }
    }
}

/// Append at most `limit` bytes of the xz stream `block` (VTK's vtkLZMADataCompressor writes
/// one per block with liblzma) to `out`, with lzma-rs on every target.
///
/// One pure-Rust decoder instead of liblzma (xz2) on the desktop and lzma-rs in the browser: the
/// C library cannot go into the web build, and in the Python wheel it would be a second shared
/// library whose symbol versions (GLIBC_2.32/2.34 on a current Debian) shut the wheel out of
/// manylinux_2_28 and the clusters that run RHEL 8. The tests below check lzma-rs against
/// liblzma's own encoder and decoder on streams as VTK writes them; liblzma stays a test-only
/// dependency for that.
///
/// lzma-rs grows its dictionary with the output, and the output stops at `limit` bytes (what is
/// past it is not decoded), so memory stays bounded by what the block declares.
fn unxz(block: &[u8], limit: u64, out: &mut Vec<u8>) -> Result<(), String> {
    struct Bounded<'a> {
        out: &'a mut Vec<u8>,
        left: u64,
    }
    impl std::io::Write for Bounded<'_> {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            let n = buf
                .len()
                .min(usize::try_from(self.left).unwrap_or(usize::MAX));
            if n == 0 && !buf.is_empty() {
                return Err(std::io::Error::other(FULL));
            }
            self.out.extend_from_slice(&buf[..n]);
            self.left -= n as u64;
            Ok(n)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    const FULL: &str = "the block holds more than it declares";
    let mut w = Bounded { out, left: limit };
    match lzma_rs::xz_decompress(&mut std::io::BufReader::new(block), &mut w) {
        Ok(()) => Ok(()),
        // Cut at the limit: the caller's length check says what is wrong.
        Err(_) if w.left == 0 => Ok(()),
        Err(e) => Err(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write as _;

    /// What liblzma's own decoder gives back, cut at `limit` as `unxz` cuts: the truth.
    fn liblzma(xz: &[u8], limit: u64) -> Vec<u8> {
        let mut out = Vec::new();
        xz2::read::XzDecoder::new(xz)
            .take(limit)
            .read_to_end(&mut out)
            .unwrap();
        out
    }

    /// Streams as VTK writes them (liblzma's easy encoder, CRC64), of data with and without
    /// repeats: lzma-rs gives back exactly what liblzma was given, as liblzma's own decoder
    /// does, stops at the limit where it does, and refuses a truncated stream.
    #[test]
    fn the_pure_rust_decoder_agrees_with_liblzma() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let noise: Vec<u8> = (0..70_000)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 24) as u8
            })
            .collect();
        let doubles: Vec<u8> = (0..20_000)
            .flat_map(|i| (f64::from(i) * 0.25).sin().to_le_bytes())
            .collect();
        for data in [Vec::new(), b"tensor".repeat(5000), noise, doubles] {
            for level in [0, 6, 9] {
                let mut enc = xz2::write::XzEncoder::new(Vec::new(), level);
                enc.write_all(&data).unwrap();
                let xz = enc.finish().unwrap();
                let n = data.len() as u64;
                let mut pure = Vec::new();
                unxz(&xz, n + 1, &mut pure).unwrap();
                assert_eq!(liblzma(&xz, n + 1), data, "liblzma, level {level}");
                assert_eq!(pure, data, "lzma-rs, level {level}");
                if n > 10 {
                    let mut pure = Vec::new();
                    unxz(&xz, n / 2, &mut pure).unwrap();
                    assert_eq!(liblzma(&xz, n / 2), pure, "cut at the limit alike");
                    assert_eq!(pure.len() as u64, n / 2);
                }
                let mut cut = Vec::new();
                assert!(
                    unxz(&xz[..xz.len() / 2], n + 1, &mut cut).is_err() || data.is_empty(),
                    "a truncated stream is an error"
                );
            }
        }
    }
}
