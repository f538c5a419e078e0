//! The maxima of f on the sphere (fibre directions) and its range (for min–max normalisation):
//! seeded on a geodesic sphere, refined by Newton ascent in the tangent plane (module doc, §4).

use std::sync::OnceLock;

use super::basis::{ShBasis, ShError};
use super::eval::ShEval;

/// Subdivisions of the icosahedron the seeds are taken from: 10242 vertices, neighbours at most
/// 2.4° apart. Fibre lobes are 15° wide and more at lmax 12; the ringing between them has
/// maxima whose basins are narrower still (1.5° in the MRtrix lmax 12 test file), which a
/// coarser sphere (4°) missed.
const SEED_LEVEL: u32 = 5;

/// Newton ascent stops when a step moves the direction less than this (radians): far below
/// the 0.01° (1.7e-4 rad) a peak is promised to.
const STEP_TOL: f64 = 1e-10;

/// Peaks within this angle (degrees) of each other are one peak, however the threshold
/// options are set: two seeds that climbed to the same maximum.
pub const SAME_PEAK_DEG: f64 = 0.01;

/// Which maxima count as peaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeakOptions {
    /// Keep a maximum only if its value is at least this fraction of the largest (DIPY's
    /// `relative_peak_threshold`, 0.5 in `peaks_from_model`'s examples; 0 keeps every
    /// maximum of positive value; −∞ every maximum, negative ones too, as MRtrix's `sh2peaks`
    /// does without `-threshold`).
    pub relative_threshold: f64,
    /// Drop a maximum within this angle (degrees, either way along the axis) of a larger one
    /// (DIPY's `min_separation_angle`, 25).
    pub min_separation_deg: f64,
    /// At most this many peaks, largest first (`sh2peaks -num`, 3).
    pub max_peaks: usize,
}

impl Default for PeakOptions {
    /// DIPY's `peaks_from_model` settings with five peaks.
    fn default() -> Self {
        PeakOptions {
            relative_threshold: 0.5,
            min_separation_deg: 25.0,
            max_peaks: 5,
        }
    }
}

/// One maximum of f: a unit direction (either of ±u; the one given has its largest-magnitude
/// component positive) and f there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    pub direction: [f64; 3],
    pub value: f64,
}

/// The geodesic seed sphere: vertices and each vertex's neighbours.
struct Seeds {
    vertices: Vec<[f64; 3]>,
    neighbours: Vec<Vec<u32>>,
}

fn seeds() -> &'static Seeds {
    static SEEDS: OnceLock<Seeds> = OnceLock::new();
    SEEDS.get_or_init(|| icosphere(SEED_LEVEL))
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    a.map(|x| x / n)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The geodesic sphere of `level` ([`crate::geodesic`]) and each vertex's neighbours.
fn icosphere(level: u32) -> Seeds {
    let (v, faces) = crate::geodesic::icosphere(level);
    let mut neighbours = vec![Vec::new(); v.len()];
    for f in &faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            for (x, y) in [(a, b), (b, a)] {
                if !neighbours[x as usize].contains(&y) {
                    neighbours[x as usize].push(y);
                }
            }
        }
    }
    Seeds {
        vertices: v,
        neighbours,
    }
}

/// Finds the peaks and range of SH series of one lmax and basis; holds the seed sphere's
/// basis functions, so that each voxel costs one matrix–vector product and a few ascents.
#[derive(Clone)]
pub struct PeakFinder {
    eval: ShEval,
    /// Basis functions at each seed vertex, row after row.
    rows: Vec<f64>,
}

impl PeakFinder {
    pub fn new(lmax: u32, basis: ShBasis) -> Result<Self, ShError> {
        let mut eval = ShEval::new(lmax, basis)?;
        let n = eval.count();
        let s = seeds();
        let mut rows = vec![0.0; s.vertices.len() * n];
        for (row, &u) in rows.chunks_exact_mut(n).zip(&s.vertices) {
            eval.row(u, row);
        }
        Ok(PeakFinder { eval, rows })
    }

    /// f at every seed vertex.
    fn sample(&self, c: &[f64]) -> Vec<f64> {
        self.rows
            .chunks_exact(self.eval.count())
            .map(|r| r.iter().zip(c).map(|(a, b)| a * b).sum())
            .collect()
    }

    /// The local maxima of `sign · f` (sampled at the seeds as `values`), refined: (direction,
    /// sign · f).
    fn maxima(&mut self, c: &[f64], values: &[f64], sign: f64) -> Vec<Peak> {
        let s = seeds();
        let mut found: Vec<Peak> = Vec::new();
        for (i, &v) in values.iter().enumerate() {
            let v = sign * v;
            // Ties go to the lower index, so a plateau seeds once.
            let top = s.neighbours[i].iter().all(|&j| {
                let w = sign * values[j as usize];
                v > w || (v == w && i < j as usize)
            });
            // Each axis is seeded from its vertex with z > 0 (or on the equator, both): the
            // series is even, the other half repeats it.
            if !top || !v.is_finite() || s.vertices[i][2] < 0.0 {
                continue;
            }
            let p = self.ascend(c, s.vertices[i], sign);
            let same = found
                .iter()
                .any(|q| dot(q.direction, p.direction).abs() >= SAME_PEAK_DEG.to_radians().cos());
            if !same {
                found.push(p);
            }
        }
        found.sort_by(|a, b| b.value.total_cmp(&a.value));
        found
    }

    /// Newton ascent of `sign · f` from `u` along the sphere, backed by gradient steps where
    /// the tangent Hessian is not negative definite, within a trust radius.
    fn ascend(&mut self, c: &[f64], u0: [f64; 3], sign: f64) -> Peak {
        let mut u = u0;
        let (mut v, mut g) = self.eval.value_gradient(c, u);
        v *= sign;
        g = g.map(|x| sign * x);
        let mut radius: f64 = 0.05;
        for _ in 0..200 {
            let (t1, t2) = tangents(u);
            let gt = [dot(g, t1), dot(g, t2)];
            // The tangent Hessian from central differences of the exact gradient along the
            // two geodesics: its error (h² times the third derivative) only slows Newton,
            // the fixed point is where the exact gradient vanishes.
            let h = 1e-5;
            let mut hess = [[0.0; 2]; 2];
            for (k, t) in [t1, t2].into_iter().enumerate() {
                let gp = self.eval.value_gradient(c, geodesic(u, t, h)).1;
                let gm = self.eval.value_gradient(c, geodesic(u, t, -h)).1;
                let d: [f64; 3] = std::array::from_fn(|i| sign * (gp[i] - gm[i]) / (2.0 * h));
                hess[k] = [dot(d, t1), dot(d, t2)];
            }
            let (a, b, d) = (hess[0][0], 0.5 * (hess[0][1] + hess[1][0]), hess[1][1]);
            let det = a * d - b * b;
            let mut step = if a < 0.0 && det > 0.0 {
                // δ = −H⁻¹ g.
                [
                    -(d * gt[0] - b * gt[1]) / det,
                    -(a * gt[1] - b * gt[0]) / det,
                ]
            } else {
                gt
            };
            let len = step[0].hypot(step[1]);
            if !(len.is_finite()) || len == 0.0 {
                break;
            }
            if len > radius {
                step = step.map(|x| x * radius / len);
            }
            let len = len.min(radius);
            let dir: [f64; 3] = std::array::from_fn(|i| (step[0] * t1[i] + step[1] * t2[i]) / len);
            let next = geodesic(u, dir, len);
            let (nv, ng) = self.eval.value_gradient(c, next);
            let nv = sign * nv;
            // Near the top f is flat to rounding: a step that loses no more than rounding is
            // taken, so that the ascent ends where the gradient vanishes, not where the values
            // stop telling points apart (about 3e-9 rad away).
            if nv >= v - 4.0 * f64::EPSILON * v.abs() {
                u = next;
                v = nv;
                g = ng.map(|x| sign * x);
                if len < STEP_TOL {
                    break;
                }
                radius = (radius * 2.0).min(0.2);
            } else {
                radius = len / 4.0;
                if radius < STEP_TOL {
                    break;
                }
            }
        }
        Peak {
            direction: canonical(u),
            value: v,
        }
    }

    /// The peaks of f (coefficients `c`), largest first: every local maximum on the sphere
    /// (one per axis), refined, then thresholded and thinned as `opts` say. None for a series
    /// whose largest maximum is not positive, or that is not finite.
    pub fn peaks(&mut self, c: &[f64], opts: &PeakOptions) -> Vec<Peak> {
        if c.len() != self.eval.count() || c.iter().any(|x| !x.is_finite()) {
            return Vec::new();
        }
        let values = self.sample(c);
        if flat(&values).is_some() {
            return Vec::new();
        }
        let all = self.maxima(c, &values, 1.0);
        let Some(top) = all.first().map(|p| p.value).filter(|&v| v > 0.0) else {
            return Vec::new();
        };
        let cos_sep = opts.min_separation_deg.to_radians().cos();
        let mut kept: Vec<Peak> = Vec::new();
        for p in all {
            if p.value < opts.relative_threshold * top || kept.len() == opts.max_peaks {
                break;
            }
            if kept
                .iter()
                .all(|q| dot(q.direction, p.direction).abs() < cos_sep)
            {
                kept.push(p);
            }
        }
        kept
    }

    /// The smallest and largest value of f on the sphere, each refined as peaks are; `None`
    /// when the coefficients are not finite or not as many as the lmax holds.
    pub fn range(&mut self, c: &[f64]) -> Option<(f64, f64)> {
        if c.len() != self.eval.count() || c.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let values = self.sample(c);
        if let Some(range) = flat(&values) {
            return Some(range);
        }
        let max = self.maxima(c, &values, 1.0).first()?.value;
        let min = -self.maxima(c, &values, -1.0).first()?.value;
        Some((min, max))
    }
}

/// The samples' range if they differ by no more than rounding (1e-12 of their magnitude): a
/// constant f, whose every sample is a maximum of rounding errors and has no peak.
fn flat(values: &[f64]) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    (hi - lo <= 1e-12 * lo.abs().max(hi.abs())).then_some((lo, hi))
}

/// f normalised to [0, 1] by its range on the sphere, as DIPY's `minmax_normalize` does to
/// an ODF's samples (1 everywhere for a constant f).
pub fn min_max(value: f64, (min, max): (f64, f64)) -> f64 {
    if max > min {
        (value - min) / (max - min)
    } else {
        1.0
    }
}

/// Two unit tangents at `u`, orthogonal to it and to each other.
fn tangents(u: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if u[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let t1 = normalise(cross(u, a));
    (t1, cross(u, t1))
}

/// The point `angle` radians from `u` along the unit tangent `t`.
fn geodesic(u: [f64; 3], t: [f64; 3], angle: f64) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    normalise(std::array::from_fn(|i| u[i] * c + t[i] * s))
}

/// The one of ±u whose largest-magnitude component is positive.
fn canonical(u: [f64; 3]) -> [f64; 3] {
    let k = (0..3)
        .max_by(|&a, &b| u[a].abs().total_cmp(&u[b].abs()))
        .unwrap_or(0);
    if u[k] < 0.0 { u.map(|x| -x) } else { u }
}

#[cfg(test)]
mod tests {
    use super::super::basis::{convert, index};
    use super::*;

    /// The coefficients (tournier07, lmax 8) of Σ_k w_k δ-like lobes: a sharp axially
    /// symmetric kernel (Λ_l^0 at the pole) rotated to each `axis` by the addition theorem,
    /// f(u) = Σ_k w_k Σ_l g_l P_l(u·a_k), exactly representable.
    fn lobes(axes: &[([f64; 3], f64)]) -> Vec<f64> {
        let lmax = 8;
        let mut e = ShEval::new(lmax, ShBasis::Tournier07).unwrap();
        let n = e.count();
        let mut c = vec![0.0; n];
        let mut row = vec![0.0; n];
        for &(a, w) in axes {
            // δ's expansion truncated at lmax: c_j = Y_j(a), a peak at a.
            e.row(a, &mut row);
            for j in 0..n {
                c[j] += w * row[j];
            }
        }
        c
    }

    fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
        dot(normalise(a), normalise(b))
            .abs()
            .min(1.0)
            .acos()
            .to_degrees()
    }

    #[test]
    fn the_seed_sphere_is_a_closed_geodesic_mesh() {
        let s = seeds();
        assert_eq!(s.vertices.len(), 10242);
        // 30 · 4^5 edges, each counted from both ends.
        assert_eq!(s.neighbours.iter().map(Vec::len).sum::<usize>(), 2 * 30720);
        let worst = s
            .vertices
            .iter()
            .enumerate()
            .flat_map(|(i, &u)| s.neighbours[i].iter().map(move |&j| (u, j)))
            .map(|(u, j)| angle_deg(u, s.vertices[j as usize]))
            .fold(0.0, f64::max);
        assert!(worst < 2.4, "{worst}");
    }

    #[test]
    fn truncated_delta_lobes_peak_at_their_axes() {
        // Two crossing fibres 60° apart, the second weaker, off every seed vertex.
        let a = normalise([0.31, -0.2, 0.93]);
        let b = normalise([0.9, 0.35, -0.1]);
        let c = lobes(&[(a, 1.0), (b, 0.7)]);
        for &basis in ShBasis::VALUES {
            let cb = convert(&c, ShBasis::Tournier07, basis).unwrap();
            let mut finder = PeakFinder::new(8, basis).unwrap();
            let p = finder.peaks(&cb, &PeakOptions::default());
            assert_eq!(p.len(), 2, "{basis}: {p:?}");
            // A truncated δ sum peaks near, not exactly at, its axes when lobes overlap: the
            // ascent's answer is checked by the gradient, the axes loosely.
            assert!(angle_deg(p[0].direction, a) < 3.0, "{p:?}");
            assert!(angle_deg(p[1].direction, b) < 3.0, "{p:?}");
            let mut e = ShEval::new(8, basis).unwrap();
            for q in &p {
                let (v, g) = e.value_gradient(&cb, q.direction);
                assert!((v - q.value).abs() < 1e-12);
                assert!(dot(g, g).sqrt() < 1e-9 * v.abs(), "{g:?}");
            }
        }
    }

    #[test]
    fn a_single_lobe_peaks_exactly_on_its_axis_even_at_a_pole() {
        for a in [
            [0.0, 0.0, 1.0],
            normalise([1.0, 2.0, 3.0]),
            [0.0, -1.0, 0.0],
        ] {
            let c = lobes(&[(a, 2.0)]);
            let p = PeakFinder::new(8, ShBasis::Tournier07)
                .unwrap()
                .peaks(&c, &PeakOptions::default());
            assert_eq!(p.len(), 1, "{p:?}");
            assert!(angle_deg(p[0].direction, a) < 1e-6, "{a:?}: {p:?}");
        }
    }

    #[test]
    fn thresholds_separation_and_count_thin_the_maxima() {
        let a = normalise([0.0, 0.2, 1.0]);
        let b = normalise([1.0, 0.0, 0.1]);
        let c = lobes(&[(a, 1.0), (b, 0.3)]);
        let mut f = PeakFinder::new(8, ShBasis::Tournier07).unwrap();
        let strict = f.peaks(&c, &PeakOptions::default());
        assert_eq!(strict.len(), 1);
        let loose = PeakOptions {
            relative_threshold: 0.0,
            ..PeakOptions::default()
        };
        let all = f.peaks(&c, &loose);
        assert!(all.len() >= 2);
        assert!(all.windows(2).all(|w| w[0].value >= w[1].value));
        let one = PeakOptions {
            max_peaks: 1,
            ..loose
        };
        assert_eq!(f.peaks(&c, &one).len(), 1);
        // Constant and non-finite series: no peaks, and a flat range.
        let mut iso = vec![0.0; 45];
        iso[index(0, 0)] = 1.0;
        assert!(f.peaks(&iso, &loose).is_empty());
        let (lo, hi) = f.range(&iso).unwrap();
        assert!((hi - lo).abs() < 1e-15 && min_max(0.3, (lo, hi)) == 1.0);
        iso[3] = f64::NAN;
        assert!(f.peaks(&iso, &loose).is_empty());
        assert!(f.range(&iso).is_none());
    }

    #[test]
    fn the_range_bounds_every_sample_and_is_reached() {
        let c = lobes(&[([0.0, 0.6, 0.8], 1.0), ([1.0, 0.0, 0.0], 0.8)]);
        let mut f = PeakFinder::new(8, ShBasis::Tournier07).unwrap();
        let (lo, hi) = f.range(&c).unwrap();
        let mut e = ShEval::new(8, ShBasis::Tournier07).unwrap();
        let mut seen = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..20000 {
            // A Fibonacci sphere, denser than the seeds.
            let z = 1.0 - (2.0 * i as f64 + 1.0) / 20000.0;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f64 * 2.399_963_229_728_653;
            let v = e.value(&c, [r * phi.cos(), r * phi.sin(), z]);
            seen = (seen.0.min(v), seen.1.max(v));
        }
        assert!(seen.0 >= lo - 1e-12 && seen.1 <= hi + 1e-12);
        assert!(seen.0 - lo < 1e-3 * (hi - lo) && hi - seen.1 < 1e-3 * (hi - lo));
        assert!((min_max(hi, (lo, hi)) - 1.0).abs() < 1e-15 && min_max(lo, (lo, hi)) == 0.0);
    }
}
