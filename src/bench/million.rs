//! What a large field costs against grid40's 64,000 glyphs in the same views: the `grid:N`
//! demo (N = 100: a million glyphs) and grid40 framed alike (as `render` frames them), whole
//! and zoomed, drawn as `render` draws them by default (Gumhold ellipsoids, the prepass and
//! splats; by bricks where the frustum leaves out enough of them,
//! [`crate::render::gumhold::occlusion`]), the scenes
//! interleaved across repetitions. The rows are ratios of one run, as every bench row.

use std::fmt::Write as _;

use crate::camera::{Camera, Framing};
use crate::error::RenderError;
use crate::render::GpuRenderer;
use crate::request::{FrameRequest, Method, Preset};
use crate::scene::Scene;

/// The zooms of the views: the whole field, then two views the frustum cuts.
pub const ZOOMS: [f64; 3] = [1.0, 4.0, 8.0];

/// One view of both fields.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MillionRow {
    pub zoom: f64,
    /// Median steady frame of grid40 and of the large field.
    pub grid40_ms: f64,
    pub large_ms: f64,
    /// `large_ms` over `grid40_ms`.
    pub ratio: f64,
    /// Glyphs that show in at least one pixel.
    pub grid40_shown: usize,
    pub large_shown: usize,
    /// Whether the large field's frame was drawn by bricks.
    pub by_bricks: bool,
}

/// Time `large` (the grid:N demo) against `grid40` at `size`, `frames` repetitions each view;
/// both scenes as `render` builds them.
pub fn run(
    gpu: &GpuRenderer,
    grid40: &Scene,
    large: &Scene,
    size: (u32, u32),
    frames: u32,
) -> Result<Vec<MillionRow>, RenderError> {
    let scenes = [grid40, large];
    let buffers = [gpu.upload(scenes[0])?, gpu.upload(scenes[1])?];
    let req = FrameRequest {
        frames: 2,
        ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
    };
    let mut rows = Vec::new();
    for zoom in ZOOMS {
        let framing = Framing {
            zoom,
            ..Framing::default()
        };
        let cameras: Vec<Camera> = scenes
            .iter()
            .map(|s| Camera::frame_box(&framing, s.centre, s.half, size.0, size.1))
            .collect();
        let mut times = [Vec::new(), Vec::new()];
        let mut shown = [0, 0];
        for _ in 0..frames.max(1) {
            for k in 0..2 {
                let frame = gpu.render_uploaded(&buffers[k], &cameras[k], &req)?;
                times[k].extend(super::steady_ms(&frame));
                shown[k] = frame.visible_glyphs();
            }
        }
        let [grid40_ms, large_ms] = times.map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        });
        rows.push(MillionRow {
            zoom,
            grid40_ms,
            large_ms,
            ratio: large_ms / grid40_ms,
            grid40_shown: shown[0],
            large_shown: shown[1],
            by_bricks: buffers[1].culls_bricks(&cameras[1]),
        });
    }
    Ok(rows)
}

pub fn csv(rows: &[MillionRow]) -> String {
    let mut s = String::from("zoom,grid40_ms,large_ms,ratio,grid40_shown,large_shown,by_bricks\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{:.3},{:.3},{:.3},{},{},{}",
            r.zoom, r.grid40_ms, r.large_ms, r.ratio, r.grid40_shown, r.large_shown, r.by_bricks
        );
    }
    s
}

/// The report's table, for `grid:n`.
pub fn markdown(rows: &[MillionRow], n: usize) -> String {
    let mut s = format!(
        "grid:{n} ({} glyphs) against grid40 (64,000), framed alike, `render`'s default path \
         (ms per steady frame, medians):\n\n\
         | zoom | grid40 ms | grid:{n} ms | ratio | glyphs shown (grid40, grid:{n}) | grid:{n} drawn |\n\
         |---:|---:|---:|---:|---:|---|\n",
        n * n * n
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.1} | {:.2} | {}, {} | {} |",
            r.zoom,
            r.grid40_ms,
            r.large_ms,
            r.ratio,
            r.grid40_shown,
            r.large_shown,
            if r.by_bricks {
                "by bricks"
            } else {
                "in file order"
            }
        );
    }
    s
}
