//! The bench's CSV and Markdown report, written whole (temporary file, then rename).

use std::fmt::Write as _;
use std::path::Path;

use super::Row;

pub const CSV_HEADER: &str = "scene,view,method,glyph,depth_correction,frame_ms_median,frame_ms_min,frame_ms_max,fragments,vertices,bytes_per_glyph,coverage_mismatch,id_mismatch,depth_err_rel_p99,normal_err_deg_p99,color_psnr_db,status";

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
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.scene,
            r.view,
            r.method,
            r.glyph,
            r.depth_correction,
            num(r.frame_ms_median),
            num(r.frame_ms_min),
            num(r.frame_ms_max),
            opt(r.fragments),
            opt(r.vertices),
            r.bytes_per_glyph,
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
        "| method | glyph | depth corr. | ms (median) | fragments | frags/covered px | coverage mismatch | id mismatch | depth err p99 | normal err p99 (°) | PSNR (dB) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        if !r.skipped.is_empty() {
            let _ = writeln!(
                out,
                "| {} | {} | {} | skipped: {} | | | | | | | |",
                r.method,
                r.glyph,
                yes(r.depth_correction),
                r.skipped
            );
            continue;
        }
        let a = &r.accuracy;
        let per_px = match r.fragments {
            Some(f) if r.covered_pixels > 0 => format!("{:.2}", f as f64 / r.covered_pixels as f64),
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.1} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.3} | {:.1} |",
            r.method,
            r.glyph,
            yes(r.depth_correction),
            r.frame_ms_median,
            opt(r.fragments),
            per_px,
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

/// Write `text` to `path` whole or not at all.
pub fn write_atomic(path: &Path, text: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("no file name"))?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = std::fs::write(&tmp, text).and_then(|_| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// One paragraph per scene on what the numbers say, computed from the rows.
pub fn findings(rows: &[Row]) -> String {
    let mut out = String::new();
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let ok = |r: &&Row| r.skipped.is_empty() && r.frame_ms_median.is_finite();
    for scene in scenes {
        let find = |view: &str, method: &str| -> Option<&Row> {
            rows.iter().filter(ok).find(|r| {
                r.scene == scene
                    && r.view == view
                    && r.method.to_string() == method
                    && r.glyph == crate::render::GlyphKind::Ellipsoid
                    && r.depth_correction
            })
        };
        let meshes = |view: &str| -> Vec<&Row> {
            rows.iter()
                .filter(ok)
                .filter(|r| {
                    r.scene == scene
                        && r.view == view
                        && r.method.to_string().starts_with("mesh:")
                        && r.glyph == crate::render::GlyphKind::Ellipsoid
                        && r.depth_correction
                })
                .collect()
        };
        let _ = write!(out, "**{scene}.** ");
        if let Some(g) = find("default", "gumhold") {
            if let Some(m) = meshes("default")
                .into_iter()
                .min_by(|a, b| a.frame_ms_median.total_cmp(&b.frame_ms_median))
            {
                let _ = write!(
                    out,
                    "Whole-field view: Gumhold ellipsoids take {:.1} ms per frame against {:.1} ms for \
                     the cheapest mesh ({}), {:.1}x faster, with coverage mismatch {:.2e} vs {:.2e} \
                     and normal error p99 {:.3}° vs {:.2}°. ",
                    g.frame_ms_median,
                    m.frame_ms_median,
                    m.method,
                    m.frame_ms_median / g.frame_ms_median,
                    g.accuracy.coverage_mismatch,
                    m.accuracy.coverage_mismatch,
                    g.accuracy.normal_err_deg_p99,
                    m.accuracy.normal_err_deg_p99
                );
            }
            if let (Some(f), true) = (g.fragments, g.covered_pixels > 0) {
                let _ = write!(
                    out,
                    "Gumhold shades {:.2} fragments per covered pixel (an isolated quad predicts \
                     4/π = 1.27; overlap between glyphs raises it). ",
                    f as f64 / g.covered_pixels as f64
                );
            }
        }
        let ratio = |view: &str| -> Option<(f64, String)> {
            let g = find(view, "gumhold")?;
            let m = meshes(view)
                .into_iter()
                .filter(|m| m.accuracy.normal_err_deg_p99 <= 1.0)
                .min_by(|a, b| a.frame_ms_median.total_cmp(&b.frame_ms_median))?;
            Some((m.frame_ms_median / g.frame_ms_median, m.method.to_string()))
        };
        if let (Some((close, cm)), Some((far, fm))) = (ratio("close"), ratio("far")) {
            let _ = write!(
                out,
                "Against the cheapest mesh with normal error under 1° the speed-up of ray casting is \
                 {close:.1}x in the close view ({cm}, few large glyphs, fill-bound) and {far:.1}x in \
                 the far view ({fm}, many tiny glyphs, setup-bound){}",
                if close < far {
                    ": as Gumhold found, ray casting wins most for small glyphs and loses ground as \
                     glyphs grow on screen."
                } else {
                    "."
                }
            );
        }
        out.push_str("\n\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Accuracy;
    use crate::render::{GlyphKind, Method};

    #[test]
    fn csv_has_the_documented_columns_and_marks_skips() {
        let row = Row {
            scene: "grid40".into(),
            view: "default".into(),
            method: Method::Gumhold,
            glyph: GlyphKind::Ellipsoid,
            depth_correction: true,
            frame_ms_median: 12.5,
            frame_ms_min: 11.0,
            frame_ms_max: 14.0,
            fragments: Some(1000),
            vertices: Some(400),
            bytes_per_glyph: 48,
            covered_pixels: 800,
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
        assert!(lines[1].starts_with("grid40,default,gumhold,ellipsoid,true,1.250000e1"));
        assert!(lines[2].ends_with("\"skipped: predicted over budget\""));
    }
}
