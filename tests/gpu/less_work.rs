//! Doing less work must not change the picture: chunked uploads, vertex-stage culling, the
//! front-to-back order and the alternative proxies (octagon, triangle, conservative depth), each checked
//! against the plain path or the f64 reference on lavapipe.

use tensorglyph::camera::{Camera, Framing};
use tensorglyph::field::synthetic::grid;
use tensorglyph::frame::Frame;
use tensorglyph::glyph::{GlyphStyle, derive_glyphs};
use tensorglyph::request::{
    DrawOptions, FrameRequest, GlyphKind, Method, Preset, Proxy, ProxyShape,
};
use tensorglyph::scene::Scene;
use tensorglyph::staging::field_spacing;

fn grid_scene(n: usize, glyph: GlyphKind) -> Scene {
    let field = grid(n);
    let set = derive_glyphs(&field, &tensorglyph::progress::Silent);
    let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
    Scene::build(&set, &style, glyph)
}

fn camera(scene: &Scene, zoom: f64, w: u32, h: u32) -> Camera {
    let framing = Framing {
        zoom,
        ..Framing::default()
    };
    Camera::frame(&framing, scene.centre, scene.radius, w, h)
}

/// The CPU glyph index shown at each pixel (ids are instance indices + 1, which reordering
/// changes), 0 for background.
fn glyph_ids(frame: &Frame, scene: &Scene) -> Vec<u32> {
    frame
        .ids
        .iter()
        .map(|&i| {
            if i == 0 {
                0
            } else {
                scene.instances[i as usize - 1].glyph + 1
            }
        })
        .collect()
}

#[test]
fn chunked_upload_draws_the_same_image() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let scene = grid_scene(10, GlyphKind::Ellipsoid);
    let cam = camera(&scene, 1.0, 320, 240);
    for method in [Method::Gumhold, Method::Sigg, Method::Mesh(0)] {
        let req = FrameRequest::new(method);
        let whole = gpu.render(&scene, &cam, &req).unwrap();
        // 1000 glyphs in chunks of 137: 8 buffers, the last one partly full.
        let buffers = gpu.upload_chunked(&scene, 137).unwrap();
        assert_eq!(buffers.chunks(), 1000usize.div_ceil(137));
        let chunked = gpu.render_uploaded(&buffers, &cam, &req).unwrap();
        assert!(whole.covered_pixels() > 10_000, "{method}: a real image");
        assert_eq!(whole.ids, chunked.ids, "{method}: ids");
        assert_eq!(whole.color, chunked.color, "{method}: colours");
    }
}

#[test]
fn culling_keeps_the_image_and_the_count_matches_its_twin() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let scene = grid_scene(12, GlyphKind::Ellipsoid);
    // Zoomed in: most glyphs are outside the frustum or in front of the near plane.
    let cam = camera(&scene, 4.0, 320, 240);
    // Gumhold's method for every kind; Sigg's and a mesh's culling once each.
    let gumhold = GlyphKind::VALUES.iter().map(|&k| (Method::Gumhold, k));
    for (method, glyph) in gumhold.chain([
        (Method::Sigg, GlyphKind::Ellipsoid),
        // Tessellated superquadrics cull with their box's corner, length(radii).
        (Method::Mesh(1), GlyphKind::Superquadric),
    ]) {
        let scene = grid_scene(12, glyph);
        let req = FrameRequest {
            cull: true,
            ..FrameRequest::new(method)
        };
        let culled = gpu.render(&scene, &cam, &req).unwrap();
        let all = gpu
            .render(&scene, &cam, &FrameRequest { cull: false, ..req })
            .unwrap();
        assert!(culled.covered_pixels() > 5_000, "{method} {glyph}");
        assert_eq!(
            culled.ids, all.ids,
            "{method} {glyph}: culling changed the image"
        );
        let vis = scene.visibility(&cam, true, 0.0);
        assert!(
            vis.culled > scene.instances.len() / 4,
            "{method} {glyph}: {vis:?}"
        );
        // No glyph the twin calls culled shows in the image.
        let shown: std::collections::HashSet<u32> = culled.ids.iter().copied().collect();
        for &id in shown.iter().filter(|&&i| i != 0) {
            let one = Scene {
                instances: vec![scene.instances[id as usize - 1]],
                ..scene.clone()
            };
            assert_eq!(
                one.visibility(&cam, true, 0.0).culled,
                0,
                "{method} {glyph}: glyph {id} is shown but its twin culls it"
            );
        }
    }
}

#[test]
fn min_pixel_radius_skips_only_small_glyphs() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let scene = grid_scene(12, GlyphKind::Ellipsoid);
    let cam = camera(&scene, 1.0, 320, 240);
    let req = FrameRequest::default();
    let all = gpu.render(&scene, &cam, &req).unwrap();
    // A threshold between the smallest and largest projected sizes.
    let min_px = 3.0;
    let some = gpu
        .render(
            &scene,
            &cam,
            &FrameRequest {
                min_pixel_radius: min_px,
                ..req
            },
        )
        .unwrap();
    let vis = scene.visibility(&cam, false, min_px);
    assert!(
        vis.culled > 0 && vis.culled < scene.instances.len(),
        "{vis:?}"
    );
    assert!(some.covered_pixels() < all.covered_pixels());
    // Where a kept glyph is the front-most in both, the pixel is identical.
    let mut same = 0;
    for (k, (&a, &b)) in all.ids.iter().zip(&some.ids).enumerate() {
        if a != 0 && a == b {
            same += 1;
            assert_eq!(all.color[4 * k..4 * k + 4], some.color[4 * k..4 * k + 4]);
        }
    }
    assert!(same > 1000);
}

/// Order changes which pixels the splats' compute pass casts (and what a baseline quad
/// overdraws), never what wins: the sorted scene shows the same glyph at every pixel but for
/// exact depth ties, with the baseline and with `render`'s default (splats), for every kind with
/// splats.
#[test]
fn front_to_back_order_draws_the_same_glyphs() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for glyph in GlyphKind::VALUES
        .iter()
        .copied()
        .filter(|k| k.caps().splats)
    {
        let scene = grid_scene(12, glyph);
        let cam = camera(&scene, 1.0, 320, 240);
        let mut sorted = scene.clone();
        sorted.sort_front_to_back(&cam);
        let f = cam.forward();
        let depth = |g: &tensorglyph::scene::GlyphInstance| {
            (glam::DVec3::from(g.centre.map(f64::from)) + scene.origin - cam.eye).dot(f)
        };
        // In layers: no glyph is a layer's thickness behind a later one.
        let diameter = scene
            .instances
            .iter()
            .map(|g| 2.0 * f64::from(g.radii.into_iter().fold(0.0, f32::max)))
            .sum::<f64>()
            / scene.instances.len() as f64;
        let thickness = f64::from(tensorglyph::scene::LAYER_DIAMETERS) * diameter;
        assert!(
            sorted
                .instances
                .windows(2)
                .all(|w| depth(&w[0]) <= depth(&w[1]) + thickness)
        );
        assert!(sorted.instances.first().map(depth) < scene.instances.first().map(depth));
        for preset in [Preset::Baseline, Preset::Splat] {
            let req = FrameRequest::preset(Method::Gumhold, true, preset);
            let a = gpu.render(&scene, &cam, &req).unwrap();
            let b = gpu.render(&sorted, &cam, &req).unwrap();
            let (ia, ib) = (glyph_ids(&a, &scene), glyph_ids(&b, &sorted));
            let differ = ia.iter().zip(&ib).filter(|(x, y)| x != y).count();
            // Only exact depth ties at intersection curves may resolve differently.
            assert!(
                differ as f64 <= 1e-3 * ia.len() as f64,
                "{glyph} {preset:?}: {differ} pixels differ"
            );
            assert_eq!(a.covered_pixels(), b.covered_pixels(), "{glyph} {preset:?}");
        }
    }
}

#[test]
fn other_proxies_and_conservative_depth_match_the_reference() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for &glyph in GlyphKind::VALUES {
        let scene = grid_scene(8, glyph);
        for (ortho, zoom) in [(false, 1.0), (false, 2.5), (true, 1.0)] {
            let mut cam = camera(&scene, zoom, 400, 300);
            if ortho {
                cam = Camera::frame(
                    &Framing {
                        ortho: true,
                        ..Framing::default()
                    },
                    scene.centre,
                    scene.radius,
                    400,
                    300,
                );
            }
            for proxy in [
                Proxy {
                    shape: ProxyShape::Octagon,
                    ..Proxy::BASELINE
                },
                Proxy {
                    shape: ProxyShape::Triangle,
                    ..Proxy::BASELINE
                },
                Proxy {
                    conservative: true,
                    ..Proxy::BASELINE
                },
                Proxy {
                    shape: ProxyShape::Octagon,
                    conservative: true,
                    early_depth: true,
                },
            ] {
                let req = crate::check::proxy_request(proxy);
                // Early depth is declared where the adapter and the scene allow it.
                let req = if proxy.early_depth {
                    gpu.with_early_depth(req, &scene, &cam)
                } else {
                    req
                };
                let frame = gpu.render(&scene, &cam, &req).unwrap();
                let label = format!("{glyph} ortho {ortho} zoom {zoom} {proxy:?}");
                crate::check::assert_scene_bounds(&label, &frame, &scene, &cam, &req);
            }
        }
    }
}

#[test]
fn octagon_shades_fewer_fragments_for_a_large_glyph() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let scene = crate::scenes::sphere();
    let cam = Camera::frame(&Framing::default(), scene.centre, scene.radius, 512, 384);
    let count = |shape| {
        let opts = DrawOptions {
            proxy: shape,
            ..crate::check::baseline()
        };
        let req = FrameRequest::with_options(Method::Gumhold, true, &opts);
        let f = gpu.render(&scene, &cam, &req).unwrap();
        (f.fragments, f.covered_pixels())
    };
    let (quad, covered) = count(ProxyShape::Quad);
    let (octagon, covered8) = count(ProxyShape::Octagon);
    assert_eq!(covered, covered8);
    let (Some(quad), Some(octagon)) = (quad, octagon) else {
        assert!(std::env::var_os("CI").is_none(), "lavapipe has statistics");
        return;
    };
    let (q, o) = (
        quad as f64 / covered as f64,
        octagon as f64 / covered as f64,
    );
    eprintln!("fragments per covered pixel: quad {q:.3}, octagon {o:.3}");
    // Theory (plain area): 4/π = 1.273 and 8 tan(π/8)/π = 1.055; lavapipe adds whole 4x4
    // blocks along every triangle edge.
    assert!(o < q, "octagon {o} vs quad {q}");
    assert!(q >= 1.2 && o >= 1.0);
}

#[test]
fn every_proxy_shape_covers_the_view_from_near_a_cylinder_cap() {
    // The eye inside the cylinder's bounding ellipsoid: the proxy is the whole near plane, made
    // of the same polygon as the glyph proxies.
    let (scene, cam) = crate::scenes::near_a_cap();
    for glyph in [GlyphKind::Cylinder, GlyphKind::Capsule] {
        for shape in [ProxyShape::Quad, ProxyShape::Octagon, ProxyShape::Triangle] {
            let proxy = Proxy {
                shape,
                ..Proxy::BASELINE
            };
            let req = crate::check::proxy_request(proxy);
            let label = format!("near cap {glyph} {shape:?}");
            let Some((_, acc)) =
                crate::check::check_request(&label, &scene.drawn_as(glyph), &cam, &req)
            else {
                return;
            };
            crate::check::assert_tight(&label, &acc);
        }
    }
}

#[test]
fn bricks_culled_draw_the_same_image_as_file_order() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for glyph in [GlyphKind::Ellipsoid, GlyphKind::Superquadric] {
        // 140,608 glyphs: bricks from 2^17 on, in one chunk; chunked, the same glyphs in file order.
        let scene = grid_scene(52, glyph);
        let whole = gpu.upload(&scene).unwrap();
        let chunked = gpu.upload_chunked(&scene, 100_000).unwrap();
        let req = FrameRequest {
            aux: true,
            ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
        };
        for (zoom, ortho, azimuth) in [(4.0, false, 0.0), (7.0, false, 30.0), (4.0, true, -20.0)] {
            let framing = Framing {
                zoom,
                ortho,
                azimuth,
                ..Framing::default()
            };
            let cam = Camera::frame(&framing, scene.centre, scene.radius, 400, 300);
            let label = format!("{glyph} zoom {zoom} ortho {ortho} azimuth {azimuth}");
            assert!(whole.culls_bricks(&cam), "{label}: drawn by bricks");
            assert!(!chunked.culls_bricks(&cam), "{label}: in file order");
            let culled = gpu.render_uploaded(&whole, &cam, &req).unwrap();
            let plain = gpu.render_uploaded(&chunked, &cam, &req).unwrap();
            assert!(plain.covered_pixels() > 50_000, "{label}: a real image");
            let differ = |a: &[u32], b: &[u32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
            let ids = differ(&glyph_ids(&culled, &scene), &glyph_ids(&plain, &scene));
            assert_eq!(ids, 0, "{label}: pixels whose glyph differs");
            assert!(
                culled.aux == plain.aux,
                "{label}: normals and depths differ"
            );
            assert!(culled.color == plain.color, "{label}: colours differ");
            crate::check::assert_scene_bounds(&label, &culled, &scene, &cam, &req);
        }
        // The whole field in view: most bricks are seen, and the frame is drawn in file order.
        assert!(!whole.culls_bricks(&camera(&scene, 1.0, 400, 300)));
    }
}
