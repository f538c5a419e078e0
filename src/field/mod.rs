//! Reading and holding tensor data: a [`TensorField`] is positions plus raw 3x3 tensors in file
//! order, with what is known about where they came from.
//!
//! Imports go one way. This module is the top: [`read_field`] and [`read_scalar_volume`] pick
//! the reader by the file's name. The readers (`vtk`, `nifti`, `nrrd`, `mif`, `fsl_eigen`) are below
//! it, and below them what they share: the [`TensorField`] they make, the [`ScalarVolume`]
//! (`scalar`), [`ReadOptions`], `frame`, `order`, `number`, [`Inputs`] (where every reader
//! gets its bytes, and the record of what it read) and `guard`. `synthetic`
//! makes fields in code, `array` of numbers handed over in memory (as the NIfTI reader would).
//! [`read_sh_field`] reads spherical-harmonic coefficients (fibre ODFs) from NIfTI and MRtrix
//! images into an [`ShField`] (`sh_field`), and [`FieldKind::of_file`] (`kind`) tells such a file from tensors.

pub mod array;
pub mod bep016;
pub mod frame;
pub mod fsl_eigen;
mod guard;
pub mod gzip;
pub mod inputs;
pub mod kind;
pub mod mif;
pub mod nifti;
pub mod nrrd;
pub(crate) mod number;
mod options;
pub mod order;
pub mod peaks;
pub mod scalar;
pub mod sh_field;
pub mod synthetic;
mod tensor_field;
pub mod vtk;

pub use frame::{ReadMeta, TensorFrame};
pub use inputs::Inputs;
pub use kind::FieldKind;
pub use options::ReadOptions;
pub use order::ComponentOrder;
pub use peaks::PeakField;
pub use scalar::ScalarVolume;
pub use sh_field::{Coefficients, ShField, ShLayout};
pub use tensor_field::{
    DatasetKind, Location, Positions, TensorArrayInfo, TensorField, Tensors, rotate_tensor,
};

use std::path::Path;

use crate::error::LoadError;

/// Read a tensor field from a file, the reader picked by the name: FSL's eigen set
/// (`PREFIX_L1.nii.gz` .. `PREFIX_V3.nii.gz`, or `PREFIX`), `.nii` and `.nii.gz` NIfTI-1, `.nrrd`
/// and `.nhdr` NRRD, `.mif`, `.mif.gz` and `.mih` MRtrix, anything else VTK (whose format is
/// then told by the content).
pub fn read_field(path: &Path, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    read_field_from(&Inputs::file_system(), path, opts)
}

/// [`read_field`] of the file `path` among `inputs` (the file system or named buffers), which
/// record every file the reader opens: the file, its detached data, its pieces, its set.
pub fn read_field_from(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<TensorField, LoadError> {
    if let Some(set) = fsl_eigen::EigenSet::named_by(path, inputs) {
        fsl_eigen::read(inputs, &set, opts)
    } else if nifti::is_nifti_path(path) {
        guard::guarded(path, || read_nifti(inputs, path, opts))
    } else if nrrd::is_nrrd_path(path) {
        guard::guarded(path, || nrrd::read(inputs, path, opts))
    } else if mif::is_mif_path(path) {
        guard::guarded(path, || mif::read(inputs, path, opts))
    } else {
        vtk::read_field_from(inputs, path, opts)
    }
}

/// The files besides `path` itself that reading it will open, as far as its header says (a
/// `.mih`'s or `.nhdr`'s data file, the members of an FSL eigen set): so that a front end can
/// refuse an output over one of them before any work. Read in full, [`Inputs::paths_read`]
/// has every file (a `.pvti`'s pieces too).
pub fn companion_files(path: &Path) -> Vec<std::path::PathBuf> {
    let inputs = Inputs::file_system();
    if let Some(set) = fsl_eigen::EigenSet::named_by(path, &inputs) {
        return set.files();
    }
    let named = if nrrd::is_nrrd_path(path) {
        nrrd::data_file(&inputs, path)
    } else if mif::is_mif_path(path) {
        mif::data_file(&inputs, path)
    } else {
        None
    };
    named.into_iter().collect()
}

/// A NIfTI tensor file; a BEP016 map's frame and order from its sidecar, unless the options
/// say otherwise.
fn read_nifti(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<TensorField, crate::error::LoadErrorKind> {
    if !bep016::is_bep016_name(path) {
        return nifti::read(&inputs.open(path)?, opts);
    }
    // The map first, so that a missing map is told as such, not as a missing sidecar.
    let input = inputs.open(path)?;
    let d = bep016::decide(inputs, path);
    let sidecar_decides = d.frame.is_some();
    let given = ReadOptions {
        // Dxx Dxy Dxz Dyy Dyz Dzz, with or without a sidecar.
        order: opts.order.or(Some(ComponentOrder::Fsl)),
        tensor_frame: opts.tensor_frame.or(d.frame),
        ..opts.clone()
    };
    let mut field = nifti::read(&input, &given)?;
    if let Some(l) = &mut field.meta.layout
        && opts.order.is_none()
        && l.why == frame::Why::Flag
    {
        l.why = if sidecar_decides {
            frame::Why::Sidecar
        } else {
            frame::Why::Default
        };
    }
    field.meta.sidecar = Some(d.sidecar);
    field.meta.notes.extend(d.note);
    Ok(field)
}

/// Read a 3-D scalar image (or a 4-D one holding a single volume), the reader picked by the
/// extension as for tensors: `.nii`/`.nii.gz` NIfTI-1 (uint8, int8, int16, uint16, int32,
/// uint32, int64, uint64, float32, float64; `scl_slope` and `scl_inter` applied), `.nrrd`/`.nhdr`
/// NRRD (the same types; `dimension: 3`), `.mif`/`.mif.gz`/`.mih` MRtrix (the same types, any
/// `layout`; `scaling` applied), anything else VTK image data (`.vti`, or legacy
/// `STRUCTURED_POINTS`) with a one-component point-data array, the first one if there are
/// several.
///
/// Errors name the file and, where there is one, the header field: a tensor volume where a
/// scalar volume is expected, data shorter than the header says, a voxel-to-world matrix that
/// cannot be inverted. Memory is bounded as for tensors (nothing is allocated for data the bytes
/// cannot hold), and a panic inside a reader becomes an error.
pub fn read_scalar_volume(path: &Path) -> Result<ScalarVolume, LoadError> {
    read_scalar_volume_from(&Inputs::file_system(), path)
}

/// [`read_scalar_volume`] of the file `path` among `inputs`, which record what it read.
pub fn read_scalar_volume_from(inputs: &Inputs, path: &Path) -> Result<ScalarVolume, LoadError> {
    guard::guarded(path, || {
        if nifti::is_nifti_path(path) {
            nifti::read_scalar(&inputs.open(path)?)
        } else if nrrd::is_nrrd_path(path) {
            nrrd::read_scalar(inputs, path)
        } else if mif::is_mif_path(path) {
            mif::read_scalar(inputs, path)
        } else {
            vtk::parse_scalar_bytes(&inputs.read(path)?)
        }
    })
}

/// Every value of an MRtrix image (`.mif`, `.mif.gz`, `.mih`) whatever its number of values per
/// voxel ([`mif::read_volumes`]: spherical-harmonic coefficients, a DWI series), with the
/// readers' bounds, and a panic inside the reader as an error naming the file.
pub fn read_mif_volumes_from(inputs: &Inputs, path: &Path) -> Result<mif::Volumes, LoadError> {
    guard::guarded(path, || mif::read_volumes(inputs, path))
}

/// Read a volume of SH coefficients (a fibre ODF per voxel) from a NIfTI-1 file (`.nii`,
/// `.nii.gz`: DIPY's `shm_coeff`, MRtrix's) or an MRtrix image (`.mif`, `.mif.gz`, `.mih`:
/// `dwi2fod`). The count of values per voxel must be an SH count; the basis is
/// `opts.sh_basis`, else the writer's (`field::sh_field`). Errors name the file: a count that
/// is no SH count, data shorter than the header, a coefficient that is not finite.
pub fn read_sh_field(path: &Path, opts: &ReadOptions) -> Result<ShField, LoadError> {
    read_sh_field_from(&Inputs::file_system(), path, opts)
}

/// [`read_sh_field`] of the file `path` among `inputs`.
pub fn read_sh_field_from(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<ShField, LoadError> {
    guard::guarded(path, || {
        if nifti::is_nifti_path(path) {
            nifti::read_sh(&inputs.open(path)?, opts)
        } else if mif::is_mif_path(path) {
            mif::read_sh(inputs, path, opts)
        } else {
            Err(crate::error::LoadErrorKind::Other(
                "SH coefficients are read from NIfTI-1 (.nii, .nii.gz) and MRtrix images (.mif, .mif.gz, .mih)".into(),
            ))
        }
    })
}

/// Read the peaks file `path` among `inputs`: an MRtrix image whose header says `sh2peaks` wrote
/// it, or a NIfTI file of peaks (DIPY's `…dirs…` file takes its amplitudes from the `…values…`
/// file of the same name beside it, where there is one: `nifti::peaks::values_beside`).
pub fn read_peak_field_from(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<PeakField, LoadError> {
    if nifti::is_nifti_path(path) {
        let mut field =
            guard::guarded(path, || nifti::peaks::read_peaks(&inputs.open(path)?, opts))?;
        if let Some(values) = nifti::peaks::values_beside(inputs, path) {
            guard::guarded(&values, || {
                nifti::peaks::scale_by(&mut field, &inputs.open(&values)?)
            })?;
        }
        return Ok(field);
    }
    guard::guarded(path, || {
        if !mif::is_mif_path(path) {
            return Err(crate::error::LoadErrorKind::Other(
                "peaks are read from MRtrix images that sh2peaks wrote (.mif, .mif.gz, .mih) \
                 and from NIfTI files (.nii, .nii.gz)"
                    .into(),
            ));
        }
        mif::read_peaks(inputs, path, opts)
    })
}
