//! Reading and holding tensor data: a [`TensorField`] is positions plus raw 3x3 tensors in file
//! order, with what is known about where they came from.
//!
//! Imports go one way. This module is the top: [`read_field`] and [`read_scalar_volume`] pick
//! the reader by the file's name. The readers (`vtk`, `nifti`, `nrrd`, `fsl_eigen`) are below
//! it, and below them what they share: the [`TensorField`] they make, the [`ScalarVolume`]
//! (`scalar`), [`ReadOptions`], `frame`, `order`, `number`, [`Inputs`] (where every reader
//! gets its bytes, and the record of what it read) and `guard`. `synthetic`
//! makes fields in code, `array` of numbers handed over in memory (as the NIfTI reader would).

pub mod array;
pub mod frame;
pub mod fsl_eigen;
mod guard;
pub mod inputs;
pub mod nifti;
pub mod nrrd;
pub(crate) mod number;
mod options;
pub mod order;
pub mod scalar;
pub mod synthetic;
mod tensor_field;
pub mod vtk;

pub use frame::{ReadMeta, TensorFrame};
pub use inputs::Inputs;
pub use options::ReadOptions;
pub use order::ComponentOrder;
pub use scalar::ScalarVolume;
pub use tensor_field::{DatasetKind, Location, TensorArrayInfo, TensorField, rotate_tensor};

use std::path::Path;

use crate::error::LoadError;

/// Read a tensor field from a file, the reader picked by the name: FSL's eigen set
/// (`PREFIX_L1.nii.gz` .. `PREFIX_V3.nii.gz`, or `PREFIX`), `.nii` and `.nii.gz` NIfTI-1, `.nrrd`
/// and `.nhdr` NRRD, anything else VTK (whose format is then told by the content).
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
        guard::guarded(path, || {
            let bytes = inputs.read(path)?;
            nifti::parse(&bytes, opts)
        })
    } else if nrrd::is_nrrd_path(path) {
        guard::guarded(path, || {
            let bytes = inputs.read(path)?;
            nrrd::parse(inputs, path, &bytes, opts)
        })
    } else {
        vtk::read_field_from(inputs, path, opts)
    }
}

/// Read a 3-D scalar image (or a 4-D one holding a single volume), the reader picked by the
/// extension as for tensors: `.nii`/`.nii.gz` NIfTI-1 (uint8, int8, int16, uint16, int32,
/// uint32, int64, uint64, float32, float64; `scl_slope` and `scl_inter` applied), `.nrrd`/`.nhdr`
/// NRRD (the same types; `dimension: 3`), anything else VTK image data (`.vti`, or legacy
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
        let bytes = inputs.read(path)?;
        if nifti::is_nifti_path(path) {
            nifti::parse_scalar(&bytes)
        } else if nrrd::is_nrrd_path(path) {
            nrrd::parse_scalar(inputs, path, &bytes)
        } else {
            vtk::parse_scalar_bytes(&bytes)
        }
    })
}
