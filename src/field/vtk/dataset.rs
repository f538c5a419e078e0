//! A dataset as the readers parse it: geometry, cells and array descriptors, and the rule that
//! picks the tensor array.

use super::malformed::{Res, malformed};
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::tensor_field::{DatasetKind, Location};

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

pub(super) fn product(d: [usize; 3]) -> Res<usize> {
    d[0].checked_mul(d[1])
        .and_then(|v| v.checked_mul(d[2]))
        .ok_or_else(|| malformed(format!("dimensions {d:?} overflow")))
}

pub(super) fn cell_dims(d: [usize; 3]) -> [usize; 3] {
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

/// Arrays listed in errors; a file may declare thousands, the line stays readable.
const LISTED_ARRAYS: usize = 20;

pub(crate) fn describe_arrays(arrays: &[ArrayDesc]) -> String {
    if arrays.is_empty() {
        return "none".into();
    }
    let mut s = arrays
        .iter()
        .take(LISTED_ARRAYS)
        .map(|a| {
            let loc = match a.location {
                Some(l) => l.as_str(),
                None => "field",
            };
            format!("'{}' ({} components, {loc})", esc(&a.name), a.ncomp)
        })
        .collect::<Vec<_>>()
        .join(", ");
    if arrays.len() > LISTED_ARRAYS {
        s += &format!(" and {} more", arrays.len() - LISTED_ARRAYS);
    }
    s
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
                        "array '{}' is dataset-level field data, not point or cell data",
                        esc(name)
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
