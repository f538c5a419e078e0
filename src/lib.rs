//! tensorglyph: ray-cast glyphs for 3D symmetric tensor fields.
//!
//! Data flows one way:
//!
//! ```text
//! file ─read─▶ TensorField ─eigen─▶ GlyphSet ─select, style─▶ Scene ─▶ Backend ─▶ Frame
//!  (field)       (field)              (glyph)   (staging)     (scene)   GPU renderer (render)
//!                                                                       or exact reference
//! ```
//!
//! [`staging`] runs the first stages for every front end; a [`Backend`] renders a [`Scene`] seen
//! by a [`Camera`] as a [`FrameRequest`] asks (a method with the options it takes, see
//! [`MethodConfig`]); [`compare`] measures a GPU [`Frame`] against the exact f64 reference of the
//! very same instances. The crate root re-exports what a program needs for that; the modules
//! hold the rest.
//!
//! Cargo features, all on by default: `viewer` (the interactive viewer, `viewer`: eframe, egui,
//! winit), `bench` (`bench` and `stability`: plotters) and `cli` (the command line and the
//! binary: clap, indicatif; it takes the other two). With `default-features = false` the crate
//! is the core above: the readers, fields, glyphs, scenes, both renderers, PNG output and
//! reports.
//!
//! ```no_run
//! use tensorglyph::{Backend, Camera, Demo, FrameRequest, Framing, Method, Preset, Recipe,
//!                   Silent, Source, stage};
//! let staged = stage(&Source::Demo(Demo { n: 40 }), &Recipe::default(), &Silent)?;
//! let camera = Camera::frame(&Framing::default(), staged.frame_centre, staged.frame_radius, 800, 600);
//! let (backend, _fell_back) = Backend::for_method(Method::Gumhold)?;
//! let req = FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT);
//! let frame = backend.render(&staged.scene, &camera, &req, &mut Default::default(), &Silent)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// deny, not forbid: render::pipeline_cache holds the library's one audited unsafe call.
#![deny(unsafe_code)]

// Below everything: shared vocabulary.
pub mod camera;
pub mod effects;
pub mod error;
pub mod frame;
pub mod geodesic;
mod names;
pub mod percentile;
pub mod progress;
pub mod request;
pub mod shape;

// The flow: file → field → glyphs → scene.
pub mod defaults;
pub mod field;
pub mod glyph;
pub mod scene;
pub mod select;
pub mod sh;
pub mod staging;
pub mod tensor;

// Back ends and what judges them. `backend` and `tiles` wait on the GPU, which only the
// desktop can: the web build draws through `render`'s async core.
#[cfg(not(target_arch = "wasm32"))]
pub mod backend;
pub mod metrics;
pub mod reference;
pub mod render;
#[cfg(not(target_arch = "wasm32"))]
pub mod tiles;
pub mod twin;

// What the front ends share.
pub mod bids;
pub mod files;
pub mod image_out;
pub mod info;
pub mod legend;
pub mod mem;
pub mod peaks_info;
#[cfg(not(target_arch = "wasm32"))]
pub mod report;
pub mod sh_info;

// Front ends in the library; `cli` is the command line (arguments, dispatch and output
// formatting), which the binary and the Python package's console script run. The viewer is
// the one front end of the web build (web/); the others are the desktop's.
#[cfg(all(feature = "bench", not(target_arch = "wasm32")))]
pub mod bench;
#[cfg(all(feature = "cli", not(target_arch = "wasm32")))]
pub mod cli;
#[cfg(all(feature = "bench", not(target_arch = "wasm32")))]
pub mod stability;
#[cfg(feature = "viewer")]
pub mod viewer;

#[cfg(test)]
pub(crate) mod test_vectors;

#[cfg(not(target_arch = "wasm32"))]
pub use backend::Backend;
pub use camera::{Camera, Framing, ViewPreset};
pub use error::{LoadError, RenderError};
pub use field::{ComponentOrder, ReadOptions, TensorField, TensorFrame, read_field};
pub use frame::{Frame, Lighting};
pub use glyph::{ColorScheme, GlyphSet, GlyphStyle, Normalize, Scale, SizeBy};
pub use image_out::write_png_atomic;
pub use metrics::{Accuracy, compare, diff_image};
pub use progress::{Progress, Silent};
pub use reference::ReferenceScene;
pub use render::{GpuContext, GpuRenderer};
pub use request::{DrawOptions, FrameRequest, Method, MethodConfig, Preset, Proxy, ProxyShape};
pub use scene::Scene;
pub use select::{Plane, Selection, Slicing};
pub use shape::{GlyphKind, Shape};
pub use staging::{
    Built, Demo, Recipe, Source, StageError, Staged, Timings, build, decompose, field_spacing,
    read, stage,
};
