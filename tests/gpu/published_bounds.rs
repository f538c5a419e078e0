//! The bounds the book promises for the canonical scene (docs/book/src/results/accuracy.md):
//! grid40 (64,000 ellipsoids) at 1024x768, Gumhold's method on the GPU against the exact f64
//! reference.

use tensorglyph::camera::{Camera, Framing};
use tensorglyph::field::synthetic::grid40;
use tensorglyph::glyph::{GlyphStyle, derive_glyphs};
use tensorglyph::metrics::compare;
use tensorglyph::reference::ReferenceScene;
use tensorglyph::request::{FrameRequest, GlyphKind, Method, Preset};
use tensorglyph::scene::Scene;
use tensorglyph::staging::field_spacing;

#[test]
fn grid40_gumhold_meets_the_published_bounds() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let field = grid40();
    let set = derive_glyphs(&field, &tensorglyph::progress::Silent);
    let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
    let scene = Scene::build(&set, &style, GlyphKind::Ellipsoid);
    let camera = Camera::frame(&Framing::default(), scene.centre, scene.radius, 1024, 768);
    let baseline = FrameRequest {
        aux: true,
        ..FrameRequest::new(Method::Gumhold)
    };
    let render_default = FrameRequest {
        aux: true,
        ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
    };
    let reference = ReferenceScene::new(&scene, &camera).render(&baseline);
    // Most of the 64,000 glyphs are visible pixels, not a blank frame.
    assert!(reference.covered_pixels() > 200_000);
    // `render`'s default (splats from the compute prepass) and `--baseline` (a quad per glyph).
    for req in [render_default, baseline] {
        let frame = gpu.render(&scene, &camera, &req).unwrap();
        let a = compare(&frame, &reference, &scene);
        eprintln!("splat {}: {a:?}", req.splat_pixels());
        // grid40's acceptance bounds (docs/book/src/results/accuracy.md). Coverage and identity
        // flip only on pixel centres within f32 rounding of a silhouette or an intersection
        // curve; depth (relative to the glyph's largest radius) and normals are limited at the
        // rims, where the hit moves fastest with the ray.
        assert!(a.coverage_mismatch <= 5e-4, "{a:?}");
        assert!(a.id_mismatch <= 1e-3, "{a:?}");
        assert!(a.depth_err_rel_p99 <= 1e-4, "{a:?}");
        assert!(a.normal_err_deg_p99 <= 0.5, "{a:?}");
        // What this code holds, well inside them (issue 37's aim of 1e-5 for depth): the
        // pixel's offset from a glyph's centre ray is formed in double-f32 (centre_ray), and the
        // reference casts the instances as stored. Measured on lavapipe: depth p99 1.06e-6,
        // normals 0.0002°, ids 0 (they were 3.95e-5, 0.009° and 1.7e-5).
        assert!(a.depth_err_rel_p99 <= 5e-6, "{a:?}");
        assert!(a.normal_err_deg_p99 <= 2e-3, "{a:?}");
        assert!(a.id_mismatch <= 1e-5, "{a:?}");
    }
}
