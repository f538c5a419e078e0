//! Scaling that survives real fields: VTK's own point-load stress field (tests/stress, written
//! by `vtkPointLoad`, a singularity at the load) shows visible glyphs with the default scale,
//! where sizing by the single largest eigenvalue left specks; `--scale F` stays exact.
//!
//! Coverage is counted by the exact CPU reference (`--method reference`), so no GPU is needed.

mod common;

use common::cli::{json, stderr, tg};

fn coverage(extra: &[&str]) -> (f64, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let input = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/stress/pointload.vti");
    let mut args = vec![
        "render",
        input,
        "-o",
        out.to_str().unwrap(),
        "--size",
        "800x600",
        "--method",
        "reference",
        "--json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = tg(&args);
    assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
    let j = json(&o);
    let covered = j["covered_pixels"].as_f64().unwrap() / (800.0 * 600.0);
    (covered, j)
}

#[test]
fn the_default_scale_shows_a_point_load_field() {
    let (default, j) = coverage(&[]);
    let clamped = j["glyphs_clamped"].as_u64().unwrap();
    // Glyphs cover at least 4 % of the image, and the few near the load that the robust size
    // clamps are counted (2 % of 8000 at the 98th percentile).
    assert!(default >= 0.04, "default scale covers {default}");
    assert!((100..=200).contains(&clamped), "{clamped} clamped");
    // Linear sizing from the robust magnitude also beats the largest |λ| by far, but the
    // logarithm the default picks for stress fields shows more.
    let (linear, _) = coverage(&["--size-by", "linear"]);
    assert!(linear < default && linear > 0.01, "linear {linear}");
}

#[test]
fn a_scale_factor_is_exact_and_clamps_nothing() {
    let (_, j) = coverage(&["--scale", "0.05"]);
    assert_eq!(j["glyphs_clamped"], 0);
}
