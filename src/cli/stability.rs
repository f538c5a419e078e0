//! `tensorglyph stability`: the adversarial suite; see `tensorglyph::stability`.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use super::args::one_of;
use crate::bench::report::write_atomic;
use crate::render::{GpuContext, GpuRenderer};
use crate::request::{GlyphKind, Method};
use crate::stability::{self, Options, Status, report};

#[derive(Args, Debug)]
pub struct StabilityArgs {
    /// Folder for stability.md, stability.csv (or .jsonl) and the charts (created if missing).
    #[arg(long, default_value = "stability-out")]
    pub out: PathBuf,
    /// Also write stability.jsonl and print the rows as JSON lines on stdout.
    #[arg(long)]
    pub json: bool,
    /// Only the quick regression subset.
    #[arg(long)]
    pub quick: bool,
    /// Only these methods (repeatable; default every GPU method).
    #[arg(long = "method")]
    pub methods: Vec<Method>,
    /// Only the cases whose key starts with PREFIX (repeatable, e.g. `--case 2-anisotropy`;
    /// default every case).
    #[arg(long = "case", value_name = "PREFIX")]
    pub cases: Vec<String>,
    /// Only these glyphs (repeatable; default every glyph).
    #[arg(long = "glyph", value_parser = one_of::<GlyphKind>(GlyphKind::NAMES))]
    pub glyphs: Vec<GlyphKind>,
}

pub fn run(args: StabilityArgs) -> Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the output folder", args.out.display()))?;
    let ctx = GpuContext::new().context("stability needs a GPU adapter (lavapipe counts)")?;
    let adapter = format!("{} ({})", ctx.adapter_name, ctx.backend);
    let gpu = GpuRenderer::new(ctx)?;
    let mut opts = Options {
        quick: args.quick,
        cases: args.cases.clone(),
        ..Options::default()
    };
    if let Some(m) = args.methods.iter().find(|m| **m == Method::Reference) {
        bail!("--method {m}: the suite measures the GPU methods against the reference");
    }
    if !args.methods.is_empty() {
        opts.methods = args.methods.clone();
    }
    if !args.glyphs.is_empty() {
        opts.glyphs = args.glyphs.clone();
    }
    let rows = stability::run(Some(&gpu), &opts, |msg| eprintln!("{msg}"));
    let charts = report::charts(&rows, &args.out);
    let md = report::markdown(&rows, &charts, &adapter);
    let write = |name: &str, text: &str| {
        let p = args.out.join(name);
        write_atomic(&p, text.as_bytes()).with_context(|| format!("{}: cannot write", p.display()))
    };
    write("stability.md", &md)?;
    write("stability.csv", &report::csv(&rows))?;
    if args.json {
        let j = report::json_lines(&rows);
        write("stability.jsonl", &j)?;
        super::stdout::print(&j)?;
    }
    let fails = rows.iter().filter(|r| r.status == Status::Fail).count();
    let degraded = rows.iter().filter(|r| r.status == Status::Degraded).count();
    eprintln!(
        "{} rows: {} pass, {degraded} degraded, {fails} fail; report in {}",
        rows.len(),
        rows.len() - fails - degraded,
        args.out.display()
    );
    Ok(())
}
