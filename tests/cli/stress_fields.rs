//! Stress fields as a stress analyst sees them: the yield-criterion and invariant colourings
//! against VTK's own filters, and the default image of every stress field in the tests.
//!
//! Truth: tests/data/stress/yield_truth.json, written by tests/data/stress/yield_truth.py with
//! VTK's `vtkYieldCriteria` and `vtkTensorPrincipalInvariants` (VTK 9.7) on VTK's point-load
//! field (tests/data/stress/pointload.vti), the scikit-fem beam (beam.vtu there) and three
//! scikit-fem solutions of tests/data/stress/make_fem_fields.py: a twisted cantilever on P1
//! tetrahedra (cell data), a plate with a hole on hexahedra (point data, six components) and a
//! notched bar on P2 tetrahedra (cell data). Images are counted by the exact CPU reference
//! (`--method reference`), so no GPU is needed.

use std::path::{Path, PathBuf};

use crate::cli::{json, stderr, tg};
use serde_json::Value;
use tensorglyph::glyph::ColorScheme;
use tensorglyph::legend::Legend;
use tensorglyph::scene::UnderlaySource;
use tensorglyph::select::{Plane, Slicing};
use tensorglyph::tensor::measure::Measure;
use tensorglyph::{GlyphStyle, Recipe, Selection, Silent, Source, stage};

/// Every stress field of the tests, where it is today.
const FIELDS: [&str; 5] = [
    "tests/data/stress/pointload.vti",
    "tests/data/stress/beam.vtu",
    "tests/data/stress/cantilever_twist.vtu",
    "tests/data/stress/plate_hole.vtu",
    "tests/data/stress/notched_bar.vtu",
];

fn path(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn truth() -> Value {
    let text = std::fs::read_to_string(path("tests/data/stress/yield_truth.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn file_name(rel: &str) -> &str {
    rel.rsplit('/').next().unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("a number: {v}"))
}

/// `info --json` with every sample VTK computed: the principal stresses, von Mises, Tresca and
/// the mean stress of each, and the summary's ranges, to 1e-9 of the field's largest |σ|; the
/// triaxiality (the library's, from those principal stresses) to the same over its von Mises.
#[test]
fn info_reports_the_yield_criteria_vtk_computes() {
    let truth = truth();
    for rel in FIELDS {
        let t = &truth["fields"][file_name(rel)];
        let scale = f(&t["max_abs_sigma"]);
        let tol = 1e-9 * scale;
        let samples = t["samples"].as_array().unwrap();
        let input = path(rel);
        let mut args = vec!["info", input.to_str().unwrap(), "--json", "--quiet"];
        let indices: Vec<String> = samples.iter().map(|s| s["index"].to_string()).collect();
        for i in &indices {
            args.extend(["--sample", i]);
        }
        let o = tg(&args);
        assert!(o.status.success(), "{rel}: {}", stderr(&o));
        let r = json(&o);
        assert_eq!(r["valid"], t["valid"], "{rel}");
        let mut worst = 0.0f64;
        for (want, got) in samples.iter().zip(r["samples"].as_array().unwrap()) {
            assert_eq!(want["index"], got["index"]);
            let p = &got["principal_stresses"];
            let pairs = [
                (f(&p[0]), f(&want["sigma1"])),
                (f(&p[1]), f(&want["sigma2"])),
                (f(&p[2]), f(&want["sigma3"])),
                (f(&got["von_mises"]), f(&want["von_mises"])),
                (f(&got["tresca"]), f(&want["tresca"])),
                (f(&got["mean"]), f(&want["mean"])),
            ];
            for (g, w) in pairs {
                assert!(
                    (g - w).abs() <= tol,
                    "{rel} #{}: {g} vs VTK {w}",
                    want["index"]
                );
                worst = worst.max((g - w).abs() / scale);
            }
            let principal = [f(&p[0]), f(&p[1]), f(&p[2])];
            let tri = Measure::Triaxiality.of(principal);
            let (w, vm) = (f(&want["triaxiality"]), f(&want["von_mises"]));
            assert!(
                (tri - w).abs() * vm <= tol,
                "{rel} #{}: triaxiality {tri} vs VTK {w}",
                want["index"]
            );
        }
        let ranges = &t["ranges"];
        let st = &r["stress"];
        let ev = &r["eigenvalues"];
        for (g, w) in [
            (&st["von_mises"]["min"], &ranges["von_mises"][0]),
            (&st["von_mises"]["max"], &ranges["von_mises"][1]),
            (&st["tresca"]["min"], &ranges["tresca"][0]),
            (&st["tresca"]["max"], &ranges["tresca"][1]),
            (&st["mean"]["min"], &ranges["mean"][0]),
            (&st["mean"]["max"], &ranges["mean"][1]),
            (&ev["min"][0], &ranges["sigma1"][0]),
            (&ev["max"][0], &ranges["sigma1"][1]),
            (&ev["min"][2], &ranges["sigma3"][0]),
            (&ev["max"][2], &ranges["sigma3"][1]),
        ] {
            assert!((f(g) - f(w)).abs() <= tol, "{rel}: range {g} vs VTK {w}");
        }
        eprintln!(
            "{rel}: {} samples, largest difference from VTK {worst:.1e} of max |σ|",
            samples.len()
        );
    }
}

/// The stress colourings map the field's 2nd–98th percentiles as VTK's values give them (the
/// glyphs carry f32 eigenvalues: to 1e-6 of the largest |σ|; triaxiality, a ratio, to 1e-5),
/// with diverging maps for the signed measures and legends titled with the field's units.
#[test]
fn colourings_take_vtk_s_percentiles_and_have_legends() {
    let truth = truth();
    let units = [None, None, Some("Pa"), Some("MPa"), None];
    for (rel, units) in FIELDS.into_iter().zip(units) {
        let t = &truth["fields"][file_name(rel)];
        let scale = f(&t["max_abs_sigma"]);
        for &scheme in ColorScheme::VALUES {
            let Some(m) = scheme.measure() else { continue };
            if matches!(m, Measure::Fa | Measure::Md) {
                continue;
            }
            let recipe = Recipe {
                style: GlyphStyle {
                    color: scheme,
                    ..GlyphStyle::default()
                },
                ..Recipe::default()
            };
            let staged = stage(&Source::File(path(rel)), &recipe, &Silent).unwrap();
            let want = &t["percentiles_2_98"][m.name().replace('-', "_")];
            let tol = if m == Measure::Triaxiality {
                1e-5
            } else {
                1e-6 * scale
            };
            for k in 0..2 {
                let (g, w) = (staged.style.color_range[k], f(&want[k]));
                assert!((g - w).abs() <= tol, "{rel} {m}: range {g} vs VTK {w}");
            }
            let Legend::Bar {
                title, diverging, ..
            } = Legend::of(&staged.style)
            else {
                panic!("{rel} {m}: a colour bar");
            };
            assert_eq!(diverging, m.signed());
            assert_eq!(title, m.title(units), "{rel}");
        }
    }
    // Units handed over name the legend of a field whose array's name has none.
    let recipe = Recipe {
        style: GlyphStyle {
            color: ColorScheme::Tresca,
            units: Some("MPa".into()),
            ..GlyphStyle::default()
        },
        ..Recipe::default()
    };
    let staged = stage(&Source::File(path(FIELDS[4])), &recipe, &Silent).unwrap();
    assert!(
        matches!(Legend::of(&staged.style), Legend::Bar { title, .. } if title == "Tresca (MPa)")
    );
}

/// A stress measure as an underlay of image data: VTK's von Mises over the point-load field,
/// windowed at its 2nd–98th percentiles.
#[test]
fn a_stress_underlay_on_image_data() {
    let truth = truth();
    let t = &truth["fields"]["pointload.vti"];
    let recipe = Recipe {
        underlay: Some(UnderlaySource::Measure(Measure::VonMises)),
        selection: Selection {
            slicing: Slicing::Planes(vec![Plane { axis: 1, index: 10 }]),
            ..Selection::default()
        },
        ..Recipe::default()
    };
    let staged = stage(&Source::File(path(FIELDS[0])), &recipe, &Silent).unwrap();
    let u = staged.scene.underlay.expect("an underlay");
    assert_eq!(u.label, "von Mises");
    let want = &t["percentiles_2_98"]["von_mises"];
    for k in 0..2 {
        let (g, w) = (f64::from(u.window[k]), f(&want[k]));
        assert!((g - w).abs() <= 1e-6 * w.abs(), "window {g} vs VTK {w}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("u.png");
    let o = tg(&[
        "render",
        path(FIELDS[0]).to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--underlay",
        "sigma9",
    ]);
    assert_eq!(o.status.code(), Some(2), "an unknown file: {}", stderr(&o));
    assert!(stderr(&o).contains("sigma9"), "{}", stderr(&o));
    assert!(!out.exists());
}

/// Render a field at 800×600 with the exact reference: (coverage, report).
fn render(rel: &str, extra: &[&str]) -> (f64, Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let input = path(rel);
    let mut args = vec![
        "render",
        input.to_str().unwrap(),
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
    assert!(o.status.success(), "{rel} {extra:?}: {}", stderr(&o));
    let j = json(&o);
    (j["covered_pixels"].as_f64().unwrap() / (800.0 * 600.0), j)
}

/// The first image of every stress field shows its glyphs: at least 4 % of an 800×600 image
/// covered, for ellipsoids (coloured by von Mises) and for principal bars (by sign), with the
/// glyphs the automatic size clamped counted.
#[test]
fn the_default_image_of_every_stress_field_shows_its_glyphs() {
    for rel in FIELDS {
        for (glyph, color) in [("ellipsoid", "von-mises"), ("principal", "sign")] {
            let (covered, j) = render(rel, &["--glyph", glyph]);
            eprintln!(
                "{rel} {glyph}: {:.2} % covered, {} of {} glyphs clamped",
                100.0 * covered,
                j["glyphs_clamped"],
                j["glyphs_total"]
            );
            assert_eq!(j["color"], color, "{rel} {glyph}");
            assert!(j["glyphs_clamped"].is_u64());
            assert!(covered >= 0.04, "{rel} {glyph}: {covered} covered");
        }
    }
}

#[test]
fn colour_options_are_checked() {
    let input = path(FIELDS[3]);
    let input = input.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    for (args, says) in [
        (vec!["--color-range", "5,1"], "LO,HI"),
        (
            vec!["--color", "shape", "--color-range", "0,1"],
            "--color-range",
        ),
        (vec!["--color", "von_mises"], "von-mises"),
    ] {
        let mut all = vec!["render", input, "-o", out.to_str().unwrap()];
        all.extend(args.iter().copied());
        let o = tg(&all);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(!out.exists());
    }
    // A range given is the range mapped, and the report says so.
    let (_, j) = render(FIELDS[3], &["--color", "mean", "--color-range", "-50,150"]);
    assert_eq!(j["color_range"], serde_json::json!([-50.0, 150.0]));
    assert_eq!(j["units"], "MPa");
}
