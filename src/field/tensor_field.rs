//! A tensor field as the readers make it: positions plus raw 3x3 tensors in file order, the
//! dataset they came from, and the rotation that takes them to world.

use serde::Serialize;

use super::frame::ReadMeta;

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
///
/// [`ComponentOrder`]: crate::field::ComponentOrder
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
