//! How much room each glyph has, for `--scale auto`: the typical point spacing of unstructured
//! data ([`median_nn_distance`]) and each point's own ([`local_spacing`]).
//!
//! Both search a uniform grid of buckets (counting sort, O(n)) whose cell size gives about one
//! point per cell over the non-degenerate axes of the bounding box (so planar and linear point
//! sets work too); a query searches rings of cells outward until no closer point can exist.
//! Hand-written rather than a k-d tree crate: the points are a mesh's nodes or cell centres,
//! nearly uniform at the scale of a cell, where a grid's buckets answer a k-nearest query in a
//! ring or two, with no tree to build.

use rayon::prelude::*;

/// At most this many query points are used for the median (deterministic stride sample).
const MAX_SAMPLES: usize = 20_000;

/// The bucketed points.
struct Grid {
    pts: Vec<[f64; 3]>,
    lo: [f64; 3],
    h: f64,
    g: [usize; 3],
    /// Points of cell c: `order[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    order: Vec<u32>,
    /// Axes with real extent (1 to 3).
    dims: usize,
}

impl Grid {
    /// `None` when there are fewer than two distinct finite points.
    fn new(positions: &[[f64; 3]]) -> Option<Self> {
        let pts: Vec<[f64; 3]> = positions
            .iter()
            .copied()
            .filter(|p| p.iter().all(|x| x.is_finite()))
            .collect();
        let n = pts.len();
        if n < 2 {
            return None;
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &pts {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let ext: [f64; 3] = std::array::from_fn(|k| hi[k] - lo[k]);
        let max_ext = ext[0].max(ext[1]).max(ext[2]);
        if max_ext <= 0.0 {
            return None; // all points coincide
        }
        // Cell size: about one point per cell over the axes with real extent.
        let live: Vec<f64> = ext
            .iter()
            .copied()
            .filter(|&e| e > 1e-9 * max_ext)
            .collect();
        let vol: f64 = live.iter().product();
        let mut h = (vol / n as f64).powf(1.0 / live.len() as f64);
        if !(h.is_finite() && h > 0.0) {
            h = max_ext / n as f64;
        }
        // Keep the cell count bounded (≤ 2 n + some), enlarging h if needed.
        let dims_of = |h: f64| -> [usize; 3] { std::array::from_fn(|k| (ext[k] / h) as usize + 1) };
        let mut g = dims_of(h);
        while (g[0] as u128) * (g[1] as u128) * (g[2] as u128) > 2 * n as u128 + 64 {
            h *= 1.25;
            g = dims_of(h);
        }
        let mut grid = Grid {
            pts: Vec::new(),
            lo,
            h,
            g,
            start: Vec::new(),
            order: Vec::new(),
            dims: live.len(),
        };
        let ncells = g[0] * g[1] * g[2];
        // Counting sort of point indices by cell.
        let cells: Vec<u32> = pts
            .iter()
            .map(|p| grid.flat(grid.cell_of(p)) as u32)
            .collect();
        let mut start = vec![0u32; ncells + 1];
        for &c in &cells {
            start[c as usize + 1] += 1;
        }
        for i in 0..ncells {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; n];
        for (i, &c) in cells.iter().enumerate() {
            order[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        grid.pts = pts;
        grid.start = start;
        grid.order = order;
        Some(grid)
    }

    fn cell_of(&self, p: &[f64; 3]) -> [usize; 3] {
        std::array::from_fn(|k| (((p[k] - self.lo[k]) / self.h) as usize).min(self.g[k] - 1))
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        (c[2] * self.g[1] + c[1]) * self.g[0] + c[0]
    }

    /// The distance from `p` to its `k`-th nearest distinct point (points at distance 0 are
    /// `p` itself or its duplicates); infinite when there are fewer than `k`. `best` is
    /// scratch space.
    fn kth_distance(&self, p: [f64; 3], k: usize, best: &mut Vec<f64>) -> f64 {
        best.clear();
        let c = self.cell_of(&p);
        let g = self.g;
        let max_ring = g[0].max(g[1]).max(g[2]);
        // The k smallest squared distances so far, ascending.
        let worst = |best: &Vec<f64>| {
            if best.len() < k {
                f64::INFINITY
            } else {
                best[k - 1]
            }
        };
        for r in 0..=max_ring {
            let rng = |a: usize| c[a].saturating_sub(r)..=(c[a] + r).min(g[a] - 1);
            for z in rng(2) {
                for y in rng(1) {
                    for x in rng(0) {
                        // Only the shell at Chebyshev distance exactly r.
                        let d = (x.abs_diff(c[0]))
                            .max(y.abs_diff(c[1]))
                            .max(z.abs_diff(c[2]));
                        if d != r {
                            continue;
                        }
                        let f = self.flat([x, y, z]);
                        let bucket =
                            &self.order[self.start[f] as usize..self.start[f + 1] as usize];
                        for &j in bucket {
                            let q = self.pts[j as usize];
                            let d2 = (q[0] - p[0]).powi(2)
                                + (q[1] - p[1]).powi(2)
                                + (q[2] - p[2]).powi(2);
                            if d2 > 0.0 && d2 < worst(best) {
                                let at = best.partition_point(|&b| b <= d2);
                                best.insert(at, d2);
                                best.truncate(k);
                            }
                        }
                    }
                }
            }
            // Points beyond rings 0..=r are more than r·h away along some axis.
            let reach = r as f64 * self.h;
            if worst(best) <= reach * reach {
                break;
            }
        }
        worst(best).sqrt()
    }
}

/// Median distance from a point to its nearest *distinct* neighbour.
///
/// If `n > 20,000`, an evenly strided sample of 20,000 query points is used (the search still
/// sees all points). Non-finite positions are ignored. Returns 1.0 when there are fewer than two
/// distinct finite points.
pub fn median_nn_distance(positions: &[[f64; 3]]) -> f64 {
    let Some(grid) = Grid::new(positions) else {
        return 1.0;
    };
    let n = grid.pts.len();
    let step = n.div_ceil(MAX_SAMPLES).max(1);
    let mut best = Vec::new();
    let mut dists: Vec<f64> = (0..n)
        .step_by(step)
        .map(|i| grid.kth_distance(grid.pts[i], 1, &mut best))
        .filter(|d| d.is_finite())
        .collect();
    if dists.is_empty() {
        return 1.0;
    }
    let mid = dists.len() / 2;
    let (_, m, _) = dists.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    *m
}

/// Each point's own spacing: the distance to its `2 d`-th nearest distinct neighbour, `d` the
/// number of axes the points extend along (6 in a volume): on a lattice, the lattice step
/// (its `2 d` face neighbours), and among irregular points (the cell centres of a
/// tetrahedral mesh, a graded mesh's nodes) a size that follows the local density rather
/// than the closest pair, which a mesher's slivers and a hexahedron's six tetrahedra put far
/// closer than the cells are large. NaN for a non-finite position; `None` when there are fewer
/// than two distinct finite points.
pub fn local_spacing(positions: &[[f64; 3]]) -> Option<Vec<f32>> {
    let grid = Grid::new(positions)?;
    let k = 2 * grid.dims;
    Some(
        positions
            .par_iter()
            .map_init(Vec::new, |best, p| {
                if p.iter().all(|x| x.is_finite()) {
                    let d = grid.kth_distance(*p, k, best);
                    // Fewer than k distinct points in all: the farthest there is.
                    let d = if d.is_finite() {
                        d
                    } else {
                        best.last().map_or(f64::NAN, |b| b.sqrt())
                    };
                    d as f32
                } else {
                    f32::NAN
                }
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_grid() {
        let mut p = vec![];
        for z in 0..10 {
            for y in 0..12 {
                for x in 0..7 {
                    p.push([x as f64 * 0.3, y as f64 * 0.3, z as f64 * 0.3 + 100.0]);
                }
            }
        }
        assert!((median_nn_distance(&p) - 0.3).abs() < 1e-12);
    }

    #[test]
    fn planar_line_and_degenerate() {
        let plane: Vec<[f64; 3]> = (0..400)
            .map(|i| [(i % 20) as f64 * 2.0, (i / 20) as f64 * 2.0, 5.0])
            .collect();
        assert!((median_nn_distance(&plane) - 2.0).abs() < 1e-12);
        let line: Vec<[f64; 3]> = (0..50).map(|i| [0.0, 0.0, i as f64 * 0.5]).collect();
        assert!((median_nn_distance(&line) - 0.5).abs() < 1e-12);
        assert_eq!(median_nn_distance(&[]), 1.0);
        assert_eq!(median_nn_distance(&[[1.0, 2.0, 3.0]; 5]), 1.0);
        // duplicates are ignored in favour of the nearest distinct point
        let dup = [[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        assert_eq!(median_nn_distance(&dup), 1.0);
    }

    #[test]
    fn random_points_match_brute_force() {
        // xorshift for determinism
        let mut s = 0x9E3779B97F4A7C15u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<[f64; 3]> = (0..1500)
            .map(|_| [rnd() * 10.0, rnd() * 3.0, rnd() * 50.0])
            .collect();
        let mut bf: Vec<f64> = pts
            .iter()
            .map(|p| {
                pts.iter()
                    .map(|q| {
                        ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2))
                            .sqrt()
                    })
                    .filter(|&d| d > 0.0)
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        bf.sort_by(|a, b| a.total_cmp(b));
        let want = bf[bf.len() / 2];
        assert_eq!(median_nn_distance(&pts), want);
    }

    #[test]
    fn local_spacing_is_the_lattice_step_inside_and_follows_the_density() {
        // A 6 x 5 x 4 lattice of step 0.5: inside, the six face neighbours are at 0.5.
        let mut p = vec![];
        for z in 0..4 {
            for y in 0..5 {
                for x in 0..6 {
                    p.push([x as f64 * 0.5, y as f64 * 0.5, z as f64 * 0.5]);
                }
            }
        }
        let h = local_spacing(&p).unwrap();
        let at = |x: usize, y: usize, z: usize| h[x + 6 * (y + 5 * z)];
        assert_eq!(at(2, 2, 1), 0.5);
        // A face point has five neighbours at the step: its sixth is a diagonal.
        assert!((at(0, 2, 1) - 0.5 * 2f32.sqrt()).abs() < 1e-6);
        // A planar lattice: four neighbours.
        let plane: Vec<[f64; 3]> = (0..100)
            .map(|i| [(i % 10) as f64, (i / 10) as f64, 0.0])
            .collect();
        assert_eq!(local_spacing(&plane).unwrap()[55], 1.0);
        // Pairs of points 0.01 apart on a lattice of step 1: the pair's distance is the median
        // nearest neighbour, the local spacing stays near the step.
        let pairs: Vec<[f64; 3]> = p
            .iter()
            .flat_map(|q| {
                [
                    q.map(|x| 2.0 * x),
                    [2.0 * q[0] + 0.01, 2.0 * q[1], 2.0 * q[2]],
                ]
            })
            .collect();
        assert!((median_nn_distance(&pairs) - 0.01).abs() < 1e-9);
        let h = local_spacing(&pairs).unwrap();
        // The first of the pair at lattice point (2, 2, 1).
        let inside = 2 * (2 + 6 * (2 + 5));
        assert!((h[inside] - 1.0).abs() < 0.02, "{}", h[inside]);
        // Non-finite positions have none; too few points, none at all.
        let mut with_nan = p.clone();
        with_nan[3] = [f64::NAN, 0.0, 0.0];
        assert!(local_spacing(&with_nan).unwrap()[3].is_nan());
        assert_eq!(local_spacing(&[[1.0; 3]]), None);
        // Three distinct points: fewer than six neighbours, the farthest.
        let three = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        assert_eq!(local_spacing(&three).unwrap()[0], 2.0);
    }

    #[test]
    fn kth_distance_matches_brute_force() {
        let mut s = 0x2545F4914F6CDD1Du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<[f64; 3]> = (0..800)
            .map(|_| [rnd() * 4.0, rnd() * 40.0, rnd() * 2.0])
            .collect();
        let h = local_spacing(&pts).unwrap();
        for (i, p) in pts.iter().enumerate().step_by(37) {
            let mut d: Vec<f64> = pts
                .iter()
                .map(|q| {
                    ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)).sqrt()
                })
                .filter(|&d| d > 0.0)
                .collect();
            d.sort_by(f64::total_cmp);
            assert_eq!(h[i], d[5] as f32, "point {i}");
        }
    }
}
