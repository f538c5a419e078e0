//! `tensorglyph bench`: every method × glyph × depth setting on the same scenes, timed in one
//! run, each compared with the exact reference; CSV, charts and a Markdown report.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use super::args::{SceneArgs, one_of, parse_size};
use super::progress::Terminal;
use crate::backend::render_gpu;
use crate::bench::{self, Options, Row, chart, report};
use crate::camera::{Camera, Framing};
use crate::defaults::DataKind;
use crate::progress::Progress;
use crate::render::{GpuContext, GpuRenderer};
use crate::request::{FrameRequest, GlyphKind, Method, Preset};
use crate::scene::Scene;
use crate::select::Selection;
use crate::staging::{self, Demo, Source, Timings, field_spacing};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Folder for speed_accuracy.csv, the charts and report.md (created if missing).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Timed repetitions per configuration.
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// A scene: grid40, grid:N or a tensor file; repeatable (default grid40).
    #[arg(long = "scene")]
    pub scenes: Vec<String>,
    /// Seconds one frame may take; configurations predicted or measured slower are skipped and
    /// listed as skipped.
    #[arg(long, default_value_t = 20.0)]
    pub budget: f64,
    /// Only these methods (repeatable; default all GPU methods).
    #[arg(long = "method")]
    pub methods: Vec<Method>,
    /// Only these glyphs (repeatable; default ellipsoid and cylinder).
    #[arg(long = "glyph", value_parser = one_of::<GlyphKind>(GlyphKind::NAMES))]
    pub glyphs: Vec<GlyphKind>,
    /// Also run the grid:N demo (N³ tensors) once through the staged pipeline of `render`
    /// (load, eigen, scene, upload, first frame) and report stage times and peak memory in
    /// report.md and large_volume.csv; 0 = off. Runs first, so its peak memory is its own.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub large: usize,
    /// Also time a whole-brain DTI volume (128×128×70 float32 tensors, gzip NIfTI, written to
    /// a temporary file first): reading it and its first image as `render` shows it (the middle
    /// axial slice, DTI defaults); in report.md and brain_volume.csv; and its glyph report as
    /// a BEP016 folder (`report`): time and peak RSS in brain_report.csv.
    #[arg(long)]
    pub brain: bool,
    /// Also measure what the figure effects cost, as Sigg et al.'s Table 1 (direct vs deferred
    /// Phong, + outlines, + shadows, + both, adaptive PCF on and off, on the first scene's
    /// whole and close views of ellipsoids): effects_cost.csv and a table in report.md.
    #[arg(long)]
    pub effects: bool,
    /// Also time the grid:N demo against grid40 in the same views (whole, zoomed 4× and 8×),
    /// as `render` draws them: what a large field costs against the glyphs it shows
    /// (N = 100: a million glyphs); million_glyphs.csv and a table in report.md; 0 = off.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub million: usize,
    /// Also time the start-up as a pipeline meets it: this binary run as new processes, from
    /// start to PNG (grid40, grid:2, the baseline preset, a report of one whole-brain
    /// participant), cold and warm caches interleaved; startup.csv and a table in report.md.
    #[arg(long)]
    pub startup: bool,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// What one run through the staged pipeline (`--large N`, `--brain`) measured.
struct Large {
    /// The section's title in report.md.
    title: String,
    /// What it is, in a sentence.
    about: String,
    method: Method,
    timings: Timings,
    /// Stages that ran (a failed stage ends the run: later ones did not).
    stages_run: usize,
    error: Option<String>,
    glyphs: usize,
    peak_rss_bytes: Option<u64>,
}

impl Large {
    fn new(title: String, about: String, method: Method) -> Self {
        Self {
            title,
            about,
            method,
            timings: Timings::default(),
            stages_run: 0,
            error: None,
            glyphs: 0,
            peak_rss_bytes: None,
        }
    }
}

/// One run of grid:N through the staged pipeline; a failure is recorded, not fatal.
fn run_large(args: &BenchArgs, gpu: &GpuRenderer, method: Method, glyph: GlyphKind) -> Large {
    let n = args.large;
    let source = Source::Demo(Demo { n });
    let recipe = args
        .scene
        .recipe(Selection::default(), glyph, &DataKind::General.defaults());
    let title = format!("Large volume (grid:{n}, {} tensors)", n * n * n);
    run_staged(args, gpu, method, &source, recipe, title, String::new())
}

/// The whole-brain DTI volume, written to a temporary file, read and shown as `render` does.
fn run_brain(args: &BenchArgs, gpu: &GpuRenderer, method: Method) -> Large {
    let title = "Whole-brain DTI volume (128×128×70, float32, gzip NIfTI)".to_string();
    // Beside the outputs, removed after the run.
    let path = args
        .out
        .join(format!(".brain-{}.nii.gz", std::process::id()));
    if let Err(e) = bench::brain::write(&path) {
        std::fs::remove_file(&path).ok();
        let mut l = Large::new(title, String::new(), method);
        l.error = Some(format!("writing the volume: {e}"));
        return l;
    }
    let bytes = std::fs::metadata(&path).map_or(0, |m| m.len());
    let source = Source::File(path.clone());
    let defaults = DataKind::of(&source).defaults();
    let recipe = args
        .scene
        .recipe(Selection::default(), GlyphKind::Ellipsoid, &defaults)
        .map(|r| staging::Recipe {
            middle_slice: defaults.middle_slice,
            ..r
        });
    let about = format!(
        "The file is {:.1} MB. `load` is reading and inflating it; the first image is the \
         middle axial slice with the DTI defaults, as `tensorglyph render FILE` shows it.",
        bytes as f64 / 1e6
    );
    let run = run_staged(args, gpu, method, &source, recipe, title, about);
    std::fs::remove_file(&path).ok();
    run
}

/// The whole-brain volume's report, as `report` makes it of a BEP016 folder, with its own back
/// end (as a pipeline's report process has): brain_report.csv.
fn brain_report(args: &BenchArgs) -> Result<()> {
    let dir = args
        .out
        .join(format!(".brain-report-{}", std::process::id()));
    let (backend, _) = crate::backend::Backend::for_method(Method::Gumhold)?;
    let run = bench::brain::report(&dir, &backend);
    std::fs::remove_dir_all(&dir).ok();
    let path = args.out.join("brain_report.csv");
    report::write_atomic(&path, bench::brain::report_csv(&run).as_bytes())
        .with_context(|| format!("{}: cannot write", path.display()))?;
    if !args.scene.quiet {
        eprintln!(
            "whole-brain report: {:.0} ms, peak RSS {:.0} MiB",
            run.ms,
            run.peak_rss_bytes.unwrap_or(0) as f64 / 1048576.0
        );
    }
    Ok(())
}

/// One run through the staged pipeline of `render`; a failure is recorded, not fatal.
#[allow(clippy::too_many_arguments)]
fn run_staged(
    args: &BenchArgs,
    gpu: &GpuRenderer,
    method: Method,
    source: &Source,
    recipe: Result<staging::Recipe>,
    title: String,
    about: String,
) -> Large {
    let mut large = Large::new(title, about, method);
    let progress = Terminal::new(args.scene.quiet);
    let staged = recipe.and_then(|recipe| Ok(staging::stage(source, &recipe, &progress)?));
    match staged {
        Err(e) => large.error = Some(format!("{e:#}")),
        Ok(staged) => {
            large.timings = staged.timings;
            large.stages_run = 3;
            large.glyphs = staged.glyphs_selected;
            let (w, h) = args.size;
            let mut framing = Framing::default();
            let (centre, half) = match staged.face {
                Some(face) => {
                    framing.toward = Some(face.toward);
                    (face.centre, face.half)
                }
                None => (staged.frame_centre, staged.frame_half),
            };
            let camera = Camera::frame_box(&framing, centre, half, w, h);
            // As `render` draws it by default.
            let req = FrameRequest::preset(method, true, Preset::DEFAULT);
            let result = render_gpu(
                gpu,
                &staged.scene,
                &camera,
                &req,
                &mut large.timings,
                &progress,
            );
            match result {
                Ok(_) => large.stages_run = 5,
                Err(e) => {
                    // Upload or first frame failed; which one shows in the timings.
                    large.stages_run = if large.timings.first_frame > 0.0 {
                        4
                    } else {
                        3
                    };
                    large.error = Some(e.to_string());
                }
            }
        }
    }
    large.peak_rss_bytes = crate::mem::peak_rss_bytes();
    large
}

/// Each stage of a `--large` run: name, ms, peak RSS after it, and whether it ran (`Some(true)`),
/// failed (`Some(false)`) or was not reached (`None`).
fn large_stages(l: &Large) -> Vec<(&'static str, f64, Option<u64>, Option<bool>)> {
    l.timings
        .stages()
        .into_iter()
        .zip(l.timings.peak_rss_after)
        .enumerate()
        .map(|(k, ((stage, ms), peak))| {
            let outcome = if k < l.stages_run {
                Some(true)
            } else if k == l.stages_run && l.error.is_some() {
                Some(false)
            } else {
                None
            };
            (stage, ms, peak, outcome)
        })
        .collect()
}

fn large_csv(l: &Large) -> String {
    let mut out = String::from("stage,ms,peak_rss_bytes_after,status\n");
    for (stage, ms, peak, outcome) in large_stages(l) {
        let (ms, peak, status) = match outcome {
            Some(ran) => (
                format!("{ms:.1}"),
                peak.map_or(String::new(), |p| p.to_string()),
                if ran { "ok" } else { "failed" },
            ),
            None => (String::new(), String::new(), "not run"),
        };
        let _ = writeln!(out, "{stage},{ms},{peak},{status}");
    }
    let _ = writeln!(
        out,
        "total,{:.1},{},{}",
        l.timings.stages().iter().map(|s| s.1).sum::<f64>(),
        l.peak_rss_bytes.map_or(String::new(), |p| p.to_string()),
        if l.error.is_some() { "failed" } else { "ok" }
    );
    out
}

fn large_markdown(l: &Large) -> String {
    let mib = |b: Option<u64>| {
        b.map_or("–".to_string(), |b| {
            format!("{:.0}", b as f64 / 1048576.0)
        })
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## {}\n\nOne run of the staged pipeline of `render` ({}, ellipsoids, {} glyphs in the \
         scene). Peak RSS is the process's high-water mark (VmHWM) after each stage. {}\n",
        l.title, l.method, l.glyphs, l.about
    );
    let _ = writeln!(md, "| stage | ms | peak RSS after (MiB) |\n|---|---:|---:|");
    for (stage, ms, peak, outcome) in large_stages(l) {
        if outcome.is_some() {
            let _ = writeln!(md, "| {stage} | {ms:.0} | {} |", mib(peak));
        } else {
            let _ = writeln!(md, "| {stage} | not run | |");
        }
    }
    let _ = writeln!(md, "\nPeak RSS of the run: {} MiB.", mib(l.peak_rss_bytes));
    if let Some(e) = &l.error {
        let _ = writeln!(md, "\n**Stopped:** {e}");
    }
    md
}

pub fn run(args: BenchArgs) -> Result<()> {
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if args.budget.is_nan() || args.budget <= 0.0 {
        bail!("--budget must be a positive number of seconds");
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the output folder", args.out.display()))?;
    // First, while this process holds no device.
    let startup = args.startup.then(|| run_startup(&args)).transpose()?;
    let ctx = GpuContext::new().context("bench needs a GPU adapter (lavapipe counts)")?;
    let adapter = format!("{} ({})", ctx.adapter_name, ctx.backend);
    let gpu = GpuRenderer::new(ctx)?;
    let scenes = if args.scenes.is_empty() {
        vec!["grid40".to_string()]
    } else {
        args.scenes.clone()
    };
    let glyphs = if args.glyphs.is_empty() {
        GlyphKind::VALUES
            .iter()
            .copied()
            .filter(|k| k.caps().benched_by_default)
            .collect()
    } else {
        args.glyphs.clone()
    };
    let opts = Options {
        frames: args.frames,
        budget_s: args.budget,
        methods: if args.methods.is_empty() {
            Method::gpu_methods()
        } else {
            args.methods
                .iter()
                .copied()
                .filter(|m| m.is_gpu())
                .collect()
        },
        glyphs: glyphs.clone(),
    };
    let style = args.scene.style(&DataKind::General.defaults())?;
    let method = opts.methods.first().copied().unwrap_or(Method::Gumhold);
    let mut staged_runs = Vec::new();
    if args.large > 0 {
        staged_runs.push((
            "large_volume.csv",
            run_large(&args, &gpu, method, glyphs[0]),
        ));
    }
    if args.brain {
        staged_runs.push(("brain_volume.csv", run_brain(&args, &gpu, method)));
        brain_report(&args)?;
    }
    for (csv, l) in &staged_runs {
        let path = args.out.join(csv);
        report::write_atomic(&path, large_csv(l).as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        if let (Some(e), false) = (&l.error, args.scene.quiet) {
            eprintln!("warning: {}: {e}", l.title);
        }
    }
    let (w, h) = args.size;
    let mut rows: Vec<Row> = Vec::new();
    let mut effects_rows = None;
    for name in &scenes {
        let source = match name.parse::<Demo>() {
            Ok(d) => Source::Demo(d),
            Err(_) => Source::File(PathBuf::from(name)),
        };
        let progress = Terminal::new(args.scene.quiet);
        let field = staging::read(&source, &args.scene.read_options(), &progress)?;
        let set = staging::decompose(&field, &progress);
        let resolved = style.resolve(&set, field_spacing(&field));
        let views: Vec<(GlyphKind, Vec<bench::View>)> = glyphs
            .iter()
            .map(|&g| {
                let scene = Scene::build(&set, &resolved, g);
                (g, bench::standard_views(&scene, w, h))
            })
            .collect();
        let report_progress = |done: u64, total: u64, what: &str| {
            progress.steps(total, "");
            progress.step_to(done, &format!("{name}: {what}"));
        };
        rows.extend(bench::run(&gpu, name, &views, &opts, &report_progress));
        progress.end();
        if args.effects && effects_rows.is_none() {
            let ellipsoids = match views.iter().find(|(g, _)| *g == GlyphKind::Ellipsoid) {
                Some((_, v)) => v.clone(),
                None => bench::standard_views(
                    &Scene::build(&set, &resolved, GlyphKind::Ellipsoid),
                    w,
                    h,
                ),
            };
            let chosen: Vec<bench::View> = ellipsoids
                .into_iter()
                .filter(|v| v.name == "default" || v.name == "close")
                .collect();
            effects_rows = Some(bench::effects::run(&gpu, &chosen, args.frames)?);
        }
    }
    let million = if args.million > 0 {
        let progress = Terminal::new(args.scene.quiet);
        let demo = |name: String| -> Result<Scene> {
            let source = Source::Demo(name.parse::<Demo>().map_err(anyhow::Error::msg)?);
            let field = staging::read(&source, &args.scene.read_options(), &progress)?;
            let set = staging::decompose(&field, &progress);
            let resolved = style.resolve(&set, field_spacing(&field));
            Ok(Scene::build(&set, &resolved, GlyphKind::Ellipsoid))
        };
        let grid40 = demo("grid40".into())?;
        let large = demo(format!("grid:{}", args.million))?;
        progress.end();
        let rows = bench::million::run(&gpu, &grid40, &large, args.size, args.frames)?;
        let path = args.out.join("million_glyphs.csv");
        report::write_atomic(&path, bench::million::csv(&rows).as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        Some(bench::million::markdown(&rows, args.million))
    } else {
        None
    };
    if let Some(rows) = &effects_rows {
        let path = args.out.join("effects_cost.csv");
        report::write_atomic(&path, bench::effects::csv(rows).as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    let runs: Vec<&Large> = staged_runs.iter().map(|(_, l)| l).collect();
    let startup = startup.map(|rows| bench::startup::markdown(&rows, args.frames, &adapter));
    write_outputs(
        &args,
        &rows,
        &adapter,
        &runs,
        effects_rows.as_deref(),
        million,
        startup,
    )
}

/// `--startup`: this binary run as new processes in a temporary folder (removed after), with a
/// one-participant BIDS folder for the report; startup.csv written.
fn run_startup(args: &BenchArgs) -> Result<Vec<bench::startup::StartupRow>> {
    let exe = std::env::current_exe().context("cannot find this binary to run it")?;
    let work = args.out.join(format!(".startup-{}", std::process::id()));
    std::fs::create_dir_all(&work).with_context(|| format!("{}: cannot create", work.display()))?;
    let rows = (|| {
        let bids = bench::startup::write_bids(&work)
            .with_context(|| format!("{}: cannot write the BIDS folder", work.display()))?;
        let cases = bench::startup::cases(Some(&bids));
        let runs = work.join("runs");
        std::fs::create_dir_all(&runs)?;
        anyhow::Ok(bench::startup::run(&exe, &runs, &cases, args.frames))
    })();
    let _ = std::fs::remove_dir_all(&work);
    let rows = rows?;
    let path = args.out.join("startup.csv");
    report::write_atomic(&path, bench::startup::csv(&rows).as_bytes())
        .with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(rows)
}

fn chart_name(scene_index: usize, scene: &str, view: &str) -> String {
    let suffix = if view == "default" {
        String::new()
    } else {
        format!("_{view}")
    };
    if scene_index == 0 {
        format!("speed_accuracy{suffix}.png")
    } else {
        let safe: String = scene
            .chars()
            .map(|c| if c.is_alphanumeric() { c } else { '_' })
            .collect();
        format!("speed_accuracy{suffix}_{safe}.png")
    }
}

fn write_outputs(
    args: &BenchArgs,
    rows: &[Row],
    adapter: &str,
    staged_runs: &[&Large],
    effects: Option<&[bench::effects::EffectsRow]>,
    million: Option<String>,
    startup: Option<String>,
) -> Result<()> {
    let csv_path = args.out.join("speed_accuracy.csv");
    report::write_atomic(&csv_path, report::csv(rows).as_bytes())
        .with_context(|| format!("{}: cannot write", csv_path.display()))?;
    let mut md = String::new();
    let _ = writeln!(md, "# tensorglyph bench\n");
    let _ = writeln!(
        md,
        "Adapter: {adapter}. Image {}x{}, {} timed frames per configuration, methods interleaved \
         across repetitions. Errors against the exact f64 reference of the same glyphs.\n",
        args.size.0, args.size.1, args.frames
    );
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for (si, scene) in scenes.iter().enumerate() {
        let mut views: Vec<&str> = Vec::new();
        for r in rows.iter().filter(|r| r.scene == *scene) {
            if !views.contains(&r.view.as_str()) {
                views.push(&r.view);
            }
        }
        for view in views {
            let these: Vec<&Row> = rows
                .iter()
                .filter(|r| r.scene == *scene && r.view == view)
                .collect();
            let file = chart_name(si, scene, view);
            let title = format!("{scene}, {view} view: frame time against normal error");
            if let Err(e) = chart::speed_accuracy_png(&args.out.join(&file), &title, &these) {
                eprintln!("warning: chart {file}: {e}");
            }
            let _ = writeln!(md, "## {scene}, {view} view\n\n![{title}]({file})\n");
            let _ = writeln!(md, "{}", report::table(&these));
        }
    }
    for l in staged_runs {
        let _ = writeln!(md, "{}", large_markdown(l));
    }
    if let Some(e) = effects {
        let _ = writeln!(
            md,
            "## What the figure effects cost (Sigg et al. 2006, Table 1)\n\n{}",
            bench::effects::markdown(e)
        );
    }
    if let Some(m) = million {
        let _ = writeln!(md, "## A large field against grid40\n\n{m}");
    }
    if let Some(s) = startup {
        let _ = writeln!(md, "{s}");
    }
    let _ = writeln!(md, "## What this shows\n\n{}", report::findings(rows));
    let md_path = args.out.join("report.md");
    report::write_atomic(&md_path, md.as_bytes())
        .with_context(|| format!("{}: cannot write", md_path.display()))?;
    if !args.scene.quiet {
        eprintln!(
            "wrote {}, charts and {}",
            csv_path.display(),
            md_path.display()
        );
    }
    Ok(())
}
