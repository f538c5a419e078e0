//! The three real, antipodally symmetric SH bases, the order of their coefficients, the count ↔
//! lmax rule, and exact conversion between them (module doc: the formulas and their sources).

use serde::Serialize;

/// The largest lmax read: 496 coefficients. MRtrix and DIPY write lmax ≤ 12 in practice; the
/// recurrence stays accurate far beyond, the bound only keeps a header's count honest.
pub const MAX_LMAX: u32 = 30;

/// A real symmetric SH basis: which function each coefficient multiplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum ShBasis {
    /// MRtrix3's basis (`dwi2fod`, `sh2amp`; DIPY's `tournier07` with `legacy=False`).
    #[serde(rename = "tournier07")]
    Tournier07,
    /// DIPY's `descoteaux07` with `legacy=False`: Descoteaux et al. 2007 as published.
    #[serde(rename = "descoteaux07")]
    Descoteaux07,
    /// DIPY's default (`legacy=True`), which takes |m| for m < 0: what `shm_coeff` holds
    /// when DIPY saves it without being told otherwise.
    #[serde(rename = "descoteaux07-legacy")]
    Descoteaux07Legacy,
}

crate::names::named_values!(ShBasis {
    Tournier07 => "tournier07",
    Descoteaux07 => "descoteaux07",
    Descoteaux07Legacy => "descoteaux07-legacy",
});

/// What is wrong with a set of SH coefficients.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShError {
    /// Not (L+1)(L+2)/2 for an even L ≤ [`MAX_LMAX`].
    #[error(
        "{count} values per voxel is no count of SH coefficients: even orders up to lmax hold \
         (lmax+1)(lmax+2)/2 (6, 15, 28, 45, 66, 91 for lmax 2 to 12)"
    )]
    Count { count: usize },
    /// Odd, or above [`MAX_LMAX`].
    #[error("lmax {lmax} is not an even order from 0 to {MAX_LMAX}")]
    Lmax { lmax: u32 },
}

/// How many coefficients the even orders 0, 2, …, `lmax` hold.
pub fn count_of_lmax(lmax: u32) -> Result<usize, ShError> {
    if !lmax.is_multiple_of(2) || lmax > MAX_LMAX {
        return Err(ShError::Lmax { lmax });
    }
    let l = lmax as usize;
    Ok((l + 1) * (l + 2) / 2)
}

/// The lmax whose even orders hold `count` coefficients.
pub fn lmax_of_count(count: usize) -> Result<u32, ShError> {
    (0..=MAX_LMAX)
        .step_by(2)
        .find(|&l| count_of_lmax(l) == Ok(count))
        .ok_or(ShError::Count { count })
}

/// The place of coefficient (l, m) (l even, |m| ≤ l) in all three bases: orders ascending, m
/// from −l to l within each (MRtrix's `index(l, m)`, DIPY's `sph_harm_ind_list`).
pub fn index(l: u32, m: i32) -> usize {
    let l = l as usize;
    (l * (l + 1) / 2).wrapping_add_signed(m as isize)
}

/// The (l, m) of every coefficient up to `lmax`, in storage order.
pub fn degrees(lmax: u32) -> impl Iterator<Item = (u32, i32)> {
    (0..=lmax)
        .step_by(2)
        .flat_map(|l| (-(l as i32)..=l as i32).map(move |m| (l, m)))
}

/// The azimuthal factor of a basis function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Trig {
    /// m = 0: none.
    One,
    /// cos(|m| φ).
    Cos,
    /// sin(|m| φ).
    Sin,
}

impl ShBasis {
    /// The function coefficient `m` multiplies, as `sign · w · Λ_l^|m|(θ) · trig(|m| φ)`
    /// (`w` = √2 for m ≠ 0): its trig factor and sign. The module doc derives each case.
    pub(crate) fn term(self, m: i32) -> (Trig, f64) {
        let cs = if m % 2 == 0 { 1.0 } else { -1.0 };
        match (self, m.signum()) {
            (_, 0) => (Trig::One, 1.0),
            (ShBasis::Tournier07, 1) => (Trig::Cos, cs),
            (ShBasis::Tournier07, _) => (Trig::Sin, cs),
            (_, 1) => (Trig::Sin, cs),
            (ShBasis::Descoteaux07, _) => (Trig::Cos, 1.0),
            (ShBasis::Descoteaux07Legacy, _) => (Trig::Cos, cs),
        }
    }

    /// The m under which this basis keeps the function `trig(|m| φ)` (the other sign of m, or
    /// the same).
    fn m_of(self, trig: Trig, abs_m: i32) -> i32 {
        let positive = match self {
            ShBasis::Tournier07 => Trig::Cos,
            ShBasis::Descoteaux07 | ShBasis::Descoteaux07Legacy => Trig::Sin,
        };
        match trig {
            Trig::One => 0,
            t if t == positive => abs_m,
            _ => -abs_m,
        }
    }
}

/// The coefficients `c` (of `from`) in the basis `to`: the same function on the sphere. Each
/// basis function of one basis is ± one of the other's, so this moves and negates numbers and
/// never rounds.
pub fn convert(c: &[f64], from: ShBasis, to: ShBasis) -> Result<Vec<f64>, ShError> {
    let lmax = lmax_of_count(c.len())?;
    let mut out = vec![0.0; c.len()];
    for (l, m) in degrees(lmax) {
        let (trig, s_from) = from.term(m);
        let m_to = to.m_of(trig, m.abs());
        let (trig_to, s_to) = to.term(m_to);
        debug_assert_eq!(trig, trig_to);
        out[index(l, m_to)] = c[index(l, m)] * s_from * s_to;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_lmax_go_both_ways_and_other_counts_are_refused() {
        let counts: Vec<usize> = (0..=12)
            .step_by(2)
            .map(|l| count_of_lmax(l).unwrap())
            .collect();
        assert_eq!(counts, [1, 6, 15, 28, 45, 66, 91]);
        for l in (0..=MAX_LMAX).step_by(2) {
            assert_eq!(lmax_of_count(count_of_lmax(l).unwrap()), Ok(l));
        }
        for bad in [0, 2, 7, 9, 16, 44, 46, 81, 92, 497, usize::MAX] {
            assert_eq!(lmax_of_count(bad), Err(ShError::Count { count: bad }));
        }
        assert_eq!(count_of_lmax(3), Err(ShError::Lmax { lmax: 3 }));
        assert_eq!(count_of_lmax(32), Err(ShError::Lmax { lmax: 32 }));
        assert_eq!(degrees(12).count(), 91);
        for (j, (l, m)) in degrees(12).enumerate() {
            assert_eq!(index(l, m), j);
        }
    }

    #[test]
    fn every_basis_keeps_each_trig_function_once_per_degree() {
        for b in ShBasis::VALUES {
            for a in 1..=4 {
                for trig in [Trig::Cos, Trig::Sin] {
                    let m = b.m_of(trig, a);
                    assert_eq!(m.abs(), a);
                    assert_eq!(b.term(m).0, trig, "{b} m {m}");
                }
                assert_ne!(b.m_of(Trig::Cos, a), b.m_of(Trig::Sin, a));
            }
        }
    }

    #[test]
    fn conversion_round_trips_bit_for_bit() {
        let c: Vec<f64> = (0..45).map(|i| (i as f64 * 0.37).sin() + 0.1).collect();
        for &a in ShBasis::VALUES {
            for &b in ShBasis::VALUES {
                let there = convert(&c, a, b).unwrap();
                assert_eq!(convert(&there, b, a).unwrap(), c, "{a} → {b} → {a}");
            }
            assert_eq!(convert(&c, a, a).unwrap(), c);
        }
        assert!(convert(&c[..44], ShBasis::Tournier07, ShBasis::Descoteaux07).is_err());
    }
}
