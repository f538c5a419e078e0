//! Real diffusion data end to end: DIPY's tensor fit of its `small_101D` DWI, written by DIPY's own
//! `dipy_fit_dti` workflow, with its FA map, mean b0 and two masks beside it
//! (`tests/data/dti/make_dipy_fit.py`; numpy's truth in
//! `tests/data/dti/dipy_small101/expected.json`).
//!
//! The tensors read to numpy's eigenvalues; the scalar volumes read to nibabel's values and
//! line up with the glyphs voxel for voxel; glyph FA is DIPY's FA; `--mask` keeps the voxels
//! numpy's own nearest-voxel rule keeps, on the tensors' lattice and on a coarser shifted one.

use std::path::PathBuf;

use glam::DVec3;
use serde_json::Value;
use tensorglyph::field::{ReadOptions, TensorField, read_field, read_scalar_volume};
use tensorglyph::glyph::{GlyphSet, derive_glyphs};
use tensorglyph::select::{Mask, Selection, lattice_coords};
use tensorglyph::tensor::eigen::{symmetric_eigen, symmetrise};
use tensorglyph::tensor::shape;

use crate::cli::{json, stderr, tg};
use crate::data;

fn data(name: &str) -> PathBuf {
    data::path("dti/dipy_small101").join(name)
}

fn expected() -> Value {
    let text = std::fs::read_to_string(data("expected.json")).expect("expected.json");
    serde_json::from_str(&text).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn indices(v: &Value) -> Vec<u32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as u32)
        .collect()
}

fn tensors() -> (TensorField, GlyphSet) {
    let f = read_field(&data("tensors.nii.gz"), &ReadOptions::default()).unwrap();
    let set = derive_glyphs(&f, &tensorglyph::Silent);
    assert_eq!(set.glyphs.len(), 600, "every voxel was fitted");
    (f, set)
}

#[test]
fn dipy_tensors_read_numpys_eigenvalues_at_nibabels_positions() {
    let exp = expected();
    let (f, _) = tensors();
    assert_eq!(f.dims, Some([6, 10, 10]));
    let layout = f.meta.layout.as_ref().unwrap();
    assert_eq!(layout.order, "nifti", "5-D lower triangle, from the intent");
    let eig = exp["eigenvalues"].as_array().unwrap();
    let affine: Vec<Vec<f64>> = exp["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(floats)
        .collect();
    assert_eq!(f.len(), eig.len());
    for (i, want) in eig.iter().enumerate() {
        let got = symmetric_eigen(&symmetrise(&f.world_tensor(i)).0).values;
        let want = floats(want);
        let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() <= 1e-12 * scale,
                "voxel {i} λ{}: {} vs numpy {}",
                k + 1,
                got[k],
                want[k]
            );
        }
        let ijk = lattice_coords(i, [6, 10, 10]).map(|c| c as f64);
        for (a, row) in affine.iter().take(3).enumerate() {
            let p = (0..3).map(|c| row[c] * ijk[c]).sum::<f64>() + row[3];
            assert!(
                (f.position(i)[a] - p).abs() <= 1e-9,
                "voxel {i}: {:?}, nibabel's affine puts it at {a}: {p}",
                f.position(i)
            );
        }
    }
}

#[test]
fn fa_and_b0_volumes_read_nibabels_values() {
    let exp = expected();
    for (file, key) in [("fa.nii.gz", "fa_file"), ("b0.nii.gz", "b0_file")] {
        let v = read_scalar_volume(&data(file)).unwrap();
        assert_eq!(v.dims, [6, 10, 10], "{file}");
        let want = floats(&exp[key]);
        assert_eq!(v.values.len(), want.len(), "{file}");
        for (i, (got, w)) in v.values.iter().zip(&want).enumerate() {
            assert_eq!(*got, *w as f32, "{file} voxel {i}");
        }
    }
}

#[test]
fn glyph_fa_is_dipys_and_the_fa_map_under_each_glyph_is_its_voxels() {
    let exp = expected();
    let dipy_fa = floats(&exp["fa"]);
    let (f, set) = tensors();
    let fa_map = read_scalar_volume(&data("fa.nii.gz")).unwrap();
    for g in &set.glyphs {
        let i = g.index as usize;
        // The tensors' eigenvalues in f64, and the glyph's (stored as f32).
        let exact = shape::fa(symmetric_eigen(&symmetrise(&f.world_tensor(i)).0).values);
        assert!(
            (exact - dipy_fa[i]).abs() <= 1e-10,
            "voxel {i}: {exact} vs DIPY {}",
            dipy_fa[i]
        );
        let glyph = shape::fa(g.eigenvalues.map(f64::from));
        assert!(
            (glyph - dipy_fa[i]).abs() <= 1e-6,
            "voxel {i}: {glyph} vs DIPY {}",
            dipy_fa[i]
        );
        // Same lattice: the nearest voxel of the FA map is the glyph's own.
        let sampled = fa_map.nearest(DVec3::from_array(g.centre)).unwrap();
        assert_eq!(sampled, fa_map.values[i], "voxel {i}");
        assert!((f64::from(sampled) - dipy_fa[i]).abs() <= 1e-6, "voxel {i}");
    }
}

/// File-order indices of the glyphs `mask` keeps.
fn kept_by(mask: &str) -> Vec<u32> {
    let (f, set) = tensors();
    let sel = Selection {
        mask: Some(Mask::read(&data(mask)).unwrap()),
        ..Selection::default()
    };
    sel.check_field(&f).unwrap();
    sel.select(&f, &set)
        .into_iter()
        .map(|k| set.glyphs[k].index)
        .collect()
}

#[test]
fn a_mask_on_the_tensors_lattice_keeps_exactly_its_non_zero_voxels() {
    let want = indices(&expected()["mask_kept"]);
    assert!(!want.is_empty() && want.len() < 600);
    assert_eq!(kept_by("mask.nii.gz"), want);
}

#[test]
fn a_coarser_shifted_mask_keeps_the_voxels_numpys_nearest_voxel_rule_keeps() {
    let exp = expected();
    let want = indices(&exp["mask_coarse_kept"]);
    assert!(exp["mask_coarse_outside"].as_u64().unwrap() > 0);
    assert_eq!(kept_by("mask_coarse.nii.gz"), want);
}

/// `render` of the DIPY tensors (every voxel), small and on the CPU, with `extra` flags.
fn render(extra: &[&str]) -> (std::process::Output, bool) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.png");
    let tensors = data("tensors.nii.gz");
    let mut args = vec![
        "render",
        tensors.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "64x48",
        "--method",
        "reference",
        // The whole lattice: DTI files otherwise open on their middle axial slice.
        "--slice",
        "all",
        "--json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = tg(&args);
    let written = out.exists();
    (o, written)
}

#[test]
fn render_mask_draws_the_masked_glyphs() {
    let exp = expected();
    let mask = data("mask.nii.gz");
    let (o, written) = render(&["--mask", mask.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(written);
    let j = json(&o);
    let want = exp["mask_kept"].as_array().unwrap().len() as u64;
    assert_eq!(j["glyphs_selected"], want);
    assert_eq!(j["glyphs_total"], 600);
    // With an FA bound too: the intersection.
    let (o, _) = render(&["--mask", mask.to_str().unwrap(), "--fa-min", "0.6"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let fa = floats(&exp["fa"]);
    let both = indices(&exp["mask_kept"])
        .iter()
        .filter(|&&i| fa[i as usize] >= 0.6)
        .count() as u64;
    assert!(both > 0 && both < want);
    // The glyph FA is within 1e-6 of DIPY's: no voxel sits that close to the bound.
    assert!(fa.iter().all(|x| (x - 0.6).abs() > 1e-5));
    assert_eq!(json(&o)["glyphs_selected"], both);
}

/// A failing `render --mask` run: status 2, one line, no image; the line.
fn render_fails(mask: &std::path::Path) -> String {
    let (o, written) = render(&["--mask", mask.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(!written, "no image on error");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

#[test]
fn render_with_a_bad_mask_stops_with_one_line_naming_it() {
    // A tensor file where a mask belongs.
    let e = render_fails(&data::path("dti/fsl4d_oblique.nii.gz"));
    assert!(e.contains("--mask"), "{e}");
    assert!(e.contains("fsl4d_oblique.nii.gz"), "{e}");
    assert!(
        e.contains("field 'dim': 6 values per voxel: a tensor volume"),
        "{e}"
    );
    let e = render_fails(&data::path("dti/no_such_mask.nii.gz"));
    assert!(e.contains("no_such_mask.nii.gz: file not found"), "{e}");
    let e = render_fails(&data::path("scalars/bad_truncated.nii.gz"));
    assert!(e.contains("bad_truncated.nii.gz"), "{e}");
    // A good volume in another part of the world keeps nothing: said as the selection.
    let e = render_fails(&data::path("scalars/u8.nii.gz"));
    assert!(
        e.contains("the selection keeps no glyph: --mask ")
            && e.contains("u8.nii.gz leaves none of the 600 valid glyphs"),
        "{e}"
    );
}
