//! Fibre peaks (MRtrix's `sh2peaks` of the CSD fit in tests/data/sh, three a voxel) as a user
//! renders them: sticks, drawn as cylinders (the default) or capsules, by Gumhold's quads and
//! Sigg's boxes in the default face-on view of the middle slice, a close oblique view of every
//! slice and an orthographic side view, against the exact f64 reference with
//! `render --reference-check`: coverage, ids, depth, normals and colours. The sticks of SH
//! series' peaks over their ODFs (`--peaks`: two kinds in one frame, depth deciding), checked
//! the same way. And what a peaks file refuses: a glyph its kind does not offer and a tensor's
//! colouring; and what `--peaks` refuses.

use crate::check::{Bounds, reference_check};
use crate::cli::{stderr, tg};

const PEAKS: &str = "tests/data/sh/sh2peaks_lmax8.mif";

/// A tensor kind's bounds (tests/gpu/kinds.rs); measured 0 / 0 / ≤ 6e-7 / ≤ 1.3e-4° / 99 dB.
const TENSOR_KIND: Bounds = Bounds {
    coverage: 1e-4,
    id: 1e-4,
    depth_p99: 1e-5,
    normal_p99_deg: 0.01,
    psnr_db: 40.0,
};

#[test]
fn sticks_match_the_reference() {
    let views: [&[&str]; 3] = [
        &[],
        &[
            "--slice",
            "all",
            "--azimuth",
            "35",
            "--elevation",
            "25",
            "--zoom",
            "2.5",
        ],
        &["--ortho", "--view", "+x", "--slice", "x=2"],
    ];
    let mut failures = Vec::new();
    for (glyph, view) in [
        ("cylinder", views[0]),
        ("cylinder", views[1]),
        ("cylinder", views[2]),
        ("capsule", views[1]),
    ] {
        for method in ["gumhold", "sigg"] {
            let mut args = vec![PEAKS, "--glyph", glyph, "--method", method];
            args.extend_from_slice(view);
            let name = format!("{glyph} {method} {view:?}");
            let (j, ok) = reference_check(&name, &args, &TENSOR_KIND);
            // Three peaks in each of the 16 voxels of a slice, of the 64 of the lattice.
            let slices = if view.contains(&"all") { 4 } else { 1 };
            assert_eq!(j["glyphs_selected"], 48 * slices, "{name}: {j}");
            assert!(j["covered_pixels"].as_u64().unwrap() > 2000, "{name}: {j}");
            if !ok {
                failures.push(format!("{name}: {j}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The peaks of SH series (`--glyph peaks`: found by the project's peak finder) and a tensor
/// field's principal directions (DIPY's fit of real DWI, over its FA) are the same sticks:
/// exact against the reference, both methods, a slice and every slice at an angle.
#[test]
fn sticks_of_series_and_tensor_peaks_match_the_reference() {
    let mut failures = Vec::new();
    for file in [
        "tests/data/sh/mrtrix_lmax8.mif",
        "tests/data/sh/dipy_lmax8_descoteaux07_legacy.nii.gz",
        "tests/data/dti/dipy_small101/tensors.nii.gz",
    ] {
        for view in [
            &[][..],
            &["--slice", "all", "--azimuth", "35", "--elevation", "25"][..],
        ] {
            for method in ["gumhold", "sigg"] {
                let mut args = vec![file, "--glyph", "peaks", "--method", method];
                args.extend_from_slice(view);
                let name = format!("{file} {method} {view:?}");
                let (j, ok) = reference_check(&name, &args, &TENSOR_KIND);
                assert_eq!(j["glyph"], "cylinder", "{name}: {j}");
                assert!(j["covered_pixels"].as_u64().unwrap() > 500, "{name}: {j}");
                if !ok {
                    failures.push(format!("{name}: {j}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The sticks of the peaks over the ODFs (`--peaks`): one frame of two kinds, exact against the
/// reference (which draws each instance as its kind) as the ODFs alone are (tests/gpu/odf.rs's
/// lmax-8 bounds), by both methods, face-on and at an angle through every slice, and with the
/// outline filter, which runs over both kinds' ids; the sticks are those `--glyph peaks` draws
/// (as many), over the 16 ODFs of a slice.
#[test]
fn peaks_over_odfs_match_the_reference() {
    let mut failures = Vec::new();
    for file in [
        "tests/data/sh/mrtrix_lmax8.mif",
        "tests/data/sh/dipy_lmax8_descoteaux07_legacy.nii.gz",
    ] {
        for (view, odfs) in [
            (&[][..], 16),
            (
                &["--slice", "all", "--azimuth", "35", "--elevation", "25"][..],
                64,
            ),
            (&["--outlines"][..], 16),
        ] {
            let mut sticks = vec![file, "--glyph", "peaks"];
            sticks.extend_from_slice(view);
            let alone = selected(&sticks);
            assert!(alone > odfs, "{file} {view:?}: {alone} sticks");
            for method in ["gumhold", "sigg"] {
                let mut args = vec![file, "--peaks", "--method", method];
                args.extend_from_slice(view);
                let name = format!("{file} --peaks {method} {view:?}");
                let (j, ok) = reference_check(&name, &args, &TENSOR_KIND);
                assert_eq!(j["glyph"], "odf", "{name}: {j}");
                assert_eq!(j["glyphs_selected"], odfs + alone, "{name}: {j}");
                if view.contains(&"--outlines") {
                    assert_eq!(j["outline_mismatch"], 0.0, "{name}: {j}");
                }
                if !ok {
                    failures.push(format!("{name}: {j}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// How many glyphs `render` with `args` draws (the reference at a small size: no GPU).
fn selected(args: &[&str]) -> u64 {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--method", "reference", "--size", "64x48", "--json", "-q"]);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let r = tg(&all);
    assert!(r.status.success(), "{all:?}: {}", stderr(&r));
    crate::cli::json(&r)["glyphs_selected"].as_u64().unwrap()
}

/// `--peaks` draws the peaks of SH series over their ODFs, and refuses in one line what it cannot:
/// shadows (the composite pass knows one kind), tensors, a peaks file and `--glyph peaks`.
#[test]
fn peaks_over_odfs_refuse_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let sh = "tests/data/sh/mrtrix_lmax8.mif";
    for (file, extra, says) in [
        (
            sh,
            &["--shadows"][..],
            "--shadows are drawn over glyphs of one kind",
        ),
        (
            "tests/data/dti/dipy_small101/tensors.nii.gz",
            &[][..],
            "tensors.nii.gz: --peaks draws the peaks of SH series over their ODF glyphs; tensors \
             have no ODFs",
        ),
        (
            PEAKS,
            &[][..],
            "a file of peaks is drawn as its sticks alone",
        ),
        (
            sh,
            &["--glyph", "peaks"][..],
            "--glyph peaks draws the peaks alone",
        ),
        (
            sh,
            &["--odf-normalize", "minmax"][..],
            "peaks are normalised by max",
        ),
    ] {
        let mut args = vec!["render", file, "--peaks", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let r = tg(&args);
        let e = stderr(&r);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(!out.exists());
    }
}

#[test]
fn a_peaks_file_refuses_what_its_kind_does_not_offer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    for (extra, says) in [
        (
            &["--glyph", "ellipsoid"][..],
            "sh2peaks_lmax8.mif: holds fibre peaks, drawn as --glyph cylinder or --glyph capsule, not ellipsoid",
        ),
        (
            &["--color", "fa"][..],
            "sh2peaks_lmax8.mif: --color fa: sticks (peaks) are coloured by dec or solid",
        ),
        (&["--fa-min", "0.2"][..], "selected by --slice only"),
    ] {
        let mut args = vec!["render", PEAKS, "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let r = tg(&args);
        let e = stderr(&r);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(!out.exists());
    }
}
