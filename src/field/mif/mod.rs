//! MRtrix3's own image format: `.mif` (header and data in one file), `.mif.gz` (the same,
//! gzip-compressed) and `.mih` (header, with the data in the file it names), as MRtrix users
//! keep their images (`dwi2tensor`, `dwi2fod` write it).
//!
//! A strict reader of our own, held to the NIfTI and NRRD readers' standard: the header is
//! read up to its `END` line and no further, every value the header asks for is checked to be
//! in the file before anything is allocated for it (a `.mif.gz` is inflated within its budget,
//! [`crate::field::gzip`]), and a detached data file is read only if it is a regular file
//! in the header's folder or below it ([`Inputs::detached`]).
//!
//! Read: any `dim` (spatial axes first, as MRtrix has them), any `layout` (the order and
//! direction in which the axes are stored: values go to their voxel and volume whatever it
//! is), the integer and float `datatype`s in either byte order (`Bit` and the complex types
//! are refused), `scaling` (of integer data: MRtrix 3.0.3 reads float data as stored), and
//! `transform`, MRtrix's scanner-space (RAS, as NIfTI) placement of the image axes, to which
//! the voxel sizes of `vox` are applied. Positions are the voxel centres in that space.
//!
//! Tensors (`dwi2tensor`): 4-D with 6 volumes in MRtrix's order D11 D22 D33 D12 D13 D23 and in
//! scanner axes, so the defaults are `--order mrtrix` and `--tensor-frame world`; 9 volumes are
//! full matrices, row-major. Scalar volumes ([`read_scalar`]: underlays and masks) and volumes
//! of many values per voxel ([`read_volumes`]: spherical-harmonic coefficients, a DWI series)
//! share the header, data and placement code, so they land in the same world as tensors.
//!
//! SH coefficients (`read_sh`: `dwi2fod`) are read into an [`ShField`] in MRtrix's basis,
//! tournier07, their directions in scanner axes.
//!
//! Layout: `header` (the text and the image it describes), `data` (the values: where they
//! are, and which voxel and volume each stored value belongs to).

mod data;
mod header;

use std::path::Path;

use crate::field::frame::{FrameInfo, Layout, TensorFrame, Why, rows4};
use crate::field::inputs::Inputs;
use crate::field::nifti::lattice_field;
use crate::field::number::try_vec;
use crate::field::options::ReadOptions;
use crate::field::order::ComponentOrder;
use crate::field::peaks::PeakField;
use crate::field::scalar::{self, ScalarVolume};
use crate::field::sh_field::{self, Coefficients, ShField, Writer};
use crate::field::tensor_field::{Location, TensorArrayInfo, TensorField, Tensors};
use header::{Header, Res, field, read_header};

/// Whether `path` names an MRtrix image by its extension (`.mif`, `.mif.gz`, `.mih`).
pub fn is_mif_path(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    name.ends_with(".mif") || name.ends_with(".mif.gz") || name.ends_with(".mih")
}

/// Read an MRtrix tensor image (6 or 9 volumes) from `path` among `inputs`.
pub fn read(inputs: &Inputs, path: &Path, opts: &ReadOptions) -> Res<TensorField> {
    let input = inputs.open(path)?;
    let h = read_header(&input)?;
    let components = tensor_components(&h)?;
    let affine = h.affine()?;
    let (layout, order) = layout(components, opts);
    let values = data::locate(inputs, path, &input, &h)?;
    let voxels = h.dims().iter().product::<usize>();
    // Known to be in the file (`locate`): allocated only now, in the file's precision.
    let mut tensors = Tensors::zeros(voxels, h.ty.fits_f32())?;
    values.each(&h, |c, v, x| tensors.set(v, c, x))?;
    if let Some(order) = order {
        tensors.map_in_place(|t| order.expand(&t[..6]));
    }
    let array = TensorArrayInfo {
        name: "tensor".into(),
        components,
        location: Location::Point,
    };
    let given = ReadOptions {
        // Scanner axes: what dwi2tensor writes.
        tensor_frame: Some(opts.tensor_frame.unwrap_or(TensorFrame::World)),
        ..opts.clone()
    };
    let mut f = lattice_field(h.dims(), affine, &given, tensors, array, layout)?;
    f.format = "mif".into();
    Ok(f)
}

/// 6 or 9 values per voxel along the fourth axis (any further axes of size 1).
fn tensor_components(h: &Header) -> Res<usize> {
    let n = h.per_voxel()?;
    if h.peaks {
        // Its 6 or 9 volumes are 2 or 3 peaks, not a tensor.
        return Err(field(
            "command_history",
            format!(
                "written by MRtrix's sh2peaks: fibre directions ({n} values, 3 a peak), not \
                 tensors"
            ),
        ));
    }
    if n == 1 {
        return Err(field(
            "dim",
            "a scalar volume (one value per voxel), not tensors: a tensor image has 6 or 9 volumes",
        ));
    }
    if n != 6 && n != 9 || h.axes.len() > 4 && h.axes[4..].iter().any(|a| a.size != 1) {
        return Err(field(
            "dim",
            format!(
                "{n} values per voxel over {} axes; a tensor image has 6 or 9 volumes on its fourth{}",
                h.axes.len(),
                sh_field::tensor_hint(n)
            ),
        ));
    }
    Ok(n)
}

/// The component order (`None`: nine values, row-major) and where it came from.
fn layout(components: usize, opts: &ReadOptions) -> (Layout, Option<ComponentOrder>) {
    if components == 9 {
        return (Layout::full(), None);
    }
    let (order, why) = match opts.order {
        Some(o) => (o, Why::Flag),
        None => (ComponentOrder::Mrtrix, Why::Default),
    };
    (Layout::six(order, why), Some(order))
}

/// Read an MRtrix scalar image (3-D, or with size-1 axes past the third) from `path` among
/// `inputs`: any integer or float datatype, `scaling` applied, placed as tensors are. Values
/// go straight to float32.
pub fn read_scalar(inputs: &Inputs, path: &Path) -> Res<ScalarVolume> {
    let v = read_volumes(inputs, path)?;
    if v.volumes != 1 {
        return Err(field(
            "dim",
            match v.volumes {
                6 | 9 => format!(
                    "{} values per voxel: a tensor image, not a scalar volume (one value per voxel)",
                    v.volumes
                ),
                n => format!("{n} values per voxel; a scalar volume has one"),
            },
        ));
    }
    scalar::checked(v.dims, v.values, v.voxel_to_world, v.source)
}

/// An image of any number of values per voxel (volumes), placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct Volumes {
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// Values per voxel: the product of the sizes past the third axis.
    pub volumes: usize,
    /// `dims` voxels of `volumes` values each, a voxel's values together, voxels i fastest.
    pub values: Vec<f32>,
    /// Rows of the 4x4 matrix taking (i, j, k, 1) to world (x, y, z, 1): voxel centres.
    pub voxel_to_world: [[f64; 4]; 4],
    /// Where the matrix came from: `transform`, or MRtrix's default without one.
    pub source: &'static str,
}

/// Read every value of an MRtrix image from `path` among `inputs`, whatever its number of
/// values per voxel (the SH coefficients of `dwi2fod`, a DWI series): as [`read_scalar`] reads
/// one. The header's sizes are checked against the bytes present before anything is
/// allocated.
pub fn read_volumes(inputs: &Inputs, path: &Path) -> Res<Volumes> {
    let input = inputs.open(path)?;
    let h = read_header(&input)?;
    let volumes = h.per_voxel()?;
    let (a, source) = h.affine()?;
    let values = data::locate(inputs, path, &input, &h)?;
    let n = h.dims().iter().product::<usize>() * volumes;
    let mut out: Vec<f32> = try_vec(n)?;
    out.resize(n, 0.0);
    values.each(&h, |c, v, x| out[v * volumes + c] = x as f32)?;
    Ok(Volumes {
        dims: h.dims(),
        volumes,
        values: out,
        voxel_to_world: rows4(&a),
        source,
    })
}

/// The detached data file the MRtrix header `path` names (a `.mih`'s), from its header only;
/// `None` when the data is in the file itself or the header cannot say.
pub(crate) fn data_file(inputs: &Inputs, path: &Path) -> Option<std::path::PathBuf> {
    let input = inputs.open(path).ok()?;
    match read_header(&input).ok()?.data {
        header::DataFile::Detached(name, _) => Inputs::detached(path, &name).ok().map(|d| d.path),
        header::DataFile::Same(_) => None,
    }
}

/// What deciding an MRtrix image's field kind needs (its header only).
pub(crate) struct KindProbe {
    /// Values per voxel.
    pub count: usize,
    /// A DWI series (`dw_scheme`).
    pub dwi: bool,
    /// `sh2peaks` wrote it (its `command_history`).
    pub peaks: bool,
}

/// [`KindProbe`] of the image `path` among `inputs`.
pub(crate) fn kind_probe(inputs: &Inputs, path: &Path) -> Res<KindProbe> {
    let input = inputs.open(path)?;
    let h = read_header(&input)?;
    Ok(KindProbe {
        count: h.per_voxel()?,
        dwi: h.dw_scheme,
        peaks: h.peaks,
    })
}

/// Read an MRtrix image of SH coefficients (`dwi2fod`'s output) from `path` among `inputs`:
/// tournier07 unless `opts.sh_basis` says otherwise, directions in scanner axes unless
/// `opts.tensor_frame` does. Kept in float32 unless the file's type is wider (float64, 32- and
/// 64-bit integers: [`fits_f32`](crate::field::number::Scalar::fits_f32)).
pub(crate) fn read_sh(inputs: &Inputs, path: &Path, opts: &ReadOptions) -> Res<ShField> {
    let input = inputs.open(path)?;
    let h = read_header(&input)?;
    let count = h.per_voxel()?;
    let layout = sh_field::layout(count, Writer::MrtrixImage, opts.sh_basis)?;
    let (a, source) = h.affine()?;
    let values = data::locate(inputs, path, &input, &h)?;
    let voxels = h.dims().iter().product::<usize>();
    // Known to be in the file (`locate`): allocated only now.
    let n = voxels * count;
    let coefficients = if h.ty.fits_f32() {
        let mut out: Vec<f32> = try_vec(n)?;
        out.resize(n, 0.0);
        values.each(&h, |c, v, x| out[c * voxels + v] = x as f32)?;
        Coefficients::F32(out)
    } else {
        let mut out: Vec<f64> = try_vec(n)?;
        out.resize(n, 0.0);
        values.each(&h, |c, v, x| out[c * voxels + v] = x)?;
        Coefficients::F64(out)
    };
    sh_field::check_finite(&coefficients, h.dims())?;
    Ok(ShField {
        format: "mif".into(),
        dims: h.dims(),
        layout,
        coefficients,
        frame: FrameInfo {
            tensor_frame: sh_field::direction_frame(Writer::MrtrixImage, opts.tensor_frame),
            world: "RAS".into(),
            voxel_to_world: Some(rows4(&a)),
            source: source.into(),
        },
    })
}

/// Read an image `sh2peaks` wrote (its header's `command_history` says so,
/// [`crate::field::FieldKind::of_file`]): 3 values a peak along the fourth axis, in scanner
/// axes.
pub(crate) fn read_peaks(inputs: &Inputs, path: &Path, opts: &ReadOptions) -> Res<PeakField> {
    if let Some(f) = opts.tensor_frame.filter(|f| *f != TensorFrame::World) {
        return Err(crate::error::LoadErrorKind::Other(format!(
            "--tensor-frame {f}: sh2peaks writes its directions in scanner axes (world)"
        )));
    }
    let v = read_volumes(inputs, path)?;
    if v.volumes % 3 != 0 || v.volumes == 0 {
        return Err(field(
            "dim",
            format!(
                "{} values per voxel: peaks take 3 each (sh2peaks writes 3 per peak)",
                v.volumes
            ),
        ));
    }
    let vectors = v
        .values
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok(PeakField {
        format: "mif".into(),
        dims: v.dims,
        per_voxel: v.volumes / 3,
        vectors,
        frame: FrameInfo {
            tensor_frame: TensorFrame::World,
            world: "RAS".into(),
            voxel_to_world: Some(v.voxel_to_world),
            source: v.source.into(),
        },
    })
}
