//! `bench --large N`: one run of grid:N through the staged pipeline `render` uses, reported as
//! a table in report.md and as large_volume.csv (stage, ms, peak RSS after the stage, status).

use crate::cli::tg;

#[test]
fn bench_large_reports_every_stage() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let o = tg(&[
        "bench",
        "--out",
        out.to_str().unwrap(),
        "--large",
        "12",
        "--scene",
        "grid:2",
        "--size",
        "64x48",
        "--frames",
        "1",
        "--method",
        "gumhold",
        "--glyph",
        "ellipsoid",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("large_volume.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], ["stage", "ms", "peak_rss_bytes_after", "status"]);
    let stages: Vec<&str> = rows[1..].iter().map(|r| r[0]).collect();
    assert_eq!(
        stages,
        ["load", "eigen", "scene", "upload", "first_frame", "total"]
    );
    for r in &rows[1..] {
        assert_eq!(r[3], "ok", "{csv}");
        let ms: f64 = r[1].parse().unwrap();
        assert!(ms >= 0.0, "{csv}");
        if cfg!(target_os = "linux") {
            let peak: u64 = r[2].parse().unwrap();
            assert!(peak > 0, "{csv}");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## Large volume (grid:12, 1728 tensors)"),
        "{md}"
    );
    assert!(md.contains("| first_frame |"), "{md}");
    // The ordinary bench still ran.
    assert!(out.join("speed_accuracy.csv").exists());
}

/// `bench --million N`: grid:N against grid40 framed alike, whole and zoomed; each row's glyphs
/// shown are what `render --json` reports for the same demo, zoom and size, and the views the
/// frustum cuts are drawn by bricks.
#[test]
fn bench_million_times_a_large_field_against_grid40() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let o = tg(&[
        "bench",
        "--out",
        out.to_str().unwrap(),
        "--million",
        "52",
        "--scene",
        "grid:2",
        "--size",
        "320x240",
        "--frames",
        "1",
        "--method",
        "gumhold",
        "--glyph",
        "ellipsoid",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("million_glyphs.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        [
            "zoom",
            "grid40_ms",
            "large_ms",
            "ratio",
            "grid40_shown",
            "large_shown",
            "by_bricks"
        ]
    );
    let zooms: Vec<&str> = rows[1..].iter().map(|r| r[0]).collect();
    assert_eq!(zooms, ["1", "4", "8"], "{csv}");
    for r in &rows[1..] {
        let v = |i: usize| r[i].parse::<f64>().unwrap();
        assert!(v(1) > 0.0 && v(2) > 0.0, "{csv}");
        assert!((v(3) - v(2) / v(1)).abs() <= 1e-3 * v(3), "{csv}");
        for (demo, shown) in [("grid40", r[4]), ("grid:52", r[5])] {
            let png = dir.path().join("m.png");
            let o = tg(&[
                "render",
                "--demo",
                demo,
                "--zoom",
                r[0],
                "--size",
                "320x240",
                "-o",
                png.to_str().unwrap(),
                "--json",
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
            assert_eq!(
                json["glyphs_visible"].to_string(),
                shown,
                "{demo} zoom {}",
                r[0]
            );
        }
    }
    // The whole field is drawn in file order, the zoomed views by bricks.
    let bricks: Vec<&str> = rows[1..].iter().map(|r| r[6]).collect();
    assert_eq!(bricks, ["false", "true", "true"], "{csv}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("## A large field against grid40"), "{md}");
}
