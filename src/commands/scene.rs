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
use tensorglyph::select::{Plane, Selection, Slicing, parse_roi};

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

/// Which glyphs to draw (`render`, `demo`, `view`, `bench`): the same selection as the viewer's
/// panel. Every flag narrows the selection; together they keep the glyphs that pass all of them.
#[derive(Args, Debug, Clone, Default)]
pub struct SelectArgs {
    /// Keep glyphs with FA ≥ F (0 to 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub fa_min: Option<f64>,
    /// Keep glyphs with FA ≤ F (0 to 1; 1 keeps indefinite tensors with FA above 1 too).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub fa_max: Option<f64>,
    /// Every N-th lattice position along each axis (file order for unstructured data); along a
    /// slice, every N-th position in its plane.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub stride: usize,
    /// A lattice plane x=I, y=J or z=K (index from 0; structured data only). Repeatable: the
    /// union of the planes is kept.
    #[arg(long = "slice", value_name = "AXIS=INDEX")]
    pub slices: Vec<Plane>,
    /// Region of interest: keep glyphs whose centre (world coordinates) is in the box
    /// x0,y0,z0,x1,y1,z1 (bounds included).
    #[arg(long, value_name = "X0,Y0,Z0,X1,Y1,Z1", value_parser = parse_roi, allow_hyphen_values = true)]
    pub roi: Option<[f64; 6]>,
}

impl SelectArgs {
    /// The selection these flags ask for, checked as far as it can be without the data.
    pub fn selection(&self) -> Result<Selection> {
        let sel = Selection {
            fa_min: self.fa_min.unwrap_or(0.0),
            fa_max: self.fa_max.unwrap_or(1.0),
            stride: self.stride,
            slicing: if self.slices.is_empty() {
                Slicing::Whole
            } else {
                Slicing::Planes(self.slices.clone())
            },
            roi: self.roi,
        };
        sel.check()?;
        Ok(sel)
    }
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
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb.set_message(message.to_string());
    pb.enable_steady_tick(std::time::Duration::from_millis(120));
    Some(pb)
}

/// A bar counting `len` items (tensors, glyphs) on a terminal, nothing otherwise or with
/// --quiet.
pub fn counter(quiet: bool, message: &str, len: u64) -> Option<ProgressBar> {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = ProgressBar::new(len);
    pb.set_style(
        ProgressStyle::with_template(
            "{msg:>18} [{elapsed_precise}] {wide_bar} {human_pos}/{human_len} ({eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb.set_message(message.to_string());
    pb.enable_steady_tick(std::time::Duration::from_millis(200));
    Some(pb)
}

/// Load the field and derive its glyphs, with progress on a terminal.
pub fn load(source: &Source, args: &SceneArgs) -> Result<(TensorField, GlyphSet)> {
    let field = read(source, args)?;
    let set = eigen(&field, args.quiet);
    Ok((field, set))
}

/// Read the file (or make the demo field), with a spinner on a terminal.
pub fn read(source: &Source, args: &SceneArgs) -> Result<TensorField> {
    let pb = spinner(args.quiet, "reading");
    let field = source
        .load(&args.read_options())
        .map_err(anyhow::Error::new);
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    field
}

/// Eigendecompose every tensor, with a counting bar on a terminal.
pub fn eigen(field: &TensorField, quiet: bool) -> GlyphSet {
    let pb = counter(quiet, "eigendecomposition", field.len() as u64);
    let set = derive_glyphs(field, pb.as_ref());
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    set
}
