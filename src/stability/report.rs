//! stability.md, stability.csv, JSON lines and one chart per case (error against the swept
//! parameter), all from one run's rows.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use super::cases::is_anisotropy;
use super::{Row, Status};
use crate::bench::chart::{Axes, Series, line_chart_png};

/// Every metric key of the rows, sorted (the CSV columns after the fixed ones).
fn metric_keys(rows: &[Row]) -> Vec<String> {
    let set: BTreeSet<&String> = rows.iter().flat_map(|r| r.metrics.keys()).collect();
    set.into_iter().cloned().collect()
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn csv(rows: &[Row]) -> String {
    let keys = metric_keys(rows);
    let mut out =
        String::from("case,parameter,value,label,method,glyph,depth_correction,status,reason");
    for k in &keys {
        out.push(',');
        out.push_str(k);
    }
    out.push('\n');
    for r in rows {
        let fixed = [
            r.case.to_string(),
            r.parameter.to_string(),
            format!("{:e}", r.value),
            r.label.clone(),
            r.method.clone(),
            r.glyph.clone(),
            r.depth_correction.to_string(),
            r.status.to_string(),
            r.reason.clone(),
        ];
        out.push_str(
            &fixed
                .iter()
                .map(|s| csv_field(s))
                .collect::<Vec<_>>()
                .join(","),
        );
        for k in &keys {
            out.push(',');
            if let Some(v) = r.metrics.get(k) {
                let _ = write!(out, "{v:e}");
            }
        }
        out.push('\n');
    }
    out
}

/// One JSON object per line: case, parameter, method, glyph, status, metrics (non-finite
/// numbers become strings, JSON has no NaN).
pub fn json_lines(rows: &[Row]) -> String {
    let mut out = String::new();
    for r in rows {
        let metrics: serde_json::Map<String, serde_json::Value> = r
            .metrics
            .iter()
            .map(|(k, v)| {
                let j = serde_json::Number::from_f64(*v)
                    .map(serde_json::Value::Number)
                    .unwrap_or_else(|| serde_json::Value::String(v.to_string()));
                (k.clone(), j)
            })
            .collect();
        let v = serde_json::json!({
            "case": r.case,
            "parameter": r.parameter,
            "value": serde_json::Number::from_f64(r.value).map(serde_json::Value::Number).unwrap_or(serde_json::Value::Null),
            "label": r.label,
            "method": r.method,
            "glyph": r.glyph,
            "depth_correction": r.depth_correction,
            "status": r.status,
            "reason": r.reason,
            "metrics": metrics,
        });
        out.push_str(&v.to_string());
        out.push('\n');
    }
    out
}

/// Chart plan per case: which metric, log axes.
fn chart_spec(case: &str) -> Option<(&'static str, &'static str, bool)> {
    Some(match case {
        "1-distance" | "7-large-world" => ("normal_err_deg_p99", "normal error p99, degrees", true),
        c if is_anisotropy(c) => ("normal_err_deg_p99", "normal error p99, degrees", true),
        "1-distance-mu" => (
            "normal_err_deg_p99",
            "normal error p99, degrees (f32 twin)",
            true,
        ),
        "3-grazing" | "3-grazing-persp" | "4-eye-approach" | "5-camera" | "6-orthographic"
        | "10-degenerate" => (
            "coverage_mismatch",
            "coverage mismatch (fraction of pixels)",
            false,
        ),
        "8-sub-pixel" => (
            "coverage_ratio",
            "covered pixels / reference covered pixels",
            false,
        ),
        "9-intersecting" => (
            "id_mismatch",
            "id mismatch (fraction of shared pixels)",
            false,
        ),
        "10-degeneracy-sweep" => ("colour_jump_raw", "colour jump across t = 0", false),
        "11-eigensolver" => ("e1_angle_deg_p99", "e1 angle error p99, degrees", true),
        "14-odf-sharp" => ("normal_err_deg_p99", "normal error p99, degrees", true),
        "14-odf-faint" => (
            "coverage_mismatch",
            "coverage mismatch (fraction of pixels)",
            false,
        ),
        _ => return None,
    })
}

/// x as charted: log scale for decade sweeps (|ẽ| − 1 for the eye approach).
fn x_of(r: &Row) -> (f64, bool) {
    match r.case {
        "1-distance" | "1-distance-mu" | "8-sub-pixel" | "11-eigensolver" | "14-odf-faint" => {
            (r.value, true)
        }
        c if is_anisotropy(c) => (r.value, true),
        "7-large-world" => (r.value.max(1.0), true),
        "4-eye-approach" => (
            (r.value - 1.0).abs().max(1e-9) * (r.value - 1.0).signum(),
            false,
        ),
        "10-degeneracy-sweep" => (r.value.max(1e-10), true),
        _ => (r.value, false),
    }
}

/// One PNG per case; returns (case, file name) of the charts written.
pub fn charts(rows: &[Row], dir: &Path) -> Vec<(String, String)> {
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case) {
            cases.push(r.case);
        }
    }
    let mut out = Vec::new();
    for case in cases {
        let Some((metric, y_desc, log_y)) = chart_spec(case) else {
            continue;
        };
        let rs: Vec<&Row> = rows.iter().filter(|r| r.case == case).collect();
        let log_x = x_of(rs[0]).1;
        let mut keys: Vec<(String, String, bool)> = Vec::new();
        for r in &rs {
            let k = (r.method.clone(), r.glyph.clone(), r.depth_correction);
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
        // Charts show a readable subset of the mesh levels (the CSV has them all).
        keys.retain(|(m, _, _)| {
            !m.starts_with("mesh:") || ["mesh:0", "mesh:3", "mesh:6"].contains(&m.as_str())
        });
        let mut methods: Vec<&str> = Vec::new();
        for (m, _, _) in &keys {
            if !methods.contains(&m.as_str()) {
                methods.push(m);
            }
        }
        let series: Vec<Series> = keys
            .iter()
            .map(|(m, g, dc)| Series {
                colour: methods.iter().position(|x| x == m).unwrap_or(0) + usize::from(!*dc) * 3,
                label: format!("{m} {g}{}", if *dc { "" } else { " (no depth corr.)" }),
                points: rs
                    .iter()
                    .filter(|r| &r.method == m && &r.glyph == g && r.depth_correction == *dc)
                    // No pixel compared (glyph absent in both): nothing to chart.
                    .filter(|r| {
                        !(metric.contains("err") && r.metrics.get("same_glyph_px") == Some(&0.0))
                    })
                    .filter_map(|r| r.metrics.get(metric).map(|&v| (x_of(r).0, v)))
                    .collect(),
                bold: g == "-" || g == "ellipsoid",
            })
            .collect();
        let x_desc = if case == "4-eye-approach" {
            "|ẽ| − 1 (linear; 0 on the surface, −0.5 inside)".to_string()
        } else {
            format!(
                "{} ({})",
                rs[0].parameter,
                if log_x { "log" } else { "index / value" }
            )
        };
        let name = format!("{case}.png");
        let axes = Axes {
            x_desc: &x_desc,
            y_desc,
            log_x,
            log_y,
            y_floor: 1e-7,
        };
        if line_chart_png(
            &dir.join(&name),
            &format!("{case}: {metric}"),
            &axes,
            &series,
        )
        .is_ok()
        {
            out.push((case.to_string(), name));
        }
        if case == "11-eigensolver" {
            out.extend(solver_speed_chart(&rs, dir));
        }
    }
    out
}

/// Case 11 against speed: per solver, median tensors per second over the gaps against the worst
/// residual and the e1 angle p99 at gap 10⁻⁴ (where f32 already reaches its limit).
fn solver_speed_chart(rs: &[&Row], dir: &Path) -> Option<(String, String)> {
    let mut solvers: Vec<&str> = Vec::new();
    for r in rs {
        if !solvers.contains(&r.method.as_str()) {
            solvers.push(&r.method);
        }
    }
    let mut series = Vec::new();
    for s in solvers {
        let mine: Vec<&Row> = rs.iter().copied().filter(|r| r.method == s).collect();
        let mut speed: Vec<f64> = mine
            .iter()
            .filter_map(|r| r.metrics.get("tensors_per_s").copied())
            .collect();
        speed.sort_by(f64::total_cmp);
        let median = *speed.get(speed.len() / 2)?;
        let res = mine
            .iter()
            .filter_map(|r| r.metrics.get("residual_rel_max").copied())
            .fold(0.0, f64::max);
        let colour = series.len() / 2;
        series.push(Series {
            colour,
            label: format!("{s}: worst residual"),
            points: vec![(median, res)],
            bold: true,
        });
        if let Some(r) = mine.iter().find(|r| r.value == 1e-4) {
            let a = r.metrics.get("e1_angle_deg_p99").copied();
            series.push(Series {
                colour,
                label: format!("{s}: e1 angle p99 (deg) at gap 1e-4"),
                points: vec![(median, a.unwrap_or(f64::NAN))],
                bold: false,
            });
        }
    }
    let axes = Axes {
        x_desc: "tensors per second (median over the gaps, one thread, log)",
        y_desc: "error (log)",
        log_x: true,
        log_y: true,
        y_floor: 1e-17,
    };
    let name = "11-eigensolver-speed.png".to_string();
    let title = "11-eigensolver: accuracy against speed";
    line_chart_png(&dir.join(&name), title, &axes, &series).ok()?;
    Some(("11-eigensolver".into(), name))
}

fn fmt(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.is_nan() {
        "NaN".into()
    } else if (1e-3..1e4).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.2e}")
    }
}

/// The Markdown report: a summary per case and method, then every non-pass row with its reason.
pub fn markdown(rows: &[Row], charts: &[(String, String)], adapter: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Stability suite\n\nAdapter: {adapter}. {} rows.\n",
        rows.len()
    );
    let count = |st: Status| rows.iter().filter(|r| r.status == st).count();
    let _ = writeln!(
        s,
        "pass {}, degraded {}, fail {}.\n",
        count(Status::Pass),
        count(Status::Degraded),
        count(Status::Fail)
    );
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case) {
            cases.push(r.case);
        }
    }
    let _ = writeln!(s, "## Summary (case × method: pass / degraded / fail)\n");
    let _ = writeln!(
        s,
        "| case | method | glyph | pass | degraded | fail | worst |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for case in &cases {
        let mut keys: Vec<(String, String)> = Vec::new();
        for r in rows.iter().filter(|r| r.case == *case) {
            let k = (r.method.clone(), r.glyph.clone());
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
        for (m, g) in keys {
            let rs: Vec<&Row> = rows
                .iter()
                .filter(|r| r.case == *case && r.method == m && r.glyph == g)
                .collect();
            let c = |st: Status| rs.iter().filter(|r| r.status == st).count();
            let worst = rs.iter().map(|r| r.status).max().unwrap_or(Status::Pass);
            let _ = writeln!(
                s,
                "| {case} | {m} | {g} | {} | {} | {} | {worst} |",
                c(Status::Pass),
                c(Status::Degraded),
                c(Status::Fail)
            );
        }
    }
    let _ = writeln!(s, "\n## Charts\n");
    for (case, file) in charts {
        let _ = writeln!(s, "### {case}\n\n![{case}]({file})\n");
    }
    let _ = writeln!(s, "## Every row that is not a pass\n");
    let _ = writeln!(
        s,
        "| case | parameter | method | glyph | depth corr. | status | reason |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for r in rows.iter().filter(|r| r.status != Status::Pass) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r.case,
            r.label,
            r.method,
            r.glyph,
            if r.depth_correction { "yes" } else { "no" },
            r.status,
            r.reason.replace('|', "\\|")
        );
    }
    let _ = writeln!(s, "\n## Key numbers per row\n");
    let _ = writeln!(
        s,
        "| case | parameter | method | glyph | status | coverage | id | depth p99 | normal p99° | other |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let g = |k: &str| {
            r.metrics
                .get(k)
                .map(|&v| fmt(v))
                .unwrap_or_else(|| "-".into())
        };
        let other: Vec<String> = r
            .metrics
            .iter()
            .filter(|(k, _)| {
                !matches!(
                    k.as_str(),
                    "coverage_mismatch"
                        | "id_mismatch"
                        | "depth_err_rel_p99"
                        | "normal_err_deg_p99"
                        | "depth_err_rel_max"
                        | "normal_err_deg_max"
                        | "color_psnr_db"
                )
            })
            .filter(|(k, v)| !(k.ends_with("_px") && **v == 0.0) || k.contains("covered"))
            .map(|(k, v)| format!("{k} {}", fmt(*v)))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.case,
            r.label,
            r.method,
            r.glyph,
            r.status,
            g("coverage_mismatch"),
            g("id_mismatch"),
            g("depth_err_rel_p99"),
            g("normal_err_deg_p99"),
            other.join(", ")
        );
    }
    s
}
