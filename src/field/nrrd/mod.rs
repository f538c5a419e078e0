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
//! Scalar volumes ([`read_scalar`]: `dimension` 3, any integer or float `type`) share the
//! header, data and geometry code, so they land in the same RAS+ world as tensors.
//!
//! Layout: `header` (the header's fields and the numbers in them), `data` (the values: type,
//! encoding, skips, the detached data file), `space` (where the lattice is in RAS+); this
//! module assembles the tensor field and the scalar volume from them.

mod data;
mod header;
mod space;

use std::path::Path;

use nalgebra::{Matrix3, Vector3};

use crate::error::escape_for_error;
use crate::field::frame::{
    FrameInfo, Layout, ReadMeta, TensorFrame, Why, rows3, rows4, smallest_spacing, tensor_rotation,
};
use crate::field::inputs::{Input, Inputs};
use crate::field::number::Scalar;
use crate::field::options::ReadOptions;
use crate::field::order::ComponentOrder;
use crate::field::scalar::{self, ScalarVolume};
use crate::field::tensor_field::{
    DatasetKind, Location, Positions, TensorArrayInfo, TensorField, Tensors,
};
use data::{big_endian, decode, encoding, payload, skip};
use header::{Header, Res, field, header_end, number, parse_header, sizes, vectors};
use space::{Placement, placement};

type Expand = fn(&[f64]) -> [f64; 9];

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

/// The header of the NRRD file `input`, read no further than its first empty line (a detached
/// header's file is all header), and the file.
fn open_header<'a>(inputs: &'a Inputs, path: &Path) -> Res<(Header, Input<'a>)> {
    let input = inputs.open(path)?;
    let mut n: u64 = 1 << 16;
    let end = loop {
        let b = input.read_at(0, n)?;
        if !b.starts_with(b"NRRD000") && b.len() >= 7 {
            break b.len();
        }
        match header_end(&b) {
            Some(end) => break end,
            None if n >= input.len() => break b.len(),
            None => n = n.saturating_mul(4),
        }
    };
    let h = parse_header(&input.read_at(0, end as u64)?)?;
    Ok((h, input))
}

/// Read a NRRD tensor volume (`.nrrd`, or a `.nhdr` and its detached data file next to it)
/// from `inputs`.
/// The detached data file the NRRD header `path` names (a `.nhdr`'s `data file`), from its
/// header only; `None` when the data follows the header or the header cannot say.
pub(crate) fn data_file(inputs: &Inputs, path: &Path) -> Option<std::path::PathBuf> {
    let (h, _) = open_header(inputs, path).ok()?;
    Inputs::detached(path, h.get("data file")?.as_bytes())
        .ok()
        .map(|d| d.path)
}

pub fn read(inputs: &Inputs, path: &Path, opts: &ReadOptions) -> Res<TensorField> {
    let (h, input) = open_header(inputs, path)?;
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
    let region = payload(inputs, path, &h, input)?;
    let (region, start) = skip(&h, region, encoding)?;

    let (order, tensor_of): (&str, Expand) = match kind {
        Kind::Full => ("full", |c| std::array::from_fn(|i| c[i])),
        Kind::Symmetric => ("fsl", |c| ComponentOrder::Fsl.expand(c)),
        Kind::Masked => ("fsl", |c| ComponentOrder::Fsl.expand(&c[1..])),
    };
    let mut masked = 0;
    // Each voxel's values are gathered and expanded as they are decoded: the tensors are the
    // only copy of the data ever held, and grow with the values read, never ahead of them.
    let mut tensors = Tensors::new(ty.fits_f32());
    let per = kind.values();
    let mut c = [0.0f64; 9];
    let mut k = 0;
    decode(&region, encoding, ty, big, count, start, |x| {
        c[k] = x;
        k += 1;
        if k == per {
            k = 0;
            // A confidence below 0.5 (or none at all: NaN) drops the voxel, as Teem's tenGlyph
            // does; it is kept as a zero tensor so that the lattice stays whole.
            if kind == Kind::Masked && (c[0] < 0.5 || c[0].is_nan()) {
                masked += 1;
                tensors.push([0.0; 9]);
            } else {
                tensors.push(tensor_of(&c[..per]));
            }
        }
    })?;

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
                "singular or too extreme for a finite rotation: no rotation to take voxel-frame tensors to world",
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
        positions: Positions::lattice(&a, dims),
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
            ..Default::default()
        },
    })
}

/// Read a NRRD scalar volume (`dimension: 3`, any integer or float `type`) from `inputs`,
/// placed in RAS+ exactly as tensor volumes are. Values go straight to float32.
pub fn read_scalar(inputs: &Inputs, path: &Path) -> Res<ScalarVolume> {
    let (h, input) = open_header(inputs, path)?;
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
    let region = payload(inputs, path, &h, input)?;
    let (region, start) = skip(&h, region, encoding)?;
    let mut values = Vec::new();
    decode(&region, encoding, ty, big, voxels, start, |x| {
        values.push(x as f32)
    })?;
    let p = placement(&h, 0)?;
    scalar::checked(dims, values, rows4(&p.a), p.source)
}
