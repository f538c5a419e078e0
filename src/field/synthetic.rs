//! Built-in demo fields. (Placeholder until the tensor branch lands.)
use super::TensorField;
pub fn grid(_: usize) -> TensorField {
    todo!()
}
pub fn write_legacy_vtk(_: &TensorField, _: &std::path::Path) -> std::io::Result<()> {
    todo!()
}
