//! Reading and holding tensor data: a [`TensorField`] is positions plus raw 3x3 tensors in file
//! order, with what is known about where they came from.

pub mod frame;
pub mod fsl_eigen;
pub mod input;
pub mod nifti;
pub mod nrrd;
pub(crate) mod number;
pub mod order;
pub mod scalar;
pub mod synthetic;
pub mod vtk;

pub use frame::{ReadMeta, TensorFrame};
pub use order::ComponentOrder;
pub use scalar::ScalarVolume;
pub use vtk::ReadOptions;

use std::path::Path;

use crate::error::LoadError;

/// Read a tensor field from a file, the reader picked by the name: FSL's eigen set
/// (`PREFIX_L1.nii.gz` .. `PREFIX_V3.nii.gz`, or `PREFIX`), `.nii` and `.nii.gz` NIfTI-1, `.nrrd`
/// and `.nhdr` NRRD, anything else VTK (whose format is then told by the content).
pub fn read_field(path: &Path, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    if let Some(set) = fsl_eigen::EigenSet::named_by(path) {
        fsl_eigen::read(&set, opts)
    } else if nifti::is_nifti_path(path) {
        vtk::guarded(path, || {
            let bytes = input::read_regular_file(path)?;
            nifti::parse(&bytes, opts)
        })
    } else if nrrd::is_nrrd_path(path) {
        vtk::guarded(path, || {
            let bytes = input::read_regular_file(path)?;
            nrrd::parse(path, &bytes, opts)
        })
    } else {
        vtk::read_field(path, opts)
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
    vtk::guarded(path, || {
        let bytes = input::read_regular_file(path)?;
        if nifti::is_nifti_path(path) {
            nifti::parse_scalar(&bytes)
        } else if nrrd::is_nrrd_path(path) {
            nrrd::parse_scalar(path, &bytes)
        } else {
            vtk::parse_scalar_bytes(&bytes)
        }
    })
}

use serde::Serialize;

/// Where a tensor array lives on the dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Location {
    Point,
    Cell,
}

impl Location {
    pub fn as_str(self) -> &'static str {
        match self {
            Location::Point => "point",
            Location::Cell => "cell",
        }
    }
}

/// The VTK dataset kind a field was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum DatasetKind {
    ImageData,
    RectilinearGrid,
    StructuredGrid,
    UnstructuredGrid,
    PolyData,
}

impl DatasetKind {
    pub fn as_str(self) -> &'static str {
        match self {
            DatasetKind::ImageData => "ImageData",
            DatasetKind::RectilinearGrid => "RectilinearGrid",
            DatasetKind::StructuredGrid => "StructuredGrid",
            DatasetKind::UnstructuredGrid => "UnstructuredGrid",
            DatasetKind::PolyData => "PolyData",
        }
    }
}

/// The tensor array that was picked.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct TensorArrayInfo {
    pub name: String,
    /// Values per tensor as stored in the file: 9 or 6; 7 for NRRD's masked tensors (the
    /// confidence first); 6 for an FSL eigen set (rebuilt symmetric).
    pub components: usize,
    pub location: Location,
}

/// A tensor field in file order.
///
/// `tensors[i]` is the i-th tensor exactly as stored (row-major 3x3; 6-component arrays expanded
/// with the chosen [`ComponentOrder`]), not yet symmetrised and not yet rotated into world space.
/// `positions[i]` is its world position (the point, or the cell centre for cell data).
#[derive(Debug, Clone)]
pub struct TensorField {
    /// Short name of the file format, e.g. `legacy-ascii`, `legacy-binary`, `vti`, `pvti`, `synthetic`.
    pub format: String,
    pub dataset: DatasetKind,
    /// Point dimensions of structured datasets (image, rectilinear, structured); `None` otherwise.
    pub dims: Option<[usize; 3]>,
    pub points: usize,
    pub cells: usize,
    pub array: TensorArrayInfo,
    pub positions: Vec<[f64; 3]>,
    pub tensors: Vec<[f64; 9]>,
    /// Image-data direction matrix (row-major, columns are the index axes in world space).
    /// Tensors are stored as in the file; world tensors are `R D Rᵀ`.
    pub direction: Option<[[f64; 3]; 3]>,
    /// The smallest grid spacing for structured data, used by `--scale auto`; `None` when the
    /// data has no lattice (then the median nearest-neighbour distance is used).
    pub spacing: Option<f64>,
    /// Layout, frames and masked voxels, as the reader found them.
    pub meta: ReadMeta,
}

impl TensorField {
    /// Samples: tensors, one position each (every reader checks that).
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The field without its tensors (freed), once they are in the glyphs: what the scene's
    /// staging reads after the eigendecomposition is the geometry (positions, lattice,
    /// direction, spacing), and dropping the largest array first keeps it from coexisting with
    /// the scene's instances (grid:256: 1.2 of 1.6 GB).
    pub fn into_geometry(mut self) -> Self {
        self.tensors = Vec::new();
        self
    }

    /// A field made in code: `tensors[i]` (row-major 3x3) at world position `positions[i]`, as
    /// unstructured points (no lattice: `--scale auto` fits glyphs to the median
    /// nearest-neighbour distance).
    pub fn from_points(positions: Vec<[f64; 3]>, tensors: Vec<[f64; 9]>) -> Self {
        assert_eq!(positions.len(), tensors.len(), "one position per tensor");
        Self {
            format: "in-memory".into(),
            dataset: DatasetKind::PolyData,
            dims: None,
            points: positions.len(),
            cells: 0,
            array: TensorArrayInfo {
                name: "tensors".into(),
                components: 9,
                location: Location::Point,
            },
            positions,
            tensors,
            direction: None,
            spacing: None,
            meta: ReadMeta::default(),
        }
    }

    /// Dimensions of the lattice the tensors sit on (points, or cells = points - 1 per axis),
    /// for slicing and strides; `None` for unstructured data.
    pub fn lattice_dims(&self) -> Option<[usize; 3]> {
        let d = self.dims?;
        match self.array.location {
            Location::Point => Some(d),
            Location::Cell => Some(d.map(|n| n.saturating_sub(1).max(1))),
        }
    }

    /// The tensor as it is in world space (direction matrix applied), still unsymmetrised.
    pub fn world_tensor(&self, i: usize) -> [f64; 9] {
        let t = self.tensors[i];
        match &self.direction {
            None => t,
            Some(r) => rotate_tensor(r, &t),
        }
    }
}

/// `R D Rᵀ` for row-major 3x3 matrices.
///
/// Entries beyond 1e100 (whose sums of products can overflow near f64::MAX) or below 1e-100
/// (whose products underflow) are rotated as an exactly rescaled copy.
pub fn rotate_tensor(r: &[[f64; 3]; 3], d: &[f64; 9]) -> [f64; 9] {
    use crate::tensor::eigen::mul_pow2;
    let m = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m > 0.0 && m.is_finite() && !(1e-100..=1e100).contains(&m) {
        let k = m.log2().floor() as i32;
        return rotate_unscaled(r, &d.map(|x| mul_pow2(x, -k))).map(|x| mul_pow2(x, k));
    }
    rotate_unscaled(r, d)
}

fn rotate_unscaled(r: &[[f64; 3]; 3], d: &[f64; 9]) -> [f64; 9] {
    let mut rd = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            rd[i][j] = (0..3).map(|k| r[i][k] * d[3 * k + j]).sum();
        }
    }
    let mut out = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            out[3 * i + j] = (0..3).map(|k| rd[i][k] * r[j][k]).sum();
        }
    }
    out
}
