//! Figures: the 3D view at any size through the very path `render` takes
//! ([`GpuRenderer::render`]'s async core, the legend, then [`write_png_atomic`] on the
//! desktop or an image in the page), and the whole window (scripted mode).

use std::path::Path;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::glyph::style::ResolvedStyle;
use crate::image_out::write_png_atomic;
use crate::legend::raster::{Caption, burn};
use crate::render::GpuRenderer;
use crate::request::FrameRequest;
use crate::scene::Scene;

/// A figure of the view as `render` writes one: `size` pixels of `ssaa`×`ssaa` samples (`req`
/// has its effects scaled for them and its background's alpha), and the legend `render
/// --legend` burns in, built from the request and camera of the figure.
pub struct Figure<'a> {
    pub size: (u32, u32),
    pub ssaa: u32,
    /// The style and clamped count the scene was built with, and whether the world is
    /// anatomical (R/A/S axes), for the legend.
    pub legend: Option<(&'a ResolvedStyle, usize, bool)>,
}

/// A rendered figure: RGBA8 pixels, row-major from the top left.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Image {
    /// The image as PNG bytes, as `render` writes them.
    pub fn png(&self) -> Result<Vec<u8>, RenderError> {
        let mut out = Vec::new();
        crate::image_out::encode_png(&mut out, self.width, self.height, &self.rgba, None)
            .map_err(|e| RenderError::Gpu(format!("encoding the PNG: {e}")))?;
        Ok(out)
    }
}

/// Render `scene` with `camera` resized to the figure's samples, downsample, and burn the
/// legend in (its caption made from the figure's own request and camera). Nothing blocks: the
/// desktop runs it to its end at once, the browser on its event loop.
pub async fn render_figure(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    figure: &Figure<'_>,
) -> Result<Image, RenderError> {
    let (cam, req) = figure_view(camera, req, figure)?;
    let frame = gpu.render_async(scene, &cam, &req).await?;
    Ok(finish(frame, scene, &cam, &req, figure))
}

/// The camera at the figure's samples and the one-frame request.
fn figure_view(
    camera: &Camera,
    req: &FrameRequest,
    figure: &Figure<'_>,
) -> Result<(Camera, FrameRequest), RenderError> {
    let ((w, h), n) = (figure.size, figure.ssaa.max(1));
    crate::frame::check_size(w.saturating_mul(n), h.saturating_mul(n))?;
    let mut cam = *camera;
    cam.width = w * n;
    cam.height = h * n;
    Ok((cam, FrameRequest { frames: 1, ..*req }))
}

fn finish(
    frame: crate::frame::Frame,
    scene: &Scene,
    cam: &Camera,
    req: &FrameRequest,
    figure: &Figure<'_>,
) -> Image {
    let (w, h) = figure.size;
    let mut frame = frame.downsample(figure.ssaa.max(1));
    if let Some((style, clamped, anatomical)) = figure.legend {
        let caption = Caption::of_frame(style, clamped, scene, req, cam, anatomical);
        burn(&mut frame.color, w, h, &frame.ids, &caption, req.background);
    }
    Image {
        width: frame.width,
        height: frame.height,
        rgba: frame.color,
    }
}

/// [`render_figure`], written as a PNG to `path`.
#[cfg(not(target_arch = "wasm32"))]
pub fn save_view(
    gpu: &GpuRenderer,
    scene: &Scene,
    camera: &Camera,
    req: &FrameRequest,
    figure: &Figure<'_>,
    path: &Path,
) -> Result<(), RenderError> {
    let image = pollster::block_on(render_figure(gpu, scene, camera, req, figure))?;
    write_png(path, image.width, image.height, &image.rgba)
}

/// Write an egui screenshot (RGBA, sRGB) as a PNG.
pub fn save_window(image: &egui::ColorImage, path: &Path) -> Result<(), RenderError> {
    let [w, h] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    write_png(path, w as u32, h as u32, &rgba)
}

pub(crate) fn write_png(path: &Path, w: u32, h: u32, rgba: &[u8]) -> Result<(), RenderError> {
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
