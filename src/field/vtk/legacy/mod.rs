//! Legacy `.vtk` files, ASCII and binary (big-endian), versions up to 5.1.
//!
//! vtkio 0.7.0-rc2 limitation this replaces: it rejects `TENSORS6` (written by VTK ≥ 9 for
//! 6-component tensors) with a parse error, and it allocates from declared counts before
//! checking them. This parser reads every section VTK 9 writes, keeps only the arrays that can
//! be tensors (or the one asked for by name), and checks each count against the bytes left.
//! `cursor` reads lines, tokens and counted runs of values; this module the sections.

mod cursor;

use super::binary::{Scalar, parse_number, to_indices, try_vec};
use super::dataset::{ArrayDesc, Cells, Geometry, Parsed};
use super::malformed::{Res, malformed};
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::tensor_field::{DatasetKind, Location};
use cursor::{Cursor, LType, ltype};

fn count(tok: Option<&&str>, what: &str) -> Res<usize> {
    tok.and_then(|t| t.parse::<usize>().ok())
        .ok_or_else(|| malformed(format!("{what}: missing or invalid count")))
}

fn arg<'a>(toks: &[&'a str], i: usize, what: &str) -> Res<&'a str> {
    toks.get(i)
        .copied()
        .ok_or_else(|| malformed(format!("{what}: incomplete header line")))
}

fn floats3(toks: &[&str], what: &str) -> Res<[f64; 3]> {
    let mut v = [0.0; 3];
    for (a, slot) in v.iter_mut().enumerate() {
        *slot = parse_number(arg(toks, a + 1, what)?.as_bytes(), what)?;
    }
    Ok(v)
}

/// Cells of one section (`CELLS`, `VERTICES`, ...), in the 4.2 or 5.1 layout.
fn read_cells(cur: &mut Cursor, toks: &[&str], v5: bool, npoints_limit: usize) -> Res<Cells> {
    let what = toks[0];
    let a = count(toks.get(1), what)?;
    let b = count(toks.get(2), what)?;
    if v5 || (a > 0 && cur.peek_keyword("OFFSETS")) {
        // 5.1: CELLS <noffsets> <nconn>, then OFFSETS <type> / CONNECTIVITY <type>.
        let t = cur
            .line()?
            .ok_or_else(|| malformed(format!("{what}: missing OFFSETS")))?;
        if t[0] != "OFFSETS" {
            return Err(malformed(format!(
                "{what}: expected OFFSETS, found '{}'",
                esc(t[0])
            )));
        }
        let off = cur
            .values(a, ltype(arg(&t, 1, "OFFSETS")?)?, true, "OFFSETS")?
            .unwrap_or_default();
        let t = cur
            .line()?
            .ok_or_else(|| malformed(format!("{what}: missing CONNECTIVITY")))?;
        if t[0] != "CONNECTIVITY" {
            return Err(malformed(format!(
                "{what}: expected CONNECTIVITY, found '{}'",
                esc(t[0])
            )));
        }
        let conn = cur
            .values(b, ltype(arg(&t, 1, "CONNECTIVITY")?)?, true, "CONNECTIVITY")?
            .unwrap_or_default();
        let off = to_indices(&off, "cell offset", b)?;
        let conn = to_indices(&conn, "point id", npoints_limit)?;
        if a == 0 {
            return Cells::from_offsets(vec![0], conn);
        }
        Cells::from_offsets(off, conn)
    } else {
        // 4.2: CELLS <ncells> <size>, then per cell: npts id...
        let raw = cur
            .values(b, LType::Num(Scalar::I32), true, what)?
            .unwrap_or_default();
        let raw = to_indices(&raw, "cell list entry", usize::MAX >> 12)?;
        let mut offsets = try_vec(a.min(raw.len()) + 1)?;
        let mut conn = try_vec(raw.len())?;
        offsets.push(0);
        let mut i = 0;
        for c in 0..a {
            let n = *raw
                .get(i)
                .ok_or_else(|| malformed(format!("{what}: cell {c} missing")))?;
            let ids = raw
                .get(i + 1..i + 1 + n)
                .ok_or_else(|| malformed(format!("{what}: cell {c} runs past the list")))?;
            conn.extend_from_slice(ids);
            offsets.push(conn.len());
            i += 1 + n;
        }
        if i != raw.len() {
            return Err(malformed(format!(
                "{what}: list size {b} does not match its {a} cells"
            )));
        }
        Cells::from_offsets(offsets, conn)
    }
}

/// Parse a legacy file. Arrays that cannot be tensors are skipped unless `wanted` names them.
pub(crate) fn parse<'a>(bytes: &'a [u8], wanted: Option<&str>) -> Res<Parsed<'a>> {
    parse_keeping(bytes, &|name, ncomp| match wanted {
        Some(w) => w == name,
        None => matches!(ncomp, 6 | 9),
    })
}

/// Parse a legacy file, decoding the arrays `keep(name, components)` accepts; the others are
/// listed but their values skipped.
pub(crate) fn parse_keeping<'a>(
    bytes: &'a [u8],
    keep: &dyn Fn(&str, usize) -> bool,
) -> Res<Parsed<'a>> {
    let mut cur = Cursor {
        b: bytes,
        pos: 0,
        binary: false,
    };
    let header = cur.raw_line().unwrap_or_default();
    let header = String::from_utf8_lossy(header);
    let version: f64 = header
        .trim()
        .rsplit(' ')
        .next()
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| {
            LoadErrorKind::NotVtk(format!("bad legacy header '{}'", esc(header.trim())))
        })?;
    let v5 = version >= 5.0;
    cur.raw_line()
        .ok_or_else(|| malformed("file ends after the header line"))?; // title
    let enc = cur
        .line()?
        .ok_or_else(|| malformed("file ends before ASCII/BINARY"))?;
    cur.binary = match enc[0].to_ascii_uppercase().as_str() {
        "ASCII" => false,
        "BINARY" => true,
        other => {
            return Err(malformed(format!(
                "expected ASCII or BINARY, found '{}'",
                esc(other)
            )));
        }
    };
    let format = if cur.binary {
        "legacy-binary"
    } else {
        "legacy-ascii"
    };

    let mut kind: Option<DatasetKind> = None;
    let mut dims: Option<[usize; 3]> = None;
    let mut origin = [0.0; 3];
    let mut spacing = [1.0; 3];
    let mut direction: Option<[[f64; 3]; 3]> = None;
    let mut points: Option<Vec<[f64; 3]>> = None;
    let mut coords: [Option<Vec<f64>>; 3] = [None, None, None];
    let mut cells: Option<Cells> = None;
    let mut cell_types: Option<Vec<u8>> = None;
    // Polydata sections in VTK cell order: verts, lines, polys, strips.
    let mut poly: [Option<Cells>; 4] = [None, None, None, None];
    let mut arrays: Vec<ArrayDesc> = Vec::new();
    let mut values: Vec<Option<Vec<f64>>> = Vec::new();
    let mut location: Option<Location> = None;
    let mut declared = 0usize;
    let npoints_limit = |points: &Option<Vec<[f64; 3]>>| points.as_ref().map_or(0, |p| p.len());

    while let Some(t) = cur.line()? {
        let kw = t[0].to_ascii_uppercase();
        match kw.as_str() {
            "DATASET" => {
                kind = Some(match arg(&t, 1, "DATASET")?.to_ascii_uppercase().as_str() {
                    "STRUCTURED_POINTS" => DatasetKind::ImageData,
                    "RECTILINEAR_GRID" => DatasetKind::RectilinearGrid,
                    "STRUCTURED_GRID" => DatasetKind::StructuredGrid,
                    "UNSTRUCTURED_GRID" => DatasetKind::UnstructuredGrid,
                    "POLYDATA" => DatasetKind::PolyData,
                    other => {
                        return Err(LoadErrorKind::UnsupportedDataset(format!(
                            "legacy DATASET {}",
                            esc(other)
                        )));
                    }
                })
            }
            "DIMENSIONS" => {
                let mut d = [0usize; 3];
                for (a, slot) in d.iter_mut().enumerate() {
                    *slot = count(t.get(a + 1), "DIMENSIONS")?;
                }
                dims = Some(d);
            }
            "ORIGIN" => origin = floats3(&t, "ORIGIN")?,
            "SPACING" | "ASPECT_RATIO" => spacing = floats3(&t, "SPACING")?,
            // Not written by VTK 9.1; newer writers emit the 9 entries of the direction matrix
            // (vtkMatrix3x3 storage, row-major). Untested against such a file.
            "DIRECTION" => {
                let mut d = [[0.0; 3]; 3];
                for (k, tok) in t[1..].iter().enumerate() {
                    if k >= 9 {
                        return Err(malformed("DIRECTION: more than 9 numbers"));
                    }
                    d[k / 3][k % 3] = parse_number(tok.as_bytes(), "DIRECTION")?;
                }
                if t.len() != 10 {
                    return Err(malformed("DIRECTION: expected 9 numbers"));
                }
                direction = Some(d);
            }
            "POINTS" => {
                let n = count(t.get(1), "POINTS")?;
                let ty = ltype(arg(&t, 2, "POINTS")?)?;
                let n3 = n
                    .checked_mul(3)
                    .ok_or_else(|| malformed("POINTS count overflows"))?;
                let v = cur.values(n3, ty, true, "POINTS")?.unwrap_or_default();
                points = Some(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
            }
            "X_COORDINATES" | "Y_COORDINATES" | "Z_COORDINATES" => {
                let a = (kw.as_bytes()[0] - b'X') as usize;
                let n = count(t.get(1), &kw)?;
                let ty = ltype(arg(&t, 2, &kw)?)?;
                coords[a] = cur.values(n, ty, true, &kw)?;
            }
            "CELLS" => cells = Some(read_cells(&mut cur, &t, v5, npoints_limit(&points))?),
            "VERTICES" | "LINES" | "POLYGONS" | "TRIANGLE_STRIPS" => {
                let slot = ["VERTICES", "LINES", "POLYGONS", "TRIANGLE_STRIPS"]
                    .iter()
                    .position(|k| *k == kw)
                    .unwrap_or(0);
                poly[slot] = Some(read_cells(&mut cur, &t, v5, npoints_limit(&points))?);
            }
            "CELL_TYPES" => {
                let n = count(t.get(1), "CELL_TYPES")?;
                let v = cur
                    .values(n, LType::Num(Scalar::I32), true, "CELL_TYPES")?
                    .unwrap_or_default();
                cell_types = Some(v.iter().map(|&x| x.clamp(0.0, 255.0) as u8).collect());
            }
            "POINT_DATA" | "CELL_DATA" => {
                declared = count(t.get(1), &kw)?;
                location = Some(if kw == "POINT_DATA" {
                    Location::Point
                } else {
                    Location::Cell
                });
            }
            "METADATA" => cur.skip_metadata(),
            "SCALARS"
            | "VECTORS"
            | "NORMALS"
            | "TENSORS"
            | "TENSORS6"
            | "TEXTURE_COORDINATES"
            | "GLOBAL_IDS"
            | "PEDIGREE_IDS"
            | "EDGE_FLAGS"
            | "COLOR_SCALARS" => {
                let loc = location
                    .ok_or_else(|| malformed(format!("{kw} before POINT_DATA or CELL_DATA")))?;
                let name = decode_name(arg(&t, 1, &kw)?);
                let ename = esc(&name);
                let (ncomp, ty) = match kw.as_str() {
                    "SCALARS" => {
                        let ty = ltype(arg(&t, 2, &kw)?)?;
                        let nc = match t.get(3) {
                            Some(s) => s
                                .parse::<usize>()
                                .map_err(|_| malformed("SCALARS: bad component count"))?,
                            None => 1,
                        };
                        // Optional LOOKUP_TABLE line.
                        if cur.peek_keyword("LOOKUP_TABLE") {
                            cur.line()?;
                        }
                        (nc, ty)
                    }
                    "VECTORS" | "NORMALS" => (3, ltype(arg(&t, 2, &kw)?)?),
                    "TENSORS" => (9, ltype(arg(&t, 2, &kw)?)?),
                    "TENSORS6" => (6, ltype(arg(&t, 2, &kw)?)?),
                    "TEXTURE_COORDINATES" => (count(t.get(2), &kw)?, ltype(arg(&t, 3, &kw)?)?),
                    "COLOR_SCALARS" => {
                        let nc = count(t.get(2), &kw)?;
                        let ty = if cur.binary {
                            LType::Num(Scalar::U8)
                        } else {
                            LType::Num(Scalar::F32)
                        };
                        (nc, ty)
                    }
                    _ => (1, ltype(arg(&t, 2, &kw)?)?),
                };
                if ncomp == 0 {
                    return Err(malformed(format!("{kw} '{ename}' has 0 components")));
                }
                let n = declared
                    .checked_mul(ncomp)
                    .ok_or_else(|| malformed(format!("{kw} '{ename}': count overflows")))?;
                let k = keep(&name, ncomp);
                let v = cur.values(n, ty, k, &format!("{kw} {ename}"))?;
                let active = kw.starts_with("TENSORS")
                    && !arrays.iter().any(|a| a.active && a.location == Some(loc));
                arrays.push(ArrayDesc {
                    name,
                    ncomp,
                    ntuples: Some(declared),
                    location: Some(loc),
                    active,
                });
                values.push(v);
            }
            "LOOKUP_TABLE" => {
                let n = count(t.get(2), "LOOKUP_TABLE")?;
                let ty = if cur.binary {
                    LType::Num(Scalar::U8)
                } else {
                    LType::Num(Scalar::F32)
                };
                let n4 = n
                    .checked_mul(4)
                    .ok_or_else(|| malformed("LOOKUP_TABLE size overflows"))?;
                cur.values(n4, ty, false, "LOOKUP_TABLE")?;
            }
            "FIELD" => {
                let narr = count(t.get(2), "FIELD")?;
                for _ in 0..narr {
                    let h = cur
                        .line()?
                        .ok_or_else(|| malformed("FIELD: file ends before all arrays"))?;
                    if h[0] == "NULL_ARRAY" {
                        continue;
                    }
                    if h[0].eq_ignore_ascii_case("METADATA") {
                        cur.skip_metadata();
                        continue;
                    }
                    let name = decode_name(h[0]);
                    let what = format!("FIELD array {}", esc(&name));
                    let ncomp = count(h.get(1), &what)?;
                    let ntup = count(h.get(2), &what)?;
                    let ty = ltype(arg(&h, 3, &what)?)?;
                    let n = ncomp
                        .checked_mul(ntup)
                        .ok_or_else(|| malformed(format!("{what}: count overflows")))?;
                    let k = location.is_some() && keep(&name, ncomp);
                    let v = cur.values(n, ty, k, &what)?;
                    if cur.peek_keyword("METADATA") {
                        cur.line()?;
                        cur.skip_metadata();
                    }
                    arrays.push(ArrayDesc {
                        name,
                        ncomp,
                        ntuples: Some(ntup),
                        location,
                        active: false,
                    });
                    values.push(v);
                }
            }
            other => {
                return Err(malformed(format!(
                    "unknown keyword '{}' near byte {}",
                    esc(other),
                    cur.pos
                )));
            }
        }
    }

    let kind = kind.ok_or_else(|| {
        LoadErrorKind::UnsupportedDataset("no DATASET section (field-only or empty file)".into())
    })?;
    let geometry = match kind {
        DatasetKind::ImageData => {
            let d = dims.ok_or_else(|| malformed("STRUCTURED_POINTS without DIMENSIONS"))?;
            let mut extent = [0i64; 6];
            for a in 0..3 {
                extent[2 * a + 1] = i64::try_from(d[a]).unwrap_or(i64::MAX) - 1;
                if d[a] == 0 {
                    return Err(malformed(format!("DIMENSIONS {d:?} has a zero")));
                }
            }
            Geometry::Image {
                extent,
                origin,
                spacing,
                direction,
            }
        }
        DatasetKind::RectilinearGrid => {
            let [x, y, z] = coords;
            let c = [
                x.ok_or_else(|| malformed("missing X_COORDINATES"))?,
                y.ok_or_else(|| malformed("missing Y_COORDINATES"))?,
                z.ok_or_else(|| malformed("missing Z_COORDINATES"))?,
            ];
            if let Some(d) = dims
                && d != [c[0].len(), c[1].len(), c[2].len()]
            {
                return Err(malformed(format!(
                    "DIMENSIONS {d:?} do not match the coordinate counts"
                )));
            }
            Geometry::Rectilinear { coords: c }
        }
        DatasetKind::StructuredGrid => {
            let d = dims.ok_or_else(|| malformed("STRUCTURED_GRID without DIMENSIONS"))?;
            let points = points.unwrap_or_default();
            let n = d[0].checked_mul(d[1]).and_then(|v| v.checked_mul(d[2]));
            if n != Some(points.len()) {
                return Err(malformed(format!(
                    "DIMENSIONS {d:?} do not match the {} points",
                    points.len()
                )));
            }
            Geometry::Points {
                points,
                dims: Some(d),
                cells: None,
            }
        }
        DatasetKind::UnstructuredGrid => {
            let mut c = cells.unwrap_or_else(|| Cells {
                offsets: vec![0],
                ..Cells::default()
            });
            let types = cell_types.unwrap_or_default();
            if types.len() != c.len() {
                return Err(malformed(format!(
                    "{} CELL_TYPES for {} cells",
                    types.len(),
                    c.len()
                )));
            }
            c.types = types;
            Geometry::Points {
                points: points.unwrap_or_default(),
                dims: None,
                cells: Some(c),
            }
        }
        DatasetKind::PolyData => {
            let mut all = Cells {
                offsets: vec![0],
                ..Cells::default()
            };
            for (sec, cells) in poly.into_iter().enumerate() {
                if let Some(cells) = cells {
                    all.append(cells, Some(sec));
                }
            }
            Geometry::Points {
                points: points.unwrap_or_default(),
                dims: None,
                cells: Some(all),
            }
        }
    };
    Ok(Parsed {
        format,
        kind,
        geometry,
        arrays,
        load: Box::new(move |i| {
            values
                .get_mut(i)
                .and_then(Option::take)
                .ok_or_else(|| malformed("the array is not numeric"))
        }),
    })
}

/// Legacy names encode special characters as `%xx`.
fn decode_name(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && i + 2 < b.len()
            && let Some(v) = std::str::from_utf8(&b[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
