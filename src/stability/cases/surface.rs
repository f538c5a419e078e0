//! Cases 2, 3, 4, 8 and 9: where rays meet glyphs at their hardest — thin glyphs, rims through
//! pixel centres, an eye on or inside the surface, glyphs smaller than a pixel, and glyphs
//! that pass through each other.

use glam::{DQuat, DVec3};

use super::probe::{H, Probe, fitted, look, oblique, ortho, probe, spec, sweep};
use crate::camera::Projection;
use crate::scene::{GlyphSpec, Scene};

/// Case 2's variants: (case, cigar, view, pair). The views: perspective from 4 radii (`close`),
/// from 400 radii with the same image size of the glyph (`far`), orthographic; `pair`: a second
/// glyph of the same shape, turned, passing through the first.
const ANISOTROPY: [(&str, bool, AnisoView, bool); 10] = [
    ("2-anisotropy-cigar", true, AnisoView::Close, false),
    ("2-anisotropy-pancake", false, AnisoView::Close, false),
    ("2-anisotropy-cigar-far", true, AnisoView::Far, false),
    ("2-anisotropy-pancake-far", false, AnisoView::Far, false),
    ("2-anisotropy-cigar-ortho", true, AnisoView::Ortho, false),
    ("2-anisotropy-pancake-ortho", false, AnisoView::Ortho, false),
    ("2-anisotropy-cigar-pair", true, AnisoView::Close, true),
    ("2-anisotropy-pancake-pair", false, AnisoView::Close, true),
    (
        "2-anisotropy-cigar-pair-ortho",
        true,
        AnisoView::Ortho,
        true,
    ),
    (
        "2-anisotropy-pancake-pair-ortho",
        false,
        AnisoView::Ortho,
        true,
    ),
];

#[derive(Debug, Clone, Copy, PartialEq)]
enum AnisoView {
    Close,
    Far,
    Ortho,
}

/// Whether `case` is one of case 2's anisotropy sweeps.
pub fn is_anisotropy(case: &str) -> bool {
    ANISOTROPY.iter().any(|a| a.0 == case)
}

/// Case 2: anisotropy with no min-radius clamp: cigars k:1:1 and pancakes 1:1:1/k (largest
/// radius 1), oblique; single and passing through a turned twin, in perspective from near and
/// far and orthographic. k = 1e7 and 1e8 lie beyond 2²⁴ (the glyph is culled: thinner than
/// f32 can place at its own scale).
pub fn anisotropy(quick: bool) -> Vec<Probe> {
    let ks = sweep(
        quick,
        &[1.0, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8],
        &[1.0, 1e6],
    );
    let dir = DVec3::new(-1.0, 1.0, -1.0).normalize();
    let turned = DQuat::from_axis_angle(DVec3::new(-0.6, 0.2, 0.7).normalize(), 0.9) * oblique();
    let mut out = Vec::new();
    for (case, cigar, view, pair) in ANISOTROPY {
        if quick && (pair || view == AnisoView::Far) && case.contains("cigar") {
            continue;
        }
        for &k in &ks {
            let radii = if cigar {
                DVec3::new(1.0, 1.0 / k, 1.0 / k)
            } else {
                DVec3::new(1.0, 1.0, 1.0 / k)
            };
            let mut specs = vec![spec(DVec3::ZERO, oblique(), radii, [60, 200, 90, 255])];
            if pair {
                specs.push(spec(
                    DVec3::new(0.15, -0.1, 0.2),
                    turned,
                    radii,
                    [220, 90, 60, 255],
                ));
            }
            let scene = Scene::from_specs(&specs);
            let cam = match view {
                AnisoView::Close => look(&scene, -dir * 4.0, DVec3::ZERO, 40.0),
                AnisoView::Far => look(
                    &scene,
                    -dir * 400.0,
                    DVec3::ZERO,
                    2.0 * (4.0f64 * 20f64.to_radians().tan() / 400.0)
                        .atan()
                        .to_degrees(),
                ),
                AnisoView::Ortho => ortho(&scene, dir, DVec3::Z, 3.0),
            };
            out.push(probe(case, "anisotropy k", k, scene, cam));
        }
    }
    out
}

/// Case 3: grazing rays. Orthographic views of spheres whose radius is a whole number of pixels
/// times (1 + δ), centred on a pixel centre: the rim passes through pixel centres (q̃² = 1 ± δ).
/// Perspective too: the same with a sphere far away, where q̃² rounds hardest.
pub fn grazing(quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    let px = 2.0 / f64::from(H); // ortho height 2: pixel size
    for &delta in &sweep(quick, &[-1e-7, -1e-8, 0.0, 1e-8, 1e-7], &[-1e-7, 0.0, 1e-7]) {
        // Pixel centres: the image centre lies on a pixel corner (even size); shift by half a pixel.
        let c = DVec3::new(px / 2.0, px / 2.0, 0.0);
        let r = 40.0 * px * (1.0 + delta);
        let specs: Vec<GlyphSpec> = vec![
            spec(c, DQuat::IDENTITY, DVec3::splat(r), [200, 200, 60, 255]),
            // A second sphere touching the first exactly at a pixel centre row.
            spec(
                c + DVec3::new(2.0 * r, 0.0, 0.0),
                DQuat::IDENTITY,
                DVec3::splat(r),
                [60, 120, 220, 255],
            ),
        ];
        let scene = Scene::from_specs(&specs);
        let eye = DVec3::new(0.0, 0.0, 10.0);
        let projection = Projection::Orthographic { height: 2.0 };
        let cam = fitted(&scene, eye, DVec3::ZERO, DVec3::Y, projection);
        let mut p = probe(
            "3-grazing",
            "rim offset δ (ortho)",
            delta,
            scene.clone(),
            cam,
        );
        p.label = format!("ortho δ={delta:e}");
        out.push(p);
        let mut cam = look(
            &scene,
            DVec3::new(0.0, 0.0, 1e4),
            DVec3::ZERO,
            2.0 * (1.0f64 / 1e4).atan().to_degrees(),
        );
        cam.up = DVec3::Y;
        let mut p = probe(
            "3-grazing-persp",
            "rim offset δ (persp, 1e4 away)",
            delta,
            scene,
            cam,
        );
        p.label = format!("persp δ={delta:e}");
        out.push(p);
    }
    out
}

/// Case 4: the eye approaching a unit sphere's surface: |ẽ| from 2 to 1 + 1e-6, on it, inside.
pub fn eye_approach(quick: bool) -> Vec<Probe> {
    let full = [
        2.0,
        1.5,
        1.1,
        1.01,
        1.0 + 1e-3,
        1.0 + 1e-4,
        1.0 + 1e-5,
        1.0 + 1e-6,
        1.0,
        0.5,
    ];
    let scene = Scene::from_specs(&[spec(
        DVec3::ZERO,
        oblique(),
        DVec3::new(1.0, 0.7, 0.5),
        [200, 90, 200, 255],
    )]);
    let geo = scene.geometry(0);
    // Eye along a fixed parameter-space direction: ẽ = E ŵ, e = c + T ẽ.
    let w = DVec3::new(-0.4, 0.8, 0.45).normalize();
    sweep(quick, &full, &[2.0, 1.01, 1.0 + 1e-6, 0.5])
        .into_iter()
        .map(|e| {
            let eye = scene.origin + geo.centre + geo.t() * (w * e);
            let mut cam = look(&scene, eye, scene.origin + geo.centre, 90.0);
            // Near plane well in front of the surface (1/10 of the gap, at least 1e-7).
            let gap = (geo.t() * (w * (e - 1.0).abs())).length();
            cam.near = (gap * 0.1).max(1e-7);
            cam.far = 4.0;
            let mut p = probe("4-eye-approach", "|ẽ|", e, scene.clone(), cam);
            p.label = match e {
                1.0 => "on surface".into(),
                0.5 => "inside".into(),
                _ => format!("1+{:.0e}", e - 1.0),
            };
            p
        })
        .collect()
}

/// Case 8: sub-pixel glyphs: a 12×9 grid of spheres of projected diameter s px, at
/// irrational sub-pixel offsets.
pub fn sub_pixel(quick: bool) -> Vec<Probe> {
    sweep(quick, &[0.1, 0.25, 0.5, 1.0, 2.0], &[0.5, 2.0])
        .into_iter()
        .map(|s| {
            let px = 2.0 / f64::from(H); // ortho height 2
            let mut specs = Vec::new();
            for j in 0..9 {
                for i in 0..12 {
                    let f = f64::from(i * 9 + j);
                    let x = (f64::from(i) - 5.5) * 20.0 * px + (f * 0.618_034).fract() * px;
                    let y = (f64::from(j) - 4.0) * 20.0 * px + (f * 0.414_214).fract() * px;
                    specs.push(spec(
                        DVec3::new(x, y, 0.0),
                        oblique(),
                        DVec3::new(1.0, 0.8, 0.6) * (s * px / 2.0),
                        [230, 230, 230, 255],
                    ));
                }
            }
            let scene = Scene::from_specs(&specs);
            let eye = DVec3::new(0.0, 0.0, 5.0);
            let projection = Projection::Orthographic { height: 2.0 };
            let cam = fitted(&scene, eye, DVec3::ZERO, DVec3::Y, projection);
            probe("8-sub-pixel", "projected size px", s, scene, cam)
        })
        .collect()
}

/// Case 9: two interpenetrating glyphs; the intersection curve with and without depth correction.
pub fn intersecting(_quick: bool) -> Vec<Probe> {
    let specs = [
        spec(
            DVec3::ZERO,
            oblique(),
            DVec3::new(1.0, 0.4, 0.4),
            [220, 60, 60, 255],
        ),
        spec(
            DVec3::new(0.3, 0.1, 0.0),
            DQuat::from_axis_angle(DVec3::new(0.2, 0.9, -0.3).normalize(), 0.6),
            DVec3::new(0.9, 0.5, 0.3),
            [60, 60, 220, 255],
        ),
    ];
    let scene = Scene::from_specs(&specs);
    let dir = DVec3::new(-1.0, 1.0, -0.6).normalize();
    let cam = look(&scene, scene.centre - dir * 5.0, scene.centre, 35.0);
    [true, false]
        .into_iter()
        .map(|dc| {
            let mut p = probe(
                "9-intersecting",
                "depth correction",
                f64::from(u8::from(dc)),
                scene.clone(),
                cam,
            );
            p.depth_correction = dc;
            p.label = if dc { "depth corrected" } else { "proxy depth" }.into();
            p
        })
        .collect()
}
