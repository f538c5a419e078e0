//! A scalar volume from VTK image data: XML `.vti` or legacy `STRUCTURED_POINTS`, with one
//! one-component point-data array.
//!
//! The same parsers as the tensor reader, so counts are checked against the bytes in the same
//! way. XML files decode only the picked array; legacy files decode their one-component arrays
//! (the first point array can only be told once the file is read: VTK writes cell data first)
//! and skip every other array's values.

use super::dataset::{Geometry, Parsed, describe_arrays, point_dims, product};
use super::family::{Family, family};
use super::malformed::Res;
use super::{legacy, xml};
use crate::error::LoadErrorKind;
use crate::field::scalar::{self, ScalarVolume};
use crate::field::tensor_field::Location;

/// A scalar volume from the bytes of a VTK file.
pub(crate) fn parse_scalar_bytes(bytes: &[u8]) -> Res<ScalarVolume> {
    match family(bytes)? {
        Family::Legacy => image_scalars(legacy::parse_keeping(bytes, &|_, ncomp| ncomp == 1)?),
        Family::Xml => xml::with_serial(bytes, image_scalars),
    }
}

fn image_scalars(mut p: Parsed<'_>) -> Res<ScalarVolume> {
    let Geometry::Image {
        extent,
        origin,
        spacing,
        direction,
    } = p.geometry
    else {
        return Err(LoadErrorKind::UnsupportedDataset(format!(
            "{}: a scalar volume is image data (.vti, or legacy STRUCTURED_POINTS)",
            p.kind.as_str()
        )));
    };
    let dims = point_dims(&extent)?;
    let points = product(dims)?;
    // VTK's active scalars are usually the first such array; any other is named in the error.
    let idx = p
        .arrays
        .iter()
        .position(|a| a.location == Some(Location::Point) && a.ncomp == 1)
        .ok_or_else(|| {
            LoadErrorKind::Other(format!(
                "no one-component point-data array to read as a scalar volume; arrays present: {}",
                describe_arrays(&p.arrays)
            ))
        })?;
    let desc = p.arrays[idx].clone();
    let count_error = |found| LoadErrorKind::TupleCount {
        name: desc.name.clone(),
        found,
        expected: points,
        location: "point",
    };
    if let Some(n) = desc.ntuples
        && n != points
    {
        return Err(count_error(n));
    }
    let values = (p.load)(idx)?;
    if values.len() != points {
        return Err(count_error(values.len()));
    }
    let r = direction.unwrap_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    // Index (extent[0] + i, ...) sits at origin + R diag(spacing) index, as the tensor reader
    // places points: the volume's voxel (i, j, k) starts at the extent's lower corner.
    let first = [extent[0], extent[2], extent[4]].map(|e| e as f64);
    let mut m = [[0.0; 4]; 4];
    for row in 0..3 {
        for col in 0..3 {
            m[row][col] = r[row][col] * spacing[col];
        }
        m[row][3] = origin[row] + (0..3).map(|c| m[row][c] * first[c]).sum::<f64>();
    }
    m[3][3] = 1.0;
    scalar::checked(
        dims,
        values.into_iter().map(|v| v as f32).collect(),
        m,
        "Spacing",
    )
}
