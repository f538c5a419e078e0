//! `tensorglyph report`: the arguments of the two forms and the output lines; the reports are
//! [`crate::report`]'s.
//!
//! - `report FILE... -o OUT_DIR`: one report per file (of tensors, of SH series: ODFs, or of
//!   peaks: sticks).
//! - `report BIDS_DIR OUT_DIR participant [--participant-label L …]`: one per participant of a
//!   BIDS derivatives folder of BEP016 tensor maps, ODF maps and peaks maps, as a BIDS App is
//!   called.
//! - `report BIDS_DIR OUT_DIR group [--participant-label L …]`: the group page over what the
//!   participant level wrote ([`crate::report::group`]).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use super::args::one_of;
use super::progress::Terminal;
use crate::backend::Backend;
use crate::report::{self, Job, Options, Outcome, Plan};
use crate::request::Method;
use crate::scene::odf::OdfNormalize;
use crate::sh::ShBasis;
use crate::shape::odf::OdfColoring;

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Tensor files, files of SH series or of peaks (with -o), or BIDS_DIR OUT_DIR LEVEL: a BIDS
    /// derivatives folder holding BEP016 tensor maps, ODF maps (_param-fod_, _param-sh_) and
    /// peaks maps (_param-peaks_) in sub-LABEL/[ses-LABEL/]dwi/, where the reports go, and the
    /// analysis level (participant: one page per participant; group: one page over the
    /// participants' reports, outliers flagged).
    #[arg(
        required = true,
        value_name = "FILE... | BIDS_DIR OUT_DIR participant|group"
    )]
    pub paths: Vec<PathBuf>,
    /// Where the reports of the files named go: NAME.html and NAME/figures/ per file.
    #[arg(short, long = "output-dir", value_name = "OUT_DIR")]
    pub output_dir: Option<PathBuf>,
    /// The participants to report on (with or without sub-); all when not given.
    #[arg(long = "participant-label", value_name = "LABEL", num_args = 1..)]
    pub participant_label: Vec<String>,
    /// The overview tiles' side, in pixels (128 to 1024). At 256 a whole-brain slice (128
    /// voxels across) gets 2 px per voxel; 480 gives it 3.
    #[arg(long = "tile-size", value_name = "PX", default_value_t = report::inset::DEFAULT_TILE,
          value_parser = parse_tile)]
    pub tile_size: u32,
    /// The region each figure's zoomed inset shows: the voxel I,J,K (lattice indices) it is
    /// centred on and its side in voxels (2 to 128), e.g. 64,64,35:48; each row's inset is
    /// the slice through that voxel. Default: the 48-voxel square of the row's middle slice
    /// where FA is highest (an ODF map's: where the fibre density, the l = 0 term, is).
    #[arg(long = "zoom-region", value_name = "I,J,K:SIZE")]
    pub zoom_region: Option<report::inset::ZoomRegion>,
    /// The basis of the files of SH series (tournier07, descoteaux07, descoteaux07-legacy),
    /// as `render --sh-basis`; default: each file's writer's (MRtrix: tournier07, others:
    /// descoteaux07-legacy). Which files are SH is their volume count's to say (15, 28, 45, …;
    /// a 6-volume file stays a tensor map).
    #[arg(long, value_parser = one_of::<ShBasis>(ShBasis::NAMES))]
    pub sh_basis: Option<ShBasis>,
    /// How each voxel's ODF is scaled in the ODF maps' figures, as `render --odf-normalize`:
    /// max (each to its own largest value), minmax (its range to the full radius, as mrview),
    /// none (sizes comparable across voxels).
    #[arg(long, default_value = "max", value_parser = one_of::<OdfNormalize>(OdfNormalize::NAMES))]
    pub odf_normalize: OdfNormalize,
    /// How the ODF maps' glyphs are coloured, as `render --color` colours a file of SH series:
    /// dec (each point by its direction from the centre, the default) or amplitude (its radius
    /// through viridis, 0 to the full radius, as DIPY's odf_slicer). Tensor maps stay DEC.
    #[arg(long, default_value = "dec", value_parser = parse_odf_color)]
    pub color: OdfColoring,
    /// Leave out of the pages what differs from run to run (times, memory): two runs over the
    /// same data on the same machine write the same bytes, so a cohort run in parallel can be
    /// checked against a serial run.
    #[arg(long)]
    pub reproducible: bool,
}

/// `--color` of the ODF maps: the colourings `render` offers a file of SH series that read a
/// series (`solid` would hide what the figure is for).
pub fn parse_odf_color(s: &str) -> Result<OdfColoring, String> {
    match s {
        "dec" => Ok(OdfColoring::Direction),
        "amplitude" => Ok(OdfColoring::Amplitude),
        _ => Err(format!(
            "'{}': the report colours ODFs by dec or amplitude",
            crate::error::escape_for_error(s)
        )),
    }
}

fn parse_tile(s: &str) -> Result<u32, String> {
    let px: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number of pixels"))?;
    report::inset::check_tile(px).map_err(|e| e.to_string())
}

/// The figures' options the arguments ask for.
pub fn options(args: &ReportArgs) -> Options {
    Options {
        tile: args.tile_size,
        zoom: args.zoom_region,
        sh_basis: args.sh_basis,
        odf_normalize: args.odf_normalize,
        odf_color: args.color,
        reproducible: args.reproducible,
    }
}

/// The job and the output folder the arguments ask for, and whether it is the group level.
pub fn job(args: ReportArgs) -> Result<(Job, PathBuf, bool)> {
    if let Some(out) = args.output_dir {
        if !args.participant_label.is_empty() {
            bail!("--participant-label applies to the BIDS form (BIDS_DIR OUT_DIR participant)");
        }
        return Ok((Job::Files(args.paths), out, false));
    }
    let [dir, out, level] = <[PathBuf; 3]>::try_from(args.paths).map_err(|paths| {
        anyhow::anyhow!(
            "report takes FILE... -o OUT_DIR, or BIDS_DIR OUT_DIR participant|group (got {} \
             paths and no -o)",
            paths.len()
        )
    })?;
    let group = match level.to_str() {
        Some("participant") => false,
        Some("group") => true,
        _ => bail!(
            "analysis level {}: participant (one report per participant) or group (one page \
             over them)",
            crate::error::escape_path(&level)
        ),
    };
    Ok((
        Job::Bids {
            dir,
            labels: args.participant_label,
        },
        out,
        group,
    ))
}

/// Run the reports: `Ok(true)` when every one was written; each failed one is named on one
/// stderr line.
pub fn run(args: ReportArgs) -> Result<bool> {
    let options = options(&args);
    let (job, out, group) = job(args)?;
    if group {
        let Job::Bids { dir, labels } = &job else {
            unreachable!("the group level is the BIDS form's")
        };
        // No image is read or drawn: no back end.
        let o = report::group::run(dir, &out, labels)?;
        println!(
            "{}: {} participants, {} maps; {} without a report, {} maps flagged",
            crate::error::escape_path(&o.page),
            o.participants,
            o.maps,
            o.without_report.len(),
            o.flagged.len()
        );
        return Ok(true);
    }
    let plan = Plan::new(&job)?.with_options(options);
    let progress = Terminal::new(true);
    // One back end for every image: the GPU's pipelines are built once.
    let (backend, fell_back) = Backend::for_method(Method::Gumhold)?;
    if fell_back {
        eprintln!("notice: no GPU adapter found; rendering with the CPU reference instead");
    }
    let Outcome { failed, .. } = plan.run(&out, &backend, &progress)?;
    for f in &failed {
        eprintln!("error: {}: {}", f.name, f.error);
    }
    Ok(failed.is_empty())
}
