//! `tensorglyph report`: per participant of a BIDS derivatives folder, the glyph figures of its
//! BEP016 tensor maps and one self-contained HTML page, as a BIDS App is called
//! (`bids_dir output_dir participant [--participant-label L …]`).
//!
//! This is the report's first form: for each map the middle axial, coronal and sagittal
//! slices (glyphs over the FA underlay, DEC colours), and a page stating the input, its layout
//! and frame with their reasons, the counts and FA range `info` reports, the back end and the
//! version. A participant is written whole or not at all; a bad one is named on stderr and the
//! others go on (exit status 1).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use base64::Engine as _;
use clap::Args;

use super::progress::Terminal;
use super::render::{FrameArgs, Rendered, render_frame};
use crate::backend::Backend;
use crate::bids::{self, Map, Participant};
use crate::field::ReadOptions;
use crate::image_out::{encode_png, write_atomic};
use crate::progress::Progress;
use crate::request::Method;
use crate::staging::{self, Source};

/// Each figure's side, in pixels.
const FIGURE_SIDE: u32 = 480;

/// The three views: the name in figure files, `--view`, and the lattice axis sliced.
const VIEWS: [(&str, &str, &str); 3] = [
    ("axial", "axial", "z"),
    ("coronal", "coronal", "y"),
    ("sagittal", "sagittal", "x"),
];

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A BIDS derivatives folder holding BEP016 tensor maps (sub-LABEL/[ses-LABEL/]dwi/).
    pub bids_dir: PathBuf,
    /// Where the reports go: sub-LABEL.html and sub-LABEL/figures/ per participant.
    pub output_dir: PathBuf,
    /// The analysis level: participant (one page per participant).
    #[arg(value_parser = ["participant"])]
    pub analysis_level: String,
    /// The participants to report on (with or without sub-); all when not given.
    #[arg(long = "participant-label", value_name = "LABEL", num_args = 1..)]
    pub participant_label: Vec<String>,
}

/// Run the report: `Ok(true)` when every participant's report was written.
pub fn run(args: ReportArgs) -> Result<bool> {
    let participants = bids::participants(&args.bids_dir, &args.participant_label)?;
    if !args.output_dir.is_dir() {
        std::fs::create_dir_all(&args.output_dir)
            .with_context(|| format!("{}: cannot create", args.output_dir.display()))?;
    }
    write_dataset_description(&args.output_dir)?;
    let progress = Terminal::new(true);
    // One back end for every image: the GPU's pipelines are built once.
    let (backend, fell_back) = Backend::for_method(Method::Gumhold)?;
    if fell_back {
        eprintln!("notice: no GPU adapter found; rendering with the CPU reference instead");
    }
    let mut all = true;
    for p in &participants {
        if let Err(e) = participant(p, &args.output_dir, &backend, &progress) {
            eprintln!("error: sub-{}: {e:#}", p.label);
            all = false;
        }
    }
    Ok(all)
}

/// What `bids_dir`'s derivatives need: the output is a derivatives dataset of its own.
fn write_dataset_description(out: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(&serde_json::json!({
        "Name": "tensorglyph glyph reports",
        "BIDSVersion": "1.10.0",
        "DatasetType": "derivative",
        "GeneratedBy": [{"Name": "tensorglyph", "Version": env!("CARGO_PKG_VERSION")}],
    }))?;
    let path = out.join("dataset_description.json");
    write_atomic(&path, &[], |w| {
        use std::io::Write as _;
        writeln!(w, "{text}")
    })
    .with_context(|| format!("{}: cannot write", path.display()))
}

/// One figure, in memory until the participant's report is whole.
struct Figure {
    file: String,
    png: Vec<u8>,
}

fn participant(
    p: &Participant,
    out: &Path,
    backend: &Backend,
    progress: &dyn Progress,
) -> Result<()> {
    if p.maps.is_empty() {
        bail!(
            "no BEP016 tensor map (sub-{0}/[ses-*/]dwi/*_model-DTI[_param-tensor]_dwimap.nii[.gz])",
            p.label
        );
    }
    let mut page = String::new();
    let mut figures = Vec::new();
    let mut inputs: Vec<PathBuf> = Vec::new();
    for map in &p.maps {
        section(map, backend, progress, &mut page, &mut figures, &mut inputs)?;
    }
    let folder = out.join(format!("sub-{}", p.label)).join("figures");
    std::fs::create_dir_all(&folder)
        .with_context(|| format!("{}: cannot create", folder.display()))?;
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    for f in &figures {
        let path = folder.join(&f.file);
        write_atomic(&path, &inputs, |w| {
            use std::io::Write as _;
            w.write_all(&f.png)
        })
        .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    let html = out.join(format!("sub-{}.html", p.label));
    let text = html_page(&p.label, &page, backend);
    write_atomic(&html, &inputs, |w| {
        use std::io::Write as _;
        w.write_all(text.as_bytes())
    })
    .with_context(|| format!("{}: cannot write", html.display()))?;
    Ok(())
}

/// One map's part of the page, and its figures.
fn section(
    map: &Map,
    backend: &Backend,
    progress: &dyn Progress,
    page: &mut String,
    figures: &mut Vec<Figure>,
    inputs: &mut Vec<PathBuf>,
) -> Result<()> {
    let src = Source::File(map.path.clone());
    let field = staging::read(&src, &ReadOptions::default(), progress)?;
    let set = staging::decompose(&field, progress);
    let info = crate::info::info_report(&field, &set, &[]).map_err(anyhow::Error::msg)?;
    let dims = field
        .lattice_dims()
        .context("a BEP016 map is a lattice, this one is not")?;
    let name = map
        .path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.trim_end_matches(".gz").trim_end_matches(".nii");
    let _ = writeln!(page, "<h2>{}</h2>", esc(&name));
    let _ = writeln!(page, "<table>");
    let row = |page: &mut String, k: &str, v: &str| {
        let _ = writeln!(page, "<tr><th>{k}</th><td>{v}</td></tr>");
    };
    row(page, "input", &esc(&map.path.display().to_string()));
    if let Some(s) = &map.session {
        row(page, "session", &esc(s));
    }
    if let Some(l) = &info.layout {
        let why = crate::info::why_text(l.why);
        row(page, "layout", &esc(&format!("{} ({why})", l.order)));
    }
    if let Some(f) = &info.frame {
        let axes = info
            .bep016_sidecar
            .as_ref()
            .and_then(|s| s.reference_axes.as_deref())
            .map_or(String::new(), |a| {
                format!(", ReferenceAxes {a} from the BEP016 sidecar")
            });
        row(
            page,
            "frame",
            &esc(&format!(
                "tensors in {} axes{axes}; world {} from {}",
                f.tensor_frame.name(),
                f.world,
                f.source
            )),
        );
    }
    for n in &info.notes {
        row(page, "note", &esc(n));
    }
    row(
        page,
        "tensors",
        &format!(
            "{} ({}×{}×{}): {} valid; skipped {} NaN, {} Inf, {} zero",
            info.tensors,
            dims[0],
            dims[1],
            dims[2],
            info.valid,
            info.skipped.nan,
            info.skipped.inf,
            info.skipped.zero
        ),
    );
    row(
        page,
        "FA",
        &format!(
            "min {:.4}, mean {:.4}, max {:.4}",
            info.fa.min, info.fa.mean, info.fa.max
        ),
    );
    drop(field);
    drop(set);
    let _ = writeln!(page, "</table>");
    let _ = writeln!(page, "<div class=\"row\">");
    for (view, preset, axis) in VIEWS {
        let k = match axis {
            "x" => 0,
            "y" => 1,
            _ => 2,
        };
        let size = format!("{FIGURE_SIDE}x{FIGURE_SIDE}");
        let slice = format!("{axis}={}", dims[k] / 2);
        let args: FrameArgs = super::parse_options([
            "--slice",
            &slice,
            "--view",
            preset,
            "--underlay",
            "fa",
            "--size",
            &size,
            "--quiet",
        ])
        .map_err(anyhow::Error::msg)?;
        let Rendered {
            width,
            height,
            color,
            report,
            read,
            ..
        } = render_frame(&src, &args, |_| Ok(backend), progress)?;
        inputs.extend(read);
        let mut png = Vec::new();
        encode_png(&mut png, width, height, &color, None)?;
        let file = format!("{stem}_{view}.png");
        let report = serde_json::to_value(&report)?;
        let _ = writeln!(
            page,
            "<figure><img alt=\"{view}\" src=\"data:image/png;base64,{}\"><figcaption>{view}, \
             slice {slice}: {} glyphs drawn</figcaption></figure>",
            base64::engine::general_purpose::STANDARD.encode(&png),
            report["glyphs_drawn"]
        );
        figures.push(Figure { file, png });
    }
    let _ = writeln!(page, "</div>");
    Ok(())
}

fn html_page(label: &str, body: &str, backend: &Backend) -> String {
    let backend = match backend {
        Backend::Reference => "the exact CPU reference (no GPU adapter)".to_string(),
        Backend::Gpu(r) => format!("the GPU ({})", r.adapter_name()),
    };
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>sub-{label}: tensorglyph report</title>\n<style>body{{font-family:sans-serif;\
         margin:2em;max-width:1600px}}th{{text-align:left;padding-right:1em}}\
         .row{{display:flex;gap:1em;flex-wrap:wrap}}figure{{margin:0}}\
         img{{background:#000}}</style></head><body>\n<h1>sub-{label}</h1>\n\
         <p>tensorglyph {}; rendered with {}.</p>\n{body}</body></html>\n",
        env!("CARGO_PKG_VERSION"),
        esc(&backend),
        label = esc(label),
    )
}

/// `s` as HTML text.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
