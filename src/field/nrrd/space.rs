//! Where a NRRD lattice is in the world: `space`, `space directions` (or `spacings`) and
//! `space origin`, turned into RAS+.

use nalgebra::{Matrix3, Matrix4, Vector3};

use super::header::{Header, Res, field, number, vector, vectors};
use crate::error::escape_for_error;

/// Signs that take the file's space to RAS+, and the name of that space.
fn space_to_ras(h: &Header) -> Res<(Vector3<f64>, &'static str)> {
    let Some(s) = h.get("space") else {
        return Ok((Vector3::new(1.0, 1.0, 1.0), "unknown (as stored)"));
    };
    let code = match s.to_ascii_lowercase().as_str() {
        "right-anterior-superior" | "ras" => "RAS",
        "left-anterior-superior" | "las" => "LAS",
        "left-posterior-superior" | "lps" => "LPS",
        "scanner-xyz" | "3d-right-handed" | "3d-left-handed" => "scanner",
        _ => {
            return Err(field(
                "space",
                format!(
                    "'{}' is not a 3-D space this reader knows (RAS, LAS, LPS, scanner-xyz)",
                    escape_for_error(s)
                ),
            ));
        }
    };
    let sign = match code {
        "LAS" => Vector3::new(-1.0, 1.0, 1.0),
        "LPS" => Vector3::new(-1.0, -1.0, 1.0),
        _ => Vector3::new(1.0, 1.0, 1.0),
    };
    Ok((sign, if code == "scanner" { "scanner" } else { "RAS" }))
}

/// Where the lattice is in the world.
pub(super) struct Placement {
    /// Voxel to world (RAS+ unless the space is `scanner`).
    pub(super) a: Matrix4<f64>,
    /// The linear part of `a`.
    pub(super) linear: Matrix3<f64>,
    /// The signs taking the file's space to RAS+, as a diagonal matrix.
    pub(super) s: Matrix3<f64>,
    pub(super) world: &'static str,
    pub(super) source: &'static str,
}

/// Geometry: space directions (or spacings), origin, then the space's signs to RAS+.
/// `leading` axes come before the three spatial ones (the tensor axis), with `none` for a
/// direction.
pub(super) fn placement(h: &Header, leading: usize) -> Res<Placement> {
    let (sign, world) = space_to_ras(h)?;
    let s = Matrix3::from_diagonal(&sign);
    let (dirs, source) = match h.get("space directions") {
        Some(v) => {
            let v = vectors("space directions", v)?;
            if v.len() != leading + 3
                || v[..leading].iter().any(Option::is_some)
                || v[leading..].iter().any(Option::is_none)
            {
                return Err(field(
                    "space directions",
                    if leading == 0 {
                        "needs three vectors"
                    } else {
                        "needs 'none' for the tensor axis and three vectors"
                    },
                ));
            }
            let cols: Vec<Vector3<f64>> = v[leading..].iter().flatten().copied().collect();
            (Matrix3::from_columns(&cols), "space directions")
        }
        None => match h.get("spacings") {
            Some(sp) => {
                let sp: Vec<f64> = sp
                    .split_whitespace()
                    .skip(leading)
                    .map(|x| number("spacings", x))
                    .collect::<Res<_>>()?;
                if sp.len() != 3 || !sp.iter().all(|x| x.is_finite() && *x != 0.0) {
                    return Err(field("spacings", "needs three finite non-zero spacings"));
                }
                (
                    Matrix3::from_diagonal(&Vector3::new(sp[0], sp[1], sp[2])),
                    "spacings",
                )
            }
            None => (Matrix3::identity(), "none (unit voxels)"),
        },
    };
    let origin = match h.get("space origin") {
        Some(o) => vector("space origin", o)?
            .ok_or_else(|| field("space origin", "'none' is not an origin"))?,
        None => Vector3::zeros(),
    };
    let linear = s * dirs;
    let mut a = Matrix4::identity();
    a.fixed_view_mut::<3, 3>(0, 0).copy_from(&linear);
    a.fixed_view_mut::<3, 1>(0, 3).copy_from(&(s * origin));
    Ok(Placement {
        a,
        linear,
        s,
        world,
        source,
    })
}
