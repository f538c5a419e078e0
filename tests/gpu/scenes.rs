//! Hand-made scenes and views shared by the modules of this group (ray_casters.rs, gumhold.rs,
//! sigg.rs, mesh.rs, less_work.rs), chosen where ray-cast impostors tend to fail. Each module
//! states its method's bounds and their reasons beside its checks.

use glam::{DQuat, DVec3};
use tensorglyph::camera::{Camera, Framing, ViewPreset};
use tensorglyph::request::GlyphKind;
use tensorglyph::scene::{GlyphSpec, Scene};

/// A glyph from its world centre, rotation (axis, angle), radii and colour.
pub fn spec(
    centre: [f64; 3],
    axis: [f64; 3],
    angle: f64,
    radii: [f64; 3],
    color: [u8; 4],
) -> GlyphSpec {
    GlyphSpec {
        centre: DVec3::from(centre),
        rotation: DQuat::from_axis_angle(DVec3::from(axis).normalize(), angle),
        radii: DVec3::from(radii),
        color,
    }
}

/// The 256x192 camera `framing` the whole scene.
pub fn framed(scene: &Scene, framing: Framing) -> Camera {
    Camera::frame(&framing, scene.centre, scene.radius, 256, 192)
}

/// A sphere of radius 0.5 at the origin.
pub fn sphere() -> Scene {
    Scene::from_specs(&[spec(
        [0.0; 3],
        [0.0, 0.0, 1.0],
        0.0,
        [0.5; 3],
        [200, 80, 40, 255],
    )])
}

/// A 20 : 1 : 1 cigar, rotated and away from the origin.
pub fn cigar() -> Scene {
    Scene::from_specs(&[spec(
        [1.0, -2.0, 0.5],
        [0.3, -0.5, 0.8],
        1.1,
        [2.0, 0.1, 0.1],
        [255, 0, 0, 255],
    )])
}

/// 1 : 1 : 0.01, to be seen obliquely: the normal varies fastest near the rim.
pub fn pancake() -> Scene {
    Scene::from_specs(&[spec(
        [0.0, 0.0, 0.0],
        [1.0, 0.2, 0.1],
        0.7,
        [1.0, 1.0, 0.01],
        [0, 255, 0, 255],
    )])
}

/// Two glyphs that cut into each other: only per-pixel depth gets the intersection curve right.
pub fn intersecting() -> Scene {
    Scene::from_specs(&[
        spec(
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            0.3,
            [1.0, 0.4, 0.4],
            [255, 0, 0, 255],
        ),
        spec(
            [0.5, 0.0, 0.1],
            [1.0, 0.0, 0.0],
            0.8,
            [0.3, 0.9, 0.5],
            [0, 0, 255, 255],
        ),
    ])
}

/// A 100° field of view with a glyph near the image corner (and a tiny one at the centre):
/// strong perspective distortion of the glyph's silhouette.
pub fn corner_of_a_wide_view() -> (Scene, Camera) {
    let scene = Scene::from_specs(&[
        spec([0.0; 3], [0.0, 0.0, 1.0], 0.0, [0.05; 3], [90, 90, 90, 255]),
        spec(
            [2.2, -1.6, 0.3],
            [0.4, 1.0, 0.0],
            0.9,
            [0.6, 0.25, 0.15],
            [255, 0, 255, 255],
        ),
    ]);
    let mut cam = Camera::frame(
        &Framing {
            view: ViewPreset::NegZ,
            fov_deg: 100.0,
            ..Framing::default()
        },
        DVec3::ZERO,
        0.5,
        256,
        192,
    );
    cam.near = 0.05;
    cam.far = 20.0;
    (scene, cam)
}

/// The intersecting pair seen orthographically from 30° azimuth.
pub fn ortho_intersecting() -> (Scene, Camera) {
    let scene = intersecting();
    let cam = framed(
        &scene,
        Framing {
            ortho: true,
            azimuth: 30.0,
            ..Framing::default()
        },
    );
    (scene, cam)
}

/// A 1 : 0.5 : 0.2 glyph seen orthographically along its third eigenvector (+z).
pub fn ortho_along_an_eigenvector() -> (Scene, Camera) {
    let scene = Scene::from_specs(&[spec(
        [0.0; 3],
        [0.0, 0.0, 1.0],
        0.0,
        [1.0, 0.5, 0.2],
        [200, 200, 0, 255],
    )]);
    let cam = framed(
        &scene,
        Framing {
            ortho: true,
            view: ViewPreset::PosZ,
            ..Framing::default()
        },
    );
    (scene, cam)
}

/// The first glyph of [`cylinders`]: as a cylinder, axis along the frame's first column,
/// elliptic cross-section.
fn oblique_cylinder() -> GlyphSpec {
    spec(
        [0.0, 0.0, 0.0],
        [0.2, 0.9, 0.3],
        0.8,
        [1.0, 0.35, 0.2],
        [255, 120, 0, 255],
    )
}

/// [`oblique_cylinder`] alone.
pub fn cylinder() -> Scene {
    Scene::from_specs(&[oblique_cylinder()])
}

/// Two cylinder glyphs: axis along the frame's first column.
pub fn cylinders() -> Scene {
    Scene::from_specs(&[
        oblique_cylinder(),
        spec(
            [0.9, 0.6, -0.2],
            [1.0, 0.0, 0.0],
            1.3,
            [0.5, 0.3, 0.3],
            [0, 120, 255, 255],
        ),
    ])
}

/// [`cylinders`]' views: oblique, side-on and orthographic.
pub fn cylinder_framings() -> [(&'static str, Framing); 3] {
    [
        ("oblique", Framing::default()),
        (
            "side",
            Framing {
                view: ViewPreset::PosY,
                ..Framing::default()
            },
        ),
        (
            "ortho",
            Framing {
                ortho: true,
                azimuth: 40.0,
                ..Framing::default()
            },
        ),
    ]
}

/// A cylinder whose axis O e1 = R_y(−90°) x = +z: seen along ∓z only a cap shows.
pub fn end_on_cylinder() -> Scene {
    Scene::from_specs(&[spec(
        [0.0; 3],
        [0.0, 1.0, 0.0],
        -std::f64::consts::FRAC_PI_2,
        [1.0, 0.4, 0.25],
        [200, 0, 200, 255],
    )])
}

/// A 1 : 0.6 : 0.4 glyph at the origin with the eye 5 % of the half-length above the +x cap
/// (as a cylinder), looking back across it; the cap fills most of the view.
pub fn near_a_cap() -> (Scene, Camera) {
    let scene = Scene::from_specs(&[spec(
        [0.0; 3],
        [0.0, 0.0, 1.0],
        0.0,
        [1.0, 0.6, 0.4],
        [0, 160, 80, 255],
    )]);
    let mut cam = Camera::frame(&Framing::default(), DVec3::ZERO, 1.0, 256, 192);
    cam.eye = DVec3::new(1.05, 0.1, 0.05);
    cam.target = DVec3::new(0.0, 0.05, 0.0);
    cam.up = DVec3::Z;
    cam.near = 1e-3;
    cam.far = 10.0;
    (scene, cam)
}

/// The cylinder scenes' views for both solid glyphs, as (glyph, name, scene, camera): the
/// cylinders side-on, end-on and oblique, and one glyph seen end-on along its axis, in
/// perspective and orthographic. Capsules are the cylinders' glyphs (R the mean of the
/// cross-section's semi-axes), held to the same bounds.
pub fn solid_views() -> Vec<(GlyphKind, &'static str, Scene, Camera)> {
    let mut views = Vec::new();
    for glyph in [GlyphKind::Cylinder, GlyphKind::Capsule] {
        let scene = cylinders();
        for (name, framing) in cylinder_framings() {
            views.push((glyph, name, scene.clone(), framed(&scene, framing)));
        }
        // Axis exactly along the view direction: a cylinder's side degenerates to the rim and
        // only the cap shows; a capsule's front ball hides the rest.
        let end_on = end_on_cylinder();
        for ortho in [false, true] {
            let framing = Framing {
                view: ViewPreset::NegZ,
                ortho,
                ..Framing::default()
            };
            views.push((glyph, "end-on", end_on.clone(), framed(&end_on, framing)));
        }
    }
    views
}
