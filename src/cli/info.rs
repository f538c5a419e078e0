//! `tensorglyph info`: what is in a tensor file, a file of SH coefficients or of peaks.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::args::{SceneArgs, source};
use super::progress::Terminal;
use crate::field::{FieldKind, Inputs};
use crate::staging::{self, Demo};

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A tensor file or a file of SH coefficients (NIfTI, MRtrix): VTK (.vtk, .vti, .vtr, .vts, .vtu, .vtp, .pvti), NIfTI-1 (.nii, .nii.gz),
    /// NRRD (.nrrd, .nhdr), MRtrix (.mif, .mif.gz, .mih) or an FSL eigen set (PREFIX_L1.nii.gz …
    /// or PREFIX).
    pub file: Option<PathBuf>,
    /// A built-in field instead of a file: grid40 or grid:N.
    #[arg(long)]
    pub demo: Option<Demo>,
    /// One JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Also report tensor I (file order, points or cells), or SH voxel I (x fastest) with its
    /// peaks; repeatable.
    #[arg(long = "sample", value_name = "I")]
    pub samples: Vec<usize>,
    #[command(flatten)]
    pub scene: SceneArgs,
}

pub fn run(args: InfoArgs) -> Result<()> {
    let opts = args.scene.read_options();
    if let Some(path) = &args.file {
        let inputs = Inputs::file_system();
        let at = |e: String| anyhow::anyhow!("{}: {e}", crate::error::escape_path(path));
        match FieldKind::of_file(&inputs, path, &opts) {
            FieldKind::Series => {
                let field = crate::field::read_sh_field_from(&inputs, path, &opts)?;
                let report = crate::sh_info::report(&field, &args.samples).map_err(at)?;
                return print(&report, args.json, crate::sh_info::human_summary);
            }
            FieldKind::Peaks => {
                let field = crate::field::read_peak_field_from(&inputs, path, &opts)?;
                let report = crate::peaks_info::report(&field, &args.samples).map_err(at)?;
                return print(&report, args.json, crate::peaks_info::human_summary);
            }
            FieldKind::Tensors => {}
        }
    }
    let src = source(args.file, args.demo)?;
    let progress = Terminal::new(args.scene.quiet);
    let field = staging::read(&src, &args.scene.read_options(), &progress)?;
    let set = staging::decompose(&field, &progress);
    let report = crate::info::info_report(&field, &set, &args.samples).map_err(|e| {
        anyhow::anyhow!(
            "{}: {e}",
            crate::error::escape_path(std::path::Path::new(&src.name()))
        )
    })?;
    print(&report, args.json, crate::info::human_summary)
}

/// A report on stdout: one JSON object, or its text.
fn print<R: serde::Serialize>(report: &R, json: bool, text: fn(&R) -> String) -> Result<()> {
    super::stdout::print(&if json {
        format!("{}\n", serde_json::to_string(report)?)
    } else {
        text(report)
    })?;
    Ok(())
}
