//! Speed against accuracy: every GPU method × glyph × depth setting on the same scenes and
//! views, timed in one process with the methods interleaved across repetitions (so machine
//! drift hits all alike), each compared once with the exact reference.

pub mod brain;
pub mod chart;
pub mod effects;
pub mod million;
pub mod report;
pub mod startup;

use glam::DVec3;
use serde::Serialize;

use crate::camera::{Camera, Framing};
use crate::frame::Frame;
use crate::metrics::{Accuracy, compare};
use crate::reference::ReferenceScene;
use crate::render::GpuRenderer;
use crate::render::gpu_data::GPU_GLYPH_SIZE;
use crate::request::{FrameRequest, GlyphKind, Method, Preset};
use crate::scene::Scene;

/// One thing to measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Config {
    pub method: Method,
    pub glyph: GlyphKind,
    pub depth_correction: bool,
    /// The way of drawing (the `path` column).
    pub path: Preset,
}

impl Config {
    /// The frame request of this configuration (`aux` for the accuracy pass).
    fn request(&self, aux: bool) -> FrameRequest {
        FrameRequest {
            aux,
            ..FrameRequest::preset(self.method, self.depth_correction, self.path)
        }
    }

    /// The scene this configuration draws: front to back for `Sorted`, else file order.
    fn scene<'v>(&self, view: &'v View) -> &'v Scene {
        if self.path.sorts() {
            &view.sorted
        } else {
            &view.scene
        }
    }
}

/// A named camera set-up over a scene.
#[derive(Debug, Clone)]
pub struct View {
    pub name: String,
    pub scene: Scene,
    pub camera: Camera,
    /// `scene` sorted front to back for `camera`.
    pub sorted: Scene,
}

impl View {
    pub fn new(name: &str, scene: Scene, camera: Camera) -> Self {
        let mut sorted = scene.clone();
        sorted.sort_front_to_back(&camera);
        Self {
            name: name.into(),
            scene,
            camera,
            sorted,
        }
    }
}

/// The three views of a field: the whole field; `close`, a few large glyphs filling the image
/// (fill-bound); `far`, the whole field shrunk so glyphs are a pixel or two (setup-bound).
pub fn standard_views(scene: &Scene, width: u32, height: u32) -> Vec<View> {
    let whole = Camera::frame(
        &Framing::default(),
        scene.centre,
        scene.radius,
        width,
        height,
    );
    let far = Camera::frame(
        &Framing {
            zoom: 0.125,
            ..Framing::default()
        },
        scene.centre,
        scene.radius,
        width,
        height,
    );
    let close_scene = nearest_to_centre(scene, 27);
    let close = Camera::frame(
        &Framing::default(),
        close_scene.centre,
        close_scene.radius,
        width,
        height,
    );
    vec![
        View::new("default", scene.clone(), whole),
        View::new("close", close_scene, close),
        View::new("far", scene.clone(), far),
    ]
}

/// The `n` glyphs nearest the scene's centre, as a scene of their own.
pub fn nearest_to_centre(scene: &Scene, n: usize) -> Scene {
    let c = scene.centre - scene.origin;
    let mut idx: Vec<usize> = (0..scene.instances.len()).collect();
    let dist =
        |i: usize| (DVec3::from(scene.instances[i].centre.map(f64::from)) - c).length_squared();
    idx.sort_by(|&a, &b| dist(a).total_cmp(&dist(b)));
    let instances = idx
        .into_iter()
        .take(n)
        .map(|i| scene.instances[i])
        .collect();
    Scene::from_instances(scene.origin, instances)
}

/// Below this (the untimed frame's time), each timed repetition draws two frames and times the
/// second. On lavapipe the first frame of a render call costs up to twice a steady one on small
/// scenes (the close view: 9 against 4.6 ms for superquadrics), which had diluted the ratios
/// between methods there; `render --frames N` and the viewer report the steady frames too.
/// Slower frames are timed alone: a few milliseconds do not show beside a second.
pub const WARM_UP_BELOW_MS: f64 = 1000.0;

/// The frames of `f` after its first, or its one frame.
pub(crate) fn steady_ms(f: &Frame) -> &[f64] {
    &f.frame_ms[f.frame_ms.len().saturating_sub(1).min(1)..]
}

/// A measured configuration: one CSV row.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub scene: String,
    pub view: String,
    pub method: Method,
    pub glyph: GlyphKind,
    pub depth_correction: bool,
    /// [`Preset`] of the configuration.
    pub path: String,
    pub frame_ms_median: f64,
    pub frame_ms_min: f64,
    pub frame_ms_max: f64,
    pub fragments: Option<u64>,
    pub vertices: Option<u64>,
    pub bytes_per_glyph: usize,
    /// Glyphs the vertex stage culls (outside the frustum).
    pub glyphs_culled: usize,
    pub covered_pixels: usize,
    /// Fragments the method's proxies should shade (Gumhold: the quads' pixel area; Sigg: the
    /// boxes' pixels), where a model exists.
    pub predicted_fragments: Option<f64>,
    /// The same under lavapipe's counting (16 per 4x4 tile a triangle touches).
    pub predicted_tile_fragments: Option<f64>,
    pub accuracy: Accuracy,
    /// Empty when measured; else why not.
    pub skipped: String,
}

impl Row {
    /// Fragment-shader invocations per pixel covered in the final image.
    pub fn fragments_per_covered_pixel(&self) -> Option<f64> {
        self.fragments
            .filter(|_| self.covered_pixels > 0)
            .map(|f| f as f64 / self.covered_pixels as f64)
    }
}

/// Bench settings.
#[derive(Debug, Clone)]
pub struct Options {
    /// Timed repetitions per configuration.
    pub frames: u32,
    /// Seconds one frame of a configuration may take; predicted or measured beyond it, the
    /// configuration is skipped (and listed as skipped).
    pub budget_s: f64,
    pub methods: Vec<Method>,
    pub glyphs: Vec<GlyphKind>,
}

/// Progress callback: (done, total, what).
pub type Progress<'a> = &'a (dyn Fn(u64, u64, &str) + Sync);

/// Measure every configuration on every view. Scenes come per glyph kind (a cylinder scene has
/// its frames reordered), each with the same list of views.
pub fn run(
    gpu: &GpuRenderer,
    scene_name: &str,
    views_by_glyph: &[(GlyphKind, Vec<View>)],
    opts: &Options,
    progress: Progress<'_>,
) -> Vec<Row> {
    let configs: Vec<Config> = opts
        .glyphs
        .iter()
        .flat_map(|&glyph| {
            opts.methods.iter().flat_map(move |&method| {
                // Meshes write their rasterised depth either way (their rows show it costs
                // nothing); the ray casters write the proxy's depth without correction.
                let mut v: Vec<Config> = [true, false]
                    .into_iter()
                    .map(|depth_correction| Config {
                        method,
                        glyph,
                        depth_correction,
                        path: Preset::Baseline,
                    })
                    .collect();
                v.extend(
                    Preset::VALUES[1..]
                        .iter()
                        .copied()
                        .filter(|p| p.applies_to(method, glyph))
                        .map(|path| Config {
                            method,
                            glyph,
                            depth_correction: true,
                            path,
                        }),
                );
                v
            })
        })
        .filter(|c| views_by_glyph.iter().any(|(g, _)| *g == c.glyph))
        .collect();
    let view_count = views_by_glyph.first().map_or(0, |(_, v)| v.len());
    let total = (view_count * configs.len() * (opts.frames as usize + 1)) as u64;
    let mut done = 0u64;
    let mut rows = Vec::new();
    for v in 0..view_count {
        let view_of = |g: GlyphKind| &views_by_glyph.iter().find(|(k, _)| *k == g).unwrap().1[v];
        let mut states: Vec<(Config, State)> =
            configs.iter().map(|&c| (c, State::default())).collect();
        // Untimed pass: the reference once per glyph kind, then one frame with the aux target per
        // configuration for its accuracy and a first estimate of its time.
        let mut references: Vec<(GlyphKind, Frame)> = Vec::new();
        let mut cost = CostModel::default();
        for (cfg, st) in states.iter_mut() {
            let view = view_of(cfg.glyph);
            progress(
                done,
                total,
                &format!("{} {} {}", view.name, cfg.method, cfg.glyph),
            );
            done += 1;
            if let Some(reason) = cost.over_budget(cfg, opts.budget_s) {
                st.skipped = reason;
                continue;
            }
            if !references.iter().any(|(g, _)| *g == cfg.glyph) {
                let req = FrameRequest {
                    aux: true,
                    ..FrameRequest::new(Method::Reference)
                };
                let f = ReferenceScene::new(&view.scene, &view.camera).render(&req);
                rows.push(reference_row(scene_name, &view.name, cfg.glyph, &f));
                references.push((cfg.glyph, f));
            }
            let reference = &references.iter().find(|(g, _)| *g == cfg.glyph).unwrap().1;
            let scene = cfg.scene(view);
            let req = gpu.with_early_depth(cfg.request(true), scene, &view.camera);
            match gpu.render(scene, &view.camera, &req) {
                Ok(f) => {
                    // Ids are instance indices: compare against a reference of the same order.
                    st.accuracy = if !cfg.path.sorts() || scene.instances.is_empty() {
                        compare(&f, reference, &view.scene)
                    } else {
                        compare(&f, &reorder_ids(reference, &view.scene, scene), scene)
                    };
                    st.covered = f.covered_pixels();
                    st.culled = scene
                        .visibility(&view.camera, req.cull, req.min_pixel_radius)
                        .culled;
                    (st.predicted, st.predicted_tiles) =
                        predicted_fragments(&view.scene, &view.camera, cfg).unzip();
                    cost.record(cfg, f.median_ms());
                    st.frames = if f.median_ms() < WARM_UP_BELOW_MS {
                        2
                    } else {
                        1
                    };
                    if f.median_ms() > opts.budget_s * 1e3 {
                        st.skipped = format!("over budget: {:.1} s per frame", f.median_ms() / 1e3);
                    }
                }
                Err(e) => st.skipped = format!("failed: {e}"),
            }
        }
        // Timed repetitions, interleaved across configurations.
        for _ in 0..opts.frames {
            for (cfg, st) in states.iter_mut() {
                let view = view_of(cfg.glyph);
                progress(
                    done,
                    total,
                    &format!("{} {} {}", view.name, cfg.method, cfg.glyph),
                );
                done += 1;
                if !st.skipped.is_empty() {
                    continue;
                }
                let scene = cfg.scene(view);
                let req = FrameRequest {
                    frames: st.frames,
                    ..gpu.with_early_depth(cfg.request(false), scene, &view.camera)
                };
                match gpu.render(scene, &view.camera, &req) {
                    Ok(f) => {
                        st.times.extend(steady_ms(&f));
                        st.fragments = f.fragments.or(st.fragments);
                        st.vertices = f.vertices.or(st.vertices);
                    }
                    Err(e) => st.skipped = format!("failed: {e}"),
                }
            }
        }
        for (cfg, st) in states {
            rows.push(st.into_row(scene_name, &view_of(cfg.glyph).name, cfg));
        }
    }
    rows
}

/// `reference` (rendered from `from`) with its ids renumbered to the instance order of `to` (the
/// same glyphs reordered).
fn reorder_ids(reference: &Frame, from: &Scene, to: &Scene) -> Frame {
    // An instance is itself (a glyph's parts share its index, not their geometry).
    let key = |g: &crate::scene::GlyphInstance| bytemuck::cast::<_, [u32; 14]>(*g);
    let mut new_index = vec![0u32; from.instances.len()];
    let mut by_instance = std::collections::HashMap::with_capacity(to.instances.len());
    for (k, g) in to.instances.iter().enumerate() {
        by_instance.insert(key(g), k as u32 + 1);
    }
    for (k, g) in from.instances.iter().enumerate() {
        new_index[k] = by_instance.get(&key(g)).copied().unwrap_or(0);
    }
    let mut f = reference.clone();
    for id in &mut f.ids {
        if *id != 0 {
            *id = new_index[*id as usize - 1];
        }
    }
    f
}

/// What the bounding proxies of Gumhold's and Sigg's methods predict for the fragment count
/// (every proxy pixel is shaded: writing depth turns early depth rejection off): (pixel area,
/// lavapipe's 4x4-tile count).
fn predicted_fragments(scene: &Scene, camera: &Camera, cfg: &Config) -> Option<(f64, f64)> {
    use crate::twin::gumhold_ellipsoid::{proxy_shape, tile_invocations};
    use rayon::prelude::*;
    let (w, h) = (camera.width, camera.height);
    let n = scene.instances.len();
    let per_glyph: Box<dyn Fn(usize) -> (f64, f64) + Sync> = match cfg.method {
        // The model is of the quad.
        Method::Gumhold
            if matches!(cfg.path, Preset::Octagon | Preset::Triangle | Preset::Splat) =>
        {
            return None;
        }
        Method::Gumhold => Box::new(|i| {
            let p = proxy_shape(scene, camera, i);
            (
                p.area(w, h),
                tile_invocations(&p.triangles(w, h), w, h, 4) as f64,
            )
        }),
        Method::Sigg => Box::new(|i| {
            let p = crate::twin::sigg::scene_proxy(scene, camera, i);
            (
                p.pixels(w, h) as f64,
                p.strip_tile_invocations(w, h, 4) as f64,
            )
        }),
        _ => return None,
    };
    Some(
        (0..n)
            .into_par_iter()
            .map(&per_glyph)
            .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1)),
    )
}

fn reference_row(scene: &str, view: &str, glyph: GlyphKind, f: &Frame) -> Row {
    let ms = f.median_ms();
    Row {
        scene: scene.into(),
        view: view.into(),
        method: Method::Reference,
        glyph,
        depth_correction: true,
        path: Preset::Baseline.to_string(),
        frame_ms_median: ms,
        frame_ms_min: ms,
        frame_ms_max: ms,
        fragments: None,
        vertices: None,
        bytes_per_glyph: GPU_GLYPH_SIZE,
        glyphs_culled: 0,
        covered_pixels: f.covered_pixels(),
        predicted_fragments: None,
        predicted_tile_fragments: None,
        // The reference is the truth it is compared with.
        accuracy: Accuracy {
            color_psnr_db: 99.0,
            ..Accuracy::default()
        },
        skipped: String::new(),
    }
}

/// Predicts a configuration's frame time from a cheaper one of the same family (mesh levels:
/// time scales with triangles), so hopeless configurations are skipped before they run.
#[derive(Default)]
struct CostModel {
    /// (glyph, depth_correction) → (triangles per glyph, measured ms) of the last mesh level.
    measured: Vec<((GlyphKind, bool), (u64, f64))>,
}

impl CostModel {
    fn over_budget(&self, cfg: &Config, budget_s: f64) -> Option<String> {
        let tris = crate::render::mesh::triangles_per_glyph(cfg.method, cfg.glyph)?;
        let (_, (t0, ms0)) = self
            .measured
            .iter()
            .find(|(k, _)| *k == (cfg.glyph, cfg.depth_correction))?;
        let predicted = ms0 * tris as f64 / *t0 as f64;
        (predicted > budget_s * 1e3).then(|| {
            format!(
                "predicted over budget: {:.1} s per frame ({} triangles per glyph)",
                predicted / 1e3,
                tris
            )
        })
    }

    fn record(&mut self, cfg: &Config, ms: f64) {
        let Some(tris) = crate::render::mesh::triangles_per_glyph(cfg.method, cfg.glyph) else {
            return;
        };
        let key = (cfg.glyph, cfg.depth_correction);
        self.measured.retain(|(k, _)| *k != key);
        self.measured.push((key, (tris, ms)));
    }
}

#[derive(Default)]
struct State {
    times: Vec<f64>,
    fragments: Option<u64>,
    vertices: Option<u64>,
    accuracy: Accuracy,
    covered: usize,
    predicted: Option<f64>,
    predicted_tiles: Option<f64>,
    culled: usize,
    skipped: String,
    /// Frames per timed repetition: 2 (the second timed) or, for frames slower than
    /// [`WARM_UP_BELOW_MS`], 1.
    frames: u32,
}

impl State {
    fn into_row(mut self, scene: &str, view: &str, cfg: Config) -> Row {
        self.times.sort_by(f64::total_cmp);
        let (min, med, max) = if self.times.is_empty() {
            (f64::NAN, f64::NAN, f64::NAN)
        } else {
            (
                self.times[0],
                self.times[self.times.len() / 2],
                self.times[self.times.len() - 1],
            )
        };
        Row {
            scene: scene.into(),
            view: view.into(),
            method: cfg.method,
            glyph: cfg.glyph,
            depth_correction: cfg.depth_correction,
            path: cfg.path.to_string(),
            frame_ms_median: med,
            frame_ms_min: min,
            frame_ms_max: max,
            fragments: self.fragments,
            vertices: self.vertices,
            bytes_per_glyph: GPU_GLYPH_SIZE,
            glyphs_culled: self.culled,
            covered_pixels: self.covered,
            predicted_fragments: self.predicted,
            predicted_tile_fragments: self.predicted_tiles,
            accuracy: self.accuracy,
            skipped: self.skipped,
        }
    }
}
