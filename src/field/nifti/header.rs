//! A NIfTI-1 file's 348-byte header, parsed by the `nifti` crate and checked here: the lattice
//! and the values per voxel, the data type, and the voxel-to-world matrix (sform, qform or
//! pixdim).

use std::borrow::Cow;
use std::io::Cursor;

use nalgebra::Matrix4;
use nifti::NiftiHeader;

use crate::error::LoadErrorKind;
use crate::field::gzip::is_gzip;
use crate::field::inputs::Input;
use crate::field::number::Scalar;

pub(super) type Res<T> = Result<T, LoadErrorKind>;

const HEADER_LEN: usize = 348;
/// The header plus the 4-byte extension flag of a single `.nii` file.
pub(super) const MIN_OFFSET: u64 = 352;
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

pub(super) fn field(name: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.to_string(),
        message: message.into(),
    }
}

/// What a caller reads from a NIfTI-1 file.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Values {
    /// Tensors (and FSL's eigen maps): float32 or float64, the values of a voxel along the 4th
    /// dimension, or the 5th of an `X×Y×Z×1×C` file.
    Tensor,
    /// A scalar volume: any integer or float datatype, one value per voxel.
    Scalar,
    /// Series of spherical-harmonic coefficients: laid out as tensors are, of any integer or
    /// float datatype (MRtrix reads an integer image of them, `scl_slope` applied).
    Series,
    /// Fibre peaks: 3 values a peak along the 4th dimension (`sh2peaks`' layout), or DIPY's
    /// `X×Y×Z×N×3` (the peaks along the 4th, their 3 values along the 5th); any datatype.
    Peaks,
}

/// A NIfTI-1 file's header and the lattice it gives, read before any voxel data is inflated.
pub(crate) struct Header {
    pub(super) h: NiftiHeader,
    pub(super) shape: Shape,
    pub(super) gz: bool,
}

/// Read and check the header of a NIfTI-1 file (gzip-compressed or not): its first 352 bytes,
/// nothing more.
///
/// `check` is given the number of values per voxel (volumes of a 4-D file, the fifth
/// dimension of a 5-D one, 1 for a 3-D one) and refuses what its caller cannot use, before the
/// data type is looked at: a 3-D mask given as tensors is told as such, not as "uint8". The
/// values are float32 or float64, as tensors are.
pub(crate) fn read_header(input: &Input, check: impl FnOnce(usize) -> Res<()>) -> Res<Header> {
    read_head(input, Values::Tensor, check)
}

/// [`read_header`] for tensors or for a scalar volume.
pub(super) fn read_head(
    input: &Input,
    values: Values,
    check: impl FnOnce(usize) -> Res<()>,
) -> Res<Header> {
    let gz = is_gzip(&input.read_at(0, 2)?);
    let head: Cow<[u8]> = if gz {
        let mut g = input.gunzip(0, "the header")?;
        g.need(MIN_OFFSET)?;
        let mut b = vec![0u8; MIN_OFFSET as usize];
        let n = g.fill(&mut b)?;
        b.truncate(n);
        Cow::Owned(b)
    } else {
        input.read_at(0, MIN_OFFSET)?
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
pub(super) struct Shape {
    pub(super) dims: [usize; 3],
    pub(super) voxels: usize,
    pub(super) components: usize,
    /// 5-D (`X×Y×Z×1×C`), the NIfTI way of storing vectors and matrices.
    pub(super) five_d: bool,
    /// Peaks laid out as DIPY's `X×Y×Z×N×3` (N > 1): value `k` of peak `p` is volume
    /// `p + N k`, not `3 p + k`.
    pub(super) peak_axis: bool,
    pub(super) width: usize,
    pub(super) ty: Scalar,
}

impl Shape {
    fn of(h: &NiftiHeader, values: Values, check: impl FnOnce(usize) -> Res<()>) -> Res<Self> {
        let d = axes(h)?;
        let nd = d.len();
        let at = |i: usize| d.get(i).copied().unwrap_or(1);
        let dims = [at(0), at(1), at(2)];
        let peak_axis = values == Values::Peaks && nd == 5 && at(3) > 1 && at(4) == 3;
        let (components, five_d) = match values {
            Values::Peaks if peak_axis => (at(3) * 3, true),
            Values::Tensor | Values::Series | Values::Peaks => match nd {
                1..=3 => (1, false),
                4 => (at(3), false),
                5 if at(3) == 1 => (at(4), true),
                5 if values == Values::Peaks => {
                    return Err(field(
                        "dim",
                        format!(
                            "5-D with {} × {} values per voxel: peaks are X×Y×Z×N×3 (DIPY's) \
                             or 3 values a peak along the fourth axis",
                            at(3),
                            at(4)
                        ),
                    ));
                }
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
                        Values::Scalar | Values::Series | Values::Peaks => {
                            "read are the integer types, float32 and float64"
                        }
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
            peak_axis,
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
