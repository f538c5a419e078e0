//! Nearest-rank percentiles: the default window of an underlay and the default range of a
//! scalar colouring, one rule for both.

use std::cmp::Ordering;

/// The default range: the 2nd and 98th percentiles, so that a few extreme values (a
/// singularity, a stress concentration, CSF in a brain) do not wash out the rest.
pub const DEFAULT_RANGE: [f64; 2] = [0.02, 0.98];

/// At most this many values (evenly spread) estimate the percentiles of a larger set.
pub const MAX_SAMPLES: usize = 1 << 20;

/// The `q` quantiles of `values` by nearest rank (the value at sorted position
/// `round(q (n − 1))`, halves away from zero), ordered by `cmp`; `None` when there are none.
pub fn percentiles<T: Copy>(
    mut values: Vec<T>,
    q: [f64; 2],
    cmp: fn(&T, &T) -> Ordering,
) -> Option<[T; 2]> {
    if values.is_empty() {
        return None;
    }
    let n = values.len();
    let rank = |q: f64| ((q * (n - 1) as f64).round() as usize).min(n - 1);
    let mut pick = |q: f64| *values.select_nth_unstable_by(rank(q), cmp).1;
    Some([pick(q[0]), pick(q[1])])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank() {
        let v: Vec<f32> = (0..=100).rev().map(|x| x as f32).collect();
        assert_eq!(
            percentiles(v, DEFAULT_RANGE, f32::total_cmp),
            Some([2.0, 98.0])
        );
        // n − 1 = 49: 0.98 · 49 = 48.02 → 48; 0.02 · 49 = 0.98 → 1.
        let v: Vec<f64> = (0..50).map(f64::from).collect();
        assert_eq!(
            percentiles(v, DEFAULT_RANGE, f64::total_cmp),
            Some([1.0, 48.0])
        );
        assert_eq!(
            percentiles(Vec::<f64>::new(), DEFAULT_RANGE, f64::total_cmp),
            None
        );
    }
}
