//! How far a rendered frame is from the reference: coverage, glyph identity, depth, normal and
//! colour, on the pixels where each comparison means something.

use serde::Serialize;

use crate::effects::Effects;
use crate::frame::Frame;
use crate::reference::ReferenceScene;
use crate::scene::Scene;

/// The accuracy report of `--reference-check`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Accuracy {
    /// Fraction of all pixels where one frame shows a glyph and the other background.
    pub coverage_mismatch: f64,
    /// Fraction of pixels covered in both whose front-most glyph differs (the glyph, not the
    /// instance: where a glyph is several instances, its parts meeting at equal depth are one
    /// glyph's). After [`Accuracy::with_ties`], without the ties.
    pub id_mismatch: f64,
    /// After [`Accuracy::with_ties`]: fraction of pixels covered in both whose front-most glyph
    /// differs where the two glyphs' exact depths are a tie (within [`TIE_ULPS`] steps of the
    /// depth buffer): no depth test orders them, so they are counted apart from errors.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub id_ties: Option<f64>,
    /// |z_view − z_ref| / (that glyph's largest radius), on pixels showing the same glyph; both
    /// view depths are taken relative to the glyph's centre (see `Frame::aux`).
    pub depth_err_rel_p99: f64,
    pub depth_err_rel_max: f64,
    /// Angle between normals in degrees, on pixels showing the same glyph.
    pub normal_err_deg_p99: f64,
    pub normal_err_deg_max: f64,
    /// PSNR of the RGB images (∞ for identical images is reported as 99).
    pub color_psnr_db: f64,
    /// Pixels compared for depth and normal (the same instance in front).
    pub same_glyph_pixels: usize,
    /// With outlines: fraction of all pixels whose outline state differs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outline_mismatch: Option<f64>,
    /// With shadows: fraction of pixels covered in both whose lit fraction differs from the
    /// exact hard shadow by more than 0.5 (a penumbra's softness is not counted as error).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shadow_mismatch: Option<f64>,
    /// With ambient occlusion: the mean and the 95th percentile of |open fraction − the exact
    /// one| on pixels covered in both (the GPU's is an estimate, [`crate::effects::ao`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ao_error_mean: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ao_error_p95: Option<f64>,
}

/// Compare `frame` with `reference` (same size; both need aux data for depth and normal).
pub fn compare(frame: &Frame, reference: &Frame, scene: &Scene) -> Accuracy {
    assert_eq!(
        (frame.width, frame.height),
        (reference.width, reference.height)
    );
    let n = frame.ids.len();
    let mut coverage = 0usize;
    let mut both = 0usize;
    let mut id_diff = 0usize;
    let mut depth = Vec::new();
    let mut normal = Vec::new();
    let radius: Vec<f64> = scene
        .instances
        .iter()
        .map(|g| f64::from(g.radii.iter().copied().fold(0.0f32, f32::max)))
        .collect();
    for k in 0..n {
        let (a, b) = (frame.ids[k], reference.ids[k]);
        if (a != 0) != (b != 0) {
            coverage += 1;
        }
        if a != 0 && b != 0 {
            both += 1;
            if other_glyph(scene, a, b) {
                id_diff += 1;
            } else if a != b {
                // Two parts of one glyph meeting at equal depth: neither depth nor normal
                // belongs to the other.
            } else if let (Some(fa), Some(ra)) = (&frame.aux, &reference.aux) {
                let (p, q) = (fa[k], ra[k]);
                let r = radius.get(a as usize - 1).copied().unwrap_or(1.0);
                depth.push((f64::from(p[3]) - f64::from(q[3])).abs() / r);
                let dot = f64::from(p[0]) * f64::from(q[0])
                    + f64::from(p[1]) * f64::from(q[1])
                    + f64::from(p[2]) * f64::from(q[2]);
                let len = (f64::from(p[0]).powi(2)
                    + f64::from(p[1]).powi(2)
                    + f64::from(p[2]).powi(2))
                .sqrt()
                    * (f64::from(q[0]).powi(2) + f64::from(q[1]).powi(2) + f64::from(q[2]).powi(2))
                        .sqrt();
                let angle = if len > 0.0 && (dot / len).is_finite() {
                    (dot / len).clamp(-1.0, 1.0).acos().to_degrees()
                } else {
                    180.0
                };
                normal.push(angle);
            }
        }
    }
    let same = depth.len();
    let (depth_p99, depth_max) = p99_max(&mut depth);
    let (normal_p99, normal_max) = p99_max(&mut normal);
    Accuracy {
        coverage_mismatch: ratio(coverage, n),
        id_mismatch: ratio(id_diff, both),
        depth_err_rel_p99: depth_p99,
        depth_err_rel_max: depth_max,
        normal_err_deg_p99: normal_p99,
        normal_err_deg_max: normal_max,
        color_psnr_db: psnr(&frame.color, &reference.color),
        same_glyph_pixels: same,
        id_ties: None,
        outline_mismatch: None,
        shadow_mismatch: None,
        ao_error_mean: None,
        ao_error_p95: None,
    }
}

/// Whether instance ids `a` and `b` (both drawn) show different glyphs: a glyph's parts meeting
/// at equal depth are one glyph's.
fn other_glyph(scene: &Scene, a: u32, b: u32) -> bool {
    let glyph = |id: u32| scene.instances.get(id as usize - 1).map(|g| g.glyph);
    a != b && glyph(a).zip(glyph(b)).is_none_or(|(x, y)| x != y)
}

/// Steps of the f32 depth buffer within which two glyphs' exact depths at a pixel are a tie:
/// surfaces that meet (neighbouring caps in one plane, glyphs passing through each other) lie
/// within this of each other along a band of pixels, and the GPU's depth, exact to a step or so,
/// cannot order them there any more than the reference's choice of the nearer f64 root means.
pub const TIE_ULPS: u32 = 2;

/// Whether two depth-buffer values lie within [`TIE_ULPS`] f32 steps of each other.
fn depth_tie(a: f64, b: f64) -> bool {
    let (a, b) = (a as f32, b as f32);
    a.is_finite()
        && b.is_finite()
        && a >= 0.0
        && b >= 0.0
        && a.to_bits().abs_diff(b.to_bits()) <= TIE_ULPS
}

impl Accuracy {
    /// Count apart the id mismatches that are ties: pixels where the glyph `frame` shows meets
    /// the pixel's ray, in the exact reference `exact` (the one `reference` was rendered by),
    /// within [`TIE_ULPS`] depth-buffer steps of the glyph the reference shows.
    pub fn with_ties(
        mut self,
        frame: &Frame,
        reference: &Frame,
        scene: &Scene,
        exact: &ReferenceScene,
    ) -> Self {
        let w = frame.width as usize;
        let (mut both, mut differ, mut ties) = (0usize, 0usize, 0usize);
        for k in 0..frame.ids.len() {
            let (a, b) = (frame.ids[k], reference.ids[k]);
            if a == 0 || b == 0 {
                continue;
            }
            both += 1;
            if !other_glyph(scene, a, b) {
                continue;
            }
            differ += 1;
            let (i, j) = ((k % w) as u32, (k / w) as u32);
            let tie = exact
                .depth_of(a as usize - 1, i, j)
                .zip(exact.depth_of(b as usize - 1, i, j))
                .is_some_and(|(da, db)| depth_tie(da, db));
            if tie {
                ties += 1;
            }
        }
        self.id_mismatch = ratio(differ - ties, both);
        self.id_ties = Some(ratio(ties, both));
        self
    }

    /// The mismatches of the `effects` that are on, where both frames carry their per-pixel
    /// effects (rendered with aux).
    pub fn with_effects(self, frame: &Frame, reference: &Frame, effects: &Effects) -> Self {
        let (Some(a), Some(b)) = (&frame.effects, &reference.effects) else {
            return self;
        };
        let n = a.len().min(b.len());
        let outlined = |e: &[f32; 3]| e[1] > 0.5;
        let outline = (0..n)
            .filter(|&k| outlined(&a[k]) != outlined(&b[k]))
            .count();
        let covered: Vec<usize> = (0..n)
            .filter(|&k| frame.ids[k] != 0 && reference.ids[k] != 0)
            .collect();
        let shadow = covered
            .iter()
            .filter(|&&k| (a[k][0] - b[k][0]).abs() > 0.5)
            .count();
        let mut ao: Vec<f64> = covered
            .iter()
            .map(|&k| f64::from((a[k][2] - b[k][2]).abs()))
            .collect();
        ao.sort_by(f64::total_cmp);
        let mean = ao.iter().sum::<f64>() / ao.len().max(1) as f64;
        let p95 = ao
            .get((ao.len() * 95).div_ceil(100).saturating_sub(1))
            .copied()
            .unwrap_or(0.0);
        Self {
            outline_mismatch: effects.outlines.map(|_| ratio(outline, n)),
            shadow_mismatch: effects.shadows.map(|_| ratio(shadow, covered.len())),
            ao_error_mean: effects.ao.map(|_| mean),
            ao_error_p95: effects.ao.map(|_| p95),
            ..self
        }
    }
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 { 0.0 } else { a as f64 / b as f64 }
}

/// 99th percentile (nearest rank) and maximum; NaN counts as the worst error.
fn p99_max(v: &mut [f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    for x in v.iter_mut() {
        if x.is_nan() {
            *x = f64::INFINITY;
        }
    }
    v.sort_by(f64::total_cmp);
    let rank = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len());
    (v[rank - 1], v[v.len() - 1])
}

/// PSNR over the RGB channels of two RGBA8 images.
pub fn psnr(a: &[u8], b: &[u8]) -> f64 {
    let mut se = 0.0f64;
    let mut count = 0usize;
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for c in 0..3 {
            let d = f64::from(pa[c]) - f64::from(pb[c]);
            se += d * d;
            count += 1;
        }
    }
    if count == 0 || se == 0.0 {
        return 99.0;
    }
    let mse = se / count as f64;
    (10.0 * (255.0f64 * 255.0 / mse).log10()).min(99.0)
}

/// A picture of where two frames differ: red = coverage differs, yellow = another glyph in
/// front, blue shades = colour difference, grey = agreement.
pub fn diff_image(frame: &Frame, reference: &Frame) -> Vec<u8> {
    let mut out = Vec::with_capacity(frame.color.len());
    for k in 0..frame.ids.len() {
        let (a, b) = (frame.ids[k], reference.ids[k]);
        let px = if (a != 0) != (b != 0) {
            [255, 0, 0, 255]
        } else if a != b {
            [255, 200, 0, 255]
        } else {
            let d: u32 = (0..3)
                .map(|c| u32::from(frame.color[4 * k + c].abs_diff(reference.color[4 * k + c])))
                .sum();
            if d > 6 {
                [0, 0, (64 + d * 4).min(255) as u8, 255]
            } else {
                let g = reference.color[4 * k..4 * k + 3]
                    .iter()
                    .map(|&c| u32::from(c))
                    .sum::<u32>()
                    / 6;
                [g as u8, g as u8, g as u8, 255]
            }
        };
        out.extend_from_slice(&px);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_and_psnr() {
        let mut v: Vec<f64> = (1..=200).map(f64::from).collect();
        assert_eq!(p99_max(&mut v), (198.0, 200.0));
        let a = [10u8, 20, 30, 255];
        assert_eq!(psnr(&a, &a), 99.0);
        // One channel off by 255 of three: MSE = 255²/3 → PSNR = 10 log10(3).
        let b = [255u8, 20, 30, 255];
        let want = 10.0 * 3.0f64.log10();
        assert!((psnr(&[0, 20, 30, 255], &b) - want).abs() < 1e-12);
    }

    /// Two coincident spheres meet every ray at one depth: showing either where the reference
    /// shows the other is a tie. Showing a third sphere that lies behind them is an error.
    #[test]
    fn ties_are_counted_apart_from_errors() {
        use crate::camera::{Camera, Framing};
        use crate::request::{FrameRequest, Method};
        use crate::scene::GlyphSpec;
        use glam::{DQuat, DVec3};
        let sphere = |x: f64, z: f64| GlyphSpec {
            centre: DVec3::new(x, 0.0, z),
            rotation: DQuat::IDENTITY,
            radii: DVec3::ONE,
            color: [200, 200, 200, 255],
        };
        let scene = Scene::from_specs(&[sphere(0.0, 0.0), sphere(0.0, 0.0), sphere(0.5, -1.0)]);
        let camera = Camera::frame(&Framing::default(), scene.centre, scene.radius, 96, 72);
        let exact = ReferenceScene::new(&scene, &camera);
        let reference = exact.render(&FrameRequest {
            aux: true,
            ..FrameRequest::new(Method::Reference)
        });
        let mut frame = reference.clone();
        let (mut swapped, mut wrong) = (0, None);
        let w = frame.width as usize;
        for k in 0..frame.ids.len() {
            let id = reference.ids[k];
            if id == 1 || id == 2 {
                frame.ids[k] = 3 - id;
                swapped += 1;
                let (i, j) = ((k % w) as u32, (k / w) as u32);
                let behind = exact.depth_of(2, i, j).zip(exact.depth_of(0, i, j));
                if wrong.is_none() && behind.is_some_and(|(c, a)| c > a + 1e-3) {
                    wrong = Some(k);
                }
            }
        }
        let k = wrong.expect("the third sphere shows behind the pair somewhere");
        frame.ids[k] = 3;
        let both = reference.covered_pixels() as f64;
        let a = compare(&frame, &reference, &scene);
        assert_eq!(a.id_mismatch, swapped as f64 / both);
        let a = a.with_ties(&frame, &reference, &scene, &exact);
        assert_eq!(a.id_ties, Some((swapped - 1) as f64 / both));
        assert_eq!(a.id_mismatch, 1.0 / both);
    }
}
