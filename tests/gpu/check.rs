//! Rendering a scene on the GPU and with the exact f64 reference and holding the difference
//! to stated bounds: the helpers every module of this group uses.

use tensorglyph::render::{GpuContext, GpuRenderer};

/// The GPU renderer, or `None` (skip) when no adapter exists. Under CI a missing adapter fails:
/// a GPU test must never be skipped silently there.
pub fn gpu() -> Option<GpuRenderer> {
    match GpuContext::new() {
        Ok(ctx) => Some(GpuRenderer::new(ctx).expect("pipelines build on this adapter")),
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set but no GPU adapter is available: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

use tensorglyph::camera::Camera;
use tensorglyph::frame::Frame;
use tensorglyph::metrics::{Accuracy, compare};
use tensorglyph::reference::ReferenceScene;
use tensorglyph::request::{DrawOptions, FrameRequest, GlyphKind, Method, Preset, Proxy};
use tensorglyph::scene::Scene;

/// Render `scene` with `req` (which must ask for aux data) on the GPU and with the reference;
/// the GPU frame and its accuracy, or `None` without an adapter.
pub fn check_request(
    name: &str,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
) -> Option<(Frame, Accuracy)> {
    let gpu = gpu()?;
    let frame = gpu.render(scene, camera, req).expect("GPU frame");
    let reference = ReferenceScene::new(scene, camera).render(req);
    let acc = compare(&frame, &reference, scene);
    eprintln!(
        "{name} ({} {}): {acc:?} (covered {}, fragments {:?})",
        req.method.method(),
        scene.kind,
        reference.covered_pixels(),
        frame.fragments
    );
    assert!(
        reference.covered_pixels() > 100,
        "{name}: scene shows too little"
    );
    Some((frame, acc))
}

/// Bounds for a smooth single-glyph view at 256x192: the rim pixels whose centres lie within
/// f32 rounding of the silhouette can flip (a handful of a 49k-pixel image: 0.1 %); depth and
/// normal in f32 are good to ~1e-5 glyph sizes and well under 0.1° except at grazing rims,
/// which the 99th percentile excludes. Colour is 8-bit: off-by-one rounding on a few channels
/// keeps PSNR far above 40 dB.
pub fn assert_tight(name: &str, a: &Accuracy) {
    assert!(a.coverage_mismatch <= 1e-3, "{name}: coverage {a:?}");
    assert!(a.id_mismatch <= 1e-3, "{name}: id {a:?}");
    assert!(a.depth_err_rel_p99 <= 1e-4, "{name}: depth {a:?}");
    assert!(a.normal_err_deg_p99 <= 0.1, "{name}: normal {a:?}");
    assert!(a.color_psnr_db >= 40.0, "{name}: colour {a:?}");
}

/// Compare `frame` (rendered with `req`, which asks for aux data) with the reference of the same
/// scene and camera and hold it to the bounds of a many-glyph scene: grid40's acceptance
/// bounds for coverage, depth and normals, with ids at 0.2 % (small scenes have proportionally
/// more glyph-to-glyph edges than grid40).
pub fn assert_scene_bounds(
    label: &str,
    frame: &Frame,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
) -> Accuracy {
    let reference = ReferenceScene::new(scene, camera).render(req);
    let a = compare(frame, &reference, scene);
    eprintln!("{label}: {a:?}");
    assert!(reference.covered_pixels() > 5_000, "{label}: a real image");
    assert!(a.coverage_mismatch <= 5e-4, "{label}: {a:?}");
    assert!(a.id_mismatch <= 2e-3, "{label}: {a:?}");
    assert!(a.depth_err_rel_p99 <= 1e-4, "{label}: {a:?}");
    assert!(a.normal_err_deg_p99 <= 0.5, "{label}: {a:?}");
    a
}

/// A request for `method` with aux data (as [`check_request`] needs).
pub fn aux_request(method: Method, depth_correction: bool) -> FrameRequest {
    FrameRequest {
        aux: true,
        ..FrameRequest::with_options(method, depth_correction, &baseline())
    }
}

/// The baseline's draw options (a proxy per glyph, no culling), to change one at a time.
pub fn baseline() -> DrawOptions {
    Preset::Baseline.options()
}

/// Gumhold with `proxy`'s shape and conservative placement, with the aux target (early depth
/// is the renderer's to declare: [`GpuRenderer::with_early_depth`]).
pub fn proxy_request(proxy: Proxy) -> FrameRequest {
    let opts = DrawOptions {
        proxy: proxy.shape,
        conservative: proxy.conservative,
        ..baseline()
    };
    FrameRequest {
        aux: true,
        ..FrameRequest::with_options(Method::Gumhold, true, &opts)
    }
}

/// [`check_request`] for `method` and the scene's glyphs drawn as `glyph`
/// ([`Scene::drawn_as`]): the accuracy only.
pub fn check(
    name: &str,
    scene: &Scene,
    camera: &Camera,
    method: Method,
    glyph: GlyphKind,
    depth_correction: bool,
) -> Option<Accuracy> {
    let req = aux_request(method, depth_correction);
    check_request(name, &scene.drawn_as(glyph), camera, &req).map(|(_, a)| a)
}

/// [`check`] with depth correction, held to [`assert_tight`]'s bounds (skipped without an
/// adapter).
pub fn check_tight(name: &str, scene: &Scene, camera: &Camera, method: Method, glyph: GlyphKind) {
    if let Some(a) = check(name, scene, camera, method, glyph, true) {
        assert_tight(&format!("{name} ({method} {glyph})"), &a);
    }
}
