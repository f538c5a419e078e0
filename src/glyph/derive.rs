//! TensorField → GlyphSet.
use super::GlyphSet;
use crate::field::TensorField;

pub fn derive_glyphs(_field: &TensorField, _progress: Option<&indicatif::ProgressBar>) -> GlyphSet {
    todo!()
}
