//! TensorField → GlyphSet: every tensor in file order is rotated to world space, checked,
//! symmetrised and eigendecomposed, in parallel chunks (rayon); glyph order is file order.
//!
//! Nothing is dropped silently: tensors with a NaN component are counted in `skipped_nan`, else
//! with an infinite component in `skipped_inf`, else all-zero tensors in `skipped_zero`, and
//! finite tensors whose eigenvalues leave the f32 range a glyph stores in `skipped_overflow`
//! (beyond 3.4e38 the glyph's size is infinite and it cannot be drawn or scaled).
//! Non-symmetric tensors (see [`crate::tensor::eigen::SYMMETRY_TOL`]) are replaced by
//! `(A + Aᵀ)/2` and counted in `symmetrised`.

use rayon::prelude::*;

use super::{FieldStats, Glyph, GlyphSet};
use crate::field::TensorField;
use crate::progress::Progress;
use crate::tensor::eigen::{frame_to_quat, symmetric_eigen, symmetrise};
use crate::tensor::shape::{self, DEFAULT_CLASS_THRESHOLD};
use crate::tensor::stress;

/// Tensors per parallel work item (also the progress-bar granularity).
const CHUNK: usize = 8192;

/// What happened to one tensor.
#[derive(Debug, Clone, Copy)]
enum Outcome {
    Nan,
    Inf,
    Zero,
    Overflow,
    Valid {
        glyph: Glyph,
        values: [f64; 3],
        symmetrised: bool,
    },
}

/// Why a world-space tensor gives no glyph (NaN before Inf before all-zero), or `None` if it is
/// valid.
#[inline]
fn skipped(t: &[f64; 9]) -> Option<Outcome> {
    // One branch-free pass over the nine components.
    let (mut nan, mut inf, mut nonzero) = (false, false, false);
    for &x in t {
        nan |= x.is_nan();
        inf |= x.is_infinite();
        nonzero |= x != 0.0;
    }
    if nan {
        Some(Outcome::Nan)
    } else if inf {
        Some(Outcome::Inf)
    } else if !nonzero {
        Some(Outcome::Zero)
    } else {
        None
    }
}

/// Classify and decompose one world-space tensor.
#[inline]
fn process(t: &[f64; 9], centre: [f64; 3], index: usize) -> Outcome {
    if let Some(skipped) = skipped(t) {
        return skipped;
    }
    let (s, symmetrised) = symmetrise(t);
    let e = symmetric_eigen(&s);
    // A NaN the overflow may have made is out of range too.
    let in_range = |v: &f64| v.is_finite() && v.abs() <= f64::from(f32::MAX);
    if !e.values.iter().all(in_range) {
        return Outcome::Overflow;
    }
    Outcome::Valid {
        glyph: Glyph {
            centre,
            eigenvalues: e.values.map(|v| v as f32),
            rotation: frame_to_quat(&e.vectors),
            index: index as u32,
        },
        values: e.values,
        symmetrised,
    }
}

/// Per-chunk statistics, merged in file order.
struct Partial {
    stats: FieldStats,
    fa_sum: f64,
}

impl Partial {
    fn new() -> Self {
        Partial {
            stats: FieldStats {
                eigenvalues_min: [f64::INFINITY; 3],
                eigenvalues_max: [f64::NEG_INFINITY; 3],
                fa_min: f64::INFINITY,
                fa_max: f64::NEG_INFINITY,
                md_min: f64::INFINITY,
                md_max: f64::NEG_INFINITY,
                von_mises_min: f64::INFINITY,
                von_mises_max: f64::NEG_INFINITY,
                tresca_min: f64::INFINITY,
                tresca_max: f64::NEG_INFINITY,
                ..FieldStats::default()
            },
            fa_sum: 0.0,
        }
    }

    /// Count `o`; its glyph, if it is valid.
    #[inline]
    fn add(&mut self, o: Outcome) -> Option<Glyph> {
        let s = &mut self.stats;
        s.tensors += 1;
        match o {
            Outcome::Nan => s.skipped_nan += 1,
            Outcome::Inf => s.skipped_inf += 1,
            Outcome::Zero => s.skipped_zero += 1,
            Outcome::Overflow => s.skipped_overflow += 1,
            Outcome::Valid {
                glyph,
                values,
                symmetrised,
            } => {
                s.valid += 1;
                s.symmetrised += usize::from(symmetrised);
                s.indefinite += usize::from(values[2] < 0.0);
                for (k, &v) in values.iter().enumerate() {
                    s.eigenvalues_min[k] = s.eigenvalues_min[k].min(v);
                    s.eigenvalues_max[k] = s.eigenvalues_max[k].max(v);
                }
                let fa = shape::fa(values);
                s.fa_min = s.fa_min.min(fa);
                s.fa_max = s.fa_max.max(fa);
                self.fa_sum += fa;
                let md = shape::md(values);
                s.md_min = s.md_min.min(md);
                s.md_max = s.md_max.max(md);
                let vm = stress::von_mises(values);
                s.von_mises_min = s.von_mises_min.min(vm);
                s.von_mises_max = s.von_mises_max.max(vm);
                let tresca = stress::tresca(values);
                s.tresca_min = s.tresca_min.min(tresca);
                s.tresca_max = s.tresca_max.max(tresca);
                s.max_abs_eigenvalue = s
                    .max_abs_eigenvalue
                    .max(values[0].abs())
                    .max(values[2].abs());
                s.classes[shape::classify(values, DEFAULT_CLASS_THRESHOLD).index()] += 1;
                return Some(glyph);
            }
        }
        None
    }

    /// Merge the counters and ranges of `o`.
    fn merge_stats(&mut self, o: &Partial) {
        let (a, b) = (&mut self.stats, &o.stats);
        a.tensors += b.tensors;
        a.valid += b.valid;
        a.skipped_nan += b.skipped_nan;
        a.skipped_inf += b.skipped_inf;
        a.skipped_zero += b.skipped_zero;
        a.skipped_overflow += b.skipped_overflow;
        a.symmetrised += b.symmetrised;
        a.indefinite += b.indefinite;
        for k in 0..3 {
            a.eigenvalues_min[k] = a.eigenvalues_min[k].min(b.eigenvalues_min[k]);
            a.eigenvalues_max[k] = a.eigenvalues_max[k].max(b.eigenvalues_max[k]);
        }
        a.fa_min = a.fa_min.min(b.fa_min);
        a.fa_max = a.fa_max.max(b.fa_max);
        a.md_min = a.md_min.min(b.md_min);
        a.md_max = a.md_max.max(b.md_max);
        a.von_mises_min = a.von_mises_min.min(b.von_mises_min);
        a.von_mises_max = a.von_mises_max.max(b.von_mises_max);
        a.tresca_min = a.tresca_min.min(b.tresca_min);
        a.tresca_max = a.tresca_max.max(b.tresca_max);
        a.max_abs_eigenvalue = a.max_abs_eigenvalue.max(b.max_abs_eigenvalue);
        for k in 0..4 {
            a.classes[k] += b.classes[k];
        }
        self.fa_sum += o.fa_sum;
    }

    /// Final stats: ranges of an empty set are 0, FA mean is the average over valid tensors.
    fn finish(mut self, glyphs: Vec<Glyph>) -> GlyphSet {
        let s = &mut self.stats;
        if s.valid == 0 {
            s.eigenvalues_min = [0.0; 3];
            s.eigenvalues_max = [0.0; 3];
            s.fa_min = 0.0;
            s.fa_max = 0.0;
            s.md_min = 0.0;
            s.md_max = 0.0;
            s.von_mises_min = 0.0;
            s.von_mises_max = 0.0;
            s.tresca_min = 0.0;
            s.tresca_max = 0.0;
            s.fa_mean = 0.0;
        } else {
            s.fa_mean = self.fa_sum / s.valid as f64;
        }
        GlyphSet {
            glyphs,
            stats: self.stats,
        }
    }
}

/// Eigendecompose every tensor of `field` into glyphs and field statistics (see module docs).
/// `progress` is advanced by the number of tensors processed.
pub fn derive_glyphs(field: &TensorField, progress: &dyn Progress) -> GlyphSet {
    let n = field.len();
    assert_eq!(
        field.positions.len(),
        n,
        "TensorField: positions and tensors differ in length"
    );
    // Two passes keep one copy of the glyphs in memory (16.7 M glyphs are 0.9 GB): count the
    // valid tensors of each chunk, then decompose each chunk straight into its own part of the
    // output, in parallel, in file order.
    let chunk_range = |c: usize| c * CHUNK..((c + 1) * CHUNK).min(n);
    let counts: Vec<usize> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            chunk_range(c)
                .filter(|&i| skipped(&field.world_tensor(i)).is_none())
                .count()
        })
        .collect();
    let placeholder = Glyph {
        centre: [0.0; 3],
        eigenvalues: [0.0; 3],
        rotation: [0.0, 0.0, 0.0, 1.0],
        index: 0,
    };
    let mut glyphs = vec![placeholder; counts.iter().sum()];
    let mut outputs: Vec<&mut [Glyph]> = Vec::with_capacity(counts.len());
    let mut rest = glyphs.as_mut_slice();
    for &k in &counts {
        let (head, tail) = rest.split_at_mut(k);
        outputs.push(head);
        rest = tail;
    }
    let partials: Vec<(Partial, usize)> = outputs
        .into_par_iter()
        .enumerate()
        .map(|(c, out)| {
            let range = chunk_range(c);
            let len = range.len();
            let mut p = Partial::new();
            let mut slots = out.iter_mut();
            let mut filled = 0;
            for i in range {
                let t = field.world_tensor(i);
                if let Some(g) = p.add(process(&t, field.position(i), i)) {
                    *slots.next().expect("no more valid tensors than counted") = g;
                    filled += 1;
                }
            }
            progress.advance(len as u64);
            (p, filled)
        })
        .collect();

    // The count saw only NaN, Inf and zero; a chunk holding tensors whose eigenvalues overflow
    // filled fewer slots than it was given: close the gaps, in order.
    let mut end = 0;
    let mut start = 0;
    for (&given, &(_, filled)) in counts.iter().zip(&partials) {
        glyphs.copy_within(start..start + filled, end);
        start += given;
        end += filled;
    }
    glyphs.truncate(end);

    let mut total = Partial::new();
    for (p, _) in &partials {
        total.merge_stats(p);
    }
    total.finish(glyphs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{DatasetKind, Location, Positions, TensorArrayInfo, Tensors};

    fn field(tensors: Vec<[f64; 9]>) -> TensorField {
        let n = tensors.len();
        TensorField {
            format: "test".into(),
            dataset: DatasetKind::PolyData,
            dims: None,
            points: n,
            cells: 0,
            array: TensorArrayInfo {
                name: "t".into(),
                components: 9,
                location: Location::Point,
            },
            positions: Positions::Points((0..n).map(|i| [i as f64, 0.0, 0.0]).collect()),
            tensors: Tensors::F64(tensors),
            direction: None,
            spacing: None,
            meta: Default::default(),
        }
    }

    /// Eigenvalues beyond what a glyph stores are a category of their own, not a valid glyph of
    /// infinite size (nor of garbage: all-f64::MAX entries gave λ3 = −3.9e261).
    #[test]
    fn overflowing_eigenvalues_are_skipped() {
        let m = f64::MAX;
        let diag = |a: f64, b: f64, c: f64| [a, 0.0, 0.0, 0.0, b, 0.0, 0.0, 0.0, c];
        let f32max = f64::from(f32::MAX);
        let tensors = vec![
            [m; 9],
            diag(1e300, 5e299, 2e299),
            diag(2.0 * f32max, 1.0, 1.0),
            diag(-2.0 * f32max, 1.0, 1.0),
            // Within range: drawn.
            diag(f32max, 1.0, 1.0),
            diag(1.0, 0.5, 0.2),
        ];
        let set = derive_glyphs(&field(tensors), &crate::progress::Silent);
        let s = &set.stats;
        assert_eq!((s.skipped_overflow, s.valid), (4, 2));
        assert_eq!(
            set.glyphs.iter().map(|g| g.index).collect::<Vec<_>>(),
            vec![4, 5]
        );
        assert!(
            set.glyphs
                .iter()
                .all(|g| g.eigenvalues.iter().all(|v| v.is_finite()))
        );
        assert_eq!(s.eigenvalues_max[0], f32max);

        // Across chunks: each chunk's gaps are closed, in file order.
        let n = 2 * CHUNK + 77;
        let bad = |i: usize| i % 1000 == 7 || i == CHUNK - 1;
        let tensors = (0..n)
            .map(|i| if bad(i) { [m; 9] } else { diag(1.0, 0.5, 0.2) })
            .collect();
        let set = derive_glyphs(&field(tensors), &crate::progress::Silent);
        let want: Vec<u32> = (0..n).filter(|&i| !bad(i)).map(|i| i as u32).collect();
        assert_eq!(set.glyphs.iter().map(|g| g.index).collect::<Vec<_>>(), want);
        assert_eq!(set.stats.skipped_overflow, n - want.len());
    }

    #[test]
    fn counts_on_handmade_field() {
        let id = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let cigar = [3.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut nan = id;
        nan[4] = f64::NAN;
        let mut inf = id;
        inf[8] = f64::INFINITY;
        let mut both = id;
        both[0] = f64::NEG_INFINITY;
        both[1] = f64::NAN; // NaN wins
        let nonsym = [2.0, 0.5, 0.0, -0.5, 2.0, 0.0, 0.0, 0.0, 0.1];
        let roundoff = [2.0, 0.5, 0.0, 0.5 + 1e-12, 2.0, 0.0, 0.0, 0.0, 0.1];
        let indefinite = [1.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.5];
        let tensors = vec![
            id, nan, cigar, [0.0; 9], inf, nonsym, both, roundoff, indefinite, [-0.0; 9],
        ];
        let set = derive_glyphs(&field(tensors), &crate::progress::Silent);
        let s = &set.stats;
        assert_eq!(s.tensors, 10);
        assert_eq!(s.skipped_nan, 2);
        assert_eq!(s.skipped_inf, 1);
        assert_eq!(s.skipped_zero, 2);
        assert_eq!(s.valid, 5);
        assert_eq!(s.symmetrised, 1);
        assert_eq!(s.indefinite, 1);
        assert_eq!(
            set.glyphs.iter().map(|g| g.index).collect::<Vec<_>>(),
            vec![0, 2, 5, 7, 8]
        );
        assert_eq!(set.glyphs[1].centre, [2.0, 0.0, 0.0]);
        assert_eq!(set.glyphs[1].eigenvalues, [3.0, 1.0, 1.0]);
        // nonsym symmetrises to diag(2, 2, 0.1): pancake
        assert_eq!(set.glyphs[2].eigenvalues, [2.0, 2.0, 0.1]);
        // classes: id ball, cigar linear, nonsym planar, roundoff (2.5, 1.5, 0.1) cp = 0.56
        // planar, indefinite magnitudes (2, 1, 0.5): cl = 0.5 → linear
        assert_eq!(s.classes, [2, 2, 1, 0]);
        assert_eq!(s.max_abs_eigenvalue, 3.0);
        assert_eq!(s.eigenvalues_max[0], 3.0);
        assert_eq!(s.eigenvalues_min[2], -2.0);
        assert_eq!(s.fa_min, 0.0);
        assert!((s.md_min - (-0.5 / 3.0)).abs() < 1e-15);
        // von Mises: 0 for the identity; Tresca: the cigar's 2 … the indefinite tensor's 3.
        assert_eq!(s.von_mises_min, 0.0);
        assert_eq!((s.tresca_min, s.tresca_max), (0.0, 3.0));
        assert_eq!(s.von_mises_max, stress::von_mises([1.0, 0.5, -2.0]));
        assert!(s.fa_mean > 0.0 && s.fa_mean < s.fa_max);
    }

    #[test]
    fn empty_and_all_invalid() {
        let set = derive_glyphs(&field(vec![]), &crate::progress::Silent);
        assert_eq!(set.stats.tensors, 0);
        assert!(set.glyphs.is_empty());
        let set = derive_glyphs(
            &field(vec![[0.0; 9], [f64::NAN; 9]]),
            &crate::progress::Silent,
        );
        assert_eq!(set.stats.valid, 0);
        assert_eq!(set.stats.fa_min, 0.0);
        assert_eq!(set.stats.eigenvalues_min, [0.0; 3]);
    }

    #[test]
    fn order_across_chunks() {
        let n = 3 * CHUNK + 17;
        let tensors: Vec<[f64; 9]> = (0..n)
            .map(|i| {
                let v = if i % 7 == 0 { 0.0 } else { 1.0 + i as f64 };
                [v, 0.0, 0.0, 0.0, v, 0.0, 0.0, 0.0, v]
            })
            .collect();
        let set = derive_glyphs(&field(tensors), &crate::progress::Silent);
        assert_eq!(set.stats.skipped_zero, n.div_ceil(7));
        assert!(set.glyphs.windows(2).all(|w| w[0].index < w[1].index));
        assert_eq!(set.glyphs.len(), set.stats.valid);
    }
}
