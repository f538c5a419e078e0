//! NIfTI files of fibre peaks, as MRtrix and DIPY write them, against what those tools stored:
//! MRtrix's `sh2peaks` output converted by `mrconvert` (tests/data/sh/make_peaks.sh) against the
//! same peaks in the `.mif` (expected.json, read back by nibabel in make_sh.py), DIPY's
//! `pam_to_niftis` in both its layouts (make_dipy_peaks.py) against DIPY's arrays read back by
//! nibabel (dipy_peaks.json). Voxels are matched by world position.

use std::path::{Path, PathBuf};

use serde_json::Value;
use tensorglyph::field::{
    FieldKind, Inputs, PeakField, ReadOptions, read_field, read_peak_field_from,
};

use crate::cli::{json, stderr, tg};

fn sh(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/sh")
        .join(name)
}

fn load(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(sh(name)).unwrap()).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn holds(kind: FieldKind) -> ReadOptions {
    ReadOptions {
        holds: Some(kind),
        ..ReadOptions::default()
    }
}

/// The voxel of `field` at world position `at` (within 1e-4).
fn voxel_at(field: &PeakField, at: &[f64]) -> usize {
    (0..field.voxels())
        .find(|&v| {
            field
                .position(v)
                .iter()
                .zip(at)
                .all(|(a, b)| (a - b).abs() < 1e-4)
        })
        .unwrap_or_else(|| panic!("no voxel at {at:?}"))
}

/// `got` is `value` × `direction` (unit) within 1e-5 (relative for the length).
fn assert_peak(got: [f32; 3], direction: &[f64], value: f64, what: &str) {
    let len = got
        .iter()
        .map(|x| f64::from(*x).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        (len - value).abs() <= 1e-5 * value.max(1.0),
        "{what}: {len} {value}"
    );
    for c in 0..3 {
        assert!(
            (f64::from(got[c]) / len - direction[c]).abs() < 1e-5,
            "{what}: {got:?} {direction:?}"
        );
    }
}

/// `sh2peaks` output converted to NIfTI: 9 volumes that nothing in the header names, so read as
/// neither tensors nor peaks without `--holds`; with `--holds peaks`, MRtrix's peaks (in scanner
/// axes, as `descrip` says MRtrix wrote the file), voxel for voxel the `.mif`'s.
#[test]
fn mrtrix_peaks_converted_to_nifti_are_the_mif_peaks_with_holds_peaks() {
    let p = sh("sh2peaks_lmax8.nii.gz");
    let inputs = Inputs::file_system();
    let e = read_field(&p, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("give --holds tensors or --holds peaks"), "{e}");
    let opts = holds(FieldKind::Peaks);
    assert_eq!(FieldKind::of_file(&inputs, &p, &opts), FieldKind::Peaks);
    let field = read_peak_field_from(&inputs, &p, &opts).unwrap();
    assert_eq!(
        (field.format.as_str(), field.dims, field.per_voxel),
        ("nifti", [4, 4, 4], 3)
    );
    let all = load("expected.json");
    let want = &all["files"]["mrtrix_lmax8.mif"];
    let peaks = want["peaks"].as_object().unwrap();
    assert_eq!(peaks.len(), 64);
    for (v, pk) in peaks {
        let at = floats(&want["positions"][v.parse::<usize>().unwrap()]);
        let got: Vec<[f32; 3]> = field.peaks_of(voxel_at(&field, &at)).collect();
        let dirs = pk["directions"].as_array().unwrap();
        assert_eq!(got.len(), dirs.len(), "voxel {v}");
        for ((g, d), value) in got.iter().zip(dirs).zip(floats(&pk["values"])) {
            assert_peak(*g, &floats(d), value, &format!("voxel {v}"));
        }
    }
}

/// DIPY's peaks as its workflows save them (4-D, 15 volumes: five peaks or an lmax-4 series, so
/// `--holds peaks`) and as `peak_dirs` is held (5-D `X×Y×Z×5×3`, peaks by its shape alone):
/// DIPY's unit directions (voxel axes) turned into world by the affine's rotation and scaled by
/// the `peaks_values` file beside them, every voxel.
#[test]
fn dipy_peaks_in_both_layouts_are_what_dipy_stored() {
    let truth = load("dipy_peaks.json");
    let voxels = truth["voxels"].as_object().unwrap();
    let inputs = Inputs::file_system();
    let five = sh("dipy5d_peak_dirs.nii.gz");
    assert_eq!(
        FieldKind::of_file(&inputs, &five, &ReadOptions::default()),
        FieldKind::Peaks
    );
    for (path, opts) in [
        (sh("dipy_peaks_dirs.nii.gz"), holds(FieldKind::Peaks)),
        (five, ReadOptions::default()),
    ] {
        let field = read_peak_field_from(&inputs, &path, &opts).unwrap();
        assert_eq!((field.dims, field.per_voxel), ([4, 4, 4], 5), "{path:?}");
        let mut seen = 0;
        for (ijk, t) in voxels {
            let got: Vec<[f32; 3]> = field
                .peaks_of(voxel_at(&field, &floats(&t["position"])))
                .collect();
            let world = t["world"].as_array().unwrap();
            assert_eq!(got.len(), world.len(), "{path:?} voxel {ijk}");
            for ((g, d), value) in got.iter().zip(world).zip(floats(&t["values"])) {
                assert_peak(*g, &floats(d), value, &format!("{path:?} voxel {ijk}"));
                seen += 1;
            }
        }
        assert!(seen > 100, "{seen} peaks");
    }
}

/// Without `peaks_values` beside it, DIPY's directions are unit sticks; with one that does not
/// fit, the values file is named in one line.
#[test]
fn dipy_directions_without_or_with_unfitting_values() {
    let dir = tempfile::tempdir().unwrap();
    let dirs = dir.path().join("peaks_dirs.nii.gz");
    std::fs::copy(sh("dipy_peaks_dirs.nii.gz"), &dirs).unwrap();
    let inputs = Inputs::file_system();
    let opts = holds(FieldKind::Peaks);
    let field = read_peak_field_from(&inputs, &dirs, &opts).unwrap();
    let lengths: Vec<f64> = (0..field.voxels())
        .flat_map(|v| field.peaks_of(v))
        .map(|x| glam::Vec3::from(x).as_dvec3().length())
        .collect();
    assert!(!lengths.is_empty() && lengths.iter().all(|l| (l - 1.0).abs() < 1e-5));
    // The 15-volume directions given as their own amplitudes: 15 values beside 5 peaks.
    std::fs::copy(
        sh("dipy_peaks_dirs.nii.gz"),
        dir.path().join("peaks_values.nii.gz"),
    )
    .unwrap();
    let e = read_peak_field_from(&inputs, &dirs, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("peaks_values.nii.gz") && e.contains("15 values per voxel beside 5 peaks"),
        "{e}"
    );
}

/// The command line: `info` and `render` of peaks files, and `--holds peaks` on a file whose
/// count is no multiple of 3, refused in one line.
#[test]
fn peaks_files_from_the_command_line() {
    let five = sh("dipy5d_peak_dirs.nii.gz");
    let o = tg(&["info", five.to_str().unwrap(), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["kind"], "peaks");
    let counts: Vec<u64> = j["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    assert_eq!(counts.iter().sum::<u64>(), 64);
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("peaks.png");
    let nine = sh("sh2peaks_lmax8.nii.gz");
    let o = tg(&[
        "render",
        nine.to_str().unwrap(),
        "--holds",
        "peaks",
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(png.exists());
    // Fifteen volumes are five peaks or an lmax-4 series: nothing said, refused naming both.
    let dirs = sh("dipy_peaks_dirs.nii.gz");
    let o = tg(&["info", dirs.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("dipy_peaks_dirs.nii.gz")
            && err.contains("15 volumes per voxel")
            && err.contains("give --holds series (or --sh-basis) or --holds peaks"),
        "{err}"
    );
    let o = tg(&[
        "info",
        dirs.to_str().unwrap(),
        "--holds",
        "series",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(json(&o)["kind"], "sh");
    let series = sh("dipy_lmax12_descoteaux07_legacy_f32.nii.gz");
    let o = tg(&["info", series.to_str().unwrap(), "--holds", "peaks"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("dipy_lmax12_descoteaux07_legacy_f32.nii.gz")
            && err.contains("91 values per voxel: peaks take 3 each"),
        "{err}"
    );
}

/// `--glyph peaks` on a file of SH series: each voxel's peaks found by the project's finder
/// (DIPY's settings: half the voxel's largest, 25° apart) as sticks, each within 1° of a peak
/// MRtrix's `sh2peaks` found in the same voxel (expected.json; scanner axes, as the file's
/// series) where `sh2peaks` lists it (its three largest, with no separation rule: a stick
/// smaller than its third is not in the truth), the voxel's largest one voxel step long under
/// `--odf-normalize max`.
#[test]
fn series_peaks_are_sh2peaks_peaks_within_1_degree() {
    use tensorglyph::staging::{Recipe, Source, stage};
    let p = sh("mrtrix_lmax8.mif");
    let recipe = Recipe {
        peaks: true,
        style: tensorglyph::glyph::GlyphStyle {
            color: tensorglyph::glyph::ColorScheme::Dec,
            ..Default::default()
        },
        ..Recipe::default()
    };
    let staged = stage(&Source::File(p), &recipe, &tensorglyph::progress::Silent).unwrap();
    let all = load("expected.json");
    let truth = &all["files"]["mrtrix_lmax8.mif"]["peaks"];
    let mut by_voxel = std::collections::BTreeMap::<u32, Vec<f64>>::new();
    let mut checked = 0;
    for g in &staged.scene.instances {
        let axis = tensorglyph::tensor::eigen::quat_to_frame(g.rotation)[0];
        let t = &truth[g.glyph.to_string()];
        let want = t["directions"].as_array().unwrap();
        // This stick's ODF value: its length over the voxel's longest, times sh2peaks' largest.
        let values = floats(&t["values"]);
        let longest = staged
            .scene
            .instances
            .iter()
            .filter(|h| h.glyph == g.glyph)
            .map(|h| f64::from(h.radii[0]))
            .fold(0.0, f64::max);
        let value = f64::from(g.radii[0]) / longest * values[0];
        by_voxel
            .entry(g.glyph)
            .or_default()
            .push(f64::from(g.radii[0]));
        if value < values[values.len() - 1] * (1.0 - 1e-3) {
            continue;
        }
        checked += 1;
        let best = want
            .iter()
            .map(|d| {
                let d = floats(d);
                let c = (axis[0] * d[0] + axis[1] * d[1] + axis[2] * d[2]).abs();
                c.min(1.0).acos().to_degrees()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            best < 1.0,
            "voxel {}: {best}° from sh2peaks' nearest",
            g.glyph
        );
    }
    assert_eq!(by_voxel.len(), 64);
    assert!(checked >= 100, "{checked} sticks checked");
    // The voxel step is 2 mm: each voxel's largest half-length is half of it.
    for (v, lengths) in &by_voxel {
        let top = lengths.iter().copied().fold(0.0, f64::max);
        assert!((top - 1.0).abs() < 1e-5, "voxel {v}: {lengths:?}");
    }
}

/// What `--glyph peaks` refuses, each in one line: tensors off a lattice (a stick is a fraction
/// of its step), `--odf-normalize minmax` (a peak has no minimum), a tensor's colouring, and
/// the viewer (no sticks there yet).
#[test]
fn glyph_peaks_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let beam = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/stress/beam.vtu");
    let dti = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dti/fsl4d_oblique.nii.gz");
    let series = sh("mrtrix_lmax8.mif");
    for (args, says) in [
        (
            vec!["render", beam.to_str().unwrap(), "--glyph", "peaks"],
            "--glyph peaks: the sticks of tensors need a lattice",
        ),
        (
            vec![
                "render",
                dti.to_str().unwrap(),
                "--glyph",
                "peaks",
                "--color",
                "fa",
            ],
            "--color fa: sticks (peaks) are coloured by dec or solid",
        ),
        (
            vec![
                "render",
                series.to_str().unwrap(),
                "--glyph",
                "peaks",
                "--odf-normalize",
                "minmax",
            ],
            "mrtrix_lmax8.mif: --odf-normalize minmax: peaks are normalised by max",
        ),
        (
            vec!["view", series.to_str().unwrap(), "--glyph", "peaks"],
            "--glyph peaks: the viewer does not draw sticks yet",
        ),
    ] {
        let mut all = args.clone();
        if all[0] == "render" {
            all.extend_from_slice(&["-o", out.to_str().unwrap()]);
        }
        let r = tg(&all);
        let e = stderr(&r);
        assert_eq!(r.status.code(), Some(2), "{all:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{all:?}: {e}");
        assert!(e.contains(says), "{all:?}: {e}");
        assert!(!out.exists());
    }
}

/// `--glyph peaks` on tensors: FSL's V1 lines. One stick a valid tensor of DIPY's fit of real
/// DWI (tests/data/dti/dipy_small101), along its glyph's e1 (the eigenvector the ellipsoid's
/// long axis follows), half a voxel step × FA long each side, FA as DIPY computed it
/// (expected.json), coloured by direction.
#[test]
fn tensor_sticks_are_e1_scaled_by_dipys_fa() {
    use tensorglyph::staging::{Recipe, build, decompose, field_spacing};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dti/dipy_small101");
    let field = read_field(&dir.join("tensors.nii.gz"), &ReadOptions::default()).unwrap();
    let silent = tensorglyph::progress::Silent;
    let set = decompose(&field, &silent);
    let recipe = Recipe {
        peaks: true,
        glyph: tensorglyph::shape::GlyphKind::Cylinder,
        style: tensorglyph::glyph::GlyphStyle {
            color: tensorglyph::glyph::ColorScheme::Dec,
            ..Default::default()
        },
        ..Recipe::default()
    };
    let built = build(&field, &set, field_spacing(&field), &recipe, None, &silent).unwrap();
    let truth: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    let fa = floats(&truth["fa"]);
    let step = field.spacing.unwrap();
    let mut n = 0;
    for g in &built.scene.instances {
        let t = &set.glyphs[built.selected[g.glyph as usize]];
        let want_fa = fa[t.index as usize];
        assert!(
            (f64::from(g.radii[0]) - 0.5 * step * want_fa).abs() < 1e-5 * step,
            "tensor {}: half-length {} for FA {want_fa}",
            t.index,
            g.radii[0]
        );
        let axis = tensorglyph::tensor::eigen::quat_to_frame(g.rotation)[0];
        let e1 = tensorglyph::tensor::eigen::quat_to_frame(t.rotation)[0];
        let cos = (0..3).map(|c| axis[c] * e1[c]).sum::<f64>().abs();
        assert!(cos > 1.0 - 1e-6, "tensor {}: {axis:?} {e1:?}", t.index);
        let [r, gr, b, _] = g.color.to_le_bytes();
        let dec = e1.map(|c| (c.abs() * 255.0).round() as u8);
        assert_eq!([r, gr, b], dec, "tensor {}", t.index);
        n += 1;
    }
    assert_eq!(n, set.glyphs.len());
}
