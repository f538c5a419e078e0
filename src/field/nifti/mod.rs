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
//! - 9 volumes (4-D, or 5-D with a 1 in the fourth place): full matrices, row-major, where the
//!   intent (GENMATRIX or SYMMATRIX) or `--holds tensors` says so; three fibre peaks
//!   (`sh2peaks`' layout) otherwise as likely, so nothing else is read (`peaks`).
//!
//! Tensors are taken to be in the voxel axes unless `--tensor-frame` says otherwise: FSL, DIPY
//! and ANTs (whose tensors ITK's direction matrix, the rotation of the qform, takes to world)
//! all store them so.
//!
//! Scalar volumes ([`read_scalar`]: FA maps, masks, anatomy) and FSL's eigen sets share the
//! header, data and affine code (`read_header`, `Header::voxels`), so they land in the
//! same world as tensors.
//!
//! SH coefficient volumes (`read_sh`: DIPY's `shm_coeff`, MRtrix's `dwi2fod` converted) share
//! them too; `descrip` tells MRtrix's files from the others (`field::sh_field`).
//!
//! Layout: `header` (the header: lattice, values per voxel, data type, voxel-to-world matrix),
//! `voxels` (the voxel data); this module makes tensor fields and scalar volumes of them.

mod header;
pub(crate) mod peaks;
mod voxels;

use std::path::Path;

use nalgebra::{Matrix3, Matrix4};
use nifti::NiftiHeader;

use crate::field::FieldKind;
use crate::field::frame::{
    FrameInfo, Layout, ReadMeta, TensorFrame, Why, rows3, rows4, smallest_spacing, tensor_rotation,
};
use crate::field::inputs::Input;
use crate::field::options::ReadOptions;
use crate::field::order::ComponentOrder;
use crate::field::scalar::{self, ScalarVolume};
use crate::field::sh_field::{self, Coefficients, ShField, Writer};
use crate::field::tensor_field::{
    DatasetKind, Location, Positions, TensorArrayInfo, TensorField, Tensors,
};
pub(crate) use header::{Header, read_header};
use header::{Res, Shape, Values, field, read_head};

const INTENT_GENMATRIX: i16 = 1004;
const INTENT_SYMMATRIX: i16 = 1005;

/// Read a NIfTI-1 tensor volume (gzip-compressed or not) from `input`.
pub fn read(input: &Input, opts: &ReadOptions) -> Res<TensorField> {
    let head = read_header(input, tensor_components)?;
    let (layout, expand) = layout(&head.h, &head.shape, opts)?;
    let affine = head.affine()?;
    let components = head.shape.components;
    // Each value goes straight into its voxel's matrix, which is then expanded in place: the
    // tensors are the only copy of the data ever held.
    // They grow with the values read (voxel after voxel of the first volume), never ahead of
    // them: a header asking for more than the data holds allocates nothing for it.
    let mut tensors = Tensors::new(head.shape.ty.fits_f32());
    head.each_value(input, |c, v, x| {
        if c == 0 {
            let mut t = [0.0; 9];
            t[0] = x;
            tensors.push(t);
        } else {
            tensors.set(v, c, x);
        }
    })?;
    tensors.map_in_place(|t| expand(&t[..components]));
    let array = TensorArrayInfo {
        name: "tensor".into(),
        components,
        location: Location::Point,
    };
    lattice_field(head.dims(), affine, opts, tensors, array, layout)
}

/// Read a NIfTI-1 scalar volume (3-D, or 4-D and up with one value per voxel) from `input`:
/// any integer or float datatype, `scl_slope` and `scl_inter` applied, placed in RAS by the
/// same sform/qform/pixdim rule as tensors. Values go straight to float32.
pub fn read_scalar(input: &Input) -> Res<ScalarVolume> {
    let head = read_head(input, Values::Scalar, |_| Ok(()))?;
    let (a, source) = head.affine()?;
    let values = head.values(input, |x| x as f32)?;
    scalar::checked(head.dims(), values, rows4(&a), source)
}

/// The field of `tensors` (file order, in the frame they were stored in) on a NIfTI lattice of
/// `dims` voxels placed by the affine `a` (from `source`): positions in world (RAS), and the
/// rotation that `--tensor-frame` (default `voxel`) takes the tensors to world with.
pub(crate) fn lattice_field(
    dims: [usize; 3],
    (a, source): (Matrix4<f64>, &'static str),
    opts: &ReadOptions,
    tensors: Tensors,
    array: TensorArrayInfo,
    layout: Layout,
) -> Res<TensorField> {
    let linear: Matrix3<f64> = a.fixed_view::<3, 3>(0, 0).into_owned();
    let tensor_frame = opts.tensor_frame.unwrap_or(TensorFrame::Voxel);
    let rotation = tensor_rotation(tensor_frame, &linear);
    if rotation.is_none() && tensor_frame != TensorFrame::World {
        return Err(field(
            source,
            "the voxel-to-world matrix is singular or not finite: no rotation to take voxel-frame tensors to world",
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
        positions: Positions::lattice(&a, dims),
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
            ..Default::default()
        },
    })
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
            format!(
                "{components} volumes per voxel; a tensor volume has 6 or 9{}",
                sh_field::tensor_hint(components)
            ),
        ));
    }
    Ok(())
}

type Expand = fn(&[f64]) -> [f64; 9];

/// The component order and the function expanding one voxel's numbers to a row-major matrix.
fn layout(h: &NiftiHeader, s: &Shape, opts: &ReadOptions) -> Res<(Layout, Expand)> {
    if s.components == 9 {
        nine_volumes(h, opts)?;
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

/// A 4-D file of 9 volumes is full 3×3 tensors or three fibre peaks (`sh2peaks`' layout,
/// which pipelines keep as NIfTI): read as tensors only where something says so, the header's
/// intent (a matrix) or `--holds tensors`; else refused in one line that names the option.
fn nine_volumes(h: &NiftiHeader, opts: &ReadOptions) -> Res<()> {
    let matrix = h.intent_code == INTENT_GENMATRIX || h.intent_code == INTENT_SYMMATRIX;
    if matrix || opts.holds == Some(FieldKind::Tensors) {
        return Ok(());
    }
    Err(field(
        "dim",
        "9 volumes per voxel: full 3×3 tensors or three fibre peaks (as sh2peaks writes \
         them), and the header does not say which: give --holds tensors or --holds peaks",
    ))
}

/// A file of 15 volumes is an lmax-4 SH series or five fibre peaks (DIPY's `peaks_dirs`, as its
/// workflows save it): read as SH only where something says so (`--holds series`, or the
/// basis named with `--sh-basis`); else refused in one line that names the options.
fn fifteen_volumes(count: usize, opts: &ReadOptions) -> Res<()> {
    if count != 15 || opts.sh_basis.is_some() || opts.holds == Some(FieldKind::Series) {
        return Ok(());
    }
    Err(field(
        "dim",
        "15 volumes per voxel: an lmax-4 SH series or five fibre peaks (as DIPY saves \
         peaks_dirs), and the header does not say which: give --holds series (or --sh-basis) \
         or --holds peaks",
    ))
}

/// Whether `path` names a NIfTI file by its extension.
pub fn is_nifti_path(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    name.ends_with(".nii") || name.ends_with(".nii.gz")
}

/// Who wrote a NIfTI file, as far as SH needs to know: MRtrix writes `MRtrix version: …` into
/// `descrip` (`mrconvert`, `dwi2fod`), which nothing else does.
pub(super) fn sh_writer(h: &NiftiHeader) -> Writer {
    if h.descrip.starts_with(b"MRtrix version") {
        Writer::MrtrixNifti
    } else {
        Writer::Other
    }
}

/// What deciding between SH and tensors needs of a NIfTI file (its header only): values per
/// voxel.
pub(crate) fn sh_probe(input: &Input) -> Res<usize> {
    Ok(read_head(input, Values::Series, |_| Ok(()))?
        .shape
        .components)
}

/// Read a NIfTI-1 volume of SH coefficients (4-D, coefficients along the fourth axis, or
/// 5-D `X×Y×Z×1×C`; any integer or float datatype) from `input`: the basis from `opts.sh_basis`, else
/// by the writer (MRtrix: tournier07; others: DIPY's descoteaux07-legacy), directions in
/// scanner axes for MRtrix's files and voxel axes for the others unless `opts.tensor_frame`
/// says otherwise. Kept in float32 unless the file's type is wider (float64, 32- and 64-bit
/// integers: [`fits_f32`](crate::field::number::Scalar::fits_f32)).
pub(crate) fn read_sh(input: &Input, opts: &ReadOptions) -> Res<ShField> {
    let head = read_head(input, Values::Series, |_| Ok(()))?;
    fifteen_volumes(head.shape.components, opts)?;
    let writer = sh_writer(&head.h);
    let layout = sh_field::layout(head.shape.components, writer, opts.sh_basis)?;
    let (a, source) = head.affine()?;
    // Volume after volume, as the file stores them and as the field keeps them.
    let coefficients = if head.shape.ty.fits_f32() {
        Coefficients::F32(head.values(input, |x| x as f32)?)
    } else {
        Coefficients::F64(head.values(input, |x| x)?)
    };
    sh_field::check_finite(&coefficients, head.dims())?;
    Ok(ShField {
        format: "nifti".into(),
        dims: head.dims(),
        layout,
        coefficients,
        frame: FrameInfo {
            tensor_frame: sh_field::direction_frame(writer, opts.tensor_frame),
            world: "RAS".into(),
            voxel_to_world: Some(rows4(&a)),
            source: source.into(),
        },
    })
}
