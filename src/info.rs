//! Placeholder until the tensor branch lands.
#[derive(serde::Serialize)]
pub struct InfoReport;
pub fn info_report(
    _: &crate::field::TensorField,
    _: &crate::glyph::GlyphSet,
    _: &[usize],
) -> Result<InfoReport, String> {
    Err("todo".into())
}
pub fn human_summary(_: &InfoReport) -> String {
    String::new()
}
