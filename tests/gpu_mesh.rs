//! The triangle-mesh baselines (`mesh:N`, `box`) on the GPU against the exact f64 reference:
//! accuracy must improve with the subdivision level, and the box must enclose the glyph.
//! Bounds are stated beside each check with their reason.

mod common;

use common::scenes::{self, framed};
use glam::DVec3;
use tensorglyph::camera::{Camera, Framing, ViewPreset};
use tensorglyph::frame::Frame;
use tensorglyph::metrics::{Accuracy, compare};
use tensorglyph::reference::ReferenceScene;
use tensorglyph::render::GpuRenderer;
use tensorglyph::render::mesh::mesh_stats;
use tensorglyph::request::{FrameRequest, GlyphKind, Method};
use tensorglyph::scene::{GlyphSpec, Scene};

/// A glyph centred where [`scenes::cigar`] is.
fn spec(axis: [f64; 3], angle: f64, radii: [f64; 3], color: [u8; 4]) -> GlyphSpec {
    common::spec([1.0, -2.0, 0.5], axis, angle, radii, color)
}

fn sphere() -> Scene {
    Scene::from_specs(&[spec([0.0, 0.0, 1.0], 0.0, [0.5; 3], [200, 80, 40, 255])])
}

/// Axis along the frame's first column, elliptic cross-section, seen obliquely (caps and side).
fn cylinder() -> Scene {
    Scene::from_specs(&[spec(
        [0.2, 0.9, 0.3],
        0.8,
        [1.0, 0.35, 0.2],
        [255, 120, 0, 255],
    )])
}

fn camera(scene: &Scene) -> Camera {
    framed(scene, Framing::default())
}

/// One frame of `method` and the reference, compared.
fn check(
    gpu: &GpuRenderer,
    name: &str,
    scene: &Scene,
    method: Method,
    glyph: GlyphKind,
) -> (Accuracy, Frame, Frame) {
    check_view(gpu, name, scene, &camera(scene), method, glyph, true)
}

fn check_view(
    gpu: &GpuRenderer,
    name: &str,
    scene: &Scene,
    cam: &Camera,
    method: Method,
    glyph: GlyphKind,
    depth_correction: bool,
) -> (Accuracy, Frame, Frame) {
    let req = common::aux_request(method, glyph, depth_correction);
    let frame = gpu.render(scene, cam, &req).expect("GPU frame");
    let reference = ReferenceScene::new(scene, cam, glyph).render(&req);
    let acc = compare(&frame, &reference, scene);
    let (v, t) = mesh_stats(method, glyph);
    eprintln!(
        "{name} {method}: {v} vertices, {t} triangles; VS {:?} FS {:?} invocations; \
         covered {} (ref {}); {acc:?}",
        frame.vertices,
        frame.fragments,
        frame.covered_pixels(),
        reference.covered_pixels()
    );
    assert!(
        reference.covered_pixels() > 1000,
        "{name}: scene shows too little"
    );
    (acc, frame, reference)
}

/// Levels 0..=4 must get strictly better in coverage and normals; level 4 and above must be
/// close to the reference, level 6 closer.
fn improves_with_level(name: &str, scene: &Scene, glyph: GlyphKind) {
    let Some(gpu) = common::gpu() else {
        return;
    };
    // For comparison in the log only (vertex and fragment invocations of the ray caster).
    check(&gpu, name, scene, Method::Gumhold, glyph);
    let acc: Vec<Accuracy> = (0..=Method::MAX_MESH_LEVEL)
        .map(|n| check(&gpu, name, scene, Method::Mesh(n), glyph).0)
        .collect();
    for n in 1..=4 {
        let (a, b) = (&acc[n - 1], &acc[n]);
        // Once a level is within a pixel or two of the reference, coverage cannot get
        // measurably better; it must not get worse.
        let pixels = 256.0 * 192.0;
        assert!(
            b.coverage_mismatch < a.coverage_mismatch
                || (b.coverage_mismatch <= a.coverage_mismatch
                    && b.coverage_mismatch <= 2.0 / pixels),
            "{name}: coverage does not improve from level {} to {n}: {a:?} -> {b:?}",
            n - 1
        );
        assert!(
            b.normal_err_deg_p99 < a.normal_err_deg_p99,
            "{name}: normals do not improve from level {} to {n}: {a:?} -> {b:?}",
            n - 1
        );
    }
    for (n, a) in acc.iter().enumerate().skip(4) {
        assert_close(&format!("{name} mesh:{n}"), a);
    }
    let a = &acc[6];
    // Level 6 (1.0° between vertices on the sphere, 384 prism sides): a tenth of level 4's
    // bounds for normal and depth (measured: 15–17x below level 4 for both).
    assert!(a.normal_err_deg_p99 <= 0.1, "{name} mesh:6: normal {a:?}");
    assert!(a.depth_err_rel_p99 <= 1e-3, "{name} mesh:6: depth {a:?}");
}

/// Bounds for level 4 and finer at 256x192 (measured at level 4: sphere / cigar / cylinder).
fn assert_close(name: &str, a: &Accuracy) {
    // Inscribed mesh: at level 4 the surface is at most ~8e-4 r inside the glyph (1 − cos of
    // the largest triangle's circumradius angle, ~2.3°), a twentieth of a pixel here: only rim
    // pixels whose centres lie that close to the silhouette flip (measured 14 / 1 / 0 pixels).
    assert!(a.coverage_mismatch <= 1e-3, "{name}: coverage {a:?}");
    // One glyph: the id is always right where both show it.
    assert!(a.id_mismatch == 0.0, "{name}: id {a:?}");
    // The radial gap is ~8e-4 r, but along a ray grazing the rim the depth gap grows like the
    // square root of it; the p99 includes those rim pixels (measured 7e-3 / 4e-4 / 6e-4).
    assert!(a.depth_err_rel_p99 <= 1e-2, "{name}: depth {a:?}");
    // Phong-interpolated vertex normals err by a fraction of the ~4° between neighbouring
    // vertices (~1.9° around the prism), worst across the cigar's thin waist where the normal
    // turns fastest (measured 0.42° / 0.74° / 0.23°).
    assert!(a.normal_err_deg_p99 <= 1.0, "{name}: normal {a:?}");
    // Each flipped rim pixel is a full glyph-vs-background error: with a dozen of them PSNR
    // sits in the high 30s (measured 36.5 / 47.6 / 68.0 dB).
    assert!(a.color_psnr_db >= 33.0, "{name}: colour {a:?}");
}

#[test]
fn sphere_improves_with_level() {
    improves_with_level("sphere", &sphere(), GlyphKind::Ellipsoid);
}

#[test]
fn rotated_cigar_improves_with_level() {
    improves_with_level("cigar", &scenes::cigar(), GlyphKind::Ellipsoid);
}

#[test]
fn cylinder_improves_with_level() {
    improves_with_level("cylinder", &cylinder(), GlyphKind::Cylinder);
}

#[test]
fn capsule_improves_with_level() {
    improves_with_level("capsule", &cylinder(), GlyphKind::Capsule);
}

#[test]
fn box_covers_the_glyph() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    for (name, scene, glyph) in [
        ("sphere", sphere(), GlyphKind::Ellipsoid),
        ("cigar", scenes::cigar(), GlyphKind::Ellipsoid),
        ("cylinder", cylinder(), GlyphKind::Cylinder),
        ("capsule", cylinder(), GlyphKind::Capsule),
    ] {
        let (_, frame, reference) = check(&gpu, name, &scene, Method::Box, glyph);
        let missed = frame
            .ids
            .iter()
            .zip(&reference.ids)
            .filter(|&(&b, &r)| r != 0 && b == 0)
            .count();
        assert_eq!(missed, 0, "{name}: the box misses glyph pixels");
        assert!(frame.covered_pixels() > reference.covered_pixels());
    }
}

/// Orthographic views and a cylinder seen end-on: back-face culling must keep the front faces
/// under every projection, and level 4 stays within the same bounds.
#[test]
fn orthographic_and_end_on_views() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    // The axis O e1 = R_y(−90°) x = +z: seen along ∓z only a cap shows.
    let end_on = Scene::from_specs(&[spec(
        [0.0, 1.0, 0.0],
        -std::f64::consts::FRAC_PI_2,
        [1.0, 0.4, 0.25],
        [200, 0, 200, 255],
    )]);
    for (name, scene, glyph, framing) in [
        (
            "ortho cigar",
            scenes::cigar(),
            GlyphKind::Ellipsoid,
            Framing {
                ortho: true,
                azimuth: 30.0,
                ..Framing::default()
            },
        ),
        (
            "ortho cylinder",
            cylinder(),
            GlyphKind::Cylinder,
            Framing {
                ortho: true,
                azimuth: 40.0,
                ..Framing::default()
            },
        ),
        (
            "end-on cylinder",
            end_on.clone(),
            GlyphKind::Cylinder,
            Framing {
                view: ViewPreset::NegZ,
                ..Framing::default()
            },
        ),
        (
            "ortho end-on cylinder",
            end_on,
            GlyphKind::Cylinder,
            Framing {
                view: ViewPreset::PosZ,
                ortho: true,
                ..Framing::default()
            },
        ),
    ] {
        let cam = framed(&scene, framing);
        let (a, _, _) = check_view(&gpu, name, &scene, &cam, Method::Mesh(4), glyph, true);
        assert_close(name, &a);
        if name.contains("end-on") {
            // Only the flat cap shows, and the mesh's cap lies in the cap plane: f32 exact.
            assert!(a.normal_err_deg_p99 <= 1e-3, "{name}: normal {a:?}");
            assert!(a.depth_err_rel_p99 <= 1e-5, "{name}: depth {a:?}");
        }
    }
}

/// A mesh's depth is its rasterised depth: with and without "depth correction" the frames of
/// two intersecting glyphs are the same, and the intersection curve is close to the reference.
#[test]
fn intersecting_glyphs_use_the_mesh_depth() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let mut b = spec([1.0, 0.0, 0.0], 0.8, [0.3, 0.9, 0.5], [0, 0, 255, 255]);
    b.centre += DVec3::new(0.5, 0.0, 0.1);
    let scene = Scene::from_specs(&[
        spec([0.0, 0.0, 1.0], 0.3, [1.0, 0.4, 0.4], [255, 0, 0, 255]),
        b,
    ]);
    let cam = camera(&scene);
    let m = Method::Mesh(4);
    let (with, f1, _) = check_view(&gpu, "meet", &scene, &cam, m, GlyphKind::Ellipsoid, true);
    let (_, f2, _) = check_view(&gpu, "meet", &scene, &cam, m, GlyphKind::Ellipsoid, false);
    assert_eq!(f1.ids, f2.ids);
    assert_eq!(f1.color, f2.color);
    // The curve where the meshes cut each other moves by the meshes' depth error (~1e-3 of a
    // radius, up to ~1e-2 on steep parts): a few pixels along it change glyph.
    assert!(with.id_mismatch <= 2e-3, "meet: id {with:?}");
}

/// The eye inside a glyph: the reference does not draw it, and neither does the culled mesh
/// (every face is a back face from inside).
#[test]
fn eye_inside_a_glyph_draws_nothing() {
    let Some(gpu) = common::gpu() else {
        return;
    };
    let scene = sphere();
    let mut cam = camera(&scene);
    cam.eye = scene.centre + DVec3::new(0.1, 0.05, 0.0);
    cam.target = scene.centre + DVec3::new(1.0, 0.0, 0.0);
    cam.up = DVec3::Z;
    cam.near = 1e-3;
    for glyph in [
        GlyphKind::Ellipsoid,
        GlyphKind::Cylinder,
        GlyphKind::Capsule,
    ] {
        for method in [Method::Mesh(2), Method::Box] {
            let req = FrameRequest::new(method, glyph);
            let frame = gpu.render(&scene, &cam, &req).expect("GPU frame");
            assert_eq!(frame.covered_pixels(), 0, "{method} {glyph}");
        }
    }
}

#[test]
fn mesh_levels_parse() {
    assert_eq!("mesh:0".parse::<Method>(), Ok(Method::Mesh(0)));
    assert_eq!("mesh:6".parse::<Method>(), Ok(Method::Mesh(6)));
    assert_eq!("box".parse::<Method>(), Ok(Method::Box));
    for bad in ["mesh:7", "mesh:x"] {
        let e = bad.parse::<Method>().unwrap_err();
        assert!(
            e.contains(bad) && e.contains("0 to 6"),
            "{bad}: unclear error '{e}'"
        );
    }
}
