//! From a parsed dataset to a [`TensorField`]: the picked array checked against the geometry,
//! and the positions of its tuples (points, or cell centres as VTK computes them).

use super::dataset::{Geometry, Parsed, cell_dims, pick, point_dims, product};
use super::malformed::{Res, malformed};
use crate::error::LoadErrorKind;
use crate::field::frame::{FrameInfo, Layout, ReadMeta, TensorFrame, Why};
use crate::field::options::ReadOptions;
use crate::field::tensor_field::{Location, Positions, TensorArrayInfo, TensorField, Tensors};

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
            .map(|c| opts.order.unwrap_or_default().expand(c))
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
    let layout = if desc.ncomp == 9 {
        Layout::full()
    } else {
        let why = if opts.order.is_some() {
            Why::Flag
        } else {
            Why::Default
        };
        Layout::six(opts.order.unwrap_or_default(), why)
    };
    let meta = ReadMeta {
        layout: Some(layout),
        frame: Some(FrameInfo {
            // An image's Direction rotates its tensors, as VTK's filters do; other datasets
            // have no voxel axes.
            tensor_frame: if direction.is_some() {
                TensorFrame::Voxel
            } else {
                TensorFrame::World
            },
            world: "VTK".into(),
            voxel_to_world: None,
            source: "VTK".into(),
        }),
        masked: 0,
        ..Default::default()
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
        positions: Positions::Points(positions),
        tensors: Tensors::F64(tensors),
        direction,
        spacing,
        meta,
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
