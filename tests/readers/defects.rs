//! Named regression tests of the reader defects issue 30's mutation campaign found (the NIfTI,
//! NRRD, FSL-eigen, `--underlay` and `--mask` readers), one test (or more) per defect, each
//! named for what it guards. Inputs are copied into a temporary folder: nothing under `tests/`
//! is ever written.

use std::path::{Path, PathBuf};

use crate::cli::{stderr, tg};

fn dti(name: &str) -> PathBuf {
    crate::data::path("dti").join(name)
}

fn vtk(name: &str) -> PathBuf {
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
    let d = dti("dipy_small101");
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
    let pvti = copy(&vtk("pvti_3pieces_binary.pvti"), dir.path());
    let pieces: Vec<PathBuf> = (0..3)
        .map(|k| copy(&vtk(&format!("pvti_3pieces_binary_{k}.vti")), dir.path()))
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

// Helpers for the files the tests below write: NIfTI-1 headers edited from files nibabel wrote,
// gzip streams made by flate2, NRRD headers as text.

fn gz(data: &[u8]) -> Vec<u8> {
    use std::io::Write as _;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

fn gunzip(data: &[u8]) -> Vec<u8> {
    use std::io::Read as _;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(data)
        .read_to_end(&mut out)
        .unwrap();
    out
}

/// The first 352 bytes (header and extension flag) of a little-endian NIfTI-1 file nibabel
/// wrote, with `dim` set to `dims` (dim[0], their count, set from it).
fn nifti_header(from: &Path, dims: &[i16]) -> Vec<u8> {
    let raw = std::fs::read(from).unwrap();
    let raw = if raw.starts_with(&[0x1f, 0x8b]) {
        gunzip(&raw)
    } else {
        raw
    };
    let mut h = raw[..352].to_vec();
    assert_eq!(i32::from_le_bytes(h[0..4].try_into().unwrap()), 348);
    h[40..56].fill(0);
    h[40..42].copy_from_slice(&(dims.len() as i16).to_le_bytes());
    for (k, d) in dims.iter().enumerate() {
        h[42 + 2 * k..44 + 2 * k].copy_from_slice(&d.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h
}

/// `members` gzip members, each `chunk` zero bytes: a stream that inflates to
/// `members × chunk` bytes from about a thousandth of that.
fn gz_zeros(members: usize, chunk: usize) -> Vec<u8> {
    gz(&vec![0u8; chunk]).repeat(members)
}

/// The error line of reading the tensor file `path`.
fn field_error(path: &Path) -> String {
    use tensorglyph::field::{ReadOptions, read_field};
    read_field(path, &ReadOptions::default())
        .map(|f| panic!("{} read, {} tensors", path.display(), f.tensors.len()))
        .unwrap_err()
        .to_string()
}

/// One clean error line, exit status 2, containing `want`, for `tensorglyph args`.
fn fails_with(args: &[&str], want: &str) {
    let o = tg(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(want), "{args:?}: want '{want}' in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

// Defect 1: decompression bombs. A small gzip file with an honest header inflated to what the
// header asked (and the expansions multiplied it); the work is now bounded before inflating.

#[test]
fn a_gzip_nifti_asking_for_more_than_its_budget_is_refused_before_inflating() {
    let dir = tempfile::tempdir().unwrap();
    // 256×256×256 voxels of six float32: 403 MB asked for by about 100 kB of gzip.
    let head = nifti_header(&dti("fsl4d_plain.nii"), &[256, 256, 256, 6]);
    let bomb = dir.path().join("bomb.nii.gz");
    std::fs::write(&bomb, [gz(&head), gz_zeros(100, 1 << 20)].concat()).unwrap();
    let e = field_error(&bomb);
    assert!(e.contains("budget") || e.contains("can hold"), "{e}");
    fails_with(&["info", bomb.to_str().unwrap()], "gzip-compressed bytes");
}

#[test]
fn a_gzip_stream_inflating_past_its_budget_after_the_data_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // An honest 2×2×2 header and its data, then 100 MiB of zeros in further members.
    let head = nifti_header(&dti("fsl4d_plain.nii"), &[2, 2, 2, 6]);
    let data = vec![0u8; 2 * 2 * 2 * 6 * 4];
    let bomb = dir.path().join("tail.nii.gz");
    std::fs::write(
        &bomb,
        [gz(&[head, data].concat()), gz_zeros(100, 1 << 20)].concat(),
    )
    .unwrap();
    let e = field_error(&bomb);
    assert!(e.contains("inflates to more than"), "{e}");
}

#[test]
fn a_gzip_mask_or_underlay_bomb_is_refused_before_inflating() {
    use tensorglyph::field::read_scalar_volume;
    let dir = tempfile::tempdir().unwrap();
    let mask = dti("dipy_small101/mask.nii.gz");
    // 1024×1024×128 bytes (134 MB) from about 130 kB.
    let head = nifti_header(&mask, &[1024, 1024, 128]);
    let bomb = dir.path().join("mask.nii.gz");
    std::fs::write(&bomb, [gz(&head), gz_zeros(128, 1 << 20)].concat()).unwrap();
    let e = read_scalar_volume(&bomb).unwrap_err().to_string();
    assert!(e.contains("budget"), "{e}");
    let tensors = dti("dipy_small101/tensors.nii.gz");
    for option in ["--mask", "--underlay"] {
        fails_with(
            &[
                "render",
                tensors.to_str().unwrap(),
                option,
                bomb.to_str().unwrap(),
                "-o",
                dir.path().join("o.png").to_str().unwrap(),
                "--size",
                "32x32",
                "--method",
                "reference",
            ],
            "budget",
        );
    }
    assert!(!dir.path().join("o.png").exists());
}

// Defect 3: gzip integrity was never checked (reading stopped at the bytes the header needed).

#[test]
fn a_gzip_nifti_with_a_bad_crc_flipped_data_or_trailing_garbage_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(dti("fsl4d_oblique.nii.gz")).unwrap();
    let path = dir.path().join("t.nii.gz");
    let mut cases: Vec<(String, Vec<u8>)> = Vec::new();
    // The CRC-32 (8 to 5 bytes from the end) and the size (the last 4).
    for back in [8, 5, 4, 1] {
        let mut b = good.clone();
        let at = b.len() - back;
        b[at] ^= 0x01;
        cases.push((format!("trailer byte -{back}"), b));
    }
    // One bit flipped at a spread of places in the compressed data.
    for k in 1..20 {
        let mut b = good.clone();
        let at = 20 + (b.len() - 28) * k / 20;
        b[at] ^= 0x04;
        cases.push((format!("data byte {at}"), b));
    }
    cases.push(("garbage after".into(), [&good[..], b"trailing"].concat()));
    for (what, bytes) in cases {
        std::fs::write(&path, &bytes).unwrap();
        let e = field_error(&path);
        assert!(
            e.contains("gzip data is corrupt or truncated") || e.contains("t.nii.gz: "),
            "{what}: {e}"
        );
    }
    std::fs::write(&path, [&good[..], b"trailing"].concat()).unwrap();
    fails_with(
        &["info", path.to_str().unwrap()],
        "gzip data is corrupt or truncated",
    );
}

// Defect 4: duplicate NRRD keys were found by comparing each key with every earlier one.

#[test]
fn a_nrrd_header_of_a_hundred_thousand_fields_reads_in_linear_time() {
    use tensorglyph::field::{ReadOptions, read_field};
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 2 1 1\nencoding: raw\nendian: little\n\
         kinds: 3D-symmetric-matrix space space space\n",
    );
    for i in 0..100_000 {
        text.push_str(&format!("unknown field {i}: value {i}\n"));
    }
    text.push('\n');
    let mut bytes = text.into_bytes();
    for x in [1f32, 0., 0., 1., 0., 1., 2., 0., 0., 2., 0., 2.] {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    let path = dir.path().join("many.nrrd");
    std::fs::write(&path, &bytes).unwrap();
    let t = std::time::Instant::now();
    let f = read_field(&path, &ReadOptions::default()).unwrap();
    // A bound on a hang, not a speed: the quadratic check took 31 s here; a map takes
    // milliseconds.
    assert!(t.elapsed().as_secs_f64() < 10.0, "{:?}", t.elapsed());
    assert_eq!(f.tensors.len(), 2);
    assert_eq!(f.tensor(1)[0], 2.0);
    // A field given twice is still refused, wherever it is.
    let dup = [&bytes[..9], b"unknown field 99999: again\n", &bytes[9..]].concat();
    std::fs::write(&path, dup).unwrap();
    assert!(field_error(&path).contains("given twice"));
}

// Defect 5: whole files were read before the header was known.

#[test]
fn a_header_needing_few_bytes_never_reads_a_huge_data_file() {
    use tensorglyph::field::{ReadOptions, read_field};
    let dir = tempfile::tempdir().unwrap();
    const HUGE: u64 = 3 << 30;
    // A detached header needing 48 bytes of a 3 GiB (sparse) data file.
    let raw = dir.path().join("huge.raw");
    std::fs::File::create(&raw).unwrap().set_len(HUGE).unwrap();
    let nhdr = dir.path().join("small.nhdr");
    std::fs::write(
        &nhdr,
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 2 1 1\nencoding: raw\nendian: little\n\
         kinds: 3D-symmetric-matrix space space space\ndata file: huge.raw\n",
    )
    .unwrap();
    // A .nii of one voxel followed by 3 GiB.
    let head = nifti_header(&dti("fsl4d_plain.nii"), &[1, 1, 1, 6]);
    let nii = dir.path().join("one.nii");
    std::fs::write(&nii, [&head[..], &[0u8; 24][..]].concat()).unwrap();
    std::fs::OpenOptions::new()
        .append(true)
        .open(&nii)
        .unwrap()
        .set_len(352 + 24 + HUGE)
        .unwrap();
    for p in [&nhdr, &nii] {
        let f = read_field(p, &ReadOptions::default()).unwrap();
        assert_eq!(f.tensors.len() as u64, if p == &nii { 1 } else { 2 });
        // `info`, in a process of its own allowed 1 GiB of address space, reads it.
        let o = std::process::Command::new("sh")
            .args(["-c", "ulimit -v 1048576 && exec \"$0\" info \"$1\""])
            .arg(env!("CARGO_BIN_EXE_tensorglyph"))
            .arg(p)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}: {}", p.display(), stderr(&o));
    }
}

// Defect 6: Latin-1 bytes in NRRD comments and key/value lines, which Teem reads, were refused.

#[test]
fn latin1_bytes_in_nrrd_comments_and_key_values_are_read_as_teem_reads_them() {
    use tensorglyph::field::{ReadOptions, read_field};
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(dti("nrrd_raw_oblique.nrrd")).unwrap();
    let nl = good.iter().position(|&b| b == b'\n').unwrap() + 1;
    let latin1 = [
        &good[..nl],
        b"# acquired at the H\xf4pital\n",
        b"patient:=Ren\xe9e\n",
        &good[nl..],
    ]
    .concat();
    let path = dir.path().join("latin1.nrrd");
    std::fs::write(&path, latin1).unwrap();
    let opts = ReadOptions::default();
    let got = read_field(&path, &opts).unwrap();
    let want = read_field(&dti("nrrd_raw_oblique.nrrd"), &opts).unwrap();
    assert_eq!(got.tensors, want.tensors);
    assert_eq!(got.positions, want.positions);
}

// Defect 7: extreme NRRD geometry turned voxel-frame tensors into NaN (1e200) or was refused as
// singular (1e-120).

fn nrrd_with_directions(dir: &Path, scale: &str) -> PathBuf {
    let mut b = format!(
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 2 1 1\nencoding: raw\nendian: little\n\
         kinds: 3D-symmetric-matrix space space space\nspace: right-anterior-superior\n\
         space directions: none ({scale},0,0) (0,{scale},0) (0,0,{scale})\n\n"
    )
    .into_bytes();
    for x in [3f32, 1., 0., 2., 0., 1., 2., 0., 0., 2., 0., 2.] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    let path = dir.join(format!("scale{scale}.nrrd"));
    std::fs::write(&path, b).unwrap();
    path
}

#[test]
fn voxel_frame_tensors_of_extreme_lattices_keep_their_values() {
    use tensorglyph::field::{ReadOptions, TensorFrame, read_field};
    let dir = tempfile::tempdir().unwrap();
    let opts = ReadOptions {
        tensor_frame: Some(TensorFrame::Voxel),
        ..Default::default()
    };
    // A scaled identity lattice: its rotation is the identity, whatever the scale.
    let want = read_field(&nrrd_with_directions(dir.path(), "1"), &opts).unwrap();
    for scale in ["1e200", "1e-120", "1e300", "1e-300"] {
        let got = read_field(&nrrd_with_directions(dir.path(), scale), &opts).unwrap();
        for (g, w) in got.tensors.iter().zip(want.tensors.iter()) {
            for (a, b) in g.iter().zip(&w) {
                assert!((a - b).abs() < 1e-12, "{scale}: {g:?} vs {w:?}");
            }
        }
    }
    // Axes of 1e308 and 1e-308 together: no finite rotation at this precision; one line.
    let path = dir.path().join("mixed.nrrd");
    let bytes = std::fs::read(nrrd_with_directions(dir.path(), "1")).unwrap();
    let at = bytes
        .windows(23)
        .position(|w| w == b"(1,0,0) (0,1,0) (0,0,1)")
        .unwrap();
    let mixed = [
        &bytes[..at],
        b"(1e308,0,0) (0,1e308,0) (0,0,1e-308)",
        &bytes[at + 23..],
    ]
    .concat();
    std::fs::write(&path, mixed).unwrap();
    fails_with(
        &["info", path.to_str().unwrap(), "--tensor-frame", "voxel"],
        "space directions",
    );
}

// Defect 8: the smaller ones.

#[test]
fn an_all_nan_underlay_volume_is_refused_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = b"NRRD0004\ntype: float\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\
                  endian: little\n\n"
        .to_vec();
    for _ in 0..64 {
        b.extend_from_slice(&f32::NAN.to_le_bytes());
    }
    let nan = dir.path().join("nan.nrrd");
    std::fs::write(&nan, b).unwrap();
    let tensors = dti("dipy_small101/tensors.nii.gz");
    fails_with(
        &[
            "render",
            tensors.to_str().unwrap(),
            "--underlay",
            nan.to_str().unwrap(),
            "-o",
            dir.path().join("o.png").to_str().unwrap(),
            "--size",
            "32x32",
            "--method",
            "reference",
        ],
        "holds no finite value",
    );
}

#[test]
fn a_broken_member_of_a_prefix_named_eigen_set_is_named() {
    let dir = tempfile::tempdir().unwrap();
    for m in ["L1", "L2", "L3", "V2", "V3"] {
        copy(&dti(&format!("fsl_eigen_oblique_{m}.nii.gz")), dir.path());
    }
    let v1 = dir.path().join("fsl_eigen_oblique_V1.nii.gz");
    for broken in ["dangling link", "folder"] {
        let _ = std::fs::remove_file(&v1);
        let _ = std::fs::remove_dir(&v1);
        if broken == "folder" {
            std::fs::create_dir(&v1).unwrap();
        } else {
            std::os::unix::fs::symlink(dir.path().join("gone"), &v1).unwrap();
        }
        let prefix = dir.path().join("fsl_eigen_oblique");
        fails_with(
            &["info", prefix.to_str().unwrap()],
            "fsl_eigen_oblique_V1.nii.gz",
        );
    }
}

#[test]
fn an_ascii_nrrd_cut_inside_its_last_number_is_refused() {
    use tensorglyph::field::{ReadOptions, read_field};
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(dti("nrrd_ascii_flipped.nrrd")).unwrap();
    assert!(read_field(&dti("nrrd_ascii_flipped.nrrd"), &ReadOptions::default()).is_ok());
    let path = dir.path().join("cut.nrrd");
    // The final newline and the last digit gone: "…0.00155263638589531" became "…0.0015526363858953".
    std::fs::write(&path, &good[..good.len() - 2]).unwrap();
    assert!(
        field_error(&path).contains("ends inside the number"),
        "{}",
        field_error(&path)
    );
}

#[test]
fn a_long_detached_data_file_name_is_cut_in_the_error_line() {
    let dir = tempfile::tempdir().unwrap();
    let name = "d".repeat(5000);
    let nhdr = dir.path().join("long.nhdr");
    std::fs::write(
        &nhdr,
        format!(
            "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 2 1 1\nencoding: raw\n\
             endian: little\nkinds: 3D-symmetric-matrix space space space\ndata file: {name}\n"
        ),
    )
    .unwrap();
    let o = tg(&["info", nhdr.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("…"), "{err}");
    assert!(
        !err.contains(&"d".repeat(81)),
        "{} characters: {err}",
        err.len()
    );
}

#[test]
fn no_glyph_to_draw_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let tensors = dti("dipy_small101/tensors.nii.gz");
    fails_with(
        &[
            "render",
            tensors.to_str().unwrap(),
            "--fa-min",
            "0.999",
            "-o",
            dir.path().join("o.png").to_str().unwrap(),
            "--size",
            "32x32",
            "--method",
            "reference",
        ],
        "tensors.nii.gz: the selection keeps no glyph",
    );
}

#[test]
fn an_underlay_of_tiny_voxels_is_resampled_no_finer_than_the_image() {
    use tensorglyph::progress::Silent;
    use tensorglyph::scene::underlay::UnderlaySource;
    use tensorglyph::staging::{Recipe, Source, stage};
    let dir = tempfile::tempdir().unwrap();
    // 1 µm voxels over the tensors' slice (10 × 2.5 mm): the volume's voxel size would ask for
    // 25,000 texels a side.
    let mut b = b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\
                  endian: little\nspace: right-anterior-superior\n\
                  space directions: (0.001,0,0) (0,0.001,0) (0,0,0.001)\n\
                  space origin: (150,170,80)\n\n"
        .to_vec();
    for k in 0..8 {
        b.extend_from_slice(&(k as f32).to_le_bytes());
    }
    let fine = dir.path().join("fine.nrrd");
    std::fs::write(&fine, b).unwrap();
    let side = |underlay_side| {
        let recipe = Recipe {
            underlay: Some(UnderlaySource::File(fine.clone())),
            underlay_side,
            ..Recipe::default()
        };
        let src = Source::File(dti("dipy_small101/tensors.nii.gz"));
        let staged = stage(&src, &recipe, &Silent).unwrap();
        let u = staged.scene.underlay.unwrap();
        u.planes.iter().flat_map(|p| p.size).max().unwrap()
    };
    // A 160×120 image: 160 texels a side at most; left to the volume, the 4096 cap.
    assert_eq!(side(Some(160)), 160);
    assert_eq!(side(None), 4096);
}

// Issue 39 (an outside campaign of the NRRD reader): `line skip` looked for line ends through
// the whole detached data file, so a sparse 64 GB file of zeros kept `info` busy past 30 s.

/// A 64 GB sparse file: no block of it is written, every byte reads as zero.
fn sparse_zeros(path: &Path) {
    std::fs::File::create(path)
        .unwrap()
        .set_len(64 << 30)
        .unwrap();
}

#[test]
fn line_skip_through_a_sparse_64_gb_data_file_is_refused_after_16_mib() {
    let dir = tempfile::tempdir().unwrap();
    let nhdr = copy(&dti("teem_skip_bigendian.nhdr"), dir.path());
    sparse_zeros(&dir.path().join("teem_skip_bigendian.raw"));
    let o = tg(&["info", "--quiet", nhdr.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("teem_skip_bigendian.nhdr"), "{err}");
    assert!(
        err.contains(
            "field 'line skip': 2 lines not found in the first 16777216 bytes of the data"
        ),
        "{err}"
    );
    // The skip still finds its lines in the real file.
    copy(&dti("teem_skip_bigendian.raw"), dir.path());
    let o = tg(&["info", "--quiet", nhdr.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn ascii_data_far_longer_than_its_values_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let nhdr = dir.path().join("ascii.nhdr");
    std::fs::write(
        &nhdr,
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 5 4 3\n\
         kinds: 3D-symmetric-matrix space space space\nencoding: ascii\n\
         data file: ascii.txt\n",
    )
    .unwrap();
    sparse_zeros(&dir.path().join("ascii.txt"));
    let o = tg(&["info", "--quiet", nhdr.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    // 360 values: at most 360 × 128 bytes and 1 MiB.
    assert!(
        err.contains(&format!(
            "field 'sizes': 360 values as ascii take at most {} bytes, the data holds {}: not read",
            360 * 128 + (1 << 20),
            64u64 << 30
        )),
        "{err}"
    );
}
