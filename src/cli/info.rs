//! `tensorglyph info`: what is in a tensor file, or in a file of SH coefficients.

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
    if let Some(path) = &args.file
        && FieldKind::of_file(&Inputs::file_system(), path, &opts) == FieldKind::Series
    {
        let field = crate::field::read_sh_field(path, &opts)?;
        let report = crate::sh_info::report(&field, &args.samples)
            .map_err(|e| anyhow::anyhow!("{}: {e}", crate::error::escape_path(path)))?;
        super::stdout::print(&if args.json {
            format!("{}\n", serde_json::to_string(&report)?)
        } else {
            crate::sh_info::human_summary(&report)
        })?;
        return Ok(());
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
    if args.json {
        super::stdout::print(&format!("{}\n", serde_json::to_string(&report)?))?;
    } else {
        super::stdout::print(&crate::info::human_summary(&report))?;
    }
    Ok(())
}
