//! The outline filter (Sigg et al. 2006, §4.2: Sobel over the geometry buffer), one definition
//! for both back ends: `shaders/composite.wgsl` runs it on the GPU's f32 buffers, [`outline_mask`]
//! on the reference's exact f64 buffers, and `--reference-check` counts the pixels where the two
//! disagree (`outline_mismatch`).
//!
//! A covered pixel is on an outline when, among the 3×3 samples `width` apart around it
//! (clamped to the image):
//! - another glyph or the background shows (silhouettes, and touching glyphs of one colour
//!   separate), or else
//! - the Sobel gradient of the view normal exceeds [`NORMAL_EDGE`] (creases: a cylinder's rim), or
//! - the Sobel gradient of the view distance, relative to the pixel's own, exceeds
//!   [`DEPTH_EDGE`] (a glyph folding over itself).
//!
//! Background pixels are never outlined, so a transparent figure keeps its alpha.

use glam::DVec3;

/// Sobel magnitude of the unit view normal above which a crease is drawn: a 45° crease under
/// the kernel gives 4·|Δn| = 3.06, while the smooth interior of a glyph more than a few pixels
/// across stays below it.
pub const NORMAL_EDGE: f64 = 3.0;
/// Sobel magnitude of the view distance, relative to the pixel's distance, above which a depth
/// edge is drawn.
pub const DEPTH_EDGE: f64 = 0.1;

/// What the filter reads per sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// 0 for background, else the glyph (instance + 1).
    pub id: u32,
    /// Unit view normal.
    pub normal: DVec3,
    /// Distance from the eye along the view direction.
    pub distance: f64,
}

/// Sobel weights: x derivative at (dx, dy) offsets; the y derivative is its transpose.
const SOBEL_X: [[f64; 3]; 3] = [[-1.0, 0.0, 1.0], [-2.0, 0.0, 2.0], [-1.0, 0.0, 1.0]];

/// Whether the sample at (x, y) lies on an outline; `at(x, y)` reads a sample of the
/// `width`×`height` image.
pub fn is_outline(
    at: impl Fn(u32, u32) -> Sample,
    size: (u32, u32),
    x: u32,
    y: u32,
    reach: u32,
) -> bool {
    let centre = at(x, y);
    if centre.id == 0 {
        return false;
    }
    let (w, h) = size;
    let k = i64::from(reach.max(1));
    let mut gx_n = DVec3::ZERO;
    let mut gy_n = DVec3::ZERO;
    let (mut gx_d, mut gy_d) = (0.0, 0.0);
    for (j, row) in SOBEL_X.iter().enumerate() {
        for (i, &wx) in row.iter().enumerate() {
            let sx = (i64::from(x) + (i as i64 - 1) * k).clamp(0, i64::from(w) - 1) as u32;
            let sy = (i64::from(y) + (j as i64 - 1) * k).clamp(0, i64::from(h) - 1) as u32;
            let s = at(sx, sy);
            if s.id != centre.id {
                return true;
            }
            let wy = SOBEL_X[i][j];
            gx_n += s.normal * wx;
            gy_n += s.normal * wy;
            gx_d += s.distance * wx;
            gy_d += s.distance * wy;
        }
    }
    let normal = (gx_n.length_squared() + gy_n.length_squared()).sqrt();
    let depth = (gx_d * gx_d + gy_d * gy_d).sqrt() / centre.distance.abs().max(f64::MIN_POSITIVE);
    normal > NORMAL_EDGE || depth > DEPTH_EDGE
}

/// The outline state of every sample of a `width`×`height` image stored row by row.
pub fn outline_mask(samples: &[Sample], width: u32, height: u32, reach: u32) -> Vec<bool> {
    use rayon::prelude::*;
    let at = |x: u32, y: u32| samples[y as usize * width as usize + x as usize];
    (0..samples.len())
        .into_par_iter()
        .map(|k| {
            let (x, y) = ((k % width as usize) as u32, (k / width as usize) as u32);
            is_outline(at, (width, height), x, y, reach)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(id: u32) -> Sample {
        Sample {
            id,
            normal: DVec3::Z,
            distance: 10.0,
        }
    }

    #[test]
    fn a_glyph_boundary_is_outlined_on_the_glyph_side_only() {
        // Left half glyph 1, right half background, 8×4.
        let (w, h) = (8u32, 4u32);
        let s: Vec<Sample> = (0..w * h)
            .map(|k| flat(if k % w < 4 { 1 } else { 0 }))
            .collect();
        let m = outline_mask(&s, w, h, 1);
        for y in 0..h {
            let row: Vec<bool> = (0..w).map(|x| m[(y * w + x) as usize]).collect();
            assert_eq!(row, [false, false, false, true, false, false, false, false]);
        }
        // A reach of 2 samples outlines two columns.
        let m = outline_mask(&s, w, h, 2);
        assert!(m[2] && m[3] && !m[1]);
    }

    #[test]
    fn touching_glyphs_of_one_colour_separate_and_creases_show() {
        let (w, h) = (6u32, 3u32);
        let s: Vec<Sample> = (0..w * h)
            .map(|k| flat(if k % w < 3 { 1 } else { 2 }))
            .collect();
        let m = outline_mask(&s, w, h, 1);
        assert!(m[2] && m[3] && !m[0] && !m[5]);
        // One glyph with a 90° crease between columns 2 and 3: both sides' pixels next to it.
        let s: Vec<Sample> = (0..w * h)
            .map(|k| Sample {
                normal: if k % w < 3 { DVec3::Z } else { DVec3::X },
                ..flat(1)
            })
            .collect();
        let m = outline_mask(&s, w, h, 1);
        assert!(m[2] && m[3] && !m[0] && !m[5]);
        // A smooth 5° per pixel bend stays clear.
        let s: Vec<Sample> = (0..w * h)
            .map(|k| {
                let a = f64::from(k % w) * 5f64.to_radians();
                Sample {
                    normal: DVec3::new(a.sin(), 0.0, a.cos()),
                    ..flat(1)
                }
            })
            .collect();
        assert!(outline_mask(&s, w, h, 1).iter().all(|&e| !e));
    }
}
