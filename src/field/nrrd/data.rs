//! A NRRD file's values: their `type`, `encoding` and `endian`, where they are (after the
//! header or in the detached `data file`), the `line skip` and `byte skip` before them, and
//! their decoding, checked against the bytes present.

use std::borrow::Cow;
use std::path::Path;

use super::header::{Header, Res, field, number};
use crate::error::{escape_for_error, escape_path};
use crate::field::inputs::{Inputs, gunzip_prefix};
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

/// The bytes holding the data: after the header, or the detached `data file` (a regular file
/// named relative to the header's folder).
pub(super) fn payload<'a>(
    inputs: &'a Inputs,
    path: &Path,
    h: &Header,
    bytes: &'a [u8],
) -> Res<Cow<'a, [u8]>> {
    match h.get("data file") {
        Some(name) => {
            if name.starts_with("LIST") || name.contains(' ') {
                return Err(field(
                    "data file",
                    "only a single data file is read (no LIST or file patterns)",
                ));
            }
            let p = Inputs::next_to(path, name);
            inputs
                .read(&p)
                .map_err(|e| field("data file", format!("{}: {}", escape_path(&p), e)))
        }
        None => Ok(Cow::Borrowed(&bytes[h.data_start..])),
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

/// Where the values begin in what [`skip`] leaves.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(super) enum Start {
    Here,
    /// After this many bytes of the inflated stream: Teem counts a gzip file's `byte skip`
    /// there (its `line skip` in the file).
    Inflated(usize),
    /// The values are the last bytes (`byte skip: -1`, raw data only).
    AtEnd,
}

/// The data after `line skip` lines and, unless it is compressed, `byte skip` bytes.
pub(super) fn skip<'a>(h: &Header, mut data: &'a [u8], enc: Encoding) -> Res<(&'a [u8], Start)> {
    if let Some(n) = h.get("line skip") {
        let n: usize = number("line skip", n)?;
        for _ in 0..n {
            let e = data
                .iter()
                .position(|&b| b == b'\n')
                .ok_or_else(|| field("line skip", "more lines than the data holds"))?;
            data = &data[e + 1..];
        }
    }
    if let Some(n) = h.get("byte skip") {
        let n: i64 = number("byte skip", n)?;
        if n == -1 {
            if enc != Encoding::Raw {
                return Err(field("byte skip", "-1 is for raw data only"));
            }
            return Ok((data, Start::AtEnd));
        }
        let n = usize::try_from(n).map_err(|_| field("byte skip", "must be -1 or ≥ 0"))?;
        if enc == Encoding::Gzip {
            return Ok((data, Start::Inflated(n)));
        }
        data = data
            .get(n..)
            .ok_or_else(|| field("byte skip", "beyond the end of the data"))?;
    }
    Ok((data, Start::Here))
}

pub(super) fn decode(
    data: &[u8],
    enc: Encoding,
    ty: Scalar,
    big: bool,
    count: usize,
    start: Start,
) -> Res<Vec<f64>> {
    let width = ty.size();
    let short = |have: usize, what: &str| {
        field(
            "sizes",
            format!(
                "need {count} values ({} bytes), the {what} holds {have} bytes",
                count.saturating_mul(width)
            ),
        )
    };
    let bytes: Cow<[u8]> = match enc {
        Encoding::Ascii => {
            // Every value takes at least one byte and a separator.
            if data.len() < count.saturating_mul(2).saturating_sub(1) {
                return Err(short(data.len(), "ascii data"));
            }
            let mut out = Vec::with_capacity(count);
            for w in data
                .split(|b| b.is_ascii_whitespace() || *b == b',')
                .filter(|w| !w.is_empty())
            {
                if out.len() == count {
                    return Err(field(
                        "sizes",
                        format!("the ascii data holds more than {count} values"),
                    ));
                }
                let s = std::str::from_utf8(w).unwrap_or("?");
                out.push(number::<f64>("data", s)?);
            }
            if out.len() < count {
                return Err(field(
                    "sizes",
                    format!("need {count} values, the ascii data holds {}", out.len()),
                ));
            }
            return Ok(out);
        }
        Encoding::Raw => Cow::Borrowed(data),
        Encoding::Gzip => {
            let skipped = match start {
                Start::Inflated(n) => n,
                _ => 0,
            };
            let want = (count as u64)
                .saturating_mul(width as u64)
                .saturating_add(skipped as u64);
            let mut inflated = gunzip_prefix(data, want, "the NRRD data")?;
            if inflated.len() < skipped {
                return Err(field(
                    "byte skip",
                    format!(
                        "{skipped} bytes, beyond the end of the data ({} bytes inflated)",
                        inflated.len()
                    ),
                ));
            }
            inflated.drain(..skipped);
            Cow::Owned(inflated)
        }
    };
    let need = count
        .checked_mul(width)
        .ok_or_else(|| field("sizes", "the sizes overflow"))?;
    if bytes.len() < need {
        return Err(short(bytes.len(), "data"));
    }
    let b = if start == Start::AtEnd {
        &bytes[bytes.len() - need..]
    } else {
        &bytes[..need]
    };
    Ok(b.chunks_exact(width).map(|c| ty.read(c, big)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::nrrd::parse;
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

    fn read(path: &Path, bytes: &[u8]) -> Res<TensorField> {
        parse(&Inputs::file_system(), path, bytes, &ReadOptions::default())
    }

    /// The field holds the two voxels written, `xx xy xz yy yz zz` each.
    fn holds_the_values(f: &TensorField) {
        let v: Vec<f64> = values().iter().map(|&x| x as f64).collect();
        assert_eq!(f.tensors.len(), 2);
        for (i, t) in f.tensors.iter().enumerate() {
            assert_eq!(
                *t,
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
        assert_ne!(read(p, &b).unwrap().tensors[0][0], 1.0);
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
        assert_ne!(read(&nhdr, &h).unwrap().tensors[0][0], 1.0);
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
        assert_ne!(read(Path::new("a.nrrd"), &b).unwrap().tensors[0][0], 1.0);
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
