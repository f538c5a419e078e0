//! Radii and colour.
pub enum ColorScheme {}
pub struct GlyphStyle;
pub enum Normalize {}
pub struct ResolvedStyle;
pub enum Scale {}
