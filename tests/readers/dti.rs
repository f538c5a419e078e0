//! DTI files (NIfTI, NRRD) made by `tests/data/dti/make_dti_files.py`: the same world tensors in
//! every layout and frame read back to numpy's eigenvalues with e1 on the world axis the script
//! put it on; frames and layouts are reported; bad files fail with one line.

use std::path::PathBuf;

use serde_json::Value;
use tensorglyph::field::{
    ComponentOrder, FieldKind, ReadOptions, TensorField, TensorFrame, read_field,
};
use tensorglyph::tensor::eigen::{symmetric_eigen, symmetrise};

use crate::cli::{json, stderr, tg};

fn dti(name: &str) -> PathBuf {
    crate::data::path("dti").join(name)
}

fn expected() -> Value {
    let text = std::fs::read_to_string(dti("expected.json")).expect("tests/data/dti/expected.json");
    serde_json::from_str(&text).unwrap()
}

fn args_of(entry: &Value) -> Vec<String> {
    entry["args"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap().to_string())
        .collect()
}

/// The read options the command line makes of `args` (only the flags the script uses).
fn options(args: &[String]) -> ReadOptions {
    let mut o = ReadOptions::default();
    for w in args.chunks(2) {
        match w[0].as_str() {
            "--order" => o.order = Some(w[1].parse::<ComponentOrder>().unwrap()),
            "--tensor-frame" => o.tensor_frame = Some(w[1].parse::<TensorFrame>().unwrap()),
            "--holds" => o.holds = Some(w[1].parse::<FieldKind>().unwrap()),
            f => panic!("unexpected flag {f}"),
        }
    }
    o
}

/// Eigenvalues (descending) and e1 of tensor `i` in world axes.
fn world_eigen(f: &TensorField, i: usize) -> ([f64; 3], [f64; 3]) {
    let e = symmetric_eigen(&symmetrise(&f.world_tensor(i)).0);
    (e.values, e.vectors[0])
}

/// The field read from `path` holds the tensors of `name` in expected.json: numpy's
/// eigenvalues (to 1e-12 of the largest) with e1 on the world axis the script put it on.
fn agrees_with_numpy(name: &str, f: &TensorField, entry: &Value) {
    let masked: Vec<u64> = entry["masked_voxels"]
        .as_array()
        .map(|a| a.iter().map(|v| v.as_u64().unwrap()).collect())
        .unwrap_or_default();
    let want = entry["eigenvalues"].as_array().unwrap();
    assert_eq!(f.len(), want.len(), "{name}");
    assert_eq!(f.dims, Some([5, 4, 3]), "{name}");
    for (i, w) in want.iter().enumerate() {
        if masked.contains(&(i as u64)) {
            assert!(f.tensor(i).iter().all(|x| *x == 0.0), "{name} #{i} masked");
            continue;
        }
        let (values, e1) = world_eigen(f, i);
        let w: Vec<f64> = w
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let scale = w.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..3 {
            assert!(
                (values[k] - w[k]).abs() <= 1e-12 * scale,
                "{name} #{i} λ{}: {} vs numpy {}",
                k + 1,
                values[k],
                w[k]
            );
        }
        let axis = entry["e1_axis"][i].as_u64().unwrap() as usize;
        assert!(
            e1[axis].abs() > 1.0 - 1e-6,
            "{name} #{i}: e1 {e1:?} is not along world axis {axis}"
        );
    }
}

/// Every file of one family agrees with numpy and puts e1 on its world axis.
fn check_family(ext: &[&str]) -> usize {
    let exp = expected();
    let mut checked = 0;
    for (name, entry) in exp["files"].as_object().unwrap() {
        if !ext.iter().any(|e| name.ends_with(e)) {
            continue;
        }
        let f = read_field(&dti(name), &options(&args_of(entry)))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        agrees_with_numpy(name, &f, entry);
        checked += 1;
    }
    checked
}

#[test]
fn nifti_layouts_read_numpy_eigenvalues_with_e1_on_the_world_axis() {
    assert_eq!(check_family(&[".nii", ".nii.gz"]), 11);
}

#[test]
fn nifti_layouts_of_the_same_stored_tensors_give_identical_glyphs() {
    let tensors = ReadOptions {
        holds: Some(FieldKind::Tensors),
        ..ReadOptions::default()
    };
    let read = |n: &str| read_field(&dti(n), &tensors).unwrap();
    let fsl = read("fsl4d_oblique.nii.gz");
    for other in ["dipy5d_oblique.nii.gz", "full9_oblique.nii.gz"] {
        let f = read(other);
        assert_eq!(f.positions, fsl.positions, "{other}");
        for i in 0..f.len() {
            assert_eq!(world_eigen(&f, i), world_eigen(&fsl, i), "{other} #{i}");
        }
    }
}

/// Nine volumes are a full tensor or three fibre peaks (a NIfTI copy of `sh2peaks` output, as
/// pipelines keep them): a file whose header does not say which is refused in one line that
/// names the option, and read as tensors when it says so.
#[test]
fn nine_volumes_that_nothing_names_are_refused_naming_holds() {
    let path = dti("full9_oblique.nii.gz");
    let e = read_field(&path, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("full9_oblique.nii.gz")
            && e.contains("field 'dim': 9 volumes per voxel")
            && e.ends_with("give --holds tensors or --holds peaks"),
        "{e}"
    );
    let o = tg(&[
        "render",
        path.to_str().unwrap(),
        "-o",
        "never.png",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("--holds tensors or --holds peaks"), "{err}");
}

#[test]
fn layout_and_frame_are_reported_by_info() {
    let cases = [
        (
            "fsl4d_oblique.nii.gz",
            &[][..],
            "fsl",
            "default",
            "voxel",
            "sform",
        ),
        (
            "dipy5d_oblique.nii.gz",
            &[][..],
            "nifti",
            "file",
            "voxel",
            "sform",
        ),
        (
            "full9_oblique.nii.gz",
            &["--holds", "tensors"][..],
            "full",
            "file",
            "voxel",
            "sform",
        ),
        (
            "qform_oblique.nii.gz",
            &[][..],
            "fsl",
            "default",
            "voxel",
            "qform",
        ),
        (
            "mrtrix_oblique.nii.gz",
            &["--order", "mrtrix", "--tensor-frame", "world"][..],
            "mrtrix",
            "flag",
            "world",
            "sform",
        ),
    ];
    let exp = expected();
    for (name, flags, order, why, frame, source) in cases {
        let path = dti(name);
        let mut args = vec!["info", "--json", "--quiet", path.to_str().unwrap()];
        args.extend_from_slice(flags);
        for s in ["--sample", "0", "--sample", "1", "--sample", "2"] {
            args.push(s);
        }
        let o = tg(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let j = json(&o);
        assert_eq!(j["format"], "nifti", "{name}");
        assert_eq!(j["layout"]["order"], order, "{name}");
        assert_eq!(j["layout"]["why"], why, "{name}");
        assert_eq!(j["frame"]["tensor_frame"], frame, "{name}");
        assert_eq!(j["frame"]["source"], source, "{name}");
        assert_eq!(j["frame"]["world"], "RAS", "{name}");
        let m = &j["frame"]["voxel_to_world"];
        assert_eq!(m[3], serde_json::json!([0.0, 0.0, 0.0, 1.0]), "{name}");
        // Translation of the oblique lattice, as the script wrote it.
        assert!(
            (m[0][3].as_f64().unwrap() + 10.0).abs() < 1e-5,
            "{name}: {m}"
        );
        for s in 0..3 {
            let e1 = &j["samples"][s]["eigenvectors"][0];
            let axis = exp["files"][name]["e1_axis"][s].as_u64().unwrap() as usize;
            assert!(
                e1[axis].as_f64().unwrap() > 1.0 - 1e-6,
                "{name} sample {s}: e1 {e1} not along world axis {axis}"
            );
        }
    }
    // The text form says the same.
    let o = tg(&[
        "info",
        "--quiet",
        dti("dipy5d_oblique.nii.gz").to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("layout: nifti (from the file)"), "{text}");
    assert!(
        text.contains("frame: tensors in voxel axes, world RAS from sform"),
        "{text}"
    );
}

#[test]
fn fsl_frame_flips_x_for_a_positive_determinant_only() {
    let exp = expected();
    let axes = |n: &str| -> Vec<usize> {
        exp["files"][n]["e1_axis"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_u64().unwrap() as usize)
            .collect()
    };
    let frame = |f| ReadOptions {
        tensor_frame: Some(f),
        ..ReadOptions::default()
    };
    // Written in FSL's frame on a positive-determinant lattice: right only with the x-flip.
    let name = "fslframe_oblique.nii.gz";
    let a = axes(name);
    let fsl = read_field(&dti(name), &frame(TensorFrame::Fsl)).unwrap();
    let voxel = read_field(&dti(name), &frame(TensorFrame::Voxel)).unwrap();
    let mut off = 0;
    for (i, &axis) in a.iter().enumerate() {
        assert!(world_eigen(&fsl, i).1[axis].abs() > 1.0 - 1e-6);
        off += usize::from(world_eigen(&voxel, i).1[axis].abs() < 0.95);
    }
    assert!(
        off > a.len() / 2,
        "without the flip e1 leaves its axis ({off})"
    );
    // A negative determinant: FSL's frame is the voxel frame.
    let name = "fsl4d_flipped.nii.gz";
    let fsl = read_field(&dti(name), &frame(TensorFrame::Fsl)).unwrap();
    let voxel = read_field(&dti(name), &frame(TensorFrame::Voxel)).unwrap();
    for i in 0..fsl.len() {
        assert_eq!(fsl.world_tensor(i), voxel.world_tensor(i));
    }
}

/// `tensorglyph info FILE` fails with status 2 and one line naming the file and `what`.
fn fails_naming(name: &str, what: &str) {
    let path = dti(name);
    let o = tg(&["info", "--quiet", path.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
    assert!(err.contains(name), "{name}: {err}");
    assert!(err.contains(what), "{name}: expected '{what}' in: {err}");
}

#[test]
fn bad_nifti_files_fail_with_one_line_naming_file_and_field() {
    fails_naming("bad_scalar3d.nii.gz", "field 'dim': a scalar volume");
    fails_naming(
        "bad_five_volumes.nii.gz",
        "field 'dim': 5 volumes per voxel",
    );
    fails_naming("bad_int16.nii.gz", "field 'datatype': 4 (int16)");
    fails_naming("bad_truncated.nii.gz", "gzip data is corrupt or truncated");
    fails_naming("bad_short_data.nii", "field 'dim'");
    // vox_offset 4096 and 60 voxels of six float32 values.
    fails_naming(
        "bad_vox_offset.nii",
        &format!(
            "field 'dim': the header's dimensions and vox_offset need {} bytes",
            4096 + 60 * 6 * 4
        ),
    );
    fails_naming(
        "bad_nifti2.nii.gz",
        "field 'sizeof_hdr': 540: NIfTI-2 is not supported; convert it to NIfTI-1",
    );
}

#[test]
fn nrrd_layouts_frames_and_lps_read_numpy_eigenvalues_with_e1_on_the_world_axis() {
    assert_eq!(check_family(&[".nrrd", ".nhdr"]), 9);
}

#[test]
fn nrrd_confidence_below_half_is_skipped_and_counted() {
    let want = expected()["files"]["nrrd_masked.nrrd"]["masked"]
        .as_u64()
        .unwrap();
    assert!(want > 0);
    let path = dti("nrrd_masked.nrrd");
    let o = tg(&["info", "--json", "--quiet", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["skipped"]["masked"], want);
    assert_eq!(j["skipped"]["zero"], 0);
    assert_eq!(j["valid"].as_u64().unwrap(), 60 - want);
    assert_eq!(j["frame"]["source"], "space directions");
    assert_eq!(j["frame"]["tensor_frame"], "world");
}

#[test]
fn bad_nrrd_files_fail_with_one_line_naming_file_and_field() {
    fails_naming("bad_kinds.nrrd", "field 'kinds': '3D-tensor'");
    fails_naming("bad_missing_detached.nhdr", "field 'data file'");
    fails_naming("bad_short_detached.nhdr", "field 'sizes': need 360 values");
    fails_naming("bad_short_data.nrrd", "field 'sizes': need 360 values");
    fails_naming(
        "bad_components.nrrd",
        "field 'sizes': 5 values per voxel; 3D-symmetric-matrix needs 6",
    );
    fails_naming(
        "bad_scalar3d.nrrd",
        "field 'dimension': 3; a tensor volume has 4 axes",
    );
}

/// The two FSL eigen sets the script wrote (prefix, member files).
fn eigen_sets() -> Vec<(String, Vec<String>)> {
    let exp = expected();
    let sets: Vec<(String, Vec<String>)> = exp["files"]
        .as_object()
        .unwrap()
        .iter()
        .filter_map(|(name, e)| {
            let files = e["eigen_set"].as_array()?;
            Some((
                name.clone(),
                files.iter().map(|f| f.as_str().unwrap().into()).collect(),
            ))
        })
        .collect();
    assert_eq!(sets.len(), 2);
    sets
}

#[test]
fn fsl_eigen_sets_read_numpy_eigenvalues_by_prefix_or_any_member() {
    let exp = expected();
    for (prefix, files) in eigen_sets() {
        let entry = &exp["files"][&prefix];
        let by_prefix = read_field(&dti(&prefix), &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{prefix}: {e}"));
        agrees_with_numpy(&prefix, &by_prefix, entry);
        // The rebuilt tensors have the eigenvalues dtifit stored, to float32's precision
        // (its vectors are unit and orthogonal only to that).
        let stored = entry["stored_eigenvalues"].as_array().unwrap();
        for (i, l) in stored.iter().enumerate() {
            let (values, _) = world_eigen(&by_prefix, i);
            for k in 0..3 {
                let l = l[k].as_f64().unwrap();
                assert!((values[k] - l).abs() <= 1e-6 * l.abs(), "{prefix} #{i}");
            }
        }
        for file in &files {
            let f = read_field(&dti(file), &ReadOptions::default())
                .unwrap_or_else(|e| panic!("{file}: {e}"));
            assert_eq!(f.tensors, by_prefix.tensors, "{file}");
            assert_eq!(f.positions, by_prefix.positions, "{file}");
            assert_eq!(f.direction, by_prefix.direction, "{file}");
        }
    }
}

#[test]
fn fsl_eigen_sets_take_the_tensor_frame_of_fsl_tensors() {
    // The same world tensors as dtifit's tensor file and as its eigen set: the same glyphs,
    // in the default frame and in FSL's.
    for frame in [None, Some(TensorFrame::Fsl), Some(TensorFrame::World)] {
        let o = ReadOptions {
            tensor_frame: frame,
            ..ReadOptions::default()
        };
        let tensor = read_field(&dti("fsl4d_oblique.nii.gz"), &o).unwrap();
        let eigen = read_field(&dti("fsl_eigen_oblique"), &o).unwrap();
        assert_eq!(eigen.positions, tensor.positions);
        assert_eq!(eigen.direction, tensor.direction, "{frame:?}");
        assert_eq!(eigen.meta.frame, tensor.meta.frame, "{frame:?}");
        for i in 0..tensor.len() {
            let (a, b) = (world_eigen(&eigen, i), world_eigen(&tensor, i));
            for k in 0..3 {
                assert!((a.0[k] - b.0[k]).abs() <= 1e-6 * b.0[0], "#{i} {frame:?}");
                assert!(a.1[k].abs() - b.1[k].abs() < 1e-4, "#{i} {frame:?}");
            }
        }
    }
}

#[test]
fn fsl_eigen_layout_is_reported_from_the_file_names() {
    let exp = expected();
    let path = dti("fsl_eigen_oblique");
    let o = tg(&[
        "info",
        "--json",
        "--quiet",
        path.to_str().unwrap(),
        "--sample",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["layout"]["order"], "fsl-eigen");
    assert_eq!(j["layout"]["why"], "names");
    assert_eq!(j["frame"]["tensor_frame"], "voxel");
    assert_eq!(j["frame"]["source"], "sform");
    assert_eq!(
        j["tensor_array"]["name"],
        "fsl_eigen_oblique_{L1,L2,L3,V1,V2,V3}.nii.gz"
    );
    let axis = exp["files"]["fsl_eigen_oblique"]["e1_axis"][1]
        .as_u64()
        .unwrap() as usize;
    let e1 = &j["samples"][0]["eigenvectors"][0];
    assert!(e1[axis].as_f64().unwrap() > 1.0 - 1e-6, "{e1}");
    let o = tg(&[
        "info",
        "--quiet",
        dti("fsl_eigen_flipped_L2.nii").to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("layout: fsl-eigen (from the file names)"),
        "{text}"
    );
}

/// A copy of the oblique eigen set in a new folder, with `change` done to it.
fn eigen_copy(change: impl FnOnce(&std::path::Path)) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let (_, files) = eigen_sets()
        .into_iter()
        .find(|(p, _)| p == "fsl_eigen_oblique")
        .unwrap();
    for f in files {
        std::fs::copy(dti(&f), dir.path().join(&f)).unwrap();
    }
    change(dir.path());
    dir
}

/// `tensorglyph info PATH` fails with status 2 and one line naming `file` and `what`.
fn fails_with(path: &std::path::Path, file: &str, what: &str) {
    let o = tg(&["info", "--quiet", path.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(file), "expected '{file}' in: {err}");
    assert!(err.contains(what), "expected '{what}' in: {err}");
}

#[test]
fn fsl_eigen_sets_with_a_file_missing_or_differing_fail_naming_it() {
    let dir = eigen_copy(|d| std::fs::remove_file(d.join("fsl_eigen_oblique_V3.nii.gz")).unwrap());
    for given in ["fsl_eigen_oblique", "fsl_eigen_oblique_L1.nii.gz"] {
        fails_with(
            &dir.path().join(given),
            "fsl_eigen_oblique_V3.nii.gz: file not found; the files of an FSL eigen set are read together",
            "fsl_eigen_oblique_{L1,L2,L3,V1,V2,V3}.nii.gz",
        );
    }
    // The one named, missing, is just not found.
    fails_with(
        &dir.path().join("fsl_eigen_oblique_V3.nii.gz"),
        "fsl_eigen_oblique_V3.nii.gz: file not found",
        "",
    );
    let dir = eigen_copy(|d| {
        std::fs::copy(
            dti("bad_eigen_other_dims.nii.gz"),
            d.join("fsl_eigen_oblique_L2.nii.gz"),
        )
        .unwrap();
    });
    fails_with(
        &dir.path().join("fsl_eigen_oblique_V1.nii.gz"),
        "fsl_eigen_oblique_L2.nii.gz: field 'dim': 5×4×2 voxels, fsl_eigen_oblique_L1.nii.gz has 5×4×3",
        "share one lattice",
    );
    // Another lattice's V2 (an uncompressed file under the .gz name: the content tells).
    let dir = eigen_copy(|d| {
        std::fs::copy(
            dti("fsl_eigen_flipped_V2.nii"),
            d.join("fsl_eigen_oblique_V2.nii.gz"),
        )
        .unwrap();
    });
    fails_with(
        &dir.path().join("fsl_eigen_oblique"),
        "fsl_eigen_oblique_V2.nii.gz: field 'sform': the voxel-to-world matrix differs from fsl_eigen_oblique_L1.nii.gz's",
        "share one lattice",
    );
    // An eigenvalue map where a vector volume belongs, and a tensor file where a map does.
    let dir = eigen_copy(|d| {
        std::fs::copy(
            d.join("fsl_eigen_oblique_L1.nii.gz"),
            d.join("fsl_eigen_oblique_V1.nii.gz"),
        )
        .unwrap();
        std::fs::copy(
            dti("fsl4d_oblique.nii.gz"),
            d.join("fsl_eigen_oblique_L3.nii.gz"),
        )
        .unwrap();
    });
    fails_with(
        &dir.path().join("fsl_eigen_oblique_L1.nii.gz"),
        "fsl_eigen_oblique_L3.nii.gz: field 'dim': 6 values per voxel; FSL's _L3 is a 3-D map",
        "",
    );
    std::fs::copy(
        dti("fsl_eigen_oblique_L3.nii.gz"),
        dir.path().join("fsl_eigen_oblique_L3.nii.gz"),
    )
    .unwrap();
    fails_with(
        &dir.path().join("fsl_eigen_oblique_L1.nii.gz"),
        "fsl_eigen_oblique_V1.nii.gz: field 'dim': one value per voxel; FSL's _V1 is a 4-D volume of 3",
        "",
    );
}

#[test]
fn ants_tensors_are_read_by_their_intent_and_itk_vectors_in_itk_order() {
    let info = |name: &str, flags: &[&str]| {
        let path = dti(name);
        let mut args = vec!["info", "--json", "--quiet", path.to_str().unwrap()];
        args.extend_from_slice(flags);
        let o = tg(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        json(&o)
    };
    let j = info("ants5d_oblique.nii.gz", &["--order", "mrtrix"]);
    assert_eq!(
        j["layout"]["order"], "nifti",
        "the intent wins over --order"
    );
    assert_eq!(j["layout"]["why"], "file");
    assert_eq!(j["frame"]["tensor_frame"], "voxel");
    let j = info("itk5d_vector_oblique.nii.gz", &[]);
    assert_eq!(j["layout"]["order"], "fsl");
    assert_eq!(j["layout"]["why"], "default");
    let j = info("itk5d_vector_oblique.nii.gz", &["--order", "nifti"]);
    assert_eq!(j["layout"]["order"], "nifti");
    assert_eq!(j["layout"]["why"], "flag");
    // Read as the lower triangle, the upper triangle's numbers are other tensors.
    let o = ReadOptions {
        order: Some(ComponentOrder::Nifti),
        ..ReadOptions::default()
    };
    let wrong = read_field(&dti("itk5d_vector_oblique.nii.gz"), &o).unwrap();
    let right = read_field(&dti("ants5d_oblique.nii.gz"), &ReadOptions::default()).unwrap();
    let moved = (0..right.len())
        .filter(|&i| (world_eigen(&wrong, i).0[0] - world_eigen(&right, i).0[0]).abs() > 1e-6)
        .count();
    assert!(moved > right.len() / 2, "{moved}");
}
