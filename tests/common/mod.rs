//! Helpers shared by the integration tests.
#![allow(dead_code)]

use tensorglyph::render::{GpuContext, GpuRenderer};

/// The GPU renderer, or `None` (skip) when no adapter exists. Under CI a missing adapter fails:
/// a GPU test must never be skipped silently there.
pub fn gpu() -> Option<GpuRenderer> {
    match GpuContext::new() {
        Ok(ctx) => Some(GpuRenderer::new(ctx).expect("pipelines build on this adapter")),
        Err(e) => {
            if std::env::var_os("CI").is_some() {
                panic!("CI is set but no GPU adapter is available: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}
