//! Parallel image data: a `.pvti` names its pieces, each a `.vti` placed in the whole extent.

use std::path::Path;

use super::attrs::{count_attr, direction, extent, floats};
use super::decode::header_ctx;
use super::serial::parse_serial;
use super::tokenize::{Doc, tokenize};
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::inputs::Inputs;
use crate::field::options::ReadOptions;
use crate::field::tensor_field::{DatasetKind, Location, TensorField};
use crate::field::vtk::assemble::assemble;
use crate::field::vtk::binary::try_vec;
use crate::field::vtk::dataset::{ArrayDesc, Geometry, Parsed, pick, point_dims};
use crate::field::vtk::malformed::{Res, malformed};

/// Read a `.pvti` and merge its pieces into one field in whole-extent order.
pub(super) fn read_pvti(
    inputs: &Inputs,
    path: &Path,
    doc: &Doc,
    opts: &ReadOptions,
) -> Res<TensorField> {
    let ds = doc
        .tags
        .iter()
        .find(|t| t.name == "PImageData")
        .ok_or_else(|| malformed("no <PImageData> element"))?;
    let whole = extent(ds.get("WholeExtent"), "WholeExtent")?;
    let origin = floats::<3>(ds.get("Origin"), "Origin")?.unwrap_or([0.0; 3]);
    let spacing = floats::<3>(ds.get("Spacing"), "Spacing")?.unwrap_or([1.0; 3]);
    let dir = direction(ds.get("Direction"))?;
    let mut arrays = Vec::new();
    for (sec, loc) in [
        ("PPointData", Location::Point),
        ("PCellData", Location::Cell),
    ] {
        let active = doc
            .tags
            .iter()
            .find(|t| t.name == sec)
            .and_then(|s| s.get("Tensors"));
        for t in doc
            .tags
            .iter()
            .filter(|t| t.name == "PDataArray" && doc.parent(t) == sec)
        {
            let name = t.get("Name").unwrap_or("").to_string();
            arrays.push(ArrayDesc {
                active: active == Some(name.as_str()),
                ncomp: count_attr(t, "NumberOfComponents")?.max(1),
                name,
                ntuples: None,
                location: Some(loc),
            });
        }
    }
    let idx = pick(&arrays, opts.array.as_deref())?;
    let want = arrays[idx].clone();
    let loc = want.location.unwrap_or(Location::Point);
    let ncomp = want.ncomp;
    let lattice = |e: &[i64; 6]| -> [i64; 6] {
        // Cell extents: one fewer per non-flat axis.
        match loc {
            Location::Point => *e,
            Location::Cell => {
                let mut c = *e;
                for a in 0..3 {
                    if c[2 * a + 1] > c[2 * a] {
                        c[2 * a + 1] -= 1;
                    }
                }
                c
            }
        }
    };
    let wl = lattice(&whole);
    let wd = point_dims(&wl)?;
    let mut pieces: Vec<([i64; 6], Vec<f64>)> = Vec::new();
    let mut total = 0usize;
    // Each piece file once: a listing that repeats one would make us read and hold it again and
    // again.
    let mut seen = Vec::new();
    for t in doc.tags.iter().filter(|t| t.name == "Piece") {
        let src = t
            .get("Source")
            .ok_or_else(|| malformed("<Piece> without Source"))?;
        let piece_err = |k: LoadErrorKind| malformed(format!("piece '{}': {k}", esc(src)));
        let ppath = Inputs::detached(path, src.as_bytes())
            .map_err(|e| malformed(format!("piece {e}")))?
            .path;
        if let Some(id) = inputs.identity(&ppath) {
            if seen.contains(&id) {
                return Err(piece_err(malformed("the same file is listed twice")));
            }
            seen.push(id);
        }
        let bytes = inputs.read(&ppath).map_err(piece_err)?;
        let pdoc = tokenize(&bytes).map_err(piece_err)?;
        let (pctx, pty) = header_ctx(&bytes, &pdoc).map_err(piece_err)?;
        if pty != "ImageData" {
            return Err(piece_err(LoadErrorKind::UnsupportedDataset(format!(
                "piece type '{}', expected ImageData",
                esc(&pty)
            ))));
        }
        let mut parsed = parse_serial(&pctx, &pdoc, &pty).map_err(piece_err)?;
        let Geometry::Image { extent: pe, .. } = parsed.geometry else {
            return Err(piece_err(malformed("not image data")));
        };
        let i = parsed
            .arrays
            .iter()
            .position(|a| a.name == want.name && a.location == want.location)
            .ok_or_else(|| {
                piece_err(LoadErrorKind::ArrayNotFound {
                    name: want.name.clone(),
                    available: parsed
                        .arrays
                        .iter()
                        .take(20)
                        .map(|a| format!("'{}'", esc(&a.name)))
                        .collect::<Vec<_>>()
                        .join(", "),
                })
            })?;
        if parsed.arrays[i].ncomp != ncomp {
            return Err(piece_err(LoadErrorKind::ComponentCount {
                name: want.name.clone(),
                components: parsed.arrays[i].ncomp,
            }));
        }
        // Placed before it is decoded: a piece outside the whole extent is refused cheaply.
        let pl = lattice(&pe);
        for a in 0..3 {
            if pl[2 * a] < wl[2 * a] || pl[2 * a + 1] > wl[2 * a + 1] {
                return Err(piece_err(malformed(format!(
                    "extent {pe:?} is outside the whole extent {whole:?}"
                ))));
            }
        }
        let v = (parsed.load)(i).map_err(piece_err)?;
        let pd = point_dims(&pl)?;
        let n = pd[0] * pd[1] * pd[2];
        if v.len() != n * ncomp {
            return Err(piece_err(LoadErrorKind::TupleCount {
                name: want.name.clone(),
                found: v.len() / ncomp,
                expected: n,
                location: loc.as_str(),
            }));
        }
        total += n;
        pieces.push((pl, v));
    }
    let wn = wd[0]
        .checked_mul(wd[1])
        .and_then(|v| v.checked_mul(wd[2]))
        .ok_or_else(|| malformed("WholeExtent overflows"))?;
    if total < wn {
        return Err(malformed(format!(
            "the pieces hold {total} {}s but the whole extent has {wn}",
            loc.as_str()
        )));
    }
    let mut merged = try_vec::<f64>(wn * ncomp)?;
    merged.resize(wn * ncomp, f64::NAN);
    let mut covered = vec![false; wn];
    for (pl, v) in &pieces {
        let pd = point_dims(pl)?;
        let mut s = 0;
        for k in 0..pd[2] {
            for j in 0..pd[1] {
                for i in 0..pd[0] {
                    let wi = (pl[0] - wl[0]) as usize + i;
                    let wj = (pl[2] - wl[2]) as usize + j;
                    let wk = (pl[4] - wl[4]) as usize + k;
                    let w = wi + wd[0] * (wj + wd[1] * wk);
                    merged[w * ncomp..(w + 1) * ncomp]
                        .copy_from_slice(&v[s * ncomp..(s + 1) * ncomp]);
                    covered[w] = true;
                    s += 1;
                }
            }
        }
    }
    if let Some(gap) = covered.iter().position(|c| !c) {
        return Err(malformed(format!(
            "the pieces do not cover the whole extent ({} {gap} missing)",
            loc.as_str()
        )));
    }
    let mut merged = Some(merged);
    let parsed = Parsed {
        format: "pvti",
        kind: DatasetKind::ImageData,
        geometry: Geometry::Image {
            extent: whole,
            origin,
            spacing,
            direction: dir,
        },
        arrays,
        load: Box::new(move |_| merged.take().ok_or_else(|| malformed("merged twice"))),
    };
    assemble(parsed, opts)
}
