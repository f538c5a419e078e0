//! `tensorglyph view`: the interactive viewer.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use super::args::{CameraArgs, DrawArgs, EffectArgs, SceneArgs, SelectArgs, parse_size};
use crate::defaults::DataKind;
use crate::field::FieldKind;
use crate::staging::{Demo, Source};
use crate::viewer::{self, Options, state::Settings};

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// A tensor file: VTK (.vtk, .vti, .vtr, .vts, .vtu, .vtp, .pvti), NIfTI-1 (.nii, .nii.gz),
    /// NRRD (.nrrd, .nhdr), MRtrix (.mif, .mif.gz, .mih) or an FSL eigen set (PREFIX_L1.nii.gz …
    /// or PREFIX); or drop one on the window.
    pub file: Option<PathBuf>,
    /// A built-in field instead of a file: grid40 or grid:N.
    #[arg(long)]
    pub demo: Option<Demo>,
    /// Window size in points.
    #[arg(long, default_value = "1280x800", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Scripted mode: write a PNG of the whole window after --frames frames and exit.
    #[arg(long, value_name = "OUT.png")]
    pub screenshot: Option<PathBuf>,
    /// Frames to render before the scripted screenshot.
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
    /// The method, glyph and camera to start with.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// How frames are drawn, to start with.
    #[command(flatten)]
    pub draw: DrawArgs,
    /// The figure effects to start with.
    #[command(flatten)]
    pub effects: EffectArgs,
    /// Anti-aliasing of the view: 2×2 samples per pixel (1 or 2).
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=2))]
    pub ssaa: u32,
    /// Draw every frame whole, also while the camera moves (by default a scene slower than
    /// 66 ms a frame is drawn coarser while it moves, whole once it stops).
    #[arg(long)]
    pub no_draft: bool,
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
        (Some(_), Some(_)) => bail!("give either a FILE or --demo, not both"),
    };
    if args.screenshot.is_some() && source.is_none() {
        bail!("--screenshot needs a FILE or --demo");
    }
    let cam = &args.camera;
    if !cam.method.is_gpu() {
        bail!(
            "the viewer draws with the GPU methods only, not '{}'",
            cam.method
        );
    }
    if args.draw.sort_asked() {
        bail!("the viewer draws in file order: --sort (and --preset sorted) are for render");
    }
    let depth_correction = !cam.no_depth_correction;
    let defaults = source
        .as_ref()
        .map_or(DataKind::General, DataKind::of)
        .defaults();
    let [r, g, b, _] = defaults.background;
    let style = args.scene.style(&defaults)?;
    // A file of SH series is drawn as ODF glyphs, as `render` draws it.
    let kind = source
        .as_ref()
        .map_or(FieldKind::Tensors, |s| s.kind(&args.scene.read_options()));
    let name = source.as_ref().map_or(String::new(), |s| s.name());
    if let Some(refusal) = kind.viewer_refusal(&name) {
        bail!(refusal);
    }
    let (glyph, peaks) = cam.glyph_for(kind, &name)?;
    if peaks {
        bail!("--glyph peaks: the viewer does not draw sticks yet (render draws them)");
    }
    if cam.peaks {
        bail!("--peaks: the viewer does not draw peaks over ODFs yet (render draws them)");
    }
    if kind == FieldKind::Tensors && !glyph.colours(style.color) {
        bail!("--color {} applies to --glyph odf", style.color);
    }
    let settings = Settings {
        method: cam.method,
        glyph,
        depth_correction,
        style,
        background: [r, g, b].map(|c| c as f32),
        selection: args.select.selection()?,
        draw: args.draw.options(cam.method, glyph, depth_correction)?,
        underlay: args.select.underlay.clone(),
        underlay_view: args.select.underlay_view(),
        // Unscaled: the viewer scales the outline width with its own sampling.
        effects: args.effects.effects(args.size, 1)?,
        ssaa: args.ssaa,
        draft: !args.no_draft,
        odf_normalize: args.scene.odf_normalize.unwrap_or_default(),
    };
    viewer::run(Options {
        source,
        read: args.scene.read_options(),
        settings,
        framing: cam.framing()?,
        face_slice: defaults.face_on && cam.view.is_none(),
        middle_slice: defaults.middle_slice && args.select.no_slice(),
        size: args.size,
        screenshot: args.screenshot,
        frames: args.frames,
        remote: Default::default(),
        adopt_defaults: false,
        adapter_label: None,
    })?;
    Ok(())
}
