//! VTK reading: legacy `.vtk` (ASCII and binary, 4.2 and 5.1), XML `.vti/.vtr/.vts/.vtu/.vtp`
//! and parallel `.pvti`, into a [`TensorField`].
//!
//! The parsers here are our own, strict and allocation-safe: every count is checked against the
//! bytes actually present before anything is allocated, and only the picked tensor array (plus
//! the geometry) is decoded. `vtkio` 0.7.0-rc2 is not used for reading, because on files VTK 9.1
//! itself writes it (`tests/vtkio_differential.rs` checks each of these, and that vtkio agrees
//! with us on every other file):
//! - rejects legacy `TENSORS6` with `Parse(Tag)` (12 of our 40 legacy files), and legacy FIELD
//!   data holding a string array;
//! - rejects XML point/cell data with a `<Array type="String">` among the data arrays
//!   ("duplicate field `DataArray`");
//! - rejects XML appended *raw* data ("unknown variant `raw`"; 20 of 52 XML files, and a `.pvti`
//!   whose pieces use it);
//! - panics on compressed `.vtp` files (the empty `Verts`/`Lines`/`Strips` sections);
//! - drops attributes it fails to decode and still returns `Ok` (`filter_map(.. .ok())` in its
//!   XML import);
//! - concatenates `.pvti` pieces instead of placing them in the whole extent (shared points
//!   appear twice);
//! - ignores the image `Direction` and keeps origin/spacing as f32;
//! - trusts declared counts when allocating.
//!
//! Working around all of that would have needed a pre-parser about as large as a parser.
//!
//! Layout: `legacy` and `xml` turn bytes into a `Parsed` dataset (geometry, cells, array
//! descriptors and a way to load one array); `assemble` picks the tensor array, checks its
//! component and tuple counts and computes the positions (points, or cell centres as VTK's
//! vtkCellCenters does).

mod binary;
mod legacy;
mod xml;

use std::path::Path;

use super::{ComponentOrder, DatasetKind, Location, TensorArrayInfo, TensorField};
use crate::error::{LoadError, LoadErrorKind};

/// How to read a VTK file.
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    /// Tensor array to read, by name. `None`: the active tensors, else the first 9- or
    /// 6-component point array, else the first such cell array.
    pub array: Option<String>,
    /// Component order of 6-component arrays.
    pub order: ComponentOrder,
}

/// Read a tensor field from a VTK file (format detected from the content).
///
/// Never panics on bad input: every count is validated before allocation, and as a last line
/// of defence a panic inside the reader is turned into a [`LoadErrorKind::Other`].
pub fn read_field(path: &Path, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| read_inner(path, opts)))
        .unwrap_or_else(|payload| {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(LoadErrorKind::Other(format!(
                "internal reader error (please report this file): {msg}"
            )))
        });
    result.map_err(|kind| LoadError::new(path, kind))
}

type Res<T> = Result<T, LoadErrorKind>;

pub(crate) fn malformed(msg: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Malformed(msg.into())
}

pub(crate) fn read_bytes(path: &Path) -> Res<Vec<u8>> {
    match std::fs::read(path) {
        Ok(b) => Ok(b),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(LoadErrorKind::Missing),
        Err(e) => Err(LoadErrorKind::Io(e)),
    }
}

fn read_inner(path: &Path, opts: &ReadOptions) -> Res<TensorField> {
    let bytes = read_bytes(path)?;
    let start = skip_bom_ws(&bytes);
    let head = &bytes[start..];
    if head.starts_with(b"# vtk DataFile") || head.starts_with(b"# VTK DataFile") {
        let parsed = legacy::parse(&bytes, opts.array.as_deref())?;
        assemble(parsed, opts)
    } else if head.starts_with(b"<") {
        xml::read(path, &bytes, opts)
    } else if bytes.is_empty() {
        Err(LoadErrorKind::NotVtk("the file is empty".into()))
    } else {
        Err(LoadErrorKind::NotVtk(
            "neither a legacy VTK header ('# vtk DataFile Version') nor XML".into(),
        ))
    }
}

fn skip_bom_ws(b: &[u8]) -> usize {
    let mut i = if b.starts_with(&[0xEF, 0xBB, 0xBF]) {
        3
    } else {
        0
    };
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// Cell connectivity (VTK order), `offsets.len() == cells + 1`.
#[derive(Debug, Default, Clone)]
pub(crate) struct Cells {
    pub offsets: Vec<usize>,
    pub conn: Vec<usize>,
    /// VTK cell type per cell; empty when unknown (polydata: derived from the section).
    pub types: Vec<u8>,
}

impl Cells {
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Build from offsets (with or without the leading 0) and connectivity; validates them.
    pub fn from_offsets(mut offsets: Vec<usize>, conn: Vec<usize>) -> Res<Cells> {
        if offsets.first() != Some(&0) {
            offsets.insert(0, 0);
        }
        if offsets.windows(2).any(|w| w[1] < w[0]) {
            return Err(malformed("cell offsets are not increasing"));
        }
        if *offsets.last().unwrap_or(&0) != conn.len() {
            return Err(malformed(format!(
                "cell offsets end at {} but the connectivity has {} entries",
                offsets.last().unwrap_or(&0),
                conn.len()
            )));
        }
        Ok(Cells {
            offsets,
            conn,
            types: Vec::new(),
        })
    }

    /// Append `other`'s cells after ours; `poly_section` (0..4 = verts, lines, polys, strips)
    /// derives polydata cell types, else `other`'s own types are kept.
    pub fn append(&mut self, other: Cells, poly_section: Option<usize>) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        let base = self.conn.len();
        let n = other.len();
        for w in other.offsets.windows(2) {
            self.offsets.push(base + w[1]);
            if let Some(sec) = poly_section {
                self.types.push(poly_cell_type(sec, w[1] - w[0]));
            }
        }
        if poly_section.is_none() {
            self.types
                .extend_from_slice(&other.types[..other.types.len().min(n)]);
        }
        self.conn.extend_from_slice(&other.conn);
    }
}

/// VTK cell type of a polydata cell with `n` points in section `sec` (verts, lines, polys,
/// strips), as vtkPolyData::GetCellType reports it.
pub(crate) fn poly_cell_type(sec: usize, n: usize) -> u8 {
    match (sec, n) {
        (0, 1) => 1, // vertex
        (0, _) => 2, // poly-vertex
        (1, 2) => 3, // line
        (1, _) => 4, // poly-line
        (2, 3) => 5, // triangle
        (2, 4) => 9, // quad
        (2, _) => 7, // polygon
        _ => 6,      // triangle strip
    }
}

/// Where the points are.
#[derive(Debug)]
pub(crate) enum Geometry {
    /// Image data: point extent (index space), origin, spacing, direction.
    Image {
        extent: [i64; 6],
        origin: [f64; 3],
        spacing: [f64; 3],
        direction: Option<[[f64; 3]; 3]>,
    },
    Rectilinear {
        coords: [Vec<f64>; 3],
    },
    /// Explicit points; `dims` for structured grids, `cells` for unstructured grids and polydata.
    Points {
        points: Vec<[f64; 3]>,
        dims: Option<[usize; 3]>,
        cells: Option<Cells>,
    },
}

/// An array as declared in the file.
#[derive(Debug, Clone)]
pub(crate) struct ArrayDesc {
    pub name: String,
    pub ncomp: usize,
    /// Declared tuple count, when the file states it.
    pub ntuples: Option<usize>,
    /// `None` for dataset-level field data.
    pub location: Option<Location>,
    /// The active TENSORS attribute of its location.
    pub active: bool,
}

/// A dataset as parsed: everything but the tensor values, which `load` delivers.
pub(crate) struct Parsed<'a> {
    pub format: &'static str,
    pub kind: DatasetKind,
    pub geometry: Geometry,
    pub arrays: Vec<ArrayDesc>,
    /// Load array `i` of `arrays` as `ntuples * ncomp` values.
    pub load: Box<dyn FnMut(usize) -> Res<Vec<f64>> + 'a>,
}

pub(crate) fn point_dims(extent: &[i64; 6]) -> Res<[usize; 3]> {
    let mut d = [0usize; 3];
    for a in 0..3 {
        let n = extent[2 * a + 1]
            .checked_sub(extent[2 * a])
            .and_then(|v| v.checked_add(1))
            .filter(|&v| v >= 1)
            .ok_or_else(|| malformed(format!("invalid extent {extent:?}")))?;
        d[a] = usize::try_from(n).map_err(|_| malformed(format!("invalid extent {extent:?}")))?;
    }
    Ok(d)
}

fn product(d: [usize; 3]) -> Res<usize> {
    d[0].checked_mul(d[1])
        .and_then(|v| v.checked_mul(d[2]))
        .ok_or_else(|| malformed(format!("dimensions {d:?} overflow")))
}

fn cell_dims(d: [usize; 3]) -> [usize; 3] {
    d.map(|n| n.saturating_sub(1).max(1))
}

impl Geometry {
    pub fn dims(&self) -> Res<Option<[usize; 3]>> {
        Ok(match self {
            Geometry::Image { extent, .. } => Some(point_dims(extent)?),
            Geometry::Rectilinear { coords } => {
                Some([coords[0].len(), coords[1].len(), coords[2].len()])
            }
            Geometry::Points { dims, .. } => *dims,
        })
    }

    pub fn points(&self) -> Res<usize> {
        match self {
            Geometry::Points { points, .. } => Ok(points.len()),
            _ => product(self.dims()?.unwrap_or([0; 3])),
        }
    }

    pub fn cells(&self) -> Res<usize> {
        match self {
            Geometry::Points { cells: Some(c), .. } => Ok(c.len()),
            Geometry::Points {
                dims: Some(d),
                points,
                ..
            } => Ok(if points.is_empty() {
                0
            } else {
                product(cell_dims(*d))?
            }),
            Geometry::Points { .. } => Ok(0),
            _ => {
                let d = self.dims()?.unwrap_or([0; 3]);
                Ok(if product(d)? == 0 {
                    0
                } else {
                    product(cell_dims(d))?
                })
            }
        }
    }
}

fn describe_arrays(arrays: &[ArrayDesc]) -> String {
    if arrays.is_empty() {
        return "none".into();
    }
    arrays
        .iter()
        .map(|a| {
            let loc = match a.location {
                Some(l) => l.as_str(),
                None => "field",
            };
            format!("'{}' ({} components, {loc})", a.name, a.ncomp)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Index of the array to read, by name or by the default rule.
pub(crate) fn pick(arrays: &[ArrayDesc], name: Option<&str>) -> Res<usize> {
    let usable = |a: &ArrayDesc| a.location.is_some();
    if let Some(name) = name {
        let i = arrays
            .iter()
            .position(|a| a.name == name && usable(a) && matches!(a.ncomp, 6 | 9))
            .or_else(|| arrays.iter().position(|a| a.name == name && usable(a)))
            .ok_or_else(|| {
                if arrays.iter().any(|a| a.name == name) {
                    return LoadErrorKind::Other(format!(
                        "array '{name}' is dataset-level field data, not point or cell data"
                    ));
                }
                LoadErrorKind::ArrayNotFound {
                    name: name.to_string(),
                    available: describe_arrays(arrays),
                }
            })?;
        if !matches!(arrays[i].ncomp, 6 | 9) {
            return Err(LoadErrorKind::ComponentCount {
                name: name.to_string(),
                components: arrays[i].ncomp,
            });
        }
        return Ok(i);
    }
    let tensorish =
        |a: &ArrayDesc, loc: Location| a.location == Some(loc) && matches!(a.ncomp, 6 | 9);
    for loc in [Location::Point, Location::Cell] {
        if let Some(i) = arrays.iter().position(|a| a.active && tensorish(a, loc)) {
            return Ok(i);
        }
    }
    for loc in [Location::Point, Location::Cell] {
        if let Some(i) = arrays.iter().position(|a| tensorish(a, loc)) {
            return Ok(i);
        }
    }
    Err(LoadErrorKind::NoTensorArray(format!(
        "; arrays present: {}",
        describe_arrays(arrays)
    )))
}

/// Pick the array, load and check it, compute positions.
pub(crate) fn assemble(mut p: Parsed<'_>, opts: &ReadOptions) -> Res<TensorField> {
    let idx = pick(&p.arrays, opts.array.as_deref())?;
    let desc = p.arrays[idx].clone();
    let location = desc.location.unwrap_or(Location::Point);
    let npoints = p.geometry.points()?;
    let ncells = p.geometry.cells()?;
    let expected = match location {
        Location::Point => npoints,
        Location::Cell => ncells,
    };
    if let Some(n) = desc.ntuples
        && n != expected
    {
        return Err(LoadErrorKind::TupleCount {
            name: desc.name,
            found: n,
            expected,
            location: location.as_str(),
        });
    }
    let values = (p.load)(idx)?;
    if values.len() % desc.ncomp != 0 || values.len() / desc.ncomp != expected {
        return Err(LoadErrorKind::TupleCount {
            name: desc.name,
            found: values.len() / desc.ncomp,
            expected,
            location: location.as_str(),
        });
    }
    let tensors: Vec<[f64; 9]> = if desc.ncomp == 9 {
        values
            .chunks_exact(9)
            .map(|c| c.try_into().expect("chunk of 9"))
            .collect()
    } else {
        values
            .chunks_exact(6)
            .map(|c| opts.order.expand(c))
            .collect()
    };
    let positions = match location {
        Location::Point => point_positions(&p.geometry)?,
        Location::Cell => cell_centres(&p.geometry, npoints)?,
    };
    if positions.len() != tensors.len() {
        return Err(malformed(format!(
            "{} positions for {} tensors",
            positions.len(),
            tensors.len()
        )));
    }
    let dims = p.geometry.dims()?;
    let (direction, spacing) = match &p.geometry {
        Geometry::Image {
            spacing, direction, ..
        } => {
            let d = dims.unwrap_or([1; 3]);
            let on_axes = (0..3)
                .filter(|&a| d[a] > 1)
                .map(|a| spacing[a].abs())
                .filter(|s| *s > 0.0 && s.is_finite())
                .fold(f64::INFINITY, f64::min);
            let any = spacing
                .iter()
                .map(|s| s.abs())
                .filter(|s| *s > 0.0 && s.is_finite())
                .fold(f64::INFINITY, f64::min);
            let s = if on_axes.is_finite() { on_axes } else { any };
            (*direction, s.is_finite().then_some(s))
        }
        Geometry::Rectilinear { coords } => {
            let s = coords
                .iter()
                .flat_map(|c| c.windows(2).map(|w| (w[1] - w[0]).abs()))
                .filter(|s| *s > 0.0 && s.is_finite())
                .fold(f64::INFINITY, f64::min);
            (None, s.is_finite().then_some(s))
        }
        Geometry::Points { .. } => (None, None),
    };
    Ok(TensorField {
        format: p.format.to_string(),
        dataset: p.kind,
        dims,
        points: npoints,
        cells: ncells,
        array: TensorArrayInfo {
            name: desc.name,
            components: desc.ncomp,
            location,
        },
        positions,
        tensors,
        direction,
        spacing,
    })
}

fn image_point(
    origin: &[f64; 3],
    spacing: &[f64; 3],
    dir: &Option<[[f64; 3]; 3]>,
    ijk: [f64; 3],
) -> [f64; 3] {
    let v = [
        ijk[0] * spacing[0],
        ijk[1] * spacing[1],
        ijk[2] * spacing[2],
    ];
    match dir {
        None => [origin[0] + v[0], origin[1] + v[1], origin[2] + v[2]],
        Some(r) => {
            let mut p = *origin;
            for (i, row) in r.iter().enumerate() {
                p[i] += row[0] * v[0] + row[1] * v[1] + row[2] * v[2];
            }
            p
        }
    }
}

fn alloc<T>(n: usize) -> Res<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| malformed(format!("cannot allocate {n} entries")))?;
    Ok(v)
}

fn point_positions(g: &Geometry) -> Res<Vec<[f64; 3]>> {
    match g {
        Geometry::Image {
            extent,
            origin,
            spacing,
            direction,
        } => {
            let d = point_dims(extent)?;
            let mut out = alloc(product(d)?)?;
            for k in 0..d[2] {
                for j in 0..d[1] {
                    for i in 0..d[0] {
                        let ijk = [
                            (extent[0] + i as i64) as f64,
                            (extent[2] + j as i64) as f64,
                            (extent[4] + k as i64) as f64,
                        ];
                        out.push(image_point(origin, spacing, direction, ijk));
                    }
                }
            }
            Ok(out)
        }
        Geometry::Rectilinear { coords } => {
            let [x, y, z] = coords;
            let mut out = alloc(product([x.len(), y.len(), z.len()])?)?;
            for &zz in z {
                for &yy in y {
                    for &xx in x {
                        out.push([xx, yy, zz]);
                    }
                }
            }
            Ok(out)
        }
        Geometry::Points { points, .. } => Ok(points.clone()),
    }
}

/// Mid-point of each cell axis: `(a + b) / 2`, or the single coordinate on a flat axis.
fn mids(c: &[f64]) -> Vec<f64> {
    if c.len() <= 1 {
        c.to_vec()
    } else {
        c.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
    }
}

/// Cell centres as VTK's vtkCellCenters computes them (see [`vtk_cell_centre`]).
fn cell_centres(g: &Geometry, npoints: usize) -> Res<Vec<[f64; 3]>> {
    match g {
        Geometry::Image {
            extent,
            origin,
            spacing,
            direction,
        } => {
            let d = point_dims(extent)?;
            let axis = |a: usize| -> Vec<f64> {
                let c: Vec<f64> = (0..d[a])
                    .map(|i| (extent[2 * a] + i as i64) as f64)
                    .collect();
                mids(&c)
            };
            let (x, y, z) = (axis(0), axis(1), axis(2));
            let mut out = alloc(x.len() * y.len() * z.len())?;
            for &k in &z {
                for &j in &y {
                    for &i in &x {
                        out.push(image_point(origin, spacing, direction, [i, j, k]));
                    }
                }
            }
            Ok(out)
        }
        Geometry::Rectilinear { coords } => {
            let (x, y, z) = (mids(&coords[0]), mids(&coords[1]), mids(&coords[2]));
            let mut out = alloc(x.len() * y.len() * z.len())?;
            for &zz in &z {
                for &yy in &y {
                    for &xx in &x {
                        out.push([xx, yy, zz]);
                    }
                }
            }
            Ok(out)
        }
        Geometry::Points {
            points,
            dims: Some(d),
            cells: None,
        } => {
            // Structured grid: mean of the corners of each (possibly flat) hexahedron.
            let cd = cell_dims(*d);
            let steps = |a: usize| -> Vec<usize> { if d[a] > 1 { vec![0, 1] } else { vec![0] } };
            let (si, sj, sk) = (steps(0), steps(1), steps(2));
            let mut out = alloc(product(cd)?)?;
            if points.is_empty() {
                return Ok(Vec::new());
            }
            for k in 0..cd[2] {
                for j in 0..cd[1] {
                    for i in 0..cd[0] {
                        let mut s = [0.0; 3];
                        let mut n = 0.0;
                        for &dk in &sk {
                            for &dj in &sj {
                                for &di in &si {
                                    let id = (i + di) + d[0] * ((j + dj) + d[1] * (k + dk));
                                    let p = points[id];
                                    for a in 0..3 {
                                        s[a] += p[a];
                                    }
                                    n += 1.0;
                                }
                            }
                        }
                        out.push(s.map(|v| v / n));
                    }
                }
            }
            Ok(out)
        }
        Geometry::Points {
            points,
            cells: Some(cells),
            ..
        } => {
            let mut out = alloc(cells.len())?;
            for c in 0..cells.len() {
                let ids = &cells.conn[cells.offsets[c]..cells.offsets[c + 1]];
                if let Some(&bad) = ids.iter().find(|&&id| id >= npoints) {
                    return Err(malformed(format!(
                        "cell {c} refers to point {bad} but there are {npoints} points"
                    )));
                }
                let ty = cells.types.get(c).copied().unwrap_or(0);
                out.push(vtk_cell_centre(ty, ids, points));
            }
            Ok(out)
        }
        Geometry::Points { .. } => Ok(Vec::new()),
    }
}

/// The centre of one cell as VTK's vtkCellCenters computes it: the cell's parametric centre
/// (`GetParametricCenter`) mapped through its interpolation functions (`EvaluateLocation`).
/// For most linear cells (line, triangle, pixel, quad, tetra, voxel, hexahedron, prisms) that is
/// the mean of the points. Exceptions matched here, from VTK 9.1's sources: the wedge's centre
/// is (0.333333, 0.333333, 0.5), written with six digits; the pyramid's is (0.4, 0.4, 0.2); a
/// poly-vertex gives its middle point, a poly-line the midpoint of its middle segment, a
/// triangle strip the (0.333333, 0.333333) point of its middle triangle. Not matched: general
/// polygons (VTK uses the centre of the polygon's own parametric frame; we use the mean) and
/// nonlinear cells (mean of all nodes).
pub(crate) fn vtk_cell_centre(ty: u8, ids: &[usize], points: &[[f64; 3]]) -> [f64; 3] {
    let weighted = |w: &[f64], ids: &[usize]| {
        let mut x = [0.0; 3];
        for (wi, &id) in w.iter().zip(ids) {
            for a in 0..3 {
                x[a] += wi * points[id][a];
            }
        }
        x
    };
    let n = ids.len();
    const THIRD6: f64 = 0.333333;
    match (ty, n) {
        (_, 0) => [f64::NAN; 3],
        // VTK_POLY_VERTEX
        (2, _) => points[ids[n / 2]],
        // VTK_POLY_LINE
        (4, 2..) => {
            let s = (n - 1) / 2;
            weighted(&[0.5, 0.5], &ids[s..s + 2])
        }
        // VTK_TRIANGLE_STRIP
        (6, 3..) => {
            let s = (n - 2) / 2;
            weighted(&[1.0 - 2.0 * THIRD6, THIRD6, THIRD6], &ids[s..s + 3])
        }
        // VTK_TRIANGLE
        (5, 3) => {
            let t = 1.0 / 3.0;
            weighted(&[1.0 - t - t, t, t], ids)
        }
        // VTK_WEDGE
        (13, 6) => {
            let (r, s, t) = (THIRD6, THIRD6, 0.5);
            weighted(
                &[
                    (1.0 - r - s) * (1.0 - t),
                    r * (1.0 - t),
                    s * (1.0 - t),
                    (1.0 - r - s) * t,
                    r * t,
                    s * t,
                ],
                ids,
            )
        }
        // VTK_PYRAMID
        (14, 5) => {
            let (r, s, t) = (0.4, 0.4, 0.2);
            weighted(
                &[
                    (1.0 - r) * (1.0 - s) * (1.0 - t),
                    r * (1.0 - s) * (1.0 - t),
                    r * s * (1.0 - t),
                    (1.0 - r) * s * (1.0 - t),
                    t,
                ],
                ids,
            )
        }
        _ => {
            let mut x = [0.0; 3];
            for &id in ids {
                for a in 0..3 {
                    x[a] += points[id][a];
                }
            }
            x.map(|v| v / n as f64)
        }
    }
}
