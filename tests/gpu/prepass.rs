//! The compute prepass and splats (`--prepass`, `--splat PX`) must draw what the plain path
//! draws, within the f64 reference's bounds, on lavapipe: with 64-bit atomics and with the
//! 32-bit two-pass fallback, in slices, culled, perspective and orthographic, with the eye close;
//! for every kind whose capabilities have them (today ellipsoids and superquadrics).

use tensorglyph::camera::{Camera, Framing};
use tensorglyph::field::synthetic::grid;
use tensorglyph::frame::Frame;
use tensorglyph::glyph::{GlyphStyle, derive_glyphs};
use tensorglyph::render::gumhold::prepass::SPLAT_TILE;
use tensorglyph::render::{GpuContext, GpuRenderer};
use tensorglyph::request::{
    DrawOptions, FrameRequest, GlyphKind, Method, Preset, Proxy, ProxyShape,
};
use tensorglyph::scene::Scene;
use tensorglyph::staging::field_spacing;

/// The kinds with a compute prepass.
fn with_prepass() -> impl Iterator<Item = GlyphKind> {
    GlyphKind::VALUES
        .iter()
        .copied()
        .filter(|k| k.caps().prepass)
}

/// The kinds with splats.
fn with_splats() -> impl Iterator<Item = GlyphKind> {
    GlyphKind::VALUES
        .iter()
        .copied()
        .filter(|k| k.caps().splats)
}

fn grid_scene(n: usize, glyph: GlyphKind) -> Scene {
    let field = grid(n);
    let set = derive_glyphs(&field, &tensorglyph::progress::Silent);
    let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
    Scene::build(&set, &style, glyph)
}

fn camera(scene: &Scene, zoom: f64, ortho: bool) -> Camera {
    let framing = Framing {
        zoom,
        ortho,
        ..Framing::default()
    };
    Camera::frame(&framing, scene.centre, scene.radius, 400, 300)
}

fn request(prepass: bool, splat: u32) -> FrameRequest {
    request_with(Proxy::BASELINE, false, prepass, splat, true)
}

/// Gumhold's method with the aux target and these options.
fn request_with(
    proxy: Proxy,
    cull: bool,
    prepass: bool,
    splat: u32,
    depth_correction: bool,
) -> FrameRequest {
    let opts = DrawOptions {
        proxy: proxy.shape,
        conservative: proxy.conservative,
        prepass,
        splat,
        cull,
        ..Preset::Baseline.options()
    };
    FrameRequest {
        aux: true,
        ..FrameRequest::with_options(Method::Gumhold, depth_correction, &opts)
    }
}

/// The renderers to test: this adapter as it is and, where it has 64-bit atomics, forced to the
/// 32-bit fallback (a second device).
fn renderers() -> Vec<(String, GpuRenderer)> {
    let Some(gpu) = crate::check::gpu() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if gpu.ctx.int64_atomics {
        let mut ctx = GpuContext::new().expect("a second device");
        ctx.int64_atomics = false;
        out.push(("32-bit".to_string(), GpuRenderer::new(ctx).unwrap()));
    }
    let label = if gpu.ctx.int64_atomics {
        "64-bit"
    } else {
        "32-bit"
    };
    out.push((label.to_string(), gpu));
    out
}

/// Pixels whose glyph id differs between two frames of one size.
fn differing_ids(a: &Frame, b: &Frame) -> usize {
    a.ids.iter().zip(&b.ids).filter(|(x, y)| x != y).count()
}

#[test]
fn prepass_draws_the_plain_image() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for glyph in with_prepass() {
        let scene = grid_scene(10, glyph);
        for (zoom, ortho) in [(1.0, false), (3.0, false), (1.0, true)] {
            let cam = camera(&scene, zoom, ortho);
            for shape in [ProxyShape::Quad, ProxyShape::Triangle] {
                for cull in [false, true] {
                    let proxy = Proxy {
                        shape,
                        ..Proxy::BASELINE
                    };
                    let plain = request_with(proxy, cull, false, 0, true);
                    let pre = request_with(proxy, cull, true, 0, true);
                    let a = gpu.render(&scene, &cam, &plain).unwrap();
                    let b = gpu.render(&scene, &cam, &pre).unwrap();
                    // The same vertices from the same frame math: the same pixels, bit for bit
                    // (the draw order of the compacted list differs, so only exact depth ties
                    // could differ; this scene has none).
                    assert!(a.covered_pixels() > 5_000);
                    assert_eq!(
                        a.ids, b.ids,
                        "{glyph:?} zoom {zoom} ortho {ortho} {shape:?} cull {cull}"
                    );
                    assert_eq!(
                        a.color, b.color,
                        "{glyph:?} zoom {zoom} ortho {ortho} {shape:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn splats_match_the_reference() {
    for glyph in with_splats() {
        let scene = grid_scene(8, glyph);
        for (label, gpu) in renderers() {
            // Whole field (every glyph a splat), closer (a mix of splats and drawn glyphs), orthographic.
            for (zoom, ortho, splat) in [(1.0, false, 32), (2.5, false, 24), (1.0, true, 32)] {
                let cam = camera(&scene, zoom, ortho);
                let req = request(false, splat);
                let frame = gpu.render(&scene, &cam, &req).unwrap();
                let label = format!("{glyph:?} {label} zoom {zoom} ortho {ortho} splat {splat}");
                crate::check::assert_scene_bounds(&label, &frame, &scene, &cam, &req);
                // Splats skip the rasteriser: at the whole-field view every ellipsoid is one, and
                // the only vertices are the quads (4-vertex strips) of the SPLAT_TILE-pixel tiles
                // the splats touch, which hold every covered pixel; a few superquadrics, whose quad is
                // that of the larger ball holding them, are drawn. (Closer, the tiles of larger
                // splats may outnumber the glyphs they stand for.)
                let plain = gpu.render(&scene, &cam, &request(false, 0)).unwrap();
                if gpu.ctx.pipeline_statistics {
                    let (s, p) = (frame.vertices.unwrap(), plain.vertices.unwrap());
                    eprintln!("{label}: {s} vertex invocations, plain {p}");
                    if zoom == 1.0 {
                        assert!(s < p, "{label}");
                    }
                    if zoom == 1.0 && glyph == GlyphKind::Ellipsoid {
                        let tile = SPLAT_TILE;
                        let tiles =
                            u64::from(frame.width.div_ceil(tile) * frame.height.div_ceil(tile));
                        assert!(s % 4 == 0, "{label}: {s}");
                        let tile_px = u64::from(tile * tile);
                        assert!(frame.covered_pixels() as u64 <= s / 4 * tile_px, "{label}");
                        // Not the whole image: the tiles follow the splats.
                        assert!(s / 4 < tiles, "{label}: {s}");
                    }
                }
            }
        }
    }
}

#[test]
fn splats_in_slices_and_chunks_draw_the_same_image() {
    for glyph in with_splats() {
        let scene = grid_scene(10, glyph);
        let cam = camera(&scene, 1.0, false);
        for (label, gpu) in renderers() {
            let req = request(false, 32);
            let whole = gpu.render(&scene, &cam, &req).unwrap();
            // 1000 glyphs in chunks of 137: 8 chunks, a slice and a pair of passes each; splats
            // of one slice are depth tested against the earlier slices' in the targets.
            let buffers = gpu.upload_chunked(&scene, 137).unwrap();
            let chunked = gpu.render_uploaded(&buffers, &cam, &req).unwrap();
            assert!(whole.covered_pixels() > 10_000, "{glyph:?} {label}");
            let differ = differing_ids(&whole, &chunked);
            // Equal-depth ties resolve by instance within a slice and by draw order across
            // slices; nothing else may differ.
            assert!(
                differ * 10_000 <= whole.ids.len(),
                "{glyph:?} {label}: {differ} of {} pixels differ",
                whole.ids.len()
            );
            crate::check::assert_scene_bounds(&label, &chunked, &scene, &cam, &req);
        }
    }
}

#[test]
fn splats_with_culling_keep_the_image_and_near_glyphs_are_drawn() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for glyph in with_splats() {
        let scene = grid_scene(12, glyph);
        // Zoomed far in: glyphs behind the eye, in front of the near plane and around the eye,
        // where splats must give way to drawn proxies (or nothing).
        for zoom in [4.0, 12.0] {
            let cam = camera(&scene, zoom, false);
            let plain = gpu.render(&scene, &cam, &request(false, 0)).unwrap();
            for cull in [false, true] {
                let req = request_with(Proxy::BASELINE, cull, false, 32, true);
                let frame = gpu.render(&scene, &cam, &req).unwrap();
                let label = format!("{glyph:?} zoom {zoom} cull {cull}");
                crate::check::assert_scene_bounds(&label, &frame, &scene, &cam, &req);
                let differ = differing_ids(&plain, &frame);
                assert!(
                    differ * 500 <= plain.ids.len(),
                    "{label}: {differ} pixels differ from the plain path"
                );
            }
        }
    }
}

#[test]
fn splats_need_depth_correction() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    for glyph in with_splats() {
        let scene = grid_scene(6, glyph);
        let cam = camera(&scene, 1.0, false);
        let flat = |splat| FrameRequest {
            aux: false,
            ..request_with(Proxy::BASELINE, false, false, splat, false)
        };
        // Without depth correction the proxies' own depth stands, which splats do not have: the
        // request draws every glyph through the prepass instead.
        assert_eq!(flat(32).splat_pixels(), 0, "{glyph:?}");
        let a = gpu.render(&scene, &cam, &flat(0)).unwrap();
        let b = gpu.render(&scene, &cam, &flat(32)).unwrap();
        assert_eq!(a.ids, b.ids, "{glyph:?}");
    }
}
