//! The staged pipeline `render`, `demo` and `bench --large` share: read → eigendecomposition →
//! selection and scene → upload → first frame, each stage timed, with progress bars on a
//! terminal, and the field and glyph set dropped as soon as the scene is built (so peak memory
//! stays near the largest single stage).

use std::time::Instant;

use anyhow::{Result, bail};
use glam::DVec3;
use serde::Serialize;

use super::scene::{SceneArgs, counter, eigen, read, spinner};
use tensorglyph::camera::Camera;
use tensorglyph::load::{Source, field_spacing};
use tensorglyph::reference::ReferenceScene;
use tensorglyph::render::{Frame, FrameRequest, GlyphKind, GpuRenderer};
use tensorglyph::scene::Scene;
use tensorglyph::select::Selection;

/// Wall-clock milliseconds of each stage.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timings {
    /// Reading the file or generating the demo field.
    pub load: f64,
    /// Eigendecomposition of every tensor (`derive_glyphs`).
    pub eigen: f64,
    /// Selection, style and `Scene::build` (and the whole field's bounds when a selection is
    /// drawn).
    pub scene: f64,
    /// Uploading the instances to the GPU (0 for the CPU reference).
    pub upload: f64,
    /// The first frame: targets, pipelines, draw and read-back.
    pub first_frame: f64,
    /// Peak resident set size (VmHWM) after each stage, in the order of [`Self::stages`].
    #[serde(skip)]
    pub peak_rss_after: [Option<u64>; 5],
}

impl Timings {
    /// (stage name, ms) in pipeline order.
    pub fn stages(&self) -> [(&'static str, f64); 5] {
        [
            ("load", self.load),
            ("eigen", self.eigen),
            ("scene", self.scene),
            ("upload", self.upload),
            ("first_frame", self.first_frame),
        ]
    }
}

/// A built scene and what it took.
pub struct Staged {
    pub scene: Scene,
    /// Bounding sphere of the whole field (every valid glyph), which the camera frames so a
    /// selection is drawn in place.
    pub frame_centre: DVec3,
    pub frame_radius: f64,
    /// Valid tensors (glyphs before the selection).
    pub glyphs_valid: usize,
    /// Glyphs the selection kept (the scene's instances).
    pub glyphs_selected: usize,
    pub timings: Timings,
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

fn peak() -> Option<u64> {
    tensorglyph::mem::peak_rss_bytes()
}

/// Read, decompose, select and build; the field and glyphs are gone when this returns.
pub fn build_scene(
    source: &Source,
    args: &SceneArgs,
    selection: &Selection,
    glyph: GlyphKind,
) -> Result<Staged> {
    let style = args.style()?;
    selection.check()?;
    let mut timings = Timings::default();

    let t = Instant::now();
    let field = read(source, args)?;
    timings.load = ms(t);
    timings.peak_rss_after[0] = peak();
    // Lattice checks before the long part.
    selection.check_field(&field)?;

    let t = Instant::now();
    let set = eigen(&field, args.quiet);
    timings.eigen = ms(t);
    timings.peak_rss_after[1] = peak();

    let t = Instant::now();
    let resolved = style.resolve(&set, field_spacing(&field));
    let glyphs_valid = set.glyphs.len();
    let everything = selection.is_everything();
    let selected = if everything {
        None
    } else {
        Some(selection.select(&field, &set))
    };
    drop(field);
    if let Some(sel) = &selected
        && sel.is_empty()
    {
        bail!(
            "the selection keeps no glyph: {} leaves none of the {} valid glyphs",
            selection.describe(),
            glyphs_valid
        );
    }
    if glyphs_valid == 0 {
        bail!("no glyph to draw: the field has no valid tensor");
    }
    let (scene, frame_centre, frame_radius) = match selected {
        None => {
            let scene = build_with_bar(&set, &resolved, glyph, args.quiet);
            drop(set);
            let (c, r) = (scene.centre, scene.radius);
            (scene, c, r)
        }
        Some(indices) => {
            // Frame the whole field (as the viewer does) without building it.
            let pb = spinner(args.quiet, "bounds of the whole field");
            let (c, r) = Scene::bounding_sphere(&set, &resolved, glyph);
            if let Some(pb) = pb {
                pb.finish_and_clear();
            }
            let subset = Selection::subset(&set, &indices);
            drop(indices);
            drop(set);
            (build_with_bar(&subset, &resolved, glyph, args.quiet), c, r)
        }
    };
    timings.scene = ms(t);
    timings.peak_rss_after[2] = peak();
    Ok(Staged {
        glyphs_selected: scene.instances.len(),
        scene,
        frame_centre,
        frame_radius,
        glyphs_valid,
        timings,
    })
}

fn build_with_bar(
    set: &tensorglyph::glyph::GlyphSet,
    style: &tensorglyph::glyph::ResolvedStyle,
    glyph: GlyphKind,
    quiet: bool,
) -> Scene {
    let pb = counter(quiet, "scene", set.glyphs.len() as u64);
    let scene = Scene::build_with_progress(set, style, glyph, pb.as_ref());
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    scene
}

/// Upload `scene` and draw `req.frames` frames: the first timed on its own (`first_frame`),
/// the others, if any, give the frame times of the result (else the first frame's time does).
pub fn render_gpu(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    timings: &mut Timings,
    quiet: bool,
) -> Result<Frame> {
    let pb = spinner(
        quiet,
        &format!("uploading {} instances", scene.instances.len()),
    );
    let t = Instant::now();
    let uploaded = gpu.upload(scene);
    timings.upload = ms(t);
    timings.peak_rss_after[3] = peak();
    let buffers =
        uploaded.map_err(|e| anyhow::Error::new(e).context(stopped("upload", timings)))?;
    if let Some(pb) = &pb {
        pb.set_message("first frame");
    }
    let first_req = FrameRequest { frames: 1, ..*req };
    let t = Instant::now();
    let first = gpu.render_uploaded(&buffers, camera, &first_req);
    timings.first_frame = ms(t);
    timings.peak_rss_after[4] = peak();
    let mut frame =
        first.map_err(|e| anyhow::Error::new(e).context(stopped("first frame", timings)))?;
    if req.frames > 1 {
        if let Some(pb) = &pb {
            pb.set_message(format!("{} more frames", req.frames - 1));
        }
        let rest = FrameRequest {
            frames: req.frames - 1,
            ..*req
        };
        frame = gpu.render_uploaded(&buffers, camera, &rest)?;
    }
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    Ok(frame)
}

/// "stopped at STAGE after load … ms, …": what ran before a failing GPU stage, on one line.
fn stopped(stage: &str, t: &Timings) -> String {
    let ran: Vec<String> = t
        .stages()
        .iter()
        .filter(|(_, ms)| *ms > 0.0)
        .map(|(name, ms)| format!("{name} {ms:.0} ms"))
        .collect();
    let peak = tensorglyph::mem::peak_rss_bytes().map_or(String::new(), |b| {
        format!(", peak RSS {:.0} MiB", b as f64 / 1048576.0)
    });
    format!("stopped at {stage} after {}{peak}", ran.join(", "))
}

/// The exact CPU reference, timed like [`render_gpu`] (no upload).
pub fn render_reference(
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    timings: &mut Timings,
    quiet: bool,
) -> Frame {
    let pb = spinner(quiet, "reference frame");
    let t = Instant::now();
    let rs = ReferenceScene::new(scene, camera, req.glyph);
    let mut frame = rs.render(req);
    timings.upload = 0.0;
    timings.first_frame = ms(t);
    timings.peak_rss_after[3] = timings.peak_rss_after[2];
    timings.peak_rss_after[4] = peak();
    if req.frames > 1 {
        frame.frame_ms.clear();
        for _ in 1..req.frames {
            frame.frame_ms.extend(rs.render(req).frame_ms);
        }
    }
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    frame
}
