//! Scaling that survives real fields: VTK's own point-load stress field (tests/data/stress, written
//! by `vtkPointLoad`, a singularity at the load) shows visible glyphs with the default scale,
//! where sizing by the single largest eigenvalue left specks; `--scale F` stays exact.
//!
//! Coverage is counted by the exact CPU reference (`--method reference`), so no GPU is needed.

use crate::cli::{json, stderr, tg};

fn coverage(extra: &[&str]) -> (f64, serde_json::Value) {
    coverage_of("pointload.vti", extra)
}

fn coverage_of(file: &str, extra: &[&str]) -> (f64, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let input = crate::data::path("stress").join(file);
    let input = input.to_str().unwrap();
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

/// A cantilever beam solved by scikit-fem (tests/data/stress/make_beam.py): bending stress is
/// uniaxial, so its ellipsoids are needles; the stress defaults (log sizing, radii at most 4:1)
/// and framing the field's box keep them visible.
#[test]
fn the_default_scale_shows_a_bending_beam() {
    let (default, j) = coverage_of("beam.vtu", &[]);
    assert!(default >= 0.04, "default scale covers {default}");
    assert_eq!(j["glyphs_total"], 2989);
    // The needles the tensor's own ellipsoids are (radii down to 1 % of the largest).
    let (needles, _) = coverage_of("beam.vtu", &["--min-radius", "0.01"]);
    assert!(needles < default / 1.4, "needles {needles} vs {default}");
}

#[test]
fn a_scale_factor_is_exact_and_clamps_nothing() {
    let (_, j) = coverage(&["--scale", "0.05"]);
    assert_eq!(j["glyphs_clamped"], 0);
}
