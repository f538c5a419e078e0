//! An MRtrix image header: the `mrtrix image` line, `key: value` lines up to `END`, and the
//! image they describe (`dim`, `vox`, `layout`, `datatype`, `transform`, `scaling`, `file`).
//!
//! As MRtrix3 reads it (`core/formats/mrtrix_utils.h`, `core/file/key_value.cpp`): keys are
//! matched in any case, text from `#` to the end of a line is a comment, a line without a colon
//! is skipped, `transform` is given as several lines (the first three rows of 4 values are
//! used), other keys are kept by MRtrix and ignored here. Unlike MRtrix, which takes the last of
//! a repeated key, a repeated `dim`, `vox`, `layout`, `datatype`, `scaling` or `file` is refused:
//! two answers to one question make a damaged header, not a choice.

use std::borrow::Cow;

use nalgebra::{Matrix3, Matrix4};

use crate::error::{LoadErrorKind, escape_for_error};
use crate::field::gzip::is_gzip;
use crate::field::inputs::Input;
use crate::field::number::Scalar;

pub(super) type Res<T> = Result<T, LoadErrorKind>;

/// The first line of every MRtrix image header.
const MAGIC: &[u8] = b"mrtrix image";

/// A header longer than this (with no `END` line in it) is refused: MRtrix's own headers, a
/// gradient table of thousands of lines included, are a few hundred kilobytes at most.
pub(super) const MAX_HEADER: u64 = 16 << 20;

/// More axes than MRtrix itself allows (16) are refused before anything is counted.
const MAX_AXES: usize = 16;

pub(super) fn field(name: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.to_string(),
        message: message.into(),
    }
}

/// Where the values are.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum DataFile {
    /// In the header's own file (`file: . OFFSET`), from this byte (of the inflated stream for
    /// `.mif.gz`).
    Same(u64),
    /// In the file of this name (its bytes) next to the header, from this byte.
    Detached(Vec<u8>, u64),
}

/// One axis of the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Axis {
    pub(super) size: usize,
    /// Its place in the order of storage (0: contiguous), from `layout`.
    pub(super) rank: usize,
    /// Stored from the last index to the first (`layout: -N`).
    pub(super) reversed: bool,
}

/// The image a header describes.
#[derive(Debug, Clone)]
pub(super) struct Header {
    /// At least three (MRtrix gives a 1- or 2-D image size-1 axes up to three).
    pub(super) axes: Vec<Axis>,
    /// Voxel sizes of the three spatial axes, finite and positive.
    pub(super) vox: [f64; 3],
    pub(super) ty: Scalar,
    pub(super) big: bool,
    /// The first three rows of the 4x4 transform, when given.
    pub(super) transform: Option<[[f64; 4]; 3]>,
    /// `value = offset + scale * stored` for integer data; (0, 1) for float data, whose
    /// `scaling` MRtrix ignores (3.0.3: a Float32 image with `scaling: 10,3` reads as stored).
    pub(super) scaling: (f64, f64),
    pub(super) data: DataFile,
    /// Whether the header's file is gzip-compressed (`.mif.gz`).
    pub(super) gz: bool,
    /// Whether the header has a `dw_scheme`: a DWI series (`dwi2fod` keeps it as
    /// `prior_dw_scheme`).
    pub(super) dw_scheme: bool,
    /// Whether the last program of its `command_history` that makes tensors or peaks was
    /// `sh2peaks`: the image holds fibre directions (3 values a peak), whatever its count.
    pub(super) peaks: bool,
}

impl Header {
    /// Voxels of the three spatial axes.
    pub(super) fn dims(&self) -> [usize; 3] {
        [self.axes[0].size, self.axes[1].size, self.axes[2].size]
    }

    /// Values per voxel: the product of the sizes past the third axis.
    pub(super) fn per_voxel(&self) -> Res<usize> {
        self.axes[3..]
            .iter()
            .try_fold(1usize, |a, x| a.checked_mul(x.size))
            .ok_or_else(|| field("dim", "the dimensions overflow"))
    }

    /// The voxel-to-world matrix (scanner space, RAS as in NIfTI) and where it came from:
    /// `transform` with the voxel sizes applied, as MRtrix applies them (its transform maps
    /// millimetres along the image axes); without one, MRtrix's default, the identity centred
    /// on the lattice.
    pub(super) fn affine(&self) -> Res<(Matrix4<f64>, &'static str)> {
        let mut a = Matrix4::identity();
        let source = match &self.transform {
            Some(t) => {
                let linear = Matrix3::from_fn(|r, c| t[r][c]);
                // MRtrix divides each column by its length (moving it into the voxel size):
                // a column of length 0 has no direction.
                if (0..3).any(|c| linear.column(c).norm() == 0.0) {
                    return Err(field(
                        "transform",
                        "a column of the rotation is zero: the image axes have no direction",
                    ));
                }
                for r in 0..3 {
                    for c in 0..3 {
                        a[(r, c)] = t[r][c] * self.vox[c];
                    }
                    a[(r, 3)] = t[r][3];
                }
                "transform"
            }
            None => {
                for i in 0..3 {
                    a[(i, i)] = self.vox[i];
                    a[(i, 3)] = -0.5 * (self.axes[i].size as f64 - 1.0) * self.vox[i];
                }
                "no transform (MRtrix's default: centred)"
            }
        };
        if !a.iter().all(|x| x.is_finite()) {
            return Err(field("vox", "the voxel-to-world matrix is not finite"));
        }
        Ok((a, source))
    }
}

/// Read and check the header of the MRtrix image `input` (`.mif`, `.mih` or `.mif.gz`): its
/// text up to `END`, no further (nor past [`MAX_HEADER`] bytes).
pub(super) fn read_header(input: &Input) -> Res<Header> {
    let gz = is_gzip(&input.read_at(0, 2)?);
    let text: Cow<[u8]> = if gz {
        let mut g = input.gunzip(0, "the header")?;
        let mut b = Vec::new();
        let mut chunk = vec![0u8; 1 << 14];
        let mut scan = Scan::default();
        loop {
            if let Some(end) = header_end(&b, &mut scan) {
                b.truncate(end);
                break;
            }
            if b.len() as u64 >= MAX_HEADER {
                return Err(no_end(&b));
            }
            let got = g.fill(&mut chunk)?;
            if got == 0 {
                return Err(no_end(&b));
            }
            b.extend_from_slice(&chunk[..got]);
        }
        Cow::Owned(b)
    } else {
        let mut n: u64 = 1 << 14;
        let mut scan = Scan::default();
        loop {
            let b = input.read_at(0, n.min(MAX_HEADER))?;
            if let Some(end) = header_end(&b, &mut scan) {
                break match b {
                    Cow::Borrowed(s) => Cow::Borrowed(&s[..end]),
                    Cow::Owned(mut v) => {
                        v.truncate(end);
                        Cow::Owned(v)
                    }
                };
            }
            if n >= MAX_HEADER {
                return Err(no_end(&b));
            }
            if n >= input.len() {
                // A `.mih` is all header: it may end where the file does.
                if !b.starts_with(MAGIC) {
                    return Err(not_mrtrix());
                }
                let h = parse(&b, false)?;
                if let DataFile::Same(_) = h.data {
                    return Err(no_end(&b));
                }
                return Ok(h);
            }
            n = n.saturating_mul(4);
        }
    };
    parse(&text, gz)
}

/// The error for header text `b` in which no `END` line was found.
fn no_end(b: &[u8]) -> LoadErrorKind {
    if !b.starts_with(MAGIC) {
        return not_mrtrix();
    }
    LoadErrorKind::Malformed(format!(
        "an MRtrix header ends with a line 'END'; none in the first {} bytes",
        MAX_HEADER
    ))
}

/// How far a header read in growing pieces has been looked at: where the line not yet whole
/// begins, and how far into it the search for its newline has gone.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
struct Scan {
    line: usize,
    searched: usize,
}

/// Where the header ends: just after its `END` line, `None` if there is none yet. `scan` is
/// left at the first line not yet whole and how far its newline was searched for, so that a
/// header read in growing pieces is scanned once, however long its lines (a 16 MiB line was
/// searched from its start at each new piece: 5–8 s to refuse). A file that does not begin with
/// the magic ends at once (it is refused by [`parse`]).
fn header_end(b: &[u8], scan: &mut Scan) -> Option<usize> {
    if !MAGIC.starts_with(&b[..b.len().min(MAGIC.len())]) {
        return Some(0);
    }
    let mut pos = scan.line.min(b.len());
    let mut from = scan.searched.clamp(pos, b.len());
    while let Some(e) = memchr::memchr(b'\n', &b[from..]) {
        let end = from + e;
        if strip(comment_free(&b[pos..end])) == b"END" {
            return Some(end + 1);
        }
        pos = end + 1;
        from = pos;
    }
    *scan = Scan {
        line: pos,
        searched: b.len(),
    };
    None
}

fn comment_free(line: &[u8]) -> &[u8] {
    memchr::memchr(b'#', line).map_or(line, |i| &line[..i])
}

fn strip(b: &[u8]) -> &[u8] {
    let start = b.iter().position(|c| !c.is_ascii_whitespace());
    let end = b.iter().rposition(|c| !c.is_ascii_whitespace());
    match (start, end) {
        (Some(s), Some(e)) => &b[s..=e],
        _ => &[],
    }
}

fn not_mrtrix() -> LoadErrorKind {
    LoadErrorKind::Malformed("not an MRtrix image (its first line is not 'mrtrix image')".into())
}

/// The values of the keys the reader uses, as text.
#[derive(Default)]
struct Raw {
    dim: Option<String>,
    vox: Option<String>,
    layout: Option<String>,
    datatype: Option<String>,
    scaling: Option<String>,
    /// The bytes as written: a data file's name is the system's, in any encoding.
    file: Option<Vec<u8>>,
    /// The first three `transform` rows (the ones used) and how many there were: a header may
    /// hold up to 16 MiB of rows, and keeping each was 4x the header's bytes in memory.
    transform: Vec<String>,
    transform_rows: usize,
    dw_scheme: bool,
    peaks: bool,
}

/// The header `text` (up to and including its `END` line) checked into a [`Header`].
pub(super) fn parse(text: &[u8], gz: bool) -> Res<Header> {
    let first = &text[..memchr::memchr(b'\n', text).unwrap_or(text.len())];
    if strip(first) != MAGIC {
        return Err(not_mrtrix());
    }
    let mut raw = Raw::default();
    let mut starts = std::iter::once(0).chain(memchr::memchr_iter(b'\n', text).map(|e| e + 1));
    starts.next();
    let mut at = starts.next();
    while let Some(start) = at {
        at = starts.next();
        let line = &text[start..at.map_or(text.len(), |e| e - 1)];
        let line = strip(comment_free(line));
        if line == b"END" {
            break;
        }
        let Some(colon) = memchr::memchr(b':', line) else {
            continue;
        };
        // Keys compared as bytes in any case: a header of a million lines allocates for the
        // few the reader keeps, not for every line (a 16 MiB header was 0.27 s, now ~0.05 s).
        let key = strip(&line[..colon]);
        let is = |k: &str| key.eq_ignore_ascii_case(k.as_bytes());
        let bytes = strip(&line[colon + 1..]);
        let value = || String::from_utf8_lossy(bytes).into_owned();
        if is("file") {
            if raw.file.is_some() {
                return Err(field(
                    "file",
                    "given twice: only an image in one data file is read",
                ));
            }
            raw.file = Some(bytes.to_vec());
            continue;
        }
        if is("transform") {
            raw.transform_rows += 1;
            if raw.transform.len() < 3 {
                raw.transform.push(value());
            }
            continue;
        }
        if is("dw_scheme") {
            raw.dw_scheme = true;
            continue;
        }
        if is("command_history") {
            // Each line a command, the program first (MRtrix keeps one line per command run).
            match bytes.split(|c| c.is_ascii_whitespace()).next() {
                Some(b"sh2peaks") => raw.peaks = true,
                Some(b"dwi2tensor" | b"tensor2metric" | b"dwi2fod") => raw.peaks = false,
                _ => {}
            }
            continue;
        }
        let (name, slot) = if is("dim") {
            ("dim", &mut raw.dim)
        } else if is("vox") {
            ("vox", &mut raw.vox)
        } else if is("layout") {
            ("layout", &mut raw.layout)
        } else if is("datatype") {
            ("datatype", &mut raw.datatype)
        } else if is("scaling") {
            ("scaling", &mut raw.scaling)
        } else {
            continue;
        };
        if slot.is_some() {
            return Err(field(name, "given twice"));
        }
        *slot = Some(value());
    }
    let need =
        |v: Option<String>, key: &str| v.ok_or_else(|| field(key, "missing; it is required"));

    let sizes = sizes(&need(raw.dim, "dim")?)?;
    let (rank, reversed) = layout(&need(raw.layout, "layout")?, sizes.len())?;
    let mut axes: Vec<Axis> = (0..sizes.len())
        .map(|i| Axis {
            size: sizes[i],
            rank: rank[i],
            reversed: reversed[i],
        })
        .collect();
    // A 1- or 2-D image: size-1 axes stored last, as MRtrix pads it.
    while axes.len() < 3 {
        axes.push(Axis {
            size: 1,
            rank: axes.len(),
            reversed: false,
        });
    }
    let vox = voxel_sizes(&need(raw.vox, "vox")?, sizes.len())?;
    let (ty, big) = datatype(&need(raw.datatype, "datatype")?)?;
    let transform = if raw.transform.is_empty() {
        None
    } else {
        Some(transform(&raw.transform, raw.transform_rows)?)
    };
    let scaling = match raw.scaling {
        None => (0.0, 1.0),
        Some(s) => {
            let v = floats("scaling", &s)?;
            if v.len() != 2 || !v.iter().all(|x| x.is_finite()) {
                return Err(field(
                    "scaling",
                    format!(
                        "'{}' is not two finite numbers (offset,scale)",
                        escape_for_error(&s)
                    ),
                ));
            }
            (v[0], v[1])
        }
    };
    // MRtrix 3.0.3 applies `scaling` to integer data only: float values are read as stored.
    let scaling = if matches!(ty, Scalar::F32 | Scalar::F64) {
        (0.0, 1.0)
    } else {
        scaling
    };
    let file = raw
        .file
        .ok_or_else(|| field("file", "missing; it is required"))?;
    let data = data_file(&file, text.len() as u64, gz)?;
    Ok(Header {
        axes,
        vox,
        ty,
        big,
        transform,
        scaling,
        data,
        gz,
        dw_scheme: raw.dw_scheme,
        peaks: raw.peaks,
    })
}

fn floats(key: &str, s: &str) -> Res<Vec<f64>> {
    s.split(',')
        .map(|x| {
            let x = x.trim();
            // MRtrix writes the voxel size of a non-spatial axis as "nan" (or "?" in mrinfo).
            x.parse::<f64>()
                .map_err(|_| field(key, format!("'{}' is not a number", escape_for_error(x))))
        })
        .collect()
}

/// `dim`: 1 to 16 positive sizes.
fn sizes(s: &str) -> Res<Vec<usize>> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() > MAX_AXES {
        return Err(field(
            "dim",
            format!(
                "{} axes; MRtrix images have at most {MAX_AXES}",
                parts.len()
            ),
        ));
    }
    parts
        .iter()
        .map(|p| match p.parse::<usize>() {
            Ok(0) => Err(field("dim", "a size is 0")),
            Ok(n) => Ok(n),
            Err(_) => Err(field(
                "dim",
                format!("'{}' is not a positive integer", escape_for_error(p)),
            )),
        })
        .collect()
}

/// `layout`: per axis a sign and its rank in the order of storage, the ranks a permutation.
fn layout(s: &str, n: usize) -> Res<(Vec<usize>, Vec<bool>)> {
    let bad = |why: String| field("layout", format!("'{}': {why}", escape_for_error(s)));
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        return Err(bad(format!("{} axes, dim has {n}", parts.len())));
    }
    let mut rank = Vec::with_capacity(n);
    let mut reversed = Vec::with_capacity(n);
    for p in &parts {
        let (neg, digits) = match p.as_bytes().first() {
            Some(b'-') => (true, &p[1..]),
            Some(b'+') => (false, &p[1..]),
            _ => (false, *p),
        };
        let r: usize = digits
            .parse()
            .ok()
            .filter(|_| digits.bytes().all(|c| c.is_ascii_digit()))
            .ok_or_else(|| bad("each axis is a sign and a rank (+0, -1, …)".into()))?;
        if r >= n {
            return Err(bad(format!("rank {r} for {n} axes")));
        }
        rank.push(r);
        reversed.push(neg);
    }
    let mut seen = vec![false; n];
    for &r in &rank {
        if std::mem::replace(&mut seen[r], true) {
            return Err(bad(format!("rank {r} given twice")));
        }
    }
    Ok((rank, reversed))
}

/// `vox`: the voxel sizes; the first three (as many as there are axes) finite and positive.
fn voxel_sizes(s: &str, n: usize) -> Res<[f64; 3]> {
    let v = floats("vox", s)?;
    let spatial = n.min(3);
    if v.len() < spatial {
        return Err(field(
            "vox",
            format!("{} sizes for {spatial} spatial axes", v.len()),
        ));
    }
    let mut out = [1.0; 3];
    for (i, x) in v.iter().take(spatial).enumerate() {
        if !(x.is_finite() && *x > 0.0) {
            return Err(field(
                "vox",
                format!("voxel size {x} on axis {i}; the spatial axes need finite positive sizes"),
            ));
        }
        out[i] = *x;
    }
    Ok(out)
}

/// `datatype`: the element type and whether it is big-endian. MRtrix's names in any case;
/// without `LE`/`BE` a multi-byte type is in the writer's native order, taken as
/// little-endian (every machine MRtrix runs on).
fn datatype(s: &str) -> Res<(Scalar, bool)> {
    let l = s.to_ascii_lowercase();
    let (base, big) = if let Some(b) = l.strip_suffix("le") {
        (b, false)
    } else if let Some(b) = l.strip_suffix("be") {
        (b, true)
    } else {
        (l.as_str(), false)
    };
    let ty = match base {
        "int8" => Scalar::I8,
        "uint8" => Scalar::U8,
        "int16" => Scalar::I16,
        "uint16" => Scalar::U16,
        "int32" => Scalar::I32,
        "uint32" => Scalar::U32,
        "int64" => Scalar::I64,
        "uint64" => Scalar::U64,
        "float32" => Scalar::F32,
        "float64" => Scalar::F64,
        _ => {
            let why = if l == "bit" {
                "one bit per value (a mask as MRtrix packs it) is not read; convert it with \
                 mrconvert -datatype uint8"
            } else if base.starts_with("cfloat") {
                "complex values have no tensor or scalar meaning here; take their real part \
                 or magnitude with mrcalc"
            } else {
                "not an MRtrix datatype (Int8 … Float64, with LE or BE)"
            };
            return Err(field(
                "datatype",
                format!("'{}': {why}", escape_for_error(s)),
            ));
        }
    };
    Ok((ty, big))
}

/// `transform`: at least three rows (`count` in all) of four finite numbers; the first three
/// (`rows`) are used.
fn transform(rows: &[String], count: usize) -> Res<[[f64; 4]; 3]> {
    if count < 3 {
        return Err(field(
            "transform",
            format!("{count} rows; the first three rows of the 4x4 matrix are needed"),
        ));
    }
    let mut t = [[0.0; 4]; 3];
    for (r, row) in rows.iter().take(3).enumerate() {
        let v = floats("transform", row)?;
        if v.len() != 4 || !v.iter().all(|x| x.is_finite()) {
            return Err(field(
                "transform",
                format!(
                    "row {r} '{}' is not four finite numbers",
                    escape_for_error(row)
                ),
            ));
        }
        t[r].copy_from_slice(&v);
    }
    // The rotation's columns must stand for three independent directions.
    let m = Matrix3::from_fn(|r, c| t[r][c]);
    let scale = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if scale == 0.0 || (m / scale).determinant() == 0.0 {
        return Err(field(
            "transform",
            "its 3x3 part is singular: the image axes do not span space",
        ));
    }
    Ok(t)
}

/// `file`: `. OFFSET` (the data after the header in this file) or `NAME [OFFSET]`, the name
/// its bytes as written.
fn data_file(s: &[u8], header_len: u64, gz: bool) -> Res<DataFile> {
    let mut words = s
        .split(|c| c.is_ascii_whitespace())
        .filter(|w| !w.is_empty());
    let name = words.next().unwrap_or_default();
    let offset = match words.next() {
        None => 0,
        Some(o) => std::str::from_utf8(o)
            .ok()
            .and_then(|o| o.parse::<u64>().ok())
            .ok_or_else(|| {
                field(
                    "file",
                    format!("'{}' is not a byte offset", escape_for_error(o)),
                )
            })?,
    };
    if words.next().is_some() {
        return Err(field(
            "file",
            format!("'{}' is not 'NAME OFFSET'", escape_for_error(s)),
        ));
    }
    if name == b"." {
        if offset < header_len {
            return Err(field(
                "file",
                format!("data offset {offset} is inside the header ({header_len} bytes up to END)"),
            ));
        }
        return Ok(DataFile::Same(offset));
    }
    if gz {
        return Err(field(
            "file",
            format!(
                "'{}': a .mif.gz holds its own data ('file: . OFFSET')",
                escape_for_error(name)
            ),
        ));
    }
    Ok(DataFile::Detached(name.to_vec(), offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head(lines: &str) -> Res<Header> {
        let text = format!("mrtrix image\n{lines}END\n");
        parse(text.as_bytes(), false)
    }

    const GOOD: &str = "dim: 4,3,2,6\nvox: 2,2.5,3,nan\nlayout: -0,+2,+1,+3\n\
        datatype: Float32BE\nfile: . 1000\n";

    #[test]
    fn reads_mrtrix_keys_in_any_case_with_comments_and_stray_lines() {
        let h = head(&format!(
            "# a comment\nDim: 4,3,2,6 # trailing\nnot a key value line\n{}",
            &GOOD[GOOD.find("vox").unwrap()..]
        ))
        .unwrap();
        assert_eq!(h.dims(), [4, 3, 2]);
        assert_eq!(h.per_voxel().unwrap(), 6);
        assert_eq!(
            h.axes
                .iter()
                .map(|a| (a.rank, a.reversed))
                .collect::<Vec<_>>(),
            [(0, true), (2, false), (1, false), (3, false)]
        );
        assert_eq!((h.ty, h.big), (Scalar::F32, true));
        assert_eq!(h.data, DataFile::Same(1000));
        // No transform: MRtrix's default, the identity centred on the lattice.
        let (a, _) = h.affine().unwrap();
        assert_eq!(a[(0, 0)], 2.0);
        assert_eq!(a[(0, 3)], -3.0);
        assert_eq!(a[(1, 3)], -2.5);
        assert_eq!(a[(2, 3)], -1.5);
    }

    #[test]
    fn applies_voxel_sizes_to_the_transform_columns() {
        let h = head(&format!(
            "{GOOD}transform: 0,-1,0,10\ntransform: 1,0,0,20\ntransform: 0,0,1,30\n"
        ))
        .unwrap();
        let (a, source) = h.affine().unwrap();
        assert_eq!(source, "transform");
        assert_eq!(a[(0, 1)], -2.5);
        assert_eq!(a[(1, 0)], 2.0);
        assert_eq!(a[(2, 2)], 3.0);
        assert_eq!(a[(1, 3)], 20.0);
    }

    #[test]
    fn refuses_each_bad_key_with_its_name() {
        let cases: [(&str, &str, &str); 12] = [
            ("dim: 4,3,2,6", "dim: 4,0,2,6", "'dim': a size is 0"),
            (
                "dim: 4,3,2,6",
                "dim: 4,x,2,6",
                "'dim': 'x' is not a positive integer",
            ),
            (
                "layout: -0,+2,+1,+3",
                "layout: +0,+0,+1,+2",
                "rank 0 given twice",
            ),
            (
                "layout: -0,+2,+1,+3",
                "layout: +0,+1,+2",
                "3 axes, dim has 4",
            ),
            (
                "layout: -0,+2,+1,+3",
                "layout: +0,+1,+2,+9",
                "rank 9 for 4 axes",
            ),
            (
                "datatype: Float32BE",
                "datatype: CFloat32LE",
                "complex values",
            ),
            ("datatype: Float32BE", "datatype: Bit", "one bit per value"),
            (
                "datatype: Float32BE",
                "datatype: Float16",
                "not an MRtrix datatype",
            ),
            (
                "vox: 2,2.5,3,nan",
                "vox: 2,-1,3",
                "'vox': voxel size -1 on axis 1",
            ),
            (
                "vox: 2,2.5,3,nan",
                "vox: 2",
                "'vox': 1 sizes for 3 spatial axes",
            ),
            (
                "file: . 1000",
                "file: . 12",
                "data offset 12 is inside the header",
            ),
            (
                "file: . 1000",
                "file: . 1000\nfile: . 2000",
                "'file': given twice",
            ),
        ];
        for (from, to, want) in cases {
            let e = head(&GOOD.replace(from, to)).unwrap_err().to_string();
            assert!(e.contains(want), "{to}: {e}");
        }
        for (lines, want) in [
            (GOOD.replace("dim: 4,3,2,6\n", ""), "'dim': missing"),
            (
                format!("{GOOD}transform: 1,0,0,0\ntransform: 0,1,0,0\n"),
                "2 rows",
            ),
            (
                format!("{GOOD}transform: 1,0,0\ntransform: 0,1,0,0\ntransform: 0,0,1,0\n"),
                "row 0 '1,0,0' is not four finite numbers",
            ),
            (
                format!("{GOOD}transform: 1,0,0,0\ntransform: 1,0,0,0\ntransform: 0,0,1,0\n"),
                "singular",
            ),
            (
                GOOD.replace("Float32BE", "Float32BE\nscaling: 1"),
                "'scaling'",
            ),
        ] {
            let e = head(&lines).unwrap_err().to_string();
            assert!(e.contains(want), "{lines}: {e}");
        }
        let e = parse(b"mrtrix imagine\nEND\n", false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not an MRtrix image"), "{e}");
    }

    /// As MRtrix 3.0.3 reads them (`mrdump` of a two-voxel image with `scaling: 10,3`: Float32
    /// [1, 2] reads 1, 2; Int16 [1, 2] reads 13, 16): scaling applies to integers only. And a
    /// header of many `transform` rows keeps three.
    #[test]
    fn scaling_applies_to_integer_data_only_and_transform_rows_are_counted() {
        let scaled = |ty: &str| {
            head(&GOOD.replace("Float32BE", &format!("{ty}\nscaling: 10,3")))
                .unwrap()
                .scaling
        };
        assert_eq!(scaled("Float32BE"), (0.0, 1.0));
        assert_eq!(scaled("Float64LE"), (0.0, 1.0));
        assert_eq!(scaled("Int16LE"), (10.0, 3.0));
        assert_eq!(scaled("UInt8"), (10.0, 3.0));
        let rows = "transform: 1,0,0,0\ntransform: 0,1,0,0\ntransform: 0,0,1,0\n".repeat(1000);
        let good = GOOD.replace("file: . 1000", "file: . 100000");
        let h = head(&format!("{good}{rows}")).unwrap();
        assert_eq!(h.transform.unwrap()[2], [0.0, 0.0, 1.0, 0.0]);
    }

    #[test]
    fn the_header_ends_at_its_end_line() {
        let text = b"mrtrix image\ndim: 1\n  END  \r\n\x00\x01binary";
        assert_eq!(header_end(text, &mut Scan::default()), Some(text.len() - 8));
        // Read in pieces: each byte looked at once, the last whole line remembered.
        let mut scan = Scan::default();
        assert_eq!(header_end(b"mrtrix image\ndim: 1\nEN", &mut scan), None);
        assert_eq!(
            scan,
            Scan {
                line: 20,
                searched: 22
            }
        );
        assert_eq!(
            header_end(b"mrtrix image\ndim: 1\nEND\n", &mut scan),
            Some(24)
        );
        assert_eq!(header_end(b"NRRD0004\n", &mut Scan::default()), Some(0));
    }

    /// A header whose one line is 16 MiB long, read in 16 KiB pieces as a `.mif.gz` is: each
    /// piece is searched once (the old scan searched the whole line again for every piece, about
    /// 8 GiB of bytes), and the line's start is kept for when its newline comes.
    #[test]
    fn a_long_line_is_searched_once() {
        let mut b = b"mrtrix image\nkey: ".to_vec();
        let mut scan = Scan::default();
        let piece = vec![b'x'; 1 << 14];
        for _ in 0..(MAX_HEADER >> 14) {
            b.extend_from_slice(&piece);
            assert_eq!(header_end(&b, &mut scan), None);
            assert_eq!(
                scan,
                Scan {
                    line: 13,
                    searched: b.len()
                }
            );
        }
        b.extend_from_slice(b"\nEND\n");
        assert_eq!(header_end(&b, &mut scan), Some(b.len()));
    }
}
