//! PNGs: the 3D view at any size through the very path `render` takes
//! ([`GpuRenderer::render`] then [`write_png_atomic`]), and the whole window (scripted mode).

use std::path::Path;

use anyhow::{Context, Result};

use crate::camera::Camera;
use crate::image_out::write_png_atomic;
use crate::render::{FrameRequest, GpuRenderer};
use crate::scene::Scene;

/// Render `scene` with `camera` resized to `width` × `height` and write it as a PNG.
pub fn save_view(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    size: (u32, u32),
    path: &Path,
) -> Result<()> {
    let mut cam = *camera;
    cam.width = size.0;
    cam.height = size.1;
    let req = FrameRequest { frames: 1, ..*req };
    let frame = gpu.render(scene, &cam, &req)?;
    write_png_atomic(path, frame.width, frame.height, &frame.color)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Write an egui screenshot (RGBA, sRGB) as a PNG.
pub fn save_window(image: &egui::ColorImage, path: &Path) -> Result<()> {
    let [w, h] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    write_png_atomic(path, w as u32, h as u32, &rgba)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// `WxH` → (w, h), as `render --size` takes it.
pub fn parse_size(s: &str) -> Option<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X'])?;
    let (w, h) = (w.trim().parse().ok()?, h.trim().parse().ok()?);
    (w > 0 && h > 0).then_some((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_like_render() {
        assert_eq!(parse_size("1920x1080"), Some((1920, 1080)));
        assert_eq!(parse_size(" 64 X 48 "), Some((64, 48)));
        assert_eq!(parse_size("0x10"), None);
        assert_eq!(parse_size("big"), None);
    }
}
