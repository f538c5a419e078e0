//! What a caller may tell the tensor readers (VTK, NIfTI, NRRD, FSL's eigen sets) and the SH
//! readers (NIfTI, MRtrix) that the file does not say.

use super::FieldKind;
use super::frame::TensorFrame;
use super::order::ComponentOrder;
use crate::sh::ShBasis;

/// How to read a tensor file (VTK, NIfTI).
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    /// Tensor array to read, by name (VTK). `None`: the active tensors, else the first 9- or
    /// 6-component point array, else the first such cell array.
    pub array: Option<String>,
    /// Component order of 6-component arrays where the file does not say; `None`: the
    /// format's default (VTK: `vtk`; NIfTI: `fsl`, unless a 5-D file has intent SYMMATRIX).
    pub order: Option<ComponentOrder>,
    /// The axes the stored tensors are in; `None`: the format's default (NIfTI: `voxel`).
    /// VTK files are read as before: image data tensors rotated by the image's `Direction`.
    pub tensor_frame: Option<TensorFrame>,
    /// The basis of SH coefficients (`--sh-basis`); given, it also makes a file of any SH count
    /// (6 included) SH rather than tensors. `None`: the writer's (`field::sh_field`).
    pub sh_basis: Option<ShBasis>,
    /// What the file holds where its header does not say (`--holds`): a NIfTI file of 9
    /// volumes is full 3×3 tensors or three fibre peaks. Given, it is taken over the header's
    /// guess ([`FieldKind::of_file`]).
    pub holds: Option<FieldKind>,
}
