//! Options shared by every command that builds a scene: where the data comes from, how it is
//! read, and how glyphs are sized and coloured.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use tensorglyph::field::vtk::ReadOptions;
use tensorglyph::field::{ComponentOrder, TensorField};
use tensorglyph::glyph::{ColorScheme, GlyphSet, GlyphStyle, Normalize, Scale, derive_glyphs};
use tensorglyph::load::{Demo, Source};

#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// Tensor array to use (default: the active tensors, else the first 9- or 6-component array).
    #[arg(long)]
    pub array: Option<String>,
    /// Component order of 6-component arrays.
    #[arg(long, value_enum, default_value_t = ComponentOrder::Vtk)]
    pub order: ComponentOrder,
    /// Colour scheme.
    #[arg(long, value_enum, default_value_t = ColorScheme::Shape)]
    pub color: ColorScheme,
    /// Glyph scale: `auto` (largest radius = half the grid spacing) or a factor on |λ|.
    #[arg(long, default_value = "auto")]
    pub scale: Scale,
    /// Normalise eigenvalues before scaling.
    #[arg(long, value_enum, default_value_t = Normalize::None)]
    pub normalize: Normalize,
    /// Smallest radius as a fraction of the glyph's largest (keeps T invertible).
    #[arg(long, default_value_t = 0.01)]
    pub min_radius: f64,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
}

impl SceneArgs {
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions {
            array: self.array.clone(),
            order: self.order,
        }
    }

    pub fn style(&self) -> Result<GlyphStyle> {
        anyhow::ensure!(
            self.min_radius.is_finite() && (0.0..=1.0).contains(&self.min_radius),
            "--min-radius must be between 0 and 1, got {}",
            self.min_radius
        );
        Ok(GlyphStyle {
            color: self.color,
            scale: self.scale,
            normalize: self.normalize,
            min_radius: self.min_radius,
            ..GlyphStyle::default()
        })
    }
}

/// Exactly one of a file and `--demo`.
pub fn source(file: Option<PathBuf>, demo: Option<Demo>) -> Result<Source> {
    match (file, demo) {
        (Some(f), None) => Ok(Source::File(f)),
        (None, Some(d)) => Ok(Source::Demo(d)),
        (None, None) => anyhow::bail!("give a FILE or --demo grid40"),
        (Some(_), Some(_)) => anyhow::bail!("give either a FILE or --demo, not both"),
    }
}

/// A spinner on a terminal, nothing otherwise or with --quiet.
pub fn spinner(quiet: bool, message: &str) -> Option<ProgressBar> {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = ProgressBar::new_spinner();
    pb.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}] {wide_bar} {pos}/{len}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb.set_message(message.to_string());
    pb.enable_steady_tick(std::time::Duration::from_millis(120));
    Some(pb)
}

/// Load the field and derive its glyphs, with progress on a terminal.
pub fn load(source: &Source, args: &SceneArgs) -> Result<(TensorField, GlyphSet)> {
    let pb = spinner(args.quiet, "reading");
    let field = source
        .load(&args.read_options())
        .map_err(anyhow::Error::new)?;
    if let Some(pb) = &pb {
        pb.set_message("eigendecomposition");
        pb.set_length(field.len() as u64);
    }
    let set = derive_glyphs(&field, pb.as_ref());
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    Ok((field, set))
}
