//! `tensorglyph render` and `tensorglyph demo`: headless frames to PNG, with timing and an
//! optional accuracy check against the f64 reference.

use std::ops::Deref;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Serialize;

use super::args::{
    CameraArgs, DrawArgs, EffectArgs, SceneArgs, SelectArgs, parse_color, parse_size, source,
};
use super::progress::Terminal;
use crate::backend::Backend;
use crate::camera::Camera;
use crate::defaults::DataKind;
use crate::frame::Frame;
use crate::image_out::{write_png, write_png_dpi};
use crate::legend::raster::{Caption, burn};
use crate::metrics::{Accuracy, compare, diff_image};
use crate::progress::Progress;
use crate::request::{FrameRequest, GlyphKind, Method};
use crate::scene::UnderlaySource;
use crate::scene::Visibility;
use crate::staging::{Demo, Recipe, Source, Timings, stage};
use crate::tiles::Tiling;

/// Image and output options of `render` and `demo`.
#[derive(Args, Debug, Clone)]
pub struct ImageArgs {
    /// Image size.
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Background: a name (white, black, grey, paraview), #rrggbb, or r,g,b in [0, 1]
    /// (default: white; black for DTI files, NIfTI and NRRD).
    #[arg(long, value_parser = parse_color)]
    pub background: Option<[f64; 4]>,
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
    /// Anti-aliasing: render N×N samples per pixel and average them (box filter); ids and the
    /// accuracy metrics use each pixel's centre sample.
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    pub ssaa: u32,
    /// A transparent background: alpha 0 where no glyph (or underlay) is drawn.
    #[arg(long)]
    pub transparent: bool,
    /// Burn a legend into the image: the colour key, the scale, the axes (R/A/S for NIfTI and
    /// NRRD), in the corner that covers the fewest glyphs.
    #[arg(long)]
    pub legend: bool,
    /// The resolution written into the PNG (pHYs), in dots per inch.
    #[arg(long, value_name = "DPI", allow_hyphen_values = true)]
    pub dpi: Option<f64>,
}

/// Everything `render` and `demo` share besides the input and output.
#[derive(Args, Debug, Clone)]
pub struct FrameArgs {
    #[command(flatten)]
    pub image: ImageArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub draw: DrawArgs,
    #[command(flatten)]
    pub effects: EffectArgs,
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub select: SelectArgs,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// A tensor file: VTK (.vtk, .vti, .vtr, .vts, .vtu, .vtp, .pvti), NIfTI-1 (.nii, .nii.gz),
    /// NRRD (.nrrd, .nhdr), MRtrix (.mif, .mif.gz, .mih) or an FSL eigen set (PREFIX_L1.nii.gz …
    /// or PREFIX).
    pub file: Option<PathBuf>,
    /// A built-in field instead of a file: grid40 or grid:N.
    #[arg(long)]
    pub demo: Option<Demo>,
    /// Output PNG.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub frame: FrameArgs,
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
    pub frame: FrameArgs,
}

/// What `render --json` prints.
#[derive(Serialize)]
pub struct RenderReport {
    method: Method,
    glyph: GlyphKind,
    /// Shading and the effects on, e.g. "deferred+outlines+shadows".
    effects: String,
    adapter: Option<String>,
    backend: Option<String>,
    /// GPU pipelines built so far by this process.
    pipelines_built: Option<u32>,
    /// The pipeline cache on disk: where, what was loaded, or why it is off.
    pipeline_cache: Option<String>,
    width: u32,
    height: u32,
    /// Pieces the image was rendered in (1: whole; more beyond one render target).
    tiles: usize,
    glyphs_total: usize,
    /// Valid glyphs the selection kept (= glyphs_total without a selection).
    glyphs_selected: usize,
    /// Selected glyphs `--scale auto` scaled down to the robust largest size (or, on
    /// unstructured data, to their own room).
    glyphs_clamped: usize,
    /// The colour scheme in effect (`--color`, or the data's default resolved).
    color: &'static str,
    /// A scalar colouring's range, and the units its legend shows.
    color_range: Option<[f64; 2]>,
    units: Option<String>,
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
    render(&src, &args.output, &args.frame)
}

pub fn demo(args: DemoArgs) -> Result<()> {
    let demo = Demo { n: 40 };
    if let Some(path) = &args.write_vtk {
        let field = crate::field::synthetic::grid(demo.n);
        crate::field::synthetic::write_legacy_vtk(&field, path)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        if !args.frame.scene.quiet {
            eprintln!("wrote {} ({} tensors)", path.display(), field.len());
        }
        return Ok(());
    }
    render(&Source::Demo(demo), &args.output, &args.frame)
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
    crate::image_out::check_output(path, inputs)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(())
}

fn render(src: &Source, output: &Path, args: &FrameArgs) -> Result<()> {
    let FrameArgs {
        image,
        scene: scene_args,
        select,
        ..
    } = args;
    // The files its header names too (a .mih's data file), known before any work.
    let companions = match src {
        Source::File(p) => crate::field::companion_files(p),
        _ => Vec::new(),
    };
    let mut inputs: Vec<&Path> = match src {
        Source::File(p) => vec![p.as_path()],
        Source::Demo(_) | Source::Field(_) | Source::Bytes(_) => Vec::new(),
    };
    inputs.extend(companions.iter().map(PathBuf::as_path));
    if let Some(UnderlaySource::File(p)) = &select.underlay {
        inputs.push(p.as_path());
    }
    if let Some(p) = &select.mask {
        inputs.push(p.as_path());
    }
    check_output(output, &inputs)?;
    if let Some(d) = &image.diff {
        check_output(d, &inputs)?;
        if !image.reference_check {
            bail!("--diff needs --reference-check");
        }
    }
    let progress = Terminal::new(scene_args.quiet);
    let backend = |method| {
        let (backend, fell_back) = Backend::for_method(method)?;
        if fell_back {
            eprintln!("notice: no GPU adapter found; rendering with the CPU reference instead");
        }
        Ok(Box::new(backend))
    };
    let Rendered {
        width: w,
        height: h,
        color,
        diff,
        report,
        read,
    } = render_frame(src, args, backend, &progress)?;
    // Every file read, not only those named: a mask, a detached data file, the pieces.
    inputs.extend(read.iter().map(PathBuf::as_path));
    if let (Some(d), Some(diff)) = (&image.diff, &diff) {
        write_png(d, &inputs, w, h, diff)
            .with_context(|| format!("{}: cannot write", d.display()))?;
    }
    write_png_dpi(output, &inputs, w, h, &color, image.dpi)
        .with_context(|| format!("{}: cannot write", output.display()))?;
    if image.json {
        super::stdout::print(&format!("{}\n", serde_json::to_string(&report)?))?;
    } else if !scene_args.quiet {
        eprintln!(
            "wrote {} ({}x{}, {} glyphs, {:.1} ms/frame, {:?})",
            output.display(),
            w,
            h,
            report.glyphs_drawn,
            report.frame_ms,
            report.method
        );
        if report.glyphs_clamped > 0 {
            eprintln!(
                "{} glyphs larger than the 98th percentile were shown at its size (--scale auto)",
                report.glyphs_clamped
            );
        }
        if let Some(a) = &report.accuracy {
            eprintln!("{}", serde_json::to_string_pretty(a)?);
        }
    }
    Ok(())
}

/// The options of `render` without its input and output (`--size 640x480`, `--glyph
/// superquadric` …), parsed with the command line's defaults and checks, for front ends that
/// bring their own data and take the pixels (the Python package); an error names the option.
pub fn parse_frame_args(
    args: impl IntoIterator<Item = impl Into<std::ffi::OsString> + Clone>,
) -> std::result::Result<FrameArgs, Box<super::OptionError>> {
    super::parse_options(args)
}

/// An image `render` made, before it is written: RGBA8 pixels (row-major from the top left),
/// with `--diff`'s picture when asked for and what `--json` prints.
pub struct Rendered {
    pub width: u32,
    pub height: u32,
    pub color: Vec<u8>,
    pub diff: Option<Vec<u8>>,
    pub report: RenderReport,
    /// Every file read (the field's, the underlay's, the mask's): no output may replace one.
    pub read: Vec<PathBuf>,
}

/// What `render` does between its arguments and its PNG: check the options, stage `src`,
/// frame the camera, draw with the back end `backend` gives for the method (asked for once the
/// scene is staged, so a bad file fails before any GPU is set up), check against the
/// reference, burn the legend, and report. `--diff` and `-o` are the caller's to write.
pub fn render_frame<B>(
    src: &Source,
    args: &FrameArgs,
    backend: impl FnOnce(Method) -> Result<B>,
    progress: &dyn Progress,
) -> Result<Rendered>
where
    B: Deref<Target = Backend>,
{
    let FrameArgs {
        image,
        camera: cam,
        draw,
        effects,
        scene: scene_args,
        select,
    } = args;
    let mut framing = cam.framing()?;
    let defaults = DataKind::of(src).defaults();
    crate::frame::check_size(image.size.0, image.size.1)?;
    if let Some(d) = image.dpi
        && !(d.is_finite() && d > 0.0 && d / 0.0254 < f64::from(u32::MAX))
    {
        bail!("--dpi must be a positive number of dots per inch, got {d}");
    }
    let ssaa = image.ssaa;
    let (w, h) = image.size;
    let effects = effects.effects((w, h), ssaa)?;
    let depth_correction = !cam.no_depth_correction;
    let (glyph, peaks) = cam.glyph_for(src.kind(&scene_args.read_options()), &src.name())?;
    let options = draw.options(cam.method, glyph, depth_correction)?;
    let recipe = Recipe {
        underlay: select.underlay.clone(),
        middle_slice: defaults.middle_slice && select.no_slice(),
        underlay_side: Some((w.max(h) * ssaa) as usize),
        peaks,
        peaks_over: cam.peaks,
        ..scene_args.recipe(select.selection()?, glyph, &defaults)?
    };
    let recipe = if peaks && scene_args.color.is_none() {
        // Sticks are coloured by direction unless asked otherwise (solid): not by the
        // field's default scalar colouring (a stress field's).
        let mut recipe = recipe;
        recipe.style.color = crate::glyph::ColorScheme::Dec;
        recipe
    } else {
        recipe
    };
    if recipe.peaks_over && effects.shadows.is_some() {
        bail!(crate::render::effects::SHADOWS_OF_ONE_KIND);
    }
    let staged = stage(src, &recipe, progress)?;
    let mut read = staged.read.clone();
    if let Some(mask) = &recipe.selection.mask {
        read.extend_from_slice(mask.files_read());
    }
    let mut timings: Timings = staged.timings;
    let mut scene = staged.scene;
    // The whole field, not the selection: a slice is drawn where it is in the volume; but one
    // slice of a DTI volume is seen face-on and close, as DTI viewers show it.
    let (centre, half) = match staged.face {
        Some(face) if defaults.face_on && cam.view.is_none() => {
            framing.toward = Some(face.toward);
            (face.centre, face.half)
        }
        _ => (staged.frame_centre, staged.frame_half),
    };
    // With --ssaa the camera renders N×N samples per output pixel.
    let camera = Camera::frame_box(&framing, centre, half, w * ssaa, h * ssaa);
    if draw.sort() {
        scene.sort_front_to_back(&camera);
    }
    let backend = backend(cam.method)?;
    let backend: &Backend = &backend;
    let req = backend.adapt(
        FrameRequest {
            aux: image.reference_check,
            background: {
                let [r, g, b, _] = image.background.unwrap_or(defaults.background);
                [r, g, b, if image.transparent { 0.0 } else { 1.0 }]
            },
            frames: image.frames.max(1),
            underlay: select.underlay_view(),
            effects,
            ..FrameRequest::with_options(cam.method, depth_correction, &options)
        },
        &scene,
        &camera,
    );
    let method = req.method.method();
    let (adapter, backend_name, pipelines) = match backend.gpu() {
        Some(gpu) => (
            Some(gpu.ctx.adapter_name.clone()),
            Some(gpu.ctx.backend.clone()),
            Some(gpu.ctx.pipelines.clone()),
        ),
        None => (None, None, None),
    };
    // Beyond one render target (or the pixel cap) the samples are rendered in tiles, whose
    // margins hold the outline filter's reach so that outlines run on across their seams.
    let reach = req
        .effects
        .outlines
        .map_or(0, |o| o.width.div_ceil(ssaa) + 1);
    let tiling = Tiling {
        margin: Tiling::new(backend, ssaa).margin.max(reach),
        ..Tiling::new(backend, ssaa)
    };
    let tiles = if tiling.fits_whole(w, h) {
        1
    } else {
        tiling
            .plan(w, h)
            .with_context(|| format!("--ssaa {ssaa} renders {}x{} samples", w * ssaa, h * ssaa))?
            .len()
    };
    let mut frame: Frame = tiling.render(backend, &scene, &camera, &req, &mut timings, progress)?;

    let mut diff = None;
    let accuracy = if image.reference_check {
        let reference = Tiling {
            margin: tiling.margin,
            ..Tiling::new(&Backend::Reference, ssaa)
        }
        .render(
            &Backend::Reference,
            &scene,
            &camera,
            &FrameRequest { frames: 1, ..req },
            &mut Timings::default(),
            &crate::progress::Silent,
        )?;
        diff = image.diff.as_ref().map(|_| diff_image(&frame, &reference));
        let exact = crate::reference::ReferenceScene::new(&scene, &camera);
        Some(
            compare(&frame, &reference, &scene)
                .with_effects(&frame, &reference, &req.effects)
                .with_ties(&frame, &reference, &scene, &exact),
        )
    } else {
        None
    };
    if image.legend {
        let caption = Caption::of_frame(
            &staged.style,
            staged.glyphs_clamped,
            &scene,
            &req,
            &camera,
            DataKind::of(src) == DataKind::Diffusion,
        );
        burn(&mut frame.color, w, h, &frame.ids, &caption, req.background);
    }
    let Visibility {
        eye_inside,
        behind_camera,
        degenerate,
        culled,
    } = scene.visibility(&camera, req.cull, req.min_pixel_radius);
    let covered = frame.covered_pixels();
    let report = RenderReport {
        method,
        glyph,
        effects: req.effects.to_string(),
        adapter,
        backend: backend_name,
        pipelines_built: pipelines.as_ref().map(|p| p.built()),
        pipeline_cache: pipelines.as_ref().map(|p| p.describe().to_string()),
        width: w,
        height: h,
        tiles,
        glyphs_total: staged.glyphs_valid,
        glyphs_selected: staged.glyphs_selected,
        glyphs_clamped: staged.glyphs_clamped,
        color: staged.style.color.name(),
        color_range: staged
            .style
            .color
            .measure()
            .map(|_| staged.style.color_range),
        units: staged.style.units.clone(),
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
        bytes_per_glyph: crate::render::mesh::bytes_per_glyph(method),
        timings_ms: timings,
        peak_rss_bytes: crate::mem::peak_rss_bytes(),
        accuracy,
    };
    Ok(Rendered {
        width: w,
        height: h,
        color: frame.color,
        diff,
        report,
        read,
    })
}
