//! Thin discs and long needles (issue 37) as a user renders them: `render --reference-check`
//! on tests/data/extremes (discs k = 1e5, needles k = 1e4, and a mix of both at k = 1e3 … 1e6,
//! each glyph passing through its neighbours; and fields of 1,000 needles at k = 1e4, 1e5 and
//! 1e6), with `--min-radius 0`, in the three views of the issue, held to the targets against the
//! exact f64 reference: coverage ≤ 1e-3, id ≤ 1e-3, depth p99 ≤ 1e-4 of the largest radius,
//! normal p99 ≤ 0.5° (the rows: docs/book/src/results/accuracy.md).

use crate::cli::{json, stderr, tg};

/// The three views.
const VIEWS: [&[&str]; 3] = [
    &[],
    &["--zoom", "6", "--azimuth", "17", "--elevation", "-23"],
    &["--ortho", "--view", "+x"],
];

/// A bound per metric, in `render --json`'s names.
struct Bounds {
    coverage: f64,
    id: f64,
    depth: f64,
    normal_deg: f64,
}

/// The targets.
const TARGETS: Bounds = Bounds {
    coverage: 1e-3,
    id: 1e-3,
    depth: 1e-4,
    normal_deg: 0.5,
};

/// `render` of `file` (tests/data/extremes) in view `view` with `method` (and `preset`), drawn
/// as `glyph` at 400x300, held to `b`.
fn check(file: &str, view: &[&str], glyph: &str, method: &str, preset: Option<&str>, b: &Bounds) {
    check_at("400x300", file, view, glyph, method, preset, b);
}

/// [`check`] at image size `size`.
fn check_at(
    size: &str,
    file: &str,
    view: &[&str],
    glyph: &str,
    method: &str,
    preset: Option<&str>,
    b: &Bounds,
) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let input = format!("tests/data/extremes/{file}");
    let mut args = vec![
        "render",
        input.as_str(),
        "--glyph",
        glyph,
        "--scale",
        "0.8",
        "--min-radius",
        "0",
        "--method",
        method,
        "--size",
        size,
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--reference-check",
        "-q",
    ];
    if let Some(p) = preset {
        args.extend_from_slice(&["--preset", p]);
    }
    args.extend_from_slice(view);
    let r = tg(&args);
    assert!(r.status.success(), "{args:?}: {}", stderr(&r));
    let j = json(&r);
    let name = format!("{file} {size} {view:?} {glyph} {method} {preset:?}");
    assert!(j["covered_pixels"].as_u64().unwrap() > 10, "{name}: {j}");
    let v = |k: &str| j[k].as_f64().unwrap_or(f64::NAN);
    eprintln!(
        "{name}: coverage {:.2e} id {:.2e} depth p99 {:.2e} normal p99 {:.3}°",
        v("coverage_mismatch"),
        v("id_mismatch"),
        v("depth_err_rel_p99"),
        v("normal_err_deg_p99")
    );
    for (key, bound) in [
        ("coverage_mismatch", b.coverage),
        ("id_mismatch", b.id),
        ("depth_err_rel_p99", b.depth),
        ("normal_err_deg_p99", b.normal_deg),
    ] {
        assert!(v(key) <= bound, "{name}: {key} {} > {bound}", v(key));
    }
}

/// Ellipsoid discs (k = 1e5) and the mixed field (k up to 1e6) in every view, by Gumhold's
/// default path (splats from the prepass), every glyph drawn, and Sigg's: before the
/// principal frame Gumhold's discs had depth p99 3e-3 and wrong glyphs 2e-3.
#[test]
fn ellipsoid_discs_meet_the_targets() {
    if crate::check::gpu().is_none() {
        return;
    }
    for file in ["discs.vtk", "mixed.vtk"] {
        for view in VIEWS {
            check(file, view, "ellipsoid", "gumhold", None, &TARGETS);
            check(
                file,
                view,
                "ellipsoid",
                "gumhold",
                Some("baseline"),
                &TARGETS,
            );
            check(file, view, "ellipsoid", "sigg", None, &TARGETS);
        }
    }
}

/// The other kinds on the mixed field, both ray casters.
#[test]
fn other_kinds_meet_the_targets_on_the_mixed_field() {
    if crate::check::gpu().is_none() {
        return;
    }
    for glyph in ["cylinder", "capsule", "superquadric"] {
        for view in VIEWS {
            check("mixed.vtk", view, glyph, "gumhold", None, &TARGETS);
            check("mixed.vtk", view, glyph, "sigg", None, &TARGETS);
        }
    }
}

/// needles.vtk (k = 1e4: 64 needles thinner than a pixel, 12 to 105 pixels, so its p99 is its
/// worst pixel, next to a rim), every kind and both ray casters, held to the targets: 2.3–5.0°
/// before the reference cast the glyphs as stored and the rays were formed next to the glyph,
/// 0.06–1.5° after, 0.000° since thin glyphs are cast in double-f32. Gumhold's capsules seen
/// orthographically, whose ray solved from its point nearest the centre lost the needle's
/// section in f32, had 72° before capsule_slide.
#[test]
fn needles_within_their_bounds() {
    if crate::check::gpu().is_none() {
        return;
    }
    for view in VIEWS {
        for glyph in ["ellipsoid", "cylinder", "capsule", "superquadric"] {
            check("needles.vtk", view, glyph, "gumhold", None, &TARGETS);
            check("needles.vtk", view, glyph, "sigg", None, &TARGETS);
        }
    }
}

/// 1,000 needles at k = 1e4 (needle_field.vtk) at 1024x768: 250 to 2,200 pixels, so the p99 is
/// a percentile, held to the targets (normal p99 0.13–0.44° measured on lavapipe; 2.4–4.5°
/// before).
#[test]
fn needle_field_meets_the_targets() {
    if crate::check::gpu().is_none() {
        return;
    }
    for view in VIEWS {
        for method in ["gumhold", "sigg"] {
            let file = "needle_field.vtk";
            check_at("1024x768", file, view, "ellipsoid", method, None, &TARGETS);
        }
    }
}

/// 1,000 needles at k = 1e5 and 1e6 (needle_field_1e5.vtk, needle_field_1e6.vtk), thinner
/// than a pixel, held to the targets: at k = 1e5 at 1024x768 in the three views (20 to
/// 260 pixel centres meet them), ellipsoids by Gumhold's default path (splats), its drawn
/// baseline and Sigg's, cylinders, capsules and superquadrics by both; at k = 1e6, which meets 3 to 20
/// pixel centres there, at 2048x1536 in the close and orthographic views (about 60). Their rays
/// are formed in double-f32 (THIN_EXACT): before, normal p99 was 0.4–4.0° at k = 1e5 and up to
/// 9.9° at 1e6 (docs/book/src/results/accuracy.md).
#[test]
fn thin_needle_fields_meet_the_targets() {
    if crate::check::gpu().is_none() {
        return;
    }
    let all = [
        ("ellipsoid", "gumhold", None),
        ("ellipsoid", "gumhold", Some("baseline")),
        ("ellipsoid", "sigg", None),
        ("cylinder", "gumhold", None),
        ("cylinder", "sigg", None),
        ("capsule", "gumhold", None),
        ("capsule", "sigg", None),
        ("superquadric", "gumhold", None),
        ("superquadric", "sigg", None),
    ];
    for view in VIEWS {
        for (glyph, method, preset) in all {
            let file = "needle_field_1e5.vtk";
            check_at("1024x768", file, view, glyph, method, preset, &TARGETS);
        }
    }
    for view in &VIEWS[1..] {
        for (glyph, method, preset) in [all[0], all[1], all[2], all[4], all[6], all[7]] {
            let file = "needle_field_1e6.vtk";
            check_at("2048x1536", file, view, glyph, method, preset, &TARGETS);
        }
    }
}
