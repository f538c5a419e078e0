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

/// Bounds on `render --reference-check`'s measures: coverage and ids (shares of pixels), depth
/// p99 (of the glyph's radius), normal p99 (degrees), and the colours' PSNR at the pixels
/// both cover.
pub struct Bounds {
    pub coverage: f64,
    pub id: f64,
    pub depth_p99: f64,
    pub normal_p99_deg: f64,
    pub psnr_db: f64,
}

/// Run `tensorglyph render` with `args` (a field and its options) and `--reference-check` at
/// 320×240, print its measures under `name`, and return its JSON and whether they are within
/// `b`.
pub fn reference_check(name: &str, args: &[&str], b: &Bounds) -> (serde_json::Value, bool) {
    use crate::cli::{json, stderr, tg};
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[
        "--size",
        "320x240",
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--reference-check",
        "-q",
    ]);
    let r = tg(&all);
    assert!(r.status.success(), "{all:?}: {}", stderr(&r));
    let j = json(&r);
    let v = |k: &str| j[k].as_f64().unwrap_or(f64::NAN);
    eprintln!(
        "{name}: coverage {:.2e} id {:.2e} depth p99 {:.2e} normal p99 {:.5}° psnr {:.1} dB",
        v("coverage_mismatch"),
        v("id_mismatch"),
        v("depth_err_rel_p99"),
        v("normal_err_deg_p99"),
        v("color_psnr_db"),
    );
    let ok = v("coverage_mismatch") <= b.coverage
        && v("id_mismatch") <= b.id
        && v("depth_err_rel_p99") <= b.depth_p99
        && v("normal_err_deg_p99") <= b.normal_p99_deg
        && v("color_psnr_db") >= b.psnr_db;
    (j, ok)
}
