//! Images rendered in tiles: every tile's camera is a crop of the whole image's, so the stitched
//! frame must be the frame rendered in one piece. Truth: the same scene, camera and request
//! rendered whole (then box-filtered for `--ssaa`), on lavapipe and with the f64 reference; tiles
//! are forced small (64 samples a side) so a 200x150 image is cut into dozens of them.

use crate::cli::{json, stderr, tg};
use tensorglyph::camera::{Camera, Framing};
use tensorglyph::field::synthetic::grid;
use tensorglyph::frame::Frame;
use tensorglyph::glyph::{GlyphStyle, derive_glyphs};
use tensorglyph::metrics::compare;
use tensorglyph::reference::ReferenceScene;
use tensorglyph::request::{FrameRequest, GlyphKind, Method, Preset};
use tensorglyph::scene::Scene;
use tensorglyph::staging::field_spacing;
use tensorglyph::tiles::Tiling;
use tensorglyph::{Backend, RenderError};

const W: u32 = 200;
const H: u32 = 150;

fn grid_scene(n: usize, glyph: GlyphKind) -> Scene {
    let field = grid(n);
    let set = derive_glyphs(&field, &tensorglyph::progress::Silent);
    let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
    Scene::build(&set, &style, glyph)
}

/// The camera of the samples: the output size times `ssaa`, zoomed in so glyphs cross the
/// image's edges (culled and clipped at tile borders as at the image's).
fn camera(scene: &Scene, ortho: bool, ssaa: u32) -> Camera {
    let framing = Framing {
        ortho,
        zoom: 1.3,
        azimuth: 15.0,
        ..Framing::default()
    };
    Camera::frame(&framing, scene.centre, scene.radius, W * ssaa, H * ssaa)
}

/// 64 samples a side: a 200x150 image at --ssaa 2 is 8 x 6 tiles.
fn small_tiles(ssaa: u32) -> Tiling {
    Tiling {
        ssaa,
        max_side: 64,
        max_samples: 64 * 64,
        margin: 2,
    }
}

/// (pixels whose id differs, largest difference of a colour channel, pixels with a channel
/// more than 1/255 apart).
fn differences(a: &Frame, b: &Frame) -> (usize, u8, usize) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let ids = a.ids.iter().zip(&b.ids).filter(|(x, y)| x != y).count();
    let per_pixel: Vec<u8> = a
        .color
        .chunks(4)
        .zip(b.color.chunks(4))
        .map(|(x, y)| {
            x.iter()
                .zip(y)
                .map(|(p, q)| p.abs_diff(*q))
                .max()
                .unwrap_or(0)
        })
        .collect();
    let color = per_pixel.iter().copied().max().unwrap_or(0);
    let off = per_pixel.iter().filter(|&&d| d > 1).count();
    (ids, color, off)
}

#[test]
fn tiled_gpu_frames_equal_whole_frames() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let cases = [
        // render's default: splats from the compute prepass, culled per tile.
        (Method::Gumhold, GlyphKind::Ellipsoid, Preset::DEFAULT),
        (Method::Gumhold, GlyphKind::Cylinder, Preset::Culled),
        (Method::Sigg, GlyphKind::Ellipsoid, Preset::Culled),
        (Method::Sigg, GlyphKind::Cylinder, Preset::Baseline),
        (Method::Mesh(1), GlyphKind::Ellipsoid, Preset::Baseline),
    ];
    for (method, glyph, preset) in cases {
        let scene = grid_scene(6, glyph);
        let buffers = gpu.upload(&scene).unwrap();
        let req = FrameRequest {
            aux: true,
            ..FrameRequest::preset(method, true, preset)
        };
        for ortho in [false, true] {
            for ssaa in [1, 2, 3] {
                let what = format!("{method} {glyph:?} ortho {ortho} ssaa {ssaa}");
                let cam = camera(&scene, ortho, ssaa);
                let whole = gpu
                    .render_uploaded(&buffers, &cam, &req)
                    .unwrap()
                    .downsample(ssaa);
                let tiling = small_tiles(ssaa);
                assert!(tiling.plan(W, H).unwrap().len() >= 12, "{what}: tiles");
                let mut renders = 0;
                let tiled = tiling
                    .render_with(&cam, |c| {
                        renders += 1;
                        assert!(c.width <= 64 && c.height <= 64, "{what}: tile size");
                        gpu.render_uploaded(&buffers, c, &req)
                    })
                    .unwrap();
                assert!(renders >= 12, "{what}");
                assert!(whole.covered_pixels() > 5_000, "{what}: a real image");
                let (ids, color, off) = differences(&whole, &tiled);
                eprintln!(
                    "{what}: {ids} ids differ, colour within {color}/255 ({off} pixels over 1/255)"
                );
                assert_eq!(ids, 0, "{what}: ids");
                if matches!(method, Method::Mesh(_)) {
                    // A sample on the edge between two of a mesh's facets is a rasteriser's tie,
                    // which a tile's differently formed clip space may break the other way: one
                    // such sample of nine turned a pixel by 21/255 when the instances were first
                    // stored as the GPU reads them. The ray casters have no such edges.
                    assert!(
                        off <= 2,
                        "{what}: {off} pixels' colours differ (up to {color}/255)"
                    );
                } else {
                    assert!(color <= 1, "{what}: colour differs by {color}/255");
                }
                // Normals and depths of the centre samples: the same rays, so the same hits up to
                // the f32 rounding of a differently formed clip space (measured on lavapipe:
                // depth p99 ≤ 8.2e-6 glyph radii, normals p99 ≤ 0.0017°; Sigg's method exactly
                // equal). The accuracy bounds against the reference are 1e-4 and 0.5°.
                let a = compare(&tiled, &whole, &scene);
                assert_eq!(a.coverage_mismatch, 0.0, "{what}");
                assert!(a.depth_err_rel_p99 <= 5e-5, "{what}: {a:?}");
                assert!(a.normal_err_deg_p99 <= 1e-2, "{what}: {a:?}");
            }
        }
    }
}

#[test]
fn tiled_reference_frames_equal_whole_frames() {
    let scene = grid_scene(5, GlyphKind::Cylinder);
    let req = FrameRequest {
        aux: true,
        ..FrameRequest::new(Method::Reference)
    };
    for ortho in [false, true] {
        for ssaa in [1, 3] {
            let cam = camera(&scene, ortho, ssaa);
            let whole = ReferenceScene::new(&scene, &cam)
                .render(&req)
                .downsample(ssaa);
            let tiled = small_tiles(ssaa)
                .render_with(&cam, |c| {
                    Ok::<_, RenderError>(ReferenceScene::new(&scene, c).render(&req))
                })
                .unwrap();
            let (ids, color, _) = differences(&whole, &tiled);
            assert!(whole.covered_pixels() > 5_000, "a real image");
            assert_eq!(ids, 0, "ortho {ortho} ssaa {ssaa}: ids");
            assert!(color <= 1, "ortho {ortho} ssaa {ssaa}: colour {color}/255");
        }
    }
}

/// Through the back end as `render` calls it: an image that fits is rendered whole, one beyond
/// the (forced) limit in tiles, and both come out the same.
#[test]
fn the_backend_tiles_only_what_does_not_fit() {
    let scene = grid_scene(4, GlyphKind::Ellipsoid);
    let backend = Backend::Reference;
    let req = FrameRequest::new(Method::Reference);
    let cam = camera(&scene, false, 2);
    let render = |tiling: &Tiling| {
        tiling
            .render(
                &backend,
                &scene,
                &cam,
                &req,
                &mut Default::default(),
                &tensorglyph::Silent,
            )
            .unwrap()
    };
    let default = Tiling::new(&backend, 2);
    assert!(default.fits_whole(W, H));
    let forced = small_tiles(2);
    assert!(!forced.fits_whole(W, H));
    let (whole, tiled) = (render(&default), render(&forced));
    assert_eq!((tiled.width, tiled.height), (W, H));
    assert_eq!(differences(&whole, &tiled), (0, 0, 0));
}

/// An image whose samples are wider than the adapter's largest texture renders (in tiles) and
/// matches the exact reference, which renders it in one piece on the CPU.
#[test]
fn the_command_line_renders_beyond_the_texture_limit() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let max = gpu.ctx.limits.max_texture_dimension_2d;
    let ssaa = 8;
    let width = max / ssaa + 16;
    let height = 40;
    if u64::from(width * ssaa) * u64::from(height * ssaa) > tensorglyph::frame::MAX_PIXELS {
        eprintln!("skipping: a texture side of {max} is beyond the reference's pixel cap");
        return;
    }
    drop(gpu);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("strip.png");
    let size = format!("{width}x{height}");
    let r = tg(&[
        "render",
        "--demo",
        "grid:3",
        "-o",
        out.to_str().unwrap(),
        "--size",
        &size,
        "--ssaa",
        &ssaa.to_string(),
        // Glyphs as tall as the strip, across the seam in its middle.
        "--zoom",
        "3",
        "--reference-check",
        "--json",
        "-q",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let j = json(&r);
    assert_eq!(j["width"], width);
    // Wider than one render target: at least two pieces.
    assert!(j["tiles"].as_u64().unwrap() >= 2, "{j}");
    assert!(j["covered_pixels"].as_u64().unwrap() > 100, "{j}");
    // The accuracy bounds of tests/cli/commands.rs's whole-image check.
    assert!(j["coverage_mismatch"].as_f64().unwrap() <= 5e-4, "{j}");
    assert!(j["id_mismatch"].as_f64().unwrap() <= 1e-3, "{j}");
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (width, height));
}

/// Outlines and shadows run on across tile seams: each tile draws the same shadow map (the
/// light frames what the whole image sees) and filters outlines within its margin.
#[test]
fn tiled_effects_equal_whole_effects() {
    use tensorglyph::effects::{Effects, Outlines, Shadows};
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let scene = grid_scene(6, GlyphKind::Ellipsoid);
    let buffers = gpu.upload(&scene).unwrap();
    let req = FrameRequest {
        aux: true,
        effects: Effects {
            outlines: Some(Outlines::default()),
            shadows: Some(Shadows {
                map_size: 1024,
                ..Shadows::default()
            }),
            ..Effects::default()
        }
        .resolved(),
        ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
    };
    for ortho in [false, true] {
        let cam = camera(&scene, ortho, 1);
        let whole = gpu.render_uploaded(&buffers, &cam, &req).unwrap();
        let tiled = small_tiles(1)
            .render_with(&cam, |c| gpu.render_uploaded(&buffers, c, &req))
            .unwrap();
        let (ids, color, _) = differences(&whole, &tiled);
        assert_eq!(ids, 0, "ortho {ortho}");
        let (a, b) = (whole.effects.unwrap(), tiled.effects.unwrap());
        let outline = (0..a.len())
            .filter(|&k| (a[k][1] > 0.5) != (b[k][1] > 0.5))
            .count();
        let shadow = (0..a.len())
            .filter(|&k| (a[k][0] - b[k][0]).abs() > 0.5)
            .count();
        eprintln!(
            "ortho {ortho}: colour within {color}/255, {outline} outline and {shadow} shadow states differ"
        );
        assert_eq!(outline, 0, "ortho {ortho}: outlines differ at seams");
        assert!(
            shadow * 1000 <= a.len(),
            "ortho {ortho}: {shadow} shadow states differ"
        );
        assert!(color <= 2, "ortho {ortho}: colour differs by {color}/255");
    }
}
