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
