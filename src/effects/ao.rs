//! Ambient occlusion (`--ao`): how much of the sky above a surface point the glyphs around it
//! leave open, within a reach `R`.
//!
//! **The truth** (the reference, [`crate::reference::ReferenceScene`]): the fraction of
//! [`REFERENCE_DIRECTIONS`] fixed, cosine-weighted directions of the hemisphere about the
//! point's normal whose exact f64 ray meets no glyph within `R` ([`hemisphere`]).
//!
//! **The GPU's estimate** at a fixed cost per pixel, whatever the glyph count (after Grottel et
//! al. 2012, MegaMol's object-space AO): the glyphs are splatted once, when the scene is
//! uploaded, into a coarse volume over the scene's box ([`DensityVolume`]) holding the
//! extinction a ray meets there, σ = Σ S/4 per cell volume (S a glyph's surface area: a convex
//! body of random orientation shows S/4 of area on average, Cauchy's formula). In the
//! composite pass [`CONES`] cones about the normal march the volume's mip levels (coarser with
//! distance, but never so coarse that a level's blur reaches back to the surface the cone
//! leaves) and each sees exp(−∫σ) of the sky: the open fraction for glyphs
//! scattered at random. A lattice is not random, a glyph's own splat blurs into its
//! neighbourhood, and ellipsoids stand in for every kind's area, so the estimate differs from
//! the truth; `--reference-check` states by how much (`ao_error_mean`, `ao_error_p95`).

use glam::DVec3;

use crate::scene::Scene;

/// Ambient occlusion's options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmbientOcclusion {
    /// How far the occlusion darkens: the ambient and headlight terms are scaled by
    /// 1 − strength·(1 − open fraction).
    pub strength: f32,
    /// The reach `R` in mean largest glyph radii ([`reach`]).
    pub reach: f32,
}

impl AmbientOcclusion {
    /// `--ao` without a value.
    pub const DEFAULT_STRENGTH: f32 = 0.8;
    /// Four mean largest radii: two lattice steps of a field drawn at `--scale auto`.
    pub const DEFAULT_REACH: f32 = 4.0;

    /// The factor on the ambient and headlight terms of a point whose open fraction is `open`.
    pub fn factor(&self, open: f64) -> f64 {
        1.0 - f64::from(self.strength.clamp(0.0, 1.0)) * (1.0 - open.clamp(0.0, 1.0))
    }
}

impl Default for AmbientOcclusion {
    fn default() -> Self {
        Self {
            strength: Self::DEFAULT_STRENGTH,
            reach: Self::DEFAULT_REACH,
        }
    }
}

/// Directions the reference casts per pixel.
pub const REFERENCE_DIRECTIONS: usize = 32;

/// Cones the GPU marches per pixel, three steps each (composite.wgsl's `AO_CONES` pattern is
/// [`hemisphere`]`(4)`; six cones of four steps cost twice as much for a mean error 0.005–0.008
/// smaller on the scenes of `tests/gpu/effects.rs`).
pub const CONES: usize = 4;

/// Cells along the volume's longest side.
pub const VOLUME_CELLS: u32 = 64;

/// `n` fixed unit directions about +z, cosine-weighted (a Fibonacci spiral on the disc lifted
/// to the hemisphere: equal areas of the disc are equal shares of the cosine-weighted sky).
pub fn hemisphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let r = ((k as f64 + 0.5) / n as f64).sqrt();
            let phi = golden * k as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt())
        })
        .collect()
}

/// A right-handed frame whose third axis is the unit vector `n` (Frisvad's, with the
/// Duff et al. 2017 fix of its sign).
pub fn frame(n: DVec3) -> [DVec3; 3] {
    let s = 1f64.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [
        DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        DVec3::new(b, s + n.y * n.y * a, -n.y),
        n,
    ]
}

/// The reach `R` of a scene: [`AmbientOcclusion::reach`] mean largest radii of its glyphs.
pub fn reach(scene: &Scene, ao: &AmbientOcclusion) -> f64 {
    let n = scene.instances.len().max(1) as f64;
    let mean: f64 = scene
        .instances
        .iter()
        .map(|g| f64::from(g.radii.iter().fold(0.0f32, |a, &b| a.max(b.abs()))))
        .sum::<f64>()
        / n;
    let r = f64::from(ao.reach.max(0.0)) * mean;
    if r.is_finite() && r > 0.0 {
        r
    } else {
        scene.radius.max(1e-30) * 0.1
    }
}

/// Surface area of the ellipsoid with semi-axes `r` (Knud Thomsen's formula, within 1.1 %).
pub fn ellipsoid_area(r: [f64; 3]) -> f64 {
    const P: f64 = 1.6075;
    let [a, b, c] = r.map(|x| x.abs().powf(P));
    4.0 * std::f64::consts::PI * ((a * b + a * c + b * c) / 3.0).powf(1.0 / P)
}

/// The extinction volume the GPU marches: cell-centred, over the scene's box, relative to the
/// scene origin, in levels of a mip chain (each a 2×2×2 average of the one below).
#[derive(Debug, Clone, PartialEq)]
pub struct DensityVolume {
    /// Cells per axis of level 0.
    pub dims: [u32; 3],
    /// The box's low corner, relative to the scene origin.
    pub lo: DVec3,
    /// One cell's size.
    pub cell: DVec3,
    /// σ·R (the optical depth across one reach) per cell, level after level, x fastest.
    pub levels: Vec<Vec<f32>>,
}

impl DensityVolume {
    /// Splat every glyph's S/4 trilinearly into the cells about its centre.
    pub fn build(scene: &Scene, reach: f64) -> Self {
        let half = scene.half.max(DVec3::splat(scene.radius.max(1e-30) * 1e-3));
        let longest = half.max_element();
        let cell = longest * 2.0 / f64::from(VOLUME_CELLS);
        let dims = (half * 2.0 / cell)
            .ceil()
            .as_uvec3()
            .max(glam::UVec3::ONE)
            .min(glam::UVec3::splat(VOLUME_CELLS))
            .to_array();
        let cell = half * 2.0 / glam::UVec3::from_array(dims).as_dvec3();
        let lo = scene.centre - scene.origin - half;
        let [nx, ny, nz] = dims.map(|d| d as usize);
        let mut sigma = vec![0.0f64; nx * ny * nz];
        let cell_volume = cell.x * cell.y * cell.z;
        for g in &scene.instances {
            let r = g.radii.map(f64::from);
            let weight = ellipsoid_area(r) / 4.0 / cell_volume * reach;
            if !weight.is_finite() {
                continue;
            }
            let c = DVec3::from_array(g.centre.map(f64::from));
            // A glyph wider than a cell fills the cells whose centres it holds; a smaller one
            // is splatted trilinearly into the eight about its centre (cell centres sit at
            // lo + (i + ½) cell).
            let big = r.iter().fold(0.0f64, |a, &b| a.max(b.abs())) > cell.min_element();
            if big && fill(&mut sigma, dims, lo, cell, g, weight) {
                continue;
            }
            let u = (c - lo) / cell - 0.5;
            let base = u.floor();
            let t = u - base;
            for corner in 0..8 {
                let pick = |bit: usize| (corner >> bit) & 1;
                let w = (0..3)
                    .map(|a| if pick(a) == 1 { t[a] } else { 1.0 - t[a] })
                    .product::<f64>();
                let idx = [0, 1, 2].map(|a| base[a] as i64 + pick(a) as i64);
                if idx
                    .iter()
                    .zip(&dims)
                    .all(|(&i, &d)| i >= 0 && i < i64::from(d))
                {
                    let k = (idx[2] as usize * ny + idx[1] as usize) * nx + idx[0] as usize;
                    sigma[k] += weight * w;
                }
            }
        }
        let mut levels = vec![sigma.iter().map(|&s| s as f32).collect::<Vec<f32>>()];
        // Level sizes as the GPU has them, ⌊d/2⌋ (at least 1); an odd side's last cell joins
        // the last of the level above.
        let mut d = dims;
        while d.iter().any(|&x| x > 1) {
            let e = d.map(|x| (x / 2).max(1));
            let prev = levels.last().expect("level 0");
            let span = |x: u32, from: u32, to: u32| {
                let start = (2 * x).min(from - 1);
                let end = if x + 1 == to {
                    from
                } else {
                    (2 * x + 2).min(from)
                };
                start..end
            };
            let mut next = vec![0.0f32; (e[0] * e[1] * e[2]) as usize];
            for z in 0..e[2] {
                for y in 0..e[1] {
                    for x in 0..e[0] {
                        let (mut sum, mut count) = (0.0f32, 0.0f32);
                        for sz in span(z, d[2], e[2]) {
                            for sy in span(y, d[1], e[1]) {
                                for sx in span(x, d[0], e[0]) {
                                    sum += prev[((sz * d[1] + sy) * d[0] + sx) as usize];
                                    count += 1.0;
                                }
                            }
                        }
                        next[((z * e[1] + y) * e[0] + x) as usize] = sum / count.max(1.0);
                    }
                }
            }
            levels.push(next);
            d = e;
        }
        Self {
            dims,
            lo,
            cell,
            levels,
        }
    }
}

/// Spread `weight` (a glyph's S/4 per cell volume) evenly over the cells whose centres lie in
/// glyph `g`'s ellipsoid; false when none does.
fn fill(
    sigma: &mut [f64],
    dims: [u32; 3],
    lo: DVec3,
    cell: DVec3,
    g: &crate::scene::GlyphInstance,
    weight: f64,
) -> bool {
    let c = DVec3::from_array(g.centre.map(f64::from));
    let r = DVec3::from_array(g.radii.map(|x| f64::from(x.abs()).max(1e-30)));
    let q = glam::DQuat::from_array(g.rotation.map(f64::from)).normalize();
    let inv = q.inverse();
    let reach = r.max_element();
    let first = ((c - reach - lo) / cell - 0.5).ceil().max(DVec3::ZERO);
    let last = ((c + reach - lo) / cell - 0.5)
        .floor()
        .min(glam::UVec3::from_array(dims).as_dvec3() - 1.0);
    if first.cmpgt(last).any() {
        return false;
    }
    let inside = |i: f64, j: f64, k: f64| {
        let p = lo + (DVec3::new(i, j, k) + 0.5) * cell;
        (inv * (p - c) / r).length_squared() <= 1.0
    };
    let cells = || {
        let (a, b) = (first.as_uvec3(), last.as_uvec3());
        (a.z..=b.z)
            .flat_map(move |k| (a.y..=b.y).flat_map(move |j| (a.x..=b.x).map(move |i| (i, j, k))))
    };
    let count = cells()
        .filter(|&(i, j, k)| inside(f64::from(i), f64::from(j), f64::from(k)))
        .count();
    if count == 0 {
        return false;
    }
    let share = weight / count as f64;
    for (i, j, k) in cells() {
        if inside(f64::from(i), f64::from(j), f64::from(k)) {
            sigma[((k * dims[1] + j) * dims[0] + i) as usize] += share;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hemisphere_is_cosine_weighted_and_the_frame_orthonormal() {
        let d = hemisphere(4096);
        // E[cos θ] = 2/3 under the cosine weight (1/2 for a uniform hemisphere).
        let mean_z = d.iter().map(|v| v.z).sum::<f64>() / d.len() as f64;
        assert!((mean_z - 2.0 / 3.0).abs() < 1e-3, "{mean_z}");
        assert!(
            d.iter()
                .all(|v| (v.length() - 1.0).abs() < 1e-12 && v.z >= 0.0)
        );
        let mean_x = d.iter().map(|v| v.x).sum::<f64>() / d.len() as f64;
        assert!(mean_x.abs() < 1e-2);
        for n in [DVec3::Z, -DVec3::Z, DVec3::new(0.3, -0.5, 0.81).normalize()] {
            let [a, b, c] = frame(n);
            assert!((a.cross(b) - c).length() < 1e-12);
            assert!(a.dot(b).abs() < 1e-12 && a.dot(c).abs() < 1e-12);
            assert!((a.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn thomsens_area_is_within_its_bound() {
        let sphere = ellipsoid_area([2.0; 3]);
        assert!((sphere / (16.0 * std::f64::consts::PI) - 1.0).abs() < 1e-12);
        // A needle tends to a line (area → 0 with its radius), a disc to two discs (2πa²).
        let disc = ellipsoid_area([1.0, 1.0, 1e-9]);
        assert!(
            (disc / (2.0 * std::f64::consts::PI) - 1.0).abs() < 0.011,
            "{disc}"
        );
    }

    #[test]
    fn the_volume_holds_every_glyphs_share_and_its_mips_average() {
        use crate::scene::GlyphSpec;
        let specs: Vec<GlyphSpec> = (0..50)
            .map(|k| GlyphSpec {
                centre: DVec3::new(k as f64 * 0.37, (k * k % 7) as f64, (k % 3) as f64 * 0.5),
                rotation: glam::DQuat::IDENTITY,
                radii: DVec3::new(0.3, 0.2, 0.1 + 0.01 * k as f64),
                color: [255; 4],
            })
            .collect();
        let scene = Scene::from_specs(&specs);
        let reach = 1.7;
        let v = DensityVolume::build(&scene, reach);
        assert_eq!(v.dims.iter().copied().max(), Some(VOLUME_CELLS));
        // σ integrates to Σ S/4 over the volume (every centre lies inside the box's cells).
        let cell_volume = v.cell.x * v.cell.y * v.cell.z;
        let total: f64 = v.levels[0].iter().map(|&s| f64::from(s)).sum::<f64>() * cell_volume;
        let want: f64 = specs
            .iter()
            .map(|s| ellipsoid_area(s.radii.to_array()) / 4.0 * reach)
            .sum();
        assert!((total / want - 1.0).abs() < 0.02, "{total} vs {want}");
        // Each level has the GPU's size, ⌊d/2⌋ of the one below, down to one cell, which holds
        // the mean of level 0 (every cell counted once on the way up).
        let mut d = v.dims;
        for level in &v.levels {
            assert_eq!(level.len() as u32, d[0] * d[1] * d[2]);
            d = d.map(|x| (x / 2).max(1));
        }
        let top = v.levels.last().unwrap();
        assert_eq!(top.len(), 1);
        let mean = v.levels[0].iter().sum::<f32>() / v.levels[0].len() as f32;
        assert!((top[0] / mean - 1.0).abs() < 0.35, "{} vs {mean}", top[0]);
    }
}
