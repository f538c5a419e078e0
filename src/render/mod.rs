//! GPU renderers. CPU preparation (scene, instances) lives in [`crate::scene`]; this module
//! uploads and draws.

pub mod context;
pub mod gpu_data;
pub mod gumhold;
pub mod gumhold_math;
pub mod headless;
pub mod mesh;
pub mod method;
pub mod pipeline;
pub mod prepass;
pub mod query;
pub mod shaders;
pub mod sigg;
pub mod sigg_math;
pub mod targets;

pub use context::GpuContext;
pub use headless::{Frame, FrameRequest, GpuRenderer, SceneBuffers, TargetViews};
pub use method::{GlyphKind, Method};
pub use pipeline::{Proxy, ProxyShape};
pub use prepass::DEFAULT_SPLAT;
