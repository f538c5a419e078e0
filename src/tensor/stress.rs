//! The scalar measures stress analysts read, from a symmetric tensor's principal values, with
//! the definitions and sign conventions of VTK's `vtkYieldCriteria` and
//! `vtkTensorPrincipalInvariants` (ParaView's "Yield Criteria" and "Tensor Principal
//! Invariants" filters, VTK 9.3 and later), so that a colouring here and one made in ParaView
//! mean the same numbers:
//!
//! - principal stresses σ1 ≥ σ2 ≥ σ3, the eigenvalues ordered largest first (tension positive);
//! - Tresca = |σ3 − σ1| = σ1 − σ3 (twice the largest shear stress);
//! - von Mises = √(½((σ1 − σ2)² + (σ2 − σ3)² + (σ3 − σ1)²));
//! - mean = tr σ / 3 (the negative of the pressure);
//! - triaxiality = mean / von Mises (not in VTK: its ratio of the two above; ±∞ for a
//!   hydrostatic state, whose von Mises stress is zero).
//!
//! The values are computed in f64 from the eigenvalues that [`crate::tensor::eigen`] finds; VTK
//! finds them with its own Jacobi solver, and the two agree to within rounding of the largest
//! |σ| (tests/cli/stress_fields.rs compares them with VTK's numbers for every stress field of the tests).

/// σ1 ≥ σ2 ≥ σ3: `ev` in descending order (NaN last).
#[inline]
pub fn principal(ev: [f64; 3]) -> [f64; 3] {
    let mut s = ev;
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

/// The von Mises (equivalent) stress √(½((σ1 − σ2)² + (σ2 − σ3)² + (σ3 − σ1)²)), ≥ 0.
#[inline]
pub fn von_mises(ev: [f64; 3]) -> f64 {
    // Differences of values near f64::MAX overflow: scale by the largest |σ| first.
    let big = ev[0].abs().max(ev[1].abs()).max(ev[2].abs());
    if !(big > 0.0 && big.is_finite()) {
        return if big == 0.0 { 0.0 } else { f64::NAN };
    }
    let [a, b, c] = ev.map(|s| s / big);
    saturate(big * (0.5 * ((a - b) * (a - b) + (b - c) * (b - c) + (c - a) * (c - a))).sqrt())
}

/// A criterion beyond the f64 range (principal stresses of opposite signs near f64::MAX: a
/// corrupt file's) as the largest f64, so that reports stay numbers.
#[inline]
fn saturate(x: f64) -> f64 {
    if x == f64::INFINITY { f64::MAX } else { x }
}

/// The Tresca stress σ1 − σ3 (the largest principal stress difference), ≥ 0.
#[inline]
pub fn tresca(ev: [f64; 3]) -> f64 {
    let [s1, _, s3] = principal(ev);
    saturate(s1 - s3)
}

/// The mean (hydrostatic) stress tr σ / 3, tension positive.
#[inline]
pub fn mean(ev: [f64; 3]) -> f64 {
    super::shape::md(ev)
}

/// The stress triaxiality mean / von Mises: about 0.33 in uniaxial tension, 0 in pure shear,
/// −0.33 in uniaxial compression; ±∞ for a hydrostatic state (NaN for the zero tensor).
#[inline]
pub fn triaxiality(ev: [f64; 3]) -> f64 {
    mean(ev) / von_mises(ev)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// States whose measures are known in closed form.
    #[test]
    fn textbook_states() {
        let s = 120.0;
        // Uniaxial tension: every criterion equals the stress, triaxiality 1/3.
        let uni = [0.0, s, 0.0];
        assert_eq!(principal(uni), [s, 0.0, 0.0]);
        assert_eq!(von_mises(uni), s);
        assert_eq!(tresca(uni), s);
        assert_eq!(mean(uni), s / 3.0);
        assert!((triaxiality(uni) - 1.0 / 3.0).abs() < 1e-15);
        // Pure shear τ: principal stresses (τ, 0, −τ), von Mises √3 τ, Tresca 2 τ.
        let shear = [-s, 0.0, s];
        assert!((von_mises(shear) - 3f64.sqrt() * s).abs() < 1e-12);
        assert_eq!(tresca(shear), 2.0 * s);
        assert_eq!(triaxiality(shear), 0.0);
        // Equibiaxial compression: von Mises = Tresca = s, triaxiality −2/3.
        let bi = [-s, -s, 0.0];
        assert!((von_mises(bi) - s).abs() < 1e-12);
        assert_eq!(tresca(bi), s);
        assert!((triaxiality(bi) + 2.0 / 3.0).abs() < 1e-15);
        // Hydrostatic: no deviator.
        let p = [-s; 3];
        assert_eq!(von_mises(p), 0.0);
        assert_eq!(tresca(p), 0.0);
        assert_eq!(triaxiality(p), f64::NEG_INFINITY);
        assert!(triaxiality([0.0; 3]).is_nan());
    }

    /// von Mises is the deviator's norm √(3/2) ‖s‖ (the component form numpy and ANSYS use),
    /// and Tresca bounds it: √3/2 Tresca ≤ von Mises ≤ Tresca.
    #[test]
    fn von_mises_is_the_deviator_norm_and_tresca_bounds_it() {
        for ev in [
            [3.0, -1.0, 0.5],
            [1e-300, -2e-300, 5e-301],
            [8.0e307, -9.0e307, 1.0],
            [7.0, 7.0, -2.0],
        ] {
            let m = mean(ev);
            let scale = ev.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let dev: f64 = ev.iter().map(|x| ((x - m) / scale).powi(2)).sum();
            let norm = scale * (1.5 * dev).sqrt();
            let vm = von_mises(ev);
            assert!((vm - norm).abs() <= 1e-14 * vm, "{ev:?}: {vm} vs {norm}");
            let t = tresca(ev);
            if t.is_finite() {
                assert!(vm <= t * (1.0 + 1e-15) && vm >= 0.75f64.sqrt() * t * (1.0 - 1e-15));
            }
        }
        assert!(von_mises([f64::NAN, 1.0, 0.0]).is_nan());
        // Beyond the f64 range: the largest f64.
        let huge = [1.7e308, 0.0, -1.3e308];
        assert_eq!((von_mises(huge), tresca(huge)), (f64::MAX, f64::MAX));
        assert_eq!(tresca([f64::INFINITY, 0.0, 0.0]), f64::MAX);
    }
}
