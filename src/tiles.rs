//! Images larger than one render: the image is cut into tiles, each rendered by a camera cropped
//! to it ([`Camera::cropped`]: the whole image's projection, so every pixel casts the ray it
//! casts in one piece), brought to the output size on its own and copied into the output frame.
//!
//! Tiles are aligned to the supersampling factor N, so the N×N samples of an output pixel all
//! come from one tile and the box filter sees what it sees in one piece. Only the output frame
//! and one tile are held at a time, so memory follows the output size, not the number of
//! samples. Each tile also renders a margin beyond its own pixels on the sides it shares with
//! other tiles and crops it away: a screen-space pass that reads a pixel's neighbours (up to
//! the margin away) sees the same neighbours at a seam as anywhere else.

use web_time::Instant;

use crate::backend::{Backend, StageFailed, upload_timed};
use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::{Frame, MAX_PIXELS};
use crate::progress::{Progress, Silent};
use crate::request::FrameRequest;
use crate::scene::Scene;
use crate::staging::{Timings, ms};

/// Output pixels a tile renders beyond each side it shares with another tile.
pub const DEFAULT_MARGIN: u32 = 4;

/// Samples one tile renders at most (4096²): its colour, id and depth targets and their
/// read-back stay near 200 MB, and splats' per-pixel keys fit a 128 MiB storage binding.
pub const TILE_SAMPLES: u64 = 1 << 24;

/// How an image is cut: its samples per pixel and what one tile may hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tiling {
    /// N: each output pixel is the box average of N×N samples (`--ssaa`).
    pub ssaa: u32,
    /// Longest side of one render, in samples (the adapter's texture limit).
    pub max_side: u32,
    /// Samples in one tile.
    pub max_samples: u64,
    /// Output pixels rendered beyond each inner side of a tile and cropped away.
    pub margin: u32,
}

/// One tile: output pixel rectangles `[x, y, width, height]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tile {
    /// The pixels this tile fills in the output.
    pub core: [u32; 4],
    /// The pixels it renders: the core and its margins, within the image.
    pub rendered: [u32; 4],
}

impl Tiling {
    /// What one render of `backend` holds, at `ssaa` samples per pixel side: the GPU's targets
    /// are bounded by the adapter's texture side, the reference's only by the pixel budget.
    pub fn new(backend: &Backend, ssaa: u32) -> Self {
        Self {
            ssaa: ssaa.max(1),
            max_side: backend
                .gpu()
                .map_or(u32::MAX, |g| g.ctx.limits.max_texture_dimension_2d),
            max_samples: TILE_SAMPLES,
            margin: DEFAULT_MARGIN,
        }
    }

    /// Whether a `width`×`height` output renders in one piece: its samples within the side
    /// limit and [`MAX_PIXELS`].
    pub fn fits_whole(&self, width: u32, height: u32) -> bool {
        let n = u64::from(self.ssaa);
        let (w, h) = (u64::from(width) * n, u64::from(height) * n);
        let side = u64::from(self.max_side);
        w <= side && h <= side && w * h <= MAX_PIXELS
    }

    /// The tiles of a `width`×`height` output, row by row: as few as the limits allow, of
    /// balanced sizes, their cores covering every pixel once.
    pub fn plan(&self, width: u32, height: u32) -> Result<Vec<Tile>, RenderError> {
        let bad = |reason: String| RenderError::BadSize {
            width,
            height,
            reason,
        };
        if width == 0 || height == 0 {
            return Err(bad("an image has at least one pixel".into()));
        }
        let n = u64::from(self.ssaa.max(1));
        // Limits in output pixels.
        let side = u64::from(self.max_side) / n;
        let square = self.max_samples.isqrt() / n;
        let m = u64::from(self.margin);
        let split = |len: u64, limit: u64| -> Result<(u64, u64, u64), RenderError> {
            if len <= limit {
                return Ok((1, len, len));
            }
            if limit <= 2 * m {
                return Err(bad(format!(
                    "a tile of at most {limit} pixels a side (at {n}×{n} samples per pixel) \
                     cannot hold a margin of {m} pixels on both sides"
                )));
            }
            let count = len.div_ceil(limit - 2 * m);
            let core = len.div_ceil(count);
            Ok((count, core, core + 2 * m))
        };
        let (rows, core_h, tall) = split(u64::from(height), side.min(square))?;
        let wide = (self.max_samples / (n * n * tall)).min(side);
        let (cols, core_w, _) = split(u64::from(width), wide)?;
        let (w, h) = (u64::from(width), u64::from(height));
        let mut tiles = Vec::with_capacity((rows * cols) as usize);
        for r in 0..rows {
            let y0 = r * core_h;
            let y1 = (y0 + core_h).min(h);
            for c in 0..cols {
                let x0 = c * core_w;
                let x1 = (x0 + core_w).min(w);
                if x0 >= x1 || y0 >= y1 {
                    continue;
                }
                let (rx0, ry0) = (x0.saturating_sub(m), y0.saturating_sub(m));
                let (rx1, ry1) = ((x1 + m).min(w), (y1 + m).min(h));
                // Every value is at most width or height, which are u32.
                let rect = |x: u64, y: u64, xe: u64, ye: u64| {
                    [x, y, xe - x, ye - y].map(|v| u32::try_from(v).unwrap_or(u32::MAX))
                };
                tiles.push(Tile {
                    core: rect(x0, y0, x1, y1),
                    rendered: rect(rx0, ry0, rx1, ry1),
                });
            }
        }
        Ok(tiles)
    }

    /// The output frame of `camera` (its samples: the output size times `ssaa` on each side),
    /// rendered tile by tile through `render`, which gets each tile's cropped camera and
    /// returns that tile's samples. Colour is box-filtered per tile, ids, aux and effects are the centre
    /// samples', as [`Frame::downsample`] does for a whole frame. Frame times add up over the
    /// tiles (frame k is the k-th frame of every tile), as do the shader invocation counts.
    pub fn render_with<E: From<RenderError>>(
        &self,
        camera: &Camera,
        mut render: impl FnMut(&Camera) -> Result<Frame, E>,
    ) -> Result<Frame, E> {
        let n = self.ssaa.max(1);
        let full = camera.full();
        if !full.width.is_multiple_of(n) || !full.height.is_multiple_of(n) {
            return Err(RenderError::BadSize {
                width: full.width,
                height: full.height,
                reason: format!("the samples are not a whole number of {n}×{n} pixels"),
            }
            .into());
        }
        let (width, height) = (full.width / n, full.height / n);
        let tiles = self.plan(width, height)?;
        let (w, pixels) = (width as usize, width as usize * height as usize);
        let mut out = Frame {
            width,
            height,
            color: vec![0; 4 * pixels],
            ids: vec![0; pixels],
            ..Frame::default()
        };
        for (k, tile) in tiles.iter().enumerate() {
            let [rx, ry, rw, rh] = tile.rendered;
            let part = render(&full.cropped(rx * n, ry * n, rw * n, rh * n))?.downsample(n);
            if (part.width, part.height) != (rw, rh) {
                return Err(RenderError::BadSize {
                    width: part.width,
                    height: part.height,
                    reason: format!("tile {k} came back at this size, not {rw}x{rh}"),
                }
                .into());
            }
            let [cx, cy, cw, ch] = tile.core.map(|v| v as usize);
            let (sx, sy) = (cx - rx as usize, cy - ry as usize);
            // (first index in the output, first index in the tile) of each row of the core.
            let rows = (0..ch).map(|row| ((cy + row) * w + cx, (sy + row) * rw as usize + sx));
            for (dst, src) in rows.clone() {
                out.color[4 * dst..4 * (dst + cw)]
                    .copy_from_slice(&part.color[4 * src..4 * (src + cw)]);
                out.ids[dst..dst + cw].copy_from_slice(&part.ids[src..src + cw]);
            }
            if let Some(a) = &part.aux {
                let aux = out.aux.get_or_insert_with(|| vec![[0.0; 4]; pixels]);
                for (dst, src) in rows.clone() {
                    aux[dst..dst + cw].copy_from_slice(&a[src..src + cw]);
                }
            }
            if let Some(e) = &part.effects {
                let effects = out
                    .effects
                    .get_or_insert_with(|| vec![[1.0, 0.0, 1.0]; pixels]);
                for (dst, src) in rows {
                    effects[dst..dst + cw].copy_from_slice(&e[src..src + cw]);
                }
            }
            if k == 0 {
                out.frame_ms = part.frame_ms;
                out.fragments = part.fragments;
                out.vertices = part.vertices;
            } else {
                for (t, p) in out.frame_ms.iter_mut().zip(&part.frame_ms) {
                    *t += p;
                }
                out.fragments = out.fragments.zip(part.fragments).map(|(a, b)| a + b);
                out.vertices = out.vertices.zip(part.vertices).map(|(a, b)| a + b);
            }
        }
        Ok(out)
    }

    /// The output frame of `camera` (sized in samples, as for [`Self::render_with`]) on
    /// `backend`: in one piece and then downsampled when it fits, else in tiles (the GPU uploads
    /// the scene once for all of them). Tiled, `timings.first_frame` is every tile's frames.
    pub fn render(
        &self,
        backend: &Backend,
        scene: &Scene,
        camera: &Camera,
        req: &FrameRequest,
        timings: &mut Timings,
        progress: &dyn Progress,
    ) -> Result<Frame, StageFailed> {
        let n = self.ssaa.max(1);
        let full = camera.full();
        if self.fits_whole(full.width / n, full.height / n) {
            return Ok(backend
                .render(scene, &full, req, timings, progress)?
                .downsample(n));
        }
        let failed = |timings: &Timings, error| StageFailed {
            stage: "tiles",
            ran: timings.describe(),
            error,
        };
        let count = self
            .plan(full.width / n, full.height / n)
            .map_err(|e| failed(timings, e))?
            .len();
        let result = match backend {
            Backend::Gpu(gpu) => {
                let buffers =
                    upload_timed(gpu, scene, timings, progress).map_err(|e| failed(timings, e))?;
                progress.begin("tiles", Some(count as u64));
                let t = Instant::now();
                let frame = self.render_with(&full, |cam| {
                    let f = gpu.render_uploaded(&buffers, cam, req);
                    progress.advance(1);
                    f
                });
                timings.first_frame = ms(t);
                frame
            }
            Backend::Reference => {
                progress.begin("reference tiles", Some(count as u64));
                let t = Instant::now();
                let frame = self.render_with(&full, |cam| {
                    let f = backend.render(scene, cam, req, &mut Timings::default(), &Silent);
                    progress.advance(1);
                    f.map_err(|e| e.error)
                });
                timings.first_frame = ms(t);
                frame
            }
        };
        timings.peak_rss_after[4] = crate::mem::peak_rss_bytes();
        progress.end();
        result.map_err(|e| failed(timings, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiling(ssaa: u32, max_side: u32, max_samples: u64, margin: u32) -> Tiling {
        Tiling {
            ssaa,
            max_side,
            max_samples,
            margin,
        }
    }

    /// Every output pixel lies in exactly one core; every render stays within the limits, is
    /// its core grown by the margin (clipped to the image) and is aligned to whole pixels.
    fn check(t: &Tiling, w: u32, h: u32) -> usize {
        let tiles = t.plan(w, h).unwrap();
        let mut hits = vec![0u8; (w * h) as usize];
        for tile in &tiles {
            let [x, y, cw, ch] = tile.core;
            for j in y..y + ch {
                for i in x..x + cw {
                    hits[(j * w + i) as usize] += 1;
                }
            }
            let [rx, ry, rw, rh] = tile.rendered;
            let n = t.ssaa;
            assert!(rw * n <= t.max_side && rh * n <= t.max_side, "{tile:?}");
            assert!(
                u64::from(rw * n) * u64::from(rh * n) <= t.max_samples,
                "{tile:?}"
            );
            assert_eq!(rx, x.saturating_sub(t.margin));
            assert_eq!(ry, y.saturating_sub(t.margin));
            assert_eq!(rx + rw, (x + cw + t.margin).min(w));
            assert_eq!(ry + rh, (y + ch + t.margin).min(h));
        }
        assert!(hits.iter().all(|&c| c == 1));
        tiles.len()
    }

    #[test]
    fn tiles_cover_the_image_once_within_the_limits() {
        assert_eq!(check(&tiling(1, 64, 64 * 64, 4), 200, 150), 4 * 3);
        assert_eq!(check(&tiling(3, 64, 64 * 64, 2), 200, 150), 12 * 9);
        assert_eq!(check(&tiling(2, 1000, 1 << 30, 0), 500, 500), 1);
        // A strip: one row as tall as the image, tiles as wide as the budget then allows.
        assert_eq!(check(&tiling(8, 16384, 1 << 24, 4), 2100, 10), 2);
        // The pixel budget, not the side, limits: 100² samples.
        assert_eq!(check(&tiling(1, 4096, 100 * 100, 1), 300, 300), 4 * 3);
    }

    #[test]
    fn a_margin_the_tiles_cannot_hold_is_an_error() {
        let e = tiling(4, 64, 1 << 20, 8).plan(100, 100).unwrap_err();
        assert!(e.to_string().contains("margin of 8 pixels"), "{e}");
        assert!(tiling(1, 64, 1 << 20, 8).plan(0, 10).is_err());
    }
}
