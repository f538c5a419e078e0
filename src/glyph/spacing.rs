//! Typical point spacing of unstructured data, for `--scale auto`.

/// At most this many query points are used for the median (deterministic stride sample).
const MAX_SAMPLES: usize = 20_000;

/// Median distance from a point to its nearest *distinct* neighbour.
///
/// Points are bucketed in a uniform grid (counting sort, O(n)) whose cell size gives about one
/// point per cell over the non-degenerate axes of the bounding box (so planar and linear point
/// sets work too); each query searches rings of cells outward until no closer point can exist.
/// If `n > 20,000`, an evenly strided sample of 20,000 query points is used (the search still
/// sees all points). Non-finite positions are ignored. Returns 1.0 when there are fewer than two
/// distinct finite points.
pub fn median_nn_distance(positions: &[[f64; 3]]) -> f64 {
    let pts: Vec<[f64; 3]> = positions
        .iter()
        .copied()
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .collect();
    let n = pts.len();
    if n < 2 {
        return 1.0;
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
        return 1.0; // all points coincide
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
    let dims = |h: f64| -> [usize; 3] { std::array::from_fn(|k| (ext[k] / h) as usize + 1) };
    let mut g = dims(h);
    while (g[0] as u128) * (g[1] as u128) * (g[2] as u128) > 2 * n as u128 + 64 {
        h *= 1.25;
        g = dims(h);
    }
    let cell_of = |p: &[f64; 3]| -> [usize; 3] {
        std::array::from_fn(|k| (((p[k] - lo[k]) / h) as usize).min(g[k] - 1))
    };
    let flat = |c: [usize; 3]| (c[2] * g[1] + c[1]) * g[0] + c[0];
    let ncells = g[0] * g[1] * g[2];

    // Counting sort of point indices by cell.
    let cells: Vec<u32> = pts.iter().map(|p| flat(cell_of(p)) as u32).collect();
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
    drop(fill);

    let step = n.div_ceil(MAX_SAMPLES).max(1);
    let max_ring = g[0].max(g[1]).max(g[2]);
    let mut dists: Vec<f64> = Vec::with_capacity(n / step + 1);
    for qi in (0..n).step_by(step) {
        let p = pts[qi];
        let c = cell_of(&p);
        let mut best2 = f64::INFINITY;
        for r in 0..=max_ring {
            let rng = |k: usize| {
                let a = c[k].saturating_sub(r);
                let b = (c[k] + r).min(g[k] - 1);
                a..=b
            };
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
                        let f = flat([x, y, z]);
                        for &j in &order[start[f] as usize..start[f + 1] as usize] {
                            let q = pts[j as usize];
                            let d2 = (q[0] - p[0]).powi(2)
                                + (q[1] - p[1]).powi(2)
                                + (q[2] - p[2]).powi(2);
                            if d2 > 0.0 && d2 < best2 {
                                best2 = d2;
                            }
                        }
                    }
                }
            }
            // Points beyond rings 0..=r are more than r·h away along some axis.
            let reach = r as f64 * h;
            if best2 <= reach * reach {
                break;
            }
        }
        if best2.is_finite() {
            dists.push(best2.sqrt());
        }
    }
    if dists.is_empty() {
        return 1.0;
    }
    let mid = dists.len() / 2;
    let (_, m, _) = dists.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    *m
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
}
