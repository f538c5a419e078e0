//! `tensorglyph view`: the interactive viewer.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::render::parse_size;
use super::scene::{SceneArgs, SelectArgs};
use tensorglyph::load::{Demo, Source};
use tensorglyph::render::{GlyphKind, Method};
use tensorglyph::viewer::{self, Options, state::Settings};

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// A VTK file (.vtk, .vti, .vtr, .vts, .vtu, .vtp, .pvti); or drop one on the window.
    pub file: Option<PathBuf>,
    /// A built-in field instead of a file: grid40 or grid:N.
    #[arg(long)]
    pub demo: Option<Demo>,
    /// Rendering method to start with.
    #[arg(long, default_value = "gumhold")]
    pub method: Method,
    #[arg(long, value_enum, default_value_t = GlyphKind::Ellipsoid)]
    pub glyph: GlyphKind,
    /// Start without depth correction.
    #[arg(long)]
    pub no_depth_correction: bool,
    /// Start with an orthographic projection.
    #[arg(long)]
    pub ortho: bool,
    /// Window size in points.
    #[arg(long, default_value = "1280x800", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Scripted mode: write a PNG of the whole window after --frames frames and exit.
    #[arg(long, value_name = "OUT.png")]
    pub screenshot: Option<PathBuf>,
    /// Frames to render before the scripted screenshot.
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The panel's starting selection.
    #[command(flatten)]
    pub select: SelectArgs,
}

pub fn run(args: ViewArgs) -> Result<()> {
    let source = match (args.file, args.demo) {
        (Some(f), None) => Some(Source::File(f)),
        (None, Some(d)) => Some(Source::Demo(d)),
        (None, None) => None,
        (Some(_), Some(_)) => anyhow::bail!("give either a FILE or --demo, not both"),
    };
    if args.screenshot.is_some() && source.is_none() {
        anyhow::bail!("--screenshot needs a FILE or --demo");
    }
    if !args.method.is_gpu() {
        anyhow::bail!(
            "the viewer draws with the GPU methods only, not '{}'",
            args.method
        );
    }
    let settings = Settings {
        method: args.method,
        glyph: args.glyph,
        depth_correction: !args.no_depth_correction,
        style: args.scene.style()?,
        selection: args.select.selection()?,
        ..Settings::default()
    };
    viewer::run(Options {
        source,
        read: args.scene.read_options(),
        settings,
        ortho: args.ortho,
        size: args.size,
        screenshot: args.screenshot,
        frames: args.frames,
    })
}
