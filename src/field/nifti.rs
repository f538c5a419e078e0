//! NIfTI-1 tensor volumes (`.nii`, `.nii.gz`): FSL `dtifit --save_tensor`, MRtrix
//! `dwi2tensor`, DIPY/nibabel, ANTs/ITK.
//!
//! The `nifti` crate parses the 348-byte header and builds the sform/qform affines; the bytes
//! are ours: read whole through the bounded regular-file reader, inflated no further than the
//! header's dimensions need (and never further than the compressed size could hold), and the
//! voxel data is checked against the bytes present before anything is allocated for it. The
//! crate reads no NIfTI-2 (a 540-byte header): such a file is refused by its `sizeof_hdr`.
//!
//! Layouts (the file's own word wins, then `--order`, then the default):
//! - 5-D `X×Y×Z×1×6` with intent SYMMATRIX: NIfTI's lower triangle by rows `xx xy yy xz yz zz`
//!   ("file"). DIPY writes this, and so does ITK (hence ANTs) for its tensor images: it keeps
//!   them as the upper triangle `xx xy xz yy yz zz` in memory and reorders them on writing.
//! - 5-D `X×Y×Z×1×6` without that intent: `--order`, default `fsl` (`xx xy xz yy yz zz`). ITK
//!   writes 6-vector images (intent VECTOR) with their components unreordered, so tensors
//!   handled as vectors there come out in its upper-triangle order; DIPY sets the intent
//!   whenever it writes the lower triangle (and writes FSL's 4-D order otherwise).
//! - 4-D `X×Y×Z×6`: `--order`, default `fsl` (`xx xy xz yy yz zz`); MRtrix needs `--order mrtrix`;
//! - 9 volumes (4-D, or 5-D with a 1 in the fourth place): full matrices, row-major.
//!
//! Tensors are taken to be in the voxel axes unless `--tensor-frame` says otherwise: FSL, DIPY
//! and ANTs (whose tensors ITK's direction matrix, the rotation of the qform, takes to world)
//! all store them so.
//!
//! Scalar volumes ([`parse_scalar`]: FA maps, masks, anatomy) and FSL's eigen sets share the
//! header, data and affine code (`read_header`, `Header::voxels`), so they land in the
//! same world as tensors.

use std::borrow::Cow;
use std::io::Cursor;
use std::path::Path;

use nalgebra::{Matrix3, Matrix4};
use nifti::NiftiHeader;

use super::frame::{
    FrameInfo, Layout, ReadMeta, TensorFrame, Why, lattice_positions, rows3, rows4,
    smallest_spacing, tensor_rotation,
};
use super::number::Scalar;
use super::options::ReadOptions;
use super::order::ComponentOrder;
use super::scalar::{self, ScalarVolume};
use super::tensor_field::{DatasetKind, Location, TensorArrayInfo, TensorField};
use crate::error::LoadErrorKind;

type Res<T> = Result<T, LoadErrorKind>;

const HEADER_LEN: usize = 348;
/// The header plus the 4-byte extension flag of a single `.nii` file.
const MIN_OFFSET: u64 = 352;
const INTENT_SYMMATRIX: i16 = 1005;
const DT_UINT8: i16 = 2;
const DT_INT16: i16 = 4;
const DT_INT32: i16 = 8;
const DT_FLOAT32: i16 = 16;
const DT_FLOAT64: i16 = 64;
const DT_INT8: i16 = 256;
const DT_UINT16: i16 = 512;
const DT_UINT32: i16 = 768;
const DT_INT64: i16 = 1024;
const DT_UINT64: i16 = 1280;

fn field(name: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.to_string(),
        message: message.into(),
    }
}

/// Read a NIfTI-1 tensor volume from the file's bytes (gzip-compressed or not).
pub fn parse(bytes: &[u8], opts: &ReadOptions) -> Res<TensorField> {
    let head = read_header(bytes, tensor_components)?;
    let voxels = head.voxels(bytes)?;
    let (layout, expand) = layout(&head.h, &head.shape, opts)?;
    let affine = head.affine()?;
    let components = head.shape.components;
    let mut comps = vec![0.0f64; components];
    let mut tensors = Vec::with_capacity(head.shape.voxels);
    for v in 0..head.shape.voxels {
        for (c, out) in comps.iter_mut().enumerate() {
            *out = voxels.get(c, v);
        }
        tensors.push(expand(&comps));
    }
    let array = TensorArrayInfo {
        name: "tensor".into(),
        components,
        location: Location::Point,
    };
    lattice_field(head.dims(), affine, opts, tensors, array, layout)
}

/// Read a NIfTI-1 scalar volume (3-D, or 4-D and up with one value per voxel) from the file's
/// bytes: any integer or float datatype, `scl_slope` and `scl_inter` applied, placed in RAS by
/// the same sform/qform/pixdim rule as tensors.
pub fn parse_scalar(bytes: &[u8]) -> Res<ScalarVolume> {
    let head = read(bytes, Values::Scalar, |_| Ok(()))?;
    let voxels = head.voxels(bytes)?;
    let (a, source) = head.affine()?;
    let values = (0..head.shape.voxels)
        .map(|v| voxels.get(0, v) as f32)
        .collect();
    scalar::checked(head.dims(), values, rows4(&a), source)
}

/// What a caller reads from a NIfTI-1 file.
#[derive(Clone, Copy, PartialEq)]
enum Values {
    /// Tensors (and FSL's eigen maps): float32 or float64, the values of a voxel along the 4th
    /// dimension, or the 5th of an `X×Y×Z×1×C` file.
    Tensor,
    /// A scalar volume: any integer or float datatype, one value per voxel.
    Scalar,
}

/// A NIfTI-1 file's header and the lattice it gives, read before any voxel data is inflated.
pub(crate) struct Header {
    h: NiftiHeader,
    shape: Shape,
    gz: bool,
}

/// Read and check the header of a NIfTI-1 file from its bytes (gzip-compressed or not).
///
/// `check` is given the number of values per voxel (volumes of a 4-D file, the fifth
/// dimension of a 5-D one, 1 for a 3-D one) and refuses what its caller cannot use, before the
/// data type is looked at: a 3-D mask given as tensors is told as such, not as "uint8". The
/// values are float32 or float64, as tensors are.
pub(crate) fn read_header(bytes: &[u8], check: impl FnOnce(usize) -> Res<()>) -> Res<Header> {
    read(bytes, Values::Tensor, check)
}

/// [`read_header`] for tensors or for a scalar volume.
fn read(bytes: &[u8], values: Values, check: impl FnOnce(usize) -> Res<()>) -> Res<Header> {
    let gz = bytes.starts_with(&[0x1f, 0x8b]);
    let head: Cow<[u8]> = if gz {
        Cow::Owned(gunzip(bytes, MIN_OFFSET, "the header")?)
    } else {
        Cow::Borrowed(bytes)
    };
    let h = header(&head)?;
    let shape = Shape::of(&h, values, check)?;
    Ok(Header { h, shape, gz })
}

impl Header {
    pub(crate) fn dims(&self) -> [usize; 3] {
        self.shape.dims
    }

    /// The voxel-to-world matrix and the field it came from (`sform`, `qform` or `pixdim`).
    pub(crate) fn affine(&self) -> Res<(Matrix4<f64>, &'static str)> {
        affine(&self.h)
    }

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

/// The field of `tensors` (file order, in the frame they were stored in) on a NIfTI lattice of
/// `dims` voxels placed by the affine `a` (from `source`): positions in world (RAS), and the
/// rotation that `--tensor-frame` (default `voxel`) takes the tensors to world with.
pub(crate) fn lattice_field(
    dims: [usize; 3],
    (a, source): (Matrix4<f64>, &'static str),
    opts: &ReadOptions,
    tensors: Vec<[f64; 9]>,
    array: TensorArrayInfo,
    layout: Layout,
) -> Res<TensorField> {
    let linear: Matrix3<f64> = a.fixed_view::<3, 3>(0, 0).into_owned();
    let tensor_frame = opts.tensor_frame.unwrap_or(TensorFrame::Voxel);
    let rotation = tensor_rotation(tensor_frame, &linear);
    if rotation.is_none() && tensor_frame != TensorFrame::World {
        return Err(field(
            source,
            "the voxel-to-world matrix is singular: no rotation to take voxel-frame tensors to world",
        ));
    }
    let n = tensors.len();
    Ok(TensorField {
        format: "nifti".into(),
        dataset: DatasetKind::ImageData,
        dims: Some(dims),
        points: n,
        cells: dims.iter().map(|d| d.saturating_sub(1)).product(),
        array,
        positions: lattice_positions(&a, dims),
        tensors,
        direction: rotation.as_ref().map(rows3),
        spacing: smallest_spacing(&linear, dims),
        meta: ReadMeta {
            layout: Some(layout),
            frame: Some(FrameInfo {
                tensor_frame,
                world: "RAS".into(),
                voxel_to_world: Some(rows4(&a)),
                source: source.into(),
            }),
            masked: 0,
        },
    })
}

fn gunzip(bytes: &[u8], want: u64, what: &str) -> Res<Vec<u8>> {
    super::input::gunzip_prefix(bytes, want, what)
}

fn header(bytes: &[u8]) -> Res<NiftiHeader> {
    if bytes.len() < HEADER_LEN {
        return Err(LoadErrorKind::Malformed(format!(
            "a NIfTI header has {HEADER_LEN} bytes, the file holds {}",
            bytes.len()
        )));
    }
    let size = [
        i32::from_le_bytes(bytes[..4].try_into().unwrap_or_default()),
        i32::from_be_bytes(bytes[..4].try_into().unwrap_or_default()),
    ];
    if size.contains(&540) {
        return Err(field(
            "sizeof_hdr",
            "540: NIfTI-2 is not supported; convert it to NIfTI-1 \
             (nibabel's Nifti1Image.from_image, or mrconvert)",
        ));
    }
    let mut h = NiftiHeader::from_reader(Cursor::new(bytes)).map_err(|e| {
        LoadErrorKind::Malformed(format!(
            "not a NIfTI-1 header: {}",
            crate::error::escape_for_error(e.to_string())
        ))
    })?;
    if &h.magic != b"n+1\0" {
        return Err(field(
            "magic",
            format!(
                "'{}': only single-file NIfTI-1 ('n+1') is read",
                crate::error::escape_for_error(
                    h.magic
                        .iter()
                        .take_while(|b| **b != 0)
                        .copied()
                        .collect::<Vec<u8>>()
                )
            ),
        ));
    }
    // NIfTI readers treat any pixdim[0] other than -1 as 1 (the qform's handedness).
    h.fix();
    Ok(h)
}

/// The voxel lattice and how many numbers each voxel holds.
struct Shape {
    dims: [usize; 3],
    voxels: usize,
    components: usize,
    /// 5-D (`X×Y×Z×1×C`), the NIfTI way of storing vectors and matrices.
    five_d: bool,
    width: usize,
    ty: Scalar,
}

impl Shape {
    fn of(h: &NiftiHeader, values: Values, check: impl FnOnce(usize) -> Res<()>) -> Res<Self> {
        let d = axes(h)?;
        let nd = d.len();
        let at = |i: usize| d.get(i).copied().unwrap_or(1);
        let dims = [at(0), at(1), at(2)];
        let (components, five_d) = match values {
            Values::Tensor => match nd {
                1..=3 => (1, false),
                4 => (at(3), false),
                5 if at(3) == 1 => (at(4), true),
                5 => {
                    return Err(field(
                        "dim",
                        format!(
                            "5-D with {} time points: one tensor volume (X×Y×Z×1×6) is read",
                            at(3)
                        ),
                    ));
                }
                _ if d[3..].iter().all(|&x| x == 1) => (1, false),
                _ => return Err(field("dim", format!("{nd}-D data is not a tensor volume"))),
            },
            Values::Scalar => {
                let per_voxel = d
                    .iter()
                    .skip(3)
                    .try_fold(1usize, |a, &x| a.checked_mul(x))
                    .ok_or_else(|| field("dim", "the dimensions overflow"))?;
                if per_voxel != 1 {
                    return Err(field(
                        "dim",
                        match per_voxel {
                            6 | 9 => format!(
                                "{per_voxel} values per voxel: a tensor volume, not a scalar volume (one value per voxel)"
                            ),
                            n => format!(
                                "{n} values per voxel (dimensions {d:?}); a scalar volume has one"
                            ),
                        },
                    ));
                }
                (1, false)
            }
        };
        check(components)?;
        let t = h.datatype;
        let read = match values {
            Values::Tensor if t != DT_FLOAT32 && t != DT_FLOAT64 => None,
            _ => sample_type(t),
        };
        let ty = read.ok_or_else(|| {
            field(
                "datatype",
                format!(
                    "{t} ({}); {}",
                    type_name(t),
                    match values {
                        Values::Tensor => "tensors are read as float32 (16) or float64 (64)",
                        Values::Scalar => "scalar volumes are read as integers or float32/float64",
                    }
                ),
            )
        })?;
        let width = ty.size();
        check_bitpix(h, width)?;
        let voxels = dims
            .iter()
            .try_fold(1usize, |a, &x| a.checked_mul(x))
            .ok_or_else(|| field("dim", "the dimensions overflow"))?;
        Ok(Shape {
            dims,
            voxels,
            components,
            five_d,
            width,
            ty,
        })
    }
}

/// The sizes along the header's `dim[0]` axes, all positive.
fn axes(h: &NiftiHeader) -> Res<Vec<usize>> {
    let nd = h.dim[0];
    if !(1..=7).contains(&nd) {
        return Err(field("dim", format!("dim[0] = {nd} is not 1 to 7")));
    }
    let d: Vec<usize> = (1..=nd as usize).map(|i| h.dim[i] as usize).collect();
    if d.contains(&0) {
        return Err(field("dim", "a dimension is 0"));
    }
    Ok(d)
}

fn check_bitpix(h: &NiftiHeader, width: usize) -> Res<()> {
    if h.bitpix as usize != 8 * width {
        return Err(field(
            "bitpix",
            format!("{} does not match datatype {}", h.bitpix, h.datatype),
        ));
    }
    Ok(())
}

/// A tensor volume has 6 or 9 values per voxel.
fn tensor_components(components: usize) -> Res<()> {
    if components == 1 {
        return Err(field(
            "dim",
            "a scalar volume (one value per voxel), not tensors: a tensor volume has 6 or 9 volumes",
        ));
    }
    if components != 6 && components != 9 {
        return Err(field(
            "dim",
            format!("{components} volumes per voxel; a tensor volume has 6 or 9"),
        ));
    }
    Ok(())
}

fn type_name(t: i16) -> &'static str {
    match t {
        2 => "uint8",
        4 => "int16",
        8 => "int32",
        256 => "int8",
        512 => "uint16",
        768 => "uint32",
        1024 => "int64",
        1280 => "uint64",
        32 | 1792 | 2048 => "complex",
        128 | 2304 => "RGB",
        1536 => "float128",
        _ => "unknown",
    }
}

type Expand = fn(&[f64]) -> [f64; 9];

/// The component order and the function expanding one voxel's numbers to a row-major matrix.
fn layout(h: &NiftiHeader, s: &Shape, opts: &ReadOptions) -> Res<(Layout, Expand)> {
    if s.components == 9 {
        return Ok((Layout::full(), |c| std::array::from_fn(|i| c[i])));
    }
    let (order, why) = if s.five_d && h.intent_code == INTENT_SYMMATRIX {
        (ComponentOrder::Nifti, Why::File)
    } else if let Some(o) = opts.order {
        (o, Why::Flag)
    } else {
        // Only the SYMMATRIX intent says "lower triangle": ITK writes its tensors so (and
        // marks them), but a 6-vector image (intent VECTOR, or none) in its own upper-triangle
        // order, FSL's order too.
        (ComponentOrder::Fsl, Why::Default)
    };
    let expand: Expand = match order {
        ComponentOrder::Vtk => |c| ComponentOrder::Vtk.expand(c),
        ComponentOrder::Fsl => |c| ComponentOrder::Fsl.expand(c),
        ComponentOrder::Nifti => |c| ComponentOrder::Nifti.expand(c),
        ComponentOrder::Mrtrix => |c| ComponentOrder::Mrtrix.expand(c),
    };
    Ok((Layout::six(order, why), expand))
}

/// The voxel-to-world matrix and the field it came from: sform when its code is set, else
/// qform, else the voxel sizes alone (NIfTI's "method 1").
fn affine(h: &NiftiHeader) -> Res<(Matrix4<f64>, &'static str)> {
    let finite = |m: &Matrix4<f64>| m.iter().all(|x| x.is_finite());
    if h.sform_code > 0 {
        let a = h.sform_affine::<f64>();
        if !finite(&a) {
            return Err(field("srow_x", "the sform holds a non-finite number"));
        }
        return Ok((a, "sform"));
    }
    if h.qform_code > 0 {
        let p = &h.pixdim[1..4];
        let q = [h.quatern_b, h.quatern_c, h.quatern_d];
        if p.iter().any(|x| !x.is_finite() || *x < 0.0) || q.iter().any(|x| !x.is_finite()) {
            return Err(field(
                "pixdim",
                "the qform needs finite, non-negative voxel sizes and quaternion",
            ));
        }
        // Its quaternion's (b, c, d) must fit in a unit quaternion; the crate panics past
        // float32 rounding (as nibabel refuses), so that is refused here first.
        let bcd: f64 = q.iter().map(|x| (*x as f64).powi(2)).sum();
        if 1.0 - bcd < -2.0 * f32::EPSILON as f64 {
            return Err(field(
                "quatern_b",
                format!("b² + c² + d² = {bcd} is more than 1: the qform is not a rotation"),
            ));
        }
        let a = h.qform_affine::<f64>();
        if !finite(&a) {
            return Err(field("quatern_b", "the qform is not a rotation"));
        }
        return Ok((a, "qform"));
    }
    let size = |i: usize| {
        let s = h.pixdim[i].abs() as f64;
        if s > 0.0 && s.is_finite() { s } else { 1.0 }
    };
    let mut a = Matrix4::identity();
    for i in 0..3 {
        a[(i, i)] = size(i + 1);
    }
    Ok((a, "pixdim"))
}

/// The element type of a NIfTI datatype, for the integers and the floats (not complex, RGB or
/// float128).
fn sample_type(datatype: i16) -> Option<Scalar> {
    Some(match datatype {
        DT_UINT8 => Scalar::U8,
        DT_INT8 => Scalar::I8,
        DT_INT16 => Scalar::I16,
        DT_UINT16 => Scalar::U16,
        DT_INT32 => Scalar::I32,
        DT_UINT32 => Scalar::U32,
        DT_INT64 => Scalar::I64,
        DT_UINT64 => Scalar::U64,
        DT_FLOAT32 => Scalar::F32,
        DT_FLOAT64 => Scalar::F64,
        _ => return None,
    })
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

/// Whether `path` names a NIfTI file by its extension.
pub fn is_nifti_path(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    name.ends_with(".nii") || name.ends_with(".nii.gz")
}
