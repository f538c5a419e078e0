//! Each series glyph's own axes and the ellipsoid along them that holds it: the proxy its quad
//! and box are drawn for, instead of the ball of its largest radius. An ODF's lobes are thin, so
//! most of the ball is empty: on a face-on slice of CSD fits the ball's quads drew about ten
//! fragments for each pixel a glyph covers.
//!
//! **The axes** are the eigenvectors of the second moment Σₖ f⁺(uₖ)² uₖuₖᵀ over the geodesic
//! sphere's directions ([`sphere_for`]): a single fibre's lobe lies along the first, a crossing's
//! lobes span the first two.
//!
//! **The ellipsoid** has semi-axes κ·eᵢ along them, eᵢ = maxₖ |f(uₖ)| |uₖ·bᵢ| the sampled
//! extents. It holds the glyph when κ ≥ |A⁻¹p| for every surface point p = f(u) u (A the
//! ellipsoid's matrix), and |A⁻¹p| = max over unit w of Pʷ(u) = f(u) (u·A⁻¹w), a spherical
//! polynomial of degree L + 1 for each w. Each Pʷ is odd, so its maximum is its largest |value|;
//! at that maximum its gradient vanishes, the nearest sample or its opposite lies within the
//! sphere's covering radius c of it (Pʷ(−u) = −Pʷ(u), so one of each opposite pair is sampled),
//! and along the great circle between them Pʷ is a trigonometric polynomial of degree L + 1,
//! whose second derivative Bernstein's inequality bounds by (L + 1)² max |Pʷ|. So
//! max Pʷ ≤ maxₖ |Pʷ(uₖ)| / (1 − c²(L + 1)²/2), and taking the largest over w on both sides,
//! κ = maxₖ |f(uₖ)| |A⁻¹uₖ| / (1 − c²(L + 1)²/2) is rigorous (lmax 8 on 2562 directions: 8.5 %
//! over the sampled value; lmax 12 on 10242: 4 %). Negative lobes count by their size here
//! (|f|), which only makes the ellipsoid larger.

use glam::{DMat3, DVec3};
use nalgebra::{Matrix3, SymmetricEigen};

use super::series::sphere_for;

/// A glyph's axes (columns, in the series' axes, a rotation) and the semi-axes along them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid {
    pub axes: DMat3,
    pub semi: DVec3,
}

/// The ellipsoid holding the glyph r = max(f, 0) whose values at [`sphere_for`] `lmax`'s
/// directions are `values` ([module doc](self)); `None` where the glyph is empty or the
/// sampling too coarse for the bound to hold.
pub fn bounding_ellipsoid(values: &[f64], lmax: u32) -> Option<Ellipsoid> {
    let sphere = sphere_for(lmax);
    let [dx, dy, dz] = &sphere.components;
    if dx.len() != values.len() {
        return None;
    }
    let shrink = 1.0 - sphere.cover * sphere.cover * f64::from((lmax + 1) * (lmax + 1)) / 2.0;
    if shrink < 0.5 {
        return None;
    }
    // Σ f⁺² u uᵀ, its six entries as plain sums over the directions (a scene's build spent half
    // its time here when each direction made a 3×3 outer product).
    let mut sums = [0.0f64; 6];
    for (k, &v) in values.iter().enumerate() {
        let w = v.max(0.0) * v.max(0.0);
        let (x, y, z) = (dx[k], dy[k], dz[k]);
        sums[0] += w * x * x;
        sums[1] += w * x * y;
        sums[2] += w * x * z;
        sums[3] += w * y * y;
        sums[4] += w * y * z;
        sums[5] += w * z * z;
    }
    let m = Matrix3::new(
        sums[0], sums[1], sums[2], sums[1], sums[3], sums[4], sums[2], sums[4], sums[5],
    );
    if m.trace().is_nan() || m.trace() <= 0.0 {
        return None;
    }
    let eigen = SymmetricEigen::new(m);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let col = |i: usize| {
        let c = eigen.eigenvectors.column(order[i]);
        DVec3::new(c[0], c[1], c[2])
    };
    let (b1, b2) = (col(0), col(1));
    let axes = DMat3::from_cols(b1, b2, b1.cross(b2));
    // u's components along b₁, b₂, b₃ for each direction, computed in both scans below as
    // plain sums over the component arrays (which the compiler vectorises; a scene's build
    // spent a third of its time here with a matrix-vector product per direction).
    let t = axes.transpose();
    let rows = [t.row(0), t.row(1), t.row(2)];
    let along = |i: usize, k: usize| rows[i].x * dx[k] + rows[i].y * dy[k] + rows[i].z * dz[k];
    let mut e = [0.0f64; 3];
    for (k, v) in values.iter().enumerate() {
        let a = v.abs();
        for (i, ei) in e.iter_mut().enumerate() {
            *ei = ei.max(a * along(i, k).abs());
        }
    }
    let e = DVec3::from(e);
    let largest = e.max_element();
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let e = e.max(DVec3::splat(1e-6 * largest));
    let inv = (1.0 / e).to_array();
    // A direction whose |f| is below the smallest semi-axis cannot raise κ: there
    // f²|A⁻¹u|² ≤ f²/min eᵢ² < 1, while the direction that set e₁ (never left out) gives 1. So
    // κ is the largest over the rest, the same number (a margin of 1e-12 keeps rounding on the
    // safe side); of thin lobes, most directions are left out.
    let floor = e.min_element() * e.min_element() * (1.0 - 1e-12);
    let mut kappa2 = 0.0f64;
    for (k, v) in values.iter().enumerate() {
        if v * v < floor {
            continue;
        }
        let (x, y, z) = (
            along(0, k) * inv[0],
            along(1, k) * inv[1],
            along(2, k) * inv[2],
        );
        kappa2 = kappa2.max(v * v * (x * x + y * y + z * z));
    }
    let kappa = kappa2.sqrt() / shrink;
    Some(Ellipsoid {
        axes,
        semi: kappa * e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::{ShBasis, ShEval, count_of_lmax};
    use crate::shape::odf::test_util::{lcg, random_dir};
    use crate::shape::odf::{plain_of, plain_value, series::sampled_values};

    /// Truncated deltas of fibres (the sharpest lobes a series of that order has) and random
    /// series: no surface point on 200,000 random directions lies outside the ellipsoid, which
    /// is much smaller than the ball of the largest radius for single fibres.
    #[test]
    fn the_ellipsoid_holds_every_surface_point() {
        let mut seed = 29;
        let third = glam::DQuat::from_axis_angle(DVec3::Z, 120f64.to_radians());
        let x = DVec3::new(0.3, 0.9, -0.2).normalize();
        for lmax in [2, 4, 8, 12] {
            let n = count_of_lmax(lmax).unwrap();
            let mut ev = ShEval::new(lmax, ShBasis::Tournier07).unwrap();
            let mut cases: Vec<(Vec<f64>, bool)> = Vec::new();
            for fibres in [
                vec![x],
                vec![x, x.cross(DVec3::Z).normalize()],
                vec![x, third * x, third * third * x],
            ] {
                let mut sum = vec![0.0; n];
                let mut row = vec![0.0; n];
                for f in &fibres {
                    ev.row(f.to_array(), &mut row);
                    sum.iter_mut().zip(&row).for_each(|(s, r)| *s += r);
                }
                cases.push((sum, fibres.len() == 1));
            }
            let mut c: Vec<f64> = (0..n).map(|_| 0.3 * lcg(&mut seed)).collect();
            c[0] = 1.0;
            cases.push((c, false));
            for (c, single) in cases {
                let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
                let values = sampled_values(&plain, lmax);
                let e = bounding_ellipsoid(&values, lmax).unwrap();
                let t = e.axes.transpose();
                assert!((e.axes.determinant() - 1.0).abs() < 1e-12);
                let mut worst = 0.0f64;
                let mut largest = 0.0f64;
                for _ in 0..200_000 {
                    let u = random_dir(&mut seed);
                    let r = plain_value(&plain, lmax, u).max(0.0);
                    largest = largest.max(r);
                    worst = worst.max((t * (r * u) / e.semi).length());
                }
                assert!(worst <= 1.0, "lmax {lmax}: {worst}");
                // A single fibre's ellipsoid (lmax ≥ 4) is far thinner than its ball.
                let volume = e.semi.x * e.semi.y * e.semi.z / largest.powi(3);
                if single && lmax >= 4 {
                    assert!(volume < 0.25, "lmax {lmax}: {volume}");
                }
            }
        }
    }
}
