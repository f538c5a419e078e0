//! Case 14: ODF glyphs of spherical-harmonic series where their marcher is hardest. A fibre's
//! lobe is the truncated delta Σ Y_lm(n) Y_lm(u): sharper and ringing more as lmax grows. The
//! cases: one fibre, two crossing at 90° and three at 60°, at lmax 4 … 12 (the sharpest lobes
//! CSD writes, with the ringing clamped at zero around the centre); and a second fibre whose
//! weight falls to 1e-3 of the first (a near-zero lobe, thin and short). Side by side, seen
//! obliquely, each glyph filling its voxel.

use glam::{DMat3, DQuat, DVec3};

use super::probe::{Probe, look, oblique, probe, sweep};
use crate::scene::GlyphKind;
use crate::scene::odf::{OdfOptions, Series, series_scene};
use crate::sh::{ShBasis, ShEval, count_of_lmax};
use crate::shape::odf::plain_of;

/// The plain coefficients of Σ wᵢ δ(nᵢ) truncated at `lmax`.
fn fibres(lmax: u32, fibres: &[(DVec3, f64)]) -> Vec<f64> {
    let mut ev = ShEval::new(lmax, ShBasis::Tournier07).expect("an even lmax");
    let n = count_of_lmax(lmax).expect("an even lmax");
    let mut sum = vec![0.0; n];
    let mut row = vec![0.0; n];
    for &(dir, w) in fibres {
        ev.row(dir.normalize().to_array(), &mut row);
        for (s, r) in sum.iter_mut().zip(&row) {
            *s += w * r;
        }
    }
    plain_of(&sum, ShBasis::Tournier07, 1.0).expect("an even lmax")
}

/// The glyphs `per_glyph` side by side along x, one voxel apart, in a frame turned obliquely,
/// seen from an oblique eye.
fn odf_probe(
    case: &'static str,
    parameter: &'static str,
    value: f64,
    label: String,
    lmax: u32,
    per_glyph: &[Vec<(DVec3, f64)>],
) -> Probe {
    let series = per_glyph
        .iter()
        .enumerate()
        .map(|(k, f)| Series {
            index: k,
            centre: DVec3::new(k as f64, 0.0, 0.0),
            plain: fibres(lmax, f),
        })
        .collect();
    let frame = DMat3::from_quat(oblique());
    let scene = series_scene(series, lmax, frame, 0.5, &OdfOptions::default());
    let dir = DVec3::new(-0.6, 1.0, -0.8).normalize();
    let cam = look(
        &scene,
        scene.centre - dir * 3.0 * scene.radius,
        scene.centre,
        35.0,
    );
    let mut p = probe(case, parameter, value, scene, cam);
    p.label = label;
    p.only = Some(GlyphKind::Odf);
    p
}

/// Case 14a: lobes as sharp as lmax makes them (one, two and three fibres).
pub fn odf_sharp(quick: bool) -> Vec<Probe> {
    let x = DVec3::X;
    let y = DVec3::Y;
    let third = DQuat::from_axis_angle(DVec3::Z, 120f64.to_radians());
    let glyphs = vec![
        vec![(DVec3::new(0.2, 0.3, 1.0), 1.0)],
        vec![(x, 1.0), (y, 1.0)],
        vec![(x, 1.0), (third * x, 1.0), (third * third * x, 1.0)],
    ];
    sweep(quick, &[4.0, 6.0, 8.0, 10.0, 12.0], &[8.0, 12.0])
        .into_iter()
        .map(|l| {
            odf_probe(
                "14-odf-sharp",
                "lmax",
                l,
                format!("lmax {l}"),
                l as u32,
                &glyphs,
            )
        })
        .collect()
}

/// Case 14b: a second fibre at 70° whose weight falls to 1e-3 of the first (lmax 8).
pub fn odf_faint(quick: bool) -> Vec<Probe> {
    let second = DVec3::new(70f64.to_radians().cos(), 70f64.to_radians().sin(), 0.0);
    sweep(quick, &[1e-1, 3e-2, 1e-2, 3e-3, 1e-3], &[1e-2])
        .into_iter()
        .map(|w| {
            let glyphs = vec![
                vec![(DVec3::X, 1.0), (second, w)],
                vec![(DVec3::Z, 1.0), (DVec3::new(0.0, 1.0, 0.3), w)],
            ];
            odf_probe("14-odf-faint", "weight", w, format!("{w:e}"), 8, &glyphs)
        })
        .collect()
}
