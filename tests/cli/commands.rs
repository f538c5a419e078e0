//! The command line as a user meets it: outputs, JSON reports, exit status and messages on bad
//! input, and nothing half-written left behind.

use std::path::Path;
use std::process::Command;

use crate::cli::{json, stderr, tg};

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
    assert_eq!(j["tiles"], 1);
    assert_eq!(j["effects"], "direct");
    assert_eq!(j["glyphs_total"], 216);
    assert_eq!(j["glyphs_drawn"], 216);
    assert_eq!(
        j["bytes_per_glyph"],
        std::mem::size_of::<tensorglyph::render::gpu_data::GpuGlyph>()
    );
    assert_eq!(j["glyphs_culled"], 0);
    // 6³ glyphs seen from outside the lattice: the front ones hide some of the others.
    let visible = j["glyphs_visible"].as_u64().unwrap();
    assert!(visible > 50 && visible < 216, "{visible}");
    let covered = j["covered_pixels"].as_u64().unwrap();
    assert!(covered > 1000 && covered < 160 * 120);
    if let Some(f) = j["fragments"].as_u64() {
        let per = j["fragments_per_covered_pixel"].as_f64().unwrap();
        assert!((per - f as f64 / covered as f64).abs() < 1e-9);
    }
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
    // Same bounds as the acceptance figures for grid40 (docs/book/src/results/accuracy.md).
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
            &[
                "render",
                "--demo",
                "grid40",
                "-o",
                o,
                "--size",
                "100000x1000",
            ],
            "8192×8192",
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
        (
            &["render", "--demo", "grid:3", "-o", o, "--sharpness", "5"],
            "--sharpness applies to --glyph superquadric",
        ),
        (
            &[
                "render",
                "--demo",
                "grid:3",
                "-o",
                o,
                "--glyph",
                "superquadric",
                "--sharpness",
                "-1",
            ],
            "--sharpness must be between 0 and 20",
        ),
        (
            &[
                "render",
                "--demo",
                "grid:3",
                "-o",
                o,
                "--glyph",
                "superquadric",
                "--sharpness",
                "nan",
            ],
            "--sharpness must be between 0 and 20",
        ),
        // A file of SH series is drawn as ODF glyphs, selected by --slice only.
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--glyph",
                "cylinder",
            ],
            "mrtrix_lmax8.mif: holds SH series, drawn as --glyph odf, not cylinder",
        ),
        // Ellipsoid too, when asked for (it is only the default for tensors).
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--glyph",
                "ellipsoid",
            ],
            "mrtrix_lmax8.mif: holds SH series, drawn as --glyph odf, not ellipsoid",
        ),
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--fa-min",
                "0.2",
            ],
            "selected by --slice only",
        ),
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--slice",
                "z=9",
            ],
            "--slice z=9: the lattice is 4x4x4",
        ),
        // An ODF is coloured by direction, amplitude or one colour; amplitude is ODFs' alone.
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--color",
                "fa",
            ],
            "mrtrix_lmax8.mif: --color fa: a file of SH series is coloured by dec, amplitude or solid",
        ),
        (
            &[
                "render",
                "--demo",
                "grid:3",
                "-o",
                o,
                "--color",
                "amplitude",
            ],
            "--color amplitude applies to --glyph odf",
        ),
        (
            &["view", "--demo", "grid:3", "--color", "amplitude"],
            "--color amplitude applies to --glyph odf",
        ),
        (
            &[
                "render",
                "tests/data/extremes/needles.vtk",
                "-o",
                o,
                "--odf-normalize",
                "minmax",
            ],
            "needles.vtk: --odf-normalize applies to files of SH series (fibre ODFs), not to tensors",
        ),
        (
            &[
                "render",
                "tests/data/sh/mrtrix_lmax8.mif",
                "-o",
                o,
                "--odf-normalize",
                "mean",
            ],
            "invalid value 'mean' for '--odf-normalize",
        ),
    ];
    for (args, needle) in cases {
        let r = tg(args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert_eq!(
            stderr(&r).trim_end().lines().count(),
            1,
            "{args:?}: {}",
            stderr(&r)
        );
        assert!(
            stderr(&r).contains(needle),
            "{args:?}: '{needle}' not in {}",
            stderr(&r)
        );
        assert!(!out.exists(), "{args:?} left an output behind");
    }
}

/// `--odf-normalize` reaches the ODF scene: MRtrix's CSD fit (tests/data/sh) drawn with each
/// normalisation gives three different images, and `max` is the default (the scaling itself is
/// checked in src/scene/odf.rs against DIPY's basis).
#[test]
fn odf_normalize_changes_the_glyphs() {
    let dir = tempfile::tempdir().unwrap();
    let render = |extra: &[&str]| {
        let out = dir.path().join(format!("odf{}.png", extra.join("_")));
        let o = out.to_str().unwrap();
        let mut args = vec!["render", "tests/data/sh/mrtrix_lmax8.mif", "-o", o];
        args.extend_from_slice(&["--size", "160x120", "--method", "reference", "-q"]);
        args.extend_from_slice(extra);
        let r = tg(&args);
        assert!(r.status.success(), "{args:?}: {}", stderr(&r));
        image::open(&out).unwrap().to_rgba8()
    };
    let default = render(&[]);
    let max = render(&["--odf-normalize", "max"]);
    let minmax = render(&["--odf-normalize", "minmax"]);
    let none = render(&["--odf-normalize", "none"]);
    assert_eq!(default, max, "max is the default");
    assert_ne!(max, minmax);
    assert_ne!(max, none);
    assert_ne!(minmax, none);
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
    // The one line names what was read: the demo, or the file (tensors and SH alike).
    let e = stderr(&bad);
    assert!(e.starts_with("error: demo grid:4: sample index 64"), "{e}");
    for file in ["dti/nrrd_detached.nhdr", "sh/mrtrix_lmax8.mif"] {
        let f = crate::data::path(file);
        let bad = tg(&["info", f.to_str().unwrap(), "--sample", "99999"]);
        assert_eq!(bad.status.code(), Some(2));
        let e = stderr(&bad);
        assert!(
            e.contains(&format!("{}: ", f.display()))
                && e.contains("99999")
                && e.lines().count() == 1,
            "{file}: {e}"
        );
    }
}

/// Tensors whose eigenvalues leave the f32 range a glyph stores are a skipped category: counted
/// and named by `info`, never drawn, and the ranges of the others stay finite. Truth: the
/// eigenvalues of c·(all ones) are 3c, 0, 0 (3·f64::MAX overflows f64; 3·2e38 is beyond f32).
#[test]
fn eigenvalues_beyond_the_glyph_range_are_skipped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("huge.vtk");
    let row = |c: f64| format!("{c:e} {c:e} {c:e}\n").repeat(3);
    let text = format!(
        "# vtk DataFile Version 3.0\nhuge\nASCII\nDATASET POLYDATA\nPOINTS 4 double\n\
         0 0 0\n1 0 0\n2 0 0\n3 0 0\nPOINT_DATA 4\nTENSORS t double\n{}{}{}{}",
        row(f64::MAX),
        row(2e38),
        row(1e37),
        "2 0 0\n0 1 0\n0 0 1\n"
    );
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap();
    let o = tg(&["info", f, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(
        (j["valid"].as_u64(), j["skipped"]["overflow"].as_u64()),
        (Some(2), Some(2))
    );
    let max = j["eigenvalues"]["max"][0].as_f64().unwrap();
    assert!((max - 3e37).abs() <= 3e37 * 1e-12, "{max}");
    let text = tg(&["info", f]);
    assert!(
        String::from_utf8_lossy(&text.stdout).contains("2 beyond ±3.4e38"),
        "{}",
        String::from_utf8_lossy(&text.stdout)
    );
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

/// `info --json --sample` reproduces VTK's own read-back values on every VTK-written test file
/// (tests/data/vtk/expected.json): float32-exact for binary and XML files, 1e-6 relative for legacy
/// ASCII (VTK prints six significant digits there); positions to 1e-9 (cell centres are sums).
#[test]
fn info_samples_reproduce_vtk_values() {
    let dir = crate::data::path("vtk");
    let exp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    // expected.json writes NaN as "nan"; our JSON writes it as null.
    let num = |v: &serde_json::Value| match v {
        serde_json::Value::Number(n) => n.as_f64().unwrap(),
        _ => f64::NAN,
    };
    let close = |a: f64, b: f64, rel: f64| {
        (a.is_nan() && b.is_nan()) || (a - b).abs() <= rel * b.abs().max(1e-3)
    };
    let mut checked = 0;
    for (file, e) in exp.as_object().unwrap() {
        let ascii = e["format"] == "legacy-ascii";
        let (trel, prel) = if ascii { (1e-6, 1e-6) } else { (0.0, 1e-9) };
        for arr in e["arrays"].as_array().unwrap() {
            let components = arr["components"].as_u64().unwrap();
            if components != 9 && components != 6 {
                continue;
            }
            let path = dir.join(file);
            let mut args = vec![
                "info".to_string(),
                path.to_string_lossy().into_owned(),
                "--json".into(),
                "--array".into(),
                arr["name"].as_str().unwrap().to_string(),
            ];
            let samples = arr["samples"].as_array().unwrap();
            for s in samples {
                args.push("--sample".into());
                args.push(s["index"].to_string());
            }
            let argv: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = tg(&argv);
            assert!(o.status.success(), "{file}: {}", stderr(&o));
            let j = json(&o);
            assert_eq!(j["tensors"], arr["tuples"], "{file}");
            assert_eq!(j["tensor_array"]["location"], arr["location"], "{file}");
            for (k, s) in samples.iter().enumerate() {
                let got = &j["samples"][k];
                assert_eq!(got["index"], s["index"]);
                for c in 0..9 {
                    let (a, b) = (num(&got["tensor"][c]), num(&s["tensor"][c]));
                    assert!(
                        close(a, b, trel),
                        "{file} #{} tensor[{c}]: {a} vs {b}",
                        s["index"]
                    );
                }
                for c in 0..3 {
                    let (a, b) = (num(&got["position"][c]), num(&s["position"][c]));
                    assert!(
                        close(a, b, prel),
                        "{file} #{} position[{c}]: {a} vs {b}",
                        s["index"]
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 90, "only {checked} arrays checked");
}

/// Without any adapter, rendering falls back to the exact reference and says so.
#[test]
fn render_without_an_adapter_falls_back_to_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.png");
    // No backend this build supports: wgpu finds no adapter at all.
    let o = Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .args([
            "render",
            "--demo",
            "grid:3",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "96x64",
            "--json",
        ])
        .env("WGPU_BACKEND", "dx12")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("no GPU adapter"), "{}", stderr(&o));
    assert_eq!(json(&o)["method"], "reference");
    assert_eq!(png_size(&out), (96, 64));
}

/// One small `bench` run writes the CSV with its documented columns, the three charts and the
/// report.
#[test]
fn bench_writes_csv_charts_and_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let o = tg(&[
        "bench",
        "--out",
        out.to_str().unwrap(),
        "--scene",
        "grid:3",
        "--size",
        "96x64",
        "--frames",
        "2",
        "--method",
        "gumhold",
        "--method",
        "sigg",
        "--method",
        "mesh:1",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("speed_accuracy.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "scene,view,method,glyph,depth_correction,path,frame_ms_median,frame_ms_min,frame_ms_max,fragments,vertices,bytes_per_glyph,glyphs_culled,covered_pixels,fragments_per_covered_pixel,coverage_mismatch,id_mismatch,depth_err_rel_p99,normal_err_deg_p99,color_psnr_db,status"
    );
    // 3 methods x 2 glyphs x 2 depth settings x 3 views, Gumhold's other paths (culled,
    // octagon, triangle and sorted for both glyphs, conservative, prepass and splat for
    // ellipsoids) in each view, and a reference row per glyph and view.
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 3 * 2 * 2 * 3 + 11 * 3 + 2 * 3);
    for path in [
        "culled",
        "octagon",
        "triangle",
        "conservative",
        "sorted",
        "prepass",
        "splat",
    ] {
        assert!(
            rows.iter().any(
                |r| r.starts_with("grid:3,default,gumhold,ellipsoid,true,") && r.contains(path)
            ),
            "{path}"
        );
    }
    for png in [
        "speed_accuracy.png",
        "speed_accuracy_close.png",
        "speed_accuracy_far.png",
    ] {
        assert_eq!(png_size(&out.join(png)), (1280, 600), "{png}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## What this shows"));
}

/// Command-line mistakes clap catches are one line too, with the accepted values where there
/// is a list, exit status 2; help still prints in full.
#[test]
fn usage_errors_are_one_line() {
    for (args, needle) in [
        (&["render", "--demo", "grid40"][..], "--output"),
        (
            &["render", "--demo", "grid40", "-o", "x.png", "--bogus"][..],
            "--bogus",
        ),
        (
            &["render", "--demo", "grid40", "-o", "x.png", "--view", "up"][..],
            "one of: iso, +x, -x",
        ),
    ] {
        let r = tg(args);
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        let err = stderr(&r);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let help = tg(&["render", "--help"]);
    assert!(help.status.success());
    assert!(String::from_utf8_lossy(&help.stdout).contains("--preset"));
}

/// Sizes no back end should allocate are refused before any work, the CPU reference included
/// (it is also the no-adapter fallback), and the demo field is bounded by memory.
#[test]
fn size_caps_hold_for_every_method() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (
            &[
                "render",
                "--demo",
                "grid:2",
                "-o",
                o,
                "--method",
                "reference",
                "--size",
                "99999x99999",
            ][..],
            "99999x99999",
        ),
        (&["render", "--demo", "grid:1024", "-o", o][..], "N ≤ 320"),
    ] {
        let r = tg(args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert!(stderr(&r).contains(needle), "{args:?}: {}", stderr(&r));
        assert_eq!(stderr(&r).trim_end().lines().count(), 1);
        assert!(!out.exists());
    }
}

/// A reader that stops early (`info --json | head -c 100`) ends the output quietly.
#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    // 2000 samples: a report far larger than a pipe's buffer, so the writer meets the closed end.
    let mut args: Vec<String> = ["info", "--demo", "grid:30", "--json"]
        .map(String::from)
        .into();
    for i in 0..2000 {
        args.extend(["--sample".to_string(), i.to_string()]);
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .args(&args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read a little, then close our end of the pipe before the report is written whole.
    let mut first = [0u8; 1];
    drop(child.stdout.take().map(|mut s| s.read(&mut first)));
    let status = child.wait().unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(!err.contains("panicked"), "{err}");
    assert!(status.success(), "{status:?}: {err}");
}

/// An output over a file the input's header names (a `.mih`'s data file, `--diff` or `-o`) is
/// refused before any work, in one line naming it; the data file is left as it was.
#[test]
fn an_output_over_a_headers_data_file_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for f in ["tensor_detached.mih", "tensor_detached.dat"] {
        std::fs::copy(crate::data::path(&format!("mif/{f}")), d.join(f)).unwrap();
    }
    let mih = d.join("tensor_detached.mih");
    let dat = d.join("tensor_detached.dat");
    let before = std::fs::read(&dat).unwrap();
    let png = d.join("x.png");
    for args in [
        vec!["-o", dat.to_str().unwrap()],
        vec![
            "-o",
            png.to_str().unwrap(),
            "--reference-check",
            "--diff",
            dat.to_str().unwrap(),
        ],
    ] {
        let mut all = vec!["render", mih.to_str().unwrap(), "--method", "reference"];
        all.extend(args);
        let o = tg(&all);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.contains("refusing to overwrite") && e.contains("tensor_detached.dat"),
            "{e}"
        );
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(!png.exists(), "nothing was rendered");
    }
    assert_eq!(std::fs::read(&dat).unwrap(), before);
}
