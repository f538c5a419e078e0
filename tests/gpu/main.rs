//! The GPU back end against independent truth, on lavapipe where no GPU exists: every method's
//! frames against the exact f64 reference (`tensorglyph::reference`), the faster paths against
//! the plain one, and the CPU twins' predictions against what the GPU did. Bounds are stated as
//! data or beside each check, with their reason. tests/README.md is the map.
//!
//! Without an adapter the tests skip with a message, unless `CI` is set: then they fail.

#[path = "../common/cli.rs"]
mod cli;
#[path = "../common/data.rs"]
mod data;

mod check;
mod double_f32;
mod scenes;

mod effects;
mod extremes;
mod figures;
mod gumhold;
mod kinds;
mod less_work;
mod mesh;
mod odf;
mod peaks;
mod prepass;
mod published_bounds;
mod ray_casters;
mod sigg;
mod stability;
mod superquadrics;
mod tiles;
mod underlay;
