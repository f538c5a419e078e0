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
    /// With effects and aux: per pixel how lit it is by the key light (1 lit, 0 in shadow; 1
    /// without shadows), its outline state (1 on an outline) and its open fraction of the sky
    /// (ambient occlusion; 1 without it), for the accuracy check.
    pub effects: Option<Vec<[f32; 3]>>,
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

    /// A frame rendered `n`×`n` times larger, brought to its size (`--ssaa`): each pixel's
    /// colour is the box average of its n×n samples, weighted by alpha (so a transparent
    /// background adds no colour to the edges) and rounded; its id and aux are its centre
    /// sample's (the sample at (n/2, n/2): the pixel centre exactly for odd n), so picking and
    /// the metrics see single rays. Timings and counts are kept.
    pub fn downsample(self, n: u32) -> Frame {
        if n <= 1 {
            return self;
        }
        let (w, h) = (self.width / n, self.height / n);
        let (n, sw) = (n as usize, self.width as usize);
        let mut color = Vec::with_capacity(w as usize * h as usize * 4);
        let mut ids = Vec::with_capacity(w as usize * h as usize);
        let mut aux = self
            .aux
            .as_ref()
            .map(|_| Vec::with_capacity(ids.capacity()));
        let mut effects = self
            .effects
            .as_ref()
            .map(|_| Vec::with_capacity(ids.capacity()));
        for y in 0..h as usize {
            for x in 0..w as usize {
                let mut sum = [0u64; 4];
                for sy in 0..n {
                    let row = (y * n + sy) * sw;
                    for sx in 0..n {
                        let p = &self.color[4 * (row + x * n + sx)..][..4];
                        let a = u64::from(p[3]);
                        for c in 0..3 {
                            sum[c] += u64::from(p[c]) * a;
                        }
                        sum[3] += a;
                    }
                }
                let count = (n * n) as u64;
                for c in 0..3 {
                    let avg = (sum[c] + sum[3] / 2).checked_div(sum[3]).unwrap_or(0);
                    color.push(avg as u8);
                }
                color.push(((sum[3] + count / 2) / count) as u8);
                let centre = (y * n + n / 2) * sw + x * n + n / 2;
                ids.push(self.ids[centre]);
                if let (Some(out), Some(src)) = (&mut aux, &self.aux) {
                    out.push(src[centre]);
                }
                if let (Some(out), Some(src)) = (&mut effects, &self.effects) {
                    out.push(src[centre]);
                }
            }
        }
        Frame {
            width: w,
            height: h,
            color,
            ids,
            aux,
            effects,
            frame_ms: self.frame_ms,
            fragments: self.fragments,
            vertices: self.vertices,
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_colour_by_alpha_and_keeps_the_centre_id() {
        // 3x3 samples of one pixel: a glyph (id 7, red, opaque) in 4 samples, the rest a
        // transparent white background; the centre sample is the glyph's.
        let mut f = Frame {
            width: 3,
            height: 3,
            color: [255u8, 255, 255, 0].repeat(9),
            ids: vec![0; 9],
            aux: Some(vec![[0.0; 4]; 9]),
            frame_ms: vec![1.5],
            ..Frame::default()
        };
        for i in [1, 3, 4, 5] {
            f.color[4 * i..4 * i + 4].copy_from_slice(&[200, 10, 20, 255]);
            f.ids[i] = 7;
            f.aux.as_mut().unwrap()[i] = [0.0, 0.0, 1.0, 0.5];
        }
        let d = f.downsample(3);
        assert_eq!((d.width, d.height), (1, 1));
        // No white bleeds in: the colour is the glyph's, the alpha its coverage 4/9.
        assert_eq!(
            d.color,
            vec![200, 10, 20, (4.0f64 * 255.0 / 9.0).round() as u8]
        );
        assert_eq!(d.ids, vec![7]);
        assert_eq!(d.aux.unwrap(), vec![[0.0, 0.0, 1.0, 0.5]]);
        assert_eq!(d.frame_ms, vec![1.5]);
        // Opaque samples average plainly.
        let g = Frame {
            width: 2,
            height: 1,
            color: vec![0, 0, 0, 255, 255, 255, 255, 255],
            ids: vec![1, 2],
            ..Frame::default()
        };
        let d = Frame {
            width: 2,
            height: 2,
            color: [g.color.clone(), g.color.clone()].concat(),
            ids: vec![1, 2, 3, 4],
            ..Frame::default()
        }
        .downsample(2);
        assert_eq!(d.color, vec![128, 128, 128, 255]);
        assert_eq!(d.ids, vec![4], "even n: the sample at (n/2, n/2)");
    }
}
