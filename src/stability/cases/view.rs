//! Cases 1, 5, 6 and 7: where the camera and the world are — far away, a near plane through
//! the glyph, a glyph behind the eye, the corner of a wide view, orthographic views, and a
//! world far from the origin.

use glam::{DQuat, DVec3};

use super::probe::{H, Probe, W, look, oblique, ortho, probe, spec, sweep};
use crate::scene::{GlyphSpec, Scene};

/// Case 1: distance / glyph size from 10 to 10⁶, the field of view narrowed so the glyph keeps
/// its size on screen (what changes is precision only).
pub fn distance(quick: bool) -> Vec<Probe> {
    let radii = DVec3::new(1.0, 0.6, 0.35);
    let scene = Scene::from_specs(&[spec(DVec3::ZERO, oblique(), radii, [220, 120, 60, 255])]);
    let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
    sweep(quick, &[10.0, 100.0, 1e3, 1e4, 1e5, 1e6], &[10.0, 1e6])
        .into_iter()
        .map(|d| {
            let fov = 2.0 * (1.3 / d).atan().to_degrees();
            let cam = look(&scene, -dir * d, DVec3::ZERO, fov);
            probe("1-distance", "distance/size", d, scene.clone(), cam)
        })
        .collect()
}

/// Case 5: near-plane crossing, behind the camera, corner of a 120° view.
pub fn camera_edges(_quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    let radii = DVec3::new(1.0, 0.6, 0.4);
    let scene = Scene::from_specs(&[spec(DVec3::ZERO, oblique(), radii, [90, 200, 220, 255])]);
    // The near plane through the glyph centre.
    let mut cam = look(&scene, DVec3::new(0.0, -5.0, 0.0), DVec3::ZERO, 30.0);
    cam.near = 5.0;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 0.0, scene.clone(), cam);
    p.label = "near plane through centre".into();
    out.push(p);
    // Behind the camera (and a visible one in front).
    let scene2 = Scene::from_specs(&[
        spec(
            DVec3::new(0.0, 5.0, 0.0),
            oblique(),
            radii,
            [90, 200, 220, 255],
        ),
        spec(
            DVec3::new(0.0, -3.0, 0.0),
            oblique(),
            radii,
            [220, 90, 90, 255],
        ),
    ]);
    let mut cam = look(&scene2, DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0), 60.0);
    cam.near = 0.05;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 1.0, scene2, cam);
    p.label = "one glyph behind the camera".into();
    out.push(p);
    // A glyph in the corner of a 120° view.
    let fov: f64 = 120.0;
    let t = (fov.to_radians() / 2.0).tan();
    let aspect = f64::from(W) / f64::from(H);
    // Direction of NDC (0.8, 0.8), 6 units away (camera looks along +y, up +z).
    let d = DVec3::new(0.8 * t * aspect, 1.0, 0.8 * t).normalize();
    let scene3 = Scene::from_specs(&[spec(d * 6.0, oblique(), radii * 0.8, [220, 220, 90, 255])]);
    let mut cam = look(&scene3, DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0), fov);
    cam.near = 0.1;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 2.0, scene3, cam);
    p.label = "corner of a 120° view".into();
    out.push(p);
    out
}

/// Case 6: orthographic, oblique and exactly along an eigenvector (±z, x).
pub fn orthographic(_quick: bool) -> Vec<Probe> {
    let radii = DVec3::new(1.0, 0.6, 0.3);
    let mut out = Vec::new();
    let views: [(&str, DQuat, DVec3, DVec3); 4] = [
        (
            "oblique",
            oblique(),
            DVec3::new(-1.0, 1.0, -1.0).normalize(),
            DVec3::Z,
        ),
        ("along e3 (−z)", DQuat::IDENTITY, DVec3::NEG_Z, DVec3::Y),
        ("along −e3 (+z)", DQuat::IDENTITY, DVec3::Z, DVec3::Y),
        ("along e1 (x)", DQuat::IDENTITY, DVec3::X, DVec3::Z),
    ];
    for (k, (label, rot, dir, up)) in views.into_iter().enumerate() {
        let scene = Scene::from_specs(&[spec(DVec3::ZERO, rot, radii, [150, 220, 120, 255])]);
        let cam = ortho(&scene, dir, up, 2.6);
        let mut p = probe("6-orthographic", "view", k as f64, scene, cam);
        p.label = label.into();
        out.push(p);
    }
    out
}

/// Case 7: the whole field translated by up to 10⁹ (camera-relative rendering).
pub fn large_world(quick: bool) -> Vec<Probe> {
    sweep(quick, &[0.0, 1e3, 1e6, 1e9], &[0.0, 1e6])
        .into_iter()
        .map(|off| {
            let shift = DVec3::new(off, -0.5 * off, 0.25 * off);
            let specs: Vec<GlyphSpec> = (0..3)
                .map(|i| {
                    let x = f64::from(i) - 1.0;
                    spec(
                        shift + DVec3::new(1.1 * x, 0.2 * x, 0.0),
                        DQuat::from_axis_angle(DVec3::new(1.0, x, 0.5).normalize(), 0.7 + x),
                        DVec3::new(0.6, 0.35, 0.2),
                        [200, 80 + 60 * i as u8, 60, 255],
                    )
                })
                .collect();
            let scene = Scene::from_specs(&specs);
            let dir = DVec3::new(-1.0, 1.0, -0.8).normalize();
            let cam = look(&scene, scene.centre - dir * 5.0, scene.centre, 40.0);
            probe("7-large-world", "translation", off, scene, cam)
        })
        .collect()
}
