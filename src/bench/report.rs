//! The bench's CSV and Markdown report, written whole (temporary file, then rename).

use std::fmt::Write as _;
use std::path::Path;

use crate::request::Preset;

use super::Row;

pub const CSV_HEADER: &str = "scene,view,method,glyph,depth_correction,path,frame_ms_median,frame_ms_min,frame_ms_max,fragments,vertices,bytes_per_glyph,glyphs_culled,covered_pixels,fragments_per_covered_pixel,coverage_mismatch,id_mismatch,depth_err_rel_p99,normal_err_deg_p99,color_psnr_db,status";

fn opt(v: Option<u64>) -> String {
    v.map_or(String::new(), |x| x.to_string())
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e}")
    } else {
        String::new()
    }
}

pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    for r in rows {
        let status = if r.skipped.is_empty() {
            "ok".to_string()
        } else {
            format!("\"skipped: {}\"", r.skipped.replace('"', "'"))
        };
        let a = &r.accuracy;
        let measured = r.skipped.is_empty();
        let acc = |x: f64| if measured { num(x) } else { String::new() };
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.scene,
            r.view,
            r.method,
            r.glyph,
            r.depth_correction,
            r.path,
            num(r.frame_ms_median),
            num(r.frame_ms_min),
            num(r.frame_ms_max),
            opt(r.fragments),
            opt(r.vertices),
            r.bytes_per_glyph,
            if measured {
                r.glyphs_culled.to_string()
            } else {
                String::new()
            },
            if measured {
                r.covered_pixels.to_string()
            } else {
                String::new()
            },
            r.fragments_per_covered_pixel().map_or(String::new(), num),
            acc(a.coverage_mismatch),
            acc(a.id_mismatch),
            acc(a.depth_err_rel_p99),
            acc(a.normal_err_deg_p99),
            acc(a.color_psnr_db),
            status
        );
    }
    out
}

/// A Markdown table of one view's rows.
pub fn table(rows: &[&Row]) -> String {
    let mut out = String::from(
        "| method | glyph | depth corr. | path | ms (median) | fragments | predicted | frags/covered px | coverage mismatch | id mismatch | depth err p99 | normal err p99 (°) | PSNR (dB) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        if !r.skipped.is_empty() {
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | skipped: {} | | | | | | | | |",
                r.method,
                r.glyph,
                yes(r.depth_correction),
                r.path,
                r.skipped
            );
            continue;
        }
        let a = &r.accuracy;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.1} | {} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.3} | {:.1} |",
            r.method,
            r.glyph,
            yes(r.depth_correction),
            r.path,
            r.frame_ms_median,
            opt(r.fragments),
            r.predicted_fragments
                .map_or(String::new(), |p| format!("{p:.0}")),
            r.fragments_per_covered_pixel()
                .map_or(String::new(), |f| format!("{f:.2}")),
            a.coverage_mismatch,
            a.id_mismatch,
            a.depth_err_rel_p99,
            a.normal_err_deg_p99,
            a.color_psnr_db
        );
    }
    out
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// Write `text` to `path` whole or not at all ([`crate::image_out::write_atomic`]).
pub fn write_atomic(path: &Path, text: &[u8]) -> std::io::Result<()> {
    crate::image_out::write_atomic(path, &[], |w| std::io::Write::write_all(w, text))
}

fn fastest(v: Vec<&Row>) -> Option<&Row> {
    v.into_iter()
        .min_by(|a, b| a.frame_ms_median.total_cmp(&b.frame_ms_median))
}

/// One paragraph per scene on what the numbers say, computed from the rows.
pub fn findings(rows: &[Row]) -> String {
    use crate::request::GlyphKind;
    let mut out = String::new();
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let measured = |r: &&Row| r.skipped.is_empty() && r.frame_ms_median.is_finite();
    for scene in scenes {
        let pick = |view: &str, glyph: GlyphKind, pred: &dyn Fn(&Row) -> bool| -> Vec<&Row> {
            rows.iter()
                .filter(measured)
                .filter(|r| r.scene == scene && r.view == view && r.glyph == glyph)
                .filter(|r| r.depth_correction && r.path == Preset::Baseline.name() && pred(r))
                .collect()
        };
        let is_mesh = |r: &Row| r.method.to_string().starts_with("mesh:");
        let _ = writeln!(out, "**{scene}.**\n");
        // Gumhold's presets against the baseline measured in the same run.
        for view in ["default", "close", "far"] {
            for glyph in GlyphKind::VALUES.iter().copied() {
                let path_row = |path: &str| {
                    rows.iter().filter(measured).find(|r| {
                        r.scene == scene
                            && r.view == view
                            && r.glyph == glyph
                            && r.method == crate::request::Method::Gumhold
                            && r.depth_correction
                            && r.path == path
                    })
                };
                let Some(base) = path_row(Preset::Baseline.name()) else {
                    continue;
                };
                let _ = write!(out, "- Paths, {view} view, {glyph}s (Gumhold; baseline ");
                let per = |r: &Row| {
                    r.fragments_per_covered_pixel()
                        .map_or("n/a".to_string(), |f| format!("{f:.2}"))
                };
                let _ = write!(
                    out,
                    "{:.1} ms, {} fragments per covered pixel):",
                    base.frame_ms_median,
                    per(base)
                );
                for path in Preset::VALUES[1..].iter().map(|p| p.to_string()) {
                    if let Some(r) = path_row(&path) {
                        let _ = write!(
                            out,
                            " {path} {:.1} ms (speed x{:.2}), {} per covered pixel, {} culled;",
                            r.frame_ms_median,
                            base.frame_ms_median / r.frame_ms_median,
                            per(r),
                            r.glyphs_culled
                        );
                    }
                }
                let _ = writeln!(out);
            }
        }
        for glyph in GlyphKind::VALUES.iter().copied() {
            let Some(g) = fastest(pick("default", glyph, &|r| {
                r.method == crate::request::Method::Gumhold
            })) else {
                continue;
            };
            let _ = write!(
                out,
                "- Whole field, {glyph}s: Gumhold takes {:.1} ms per frame. ",
                g.frame_ms_median
            );
            let as_good = fastest(pick("default", glyph, &|r| {
                is_mesh(r)
                    && r.accuracy.coverage_mismatch <= g.accuracy.coverage_mismatch
                    && r.accuracy.normal_err_deg_p99 <= g.accuracy.normal_err_deg_p99
            }));
            match as_good {
                Some(m) => {
                    let _ = write!(
                        out,
                        "The cheapest mesh at least as accurate, {}, takes {:.1} ms: ray casting is {:.1}x faster. ",
                        m.method,
                        m.frame_ms_median,
                        m.frame_ms_median / g.frame_ms_median
                    );
                }
                None => {
                    let best = pick("default", glyph, &is_mesh).into_iter().min_by(|a, b| {
                        a.accuracy
                            .normal_err_deg_p99
                            .total_cmp(&b.accuracy.normal_err_deg_p99)
                    });
                    if let Some(m) = best {
                        let _ = write!(
                            out,
                            "No mesh level within the time budget is as accurate (coverage mismatch {:.1e}, normal error {:.3}°): the best measured, {}, still has {:.1e} and {:.2}° at {:.0} ms ({:.0}x Gumhold's time). ",
                            g.accuracy.coverage_mismatch,
                            g.accuracy.normal_err_deg_p99,
                            m.method,
                            m.accuracy.coverage_mismatch,
                            m.accuracy.normal_err_deg_p99,
                            m.frame_ms_median,
                            m.frame_ms_median / g.frame_ms_median
                        );
                    }
                }
            }
            if let Some(m0) = fastest(pick("default", glyph, &is_mesh)) {
                let _ = write!(
                    out,
                    "Even the cheapest mesh, {} ({:.1e} coverage mismatch, {:.0}° normal error), takes {:.1}x Gumhold's time. ",
                    m0.method,
                    m0.accuracy.coverage_mismatch,
                    m0.accuracy.normal_err_deg_p99,
                    m0.frame_ms_median / g.frame_ms_median
                );
            }
            let _ = writeln!(out);
        }
        for glyph in GlyphKind::VALUES.iter().copied() {
            let ratio = |view: &str| -> Option<String> {
                let g = fastest(pick(view, glyph, &|r| {
                    r.method == crate::request::Method::Gumhold
                }))?;
                Some(
                    match fastest(pick(view, glyph, &|r| {
                        is_mesh(r) && r.accuracy.normal_err_deg_p99 <= 1.0
                    })) {
                        Some(m) => format!(
                            "{:.1}x ({} {:.1} ms vs Gumhold {:.1} ms)",
                            m.frame_ms_median / g.frame_ms_median,
                            m.method,
                            m.frame_ms_median,
                            g.frame_ms_median
                        ),
                        None => format!(
                            "no such mesh within the budget (Gumhold {:.1} ms)",
                            g.frame_ms_median
                        ),
                    },
                )
            };
            if let (Some(close), Some(far)) = (ratio("close"), ratio("far")) {
                let _ = writeln!(
                    out,
                    "- {glyph}s, cheapest mesh with normal error under 1° against Gumhold: close view (the 27 central glyphs filling the image, fill-bound) {close}; far view (the whole field at 1/8 zoom, glyphs of a pixel or two, setup-bound) {far}."
                );
            }
        }
        for method in [
            crate::request::Method::Gumhold,
            crate::request::Method::Sigg,
        ] {
            for view in ["close", "default"] {
                let Some(r) = fastest(pick(view, GlyphKind::Ellipsoid, &|r| r.method == method))
                else {
                    continue;
                };
                if let (Some(f), Some(p), Some(pt)) = (
                    r.fragments,
                    r.predicted_fragments,
                    r.predicted_tile_fragments,
                ) {
                    let _ = writeln!(
                        out,
                        "- {method}, {view} view: {f} fragment-shader invocations; its proxies cover {p:.0} pixels (measured/predicted {:.3}), and counted as lavapipe counts (16 per 4x4 tile a triangle touches) they predict {pt:.0} (measured/predicted {:.3}). Per covered pixel: {:.2} (overdraw of hidden glyphs included).",
                        f as f64 / p,
                        f as f64 / pt,
                        f as f64 / r.covered_pixels.max(1) as f64
                    );
                }
            }
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Accuracy;
    use crate::request::{GlyphKind, Method};

    #[test]
    fn csv_has_the_documented_columns_and_marks_skips() {
        let row = Row {
            scene: "grid40".into(),
            view: "default".into(),
            method: Method::Gumhold,
            glyph: GlyphKind::Ellipsoid,
            depth_correction: true,
            path: "default".into(),
            frame_ms_median: 12.5,
            frame_ms_min: 11.0,
            frame_ms_max: 14.0,
            fragments: Some(1000),
            vertices: Some(400),
            bytes_per_glyph: 32,
            glyphs_culled: 0,
            covered_pixels: 800,
            predicted_fragments: None,
            predicted_tile_fragments: None,
            accuracy: Accuracy::default(),
            skipped: String::new(),
        };
        let mut skipped = row.clone();
        skipped.skipped = "predicted over budget".into();
        let text = csv(&[row, skipped]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let n = CSV_HEADER.split(',').count();
        assert_eq!(lines[1].split(',').count(), n);
        assert!(lines[1].starts_with("grid40,default,gumhold,ellipsoid,true,default,1.250000e1"));
        // 1000 fragments over 800 covered pixels.
        assert!(lines[1].contains(",32,0,800,1.250000e0,"));
        assert!(lines[2].ends_with("\"skipped: predicted over budget\""));
    }
}
