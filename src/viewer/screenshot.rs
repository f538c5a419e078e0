//! PNGs: the 3D view at any size through the very path `render` takes
//! ([`GpuRenderer::render`] then [`write_png_atomic`]), and the whole window (scripted mode).

use std::path::Path;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::image_out::write_png_atomic;
use crate::render::GpuRenderer;
use crate::request::FrameRequest;
use crate::scene::Scene;

/// Render `scene` with `camera` resized to `size`, with `ssaa`×`ssaa` samples per pixel as
/// `render --ssaa` takes them (`req` has its effects scaled for them), and write it as a PNG.
pub fn save_view(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    (size, ssaa): ((u32, u32), u32),
    path: &Path,
) -> Result<(), RenderError> {
    let n = ssaa.max(1);
    crate::frame::check_size(size.0.saturating_mul(n), size.1.saturating_mul(n))?;
    let mut cam = *camera;
    cam.width = size.0 * n;
    cam.height = size.1 * n;
    let req = FrameRequest { frames: 1, ..*req };
    let frame = gpu.render(scene, &cam, &req)?.downsample(n);
    write_png(path, frame.width, frame.height, &frame.color)
}

/// Write an egui screenshot (RGBA, sRGB) as a PNG.
pub fn save_window(image: &egui::ColorImage, path: &Path) -> Result<(), RenderError> {
    let [w, h] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    write_png(path, w as u32, h as u32, &rgba)
}

fn write_png(path: &Path, w: u32, h: u32, rgba: &[u8]) -> Result<(), RenderError> {
    write_png_atomic(path, w, h, rgba).map_err(|source| RenderError::Output {
        path: path.to_path_buf(),
        source,
    })
}

/// `WxH` → (w, h), as `render --size` takes it.
pub fn parse_size(s: &str) -> Option<(u32, u32)> {
    crate::frame::parse_size(s).ok()
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
