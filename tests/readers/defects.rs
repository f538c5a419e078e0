//! Named regression tests of the reader defects issue 30's mutation campaign found (the NIfTI,
//! NRRD, FSL-eigen, `--underlay` and `--mask` readers), one test (or more) per defect, each
//! named for what it guards. Inputs are copied into a temporary folder: nothing under `tests/`
//! is ever written.

use std::path::{Path, PathBuf};

use crate::cli::{stderr, tg};

fn dti(name: &str) -> PathBuf {
    crate::data::path("dti").join(name)
}

fn data(name: &str) -> PathBuf {
    crate::data::path("vtk").join(name)
}

fn copy(from: &Path, dir: &Path) -> PathBuf {
    let to = dir.join(from.file_name().unwrap());
    std::fs::copy(from, &to).unwrap();
    to
}

/// `render` with `args` fails with status 2 and one line saying the output is an input file,
/// and `protected` is as it was.
fn refused(args: &[&str], protected: &Path) {
    let before = std::fs::read(protected).unwrap();
    let o = tg(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("is the input file"), "{err}");
    assert_eq!(
        std::fs::read(protected).unwrap(),
        before,
        "{} was replaced",
        protected.display()
    );
}

// Defect 2: `-o` and `--diff` replaced inputs other than the named file and `--underlay`.

#[test]
fn outputs_never_replace_the_mask_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = crate::data::path("dti/dipy_small101");
    let tensors = copy(&d.join("tensors.nii.gz"), dir.path());
    let mask = copy(&d.join("mask.nii.gz"), dir.path());
    let (t, m) = (tensors.to_str().unwrap(), mask.to_str().unwrap());
    let size = ["--size", "64x48", "--quiet"];
    refused(
        &[&["render", t, "--mask", m, "-o", m][..], &size].concat(),
        &mask,
    );
    let out = dir.path().join("out.png");
    let out = out.to_str().unwrap();
    refused(
        &[
            &[
                "render",
                t,
                "--mask",
                m,
                "-o",
                out,
                "--reference-check",
                "--diff",
                m,
            ][..],
            &size,
        ]
        .concat(),
        &mask,
    );
}

#[test]
fn outputs_never_replace_a_detached_nrrd_data_file() {
    let dir = tempfile::tempdir().unwrap();
    let nhdr = copy(&dti("nrrd_detached.nhdr"), dir.path());
    let raw = copy(&dti("nrrd_detached.raw"), dir.path());
    refused(
        &[
            "render",
            nhdr.to_str().unwrap(),
            "-o",
            raw.to_str().unwrap(),
            "--size",
            "64x48",
        ],
        &raw,
    );
    // A symlink to the data file is the data file.
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink(&raw, &link).unwrap();
    refused(
        &[
            "render",
            nhdr.to_str().unwrap(),
            "-o",
            link.to_str().unwrap(),
            "--size",
            "64x48",
        ],
        &raw,
    );
}

#[test]
fn outputs_never_replace_a_member_of_an_fsl_eigen_set() {
    let dir = tempfile::tempdir().unwrap();
    let members: Vec<PathBuf> = ["L1", "L2", "L3", "V1", "V2", "V3"]
        .iter()
        .map(|m| copy(&dti(&format!("fsl_eigen_oblique_{m}.nii.gz")), dir.path()))
        .collect();
    let prefix = dir.path().join("fsl_eigen_oblique");
    for (k, member) in members.iter().enumerate() {
        // By the prefix, and by another member's name.
        let named = [prefix.clone(), members[(k + 1) % members.len()].clone()];
        for n in named {
            refused(
                &[
                    "render",
                    n.to_str().unwrap(),
                    "-o",
                    member.to_str().unwrap(),
                    "--size",
                    "64x48",
                ],
                member,
            );
        }
    }
}

#[test]
fn outputs_never_replace_a_pvti_piece() {
    let dir = tempfile::tempdir().unwrap();
    let pvti = copy(&data("pvti_3pieces_binary.pvti"), dir.path());
    let pieces: Vec<PathBuf> = (0..3)
        .map(|k| copy(&data(&format!("pvti_3pieces_binary_{k}.vti")), dir.path()))
        .collect();
    for piece in &pieces {
        refused(
            &[
                "render",
                pvti.to_str().unwrap(),
                "-o",
                piece.to_str().unwrap(),
                "--size",
                "64x48",
            ],
            piece,
        );
    }
}

#[test]
fn the_library_records_every_file_a_read_opens() {
    use tensorglyph::field::{Inputs, ReadOptions, read_field_from};
    let inputs = Inputs::file_system();
    read_field_from(&inputs, &dti("nrrd_detached.nhdr"), &ReadOptions::default()).unwrap();
    assert_eq!(
        inputs.paths_read(),
        [dti("nrrd_detached.nhdr"), dti("nrrd_detached.raw")]
    );
    let inputs = Inputs::file_system();
    read_field_from(&inputs, &dti("fsl_eigen_oblique"), &ReadOptions::default()).unwrap();
    let want: Vec<PathBuf> = ["L1", "L2", "L3", "V1", "V2", "V3"]
        .iter()
        .map(|m| dti(&format!("fsl_eigen_oblique_{m}.nii.gz")))
        .collect();
    assert_eq!(inputs.paths_read(), want);
}

#[test]
fn named_buffers_read_as_the_files_do() {
    use tensorglyph::field::{Inputs, ReadOptions, read_field, read_field_from};
    // A detached header and its data, handed over by name (as a browser or Python would).
    let inputs = Inputs::named([
        (
            "in/d.nhdr".to_string(),
            std::fs::read(dti("nrrd_detached.nhdr")).unwrap(),
        ),
        (
            "in/nrrd_detached.raw".to_string(),
            std::fs::read(dti("nrrd_detached.raw")).unwrap(),
        ),
    ]);
    let opts = ReadOptions::default();
    let f = read_field_from(&inputs, Path::new("in/d.nhdr"), &opts).unwrap();
    let want = read_field(&dti("nrrd_detached.nhdr"), &opts).unwrap();
    assert_eq!(f.tensors, want.tensors);
    assert_eq!(f.positions, want.positions);
    // Without its data file the header says which file is missing, as on disk.
    let alone = Inputs::named([(
        "d.nhdr".to_string(),
        std::fs::read(dti("nrrd_detached.nhdr")).unwrap(),
    )]);
    let e = read_field_from(&alone, Path::new("d.nhdr"), &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("nrrd_detached.raw: file not found"), "{e}");
}
