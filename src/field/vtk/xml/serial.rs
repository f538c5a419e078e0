//! One serial dataset (`.vti`, `.vtr`, `.vts`, `.vtu`, `.vtp`), possibly in several pieces.

use super::attrs::{count_attr, direction, extent, floats};
use super::decode::{Ctx, Need};
use super::tokenize::{Doc, Tag};
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::tensor_field::{DatasetKind, Location};
use crate::field::vtk::binary::to_indices;
use crate::field::vtk::dataset::{ArrayDesc, Cells, Geometry, Parsed, point_dims};
use crate::field::vtk::malformed::{Res, malformed};

/// Rows of one piece's array that go, in order, into the merged array: (piece, first row, rows).
type Segments = Vec<(usize, usize, usize)>;

pub(super) fn parse_serial<'a>(ctx: &'a Ctx<'a>, doc: &'a Doc, ty: &str) -> Res<Parsed<'a>> {
    let (kind, format) = match ty {
        "ImageData" => (DatasetKind::ImageData, "vti"),
        "RectilinearGrid" => (DatasetKind::RectilinearGrid, "vtr"),
        "StructuredGrid" => (DatasetKind::StructuredGrid, "vts"),
        "UnstructuredGrid" => (DatasetKind::UnstructuredGrid, "vtu"),
        "PolyData" => (DatasetKind::PolyData, "vtp"),
        other => {
            return Err(LoadErrorKind::UnsupportedDataset(format!(
                "XML dataset type '{}'",
                esc(other)
            )));
        }
    };
    let ds = doc
        .tags
        .iter()
        .find(|t| t.name == ty)
        .ok_or_else(|| malformed(format!("no <{ty}> element")))?;
    // Each piece's tags: from its <Piece> to the next one (tags are in document order).
    let starts: Vec<usize> = doc
        .tags
        .iter()
        .enumerate()
        .filter(|(_, t)| t.name == "Piece" && doc.parent(t) == ty)
        .map(|(i, _)| i)
        .collect();
    if starts.is_empty() {
        return Err(malformed(format!("<{ty}> has no <Piece>")));
    }
    let structured = matches!(
        kind,
        DatasetKind::ImageData | DatasetKind::RectilinearGrid | DatasetKind::StructuredGrid
    );
    if structured && starts.len() > 1 {
        return Err(LoadErrorKind::UnsupportedDataset(format!(
            "{} pieces in one serial {ty} file",
            starts.len()
        )));
    }
    let ranges: Vec<(usize, usize)> = starts
        .iter()
        .enumerate()
        .map(|(k, &s)| (s, starts.get(k + 1).copied().unwrap_or(doc.tags.len())))
        .collect();
    let slices: Vec<&'a [Tag]> = ranges.iter().map(|&(s, e)| &doc.tags[s + 1..e]).collect();
    let slices2 = slices.clone();
    let arrays_in = move |k: usize, section: &str| -> Vec<&'a Tag> {
        slices[k]
            .iter()
            .filter(|t| t.name == "DataArray" && doc.parent(t) == section)
            .collect()
    };
    let section = move |k: usize, name: &str| slices2[k].iter().find(|t| t.name == name);
    let piece = &doc.tags[starts[0]];

    let mut point_segments: Segments = Vec::new();
    let mut cell_segments: Segments = Vec::new();
    let geometry = match kind {
        DatasetKind::ImageData => Geometry::Image {
            extent: extent(piece.get("Extent"), "Piece Extent")?,
            origin: floats::<3>(ds.get("Origin"), "Origin")?.unwrap_or([0.0; 3]),
            spacing: floats::<3>(ds.get("Spacing"), "Spacing")?.unwrap_or([1.0; 3]),
            direction: direction(ds.get("Direction"))?,
        },
        DatasetKind::RectilinearGrid => {
            let e = extent(piece.get("Extent"), "Piece Extent")?;
            let d = point_dims(&e)?;
            let c = arrays_in(0, "Coordinates");
            if c.len() != 3 {
                return Err(malformed(format!(
                    "<Coordinates> has {} arrays, not 3",
                    c.len()
                )));
            }
            let mut coords: [Vec<f64>; 3] = Default::default();
            for a in 0..3 {
                let axis = ["x", "y", "z"][a];
                coords[a] =
                    ctx.values(c[a], &format!("{axis} coordinates"), Need::exactly(d[a]))?;
                if coords[a].len() != d[a] {
                    return Err(malformed(format!(
                        "{axis} coordinates: {} values for extent {e:?}",
                        coords[a].len()
                    )));
                }
            }
            Geometry::Rectilinear { coords }
        }
        DatasetKind::StructuredGrid => {
            let d = point_dims(&extent(piece.get("Extent"), "Piece Extent")?)?;
            let n = d[0]
                .checked_mul(d[1])
                .and_then(|v| v.checked_mul(d[2]))
                .ok_or_else(|| malformed(format!("point dimensions {d:?} overflow")))?;
            let points = piece_points(ctx, &arrays_in(0, "Points"), n)?;
            if n != points.len() {
                return Err(malformed(format!(
                    "{} points for point dimensions {d:?}",
                    points.len()
                )));
            }
            Geometry::Points {
                points,
                dims: Some(d),
                cells: None,
            }
        }
        DatasetKind::UnstructuredGrid | DatasetKind::PolyData => {
            let mut points: Vec<[f64; 3]> = Vec::new();
            // Unstructured: one category; polydata: verts, lines, polys, strips, each gathered
            // over all pieces (the order of VTK's merged output).
            let ncat = if kind == DatasetKind::PolyData { 4 } else { 1 };
            let mut cats: Vec<Vec<(usize, usize, Cells)>> = vec![Vec::new(); ncat];
            for (k, &start) in starts.iter().enumerate() {
                let p = &doc.tags[start];
                let declared = count_attr(p, "NumberOfPoints")?;
                let pts = piece_points(ctx, &arrays_in(k, "Points"), declared)?;
                if declared != pts.len() {
                    return Err(malformed(format!(
                        "piece {k}: NumberOfPoints={declared} but <Points> holds {}",
                        pts.len()
                    )));
                }
                let base = points.len();
                point_segments.push((k, 0, pts.len()));
                points.extend_from_slice(&pts);
                let secs: &[(&str, &str)] = if kind == DatasetKind::PolyData {
                    &[
                        ("Verts", "NumberOfVerts"),
                        ("Lines", "NumberOfLines"),
                        ("Polys", "NumberOfPolys"),
                        ("Strips", "NumberOfStrips"),
                    ]
                } else {
                    &[("Cells", "NumberOfCells")]
                };
                let mut row = 0;
                for (cat, (sec, attr)) in secs.iter().enumerate() {
                    let declared = count_attr(p, attr)?;
                    let mut c = match section(k, sec) {
                        None => Cells {
                            offsets: vec![0],
                            ..Cells::default()
                        },
                        Some(_) => {
                            let arr = arrays_in(k, sec);
                            read_cells(ctx, &arr, sec, declared, pts.len(), ncat == 1)?
                        }
                    };
                    if c.len() != declared {
                        return Err(malformed(format!(
                            "piece {k}: {attr}={declared} but <{sec}> holds {}",
                            c.len()
                        )));
                    }
                    for id in &mut c.conn {
                        *id += base;
                    }
                    let n = c.len();
                    cats[cat].push((k, row, c));
                    row += n;
                }
            }
            let mut all = Cells {
                offsets: vec![0],
                ..Cells::default()
            };
            for (cat, list) in cats.into_iter().enumerate() {
                for (k, row, c) in list {
                    cell_segments.push((k, row, c.len()));
                    all.append(c, (ncat == 4).then_some(cat));
                }
            }
            Geometry::Points {
                points,
                dims: None,
                cells: Some(all),
            }
        }
    };
    if structured {
        point_segments = vec![(0, 0, usize::MAX)];
        cell_segments = vec![(0, 0, usize::MAX)];
    }

    // Arrays, as declared in the first piece.
    let mut arrays = Vec::new();
    for (sec, loc) in [("PointData", Location::Point), ("CellData", Location::Cell)] {
        let active = section(0, sec)
            .and_then(|s| s.get("Tensors"))
            .map(str::to_string);
        for t in arrays_in(0, sec) {
            let name = t.get("Name").unwrap_or("").to_string();
            let ncomp = count_attr(t, "NumberOfComponents")?.max(1);
            let declared = t
                .get("NumberOfTuples")
                .map(|_| count_attr(t, "NumberOfTuples"))
                .transpose()?;
            arrays.push(ArrayDesc {
                active: active.as_deref() == Some(name.as_str()),
                name,
                ncomp,
                ntuples: declared,
                location: Some(loc),
            });
        }
    }
    let descs = arrays.clone();
    let npieces = starts.len();
    // How many tuples each piece's array must hold, to bound its decoding. If the counts
    // overflow, `assemble` reports that before it loads anything.
    let whole = [
        geometry.points().unwrap_or(0),
        geometry.cells().unwrap_or(0),
    ];
    Ok(Parsed {
        format,
        kind,
        geometry,
        arrays,
        load: Box::new(move |i| {
            let d = &descs[i];
            let (sec, segments) = match d.location {
                Some(Location::Cell) => ("CellData", &cell_segments),
                _ => ("PointData", &point_segments),
            };
            let what = format!("array '{}'", esc(&d.name));
            let nc = d.ncomp;
            let mut per_piece = Vec::with_capacity(npieces);
            for k in 0..npieces {
                let t = arrays_in(k, sec)
                    .into_iter()
                    .find(|t| t.get("Name").unwrap_or("") == d.name)
                    .ok_or_else(|| malformed(format!("piece {k} has no {what}")))?;
                let rows = if structured {
                    whole[usize::from(sec == "CellData")]
                } else {
                    segments.iter().filter(|s| s.0 == k).map(|s| s.2).sum()
                };
                let need = rows
                    .checked_mul(nc)
                    .ok_or_else(|| malformed(format!("{what}: {rows} tuples overflow")))?;
                per_piece.push(ctx.values(t, &what, Need::exactly(need))?);
            }
            if npieces == 1 && segments.len() <= 1 {
                return Ok(per_piece.pop().unwrap_or_default());
            }
            let mut out = Vec::new();
            for &(k, row, n) in segments {
                let v = &per_piece[k];
                let rows = v.get(row * nc..(row + n) * nc).ok_or_else(|| {
                    malformed(format!(
                        "piece {k}: {what} has {} tuples, fewer than its {}s",
                        v.len() / nc,
                        sec.trim_end_matches("Data").to_lowercase()
                    ))
                })?;
                out.extend_from_slice(rows);
            }
            for (k, v) in per_piece.iter().enumerate() {
                let used: usize = segments.iter().filter(|s| s.0 == k).map(|s| s.2).sum();
                if v.len() != used * nc {
                    return Err(malformed(format!(
                        "piece {k}: {what} has {} tuples, expected {used}",
                        v.len() / nc
                    )));
                }
            }
            Ok(out)
        }),
    })
}

/// The points of one piece, which must hold `n`.
fn piece_points(ctx: &Ctx, arrays: &[&Tag], n: usize) -> Res<Vec<[f64; 3]>> {
    let t = arrays
        .first()
        .ok_or_else(|| malformed("no <Points> array"))?;
    let n3 = n
        .checked_mul(3)
        .ok_or_else(|| malformed(format!("{n} points overflow")))?;
    let v = ctx.values(t, "Points", Need::exactly(n3))?;
    if v.len() % 3 != 0 {
        return Err(malformed("Points: not a multiple of 3 values"));
    }
    Ok(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Connectivity and offsets (and types for unstructured grids) of one cell section that
/// declares `ncells` cells.
fn read_cells(
    ctx: &Ctx,
    arr: &[&Tag],
    sec: &str,
    ncells: usize,
    npoints: usize,
    with_types: bool,
) -> Res<Cells> {
    let by_name = |nm: &str| arr.iter().find(|t| t.get("Name") == Some(nm));
    let (Some(conn), Some(off)) = (by_name("connectivity"), by_name("offsets")) else {
        return Ok(Cells {
            offsets: vec![0],
            ..Cells::default()
        });
    };
    // Offsets first: their last entry is the connectivity's length, which bounds its decoding.
    // One more than the cells, for writers that store the leading 0.
    let off = ctx.values(
        off,
        &format!("{sec} offsets"),
        Need {
            min: ncells,
            max: ncells.saturating_add(1),
        },
    )?;
    let nconn = match off.last() {
        Some(&x) if x >= 0.0 && x.is_finite() => x as usize,
        _ => 0,
    };
    let conn = ctx.values(conn, &format!("{sec} connectivity"), Need::exactly(nconn))?;
    let conn = to_indices(&conn, "point id", npoints)?;
    let off = to_indices(&off, "cell offset", conn.len())?;
    let mut c = Cells::from_offsets(off, conn)?;
    if with_types {
        let t = by_name("types").ok_or_else(|| malformed("<Cells> without types"))?;
        let t = ctx.values(t, "cell types", Need::exactly(ncells))?;
        if t.len() != c.len() {
            return Err(malformed(format!(
                "{} cell types for {} cells",
                t.len(),
                c.len()
            )));
        }
        c.types = t.iter().map(|&x| x.clamp(0.0, 255.0) as u8).collect();
    }
    Ok(c)
}
