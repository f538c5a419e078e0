//! The GPU back end. A long-lived [`GpuRenderer`] (device, layouts, one drawer cache and the
//! frame loop), the per-scene [`SceneBuffers`] made by upload, the [`targets`], and one folder
//! or file per method, each recording its own passes through the [`drawer::Drawer`] trait.

pub mod ao_volume;
pub mod bricks;
pub mod context;
pub mod drawer;
pub mod effects;
pub mod gpu_data;
pub mod gumhold;
pub mod mesh;
pub mod pipeline;
pub mod pipeline_cache;
pub mod query;
pub mod renderer;
pub mod scene_buffers;
pub mod shaders;
pub mod sigg;
pub mod strip;
pub mod targets;
pub mod underlay;

pub use context::GpuContext;
pub use renderer::GpuRenderer;
pub use scene_buffers::SceneBuffers;
pub use targets::TargetViews;
