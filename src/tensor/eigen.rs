//! Eigendecomposition of symmetric 3x3 tensors (tensor-shape.md, section 1).
//!
//! `T = O Λ Oᵀ`, `Λ = diag(λ1, λ2, λ3)` with `λ1 ≥ λ2 ≥ λ3` (signed), `O = [e1 e2 e3]` orthonormal
//! and right-handed (`det O = +1`), in f64.
//!
//! The production path is a cyclic Jacobi solver specialised to 3x3 ([`jacobi_eigen`]), started
//! from a closed-form estimate of the best-separated eigenvector ([`jacobi_eigen_hybrid`]) so
//! that it usually needs one full rotation plus a few tiny ones. It is about 2.3x faster than
//! nalgebra's generic `SymmetricEigen` (kept as [`nalgebra_eigen`] and cross-checked in the
//! tests) with the same backward accuracy (Jacobi converges to f64 round-off from any orthonormal
//! start). Diagonal tensors (all off-diagonal entries exactly zero, common in synthetic and
//! masked data) take an exact fast path.
//!
//! Matrices are row-major `[f64; 9]`: `t[3 * row + col]`.

use nalgebra::{Matrix3, SymmetricEigen};

/// Eigenvalues (descending, signed) and the matching unit eigenvectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eigen {
    /// `λ1 ≥ λ2 ≥ λ3`.
    pub values: [f64; 3],
    /// `vectors[i] = e_i`, the columns of `O`; orthonormal with `e3 = e1 × e2` (det +1).
    pub vectors: [[f64; 3]; 3],
}

/// Relative tolerance for "non-symmetric": a tensor counts as non-symmetric when
/// `max_{i<j} |a_ij − a_ji| > SYMMETRY_TOL · max_ij |a_ij|`.
///
/// 1e-6 is about 16 f32 ulps: tensors computed in f32 (or written with ~7 significant digits)
/// whose two off-diagonal copies differ only by round-off are not reported, while a genuine
/// asymmetry (e.g. a velocity gradient, or a mis-ordered 6-component array) is.
pub const SYMMETRY_TOL: f64 = 1e-6;

/// `(A + Aᵀ)/2`, and whether `A` was non-symmetric beyond [`SYMMETRY_TOL`] (relative to the largest
/// absolute entry). The average is always returned, so exact round-off asymmetries are removed too.
/// Non-finite input gives `false` for the flag (it is skipped elsewhere).
#[inline]
pub fn symmetrise(t: &[f64; 9]) -> ([f64; 9], bool) {
    let pairs = [(1usize, 3usize), (2, 6), (5, 7)];
    let mut out = *t;
    let mut asym = 0.0f64;
    for &(a, b) in &pairs {
        let m = mean(t[a], t[b]);
        // May be +inf for entries of opposite sign near f64::MAX: then it is flagged, rightly.
        asym = asym.max((t[a] - t[b]).abs());
        out[a] = m;
        out[b] = m;
    }
    if asym == 0.0 {
        return (out, false);
    }
    let scale = t.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (out, asym > SYMMETRY_TOL * scale)
}

/// `(a + b) / 2` without overflow near f64::MAX (halving first would round subnormals, so that
/// is done only when the sum overflows).
#[inline]
fn mean(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s.is_finite() {
        0.5 * s
    } else {
        0.5 * a + 0.5 * b
    }
}

/// `x · 2^e`, exact unless the result overflows or is subnormal. `2f64.powi(e)` alone is not:
/// it overflows for `e > 1023` (rescaling a subnormal tensor needs up to 2^1074) and is itself
/// subnormal below 2^-1022.
#[inline]
pub(crate) fn mul_pow2(mut x: f64, mut e: i32) -> f64 {
    const STEP: i32 = 1000;
    while e > STEP {
        x *= 2f64.powi(STEP);
        e -= STEP;
    }
    while e < -STEP {
        x *= 2f64.powi(-STEP);
        e += STEP;
    }
    x * 2f64.powi(e)
}

/// Eigendecomposition of a symmetric tensor (only the upper triangle need be meaningful:
/// the input is taken as symmetric; call [`symmetrise`] first for raw data).
///
/// Eigenvalues are sorted descending (signed); the frame is orthonormal and right-handed even for
/// repeated eigenvalues (then any orthonormal basis of the eigenspace is returned). Accuracy:
/// `‖O Λ Oᵀ − A‖ ≲ 1e-15 ‖A‖`, orthonormality to ~1e-15.
#[inline]
pub fn symmetric_eigen(t: &[f64; 9]) -> Eigen {
    if t[1] == 0.0 && t[2] == 0.0 && t[5] == 0.0 {
        return diagonal_eigen([t[0], t[4], t[8]]);
    }
    jacobi_eigen(t)
}

/// Cyclic Jacobi for a symmetric 3x3 matrix (upper triangle read), the general path of
/// [`symmetric_eigen`].
///
/// Tensors whose largest entry is outside [1e-100, 1e100] (up to f64::MAX, down to subnormals)
/// are first rescaled by an exact power of two; the eigenvalues are then exact up to rounding
/// unless one exceeds f64::MAX (entries within a factor 3 of it), which gives ±inf. The start frame comes from [`jacobi_eigen_hybrid`]. A rotation in plane (p, q) is skipped
/// once `a_pq² ≤ ε² |a_pp a_qq|` (Demmel–Veselić) or `|a_pq| ≤ 2.2e-19 ‖A‖_F`; sweeps stop when a
/// sweep makes no rotation (capped at 20). The frame is a product of proper rotations,
/// re-completed as `e3 = e1 × e2` after sorting.
#[inline]
pub fn jacobi_eigen(t: &[f64; 9]) -> Eigen {
    // Keep squares of entries in range: rescale extreme tensors by an exact power of two.
    let m = t.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m > 0.0 && m.is_finite() && !(1e-100..=1e100).contains(&m) {
        let k = m.log2().floor() as i32;
        let scaled = t.map(|x| mul_pow2(x, -k));
        let mut e = jacobi_eigen_hybrid(&scaled);
        e.values = e.values.map(|x| mul_pow2(x, k));
        return e;
    }
    jacobi_eigen_hybrid(t)
}

#[inline]
fn jacobi_core(t: &[f64; 9]) -> Eigen {
    const ID: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    jacobi_from(t, ID)
}

/// Plain cyclic Jacobi from the identity frame (reference and fallback; no rescaling).
#[inline]
pub fn jacobi_plain(t: &[f64; 9]) -> Eigen {
    jacobi_core(t)
}

/// Jacobi started from a good orthonormal frame: the simple eigenvalue that is best separated
/// from the other two is computed in closed form (trigonometric method, tensor-shape.md §1),
/// its eigenvector from the largest cross product of rows of `A − λI`, completed to a
/// right-handed orthonormal basis `O0`. Jacobi then polishes `O0ᵀ A O0` (nearly block diagonal:
/// one full rotation for the remaining 2x2 block, then only tiny ones), so the result has
/// Jacobi's accuracy whatever the quality of the start.
#[inline]
pub fn jacobi_eigen_hybrid(t: &[f64; 9]) -> Eigen {
    let (a00, a11, a22, a01, a02, a12) = (t[0], t[4], t[8], t[1], t[2], t[5]);
    let q = (a00 + a11 + a22) / 3.0;
    let p1 = a01 * a01 + a02 * a02 + a12 * a12;
    let (b00, b11, b22) = (a00 - q, a11 - q, a22 - q);
    let p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1;
    if !(p2 > 0.0 && p2.is_finite()) {
        return jacobi_core(t);
    }
    let p = (p2 / 6.0).sqrt();
    let inv = 1.0 / p;
    let (c00, c11, c22, c01, c02, c12) = (
        b00 * inv,
        b11 * inv,
        b22 * inv,
        a01 * inv,
        a02 * inv,
        a12 * inv,
    );
    let det = c00 * (c11 * c22 - c12 * c12) - c01 * (c01 * c22 - c12 * c02)
        + c02 * (c01 * c12 - c11 * c02);
    let r = (0.5 * det).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let l1 = q + 2.0 * p * phi.cos();
    let l3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let l2 = 3.0 * q - l1 - l3;
    // The simple eigenvalue farthest from the middle one.
    let lam = if l1 - l2 >= l2 - l3 { l1 } else { l3 };
    let r0 = [a00 - lam, a01, a02];
    let r1 = [a01, a11 - lam, a12];
    let r2 = [a02, a12, a22 - lam];
    let (x01, x02, x12) = (cross(r0, r1), cross(r0, r2), cross(r1, r2));
    let (n01, n02, n12) = (dot(x01, x01), dot(x02, x02), dot(x12, x12));
    let (v, n) = if n01 >= n02 && n01 >= n12 {
        (x01, n01)
    } else if n02 >= n12 {
        (x02, n02)
    } else {
        (x12, n12)
    };
    if !(n > 0.0 && n.is_finite()) {
        return jacobi_core(t);
    }
    let v = v.map(|x| x / n.sqrt());
    // Any unit u ⟂ v (from the axis least aligned with v), w = v × u.
    let ax = if v[0].abs() <= v[1].abs() && v[0].abs() <= v[2].abs() {
        [1.0, 0.0, 0.0]
    } else if v[1].abs() <= v[2].abs() {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let u = normalize(cross(v, ax));
    let w = cross(v, u);
    // A' = O0ᵀ A O0 with O0 = [v u w] (columns).
    let av = mat_vec(t, v);
    let au = mat_vec(t, u);
    let aw = mat_vec(t, w);
    let tp = [
        dot(v, av),
        dot(v, au),
        dot(v, aw),
        0.0,
        dot(u, au),
        dot(u, aw),
        0.0,
        0.0,
        dot(w, aw),
    ];
    let o0 = [[v[0], u[0], w[0]], [v[1], u[1], w[1]], [v[2], u[2], w[2]]];
    jacobi_from(&tp, o0)
}

#[inline]
fn mat_vec(t: &[f64; 9], x: [f64; 3]) -> [f64; 3] {
    [
        t[0] * x[0] + t[1] * x[1] + t[2] * x[2],
        t[1] * x[0] + t[4] * x[1] + t[5] * x[2],
        t[2] * x[0] + t[5] * x[1] + t[8] * x[2],
    ]
}

/// Cyclic Jacobi on the upper triangle of `t`, accumulating rotations onto `v` (row-major; its
/// columns become the eigenvectors of `v t vᵀ`).
#[inline]
fn jacobi_from(t: &[f64; 9], v: [[f64; 3]; 3]) -> Eigen {
    let mut v = v;
    // a[0..3] diagonal, off-diagonals a01, a02, a12
    let mut d = [t[0], t[4], t[8]];
    let mut off = [t[1], t[2], t[5]];
    let norm2 = d[0] * d[0]
        + d[1] * d[1]
        + d[2] * d[2]
        + 2.0 * (off[0] * off[0] + off[1] * off[1] + off[2] * off[2]);
    let abs_floor2 = norm2 * (f64::EPSILON * 1e-3) * (f64::EPSILON * 1e-3);
    const EPS2: f64 = f64::EPSILON * f64::EPSILON;
    // planes (p, q, r, index of a_pq, index of a_rp, index of a_rq)
    const PLANES: [(usize, usize, usize, usize, usize, usize); 3] =
        [(0, 1, 2, 0, 1, 2), (0, 2, 1, 1, 0, 2), (1, 2, 0, 2, 0, 1)];
    for _sweep in 0..20 {
        let mut rotated = false;
        for &(p, q, _r, ipq, irp, irq) in &PLANES {
            let apq = off[ipq];
            let apq2 = apq * apq;
            if apq2 <= EPS2 * (d[p] * d[q]).abs() || apq2 <= abs_floor2 {
                continue;
            }
            rotated = true;
            let theta = (d[q] - d[p]) / (2.0 * apq);
            // Late rotations are tiny: for |θ| > 1e8, t = 1/(2θ) and c = 1 to f64 rounding
            // (t² < 2.5e-17 is below half an ulp of 1), saving two square roots and a division.
            let (tt, c) = if theta.abs() > 1e8 {
                (0.5 / theta, 1.0)
            } else {
                let tt = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                (tt, 1.0 / (tt * tt + 1.0).sqrt())
            };
            let sn = tt * c;
            d[p] -= tt * apq;
            d[q] += tt * apq;
            off[ipq] = 0.0;
            let (arp, arq) = (off[irp], off[irq]);
            off[irp] = c * arp - sn * arq;
            off[irq] = sn * arp + c * arq;
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - sn * vq;
                row[q] = sn * vp + c * vq;
            }
        }
        if !rotated {
            break;
        }
    }
    let order = sort3_desc(&d);
    let col = |k: usize| [v[0][k], v[1][k], v[2][k]];
    let e1 = col(order[0]);
    let e2 = col(order[1]);
    Eigen {
        values: [d[order[0]], d[order[1]], d[order[2]]],
        vectors: [e1, e2, cross(e1, e2)],
    }
}

/// Indices of `d` in descending order (a three-element sorting network; NaN-free input).
#[inline]
fn sort3_desc(d: &[f64; 3]) -> [usize; 3] {
    let mut o = [0usize, 1, 2];
    if d[o[0]] < d[o[1]] {
        o.swap(0, 1);
    }
    if d[o[1]] < d[o[2]] {
        o.swap(1, 2);
    }
    if d[o[0]] < d[o[1]] {
        o.swap(0, 1);
    }
    o
}

/// The same decomposition with nalgebra's `SymmetricEigen` (implicit QR), kept as a reference
/// for tests and benchmarks.
pub fn nalgebra_eigen(t: &[f64; 9]) -> Eigen {
    // Symmetric by contract; build from the upper triangle so that the lower one is not read.
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[4], t[5], t[2], t[5], t[8]);
    let se = SymmetricEigen::new(m);
    let ev = se.eigenvalues;
    let mut order = [0usize, 1, 2];
    // Descending sort of three values, NaN-tolerant (NaN never reaches here from derive).
    order.sort_unstable_by(|&a, &b| ev[b].total_cmp(&ev[a]));
    let values = [ev[order[0]], ev[order[1]], ev[order[2]]];
    let col = |i: usize| {
        let c = se.eigenvectors.column(order[i]);
        [c[0], c[1], c[2]]
    };
    let e1 = normalize(col(0));
    // Re-orthogonalise e2 against e1 (nalgebra's vectors are orthonormal to ~1e-16 already; this
    // guards repeated eigenvalues) and complete the frame as a proper rotation.
    let mut e2 = col(1);
    let d = dot(e1, e2);
    e2 = normalize([e2[0] - d * e1[0], e2[1] - d * e1[1], e2[2] - d * e1[2]]);
    let e3 = cross(e1, e2);
    Eigen {
        values,
        vectors: [e1, e2, e3],
    }
}

/// Exact decomposition of `diag(d)`: eigenvectors are permuted coordinate axes, the third one
/// sign-fixed so that `det O = +1`.
#[inline]
fn diagonal_eigen(d: [f64; 3]) -> Eigen {
    let mut order = [0usize, 1, 2];
    order.sort_unstable_by(|&a, &b| d[b].total_cmp(&d[a]));
    let axis = |k: usize| {
        let mut v = [0.0; 3];
        v[k] = 1.0;
        v
    };
    let e1 = axis(order[0]);
    let e2 = axis(order[1]);
    let e3 = cross(e1, e2);
    Eigen {
        values: [d[order[0]], d[order[1]], d[order[2]]],
        vectors: [e1, e2, e3],
    }
}

#[inline]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline]
fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// Unit quaternion `(x, y, z, w)` of the rotation `O = [e1 e2 e3]` (columns `frame[i]`), in f32
/// with `w ≥ 0`. Shepperd's method (largest diagonal pivot), stable for every rotation.
#[inline]
pub fn frame_to_quat(frame: &[[f64; 3]; 3]) -> [f32; 4] {
    // m(r, c) = O[r][c] = frame[c][r]
    let m = |r: usize, c: usize| frame[c][r];
    let (m00, m11, m22) = (m(0, 0), m(1, 1), m(2, 2));
    let tr = m00 + m11 + m22;
    let q: [f64; 4] = if tr >= m00.max(m11).max(m22) {
        let s = (1.0 + tr).max(0.0).sqrt() * 2.0; // 4w
        [
            (m(2, 1) - m(1, 2)) / s,
            (m(0, 2) - m(2, 0)) / s,
            (m(1, 0) - m(0, 1)) / s,
            0.25 * s,
        ]
    } else if m00 >= m11 && m00 >= m22 {
        let s = (1.0 + m00 - m11 - m22).max(0.0).sqrt() * 2.0; // 4x
        [
            0.25 * s,
            (m(0, 1) + m(1, 0)) / s,
            (m(0, 2) + m(2, 0)) / s,
            (m(2, 1) - m(1, 2)) / s,
        ]
    } else if m11 >= m22 {
        let s = (1.0 + m11 - m00 - m22).max(0.0).sqrt() * 2.0; // 4y
        [
            (m(0, 1) + m(1, 0)) / s,
            0.25 * s,
            (m(1, 2) + m(2, 1)) / s,
            (m(0, 2) - m(2, 0)) / s,
        ]
    } else {
        let s = (1.0 + m22 - m00 - m11).max(0.0).sqrt() * 2.0; // 4z
        [
            (m(0, 2) + m(2, 0)) / s,
            (m(1, 2) + m(2, 1)) / s,
            0.25 * s,
            (m(1, 0) - m(0, 1)) / s,
        ]
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let sign = if q[3] < 0.0 { -1.0 } else { 1.0 };
    let k = sign / n;
    [
        (q[0] * k) as f32,
        (q[1] * k) as f32,
        (q[2] * k) as f32,
        (q[3] * k) as f32,
    ]
}

/// The frame (`frame[i] = e_i`, columns of `O`) of a quaternion `(x, y, z, w)`; the quaternion is
/// normalised first, so the result is orthonormal to f64 rounding.
#[inline]
pub fn quat_to_frame(q: [f32; 4]) -> [[f64; 3]; 3] {
    let [x, y, z, w] = q.map(f64::from);
    let n = (x * x + y * y + z * z + w * w).sqrt();
    let (x, y, z, w) = if n > 0.0 {
        (x / n, y / n, z / n, w / n)
    } else {
        (0.0, 0.0, 0.0, 1.0)
    };
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    [
        [1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy)],
        [2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx)],
        [2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy)],
    ]
}

/// The rotation matrix `O` (row-major rows, `O[r][c]`) of a quaternion `(x, y, z, w)`.
#[inline]
pub fn quat_to_matrix(q: [f32; 4]) -> [[f64; 3]; 3] {
    let f = quat_to_frame(q);
    [
        [f[0][0], f[1][0], f[2][0]],
        [f[0][1], f[1][1], f[2][1]],
        [f[0][2], f[1][2], f[2][2]],
    ]
}

/// `O diag(values) Oᵀ` (row-major) from an eigen frame; the inverse of [`symmetric_eigen`].
pub fn reconstruct(values: [f64; 3], frame: &[[f64; 3]; 3]) -> [f64; 9] {
    let mut out = [0.0; 9];
    for r in 0..3 {
        for c in 0..3 {
            out[3 * r + c] = (0..3).map(|k| values[k] * frame[k][r] * frame[k][c]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn frob(t: &[f64; 9]) -> f64 {
        t.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    fn det(f: &[[f64; 3]; 3]) -> f64 {
        dot(f[0], cross(f[1], f[2]))
    }

    fn check(a: &[f64; 9]) {
        check_eigen(&symmetric_eigen(a), a);
        check_eigen(&jacobi_eigen(a), a);
        check_eigen(&jacobi_core(a), a);
    }

    fn check_eigen(e: &Eigen, a: &[f64; 9]) {
        assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2]);
        for i in 0..3 {
            for j in 0..3 {
                let d = dot(e.vectors[i], e.vectors[j]);
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((d - want).abs() < 1e-12, "not orthonormal: {d}");
            }
        }
        assert!((det(&e.vectors) - 1.0).abs() < 1e-12);
        let r = reconstruct(e.values, &e.vectors);
        let diff: [f64; 9] = std::array::from_fn(|k| r[k] - a[k]);
        assert!(
            frob(&diff) <= 1e-12 * frob(a) + f64::MIN_POSITIVE,
            "reconstruction error {} for {:?}",
            frob(&diff),
            a
        );
    }

    fn rot(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
        let n = dot(axis, axis).sqrt();
        let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
        let (s, c) = angle.sin_cos();
        let t = 1.0 - c;
        // Columns of the rotation matrix.
        [
            [t * x * x + c, t * x * y + s * z, t * x * z - s * y],
            [t * x * y - s * z, t * y * y + c, t * y * z + s * x],
            [t * x * z + s * y, t * y * z - s * x, t * z * z + c],
        ]
    }

    fn eigen_strategy() -> impl Strategy<Value = [f64; 3]> {
        let v = -10.0..10.0f64;
        prop_oneof![
            // general
            (v.clone(), v.clone(), v.clone()).prop_map(|(a, b, c)| [a, b, c]),
            // repeated (double), positive or negative
            (v.clone(), v.clone()).prop_map(|(a, b)| [a, a, b]),
            // triple
            v.clone().prop_map(|a| [a, a, a]),
            // nearly repeated (relative gaps 1e-14 .. 1e-4)
            (v.clone(), v.clone(), -14i32..-4).prop_map(|(a, b, e)| [
                a,
                a * (1.0 + 10f64.powi(e)),
                b
            ]),
            (v.clone(), -14i32..-4, -14i32..-4).prop_map(|(a, e1, e2)| [
                a,
                a * (1.0 + 10f64.powi(e1)),
                a * (1.0 - 10f64.powi(e2))
            ]),
            // rank 1 and rank 2
            v.clone().prop_map(|a| [a, 0.0, 0.0]),
            (v.clone(), v.clone()).prop_map(|(a, b)| [a, b, 0.0]),
            // negative definite
            (0.01..10.0f64, 0.01..10.0f64, 0.01..10.0f64).prop_map(|(a, b, c)| [-a, -b, -c]),
            // indefinite
            (0.01..10.0f64, -10.0..10.0f64, 0.01..10.0f64).prop_map(|(a, b, c)| [a, b, -c]),
            // zero
            Just([0.0, 0.0, 0.0]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn eigen_properties(
            ev in eigen_strategy(),
            axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
            angle in 0.0..std::f64::consts::TAU,
            scale_exp in -6i32..6,
        ) {
            let f = rot([axis.0, axis.1, axis.2], angle);
            let s = 10f64.powi(scale_exp);
            let a = reconstruct(ev.map(|x| x * s), &f);
            // exactly symmetric input
            let (a, _) = symmetrise(&a);
            check(&a);
        }

        #[test]
        fn jacobi_matches_nalgebra(
            ev in eigen_strategy(),
            axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
            angle in 0.0..std::f64::consts::TAU,
        ) {
            let a = symmetrise(&reconstruct(ev, &rot([axis.0, axis.1, axis.2], angle))).0;
            let j = jacobi_eigen(&a);
            let n = nalgebra_eigen(&a);
            let scale = frob(&a).max(f64::MIN_POSITIVE);
            for k in 0..3 {
                prop_assert!((j.values[k] - n.values[k]).abs() <= 1e-13 * scale);
            }
            check_eigen(&n, &a);
        }

        #[test]
        fn random_symmetric(vals in proptest::array::uniform6(-100.0..100.0f64)) {
            let [a, b, c, d, e, f] = vals;
            check(&[a, d, e, d, b, f, e, f, c]);
        }

        #[test]
        fn quaternion_round_trip(
            axis in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
            angle in 0.0..std::f64::consts::TAU,
        ) {
            prop_assume!(axis.0.abs() + axis.1.abs() + axis.2.abs() > 1e-3);
            let f = rot([axis.0, axis.1, axis.2], angle);
            let q = frame_to_quat(&f);
            let back = quat_to_frame(q);
            for i in 0..3 {
                for k in 0..3 {
                    prop_assert!((back[i][k] - f[i][k]).abs() < 1e-6);
                }
            }
        }
    }

    #[test]
    fn extreme_scales() {
        let base = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5];
        let ref_e = symmetric_eigen(&base);
        for s in [1e-300, 1e-200, 1e200, 1e300] {
            let a = base.map(|x| x * s);
            let e = symmetric_eigen(&a);
            for k in 0..3 {
                assert!(
                    (e.values[k] / s - ref_e.values[k]).abs() < 1e-14,
                    "scale {s}"
                );
                assert!((dot(e.vectors[k], ref_e.vectors[k]).abs() - 1.0).abs() < 1e-14);
            }
        }
    }

    /// Eigenvalues of `t` computed by nalgebra on the same problem scaled by 2^-k into a
    /// comfortable range (an exact scaling), scaled back.
    fn scaled_reference(t: &[f64; 9], k: i32) -> [f64; 3] {
        let s = symmetrise(&t.map(|x| mul_pow2(x, -k))).0;
        nalgebra_eigen(&s).values.map(|v| mul_pow2(v, k))
    }

    /// Entries near f64::MAX and subnormal ones: `symmetrise` used to overflow (`a + b`), the
    /// rescale used to overflow (`2^1060`), `fa` divided by a subnormal; all gave NaN/inf.
    #[test]
    fn extreme_but_finite_entries() {
        let base = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5];
        let m = f64::MAX;
        let tiny = f64::from_bits(1); // 2^-1074, the smallest subnormal
        let cases: Vec<([f64; 9], i32)> = vec![
            (base.map(|x| mul_pow2(x, 1021)), 1021),
            // A non-symmetric off-diagonal pair whose sum overflows.
            (
                [0.0, 0.9 * m, 0.0, 0.8 * m, 0.0, 0.0, 0.0, 0.0, 0.1 * m],
                1023,
            ),
            // Eigenvalues 0.9m and (−0.5 ± √0.5)/2 · m.
            (
                [
                    0.9 * m,
                    0.0,
                    0.0,
                    0.0,
                    -0.5 * m,
                    0.25 * m,
                    0.0,
                    0.25 * m,
                    0.0,
                ],
                1023,
            ),
            (base.map(|x| mul_pow2(x, -1030)), -1030),
            (base.map(|x| mul_pow2(x, -1060)), -1060),
            (
                [0.0, tiny, 0.0, tiny, 0.0, 0.0, 0.0, 0.0, 3.0 * tiny],
                -1074,
            ),
        ];
        for (t, k) in cases {
            let (sym, _) = symmetrise(&t);
            assert!(sym.iter().all(|x| x.is_finite()), "{t:?}");
            let e = symmetric_eigen(&sym);
            let want = scaled_reference(&t, k);
            let big = want.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            // Results below 2^-1022 are rounded to the subnormal grid.
            let slack = 4.0 * tiny;
            for i in 0..3 {
                assert!(e.values[i].is_finite(), "{t:?}: {:?}", e.values);
                assert!(
                    (e.values[i] - want[i]).abs() <= 1e-12 * big + slack,
                    "{t:?}: {:?} vs {want:?}",
                    e.values
                );
                for j in 0..3 {
                    let d = dot(e.vectors[i], e.vectors[j]);
                    assert!((d - f64::from(u8::from(i == j))).abs() < 1e-12);
                }
            }
            let fa = crate::tensor::shape::fa(e.values);
            let fa_want = crate::tensor::shape::fa(want.map(|v| mul_pow2(v, -k)));
            let rel = 1e-12 + 8.0 * slack / big;
            assert!(
                fa.is_finite() && (fa - fa_want).abs() <= rel,
                "{fa} vs {fa_want}"
            );
            assert!(crate::tensor::shape::md(e.values).is_finite());
        }
    }

    #[test]
    fn symmetrise_near_max() {
        let m = f64::MAX;
        let (s, flag) = symmetrise(&[0.0, 0.9 * m, 0.0, 0.8 * m, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(flag);
        assert_eq!(s[1], s[3]);
        assert!((s[1] / m - 0.85).abs() < 1e-15);
        let (s, flag) = symmetrise(&[m, m, -m, m, m, 0.0, -m, 0.0, m]);
        assert!(!flag);
        assert_eq!(s, [m, m, -m, m, m, 0.0, -m, 0.0, m]);
        // Opposite signs: the difference overflows, which is (rightly) non-symmetric.
        let (s, flag) = symmetrise(&[0.0, m, 0.0, -m, 0.0, 0.0, 0.0, 0.0, 1.0]);
        assert!(flag);
        assert_eq!((s[1], s[3]), (0.0, 0.0));
    }

    #[test]
    fn mul_pow2_is_exact_across_the_range() {
        assert_eq!(mul_pow2(1.0, 1023), 2f64.powi(1023));
        assert_eq!(mul_pow2(f64::from_bits(1), 1074), 1.0);
        assert_eq!(mul_pow2(1.0, -1074), f64::from_bits(1));
        assert_eq!(mul_pow2(3.0, -2000), 0.0);
        assert_eq!(mul_pow2(1.5, 2000), f64::INFINITY);
        assert_eq!(mul_pow2(f64::MAX, -1023), f64::MAX / 2f64.powi(1023));
    }

    #[test]
    fn diagonal_fast_path() {
        let e = symmetric_eigen(&[1.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 2.0]);
        assert_eq!(e.values, [3.0, 2.0, 1.0]);
        assert_eq!(e.vectors[0], [0.0, 1.0, 0.0]);
        assert_eq!(e.vectors[1], [0.0, 0.0, 1.0]);
        assert_eq!(e.vectors[2], [1.0, 0.0, 0.0]);
        check(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0]);
        check(&[0.0; 9]);
    }

    #[test]
    fn symmetrise_tolerance() {
        let a = [1.0, 0.5, 0.0, 0.5 + 1e-9, 1.0, 0.0, 0.0, 0.0, 1.0];
        let (s, flag) = symmetrise(&a);
        assert!(!flag);
        assert_eq!(s[1], s[3]);
        let b = [1.0, 0.5, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 1.0];
        let (s, flag) = symmetrise(&b);
        assert!(flag);
        assert!((s[1] - 0.45).abs() < 1e-15 && s[1] == s[3]);
        // relative: tiny tensors with relatively large asymmetry are flagged
        let c = b.map(|x| x * 1e-20);
        assert!(symmetrise(&c).1);
    }

    #[test]
    fn quaternion_identity_and_half_turns() {
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(frame_to_quat(&id), [0.0, 0.0, 0.0, 1.0]);
        // 180 degrees about z: e1 = -x, e2 = -y, e3 = z
        let f = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
        let q = frame_to_quat(&f);
        assert!((q[2].abs() - 1.0).abs() < 1e-7);
        let m = quat_to_matrix(q);
        assert!((m[0][0] + 1.0).abs() < 1e-7 && (m[2][2] - 1.0).abs() < 1e-7);
    }
}
