//! A tensor field as the readers make it: positions plus raw 3x3 tensors in file order, the
//! dataset they came from, and the rotation that takes them to world.

use serde::Serialize;

use super::frame::{FrameInfo, ReadMeta};

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

/// Where a field's samples are: given one by one, or implied by a lattice (24 bytes a voxel
/// fewer: a 256³ lattice's positions were 400 MB).
#[derive(Debug, Clone, PartialEq)]
pub enum Positions {
    /// One world position each: unstructured data, rectilinear and structured grids, cell
    /// centres.
    Points(Vec<[f64; 3]>),
    /// The voxel centres of a lattice of `dims` voxels (x fastest), voxel (i, j, k) at
    /// `to_world` · (i, j, k, 1) (its rows: the first three of the voxel-to-world matrix).
    Lattice {
        dims: [usize; 3],
        to_world: [[f64; 4]; 3],
    },
}

impl Positions {
    /// The lattice of `dims` voxels placed by the 4x4 voxel-to-world matrix `a`.
    pub fn lattice(a: &nalgebra::Matrix4<f64>, dims: [usize; 3]) -> Self {
        Positions::Lattice {
            dims,
            to_world: std::array::from_fn(|r| std::array::from_fn(|c| a[(r, c)])),
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Positions::Points(p) => p.len(),
            Positions::Lattice { dims, .. } => dims.iter().product(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sample `i`'s world position (a lattice's in the same arithmetic as the readers used to
    /// store it, so that both agree to the bit).
    pub fn get(&self, i: usize) -> [f64; 3] {
        match self {
            Positions::Points(p) => p[i],
            Positions::Lattice { dims, to_world: a } => {
                let v = [
                    (i % dims[0]) as f64,
                    (i / dims[0] % dims[1]) as f64,
                    (i / dims[0] / dims[1]) as f64,
                ];
                std::array::from_fn(|r| a[r][0] * v[0] + a[r][1] * v[1] + a[r][2] * v[2] + a[r][3])
            }
        }
    }

    /// Every position, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = [f64; 3]> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Every position, stored (what a nearest-neighbour search needs).
    pub fn to_vec(&self) -> Vec<[f64; 3]> {
        match self {
            Positions::Points(p) => p.clone(),
            Positions::Lattice { .. } => self.iter().collect(),
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        match self {
            Positions::Points(p) => p.len() * 24,
            Positions::Lattice { .. } => 0,
        }
    }
}

/// A field's tensors (row-major 3x3, in file order), kept in the precision the file gives:
/// float32 where its values are float32 or narrower (36 bytes a tensor instead of 72), float64
/// where it carries float64 (or 32- and 64-bit integers).
#[derive(Debug, Clone, PartialEq)]
pub enum Tensors {
    F32(Vec<[f32; 9]>),
    F64(Vec<[f64; 9]>),
}

impl Default for Tensors {
    fn default() -> Self {
        Tensors::F64(Vec::new())
    }
}

impl Tensors {
    /// None yet, to be kept in float32 if `narrow`.
    pub fn new(narrow: bool) -> Self {
        if narrow {
            Tensors::F32(Vec::new())
        } else {
            Tensors::F64(Vec::new())
        }
    }

    /// `n` zero tensors, or an error instead of an allocation failure.
    pub(crate) fn zeros(n: usize, narrow: bool) -> Result<Self, crate::error::LoadErrorKind> {
        use crate::field::number::try_vec;
        Ok(if narrow {
            let mut v = try_vec(n)?;
            v.resize(n, [0.0f32; 9]);
            Tensors::F32(v)
        } else {
            let mut v = try_vec(n)?;
            v.resize(n, [0.0f64; 9]);
            Tensors::F64(v)
        })
    }

    pub fn len(&self) -> usize {
        match self {
            Tensors::F32(v) => v.len(),
            Tensors::F64(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Tensor `i`, as f64.
    pub fn get(&self, i: usize) -> [f64; 9] {
        match self {
            Tensors::F32(v) => v[i].map(f64::from),
            Tensors::F64(v) => v[i],
        }
    }

    /// Every tensor, in order, as f64.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = [f64; 9]> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Value `c` of tensor `i` set to `x` (rounded to float32 if kept so).
    pub fn set(&mut self, i: usize, c: usize, x: f64) {
        match self {
            Tensors::F32(v) => v[i][c] = x as f32,
            Tensors::F64(v) => v[i][c] = x,
        }
    }

    /// A tensor added at the end.
    pub fn push(&mut self, t: [f64; 9]) {
        match self {
            Tensors::F32(v) => v.push(t.map(|x| x as f32)),
            Tensors::F64(v) => v.push(t),
        }
    }

    /// Each tensor replaced by `f` of it (a 6-value layout expanded in place).
    pub fn map_in_place(&mut self, f: impl Fn([f64; 9]) -> [f64; 9]) {
        match self {
            Tensors::F32(v) => v
                .iter_mut()
                .for_each(|t| *t = f(t.map(f64::from)).map(|x| x as f32)),
            Tensors::F64(v) => v.iter_mut().for_each(|t| *t = f(*t)),
        }
    }

    /// The element type kept: `float32` or `float64`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Tensors::F32(_) => "float32",
            Tensors::F64(_) => "float64",
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        match self {
            Tensors::F32(v) => v.len() * 36,
            Tensors::F64(v) => v.len() * 72,
        }
    }
}

impl From<Vec<[f64; 9]>> for Tensors {
    fn from(v: Vec<[f64; 9]>) -> Self {
        Tensors::F64(v)
    }
}

/// A tensor field in file order.
///
/// [`Self::tensor`] `i` is the i-th tensor exactly as stored (row-major 3x3; 6-component arrays
/// expanded with the chosen [`ComponentOrder`]), not yet symmetrised and not yet rotated into
/// world space, kept in the file's precision ([`Tensors`]). [`Self::position`] `i` is its world
/// position (the point, or the cell centre for cell data; implied by a lattice, [`Positions`]).
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
    pub positions: Positions,
    pub tensors: Tensors,
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
    /// A lattice holding no tensors (a field of another kind's geometry: what the viewer
    /// slices and frames): `dims` voxels placed by `frame`, the kind's values described by
    /// `array`.
    pub fn lattice_only(
        format: &str,
        dims: [usize; 3],
        frame: &FrameInfo,
        array: TensorArrayInfo,
    ) -> Self {
        TensorField {
            format: format.into(),
            dataset: DatasetKind::ImageData,
            dims: Some(dims),
            points: dims.iter().product(),
            cells: 0,
            array,
            positions: Positions::Lattice {
                dims,
                to_world: {
                    let m = frame.voxel_to_world.unwrap_or_default();
                    [m[0], m[1], m[2]]
                },
            },
            tensors: Tensors::default(),
            direction: None,
            spacing: Some(frame.smallest_step()),
            meta: ReadMeta {
                frame: Some(frame.clone()),
                ..ReadMeta::default()
            },
        }
    }

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
        self.tensors = Tensors::default();
        self
    }

    /// Sample `i`'s world position.
    pub fn position(&self, i: usize) -> [f64; 3] {
        self.positions.get(i)
    }

    /// Tensor `i` as stored (row-major, file frame), as f64.
    pub fn tensor(&self, i: usize) -> [f64; 9] {
        self.tensors.get(i)
    }

    /// Bytes the positions and tensors hold (the rest is a few hundred bytes).
    pub fn bytes(&self) -> usize {
        self.positions.bytes() + self.tensors.bytes()
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
            positions: Positions::Points(positions),
            tensors: Tensors::F64(tensors),
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
        let t = self.tensors.get(i);
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
