//! A legend burned into an RGBA image (`render --legend`): the colour scheme's key, lines of
//! text (the scale in effect, clamped glyphs) and an axis triad, on an opaque panel in the
//! image corner that covers the fewest glyph pixels (the id buffer says which).
//!
//! Text is drawn with `ab_glyph` (the rasteriser egui uses) in the Ubuntu Light face egui
//! bundles, so the binary carries no font of its own and needs none installed.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use glam::DVec3;

use crate::camera::Camera;
use crate::glyph::ResolvedStyle;
use crate::legend::{Legend, axis_labels, screen_axes, short_number};
use crate::request::FrameRequest;
use crate::scene::Scene;
use crate::tensor::shape::{ShapeClass, classify};

/// What a legend shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Caption {
    pub legend: Legend,
    /// Lines of text under the key.
    pub lines: Vec<String>,
    /// The camera's (forward, up), and whether the world is anatomical: an axis triad.
    pub axes: Option<(DVec3, DVec3, bool)>,
    /// The shape classes' threshold τ (for the Westin triangle of `shape`).
    pub class_threshold: f64,
}

impl Caption {
    /// The legend of a rendered frame: the scheme's key, the scale in effect (`auto`, whose
    /// largest radius is capped, or a factor) and the glyphs it clamped, the underlay and its
    /// window when shown, and the camera's axes.
    pub fn of_frame(
        style: &ResolvedStyle,
        clamped: usize,
        scene: &Scene,
        req: &FrameRequest,
        camera: &Camera,
        anatomical: bool,
    ) -> Self {
        let scale = if style.cap.is_finite() {
            "scale auto".to_string()
        } else {
            format!("radius = {} × size", style.k)
        };
        // A scene of SH series is sized by its ODFs' normalisation, not the tensors' scale.
        let mut lines = vec![if scene.payload.is_some() {
            "ODFs: full radius half a voxel".to_string()
        } else {
            format!("{scale}, size by {}", style.size_by)
        }];
        if clamped > 0 && style.local.is_some() {
            lines.push(format!(
                "{clamped} clamped to the 98th percentile or their room"
            ));
        } else if clamped > 0 {
            lines.push(format!("{clamped} largest shown at the 98th percentile"));
        }
        if let (Some(u), true) = (&scene.underlay, req.underlay.shown) {
            let [lo, hi] = req.underlay.window.unwrap_or(u.window);
            lines.push(format!("under: {} {lo:.3} – {hi:.3}", u.label));
        }
        Caption {
            legend: if scene.payload.is_some() {
                Legend::of_odf(style.color)
            } else {
                Legend::of(style)
            },
            lines,
            axes: Some((camera.forward(), camera.up, anatomical)),
            class_threshold: style.class_threshold,
        }
    }
}

/// Where a legend was drawn: (x, y, width, height) in pixels.
pub type Placed = [u32; 4];

/// An RGBA8 image to draw on (the report's mosaics draw their labels with it too).
pub(crate) struct Canvas<'a> {
    pub(crate) rgba: &'a mut [u8],
    pub(crate) w: i64,
    pub(crate) h: i64,
}

impl Canvas<'_> {
    /// Blend `c` over pixel (x, y) with coverage `a`; the result is opaque.
    pub(crate) fn blend(&mut self, x: i64, y: i64, c: [f64; 3], a: f64) {
        if x < 0 || y < 0 || x >= self.w || y >= self.h || a <= 0.0 {
            return;
        }
        let p = &mut self.rgba[4 * (y * self.w + x) as usize..][..4];
        let a = a.min(1.0);
        for k in 0..3 {
            let v = f64::from(p[k]) / 255.0 * (1.0 - a) + c[k].clamp(0.0, 1.0) * a;
            p[k] = (v * 255.0).round() as u8;
        }
        p[3] = 255;
    }

    pub(crate) fn rect(&mut self, x: i64, y: i64, w: i64, h: i64, c: [f64; 3]) {
        for yy in y..y + h {
            for xx in x..x + w {
                self.blend(xx, yy, c, 1.0);
            }
        }
    }

    /// A line of `width` pixels, sampled densely (for the few short strokes of a triad).
    pub(crate) fn line(&mut self, a: [f64; 2], b: [f64; 2], width: f64, c: [f64; 3]) {
        let len = ((b[0] - a[0]).hypot(b[1] - a[1])).max(1.0);
        let steps = (len * 2.0) as i64;
        let r = width / 2.0;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let (x, y) = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t);
            for yy in (y - r).floor() as i64..=(y + r).ceil() as i64 {
                for xx in (x - r).floor() as i64..=(x + r).ceil() as i64 {
                    let d = (xx as f64 + 0.5 - x).hypot(yy as f64 + 0.5 - y);
                    if d <= r {
                        self.blend(xx, yy, c, 1.0);
                    }
                }
            }
        }
    }
}

/// Text metrics and drawing in one face at one size.
pub(crate) struct Pen<'f> {
    font: FontRef<'f>,
    size: f32,
}

impl Pen<'static> {
    /// The legend's face (egui's Ubuntu Light) at `size` pixels.
    // The reports call it, and the browser's build has none.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    pub(crate) fn new(size: f32) -> Option<Self> {
        let font = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).ok()?;
        Some(Self { font, size })
    }
}

impl Pen<'_> {
    pub(crate) fn width(&self, text: &str) -> f64 {
        let f = self.font.as_scaled(PxScale::from(self.size));
        let mut w = 0.0;
        let mut prev = None;
        for ch in text.chars() {
            let id = f.glyph_id(ch);
            if let Some(p) = prev {
                w += f.kern(p, id);
            }
            w += f.h_advance(id);
            prev = Some(id);
        }
        f64::from(w)
    }

    /// Draw `text` with its top-left at (x, y).
    pub(crate) fn draw(&self, canvas: &mut Canvas<'_>, x: f64, y: f64, text: &str, c: [f64; 3]) {
        let f = self.font.as_scaled(PxScale::from(self.size));
        let mut caret = x as f32;
        let baseline = y as f32 + f.ascent();
        let mut prev = None;
        for ch in text.chars() {
            let id = f.glyph_id(ch);
            if let Some(p) = prev {
                caret += f.kern(p, id);
            }
            let glyph = id.with_scale_and_position(self.size, point(caret, baseline));
            caret += f.h_advance(id);
            prev = Some(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let b = outline.px_bounds();
                outline.draw(|gx, gy, cov| {
                    canvas.blend(
                        b.min.x as i64 + i64::from(gx),
                        b.min.y as i64 + i64::from(gy),
                        c,
                        f64::from(cov),
                    );
                });
            }
        }
    }

    pub(crate) fn line_height(&self) -> f64 {
        f64::from(self.size) * 1.35
    }
}

/// One row of the key, measured before it is drawn.
enum Row {
    Text(String),
    Swatch([f64; 3], String),
    /// The legend's colour bar.
    Bar,
    /// Two labels at the ends of the row before it.
    Ends(String, String),
    Triangle,
    Triad,
}

fn rows(caption: &Caption) -> Vec<Row> {
    let mut rows = Vec::new();
    match &caption.legend {
        Legend::Shape => {
            for (class, name) in [
                (ShapeClass::Linear, "linear (cigar)"),
                (ShapeClass::Planar, "planar (pancake)"),
                (ShapeClass::Spherical, "spherical (ball)"),
                (ShapeClass::Unclassified, "unclassified"),
            ] {
                rows.push(Row::Swatch(class.color(), name.into()));
            }
            rows.push(Row::Triangle);
        }
        Legend::Bar { lo, hi, title, .. } => {
            rows.push(Row::Text(title.clone()));
            rows.push(Row::Bar);
            rows.push(Row::Ends(short_number(*lo), short_number(*hi)));
        }
        Legend::Sign => {
            rows.push(Row::Bar);
            rows.push(Row::Ends("compression".into(), "tension".into()));
        }
        Legend::Dec | Legend::Direction => {
            let anatomical = caption.axes.is_some_and(|a| a.2);
            rows.push(Row::Text(
                if caption.legend == Legend::Dec {
                    "colour = |e1| × FA"
                } else {
                    "colour = |direction|"
                }
                .into(),
            ));
            let names = if anatomical {
                ["R–L", "A–P", "S–I"]
            } else {
                ["x", "y", "z"]
            };
            for (k, n) in names.into_iter().enumerate() {
                let mut c = [0.0; 3];
                c[k] = 1.0;
                rows.push(Row::Swatch(c, n.into()));
            }
        }
        Legend::Solid => {}
    }
    rows.extend(caption.lines.iter().map(|l| Row::Text(l.clone())));
    if caption.axes.is_some() {
        rows.push(Row::Triad);
    }
    rows
}

/// Burn `caption` into `rgba` (width × height, RGBA8) in the corner whose box covers the fewest
/// glyph pixels of `ids`; the panel is opaque, in the background's colour (white where the
/// background is transparent), its text black or white, whichever reads on it.
pub fn burn(
    rgba: &mut [u8],
    width: u32,
    height: u32,
    ids: &[u32],
    caption: &Caption,
    background: [f64; 4],
) -> Option<Placed> {
    let font = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).ok()?;
    let size = (f64::from(width.min(height)) / 45.0).clamp(11.0, 48.0);
    let pen = Pen {
        font,
        size: size as f32,
    };
    let rows = rows(caption);
    if rows.is_empty() {
        return None;
    }
    let lh = pen.line_height();
    let pad = size * 0.6;
    let swatch = size * 0.9;
    let bar_w = size * 10.0;
    let tri = size * 5.0;
    let row_size = |r: &Row| -> (f64, f64) {
        match r {
            Row::Text(t) => (pen.width(t), lh),
            Row::Swatch(_, t) => (swatch + size * 0.5 + pen.width(t), lh),
            Row::Bar => (bar_w, size),
            Row::Ends(a, b) => (pen.width(a) + pen.width(b) + size, lh),
            Row::Triangle => (tri * 1.15, tri + lh),
            Row::Triad => (tri, tri),
        }
    };
    let inner_w = rows.iter().map(|r| row_size(r).0).fold(0.0, f64::max);
    let inner_h: f64 = rows.iter().map(|r| row_size(r).1).sum();
    let (bw, bh) = (
        (inner_w + 2.0 * pad).ceil() as u32,
        (inner_h + 2.0 * pad).ceil() as u32,
    );
    if bw + 2 > width || bh + 2 > height {
        return None;
    }
    let margin = (size * 0.5) as u32;
    let corners = [
        (width.saturating_sub(bw + margin), margin),
        (
            width.saturating_sub(bw + margin),
            height.saturating_sub(bh + margin),
        ),
        (margin, margin),
        (margin, height.saturating_sub(bh + margin)),
    ];
    let covered = |&(x, y): &(u32, u32)| -> usize {
        (y..y + bh)
            .map(|yy| {
                let row = (yy * width) as usize;
                ids[row + x as usize..row + (x + bw) as usize]
                    .iter()
                    .filter(|&&i| i != 0)
                    .count()
            })
            .sum()
    };
    let (x0, y0) = corners
        .iter()
        .copied()
        .enumerate()
        .min_by_key(|(k, c)| (covered(c), *k))
        .map(|(_, c)| c)?;
    let panel = if background[3] > 0.5 {
        [background[0], background[1], background[2]]
    } else {
        [1.0; 3]
    };
    let luma = 0.2126 * panel[0] + 0.7152 * panel[1] + 0.0722 * panel[2];
    let ink = if luma > 0.5 { [0.0; 3] } else { [1.0; 3] };
    let border = panel.map(|p| p * 0.6 + ink[0] * 0.4);
    let mut canvas = Canvas {
        rgba,
        w: i64::from(width),
        h: i64::from(height),
    };
    let (x0, y0) = (i64::from(x0), i64::from(y0));
    canvas.rect(x0, y0, i64::from(bw), i64::from(bh), border);
    canvas.rect(x0 + 1, y0 + 1, i64::from(bw) - 2, i64::from(bh) - 2, panel);
    let (x, mut y) = (x0 as f64 + pad, y0 as f64 + pad);
    for r in &rows {
        let (_, h) = row_size(r);
        match r {
            Row::Text(t) => pen.draw(&mut canvas, x, y, t, ink),
            Row::Swatch(c, t) => {
                let s = swatch as i64;
                let top = y + (lh - swatch) / 2.0;
                canvas.rect(x as i64, top as i64, s, s, *c);
                pen.draw(&mut canvas, x + swatch + size * 0.5, y, t, ink);
            }
            Row::Bar => {
                for k in 0..bar_w as i64 {
                    if let Some(c) = caption.legend.bar_color(k as f64 / (bar_w - 1.0)) {
                        canvas.rect(x as i64 + k, y as i64, 1, size as i64, c);
                    }
                }
            }
            Row::Ends(a, b) => {
                pen.draw(&mut canvas, x, y, a, ink);
                pen.draw(&mut canvas, x + bar_w - pen.width(b), y, b, ink);
            }
            Row::Triangle => triangle(&mut canvas, &pen, x, y, tri, caption.class_threshold, ink),
            Row::Triad => {
                if let Some((f, u, anatomical)) = caption.axes {
                    triad(
                        &mut canvas,
                        &pen,
                        x + tri / 2.0,
                        y + tri / 2.0,
                        tri,
                        f,
                        u,
                        anatomical,
                    );
                }
            }
        }
        y += h;
    }
    Some([x0 as u32, y0 as u32, bw, bh])
}

/// The Westin triangle (corners cl, cp, cs), each point coloured by the class a tensor with
/// those measures gets.
fn triangle(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    x: f64,
    y: f64,
    side: f64,
    tau: f64,
    ink: [f64; 3],
) {
    let h = side * 3f64.sqrt() / 2.0;
    let top = y + pen.line_height() * 0.2;
    let (a, b, c) = (
        [x, top + h],          // cl
        [x + side, top + h],   // cp
        [x + side / 2.0, top], // cs
    );
    let det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
    for py in top as i64..=(top + h) as i64 {
        for px in x as i64..=(x + side) as i64 {
            let (qx, qy) = (px as f64 + 0.5, py as f64 + 0.5);
            let l1 = ((b[1] - c[1]) * (qx - c[0]) + (c[0] - b[0]) * (qy - c[1])) / det;
            let l2 = ((c[1] - a[1]) * (qx - c[0]) + (a[0] - c[0]) * (qy - c[1])) / det;
            let l3 = 1.0 - l1 - l2;
            if l1 < 0.0 || l2 < 0.0 || l3 < 0.0 {
                continue;
            }
            // λ = (1, 1 − cl, cs) has Westin measures (cl, cp, cs) = (l1, l2, l3).
            let class = classify([1.0, 1.0 - l1, l3], tau);
            canvas.blend(px, py, class.color(), 1.0);
        }
    }
    let below = top + h + 1.0;
    pen.draw(canvas, a[0], below, "cl", ink);
    pen.draw(canvas, b[0] - pen.width("cp"), below, "cp", ink);
    pen.draw(
        canvas,
        c[0] + pen.width("cs") * 0.3,
        top - pen.line_height() * 0.2,
        "cs",
        ink,
    );
}

/// World axes as the camera sees them, labelled at their positive ends.
#[allow(clippy::too_many_arguments)]
fn triad(
    canvas: &mut Canvas<'_>,
    pen: &Pen<'_>,
    cx: f64,
    cy: f64,
    size: f64,
    forward: DVec3,
    up: DVec3,
    anatomical: bool,
) {
    const COLORS: [[f64; 3]; 3] = [[0.85, 0.2, 0.2], [0.2, 0.65, 0.2], [0.25, 0.4, 0.95]];
    let labels = axis_labels(anatomical);
    let axes = screen_axes(forward, up);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| axes[a].1.total_cmp(&axes[b].1));
    let len = size * 0.3;
    for a in order {
        let [dx, dy] = axes[a].0.map(f64::from);
        let end = [cx + dx * len, cy + dy * len];
        canvas.line([cx, cy], end, (size / 40.0).max(1.5), COLORS[a]);
        let t = labels[a][0];
        let (tx, ty) = (cx + dx * len * 1.45, cy + dy * len * 1.45);
        pen.draw(
            canvas,
            tx - pen.width(t) / 2.0,
            ty - f64::from(pen.size) * 0.6,
            t,
            COLORS[a],
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, bg: [u8; 4]) -> Vec<u8> {
        bg.repeat((w * h) as usize)
    }

    #[test]
    fn the_legend_avoids_the_glyphs_and_is_opaque() {
        let (w, h) = (400u32, 300u32);
        let mut rgba = image(w, h, [255, 255, 255, 0]);
        // Glyphs fill the right half: the legend goes to the left.
        let ids: Vec<u32> = (0..w * h).map(|i| u32::from(i % w >= w / 2)).collect();
        let caption = Caption {
            legend: Legend::Shape,
            lines: vec!["scale auto, size by linear".into()],
            axes: Some((DVec3::NEG_Z, DVec3::Y, true)),
            class_threshold: 0.5,
        };
        let [x, y, bw, bh] =
            burn(&mut rgba, w, h, &ids, &caption, [1.0, 1.0, 1.0, 0.0]).expect("fits");
        assert!(x + bw <= w / 2, "left half: x {x} width {bw}");
        // Opaque inside the box, untouched (transparent) outside.
        for yy in y..y + bh {
            for xx in x..x + bw {
                assert_eq!(rgba[(4 * (yy * w + xx) + 3) as usize], 255);
            }
        }
        assert_eq!(rgba[(4 * (h - 1) * w + 4 * (w - 1) + 3) as usize], 0);
        // The class colours appear in it (the swatches and the triangle), and dark text.
        let inside = |c: [u8; 3]| {
            (y..y + bh)
                .any(|yy| (x..x + bw).any(|xx| rgba[(4 * (yy * w + xx)) as usize..][..3] == c))
        };
        for c in [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 0, 255]] {
            assert!(inside(c), "{c:?} in the legend");
        }
        // Text: dark pixels on the white panel.
        let dark = (y..y + bh)
            .flat_map(|yy| (x..x + bw).map(move |xx| (xx, yy)))
            .filter(|&(xx, yy)| {
                rgba[(4 * (yy * w + xx)) as usize..][..3]
                    .iter()
                    .all(|&v| v < 80)
            })
            .count();
        assert!(dark > 20, "{dark} text pixels");
    }

    #[test]
    fn a_legend_that_does_not_fit_is_left_out() {
        let mut rgba = image(20, 10, [0, 0, 0, 255]);
        let caption = Caption {
            legend: Legend::Sign,
            lines: vec![],
            axes: None,
            class_threshold: 0.5,
        };
        assert_eq!(
            burn(&mut rgba, 20, 10, &[0; 200], &caption, [0.0, 0.0, 0.0, 1.0]),
            None
        );
        assert!(rgba.chunks(4).all(|p| p == [0, 0, 0, 255]));
    }
}
