//! What every back end returns and reads, below both: the rendered [`Frame`] (colour, ids,
//! normals and depth for the metrics) and the [`Lighting`] the GPU shaders and the exact
//! reference shade with.

/// A rendered frame, as the GPU or the reference produced it.
#[derive(Debug, Clone, Default)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, row-major from the top-left.
    pub color: Vec<u8>,
    /// Instance index + 1 of the front-most glyph, 0 for background.
    pub ids: Vec<u32>,
    /// View-space normal and the view z of the hit relative to its glyph's centre, per pixel
    /// (where `ids` is non-zero).
    pub aux: Option<Vec<[f32; 4]>>,
    /// Wall-clock time of each frame, submit to completion.
    pub frame_ms: Vec<f64>,
    /// Fragment-shader invocations of one frame (pipeline statistics), where available.
    pub fragments: Option<u64>,
    /// Vertex-shader invocations of one frame.
    pub vertices: Option<u64>,
}

impl Frame {
    pub fn median_ms(&self) -> f64 {
        let mut t = self.frame_ms.clone();
        t.sort_by(f64::total_cmp);
        if t.is_empty() { 0.0 } else { t[t.len() / 2] }
    }

    pub fn covered_pixels(&self) -> usize {
        self.ids.iter().filter(|&&i| i != 0).count()
    }

    /// Glyphs that show in at least one pixel.
    pub fn visible_glyphs(&self) -> usize {
        let mut ids: Vec<u32> = self.ids.iter().copied().filter(|&i| i != 0).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }
}

/// Blinn-Phong headlight parameters: one set for every method and the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.3,
            shininess: 24.0,
        }
    }
}

/// The largest image any back end renders, in pixels (8192²): the exact reference keeps 24
/// bytes per pixel (colour, id, normal and depth) and the GPU read-back as much, so 1.6 GB.
/// The GPU's own texture limit may be lower and is checked where the targets are made.
pub const MAX_PIXELS: u64 = 1 << 26;

/// Refuse sizes no back end should allocate (zero sides, more than [`MAX_PIXELS`]).
pub fn check_size(width: u32, height: u32) -> Result<(), crate::error::RenderError> {
    let pixels = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || pixels > MAX_PIXELS {
        return Err(crate::error::RenderError::BadSize {
            width,
            height,
            reason: format!("an image has 1 to {MAX_PIXELS} pixels (8192×8192)"),
        });
    }
    Ok(())
}

/// `WxH` (e.g. `1024x768`, both sides ≥ 1) → (width, height): image and window sizes.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size '{s}' is not WxH (e.g. 1024x768)"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 {
        return Err(format!("size '{s}' has a zero side"));
    }
    Ok((w, h))
}
