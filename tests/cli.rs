//! The command line as a user meets it: outputs, JSON reports, exit status and messages on bad
//! input, and nothing half-written left behind.

use std::path::Path;
use std::process::{Command, Output};

fn tg(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("run tensorglyph")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.lines().count(), 1, "exactly one JSON line: {text}");
    serde_json::from_str(&text).expect("valid JSON")
}

fn png_size(p: &Path) -> (u32, u32) {
    let img = image::open(p).expect("a readable PNG");
    (img.width(), img.height())
}

#[test]
fn render_demo_writes_png_and_reports() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.png");
    let o = tg(&[
        "render",
        "--demo",
        "grid:6",
        "-o",
        out.to_str().unwrap(),
        "--size",
        "160x120",
        "--json",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(png_size(&out), (160, 120));
    assert_eq!(j["width"], 160);
    assert_eq!(j["glyphs_total"], 216);
    assert_eq!(j["glyphs_drawn"], 216);
    assert_eq!(j["bytes_per_glyph"], 48);
    for key in [
        "method",
        "glyph",
        "adapter",
        "backend",
        "height",
        "frame_ms",
        "fragments",
    ] {
        assert!(j.get(key).is_some(), "missing {key}");
    }
    // No temporary file is left beside the output.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn reference_check_on_a_small_demo() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.png");
    let diff = dir.path().join("d.png");
    let o = tg(&[
        "render",
        "--demo",
        "grid:5",
        "-o",
        out.to_str().unwrap(),
        "--size",
        "200x150",
        "--json",
        "--reference-check",
        "--diff",
        diff.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    // Same bounds as the acceptance figures for grid40 (README, "Accuracy").
    assert!(j["coverage_mismatch"].as_f64().unwrap() <= 5e-4, "{j}");
    assert!(j["id_mismatch"].as_f64().unwrap() <= 1e-3, "{j}");
    assert!(j["depth_err_rel_p99"].as_f64().unwrap() <= 1e-4, "{j}");
    assert!(j["normal_err_deg_p99"].as_f64().unwrap() <= 0.5, "{j}");
    assert_eq!(png_size(&diff), (200, 150));
}

#[test]
fn bad_options_exit_2_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "--demo", "grid40", "-o", o, "--size", "0x10"],
            "zero",
        ),
        (
            &["render", "--demo", "grid40", "-o", o, "--size", "100000x10"],
            "limit",
        ),
        (
            &["render", "--demo", "grid40", "-o", o, "--method", "voodoo"],
            "voodoo",
        ),
        (
            &["render", "--demo", "grid40", "-o", "/nonexistent/dir/x.png"],
            "does not exist",
        ),
        (&["render", "-o", o], "FILE or --demo"),
        (
            &["render", "some.vtk", "--demo", "grid40", "-o", o],
            "not both",
        ),
        (&["render", "--demo", "grid7", "-o", o], "unknown demo"),
        (
            &[
                "render",
                "--demo",
                "grid:3",
                "-o",
                o,
                "--background",
                "mauve",
            ],
            "colour",
        ),
        (
            &["render", "/nonexistent/field.vtk", "-o", o],
            "/nonexistent/field.vtk",
        ),
    ];
    for (args, needle) in cases {
        let r = tg(args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert!(
            stderr(&r).contains(needle),
            "{args:?}: '{needle}' not in {}",
            stderr(&r)
        );
        assert!(!out.exists(), "{args:?} left an output behind");
    }
}

#[test]
fn info_json_on_the_demo() {
    let o = tg(&[
        "info", "--demo", "grid:4", "--json", "--sample", "0", "--sample", "63",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["tensors"], 64);
    assert_eq!(j["valid"], 64);
    assert_eq!(j["samples"].as_array().unwrap().len(), 2);
    assert_eq!(j["samples"][1]["index"], 63);
    let bad = tg(&["info", "--demo", "grid:4", "--sample", "64"]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn demo_writes_vtk_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let vtk = dir.path().join("grid40.vtk");
    let o = tg(&["demo", "--write-vtk", vtk.to_str().unwrap(), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let i = tg(&["info", vtk.to_str().unwrap(), "--json", "--sample", "1234"]);
    assert!(i.status.success(), "{}", stderr(&i));
    let from_file = json(&i);
    let d = tg(&["info", "--demo", "grid40", "--json", "--sample", "1234"]);
    let from_demo = json(&d);
    assert_eq!(from_file["tensors"], 64000);
    assert_eq!(from_file["dims"], serde_json::json!([40, 40, 40]));
    for k in 0..9 {
        let a = from_file["samples"][0]["tensor"][k].as_f64().unwrap();
        let b = from_demo["samples"][0]["tensor"][k].as_f64().unwrap();
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1e-12),
            "component {k}: {a} vs {b}"
        );
    }
}
