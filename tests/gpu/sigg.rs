//! Sigg et al.'s method on the GPU against the exact f64 reference on the cases special to a
//! screen-space box: glyphs crossing the camera plane, the eye inside a grid, a distant glyph,
//! and the fragment count the box predicts (its CPU twin: `tensorglyph::twin::sigg`). The
//! checks it shares with Gumhold's method are ray_casters.rs. Bounds are stated beside each
//! check with their reason.

use crate::check::{assert_tight, aux_request, check_request, gpu};
use crate::scenes::{self, framed, spec};
use glam::DVec3;
use tensorglyph::camera::{Camera, Framing};
use tensorglyph::metrics::Accuracy;
use tensorglyph::request::{FrameRequest, GlyphKind, Method};
use tensorglyph::scene::Scene;
use tensorglyph::twin::screen_box::Proxy;
use tensorglyph::twin::sigg::scene_proxy;

fn check(name: &str, scene: &Scene, camera: &Camera, glyph: GlyphKind) -> Option<Accuracy> {
    crate::check::check(name, scene, camera, Method::Sigg, glyph, true)
}

fn tight(name: &str, scene: &Scene, camera: &Camera, glyph: GlyphKind) {
    crate::check::check_tight(name, scene, camera, Method::Sigg, glyph);
}

#[test]
fn near_a_cap_the_box_stands() {
    // The eye is just outside the solids (beyond the capsule's +x ball, 5 % of the half-length
    // above the cylinder's cap), and both balls and both discs lie in front of the camera plane:
    // eq. 5 still gives a (huge, viewport-clamped) box (ray_casters::eye_near_a_* check the
    // pixels).
    let (scene, cam) = scenes::near_a_cap();
    for glyph in [GlyphKind::Capsule, GlyphKind::Cylinder] {
        let proxy = scene_proxy(&scene.drawn_as(glyph), &cam, 0);
        assert!(matches!(proxy, Proxy::Box(_)), "{glyph:?}: {proxy:?}");
    }
}

#[test]
fn box_in_the_corner_of_a_wide_view() {
    // 100° field of view, glyph wholly in front of the camera plane near the image corner:
    // eq. 5's box must hold the strongly distorted silhouette.
    let scene = Scene::from_specs(&[spec(
        [3.18, -2.23, 2.5],
        [0.4, 1.0, 0.0],
        0.9,
        [0.6, 0.25, 0.15],
        [255, 0, 255, 255],
    )]);
    let mut cam = Camera::frame(
        &Framing {
            fov_deg: 100.0,
            ..Framing::default()
        },
        DVec3::ZERO,
        1.0,
        256,
        192,
    );
    cam.eye = DVec3::new(0.0, 0.0, 5.0);
    cam.target = DVec3::ZERO;
    cam.up = DVec3::Y;
    cam.near = 0.05;
    cam.far = 20.0;
    let proxy = scene_proxy(&scene, &cam, 0);
    let Proxy::Box(b) = proxy else {
        panic!("corner glyph should have a box: {proxy:?}");
    };
    assert!(b.lo.x > 0.3 && b.hi.y < -0.3, "not in the corner: {b:?}");
    tight("wide corner box", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn distant_glyph() {
    // A glyph 1000 sizes away seen through a 0.25° field of view: the box and the glyph-near
    // origin keep f32 well-conditioned.
    let scene = Scene::from_specs(&[spec(
        [310.0, 926.0, -205.0],
        [-0.2, 0.9, 0.4],
        2.0,
        [1.0, 0.6, 0.3],
        [120, 200, 80, 255],
    )]);
    let mut cam = Camera::frame(
        &Framing {
            fov_deg: 0.25,
            ..Framing::default()
        },
        DVec3::ZERO,
        1.0,
        256,
        192,
    );
    cam.eye = DVec3::new(310.0, 926.0, -205.0) - DVec3::new(0.3, 0.9, 0.2).normalize() * 1000.0;
    cam.target = DVec3::new(310.0, 926.0, -205.0);
    cam.up = DVec3::Z;
    cam.near = 1.0;
    cam.far = 2000.0;
    let Some(a) = check("distant", &scene, &cam, GlyphKind::Ellipsoid) else {
        return;
    };
    // For comparison (printed): Gumhold's path on the same view.
    let gumhold = aux_request(Method::Gumhold, true);
    check_request("distant", &scene, &cam, &gumhold);
    // The aux target stores view z in f32: at |z| = 1000 one ulp is 6.1e-5 glyph sizes, just
    // inside the tight depth bound.
    assert_tight("distant", &a);
}

#[test]
fn ellipsoid_crossing_the_camera_plane() {
    // The eye 2 % of a radius outside the surface, looking along it: the camera plane cuts the
    // glyph (r4ᵀDr4 > 0, no box), so it is drawn on a viewport-covering proxy.
    let scene = Scene::from_specs(&[spec(
        [0.0; 3],
        [0.5, -1.0, 0.3],
        0.4,
        [1.2, 0.7, 0.4],
        [40, 160, 220, 255],
    )]);
    let mut cam = Camera::frame(&Framing::default(), DVec3::ZERO, 1.0, 256, 192);
    let g = scene.geometry(0);
    // Just outside along the first axis; look across the glyph.
    cam.eye = scene.origin + g.centre + g.frame.x_axis * (g.radii.x * 1.02);
    cam.target = scene.origin + g.centre + g.frame.y_axis * 0.5;
    cam.up = g.frame.z_axis;
    cam.near = 1e-3;
    cam.far = 10.0;
    assert_eq!(scene_proxy(&scene, &cam, 0), Proxy::Viewport);
    tight("crossing", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn orthographic_camera_plane_inside_glyphs() {
    // The orthographic camera plane passes through the glyph (no eye to cull around): where the
    // entry lies behind the camera plane, the reference shows the exit (inner) surface.
    for &glyph in GlyphKind::VALUES {
        let scene = Scene::from_specs(&[spec(
            [0.0; 3],
            [0.3, 0.2, 1.0],
            0.5,
            [1.0, 0.6, 0.4],
            [220, 180, 40, 255],
        )]);
        let mut cam = framed(
            &scene,
            Framing {
                ortho: true,
                ..Framing::default()
            },
        );
        cam.eye = scene.origin + DVec3::new(0.1, 0.05, 0.1);
        cam.target = cam.eye + DVec3::new(-1.0, -0.3, -0.4);
        cam.up = DVec3::Z;
        cam.near = 0.05;
        cam.far = 10.0;
        tight("ortho inside", &scene, &cam, glyph);
    }
}

/// A 5x5x5 grid of rotated glyphs with the eye inside the grid: glyphs behind the camera
/// plane (culled), crossing it (viewport proxy) and in front (boxes), overlapping on screen.
fn eye_inside_a_grid(glyph: GlyphKind) {
    let mut specs = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            for k in 0..5 {
                let n = (i * 25 + j * 5 + k) as f64;
                let c = [i as f64 - 2.0, j as f64 - 2.0, k as f64 - 2.0];
                specs.push(spec(
                    c,
                    [n.sin(), n.cos(), 0.5],
                    0.37 * n,
                    [0.42, 0.25 + 0.02 * (n % 5.0), 0.12],
                    [
                        (40 + 8 * i) as u8,
                        (60 + 30 * j) as u8,
                        (200 - 30 * k) as u8,
                        255,
                    ],
                ));
            }
        }
    }
    let scene = Scene::from_specs(&specs).drawn_as(glyph);
    let mut cam = Camera::frame(
        &Framing {
            fov_deg: 90.0,
            ..Framing::default()
        },
        DVec3::ZERO,
        1.0,
        256,
        192,
    );
    cam.eye = scene.origin + DVec3::new(0.45, 0.55, 0.5);
    cam.target = cam.eye + DVec3::new(-1.0, -0.6, -0.3);
    cam.up = DVec3::Z;
    cam.near = 0.01;
    cam.far = 20.0;
    let proxies: Vec<Proxy> = (0..scene.instances.len())
        .map(|i| scene_proxy(&scene, &cam, i))
        .collect();
    let count = |f: fn(&Proxy) -> bool| proxies.iter().filter(|p| f(p)).count();
    let (boxes, viewport, culled) = (
        count(|p| matches!(p, Proxy::Box(_))),
        count(|p| matches!(p, Proxy::Viewport)),
        count(|p| matches!(p, Proxy::Culled)),
    );
    eprintln!("grid {glyph}: {boxes} boxes, {viewport} viewport proxies, {culled} culled");
    assert!(boxes > 0 && viewport > 0 && culled > 0);
    // 125 overlapping glyphs: more silhouette and intersection pixels than a single glyph,
    // each of which may flip within f32 rounding; the same 0.1 % bounds still hold.
    tight("grid", &scene, &cam, glyph);
    // The fragment count follows the proxies (boxes, viewport, culled) the CPU twin predicts.
    fragments_and_box_pixels("grid", &scene, &cam, glyph);
}

#[test]
fn eye_inside_a_grid_of_every_kind() {
    for &glyph in GlyphKind::VALUES {
        eye_inside_a_grid(glyph);
    }
}

#[test]
fn cylinder_crossing_the_camera_plane() {
    // The eye beside the side wall, looking along the axis: the camera plane cuts both discs'
    // hull, so the glyph is drawn on the viewport proxy.
    let scene = Scene::from_specs(&[spec(
        [0.0; 3],
        [0.0, 0.0, 1.0],
        0.0,
        [1.0, 0.3, 0.3],
        [160, 60, 200, 255],
    )]);
    let mut cam = Camera::frame(&Framing::default(), DVec3::ZERO, 1.0, 256, 192);
    cam.eye = DVec3::new(0.0, 0.33, 0.0);
    cam.target = DVec3::new(1.0, 0.2, 0.05);
    cam.up = DVec3::Z;
    cam.near = 1e-3;
    cam.far = 10.0;
    assert_eq!(
        scene_proxy(&scene.drawn_as(GlyphKind::Cylinder), &cam, 0),
        Proxy::Viewport
    );
    tight("cylinder crossing", &scene, &cam, GlyphKind::Cylinder);
    // As a capsule (R = 0.3, the eye 0.33 off the axis): the camera plane cuts the balls' hull.
    assert_eq!(
        scene_proxy(&scene.drawn_as(GlyphKind::Capsule), &cam, 0),
        Proxy::Viewport
    );
    tight("capsule crossing", &scene, &cam, GlyphKind::Capsule);
}

/// Renders `scene` with Sigg's method and returns (fragment invocations, box pixels predicted by
/// the CPU twin), or `None` without an adapter or pipeline statistics. Checks the count against
/// lavapipe's granularity first: llvmpipe shades (and counts) whole 4x4 tiles per triangle, so
/// the invocations must equal 16 x the tiles holding covered pixel centres of either triangle of
/// each box (`strip_tile_invocations`; 1 % slack for pixel centres on an edge).
fn fragments_and_box_pixels(
    name: &str,
    scene: &Scene,
    camera: &Camera,
    glyph: GlyphKind,
) -> Option<(u64, u64)> {
    let gpu = gpu()?;
    let scene = &scene.drawn_as(glyph);
    let req = FrameRequest::new(Method::Sigg);
    let frame = gpu.render(scene, camera, &req).expect("GPU frame");
    let Some(fragments) = frame.fragments else {
        eprintln!("{name}: no pipeline statistics on this adapter");
        return None;
    };
    let proxies: Vec<Proxy> = (0..scene.instances.len())
        .map(|i| scene_proxy(scene, camera, i))
        .collect();
    let (w, h) = (camera.width, camera.height);
    let pixels: u64 = proxies.iter().map(|p| p.pixels(w, h)).sum();
    let tiles: u64 = proxies
        .iter()
        .map(|p| p.strip_tile_invocations(w, h, 4))
        .sum();
    let covered = frame.covered_pixels();
    eprintln!(
        "{name} {w}x{h}: {fragments} fragment invocations; box pixels {pixels} (ratio {:.3}), \
         4x4-tile model {tiles}; covered {covered} ({:.1} % of the box pixels useful)",
        fragments as f64 / pixels as f64,
        100.0 * covered as f64 / pixels as f64
    );
    let adapter = gpu.adapter_name().to_lowercase();
    if adapter.contains("llvmpipe") || adapter.contains("lavapipe") {
        assert!(
            (fragments as f64 - tiles as f64).abs() <= 0.01 * tiles as f64,
            "{name}: {fragments} invocations vs the 4x4-tile model {tiles}"
        );
    }
    assert!(pixels > 0 && fragments >= pixels);
    Some((fragments, pixels))
}

#[test]
fn fragments_match_the_predicted_box() {
    // Small boxes (100-160 px across at 256x192): the count follows the tile model; tile
    // overhead (border + diagonal tiles) is 8-12 % of the box here, so no 10 % check.
    let scene = scenes::cigar();
    let cam = framed(&scene, Framing::default());
    fragments_and_box_pixels("cigar", &scene, &cam, GlyphKind::Ellipsoid);
    let scene = scenes::cylinder();
    let cam = framed(&scene, Framing::default());
    fragments_and_box_pixels("cylinder", &scene, &cam, GlyphKind::Cylinder);
    fragments_and_box_pixels("capsule", &scene, &cam, GlyphKind::Capsule);
    // One glyph whose box is ~220 px across (512x384): fragments within 10 % of its pixels.
    let scene = scenes::sphere();
    let cam = Camera::frame(&Framing::default(), scene.centre, scene.radius, 512, 384);
    if let Some((fragments, pixels)) =
        fragments_and_box_pixels("sphere", &scene, &cam, GlyphKind::Ellipsoid)
    {
        let ratio = fragments as f64 / pixels as f64;
        assert!(
            (1.0..=1.1).contains(&ratio),
            "sphere: {fragments} fragments vs {pixels} box pixels"
        );
    }
}
