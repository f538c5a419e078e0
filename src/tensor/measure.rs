//! One scalar per tensor, from its eigenvalues: the diffusion measures (FA, MD,
//! [`super::shape`]) and the stress measures ([`super::stress`]). What a scalar colouring
//! (`--color`) and an underlay (`--underlay`) show, named once for both.

/// A scalar measure of a tensor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Measure {
    /// Fractional anisotropy.
    Fa,
    /// Mean diffusivity (the mean eigenvalue; the same number as [`Measure::Mean`]).
    Md,
    /// The von Mises stress.
    VonMises,
    /// The Tresca stress σ1 − σ3.
    Tresca,
    /// The largest principal stress.
    Sigma1,
    /// The middle principal stress.
    Sigma2,
    /// The smallest principal stress.
    Sigma3,
    /// The mean stress tr σ / 3.
    Mean,
    /// The stress triaxiality mean / von Mises.
    Triaxiality,
}

crate::names::named_values!(Measure {
    Fa => "fa",
    Md => "md",
    VonMises => "von-mises",
    Tresca => "tresca",
    Sigma1 => "sigma1",
    Sigma2 => "sigma2",
    Sigma3 => "sigma3",
    Mean => "mean",
    Triaxiality => "triaxiality",
});

impl Measure {
    /// The measure of a tensor with eigenvalues `ev` (any order).
    pub fn of(self, ev: [f64; 3]) -> f64 {
        use super::{shape, stress};
        match self {
            Measure::Fa => shape::fa(ev),
            Measure::Md => shape::md(ev),
            Measure::VonMises => stress::von_mises(ev),
            Measure::Tresca => stress::tresca(ev),
            Measure::Sigma1 => stress::principal(ev)[0],
            Measure::Sigma2 => stress::principal(ev)[1],
            Measure::Sigma3 => stress::principal(ev)[2],
            Measure::Mean => stress::mean(ev),
            Measure::Triaxiality => stress::triaxiality(ev),
        }
    }

    /// Whether the measure has a sign that matters (tension against compression): such a
    /// measure is coloured with a diverging map centred on zero, the others with a sequential
    /// one. MD keeps its sequential map: diffusivities are positive.
    pub fn signed(self) -> bool {
        matches!(
            self,
            Measure::Sigma1
                | Measure::Sigma2
                | Measure::Sigma3
                | Measure::Mean
                | Measure::Triaxiality
        )
    }

    /// Whether the measure is in the tensor's units (FA and triaxiality are ratios).
    pub fn has_units(self) -> bool {
        !matches!(self, Measure::Fa | Measure::Triaxiality)
    }

    /// The range it is coloured over when none is asked for, if it has one of its own: FA's
    /// [0, 1], the same in every field (others take their field's 2nd–98th percentiles).
    pub fn natural_range(self) -> Option<[f64; 2]> {
        (self == Measure::Fa).then_some([0.0, 1.0])
    }

    /// What a legend calls it.
    pub fn label(self) -> &'static str {
        match self {
            Measure::Fa => "FA",
            Measure::Md => "MD",
            Measure::VonMises => "von Mises",
            Measure::Tresca => "Tresca",
            Measure::Sigma1 => "σ1",
            Measure::Sigma2 => "σ2",
            Measure::Sigma3 => "σ3",
            Measure::Mean => "mean stress",
            Measure::Triaxiality => "triaxiality",
        }
    }

    /// The legend's title: the label, with `units` in parentheses where the measure has units.
    pub fn title(self, units: Option<&str>) -> String {
        match units {
            Some(u) if self.has_units() && !u.is_empty() => format!("{} ({u})", self.label()),
            _ => self.label().to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_titles() {
        for (m, n) in Measure::VALUES.iter().zip(Measure::NAMES) {
            assert_eq!(n.parse::<Measure>(), Ok(*m));
        }
        assert_eq!(Measure::VonMises.title(Some("MPa")), "von Mises (MPa)");
        assert_eq!(Measure::Triaxiality.title(Some("MPa")), "triaxiality");
        assert_eq!(Measure::Sigma3.title(None), "σ3");
    }

    /// Each measure reads the eigenvalues in any order, and the principal stresses come out
    /// ordered.
    #[test]
    fn order_free() {
        let ev = [-4.0, 10.0, 1.0];
        assert_eq!(Measure::Sigma1.of(ev), 10.0);
        assert_eq!(Measure::Sigma2.of(ev), 1.0);
        assert_eq!(Measure::Sigma3.of(ev), -4.0);
        for &m in Measure::VALUES {
            // Up to the rounding of sums taken in another order.
            let (a, b) = (m.of(ev), m.of([10.0, 1.0, -4.0]));
            assert!((a - b).abs() <= 1e-15 * a.abs(), "{m}: {a} vs {b}");
        }
        assert_eq!(Measure::Mean.of(ev), Measure::Md.of(ev));
    }
}
