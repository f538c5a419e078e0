//! `tensorglyph bench`: every method × glyph × depth setting on the same scenes, timed in one
//! run, each compared with the exact reference; CSV, charts and a Markdown report.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use super::args::{SceneArgs, one_of, parse_size};
use super::progress::Terminal;
use tensorglyph::backend::render_gpu;
use tensorglyph::bench::{self, Options, Row, chart, report};
use tensorglyph::camera::{Camera, Framing};
use tensorglyph::defaults::DataKind;
use tensorglyph::progress::Progress;
use tensorglyph::render::{GpuContext, GpuRenderer};
use tensorglyph::request::{FrameRequest, GlyphKind, Method, Preset};
use tensorglyph::scene::Scene;
use tensorglyph::select::Selection;
use tensorglyph::staging::{self, Demo, Source, Timings, field_spacing};

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
    /// A scene: grid40, grid:N or a VTK file; repeatable (default grid40).
    #[arg(long = "scene")]
    pub scenes: Vec<String>,
    /// Seconds one frame may take; configurations predicted or measured slower are skipped and
    /// listed as skipped.
    #[arg(long, default_value_t = 20.0)]
    pub budget: f64,
    /// Only these methods (repeatable; default all GPU methods).
    #[arg(long = "method")]
    pub methods: Vec<Method>,
    /// Only these glyphs (repeatable; default all).
    #[arg(long = "glyph", value_parser = one_of::<GlyphKind>(GlyphKind::NAMES))]
    pub glyphs: Vec<GlyphKind>,
    /// Also run the grid:N demo (N³ tensors) once through the staged pipeline of `render`
    /// (load, eigen, scene, upload, first frame) and report stage times and peak memory in
    /// report.md and large_volume.csv; 0 = off. Runs first, so its peak memory is its own.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub large: usize,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// What `--large N` measured.
struct Large {
    n: usize,
    method: Method,
    timings: Timings,
    /// Stages that ran (a failed stage ends the run: later ones did not).
    stages_run: usize,
    error: Option<String>,
    glyphs: usize,
    peak_rss_bytes: Option<u64>,
}

/// One run of grid:N through the staged pipeline; a failure is recorded, not fatal.
fn run_large(args: &BenchArgs, gpu: &GpuRenderer, method: Method, glyph: GlyphKind) -> Large {
    let mut large = Large {
        n: args.large,
        method,
        timings: Timings::default(),
        stages_run: 0,
        error: None,
        glyphs: 0,
        peak_rss_bytes: None,
    };
    let source = Source::Demo(Demo { n: args.large });
    let progress = Terminal::new(args.scene.quiet);
    let staged = args
        .scene
        .recipe(Selection::default(), glyph, &DataKind::General.defaults())
        .and_then(|recipe| Ok(staging::stage(&source, &recipe, &progress)?));
    match staged {
        Err(e) => large.error = Some(format!("{e:#}")),
        Ok(staged) => {
            large.timings = staged.timings;
            large.stages_run = 3;
            large.glyphs = staged.glyphs_selected;
            let (w, h) = args.size;
            let camera = Camera::frame(
                &Framing::default(),
                staged.frame_centre,
                staged.frame_radius,
                w,
                h,
            );
            // As `render` draws it by default.
            let req = FrameRequest::preset(method, glyph, true, Preset::DEFAULT);
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
    large.peak_rss_bytes = tensorglyph::mem::peak_rss_bytes();
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
        "## Large volume (grid:{}, {} tensors)\n\nOne run of the staged pipeline of `render` \
         ({}, ellipsoids, {} glyphs in the scene). Peak RSS is the process's high-water mark \
         (VmHWM) after each stage.\n",
        l.n,
        l.n * l.n * l.n,
        l.method,
        l.glyphs
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
    let ctx = GpuContext::new().context("bench needs a GPU adapter (lavapipe counts)")?;
    let adapter = format!("{} ({})", ctx.adapter_name, ctx.backend);
    let gpu = GpuRenderer::new(ctx)?;
    let scenes = if args.scenes.is_empty() {
        vec!["grid40".to_string()]
    } else {
        args.scenes.clone()
    };
    let glyphs = if args.glyphs.is_empty() {
        vec![GlyphKind::Ellipsoid, GlyphKind::Cylinder]
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
    let large = (args.large > 0).then(|| {
        let method = opts.methods.first().copied().unwrap_or(Method::Gumhold);
        run_large(&args, &gpu, method, glyphs[0])
    });
    if let Some(l) = &large {
        let path = args.out.join("large_volume.csv");
        report::write_atomic(&path, large_csv(l).as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        if let (Some(e), false) = (&l.error, args.scene.quiet) {
            eprintln!("warning: large volume grid:{}: {e}", l.n);
        }
    }
    let (w, h) = args.size;
    let mut rows: Vec<Row> = Vec::new();
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
    }
    write_outputs(&args, &rows, &adapter, large.as_ref())
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
    large: Option<&Large>,
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
    if let Some(l) = large {
        let _ = writeln!(md, "{}", large_markdown(l));
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
