//! tensorglyph: ray-cast glyphs for 3D symmetric tensor fields.
//!
//! Data flows one way:
//! file → [`field::TensorField`] → [`glyph::GlyphSet`] → [`render::gpu_data::GpuGlyph`] instances → image.
//! The exact f64 CPU ray caster in [`reference`] renders the very same instances and is the
//! accuracy truth for every GPU method.

pub mod bench;
pub mod camera;
pub mod error;
pub mod field;
pub mod glyph;
pub mod image_out;
pub mod info;
pub mod load;
pub mod mem;
pub mod metrics;
pub mod reference;
pub mod render;
pub mod scene;
pub mod select;
pub mod stability;
pub mod tensor;
#[cfg(test)]
pub(crate) mod test_vectors;
pub mod viewer;

pub use error::{LoadError, RenderError};
