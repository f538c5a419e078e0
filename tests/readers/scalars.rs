//! Scalar volumes (`read_scalar_volume`) in every format, against writers and readers other than
//! ours: NIfTI written and read back by nibabel, NRRD written by Teem's `unu` with numpy's RAS
//! matrix, VTK image data written and read back by VTK 9.1 (`tests/data/scalars/make_*.py`). A
//! volume written beside a tensor file lines up with the tensors voxel for voxel; bad files fail
//! with one line naming the file and what is wrong.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::Value;
use tensorglyph::field::scalar::ScalarVolume;
use tensorglyph::field::{Location, ReadOptions, read_field, read_scalar_volume};
use tensorglyph::select::lattice_coords;

use crate::data;

fn scalars(name: &str) -> PathBuf {
    data::path("scalars").join(name)
}

fn load_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn read(path: &Path) -> ScalarVolume {
    read_scalar_volume(path).unwrap_or_else(|e| panic!("{e}"))
}

/// World position of voxel `ijk` through the volume's matrix.
fn world_of(v: &ScalarVolume, ijk: [usize; 3]) -> [f64; 3] {
    let m = &v.voxel_to_world;
    std::array::from_fn(|r| (0..3).map(|c| m[r][c] * ijk[c] as f64).sum::<f64>() + m[r][3])
}

/// Every NIfTI or NRRD file of `expected.json` whose name ends with one of `ext`: nibabel's
/// (or numpy's) values, exactly as f32, and the RAS matrix numpy gives.
fn check_expected(ext: &[&str], matrix_tol: f64) -> usize {
    let exp = load_json(&scalars("expected.json"));
    let mut checked = 0;
    for (name, entry) in exp["files"].as_object().unwrap() {
        if !ext.iter().any(|e| name.ends_with(e)) {
            continue;
        }
        let v = read(&scalars(name));
        let dims = floats(&entry["dims"]);
        assert_eq!(v.dims.map(|d| d as f64).to_vec(), dims, "{name}");
        let want = floats(&entry["values"]);
        assert_eq!(v.values.len(), want.len(), "{name}");
        for (i, (&got, &w)) in v.values.iter().zip(&want).enumerate() {
            assert_eq!(got, w as f32, "{name} voxel {i}: {got} vs {w}");
        }
        let m = &entry["voxel_to_world"];
        for r in 0..4 {
            for c in 0..4 {
                let w = m[r][c].as_f64().unwrap();
                assert!(
                    (v.voxel_to_world[r][c] - w).abs() <= matrix_tol,
                    "{name} [{r}][{c}]: {} vs {w}",
                    v.voxel_to_world[r][c]
                );
            }
        }
        checked += 1;
    }
    checked
}

#[test]
fn nifti_scalars_of_every_datatype_read_nibabels_values_and_affine() {
    // sform matrices are the header's float32 numbers in both readers: exact. The qform is
    // computed from the quaternion by each reader in its own order of operations.
    assert_eq!(check_expected(&[".nii", ".nii.gz"], 1e-5), 8);
}

#[test]
fn nrrd_scalars_of_every_encoding_read_teems_values_in_ras() {
    assert_eq!(check_expected(&[".nrrd", ".nhdr"], 1e-12), 5);
}

/// The tensors of `tensor_file` and the volume `scalar_file` share the world: the same matrix,
/// and the volume's value at each tensor's position is that voxel's, `value_of(i)`.
fn lines_up(tensor_file: &str, scalar_file: &Path, value_of: impl Fn(usize) -> f32) {
    let f = read_field(&data::path(tensor_file), &ReadOptions::default()).unwrap();
    let v = read(scalar_file);
    let frame = f.meta.frame.as_ref().unwrap();
    assert_eq!(frame.world, "RAS");
    assert_eq!(
        frame.voxel_to_world,
        Some(v.voxel_to_world),
        "{tensor_file}"
    );
    assert_eq!(f.dims, Some(v.dims));
    for (i, p) in f.positions.iter().enumerate() {
        assert_eq!(
            v.nearest(DVec3::from_array(p)),
            Some(value_of(i)),
            "{tensor_file} voxel {i} at {p:?}"
        );
    }
}

#[test]
fn a_scalar_volume_beside_a_tensor_file_lines_up_voxel_for_voxel() {
    // unu wrote this volume with nrrd_gzip_lps.nrrd's LPS geometry; voxel i holds i.
    lines_up(
        "dti/nrrd_gzip_lps.nrrd",
        &scalars("lps_f32_gzip.nrrd"),
        |i| i as f32,
    );
    // nibabel wrote these with fsl4d_oblique.nii.gz's affine as their sform (3-D, and 4-D
    // with one volume).
    for name in ["u8.nii.gz", "f32_4d1.nii.gz"] {
        let v = read(&scalars(name));
        lines_up("dti/fsl4d_oblique.nii.gz", &scalars(name), |i| v.values[i]);
    }
}

#[test]
fn vtk_scalars_read_vtks_values_at_vtks_points() {
    let exp = load_json(&scalars("expected_vtk.json"));
    let files = exp["files"].as_object().unwrap();
    assert_eq!(files.len(), 3);
    for (name, entry) in files {
        let v = read(&scalars(name));
        let dims: Vec<usize> = floats(&entry["dims"]).iter().map(|&d| d as usize).collect();
        assert_eq!(v.dims.to_vec(), dims, "{name}");
        let values = floats(&entry["values"]);
        let positions = entry["positions"].as_array().unwrap();
        assert_eq!(v.values.len(), values.len(), "{name}");
        for (n, w) in values.iter().enumerate() {
            assert_eq!(v.values[n], *w as f32, "{name} point {n}");
            let p = world_of(&v, lattice_coords(n, v.dims));
            let want = floats(&positions[n]);
            for a in 0..3 {
                assert!(
                    (p[a] - want[a]).abs() <= 1e-9 * (1.0 + want[a].abs()),
                    "{name} point {n}: {p:?} vs VTK {want:?}"
                );
            }
        }
    }
}

#[test]
fn image_data_of_the_tensor_tests_reads_its_pressure_where_the_tensor_reader_puts_points() {
    // tests/data/vtk/make_vtk_files.py gives every image its one-component point array
    // "pressure" = 0.5 i, first, in every encoding and compressor VTK writes.
    let mut checked = 0;
    for entry in std::fs::read_dir(data::path("vtk")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let image = name.contains("_image_") && (name.ends_with(".vtk") || name.ends_with(".vti"));
        if !image {
            continue;
        }
        let v = read(&path);
        for (i, x) in v.values.iter().enumerate() {
            assert_eq!(*x, 0.5 * i as f32, "{name} point {i}");
        }
        let f = read_field(&path, &ReadOptions::default()).unwrap();
        if f.array.location == Location::Point {
            assert_eq!(f.dims, Some(v.dims), "{name}");
            for (i, p) in f.positions.iter().enumerate() {
                let q = world_of(&v, lattice_coords(i, v.dims));
                for a in 0..3 {
                    assert!(
                        (p[a] - q[a]).abs() <= 1e-12,
                        "{name} point {i}: {p:?} {q:?}"
                    );
                }
            }
        }
        checked += 1;
    }
    assert!(checked >= 20, "{checked} image files");
}

/// `read_scalar_volume(path)` fails with one line naming the file and containing `what`.
fn fails(path: &Path, what: &str) {
    let e = read_scalar_volume(path)
        .map(|v| format!("read {:?} voxels", v.dims))
        .expect_err(&format!("{path:?} should fail"))
        .to_string();
    assert_eq!(e.lines().count(), 1, "{e}");
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(e.contains(name.as_ref()), "{e}");
    assert!(e.contains(what), "expected '{what}' in: {e}");
}

#[test]
fn bad_scalar_inputs_fail_with_one_line_naming_the_file_and_the_field() {
    let tensor = "6 values per voxel: a tensor volume, not a scalar volume";
    fails(
        &data::path("dti/fsl4d_oblique.nii.gz"),
        &format!("field 'dim': {tensor}"),
    );
    fails(
        &data::path("dti/dipy5d_oblique.nii.gz"),
        &format!("field 'dim': {tensor}"),
    );
    fails(
        &data::path("dti/full9_oblique.nii.gz"),
        "field 'dim': 9 values per voxel",
    );
    fails(
        &data::path("dti/nrrd_raw_oblique.nrrd"),
        "field 'dimension': 4 axes, '3D-symmetric-matrix' first: a tensor volume",
    );
    fails(
        &scalars("bad_two_volumes.nii.gz"),
        "field 'dim': 2 values per voxel",
    );
    fails(
        &scalars("bad_complex.nii.gz"),
        "field 'datatype': 32 (complex)",
    );
    fails(
        &scalars("bad_short.nii"),
        "field 'dim': the header's dimensions",
    );
    fails(
        &scalars("bad_truncated.nii.gz"),
        "gzip data is corrupt or truncated",
    );
    fails(&scalars("bad_short.nrrd"), "field 'sizes': need 60 values");
    fails(
        &scalars("bad_rgb.nrrd"),
        "field 'kinds': '3-color' on axis 0",
    );
    fails(
        &scalars("bad_vectors_only.vti"),
        "no one-component point-data array to read as a scalar volume; arrays present: 'vec' (3 components, point)",
    );
    fails(
        &data::path("vtk/xml_ugrid_appraw_zlib_u32.vtu"),
        "UnstructuredGrid: a scalar volume is image data",
    );
    fails(
        &data::path("vtk/pvti_2pieces_appended.pvti"),
        "parallel XML file",
    );
    fails(&scalars("no_such_file.nii.gz"), "file not found");

    // Cut short anywhere, every format fails cleanly or, where only what follows the data
    // went (a .vti's unused arrays and closing tags), reads the whole volume: never a panic,
    // never a partial volume.
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "image_extent_dir.vti",
        "image_u8.vtk",
        "lps_f32_gzip.nrrd",
        "u8.nii.gz",
    ] {
        let bytes = std::fs::read(scalars(name)).unwrap();
        let whole = read(&scalars(name));
        let p = dir.path().join(name);
        let mut failed = 0;
        for keep in (0..bytes.len()).step_by(3) {
            std::fs::write(&p, &bytes[..keep]).unwrap();
            match read_scalar_volume(&p) {
                Ok(v) => assert_eq!(v, whole, "{name} cut to {keep} bytes"),
                Err(e) => {
                    let e = e.to_string();
                    assert_eq!(e.lines().count(), 1, "{e}");
                    assert!(
                        e.contains(name) && !e.contains("internal reader error"),
                        "{e}"
                    );
                    failed += 1;
                }
            }
        }
        assert!(failed > bytes.len() / 3 / 2, "{name}: {failed} cuts failed");
    }
}

#[test]
fn corrupted_scalar_files_fail_cleanly_or_read_a_whole_volume() {
    // One bit flipped in every byte in turn (a different bit each time), in every good file.
    let mut names: Vec<String> = Vec::new();
    for json in ["expected.json", "expected_vtk.json"] {
        let exp = load_json(&scalars(json));
        names.extend(exp["files"].as_object().unwrap().keys().cloned());
    }
    let dir = tempfile::tempdir().unwrap();
    for name in &names {
        let bytes = std::fs::read(scalars(name)).unwrap();
        // A detached header keeps its data file's name: the copy sits beside the data.
        let p = if name.ends_with(".nhdr") {
            let raw = name.replace(".nhdr", ".raw");
            std::fs::copy(scalars(&raw), dir.path().join(&raw)).unwrap();
            dir.path().join(name)
        } else {
            dir.path().join(name)
        };
        for at in 0..bytes.len() {
            let mut b = bytes.clone();
            b[at] ^= 1 << (at % 8);
            std::fs::write(&p, &b).unwrap();
            match read_scalar_volume(&p) {
                Ok(v) => assert_eq!(
                    v.values.len(),
                    v.dims.iter().product::<usize>(),
                    "{name} flipped at {at}"
                ),
                Err(e) => {
                    let e = e.to_string();
                    assert_eq!(e.lines().count(), 1, "{e}");
                    assert!(!e.contains("internal reader error"), "{name} at {at}: {e}");
                }
            }
        }
    }
}
