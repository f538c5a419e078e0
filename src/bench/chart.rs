//! Frame time against error, one chart per view: log–log, one colour per method family, mesh
//! levels joined as a curve, the Pareto front (nothing both faster and more accurate) ringed.

use std::path::Path;

use plotters::prelude::*;

use super::Row;
use crate::request::{GlyphKind, Method};

/// Errors are plotted on a log axis: exact agreement is drawn at this floor.
pub const ERROR_FLOOR_DEG: f64 = 1e-4;

static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Register the bundled font once (every chart of the crate draws text with it).
pub(crate) fn ensure_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled font is valid; a failure would only lose labels.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Family name for the legend: mesh levels share one curve.
fn family(m: Method) -> String {
    let s = m.to_string();
    match s.split_once(':') {
        Some((f, _)) => f.to_string(),
        None => s,
    }
}

fn error_of(r: &Row) -> f64 {
    r.accuracy.normal_err_deg_p99.max(ERROR_FLOOR_DEG)
}

/// Rows on the Pareto front: no other row is at least as fast and at least as accurate, and
/// strictly better in one.
pub fn pareto<'r>(rows: &[&'r Row]) -> Vec<&'r Row> {
    rows.iter()
        .copied()
        .filter(|a| {
            !rows.iter().any(|b| {
                let (ta, ea, tb, eb) = (
                    a.frame_ms_median,
                    error_of(a),
                    b.frame_ms_median,
                    error_of(b),
                );
                tb <= ta && eb <= ea && (tb < ta || eb < ea)
            })
        })
        .collect()
}

/// Series colours shared by every chart.
pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Draw the chart of `rows` (one view) to a PNG at `path`: one panel per glyph shape, one
/// colour per method family, mesh levels joined as a curve, the Pareto front ringed. Only the
/// depth-corrected variants on the default path are drawn (the others differ in depth, not in
/// normals; the other paths of Gumhold's method are in the report's tables).
pub fn speed_accuracy_png(path: &Path, title: &str, rows: &[&Row]) -> Result<(), String> {
    ensure_font();
    let rows: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| {
            r.skipped.is_empty()
                && r.method.is_gpu()
                && r.depth_correction
                && r.path == crate::request::Preset::Baseline.name()
                && r.frame_ms_median.is_finite()
        })
        .collect();
    if rows.is_empty() {
        return Err("nothing measured to chart".into());
    }
    let mut glyphs: Vec<GlyphKind> = Vec::new();
    let mut families: Vec<String> = Vec::new();
    for r in &rows {
        if !glyphs.contains(&r.glyph) {
            glyphs.push(r.glyph);
        }
        if !families.contains(&family(r.method)) {
            families.push(family(r.method));
        }
    }
    // Shared axes across panels, so they can be compared at a glance.
    let (mut tmin, mut tmax) = (f64::INFINITY, 0.0f64);
    let (mut emin, mut emax) = (f64::INFINITY, 0.0f64);
    for r in &rows {
        tmin = tmin.min(r.frame_ms_median);
        tmax = tmax.max(r.frame_ms_median);
        emin = emin.min(error_of(r));
        emax = emax.max(error_of(r));
    }
    let x_range = (tmin / 1.5).max(1e-3)..(tmax * 1.5).max(tmin * 2.0);
    let y_range = (emin / 3.0)..(emax * 3.0).max(emin * 10.0);
    let (w, h) = (640 * glyphs.len() as u32, 600u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root
            .titled(title, ("sans-serif", 24))
            .map_err(|e| e.to_string())?;
        let panels = root.split_evenly((1, glyphs.len()));
        for (panel, glyph) in panels.iter().zip(&glyphs) {
            let these: Vec<&Row> = rows.iter().copied().filter(|r| r.glyph == *glyph).collect();
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{glyph} glyphs"), ("sans-serif", 20))
                .margin(15)
                .x_label_area_size(50)
                .y_label_area_size(70)
                .build_cartesian_2d(x_range.clone().log_scale(), y_range.clone().log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("frame time, ms (median, log)")
                .y_desc("normal error p99, degrees (log)")
                .x_labels(6)
                .y_labels(8)
                .x_label_formatter(&|x| format_tick(*x))
                .y_label_formatter(&|y| format_tick(*y))
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 16))
                .draw()
                .map_err(|e| e.to_string())?;
            for (k, fam) in families.iter().enumerate() {
                let colour = PALETTE[k % PALETTE.len()];
                // Joined in level order (mesh:0, mesh:1, ...), not by time.
                let mut fam_rows: Vec<&Row> = these
                    .iter()
                    .copied()
                    .filter(|r| family(r.method) == *fam)
                    .collect();
                if fam_rows.is_empty() {
                    continue;
                }
                fam_rows.sort_by_key(|r| r.method.to_string());
                let pts: Vec<(f64, f64)> = fam_rows
                    .iter()
                    .map(|r| (r.frame_ms_median, error_of(r)))
                    .collect();
                let style = ShapeStyle::from(&colour).stroke_width(2);
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(|e| e.to_string())?
                    .label(fam.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(
                            vec![(x, y), (x + 20, y)],
                            ShapeStyle::from(&colour).stroke_width(3),
                        )
                    });
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 5, colour.filled())))
                    .map_err(|e| e.to_string())?;
            }
            let front = pareto(&these);
            chart
                .draw_series(front.iter().map(|r| {
                    Circle::new(
                        (r.frame_ms_median, error_of(r)),
                        10,
                        ShapeStyle::from(&BLACK).stroke_width(2),
                    )
                }))
                .map_err(|e| e.to_string())?
                .label("Pareto front")
                .legend(|(x, y)| {
                    Circle::new((x + 10, y), 6, ShapeStyle::from(&BLACK).stroke_width(2))
                });
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 15))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    save_rgb(path, w, h, &rgb)
}

/// Write a plotters RGB buffer as a PNG, atomically.
pub(crate) fn save_rgb(path: &Path, w: u32, h: u32, rgb: &[u8]) -> Result<(), String> {
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    crate::image_out::write_png_atomic(path, w, h, &rgba)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Log-axis tick labels: few significant digits, no trailing ".0" clutter.
fn format_tick(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{x:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{x:.0e}")
    }
}

/// One curve of a [`line_chart_png`].
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// Drawn thin when false: a secondary variant (another glyph) of the same method.
    pub bold: bool,
    /// Index into the palette (series of one method share a colour).
    pub colour: usize,
}

/// Axes of a [`line_chart_png`]: labels, log scales, and the floor drawn for zero errors.
pub struct Axes<'a> {
    pub x_desc: &'a str,
    pub y_desc: &'a str,
    pub log_x: bool,
    pub log_y: bool,
    /// Values below this are drawn at it on a log y axis (exact agreement).
    pub y_floor: f64,
}

/// Error against a swept parameter: one line per series, points marked.
pub fn line_chart_png(
    path: &Path,
    title: &str,
    axes: &Axes,
    series: &[Series],
) -> Result<(), String> {
    ensure_font();
    let fix_y = |y: f64| {
        let y = if y.is_nan() { f64::INFINITY } else { y };
        if axes.log_y { y.max(axes.y_floor) } else { y }
    };
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|&(x, y)| (x, fix_y(y))))
        .filter(|p| p.0.is_finite() && p.1.is_finite() && (!axes.log_x || p.0 > 0.0))
        .collect();
    if pts.is_empty() {
        return Err("nothing to chart".into());
    }
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in &pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (w, h) = (1000u32, 650u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(title, ("sans-serif", 24))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(85);
        let xr = if axes.log_x {
            // Whole decades, so a narrow range still gets labels.
            let lo = 10f64.powf(x0.log10().floor()) / 1.5;
            let hi = 10f64.powf(x1.log10().ceil()) * 1.5;
            lo..hi
        } else {
            let pad = ((x1 - x0) * 0.05).max(0.5);
            (x0 - pad)..(x1 + pad)
        };
        let yr = if axes.log_y {
            (y0 / 3.0)..(y1 * 3.0).max(y0 * 10.0)
        } else {
            let pad = ((y1 - y0) * 0.05).max(1e-3);
            (y0 - pad)..(y1 + pad)
        };
        // plotters types differ per scale: draw through one generic closure per combination.
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart.map_err(|e| e.to_string())?;
                let fmt = |v: &f64| {
                    if v.abs() >= 1e4 || (v.abs() < 1e-2 && *v != 0.0) {
                        format!("{v:.0e}")
                    } else {
                        format!("{}", (v * 1000.0).round() / 1000.0)
                    }
                };
                chart
                    .configure_mesh()
                    .x_label_formatter(&fmt)
                    .y_label_formatter(&fmt)
                    .x_desc(axes.x_desc)
                    .y_desc(axes.y_desc)
                    .label_style(("sans-serif", 15))
                    .axis_desc_style(("sans-serif", 17))
                    .draw()
                    .map_err(|e| e.to_string())?;
                for s in series {
                    let colour = PALETTE[s.colour % PALETTE.len()];
                    let mut p: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .map(|&(x, y)| (x, fix_y(y)))
                        .filter(|p| {
                            p.0.is_finite() && p.1.is_finite() && (!axes.log_x || p.0 > 0.0)
                        })
                        .collect();
                    p.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let width = if s.bold { 2 } else { 1 };
                    chart
                        .draw_series(LineSeries::new(
                            p.clone(),
                            ShapeStyle::from(&colour).stroke_width(width),
                        ))
                        .map_err(|e| e.to_string())?
                        .label(s.label.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(
                                vec![(x, y), (x + 20, y)],
                                ShapeStyle::from(&colour).stroke_width(3),
                            )
                        });
                    chart
                        .draw_series(p.iter().map(|&q| Circle::new(q, 3, colour.filled())))
                        .map_err(|e| e.to_string())?;
                }
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 13))
                    .position(SeriesLabelPosition::UpperLeft)
                    .draw()
                    .map_err(|e| e.to_string())?;
            }};
        }
        match (axes.log_x, axes.log_y) {
            (true, true) => draw!(builder.build_cartesian_2d(xr.log_scale(), yr.log_scale())),
            (true, false) => draw!(builder.build_cartesian_2d(xr.log_scale(), yr)),
            (false, true) => draw!(builder.build_cartesian_2d(xr, yr.log_scale())),
            (false, false) => draw!(builder.build_cartesian_2d(xr, yr)),
        }
        root.present().map_err(|e| e.to_string())?;
    }
    save_rgb(path, w, h, &rgb)
}
