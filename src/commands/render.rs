//! `tensorglyph render` and `tensorglyph demo`: headless frames to PNG, with timing and an
//! optional accuracy check against the f64 reference.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Serialize;

use super::path::PathArgs;
use super::pipeline::{Timings, build_scene, render_gpu, render_reference};
use super::scene::{SceneArgs, SelectArgs, source};
use tensorglyph::camera::{Camera, Framing, ViewPreset};
use tensorglyph::error::RenderError;
use tensorglyph::image_out::write_png;
use tensorglyph::load::{Demo, Source};
use tensorglyph::metrics::{Accuracy, compare, diff_image};
use tensorglyph::reference::ReferenceScene;
use tensorglyph::render::{Frame, FrameRequest, GlyphKind, GpuContext, GpuRenderer, Method};
use tensorglyph::scene::Visibility;

/// Image, camera and method options of `render` and `demo`.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Image size.
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Rendering method: gumhold or sigg (GPU ray casting), reference (exact CPU ray caster), or
    /// the triangle-mesh baselines mesh:N (icosphere / prism subdivided N = 0..=6 times) and box.
    #[arg(long, default_value = "gumhold")]
    pub method: Method,
    #[arg(long, value_enum, default_value_t = GlyphKind::Ellipsoid)]
    pub glyph: GlyphKind,
    /// Write the proxy quad's depth instead of the ray-cast depth.
    #[arg(long)]
    pub no_depth_correction: bool,
    /// View direction preset (ParaView's +X … −Z buttons; iso looks from +x, −y, +z).
    #[arg(long, value_enum, default_value_t = ViewPreset::Iso)]
    pub view: ViewPreset,
    /// Degrees about the up axis, after the preset.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f64,
    /// Degrees about the camera's right axis, after the preset.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub elevation: f64,
    /// > 1 moves closer.
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f64,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 30.0)]
    pub fov: f64,
    /// Orthographic projection.
    #[arg(long)]
    pub ortho: bool,
    /// Background: a name (white, black, grey), #rrggbb, or r,g,b in [0, 1].
    #[arg(long, default_value = "white", value_parser = parse_color)]
    pub background: [f64; 4],
    /// Render N frames and time each (the JSON reports the median).
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// One JSON object on stdout describing the frame.
    #[arg(long)]
    pub json: bool,
    /// Also render the exact reference and report how far the image is from it.
    #[arg(long)]
    pub reference_check: bool,
    /// With --reference-check: write a picture of where the two differ.
    #[arg(long, value_name = "FILE.png")]
    pub diff: Option<PathBuf>,
    #[command(flatten)]
    pub path: PathArgs,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// A VTK file (.vtk, .vti, .vtr, .vts, .vtu, .vtp, .pvti).
    pub file: Option<PathBuf>,
    /// A built-in field instead of a file: grid40 or grid:N.
    #[arg(long)]
    pub demo: Option<Demo>,
    /// Output PNG.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub select: SelectArgs,
}

#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Output PNG.
    #[arg(short, long, default_value = "grid40.png")]
    pub output: PathBuf,
    /// Write the demo field as a legacy VTK file (so other tools can render the same data)
    /// instead of rendering it.
    #[arg(long, value_name = "FILE")]
    pub write_vtk: Option<PathBuf>,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub select: SelectArgs,
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size '{s}' is not WxH (e.g. 1024x768)"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 {
        return Err(format!("size '{s}' has a zero side"));
    }
    Ok((w, h))
}

fn parse_color(s: &str) -> Result<[f64; 4], String> {
    let named = match s.to_ascii_lowercase().as_str() {
        "white" => Some([1.0, 1.0, 1.0]),
        "black" => Some([0.0, 0.0, 0.0]),
        "grey" | "gray" => Some([0.5, 0.5, 0.5]),
        "paraview" => Some([0.32, 0.34, 0.43]),
        _ => None,
    };
    let rgb = if let Some(c) = named {
        c
    } else if let Some(hex) = s.strip_prefix('#') {
        if hex.len() != 6 {
            return Err(format!("colour '{s}' is not #rrggbb"));
        }
        let v = u32::from_str_radix(hex, 16).map_err(|_| format!("colour '{s}' is not #rrggbb"))?;
        [
            f64::from((v >> 16) & 255) / 255.0,
            f64::from((v >> 8) & 255) / 255.0,
            f64::from(v & 255) / 255.0,
        ]
    } else {
        let parts: Vec<f64> = s
            .split(',')
            .map(|p| p.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("unknown colour '{s}': use a name, #rrggbb or r,g,b"))?;
        if parts.len() != 3 || parts.iter().any(|x| !(0.0..=1.0).contains(x)) {
            return Err(format!("colour '{s}' needs three numbers in [0, 1]"));
        }
        [parts[0], parts[1], parts[2]]
    };
    Ok([rgb[0], rgb[1], rgb[2], 1.0])
}

/// What `render --json` prints.
#[derive(Serialize)]
struct RenderReport {
    method: Method,
    glyph: GlyphKind,
    adapter: Option<String>,
    backend: Option<String>,
    width: u32,
    height: u32,
    glyphs_total: usize,
    /// Valid glyphs the selection kept (= glyphs_total without a selection).
    glyphs_selected: usize,
    glyphs_drawn: usize,
    glyphs_eye_inside: usize,
    glyphs_behind_camera: usize,
    glyphs_degenerate: usize,
    frame_ms: f64,
    fragments: Option<u64>,
    bytes_per_glyph: usize,
    /// Glyphs culled in the vertex stage (outside the frustum, or below --min-pixel-radius).
    glyphs_culled: usize,
    /// Glyphs showing in at least one pixel of the image.
    glyphs_visible: usize,
    /// Pixels showing a glyph in the image.
    covered_pixels: usize,
    /// Fragment-shader invocations per covered pixel (the driver's count: lavapipe counts
    /// every pixel of each 4x4 block a triangle touches).
    fragments_per_covered_pixel: Option<f64>,
    timings_ms: Timings,
    /// Peak resident set size of the process (VmHWM), null where the system does not say.
    peak_rss_bytes: Option<u64>,
    #[serde(flatten)]
    accuracy: Option<Accuracy>,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let src = source(args.file, args.demo)?;
    render(&src, &args.output, &args.view, &args.scene, &args.select)
}

pub fn demo(args: DemoArgs) -> Result<()> {
    let demo = Demo { n: 40 };
    if let Some(path) = &args.write_vtk {
        let field = tensorglyph::field::synthetic::grid(demo.n);
        tensorglyph::field::synthetic::write_legacy_vtk(&field, path)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        if !args.scene.quiet {
            eprintln!("wrote {} ({} tensors)", path.display(), field.len());
        }
        return Ok(());
    }
    render(
        &Source::Demo(demo),
        &args.output,
        &args.view,
        &args.scene,
        &args.select,
    )
}

/// Fail before any work if the output cannot be written there (also: a FIFO, device or the
/// input file itself, see `image_out::check_output`).
fn check_output(path: &Path, inputs: &[&Path]) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "{}: output folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!("{}: is a folder, not a file", path.display());
    }
    tensorglyph::image_out::check_output(path, inputs)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(())
}

fn render(
    src: &Source,
    output: &Path,
    view: &ViewArgs,
    scene_args: &SceneArgs,
    select: &SelectArgs,
) -> Result<()> {
    let inputs: Vec<&Path> = match src {
        Source::File(p) => vec![p.as_path()],
        Source::Demo(_) => Vec::new(),
    };
    check_output(output, &inputs)?;
    if let Some(d) = &view.diff {
        check_output(d, &inputs)?;
        if !view.reference_check {
            bail!("--diff needs --reference-check");
        }
    }
    if !(view.fov > 0.0 && view.fov < 180.0) {
        bail!("--fov must be between 0 and 180 degrees, got {}", view.fov);
    }
    if !(view.zoom.is_finite() && view.zoom > 0.0) {
        bail!("--zoom must be a positive number, got {}", view.zoom);
    }
    scene_args.style()?;
    view.path.check()?;
    let selection = select.selection()?;
    let staged = build_scene(src, scene_args, &selection, view.glyph)?;
    let mut timings = staged.timings;
    let mut scene = staged.scene;
    let framing = Framing {
        view: view.view,
        azimuth: view.azimuth,
        elevation: view.elevation,
        zoom: view.zoom,
        fov_deg: view.fov,
        ortho: view.ortho,
    };
    let (w, h) = view.size;
    // The whole field, not the selection: a slice is drawn where it is in the volume.
    let camera = Camera::frame(&framing, staged.frame_centre, staged.frame_radius, w, h);
    let mut req = view.path.apply(FrameRequest {
        method: view.method,
        glyph: view.glyph,
        depth_correction: !view.no_depth_correction,
        aux: view.reference_check,
        background: view.background,
        frames: view.frames.max(1),
        ..FrameRequest::default()
    });
    if view.path.sort() {
        scene.sort_front_to_back(&camera);
    }

    let mut method = view.method;
    let mut adapter = None;
    let mut backend = None;
    let frame: Frame = if method.is_gpu() {
        match GpuContext::new() {
            Ok(ctx) => {
                adapter = Some(ctx.adapter_name.clone());
                backend = Some(ctx.backend.clone());
                let gpu = GpuRenderer::new(ctx)?;
                req = req.with_early_depth(&gpu, &scene, &camera);
                render_gpu(&gpu, &scene, &camera, &req, &mut timings, scene_args.quiet)?
            }
            Err(RenderError::NoAdapter) => {
                eprintln!("notice: no GPU adapter found; rendering with the CPU reference instead");
                method = Method::Reference;
                req.method = method;
                render_reference(&scene, &camera, &req, &mut timings, scene_args.quiet)
            }
            Err(e) => return Err(e.into()),
        }
    } else {
        render_reference(&scene, &camera, &req, &mut timings, scene_args.quiet)
    };

    let accuracy = if view.reference_check {
        let reference = ReferenceScene::new(&scene, &camera, req.glyph).render(&req);
        if let Some(d) = &view.diff {
            write_png(d, &inputs, w, h, &diff_image(&frame, &reference))
                .with_context(|| format!("{}: cannot write", d.display()))?;
        }
        Some(compare(&frame, &reference, &scene))
    } else {
        None
    };
    write_png(output, &inputs, w, h, &frame.color)
        .with_context(|| format!("{}: cannot write", output.display()))?;

    let Visibility {
        eye_inside,
        behind_camera,
        degenerate,
        culled,
    } = scene.visibility(&camera, req.cull, req.min_pixel_radius);
    let covered = frame.covered_pixels();
    let report = RenderReport {
        method,
        glyph: view.glyph,
        adapter,
        backend,
        width: w,
        height: h,
        glyphs_total: staged.glyphs_valid,
        glyphs_selected: staged.glyphs_selected,
        glyphs_drawn: scene.instances.len() - eye_inside - behind_camera - degenerate - culled,
        glyphs_culled: culled,
        glyphs_visible: frame.visible_glyphs(),
        covered_pixels: covered,
        fragments_per_covered_pixel: frame
            .fragments
            .filter(|_| covered > 0)
            .map(|f| f as f64 / covered as f64),
        glyphs_eye_inside: eye_inside,
        glyphs_behind_camera: behind_camera,
        glyphs_degenerate: degenerate,
        frame_ms: frame.median_ms(),
        fragments: frame.fragments,
        bytes_per_glyph: tensorglyph::render::mesh::bytes_per_glyph(method),
        timings_ms: timings,
        peak_rss_bytes: tensorglyph::mem::peak_rss_bytes(),
        accuracy,
    };
    if view.json {
        println!("{}", serde_json::to_string(&report)?);
    } else if !scene_args.quiet {
        eprintln!(
            "wrote {} ({}x{}, {} glyphs, {:.1} ms/frame, {:?})",
            output.display(),
            w,
            h,
            report.glyphs_drawn,
            report.frame_ms,
            method
        );
        if let Some(a) = &report.accuracy {
            eprintln!("{}", serde_json::to_string_pretty(a)?);
        }
    }
    Ok(())
}
