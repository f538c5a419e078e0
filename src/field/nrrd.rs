//! NRRD tensor volumes (`.nrrd`, `.nhdr` with a detached data file), as 3D Slicer and Teem
//! write them.
//!
//! No maintained Rust crate reads NRRD, so this is a strict reader of our own, held to the VTK
//! reader's standard: every count is checked against the bytes present before anything is
//! allocated, gzip data is inflated no further than the sizes need, a detached data file is
//! read only if it is a regular file (named relative to the header's folder).
//!
//! Read: `type` float or double; `dimension` 4 with the tensor axis first; `kinds`
//! `3D-symmetric-matrix` (6 values `xx xy xz yy yz zz`), `3D-masked-symmetric-matrix` (7, the
//! confidence first: below 0.5 the voxel is skipped and counted, as Teem does) or `3D-matrix`
//! (9, row-major); `encoding` raw, gzip or ascii; `endian`; `byte skip`, `line skip` (as Teem
//! counts them: lines in the file, bytes in the inflated data of gzip); `space`,
//! `space directions`, `space origin`, `measurement frame`; `data file`. Positions and
//! tensors are turned into RAS+ (LPS: x and y negated). Tensors are taken to be in the
//! measurement frame (world when there is none) unless `--tensor-frame` says otherwise.
//!
//! Scalar volumes ([`parse_scalar`]: `dimension` 3, any integer or float `type`) share the
//! header, data and geometry code, so they land in the same RAS+ world as tensors.

use std::borrow::Cow;
use std::path::Path;

use nalgebra::{Matrix3, Matrix4, Vector3};

use super::frame::{
    FrameInfo, Layout, ReadMeta, TensorFrame, Why, lattice_positions, rows3, rows4,
    smallest_spacing, tensor_rotation,
};
use super::input::{gunzip_prefix, read_regular_file};
use super::number::Scalar;
use super::options::ReadOptions;
use super::order::ComponentOrder;
use super::scalar::{self, ScalarVolume};
use super::tensor_field::{DatasetKind, Location, TensorArrayInfo, TensorField};
use crate::error::{LoadErrorKind, escape_for_error, escape_path};

type Res<T> = Result<T, LoadErrorKind>;
type Expand = fn(&[f64]) -> [f64; 9];

fn field(name: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.to_string(),
        message: message.into(),
    }
}

/// Whether `path` names a NRRD file by its extension.
pub fn is_nrrd_path(path: &Path) -> bool {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(ext.as_deref(), Some("nrrd" | "nhdr"))
}

/// What the tensor axis holds.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Symmetric,
    Masked,
    Full,
}

impl Kind {
    fn values(self) -> usize {
        match self {
            Kind::Symmetric => 6,
            Kind::Masked => 7,
            Kind::Full => 9,
        }
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Raw,
    Gzip,
    Ascii,
}

/// The header's fields, as text (the value after `: `).
struct Header<'a> {
    fields: Vec<(String, &'a str)>,
    /// Where the data begins when it is attached.
    data_start: usize,
}

impl<'a> Header<'a> {
    fn get(&self, key: &str) -> Option<&'a str> {
        self.fields.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
    }

    fn need(&self, key: &str) -> Res<&'a str> {
        self.get(key)
            .ok_or_else(|| field(key, "missing; the reader needs it"))
    }
}

fn parse_header(bytes: &[u8]) -> Res<Header<'_>> {
    if !bytes.starts_with(b"NRRD000") {
        return Err(LoadErrorKind::Malformed(
            "not a NRRD file (no 'NRRD000' magic)".into(),
        ));
    }
    let mut fields = Vec::new();
    let mut pos = 0;
    let mut first = true;
    loop {
        if pos >= bytes.len() {
            break;
        }
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |e| pos + e);
        let raw = &bytes[pos..end];
        pos = (end + 1).min(bytes.len());
        let line = std::str::from_utf8(raw)
            .map_err(|_| LoadErrorKind::Malformed("a header line is not UTF-8".into()))?
            .trim_end_matches('\r');
        if first {
            first = false;
            continue;
        }
        if line.is_empty() {
            break;
        }
        if line.starts_with('#') || line.contains(":=") {
            continue;
        }
        let Some((k, v)) = line.split_once(": ") else {
            return Err(LoadErrorKind::Malformed(format!(
                "header line '{}' is not 'field: value'",
                escape_for_error(line)
            )));
        };
        let key = k
            .trim()
            .to_ascii_lowercase()
            .replace("datafile", "data file");
        if fields.iter().any(|(f, _)| *f == key) {
            return Err(field(&key, "given twice"));
        }
        fields.push((key, v.trim()));
    }
    Ok(Header {
        fields,
        data_start: pos,
    })
}

fn number<T: std::str::FromStr>(key: &str, s: &str) -> Res<T> {
    s.parse()
        .map_err(|_| field(key, format!("'{}' is not a number", escape_for_error(s))))
}

/// `(a,b,c)` as a vector; `None` for `none`.
fn vector(key: &str, s: &str) -> Res<Option<Vector3<f64>>> {
    if s == "none" {
        return Ok(None);
    }
    let inner = s
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or_else(|| {
            field(
                key,
                format!("'{}' is not a vector (x,y,z)", escape_for_error(s)),
            )
        })?;
    let v: Vec<f64> = inner
        .split(',')
        .map(|x| number::<f64>(key, x.trim()))
        .collect::<Res<_>>()?;
    if v.len() != 3 || !v.iter().all(|x| x.is_finite()) {
        return Err(field(
            key,
            format!("'{}' is not a finite 3-vector", escape_for_error(s)),
        ));
    }
    Ok(Some(Vector3::new(v[0], v[1], v[2])))
}

fn vectors(key: &str, s: &str) -> Res<Vec<Option<Vector3<f64>>>> {
    s.split_whitespace().map(|w| vector(key, w)).collect()
}

/// Signs that take the file's space to RAS+, and the name of that space.
fn space_to_ras(h: &Header) -> Res<(Vector3<f64>, &'static str)> {
    let Some(s) = h.get("space") else {
        return Ok((Vector3::new(1.0, 1.0, 1.0), "unknown (as stored)"));
    };
    let code = match s.to_ascii_lowercase().as_str() {
        "right-anterior-superior" | "ras" => "RAS",
        "left-anterior-superior" | "las" => "LAS",
        "left-posterior-superior" | "lps" => "LPS",
        "scanner-xyz" | "3d-right-handed" | "3d-left-handed" => "scanner",
        _ => {
            return Err(field(
                "space",
                format!(
                    "'{}' is not a 3-D space this reader knows (RAS, LAS, LPS, scanner-xyz)",
                    escape_for_error(s)
                ),
            ));
        }
    };
    let sign = match code {
        "LAS" => Vector3::new(-1.0, 1.0, 1.0),
        "LPS" => Vector3::new(-1.0, -1.0, 1.0),
        _ => Vector3::new(1.0, 1.0, 1.0),
    };
    Ok((sign, if code == "scanner" { "scanner" } else { "RAS" }))
}

/// Read a NRRD tensor volume from the bytes of `path` (the header, with or without data).
pub fn parse(path: &Path, bytes: &[u8], opts: &ReadOptions) -> Res<TensorField> {
    let h = parse_header(bytes)?;
    let ty = match h.need("type")? {
        "float" | "float32" => Scalar::F32,
        "double" | "float64" => Scalar::F64,
        t => {
            return Err(field(
                "type",
                format!(
                    "'{}'; tensors are read as float or double",
                    escape_for_error(t)
                ),
            ));
        }
    };
    let dimension: usize = number("dimension", h.need("dimension")?)?;
    if dimension != 4 {
        return Err(field(
            "dimension",
            format!("{dimension}; a tensor volume has 4 axes (tensor, x, y, z)"),
        ));
    }
    let sizes = sizes(&h, 4)?;
    let kinds: Vec<&str> = h.need("kinds")?.split_whitespace().collect();
    if kinds.len() != 4 {
        return Err(field("kinds", "needs 4 kinds"));
    }
    let kind = match kinds[0] {
        "3D-symmetric-matrix" => Kind::Symmetric,
        "3D-masked-symmetric-matrix" => Kind::Masked,
        "3D-matrix" => Kind::Full,
        k => {
            return Err(field(
                "kinds",
                format!(
                    "'{}' on the first axis; tensors are 3D-symmetric-matrix, \
                     3D-masked-symmetric-matrix or 3D-matrix",
                    escape_for_error(k)
                ),
            ));
        }
    };
    if sizes[0] != kind.values() {
        return Err(field(
            "sizes",
            format!(
                "{} values per voxel; {} needs {}",
                sizes[0],
                kinds[0],
                kind.values()
            ),
        ));
    }
    let dims = [sizes[1], sizes[2], sizes[3]];
    let voxels = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| field("sizes", "the sizes overflow"))?;
    let count = voxels
        .checked_mul(kind.values())
        .ok_or_else(|| field("sizes", "the sizes overflow"))?;
    let encoding = encoding(&h)?;
    let big = big_endian(&h, encoding, ty)?;
    let data = payload(path, &h, bytes)?;
    let (data, start) = skip(&h, &data, encoding)?;
    let values = decode(data, encoding, ty, big, count, start)?;

    let (order, tensor_of): (&str, Expand) = match kind {
        Kind::Full => ("full", |c| std::array::from_fn(|i| c[i])),
        Kind::Symmetric => ("fsl", |c| ComponentOrder::Fsl.expand(c)),
        Kind::Masked => ("fsl", |c| ComponentOrder::Fsl.expand(&c[1..])),
    };
    let mut masked = 0;
    let mut tensors = Vec::with_capacity(voxels);
    for c in values.chunks_exact(kind.values()) {
        // A confidence below 0.5 (or none at all: NaN) drops the voxel, as Teem's tenGlyph
        // does; it is kept as a zero tensor so that the lattice stays whole.
        if kind == Kind::Masked && (c[0] < 0.5 || c[0].is_nan()) {
            masked += 1;
            tensors.push([0.0; 9]);
        } else {
            tensors.push(tensor_of(c));
        }
    }

    let Placement {
        a,
        linear,
        s,
        world,
        source,
    } = placement(&h, 1)?;

    let tensor_frame = opts.tensor_frame.unwrap_or(TensorFrame::World);
    let q = match tensor_frame {
        TensorFrame::World => {
            let m = match h.get("measurement frame") {
                Some(v) => {
                    let v = vectors("measurement frame", v)?;
                    let cols: Vec<Vector3<f64>> = v.iter().flatten().copied().collect();
                    if v.len() != 3 || cols.len() != 3 {
                        return Err(field("measurement frame", "needs three vectors"));
                    }
                    Matrix3::from_columns(&cols)
                }
                None => Matrix3::identity(),
            };
            s * m
        }
        f => tensor_rotation(f, &linear).ok_or_else(|| {
            field(
                "space directions",
                "singular: no rotation to take voxel-frame tensors to world",
            )
        })?,
    };
    let identity = q == Matrix3::identity();
    Ok(TensorField {
        format: "nrrd".into(),
        dataset: DatasetKind::ImageData,
        dims: Some(dims),
        points: voxels,
        cells: dims.iter().map(|d| d.saturating_sub(1)).product(),
        array: TensorArrayInfo {
            name: kinds[0].to_string(),
            components: kind.values(),
            location: Location::Point,
        },
        positions: lattice_positions(&a, dims),
        tensors,
        direction: (!identity).then(|| rows3(&q)),
        spacing: smallest_spacing(&linear, dims),
        meta: ReadMeta {
            layout: Some(Layout {
                order: order.into(),
                why: Why::File,
            }),
            frame: Some(FrameInfo {
                tensor_frame,
                world: world.into(),
                voxel_to_world: Some(rows4(&a)),
                source: source.into(),
            }),
            masked,
        },
    })
}

/// Read a NRRD scalar volume (`dimension: 3`, any integer or float `type`) from the bytes of
/// `path`, placed in RAS+ exactly as tensor volumes are.
pub fn parse_scalar(path: &Path, bytes: &[u8]) -> Res<ScalarVolume> {
    let h = parse_header(bytes)?;
    let dimension: usize = number("dimension", h.need("dimension")?)?;
    if dimension != 3 {
        let first = h
            .get("kinds")
            .and_then(|k| k.split_whitespace().next())
            .unwrap_or("");
        return Err(field(
            "dimension",
            if dimension == 4 && first.starts_with("3D-") && first.contains("matrix") {
                format!(
                    "4 axes, '{}' first: a tensor volume, not a scalar volume (3 axes)",
                    escape_for_error(first)
                )
            } else {
                format!("{dimension}; a scalar volume has 3 axes (x, y, z)")
            },
        ));
    }
    let t = h.need("type")?;
    let ty = Scalar::nrrd_named(t).ok_or_else(|| {
        field(
            "type",
            format!(
                "'{}'; scalar volumes are read as integer, float or double types",
                escape_for_error(t)
            ),
        )
    })?;
    let sizes = sizes(&h, 3)?;
    // A 3-D NRRD can be a 2-D colour or vector image (`kinds: 3-color space space`).
    if let Some(kinds) = h.get("kinds") {
        let kinds: Vec<&str> = kinds.split_whitespace().collect();
        if kinds.len() != 3 {
            return Err(field("kinds", "needs 3 kinds"));
        }
        if let Some((axis, k)) = kinds.iter().enumerate().find(|(_, k)| {
            !matches!(
                k.to_ascii_lowercase().as_str(),
                "domain" | "space" | "none" | "???"
            )
        }) {
            return Err(field(
                "kinds",
                format!(
                    "'{}' on axis {axis}: a scalar volume has three spatial axes (domain or space)",
                    escape_for_error(k)
                ),
            ));
        }
    }
    let dims = [sizes[0], sizes[1], sizes[2]];
    let voxels = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| field("sizes", "the sizes overflow"))?;
    let encoding = encoding(&h)?;
    let big = big_endian(&h, encoding, ty)?;
    let data = payload(path, &h, bytes)?;
    let (data, start) = skip(&h, &data, encoding)?;
    let values = decode(data, encoding, ty, big, voxels, start)?;
    let p = placement(&h, 0)?;
    scalar::checked(
        dims,
        values.into_iter().map(|v| v as f32).collect(),
        rows4(&p.a),
        p.source,
    )
}

/// The `n` sizes of `sizes`, all positive.
fn sizes(h: &Header, n: usize) -> Res<Vec<usize>> {
    let sizes: Vec<usize> = h
        .need("sizes")?
        .split_whitespace()
        .map(|s| number("sizes", s))
        .collect::<Res<_>>()?;
    if sizes.len() != n || sizes.contains(&0) {
        return Err(field("sizes", format!("needs {n} positive sizes")));
    }
    Ok(sizes)
}

/// The `encoding`, in any case (Teem writes `ASCII`).
fn encoding(h: &Header) -> Res<Encoding> {
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
fn big_endian(h: &Header, encoding: Encoding, ty: Scalar) -> Res<bool> {
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
fn payload<'a>(path: &Path, h: &Header, bytes: &'a [u8]) -> Res<Cow<'a, [u8]>> {
    match h.get("data file") {
        Some(name) => {
            if name.starts_with("LIST") || name.contains(' ') {
                return Err(field(
                    "data file",
                    "only a single data file is read (no LIST or file patterns)",
                ));
            }
            let dir = path.parent().unwrap_or(Path::new("."));
            let p = dir.join(name);
            read_regular_file(&p)
                .map(Cow::Owned)
                .map_err(|e| field("data file", format!("{}: {}", escape_path(&p), e)))
        }
        None => Ok(Cow::Borrowed(&bytes[h.data_start..])),
    }
}

/// Where the lattice is in the world.
struct Placement {
    /// Voxel to world (RAS+ unless the space is `scanner`).
    a: Matrix4<f64>,
    /// The linear part of `a`.
    linear: Matrix3<f64>,
    /// The signs taking the file's space to RAS+, as a diagonal matrix.
    s: Matrix3<f64>,
    world: &'static str,
    source: &'static str,
}

/// Geometry: space directions (or spacings), origin, then the space's signs to RAS+.
/// `leading` axes come before the three spatial ones (the tensor axis), with `none` for a
/// direction.
fn placement(h: &Header, leading: usize) -> Res<Placement> {
    let (sign, world) = space_to_ras(h)?;
    let s = Matrix3::from_diagonal(&sign);
    let (dirs, source) = match h.get("space directions") {
        Some(v) => {
            let v = vectors("space directions", v)?;
            if v.len() != leading + 3
                || v[..leading].iter().any(Option::is_some)
                || v[leading..].iter().any(Option::is_none)
            {
                return Err(field(
                    "space directions",
                    if leading == 0 {
                        "needs three vectors"
                    } else {
                        "needs 'none' for the tensor axis and three vectors"
                    },
                ));
            }
            let cols: Vec<Vector3<f64>> = v[leading..].iter().flatten().copied().collect();
            (Matrix3::from_columns(&cols), "space directions")
        }
        None => match h.get("spacings") {
            Some(sp) => {
                let sp: Vec<f64> = sp
                    .split_whitespace()
                    .skip(leading)
                    .map(|x| number("spacings", x))
                    .collect::<Res<_>>()?;
                if sp.len() != 3 || !sp.iter().all(|x| x.is_finite() && *x != 0.0) {
                    return Err(field("spacings", "needs three finite non-zero spacings"));
                }
                (
                    Matrix3::from_diagonal(&Vector3::new(sp[0], sp[1], sp[2])),
                    "spacings",
                )
            }
            None => (Matrix3::identity(), "none (unit voxels)"),
        },
    };
    let origin = match h.get("space origin") {
        Some(o) => vector("space origin", o)?
            .ok_or_else(|| field("space origin", "'none' is not an origin"))?,
        None => Vector3::zeros(),
    };
    let linear = s * dirs;
    let mut a = Matrix4::identity();
    a.fixed_view_mut::<3, 3>(0, 0).copy_from(&linear);
    a.fixed_view_mut::<3, 1>(0, 3).copy_from(&(s * origin));
    Ok(Placement {
        a,
        linear,
        s,
        world,
        source,
    })
}

impl Scalar {
    /// The type a `type` field names (every spelling the NRRD format allows; not `block`).
    fn nrrd_named(t: &str) -> Option<Scalar> {
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
enum Start {
    Here,
    /// After this many bytes of the inflated stream: Teem counts a gzip file's `byte skip`
    /// there (its `line skip` in the file).
    Inflated(usize),
    /// The values are the last bytes (`byte skip: -1`, raw data only).
    AtEnd,
}

/// The data after `line skip` lines and, unless it is compressed, `byte skip` bytes.
fn skip<'a>(h: &Header, mut data: &'a [u8], enc: Encoding) -> Res<(&'a [u8], Start)> {
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

fn decode(
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
        parse(path, bytes, &ReadOptions::default())
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
