//! `bench --brain`'s whole-brain report: the 128×128×70 volume written as a BEP016 folder and
//! reported on as a pipeline would (brain_report.csv), within the 1 GiB the issue sets (the 28 GB
//! QSIPrep's figures asked for is the anchor); nothing of the folder is left behind.

use crate::cli::{stderr, tg};

#[test]
fn the_whole_brain_report_is_written_within_a_gibibyte() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let o = tg(&[
        "bench",
        "--out",
        out.to_str().unwrap(),
        "--brain",
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
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("brain_report.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        [
            "ms",
            "peak_rss_bytes",
            "peak_is_the_reports",
            "figures",
            "status"
        ]
    );
    let r = &rows[1];
    assert_eq!((r[3], r[4]), ("3", "ok"), "{csv}");
    if cfg!(target_os = "linux") {
        let peak: u64 = r[1].parse().unwrap();
        assert_eq!(r[2], "true", "{csv}");
        assert!(peak > 0 && peak <= 1 << 30, "{csv}");
    }
    // The folder and its report were temporary.
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".brain"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}
