//! VTK reading. (Placeholder until the reader branch lands.)
use super::{ComponentOrder, TensorField};
use crate::error::LoadError;
use std::path::Path;
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    pub array: Option<String>,
    pub order: ComponentOrder,
}
pub fn read_field(_: &Path, _: &ReadOptions) -> Result<TensorField, LoadError> {
    todo!()
}
