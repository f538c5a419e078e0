//! Shape measures of a symmetric tensor from its eigenvalues (tensor-shape.md, sections 2-4, 6).
//!
//! Westin measures and the shape class use the magnitudes `|λ|` sorted descending, so that
//! indefinite (stress/strain) tensors are handled like their `|λ|` ellipsoid; MD and FA use the
//! signed eigenvalues.

use serde::Serialize;

/// Default class threshold τ.
pub const DEFAULT_CLASS_THRESHOLD: f64 = 0.5;

/// Westin measures `(cl, cp, cs)`; they sum to 1 and lie in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Westin {
    pub cl: f64,
    pub cp: f64,
    pub cs: f64,
}

impl Westin {
    pub fn as_array(&self) -> [f64; 3] {
        [self.cl, self.cp, self.cs]
    }
}

/// `|λ|` sorted descending.
#[inline]
pub fn magnitudes_desc(ev: [f64; 3]) -> [f64; 3] {
    let mut m = ev.map(f64::abs);
    if m[0] < m[1] {
        m.swap(0, 1);
    }
    if m[1] < m[2] {
        m.swap(1, 2);
    }
    if m[0] < m[1] {
        m.swap(0, 1);
    }
    m
}

/// λ1-normalised Westin measures (Westin et al. 2002) of the magnitudes:
/// `cl = (m1 − m2)/m1`, `cp = (m2 − m3)/m1`, `cs = m3/m1`. `None` for the zero tensor.
#[inline]
pub fn westin(ev: [f64; 3]) -> Option<Westin> {
    let [m1, m2, m3] = magnitudes_desc(ev);
    if m1 <= 0.0 || !m1.is_finite() {
        return None;
    }
    Some(Westin {
        cl: (m1 - m2) / m1,
        cp: (m2 - m3) / m1,
        cs: m3 / m1,
    })
}

/// Trace-normalised Westin measures (Westin et al. 1997) of the magnitudes:
/// `cl = (m1 − m2)/s`, `cp = 2 (m2 − m3)/s`, `cs = 3 m3/s`, `s = m1 + m2 + m3`.
/// `None` for the zero tensor.
#[inline]
pub fn westin_trace(ev: [f64; 3]) -> Option<Westin> {
    let [m1, m2, m3] = magnitudes_desc(ev);
    // Near f64::MAX the sum overflows; a quarter of each is exact there and keeps the ratios.
    let [m1, m2, m3] = if (m1 + m2 + m3).is_infinite() && m1.is_finite() {
        [m1, m2, m3].map(|m| 0.25 * m)
    } else {
        [m1, m2, m3]
    };
    let s = m1 + m2 + m3;
    if s <= 0.0 || !s.is_finite() {
        return None;
    }
    Some(Westin {
        cl: (m1 - m2) / s,
        cp: 2.0 * (m2 - m3) / s,
        cs: 3.0 * m3 / s,
    })
}

/// Mean diffusivity `tr(T)/3` (signed).
#[inline]
pub fn md(ev: [f64; 3]) -> f64 {
    let s = ev[0] + ev[1] + ev[2];
    if s.is_finite() || !ev.iter().all(|x| x.is_finite()) {
        return s / 3.0;
    }
    // The sum overflows near f64::MAX while the mean cannot: |mean| ≤ max |λ|, which also
    // absorbs the rounding of the quartered sum.
    let big = ev.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    ((0.25 * ev[0] + 0.25 * ev[1] + 0.25 * ev[2]) / 3.0 * 4.0).clamp(-big, big)
}

/// Fractional anisotropy `sqrt(3/2) · sqrt(Σ (λi − MD)²) / sqrt(Σ λi²)`; 0 for the zero tensor.
/// In [0, 1] for semi-definite tensors; indefinite ones reach up to `sqrt(3/2)` (trace-free
/// tensors; e.g. 1.224 for `(2, −0.6, −1.5)`), since `Σ (λi − MD)² = Σ λi² − 3 MD²`.
#[inline]
pub fn fa(ev: [f64; 3]) -> f64 {
    // Scale-free: normalise by max |λ| so that squares neither overflow nor underflow.
    let big = ev[0].abs().max(ev[1].abs()).max(ev[2].abs());
    if !(big > 0.0 && big.is_finite()) {
        return 0.0;
    }
    // Divide, not multiply by 1/big: that reciprocal overflows when big is subnormal.
    let ev = ev.map(|l| l / big);
    let m = md(ev);
    let num: f64 = ev.iter().map(|l| (l - m) * (l - m)).sum();
    let den: f64 = ev.iter().map(|l| l * l).sum();
    if den <= 0.0 {
        return 0.0;
    }
    (1.5 * num / den).sqrt()
}

/// FA directly from a (symmetric) tensor, `sqrt(3/2) ‖T − MD I‖_F / ‖T‖_F`, no eigendecomposition.
pub fn fa_of_tensor(t: &[f64; 9]) -> f64 {
    // Scale-free, as in [`fa`]: squares of raw entries overflow or underflow at the extremes.
    let big = t.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return 0.0;
    }
    let t = t.map(|x| x / big);
    let m = (t[0] + t[4] + t[8]) / 3.0;
    let mut num = 0.0;
    let mut den = 0.0;
    for (k, &x) in t.iter().enumerate() {
        let d = if k % 4 == 0 { x - m } else { x };
        num += d * d;
        den += x * x;
    }
    if den <= 0.0 {
        0.0
    } else {
        (1.5 * num / den).sqrt()
    }
}

/// Gumhold's glyph classes (red cigar, green pancake, blue ball, magenta otherwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeClass {
    Linear,
    Planar,
    Spherical,
    Unclassified,
}

impl ShapeClass {
    /// Position in [`crate::glyph::FieldStats::classes`].
    pub fn index(self) -> usize {
        match self {
            ShapeClass::Linear => 0,
            ShapeClass::Planar => 1,
            ShapeClass::Spherical => 2,
            ShapeClass::Unclassified => 3,
        }
    }

    /// Colour in [0, 1]: cigar (1,0,0), pancake (0,1,0), ball (0,0,1), unclassified (1,0,1).
    pub fn color(self) -> [f64; 3] {
        match self {
            ShapeClass::Linear => [1.0, 0.0, 0.0],
            ShapeClass::Planar => [0.0, 1.0, 0.0],
            ShapeClass::Spherical => [0.0, 0.0, 1.0],
            ShapeClass::Unclassified => [1.0, 0.0, 1.0],
        }
    }

    /// The test-vector spelling: `cigar`, `pancake`, `ball`, `unclassified`.
    pub fn glyph_name(self) -> &'static str {
        match self {
            ShapeClass::Linear => "cigar",
            ShapeClass::Planar => "pancake",
            ShapeClass::Spherical => "ball",
            ShapeClass::Unclassified => "unclassified",
        }
    }
}

/// Class by the rule of tensor-shape.md section 4: `argmax(cl, cp, cs)` of the λ1-normalised
/// measures of the magnitudes (ties: cigar, then pancake, then ball), unclassified if that
/// maximum is below `tau`, and for the zero tensor.
#[inline]
pub fn classify(ev: [f64; 3], tau: f64) -> ShapeClass {
    match westin(ev) {
        None => ShapeClass::Unclassified,
        Some(w) => classify_westin(&w, tau),
    }
}

/// [`classify`] from precomputed measures.
#[inline]
pub fn classify_westin(w: &Westin, tau: f64) -> ShapeClass {
    let (class, max) = if w.cl >= w.cp && w.cl >= w.cs {
        (ShapeClass::Linear, w.cl)
    } else if w.cp >= w.cs {
        (ShapeClass::Planar, w.cp)
    } else {
        (ShapeClass::Spherical, w.cs)
    };
    if max < tau {
        ShapeClass::Unclassified
    } else {
        class
    }
}

/// Continuous colour `(cl, cp, cs)` (barycentric in the Westin triangle); with `max1`, divided by
/// its largest component. Black for the zero tensor.
pub fn barycentric_color(ev: [f64; 3], max1: bool) -> [f64; 3] {
    match westin(ev) {
        None => [0.0; 3],
        Some(w) => {
            let c = w.as_array();
            if max1 {
                let m = c[0].max(c[1]).max(c[2]);
                c.map(|x| x / m)
            } else {
                c
            }
        }
    }
}

/// Directionally encoded colour `min(FA, 1) · |e|`, with `e` the unit eigenvector of the largest
/// `|λ|`, given here.
pub fn dec_color(ev: [f64; 3], e_major: [f64; 3]) -> [f64; 3] {
    let f = fa(ev).min(1.0);
    e_major.map(|x| f * x.abs())
}

/// Index (0..3) of the eigenvalue of largest magnitude; ties go to the positive/larger one.
#[inline]
pub fn major_index(ev: [f64; 3]) -> usize {
    let mut best = 0;
    for i in 1..3 {
        if ev[i].abs() > ev[best].abs() {
            best = i;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn hand_computed() {
        // (3, 2, 1): λ1 form all 1/3, trace form (1/6, 1/3, 1/2); MD 2; FA = sqrt(1.5·2/14)
        let w = westin([3.0, 2.0, 1.0]).unwrap();
        assert!(close(w.cl, 1.0 / 3.0) && close(w.cp, 1.0 / 3.0) && close(w.cs, 1.0 / 3.0));
        let t = westin_trace([3.0, 2.0, 1.0]).unwrap();
        assert!(close(t.cl, 1.0 / 6.0) && close(t.cp, 1.0 / 3.0) && close(t.cs, 0.5));
        assert!(close(md([3.0, 2.0, 1.0]), 2.0));
        assert!(close(fa([3.0, 2.0, 1.0]), (3.0f64 / 14.0).sqrt()));
        assert_eq!(classify([3.0, 2.0, 1.0], 0.5), ShapeClass::Unclassified);
        // (3, 1, 1): cl = 2/3 cigar
        assert!(close(westin([3.0, 1.0, 1.0]).unwrap().cl, 2.0 / 3.0));
        assert_eq!(classify([3.0, 1.0, 1.0], 0.5), ShapeClass::Linear);
        // (2, 2, 0.2): cp = 0.9 pancake
        assert!(close(westin([2.0, 2.0, 0.2]).unwrap().cp, 0.9));
        assert_eq!(classify([2.0, 2.0, 0.2], 0.5), ShapeClass::Planar);
        // (1, 0.95, 0.9): cs = 0.9 ball
        assert_eq!(classify([1.0, 0.95, 0.9], 0.5), ShapeClass::Spherical);
        // zero tensor
        assert_eq!(classify([0.0; 3], 0.5), ShapeClass::Unclassified);
        assert_eq!(fa([0.0; 3]), 0.0);
        assert!(westin([0.0; 3]).is_none());
        // indefinite: magnitudes (2, 1.5, 0.6)
        let w = westin([2.0, -0.6, -1.5]).unwrap();
        assert!(close(w.cl, 0.25) && close(w.cp, 0.45) && close(w.cs, 0.3));
        assert!((fa([2.0, -0.6, -1.5]) - 1.2244360213371532).abs() < 1e-12);
        assert!(close(fa([1.0, 0.0, -1.0]), 1.5f64.sqrt()));
        assert!(close(fa([3e200, 1e200, 1e200]), fa([3.0, 1.0, 1.0])));
        assert!(close(fa([3e-200, 1e-200, 1e-200]), fa([3.0, 1.0, 1.0])));
        // ties resolved cigar, then pancake: (2, 1, 0) has cl = cp = 0.5
        assert_eq!(classify([2.0, 1.0, 0.0], 0.5), ShapeClass::Linear);
        // exactly at tau counts
        assert_eq!(classify([1.0, 0.5, 0.25], 0.5), ShapeClass::Linear);
        assert_eq!(classify([1.0, 0.5, 0.25], 0.51), ShapeClass::Unclassified);
    }

    /// Sums near f64::MAX and reciprocals of subnormals used to give inf/NaN.
    #[test]
    fn extreme_but_finite_eigenvalues() {
        let m = f64::MAX;
        let d = f64::from_bits(1000); // subnormal
        assert!(close(fa([3.0 * d, d, d]), fa([3.0, 1.0, 1.0])));
        assert!(close(fa([m, 0.5 * m, 0.25 * m]), fa([1.0, 0.5, 0.25])));
        assert_eq!(md([m, m, m]), m);
        assert!(close(md([m, m, -m]) / m, 1.0 / 3.0));
        let w = westin_trace([m, 0.5 * m, 0.25 * m]).unwrap();
        let want = westin_trace([1.0, 0.5, 0.25]).unwrap();
        assert!(close(w.cl, want.cl) && close(w.cp, want.cp) && close(w.cs, want.cs));
        let w = westin([3.0 * d, d, d]).unwrap();
        assert!(close(w.cl, 2.0 / 3.0));
        let t = [0.0, m, 0.0, m, 0.0, 0.0, 0.0, 0.0, 0.5 * m];
        let small = [0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.5];
        assert!(close(fa_of_tensor(&t), fa_of_tensor(&small)));
        assert!(close(
            fa_of_tensor(&small.map(|x| x * d)),
            fa_of_tensor(&small)
        ));
    }

    #[test]
    fn fa_from_tensor_matches() {
        let t = [2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5];
        let e = crate::tensor::eigen::symmetric_eigen(&t);
        assert!((fa(e.values) - fa_of_tensor(&t)).abs() < 1e-12);
    }

    #[test]
    fn major_index_ties() {
        assert_eq!(major_index([2.0, 0.0, -2.0]), 0);
        assert_eq!(major_index([1.0, 0.0, -2.0]), 2);
    }
}
