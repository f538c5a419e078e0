//! Radii and colour. (Placeholder until the tensor branch lands.)
use super::{Glyph, GlyphSet};
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorScheme {
    Shape,
}
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Normalize {
    None,
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    Auto,
}
impl std::str::FromStr for Scale {
    type Err = String;
    fn from_str(_: &str) -> Result<Self, String> {
        Ok(Scale::Auto)
    }
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlyphStyle {
    pub color: ColorScheme,
    pub scale: Scale,
    pub normalize: Normalize,
    pub min_radius: f64,
}
impl Default for GlyphStyle {
    fn default() -> Self {
        Self {
            color: ColorScheme::Shape,
            scale: Scale::Auto,
            normalize: Normalize::None,
            min_radius: 0.01,
        }
    }
}
pub struct ResolvedStyle;
impl GlyphStyle {
    pub fn resolve(&self, _: &GlyphSet, _: f64) -> ResolvedStyle {
        ResolvedStyle
    }
}
impl ResolvedStyle {
    pub fn radii(&self, _: &Glyph) -> [f32; 3] {
        [1.0; 3]
    }
    pub fn color(&self, _: &Glyph) -> [u8; 4] {
        [255; 4]
    }
}
pub fn median_nn_distance(_: &[[f64; 3]]) -> f64 {
    1.0
}
