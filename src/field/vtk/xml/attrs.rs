//! Numbers held in attributes: coordinates, extents, direction matrices and counts.

use super::tokenize::Tag;
use crate::error::escape_for_error as esc;
use crate::field::vtk::binary::parse_number;
use crate::field::vtk::dataset::point_dims;
use crate::field::vtk::malformed::{Res, malformed};

pub(super) fn floats<const N: usize>(s: Option<&str>, what: &str) -> Res<Option<[f64; N]>> {
    let Some(s) = s else { return Ok(None) };
    let v: Vec<f64> = s
        .split_ascii_whitespace()
        .map(|t| parse_number(t.as_bytes(), what))
        .collect::<Res<_>>()?;
    v.try_into()
        .map(Some)
        .map_err(|_| malformed(format!("{what}: expected {N} numbers")))
}

pub(super) fn extent(s: Option<&str>, what: &str) -> Res<[i64; 6]> {
    let s = s.ok_or_else(|| malformed(format!("missing {what}")))?;
    let v: Vec<i64> = s
        .split_ascii_whitespace()
        .map(|t| t.parse::<i64>())
        .collect::<Result<_, _>>()
        .map_err(|_| malformed(format!("{what}: not integers")))?;
    let e: [i64; 6] = v
        .try_into()
        .map_err(|_| malformed(format!("{what}: expected 6 integers")))?;
    if e.iter().any(|x| x.unsigned_abs() > 1 << 40) {
        return Err(malformed(format!("{what}: implausible extent {e:?}")));
    }
    point_dims(&e)?;
    Ok(e)
}

pub(super) fn direction(s: Option<&str>) -> Res<Option<[[f64; 3]; 3]>> {
    Ok(floats::<9>(s, "Direction")?
        .map(|d| [[d[0], d[1], d[2]], [d[3], d[4], d[5]], [d[6], d[7], d[8]]]))
}

pub(super) fn count_attr(t: &Tag, k: &str) -> Res<usize> {
    match t.get(k) {
        None => Ok(0),
        Some(v) => v.trim().parse().map_err(|_| {
            malformed(format!(
                "<{}> {k}='{}' is not a count",
                esc(&t.name),
                esc(v)
            ))
        }),
    }
}
