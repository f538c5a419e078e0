//! The selection flags of `render` (`--fa-min`, `--fa-max`, `--stride`, `--slice`, `--roi`) as a
//! user meets them: glyph counts in `--json` checked against lattice arithmetic on the demo
//! grid (grid:N puts lattice position (i, j, k) at world (i, j, k)), and one clear error line
//! with exit status 2 for input that cannot be honoured. Also the stage timings and peak memory
//! that `render --json` reports.
//!
//! Counts use `--method reference` (the exact CPU ray caster) so no GPU is needed.

use std::path::Path;

use crate::cli::{json, stderr, tg};

/// `render SOURCE -o OUT` small, on the CPU, with `--json` and `extra` flags.
fn small_render(source: &[&str], out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["render"];
    args.extend_from_slice(source);
    args.extend_from_slice(&[
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--method",
        "reference",
        "--json",
        "--quiet",
    ]);
    args.extend_from_slice(extra);
    tg(&args)
}

/// `render --demo grid:N` with `extra` flags; the JSON report.
fn render_demo(n: usize, extra: &[&str]) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let o = small_render(&["--demo", &format!("grid:{n}")], &out, extra);
    assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
    assert!(out.exists());
    json(&o)
}

/// The error line of a failing `render --demo grid:8` with `extra` flags; nothing written.
fn render_error(extra: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let o = small_render(&["--demo", "grid:8"], &out, extra);
    assert_eq!(o.status.code(), Some(2), "{extra:?} should fail");
    assert!(!out.exists(), "{extra:?}: no image on error");
    let e = stderr(&o);
    assert!(!e.contains("panicked"), "{e}");
    e
}

fn selected(j: &serde_json::Value) -> u64 {
    j["glyphs_selected"].as_u64().expect("glyphs_selected")
}

#[test]
fn without_flags_every_glyph_is_selected() {
    let j = render_demo(8, &[]);
    assert_eq!(j["glyphs_total"], 512);
    assert_eq!(selected(&j), 512);
    assert_eq!(j["glyphs_drawn"], 512);
}

#[test]
fn one_slice_keeps_one_lattice_plane() {
    let j = render_demo(8, &["--slice", "z=3"]);
    assert_eq!(j["glyphs_total"], 512, "total counts the whole field");
    assert_eq!(selected(&j), 64);
    assert_eq!(j["glyphs_drawn"], 64);
}

#[test]
fn repeated_slices_keep_the_union_of_their_planes() {
    // x=1 crosses z=5 and z=6 in a line of 8 each; z=5 and z=6 are parallel.
    let j = render_demo(8, &["--slice", "x=1", "--slice", "z=5", "--slice", "z=6"]);
    assert_eq!(selected(&j), 3 * 64 - 2 * 8);
    // Three orthogonal planes: 3·64 − 3·8 + 1.
    let j = render_demo(8, &["--slice", "x=2", "--slice", "y=3", "--slice", "z=4"]);
    assert_eq!(selected(&j), 169);
}

#[test]
fn stride_runs_along_the_lattice_and_along_slices() {
    // ceil(8 / 3) = 3 positions per axis.
    assert_eq!(selected(&render_demo(8, &["--stride", "3"])), 27);
    // In the plane z=5 (not a multiple of 2): every 2nd x and y, 4 × 4.
    assert_eq!(
        selected(&render_demo(8, &["--stride", "2", "--slice", "z=5"])),
        16
    );
}

#[test]
fn roi_keeps_glyph_centres_in_the_box() {
    // Inclusive bounds: x, y, z ∈ {2, 3, 4}.
    assert_eq!(selected(&render_demo(8, &["--roi", "2,2,2,4,4,4"])), 27);
    // Negative bounds (a value starting with '-'); x ∈ {0, 1}, all y, z ∈ {0}.
    assert_eq!(
        selected(&render_demo(8, &["--roi", "-5,-5,-5,1.5,100,0.5"])),
        2 * 8
    );
    // Combined with a slice: the intersection.
    assert_eq!(
        selected(&render_demo(8, &["--roi", "0,0,0,1,7,7", "--slice", "z=3"])),
        2 * 8
    );
}

#[test]
fn fa_range_keeps_a_part_and_complements_add_up() {
    let all = selected(&render_demo(8, &[]));
    let low = selected(&render_demo(8, &["--fa-max", "0.4"]));
    let high = selected(&render_demo(8, &["--fa-min", "0.4"]));
    assert!(low > 0 && high > 0, "grid:8 has FA on both sides of 0.4");
    // Both ranges include FA = 0.4 exactly; the demo field does not hit it.
    assert_eq!(low + high, all);
}

#[test]
fn slices_render_in_place_not_reframed() {
    // The camera frames the whole field, so the planes x=0 and x=7 land on different sides of
    // the image; framed on their own, each would sit in the middle.
    let dir = tempfile::tempdir().unwrap();
    let centroid = |slice: &str| {
        let out = dir.path().join(format!("{slice}.png"));
        let o = tg(&[
            "render",
            "--demo",
            "grid:8",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x48",
            "--method",
            "reference",
            "--quiet",
            "--view",
            "+z",
            "--ortho",
            "--slice",
            slice,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let img = image::open(&out).unwrap().to_rgba8();
        let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for (x, y, p) in img.enumerate_pixels() {
            if p.0 != [255, 255, 255, 255] {
                n += 1.0;
                sx += f64::from(x);
                sy += f64::from(y);
            }
        }
        assert!(n > 0.0, "{slice} drew nothing");
        (sx / n, sy / n)
    };
    let (a, b) = (centroid("x=0"), centroid("x=7"));
    let d = (a.0 - b.0).hypot(a.1 - b.1);
    assert!(d > 16.0, "x=0 at {a:?}, x=7 at {b:?}: not in place");
}

#[test]
fn bad_selections_are_one_clear_error() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["--fa-min", "0.7", "--fa-max", "0.2"],
            "--fa-min 0.7 is greater than --fa-max 0.2",
        ),
        (
            &["--fa-min", "1.5"],
            "--fa-min must be a number between 0 and 1",
        ),
        (
            &["--fa-max", "-0.1"],
            "--fa-max must be a number between 0 and 1",
        ),
        (
            &["--fa-min", "NaN"],
            "--fa-min must be a number between 0 and 1",
        ),
        (&["--stride", "0"], "--stride must be at least 1"),
        (&["--slice", "q=1"], "is not x=I, y=J or z=K"),
        (&["--slice", "x"], "is not x=I, y=J or z=K"),
        (&["--slice", "y=-2"], "is not x=I, y=J or z=K"),
        (
            &["--slice", "z=8"],
            "slice z=8 is outside the lattice: it has 8 × 8 × 8",
        ),
        (&["--roi", "1,0,0,0,1,1"], "x0 = 1 is greater than x1 = 0"),
        (&["--roi", "0,0,0,1,1"], "six numbers"),
        (&["--roi", "0,0,0,1,1,inf"], "not a finite number"),
        (
            &["--fa-min", "0.999"],
            "the selection keeps no glyph: --fa-min 0.999 leaves none of the 512 valid glyphs",
        ),
        (
            &["--roi", "0.2,0,0,0.8,7,7"],
            "the selection keeps no glyph: --roi 0.2,0,0,0.8,7,7",
        ),
    ];
    for (flags, want) in cases {
        let e = render_error(flags);
        assert!(e.contains(want), "{flags:?}: {e}");
        assert!(e.starts_with("error: "), "{flags:?}: {e}");
    }
}

#[test]
fn slicing_unstructured_data_is_an_error_but_roi_works() {
    let data = crate::data::path("vtk");
    let Some(vtu) = std::fs::read_dir(&data)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "vtu"))
        .min()
    else {
        panic!("tests/data/vtk has a .vtu file");
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("u.png");
    let run = |extra: &[&str]| small_render(&[vtu.to_str().unwrap()], &out, extra);
    let o = run(&["--slice", "x=0"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("cannot slice x=0") && e.contains("no lattice"),
        "{e}"
    );
    let o = run(&["--roi=-1e30,-1e30,-1e30,1e30,1e30,1e30"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["glyphs_selected"], j["glyphs_total"]);
}

#[test]
fn json_reports_stage_timings_and_peak_memory() {
    for method in ["reference", "gumhold"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("t.png");
        let o = tg(&[
            "render",
            "--demo",
            "grid:16",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x48",
            "--method",
            method,
            "--frames",
            "2",
            "--json",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let j = json(&o);
        let t = &j["timings_ms"];
        for key in ["load", "eigen", "scene", "upload", "first_frame"] {
            let v = t[key]
                .as_f64()
                .unwrap_or_else(|| panic!("{method}: timings_ms.{key} is a number: {t}"));
            assert!(v >= 0.0 && v.is_finite(), "{method}: {key} = {v}");
        }
        assert!(t["first_frame"].as_f64().unwrap() > 0.0);
        assert!(j["frame_ms"].as_f64().unwrap() > 0.0);
        if cfg!(target_os = "linux") {
            let peak = j["peak_rss_bytes"]
                .as_u64()
                .expect("peak_rss_bytes on Linux");
            assert!(peak > 0);
        } else {
            assert!(j.get("peak_rss_bytes").is_some());
        }
        assert_eq!(j["glyphs_selected"], 4096);
    }
}
