//! The numbers a report states of a map: FA and MD over its valid tensors (from the glyphs'
//! eigenvalues, the same the figures show) and the glyphs `--scale auto` clamps.

use serde::Serialize;

use crate::glyph::style::Spacing;
use crate::glyph::{GlyphSet, GlyphStyle};
use crate::tensor::shape::{fa, md};

/// A measure over the valid tensors; the median of an even count is the mean of the two middle
/// values (as numpy's).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Summary {
    pub min: f64,
    pub median: f64,
    pub mean: f64,
    pub max: f64,
}

impl Summary {
    /// The summary of `values` (reordered); `None` when there are none.
    pub fn of(values: &mut [f64]) -> Option<Self> {
        let n = values.len();
        if n == 0 {
            return None;
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let (min, max) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let (_, &mut upper, _) = values.select_nth_unstable_by(n / 2, f64::total_cmp);
        let median = if n % 2 == 1 {
            upper
        } else {
            let lower = values[..n / 2]
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            (lower + upper) / 2.0
        };
        Some(Self {
            min,
            median,
            mean,
            max,
        })
    }
}

/// FA and MD summaries over every glyph of `set` (its valid tensors).
pub fn measures(set: &GlyphSet) -> (Option<Summary>, Option<Summary>) {
    let ev = |g: &crate::glyph::Glyph| g.eigenvalues.map(f64::from);
    let mut values: Vec<f64> = set.glyphs.iter().map(|g| fa(ev(g))).collect();
    let fa = Summary::of(&mut values);
    values.clear();
    values.extend(set.glyphs.iter().map(|g| md(ev(g))));
    (fa, Summary::of(&mut values))
}

/// Glyphs `style` with `--scale auto` draws at the robust largest size instead of their own.
pub fn clamped(set: &GlyphSet, style: &GlyphStyle, spacing: Spacing) -> usize {
    let resolved = style.resolve(set, spacing);
    set.glyphs.iter().filter(|g| resolved.clamps(g)).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summaries_as_numpy_gives_them() {
        // numpy: np.median([3, 1, 2]) = 2, np.median([4, 1, 3, 2]) = 2.5
        let s = Summary::of(&mut [3.0, 1.0, 2.0]).unwrap();
        assert_eq!((s.min, s.median, s.mean, s.max), (1.0, 2.0, 2.0, 3.0));
        let s = Summary::of(&mut [4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!((s.min, s.median, s.mean, s.max), (1.0, 2.5, 2.5, 4.0));
        assert_eq!(Summary::of(&mut []), None);
    }
}
