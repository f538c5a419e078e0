//! A NRRD file's values: their `type`, `encoding` and `endian`, where they are (after the
//! header or in the detached `data file`), the `line skip` and `byte skip` before them, and
//! their decoding, checked against the bytes present.

use std::io::{BufRead as _, Read as _};
use std::path::Path;

use super::header::{Header, Res, field, number};
use crate::error::{LoadErrorKind, escape_for_error};
use crate::field::inputs::{Input, Inputs};
use crate::field::number::Scalar;

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Encoding {
    Raw,
    Gzip,
    Ascii,
}

/// The `encoding`, in any case (Teem writes `ASCII`).
pub(super) fn encoding(h: &Header) -> Res<Encoding> {
    let e = h.need("encoding")?;
    Ok(match e.to_ascii_lowercase().as_str() {
        "raw" => Encoding::Raw,
        "gzip" | "gz" => Encoding::Gzip,
        "ascii" | "text" | "txt" => Encoding::Ascii,
        _ => {
            return Err(field(
                "encoding",
                format!("'{}'; read are raw, gzip and ascii", escape_for_error(e)),
            ));
        }
    })
}

/// Whether binary values are big-endian; single bytes and text need no `endian`.
pub(super) fn big_endian(h: &Header, encoding: Encoding, ty: Scalar) -> Res<bool> {
    Ok(match h.get("endian") {
        Some("little") => false,
        Some("big") => true,
        Some(e) => {
            return Err(field(
                "endian",
                format!("'{}' is neither little nor big", escape_for_error(e)),
            ));
        }
        None if encoding == Encoding::Ascii || ty.size() == 1 => false,
        None => return Err(field("endian", "missing; binary data needs it")),
    })
}

/// Where the values are: the file and the byte their region starts at (after the header, or
/// the start of the detached `data file`, a regular file named relative to the header's
/// folder).
pub(super) struct Region<'a> {
    pub(super) input: Input<'a>,
    pub(super) start: u64,
}

/// The region of `h`'s data: in `input` (the header's file) after the header, or in the
/// detached data file next to `path`.
pub(super) fn payload<'a>(
    inputs: &'a Inputs,
    path: &Path,
    h: &Header,
    input: Input<'a>,
) -> Res<Region<'a>> {
    match h.get("data file") {
        Some(name) => {
            if name.starts_with("LIST") || name.contains(' ') {
                return Err(field(
                    "data file",
                    "only a single data file is read (no LIST or file patterns)",
                ));
            }
            let d = Inputs::detached(path, name.as_bytes()).map_err(|e| field("data file", e))?;
            let input = inputs
                .open(&d.path)
                .map_err(|e| field("data file", format!("{}: {e}", d.shown)))?;
            Ok(Region { input, start: 0 })
        }
        None => Ok(Region {
            input,
            start: h.data_start as u64,
        }),
    }
}

impl Scalar {
    /// The type a `type` field names (every spelling the NRRD format allows; not `block`).
    pub(super) fn nrrd_named(t: &str) -> Option<Scalar> {
        Some(match t.to_ascii_lowercase().as_str() {
            "signed char" | "int8" | "int8_t" => Scalar::I8,
            "uchar" | "unsigned char" | "uint8" | "uint8_t" => Scalar::U8,
            "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
                Scalar::I16
            }
            "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
                Scalar::U16
            }
            "int" | "signed int" | "int32" | "int32_t" => Scalar::I32,
            "uint" | "unsigned int" | "uint32" | "uint32_t" => Scalar::U32,
            "longlong"
            | "long long"
            | "long long int"
            | "signed long long"
            | "signed long long int"
            | "int64"
            | "int64_t" => Scalar::I64,
            "ulonglong"
            | "unsigned long long"
            | "unsigned long long int"
            | "uint64"
            | "uint64_t" => Scalar::U64,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
}

/// Where the values begin in the region [`skip`] leaves.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(super) enum Start {
    Here,
    /// After this many bytes of the inflated stream: Teem counts a gzip file's `byte skip`
    /// there (its `line skip` in the file).
    Inflated(u64),
    /// The values are the last bytes (`byte skip: -1`, raw data only).
    AtEnd,
}

/// Lines skipped before the values are text (another format's header, a preamble): they may
/// span this many bytes. Past it the skip is refused instead of read on through a data file of
/// any size (a sparse file of 64 GB of zeros has no line end to stop at).
pub(super) const LINE_SKIP_MAX: u64 = 16 << 20;

/// ASCII data may hold this many bytes per value (a float in full precision and separators
/// take 25) and [`ASCII_SLACK`] more: a larger file is refused rather than read whole.
const ASCII_BYTES_PER_VALUE: u64 = 128;
const ASCII_SLACK: u64 = 1 << 20;

/// The region after `line skip` lines and, unless it is compressed, `byte skip` bytes. Lines
/// are counted as the bytes go by, never held, and no further than [`LINE_SKIP_MAX`] bytes.
pub(super) fn skip<'a>(
    h: &Header,
    mut region: Region<'a>,
    enc: Encoding,
) -> Res<(Region<'a>, Start)> {
    if let Some(n) = h.get("line skip") {
        let n: usize = number("line skip", n)?;
        if n > 0 {
            let mut r = std::io::BufReader::with_capacity(
                1 << 16,
                region.input.reader_at(region.start)?.take(LINE_SKIP_MAX),
            );
            let mut left = n;
            let mut passed = 0u64;
            while left > 0 {
                let buf = r.fill_buf().map_err(LoadErrorKind::Io)?;
                if buf.is_empty() {
                    let left_unread = region
                        .input
                        .len()
                        .saturating_sub(region.start.saturating_add(passed));
                    return Err(field(
                        "line skip",
                        if left_unread > 0 {
                            format!(
                                "{n} lines not found in the first {LINE_SKIP_MAX} bytes of the \
                                 data; skipped lines are text and are not looked for further"
                            )
                        } else {
                            "more lines than the data holds".into()
                        },
                    ));
                }
                let mut used = buf.len();
                for (i, _) in buf.iter().enumerate().filter(|(_, b)| **b == b'\n') {
                    left -= 1;
                    if left == 0 {
                        used = i + 1;
                        break;
                    }
                }
                passed += used as u64;
                r.consume(used);
            }
            drop(r);
            region.start += passed;
        }
    }
    if let Some(n) = h.get("byte skip") {
        let n: i64 = number("byte skip", n)?;
        if n == -1 {
            if enc != Encoding::Raw {
                return Err(field("byte skip", "-1 is for raw data only"));
            }
            return Ok((region, Start::AtEnd));
        }
        let n = u64::try_from(n).map_err(|_| field("byte skip", "must be -1 or ≥ 0"))?;
        if enc == Encoding::Gzip {
            return Ok((region, Start::Inflated(n)));
        }
        if n > region.input.len() - region.start {
            return Err(field("byte skip", "beyond the end of the data"));
        }
        region.start += n;
    }
    Ok((region, Start::Here))
}

/// Bytes decoded at a time.
const BLOCK: usize = 1 << 16;

/// Hand the `count` values of the region to `put`, in file order, each as soon as it is
/// decoded: only the bytes they need are read (a gzip stream is inflated to its end, within its
/// budget, to check it; ASCII data is read to the end of the file).
pub(super) fn decode(
    region: &Region<'_>,
    enc: Encoding,
    ty: Scalar,
    big: bool,
    count: usize,
    start: Start,
    mut put: impl FnMut(f64),
) -> Res<()> {
    let width = ty.size();
    let short = |have: u64, what: &str| {
        field(
            "sizes",
            format!(
                "need {count} values ({} bytes), the {what} holds {have} bytes",
                count.saturating_mul(width)
            ),
        )
    };
    let need = (count as u64)
        .checked_mul(width as u64)
        .ok_or_else(|| field("sizes", "the sizes overflow"))?;
    let have = region.input.len() - region.start.min(region.input.len());
    let mut buf = vec![0u8; BLOCK - BLOCK % width];
    let mut each = |bytes: &[u8]| {
        for c in bytes.chunks_exact(width) {
            put(ty.read(c, big));
        }
    };
    match enc {
        Encoding::Ascii => {
            // Every value takes at least one byte and a separator, and no value 128.
            if have < (count as u64).saturating_mul(2).saturating_sub(1) {
                return Err(short(have, "ascii data"));
            }
            let most = (count as u64)
                .saturating_mul(ASCII_BYTES_PER_VALUE)
                .saturating_add(ASCII_SLACK);
            if have > most {
                return Err(field(
                    "sizes",
                    format!(
                        "{count} values as ascii take at most {most} bytes, the data holds \
                         {have}: not read"
                    ),
                ));
            }
            let data = region.input.read_at(region.start, have)?;
            let mut n = 0usize;
            let mut words = data
                .split(|b| b.is_ascii_whitespace() || *b == b',')
                .filter(|w| !w.is_empty())
                .peekable();
            while let Some(w) = words.next() {
                if n == count {
                    return Err(field(
                        "sizes",
                        format!("the ascii data holds more than {count} values"),
                    ));
                }
                // A number running into the end of the file may have lost digits (1.5927 cut
                // to 1.592): Teem ends its ASCII data with a newline.
                if words.peek().is_none() && data.ends_with(w) {
                    return Err(field(
                        "data",
                        format!(
                            "the file ends inside the number '{}' (truncated?)",
                            escape_for_error(w)
                        ),
                    ));
                }
                let s = std::str::from_utf8(w).unwrap_or("?");
                put(number::<f64>("data", s)?);
                n += 1;
            }
            if n < count {
                return Err(field(
                    "sizes",
                    format!("need {count} values, the ascii data holds {n}"),
                ));
            }
            Ok(())
        }
        Encoding::Raw => {
            if have < need {
                return Err(short(have, "data"));
            }
            let from = if start == Start::AtEnd {
                region.input.len() - need
            } else {
                region.start
            };
            let mut r = region.input.reader_at(from)?;
            let mut left = need;
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                r.read_exact(&mut buf[..want]).map_err(LoadErrorKind::Io)?;
                each(&buf[..want]);
                left -= want as u64;
            }
            Ok(())
        }
        Encoding::Gzip => {
            let skipped = match start {
                Start::Inflated(n) => n,
                _ => 0,
            };
            let mut g = region.input.gunzip(region.start, "the NRRD data")?;
            g.need(need.saturating_add(skipped))?;
            if g.skip(skipped)? < skipped {
                return Err(field(
                    "byte skip",
                    format!(
                        "{skipped} bytes, beyond the end of the data ({} bytes inflated)",
                        g.inflated()
                    ),
                ));
            }
            let mut left = need;
            while left > 0 {
                let want = left.min(buf.len() as u64) as usize;
                let got = g.fill(&mut buf[..want])?;
                if got < want {
                    return Err(short(g.inflated() - skipped, "data"));
                }
                each(&buf[..want]);
                left -= want as u64;
            }
            g.finish()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::nrrd;
    use crate::field::{ComponentOrder, ReadOptions, TensorField};

    /// Two voxels (2×1×1) of six components each: voxel v holds 10v+1 .. 10v+6.
    fn values() -> Vec<f32> {
        (0..2)
            .flat_map(|v| (1..=6).map(move |c| (10 * v + c) as f32))
            .collect()
    }

    fn le_bytes() -> Vec<u8> {
        values().iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    fn header(fields: &str) -> Vec<u8> {
        format!(
            "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 2 1 1\n\
             kinds: 3D-symmetric-matrix space space space\n{fields}"
        )
        .into_bytes()
    }

    fn attached(fields: &str, data: &[u8]) -> Vec<u8> {
        let mut b = header(fields);
        b.push(b'\n');
        b.extend_from_slice(data);
        b
    }

    /// The field read from `bytes` as the file `path`: handed over by name, or, for a path in
    /// a folder (beside a detached data file), written there and read from the file system.
    fn read(path: &Path, bytes: &[u8]) -> Res<TensorField> {
        let opts = ReadOptions::default();
        if path.is_absolute() {
            std::fs::write(path, bytes).unwrap();
            return nrrd::read(&Inputs::file_system(), path, &opts);
        }
        let name = path.to_string_lossy().into_owned();
        nrrd::read(&Inputs::named([(name, bytes.to_vec())]), path, &opts)
    }

    /// The field holds the two voxels written, `xx xy xz yy yz zz` each.
    fn holds_the_values(f: &TensorField) {
        let v: Vec<f64> = values().iter().map(|&x| x as f64).collect();
        assert_eq!(f.tensors.len(), 2);
        for (i, t) in f.tensors.iter().enumerate() {
            assert_eq!(
                t,
                ComponentOrder::Fsl.expand(&v[6 * i..6 * i + 6]),
                "voxel {i}"
            );
        }
    }

    fn junk_then(junk: &[u8], data: &[u8]) -> Vec<u8> {
        [junk, data].concat()
    }

    #[test]
    fn byte_skip_skips_bytes_before_attached_raw_data() {
        let p = Path::new("a.nrrd");
        let b = attached(
            "endian: little\nencoding: raw\nbyte skip: 5\n",
            &junk_then(b"\x00\x01\x02\x03\x04", &le_bytes()),
        );
        holds_the_values(&read(p, &b).unwrap());
        // Without the skip the same bytes are other numbers (and one value too few).
        let b = attached(
            "endian: little\nencoding: raw\n",
            &junk_then(b"\x00\x01\x02\x03\x04", &le_bytes()),
        );
        assert_ne!(read(p, &b).unwrap().tensor(0)[0], 1.0);
    }

    #[test]
    fn byte_skip_minus_one_takes_the_last_bytes_of_raw_data() {
        let b = attached(
            "endian: little\nencoding: raw\nbyte skip: -1\n",
            &junk_then(b"a preamble of unknown length\n", &le_bytes()),
        );
        holds_the_values(&read(Path::new("a.nrrd"), &b).unwrap());
        let b = attached(
            "endian: little\nencoding: gzip\nbyte skip: -1\n",
            &le_bytes(),
        );
        let e = read(Path::new("a.nrrd"), &b).unwrap_err().to_string();
        assert!(e.contains("'byte skip': -1 is for raw data only"), "{e}");
    }

    #[test]
    fn line_skip_then_byte_skip_apply_to_a_detached_file() {
        let dir = tempfile::tempdir().unwrap();
        let raw = junk_then(b"first line\nsecond line\n\xff\xfe\xfd", &le_bytes());
        std::fs::write(dir.path().join("d.raw"), &raw).unwrap();
        let nhdr = dir.path().join("d.nhdr");
        let h = header(
            "endian: little\nencoding: raw\nline skip: 2\nbyte skip: 3\ndata file: ./d.raw\n",
        );
        holds_the_values(&read(&nhdr, &h).unwrap());
        // Line skip alone leaves the three bytes in front of the values.
        let h = header("endian: little\nencoding: raw\nline skip: 2\ndata file: d.raw\n");
        assert_ne!(read(&nhdr, &h).unwrap().tensor(0)[0], 1.0);
        let h = header("endian: little\nencoding: raw\nline skip: 3\ndata file: d.raw\n");
        let e = read(&nhdr, &h).unwrap_err().to_string();
        assert!(
            e.contains("'line skip': more lines than the data holds"),
            "{e}"
        );
    }

    #[test]
    fn big_endian_floats_and_doubles() {
        let be: Vec<u8> = values().iter().flat_map(|x| x.to_be_bytes()).collect();
        let b = attached("endian: big\nencoding: raw\n", &be);
        holds_the_values(&read(Path::new("a.nrrd"), &b).unwrap());
        let be64: Vec<u8> = values()
            .iter()
            .flat_map(|&x| (x as f64).to_be_bytes())
            .collect();
        let b = attached("endian: big\nencoding: raw\n", &be64);
        let b = String::from_utf8_lossy(&b[..b.len() - be64.len()])
            .replace("type: float", "type: double")
            .into_bytes();
        holds_the_values(&read(Path::new("a.nrrd"), &[b, be64].concat()).unwrap());
        // Read as little-endian, the same bytes are other numbers.
        let b = attached("endian: little\nencoding: raw\n", &be);
        assert_ne!(read(Path::new("a.nrrd"), &b).unwrap().tensor(0)[0], 1.0);
    }

    #[test]
    fn gzip_byte_skip_counts_inflated_bytes_and_line_skip_file_lines() {
        use std::io::Write as _;
        let gz = |data: &[u8]| {
            let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
            e.write_all(data).unwrap();
            e.finish().unwrap()
        };
        let inflated = gz(&junk_then(b"1234", &le_bytes()));
        let b = attached(
            "endian: little\nencoding: gzip\nline skip: 1\nbyte skip: 4\n",
            &junk_then(b"a text line before the gzip stream\n", &inflated),
        );
        holds_the_values(&read(Path::new("a.nrrd"), &b).unwrap());
        let b = attached(
            "endian: little\nencoding: gzip\nbyte skip: 1000\n",
            &inflated,
        );
        let e = read(Path::new("a.nrrd"), &b).unwrap_err().to_string();
        assert!(e.contains("'byte skip': 1000 bytes, beyond the end"), "{e}");
    }

    #[test]
    fn a_byte_skip_past_the_data_is_an_error() {
        let b = attached(
            "endian: little\nencoding: raw\nbyte skip: 4096\n",
            &le_bytes(),
        );
        let e = read(Path::new("a.nrrd"), &b).unwrap_err().to_string();
        assert!(e.contains("'byte skip': beyond the end of the data"), "{e}");
        let b = attached("endian: little\nencoding: raw\nbyte skip: 4\n", &le_bytes());
        let e = read(Path::new("a.nrrd"), &b).unwrap_err().to_string();
        assert!(e.contains("'sizes': need 12 values (48 bytes)"), "{e}");
    }
}
