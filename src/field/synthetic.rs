//! Built-in demo fields and a legacy VTK writer for them.
//!
//! # The analytic field
//!
//! On an `n × n × n` lattice with unit spacing and origin 0 (x fastest, as VTK orders points),
//! with normalised coordinates `u, v, w = i/(n−1), j/(n−1), k/(n−1)` in [0, 1]:
//!
//! * **Shape.** A phase angle `θ = 2π (0.9 u + 0.55 v) + 1.3 sin(π w)` runs around the Westin
//!   triangle. Soft-max weights of three cosines 120° apart,
//!   `a_c = exp(β cos(θ − 2πc/3)) / Σ_c' exp(β cos(θ − 2πc'/3))`, `c = 0, 1, 2`, `β = 2.6`,
//!   are barycentric coordinates in that triangle. They are pulled towards the triangle's centre
//!   in a band around the middle slab, `b_c = (1 − m) a_c + m/3` with `m = 0.7 sin⁴(π w)`, and the
//!   target λ1-normalised Westin measures are `cl = 0.95 b_0`, `cp = 0.95 b_1`,
//!   `cs = 0.05 + 0.95 b_2`. Near each phase `2πc/3` one shape dominates (cigar, pancake, ball);
//!   between them, and in the middle band, the field passes through unclassified tensors.
//!   grid40 shares (τ = 0.5): linear 28%, planar 26%, spherical 32%, unclassified 14%.
//! * **Eigenvalues.** `λ = s · (1, 1 − cl, cs)`, which has exactly those Westin measures, with a
//!   smoothly varying size `s = 1 + 0.5 sin(π (u + w)) + 0.25 v` in [0.5, 1.75]. All eigenvalues are at
//!   least `0.05 s > 0`: the field is positive definite.
//! * **Eigenvectors.** `O = Rz(α) Ry(β') Rx(γ)` with `α = π (u + 0.5 w)`,
//!   `β' = 0.8 π (v − 0.5)`, `γ = 0.5 π w`: the frame rotates smoothly through the volume.
//!
//! `T = O diag(λ) Oᵀ`, stored row-major (exactly symmetric by construction).
//!
//! Generation writes straight into the final vector in parallel (no intermediate buffers), the
//! positions implied by the lattice: `grid(256)` (16.7 M tensors) needs 72 bytes per point,
//! about 1.2 GB (the tensors are the analytic field's f64 values).

use std::f64::consts::PI;
use std::io::Write;
use std::path::Path;

use rayon::prelude::*;

use super::tensor_field::{DatasetKind, Location, Positions, TensorField, Tensors};

/// Soft-max sharpness of the shape weights (larger: fewer unclassified tensors).
const SHAPE_BETA: f64 = 2.6;
/// Largest pull of the shape weights towards the centre of the Westin triangle.
const CENTRE_PULL: f64 = 0.7;

/// The standard 40 × 40 × 40 demo field (64,000 tensors).
pub fn grid40() -> TensorField {
    grid(40)
}

/// The analytic `n × n × n` demo field described in the module docs.
pub fn grid(n: usize) -> TensorField {
    let total = n * n * n;
    let inv = if n > 1 { 1.0 / (n - 1) as f64 } else { 0.0 };
    let ijk = |idx: usize| (idx % n, (idx / n) % n, idx / (n * n));

    let mut tensors = Vec::new();
    (0..total)
        .into_par_iter()
        .map(|idx| {
            let (i, j, k) = ijk(idx);
            analytic_tensor(i as f64 * inv, j as f64 * inv, k as f64 * inv)
        })
        .collect_into_vec(&mut tensors);

    TensorField {
        format: "synthetic".into(),
        dataset: DatasetKind::ImageData,
        dims: Some([n; 3]),
        cells: n.saturating_sub(1).pow(3),
        spacing: Some(1.0),
        positions: Positions::Lattice {
            dims: [n; 3],
            to_world: [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
            ],
        },
        points: total,
        tensors: Tensors::F64(tensors),
        ..TensorField::from_points(Vec::new(), Vec::new())
    }
}

/// The tensor at normalised coordinates `(u, v, w)` (module docs).
pub fn analytic_tensor(u: f64, v: f64, w: f64) -> [f64; 9] {
    let [l1, l2, l3] = analytic_eigenvalues(u, v, w);
    let o = analytic_frame(u, v, w);
    let lam = [l1, l2, l3];
    let mut t = [0.0; 9];
    for r in 0..3 {
        for c in r..3 {
            let x = (0..3).map(|m| lam[m] * o[r][m] * o[c][m]).sum::<f64>();
            t[3 * r + c] = x;
            t[3 * c + r] = x;
        }
    }
    t
}

/// Eigenvalues `s (1, 1 − cl, cs)` at `(u, v, w)`, descending.
pub fn analytic_eigenvalues(u: f64, v: f64, w: f64) -> [f64; 3] {
    let theta = 2.0 * PI * (0.9 * u + 0.55 * v) + 1.3 * (PI * w).sin();
    let e: [f64; 3] =
        std::array::from_fn(|c| (SHAPE_BETA * (theta - 2.0 * PI * c as f64 / 3.0).cos()).exp());
    let sum = e[0] + e[1] + e[2];
    let m = CENTRE_PULL * (PI * w).sin().powi(4);
    let a = |c: usize| (1.0 - m) * e[c] / sum + m / 3.0;
    let cl = 0.95 * a(0);
    let cs = 0.05 + 0.95 * a(2);
    let s = 1.0 + 0.5 * (PI * (u + w)).sin() + 0.25 * v;
    [s, s * (1.0 - cl), s * cs]
}

/// Rotation `Rz(α) Ry(β') Rx(γ)` at `(u, v, w)`, row-major `o[row][col]`.
fn analytic_frame(u: f64, v: f64, w: f64) -> [[f64; 3]; 3] {
    let (sa, ca) = (PI * (u + 0.5 * w)).sin_cos();
    let (sb, cb) = (0.8 * PI * (v - 0.5)).sin_cos();
    let (sg, cg) = (0.5 * PI * w).sin_cos();
    let rz = [[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]];
    let ry = [[cb, 0.0, sb], [0.0, 1.0, 0.0], [-sb, 0.0, cb]];
    let rx = [[1.0, 0.0, 0.0], [0.0, cg, -sg], [0.0, sg, cg]];
    mul(&mul(&rz, &ry), &rx)
}

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}

/// Write a point-data field on an axis-aligned lattice (image data without a direction matrix,
/// e.g. [`grid`]) as legacy VTK 4.2 binary `STRUCTURED_POINTS` with a 9-component
/// `TENSORS <name> double` array (big-endian, as the legacy format requires).
///
/// ORIGIN is the first position; SPACING per axis is the distance to the next point along that
/// axis (or `field.spacing`, else 1, for axes with a single point). The file is written with
/// [`crate::image_out::write_atomic`]: whole or not at all, through symlinks, never over a FIFO
/// or device. Fields without `dims`, with cell data or with a direction matrix are rejected with
/// `InvalidInput`.
pub fn write_legacy_vtk(field: &TensorField, path: &Path) -> std::io::Result<()> {
    use std::io::{Error, ErrorKind};
    let invalid = |m: &str| Error::new(ErrorKind::InvalidInput, m.to_string());
    let dims = field
        .dims
        .ok_or_else(|| invalid("write_legacy_vtk needs a structured field (dims)"))?;
    if field.array.location != Location::Point {
        return Err(invalid("write_legacy_vtk writes point data only"));
    }
    if field.direction.is_some() {
        return Err(invalid(
            "write_legacy_vtk cannot write a direction matrix (STRUCTURED_POINTS is axis-aligned)",
        ));
    }
    let n = dims[0] * dims[1] * dims[2];
    if field.tensors.len() != n || field.positions.len() != n {
        return Err(invalid("field size does not match its dims"));
    }
    let origin = if n > 0 { field.position(0) } else { [0.0; 3] };
    let stride = [1, dims[0], dims[0] * dims[1]];
    let spacing: [f64; 3] = std::array::from_fn(|k| {
        if dims[k] > 1 {
            field.position(stride[k])[k] - origin[k]
        } else {
            field.spacing.unwrap_or(1.0)
        }
    });
    let name: String = field
        .array
        .name
        .chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect();
    let name = if name.is_empty() {
        "tensors".into()
    } else {
        name
    };

    crate::image_out::write_atomic(path, &[], |w| {
        write!(
            w,
            "# vtk DataFile Version 4.2\ntensorglyph {} field\nBINARY\nDATASET STRUCTURED_POINTS\n\
             DIMENSIONS {} {} {}\nORIGIN {:?} {:?} {:?}\nSPACING {:?} {:?} {:?}\n\
             POINT_DATA {}\nTENSORS {} double\n",
            field.format,
            dims[0],
            dims[1],
            dims[2],
            origin[0],
            origin[1],
            origin[2],
            spacing[0],
            spacing[1],
            spacing[2],
            n,
            name
        )?;
        let mut buf = Vec::with_capacity(72 * 1024);
        for chunk in (0..n).collect::<Vec<_>>().chunks(1024) {
            buf.clear();
            for t in chunk.iter().map(|&i| field.tensor(i)) {
                for x in t {
                    buf.extend_from_slice(&x.to_be_bytes());
                }
            }
            w.write_all(&buf)?;
        }
        w.write_all(b"\n")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::derive_glyphs;
    use crate::tensor::eigen::symmetric_eigen;

    #[test]
    fn grid40_has_all_classes() {
        let f = grid40();
        assert_eq!(f.len(), 64_000);
        assert_eq!(f.position(1), [1.0, 0.0, 0.0]);
        assert_eq!(f.position(40), [0.0, 1.0, 0.0]);
        assert_eq!(f.position(63_999), [39.0, 39.0, 39.0]);
        let set = derive_glyphs(&f, &crate::progress::Silent);
        let s = &set.stats;
        assert_eq!(s.valid, 64_000);
        assert_eq!(s.indefinite, 0);
        assert_eq!(s.symmetrised, 0);
        let share = s.classes.map(|c| c as f64 / s.valid as f64);
        eprintln!("grid40 class shares (l, p, s, u): {share:?}");
        for (k, sh) in share.iter().enumerate().take(3) {
            assert!(*sh >= 0.15, "class {k} share {sh}");
        }
        assert!(share[3] > 0.05, "unclassified share {}", share[3]);
        assert!(s.eigenvalues_min[2] > 0.0);
    }

    #[test]
    fn analytic_eigen_matches_decomposition() {
        for &(u, v, w) in &[(0.1, 0.2, 0.3), (0.9, 0.5, 0.0), (0.33, 0.77, 1.0)] {
            let t = analytic_tensor(u, v, w);
            let e = symmetric_eigen(&t);
            let want = analytic_eigenvalues(u, v, w);
            for k in 0..3 {
                assert!((e.values[k] - want[k]).abs() < 1e-12 * want[0]);
            }
        }
    }

    #[test]
    fn smooth_between_neighbours() {
        // Adjacent lattice tensors in grid(40) differ by a small fraction of their size.
        let f = grid(40);
        let norm = |t: &[f64; 9]| t.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut worst = 0.0f64;
        for idx in (0..f.len() - 1).step_by(7) {
            if (idx + 1) % 40 == 0 {
                continue;
            }
            let (a, b) = (&f.tensor(idx), &f.tensor(idx + 1));
            let d: [f64; 9] = std::array::from_fn(|k| a[k] - b[k]);
            worst = worst.max(norm(&d) / norm(a));
        }
        assert!(worst < 0.35, "max relative jump {worst}");
    }

    #[test]
    fn legacy_round_trip() {
        let f = grid(5);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g5.vtk");
        write_legacy_vtk(&f, &path).unwrap();
        // no temporary left behind
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let bytes = std::fs::read(&path).unwrap();
        let vtk = vtkio::Vtk::parse_legacy_be(&bytes[..]).unwrap();
        use vtkio::model::{Attribute, DataSet};
        let DataSet::ImageData {
            extent,
            origin,
            spacing,
            pieces,
            ..
        } = vtk.data
        else {
            panic!("not image data");
        };
        assert_eq!(origin, [0.0; 3]);
        assert_eq!(spacing, [1.0; 3]);
        let vtkio::model::Extent::Dims(d) = extent else {
            panic!("extent {extent:?}");
        };
        assert_eq!(d, [5, 5, 5]);
        let vtkio::model::Piece::Inline(piece) = &pieces[0] else {
            panic!("piece not inline");
        };
        let Attribute::DataArray(arr) = &piece.data.point[0] else {
            panic!("not a data array");
        };
        assert_eq!(arr.name, "tensors");
        let vals: Vec<f64> = arr.data.cast_into().unwrap();
        assert_eq!(vals.len(), 125 * 9);
        for (i, t) in f.tensors.iter().enumerate() {
            assert_eq!(&vals[9 * i..9 * i + 9], &t[..]);
        }
    }

    #[test]
    fn writer_rejects_unstructured() {
        let mut f = grid(2);
        f.dims = None;
        let dir = tempfile::tempdir().unwrap();
        let e = write_legacy_vtk(&f, &dir.path().join("x.vtk")).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    }
}
