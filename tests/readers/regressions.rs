//! Named reproducers of the defects the mutation campaign found (issue 13's, then the DTI
//! readers'), one test each (the files are in `tests/data/regressions/`, which the mutation
//! campaign in `tests/campaign/main.rs` also reads and mutates under its memory and time budget).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use tensorglyph::error::LoadErrorKind;
use tensorglyph::field::vtk::{ReadOptions, read_field};

fn regression(name: &str) -> PathBuf {
    crate::data::path("regressions").join(name)
}

fn data(name: &str) -> PathBuf {
    crate::data::path("vtk").join(name)
}

/// The error of reading `path`, checked to be one clean line naming the file.
fn clean_error(path: &Path) -> (LoadErrorKind, String) {
    let e = read_field(path, &ReadOptions::default()).expect_err("must fail");
    let msg = e.to_string();
    assert!(
        !msg.chars().any(char::is_control),
        "control characters in {msg:?}"
    );
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(msg.contains(name.as_ref()), "{msg}");
    (e.kind, msg)
}

/// Run `f` on another thread; fail if it does not return within `secs` (a FIFO opened for
/// reading blocks forever).
fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(secs))
        .expect("did not return in time (blocked?)")
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tensorglyph"));
    c.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    c
}

fn mkfifo(path: &Path) -> bool {
    Command::new("mkfifo")
        .arg(path)
        .status()
        .is_ok_and(|s| s.success())
}

// Item 1 ---------------------------------------------------------------------------------------

/// 8,000 nested elements (24 KB of `<a>`) took 1.8 GB: every tag cloned the open-element stack.
#[test]
fn nested_8000_elements_are_refused_at_depth_64() {
    let t0 = Instant::now();
    let (k, msg) = clean_error(&regression("nested_8000.vti"));
    assert!(matches!(k, LoadErrorKind::Malformed(_)), "{k:?}");
    assert!(msg.contains("nests deeper than 64"), "{msg}");
    assert!(t0.elapsed() < Duration::from_secs(1));
}

#[test]
fn nesting_up_to_the_cap_still_parses_to_the_usual_error() {
    let dir = tempfile::tempdir().unwrap();
    // 62 levels inside <VTKFile>: legal depth, but no dataset in it.
    let body = format!("{}{}", "<a>".repeat(62), "</a>".repeat(62));
    let p = dir.path().join("deep_ok.vti");
    std::fs::write(
        &p,
        format!("<VTKFile type=\"ImageData\">{body}</VTKFile>\n"),
    )
    .unwrap();
    let (_, msg) = clean_error(&p);
    assert!(msg.contains("no <ImageData> element"), "{msg}");
}

// Item 3 ---------------------------------------------------------------------------------------

/// An 8-point image whose zlib block claims 16 MiB (16 KB compressed, within zlib's ratio):
/// refused from its header, before anything is inflated.
#[test]
fn zlib_bomb_is_refused_from_its_header() {
    let (k, msg) = clean_error(&regression("zlib_bomb_8_points.vti"));
    assert!(matches!(k, LoadErrorKind::Malformed(_)), "{k:?}");
    assert!(
        msg.contains("claims 16777216 bytes but the array needs 72"),
        "{msg}"
    );
}

/// Found by the campaign (seed 13): the same bomb in an extent claiming 2^32 points, so that
/// the block's claim is below the geometry's need. Binary data must hold exactly what the
/// geometry needs, so this is refused from the header too.
#[test]
fn zlib_bomb_with_a_lying_extent_is_refused_from_its_header() {
    let (_, msg) = clean_error(&regression("zlib_bomb_lying_extent.vti"));
    assert!(
        msg.contains("holds 16777216 bytes but the array needs 154618822692"),
        "{msg}"
    );
}

/// The same bound in a multi-block stream, and blocks that claim less than they inflate to
/// are cut at their claim (lz4 and lzma too).
#[test]
fn every_compressor_is_bounded_by_the_array() {
    for f in [
        "xml_image_appraw_zlib_u32.vti",
        "xml_image_appraw_lz4_u64.vti",
        "xml_image_appraw_lzma_u64.vti",
        "xml_image_binary_zlib_u64.vti",
        "xml_image_appb64_lz4_u32.vti",
    ] {
        read_field(&data(f), &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    }
}

// Item 5 ---------------------------------------------------------------------------------------

/// 50 bytes whose error cleared the terminal (`ESC[2J`) when `info` failed.
#[test]
fn escape_sequences_in_the_file_are_escaped() {
    let (_, msg) = clean_error(&regression("escape_clears_screen.vtk"));
    assert!(msg.contains("found '\\x1B[2J\\x1B[H\\x00'"), "{msg}");
}

#[test]
fn newlines_in_attributes_and_broken_end_tags_stay_on_one_line() {
    let (_, msg) = clean_error(&regression("newline_in_attribute.vti"));
    assert!(
        msg.contains("evil\\nline two\\r\\x1B]0;title\\x07"),
        "{msg}"
    );
    let (_, msg) = clean_error(&regression("broken_end_tag.vti"));
    assert!(msg.contains("</Image\\nData>"), "{msg}");
}

#[test]
fn long_names_are_cut_and_paths_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let name = "n".repeat(5000);
    let text = format!(
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 1 1 1\n\
         POINT_DATA 1\nSCALARS {name} float 1\nLOOKUP_TABLE default\n1\n"
    );
    let p = dir.path().join("line\nbreak.vtk");
    std::fs::write(&p, text).unwrap();
    let e = read_field(&p, &ReadOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(!msg.chars().any(char::is_control), "{msg:?}");
    assert!(msg.contains("line\\nbreak.vtk"), "{msg}");
    assert!(msg.contains(&format!("'{}…'", "n".repeat(80))), "{msg}");
    assert!(msg.len() < 400, "{} bytes", msg.len());
    // The requested name is escaped too (it comes from the command line).
    let e = read_field(
        &p,
        &ReadOptions {
            array: Some("a\u{1b}[2Jb".into()),
            ..ReadOptions::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("'a\\x1B[2Jb' not found"), "{e}");
}

/// Found by tests/readers/corrupted.rs (xml_ugrid_binary_lzma_u32.vtu, byte 1486 bit 2 flipped): a
/// 326-byte piece of file text sliced past its end in escape_for_error, a panic that the reader
/// turned into "internal reader error".
#[test]
fn error_text_of_326_bytes_is_cut_cleanly() {
    let (_, msg) = clean_error(&regression("long_base64_error_text.vtu"));
    assert!(!msg.contains("internal reader error"), "{msg}");
    assert!(msg.contains('…'), "{msg}");
}

#[test]
fn info_failure_prints_exactly_one_line() {
    let out = bin()
        .args(["info"])
        .arg(regression("escape_clears_screen.vtk"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.matches('\n').count(), 1, "{err:?}");
    assert!(!err.trim_end().chars().any(char::is_control), "{err:?}");
}

// Item 6 ---------------------------------------------------------------------------------------

/// Tensors near f64::MAX and subnormal ones were counted valid but `info` showed null
/// eigenvalues and FA.
#[test]
fn extreme_tensors_give_finite_eigenvalues_and_fa() {
    let f = read_field(&regression("extreme_tensors.vtk"), &ReadOptions::default()).unwrap();
    let set = tensorglyph::glyph::derive_glyphs(&f, &tensorglyph::progress::Silent);
    // The first one's eigenvalues (0.95·f64::MAX) are beyond what a glyph stores (f32): it is
    // counted as such, not drawn; `info`'s samples still decompose it exactly, in f64.
    assert_eq!((set.stats.valid, set.stats.skipped_overflow), (3, 1));
    let r = tensorglyph::info::info_report(&f, &set, &[0, 1, 2, 3]).unwrap();
    for s in &r.samples {
        assert!(s.eigenvalues.iter().all(|x| x.is_finite()), "{s:?}");
        assert!(
            s.eigenvectors.iter().flatten().all(|x| x.is_finite()),
            "{s:?}"
        );
    }
    assert!(r.fa.min.is_finite() && r.fa.mean.is_finite() && r.fa.max.is_finite());
    assert!(
        r.eigenvalues
            .min
            .iter()
            .chain(&r.eigenvalues.max)
            .all(|x| x.is_finite())
    );
    // First tensor: [[0.1, 0.85], [0.85, 0.1]] ⊕ [0.1] times f64::MAX after symmetrising.
    let m = f64::MAX;
    let e = r.samples[0].eigenvalues;
    for (got, want) in e.iter().zip([0.95 * m, 0.1 * m, -0.75 * m]) {
        assert!((got - want).abs() <= 1e-12 * m, "{e:?}");
    }
    // Third: diag(1, 3, 2) × 2^-1074, exactly.
    let tiny = f64::from_bits(1);
    assert_eq!(r.samples[2].eigenvalues, [3.0 * tiny, 2.0 * tiny, tiny]);
    let json = serde_json::to_string(&r).unwrap();
    assert!(!json.contains("null"), "{json}");
}

// Item 7 ---------------------------------------------------------------------------------------

#[test]
fn fifo_input_is_refused_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.vtk");
    if !mkfifo(&fifo) {
        eprintln!("skipping: mkfifo not available");
        return;
    }
    let f = fifo.clone();
    let kind = within(10, move || {
        read_field(&f, &ReadOptions::default()).unwrap_err().kind
    });
    assert!(
        matches!(kind, LoadErrorKind::NotRegularFile("a FIFO")),
        "{kind:?}"
    );
    // As a .pvti piece beside it; by absolute Source it is not even looked at (a header names
    // files in its folder or below it).
    let pvti = std::fs::read_to_string(data("pvti_3pieces_binary.pvti")).unwrap();
    for (src, want) in [
        ("pipe.vtk".to_string(), "not a regular file (a FIFO)"),
        (
            fifo.display().to_string(),
            "is not in the header's folder or below it",
        ),
    ] {
        let p = dir.path().join("via_fifo.pvti");
        std::fs::write(&p, pvti.replacen("pvti_3pieces_binary_0.vti", &src, 1)).unwrap();
        let msg = within(10, move || clean_error(&p).1);
        assert!(msg.contains(want), "{msg}");
    }
}

#[test]
fn devices_are_refused_as_input_and_as_piece() {
    let dir = tempfile::tempdir().unwrap();
    let pvti = std::fs::read_to_string(data("pvti_3pieces_binary.pvti")).unwrap();
    for dev in ["/dev/zero", "/dev/urandom"] {
        if !Path::new(dev).exists() {
            continue;
        }
        let d = PathBuf::from(dev);
        let kind = within(10, move || {
            read_field(&d, &ReadOptions::default()).unwrap_err().kind
        });
        assert!(
            matches!(kind, LoadErrorKind::NotRegularFile("a character device")),
            "{dev}: {kind:?}"
        );
        // As a piece: refused by its place before it is opened.
        let p = dir.path().join("via_dev.pvti");
        std::fs::write(&p, pvti.replacen("pvti_3pieces_binary_0.vti", dev, 1)).unwrap();
        let msg = within(10, move || clean_error(&p).1);
        assert!(
            msg.contains("is not in the header's folder or below it"),
            "{msg}"
        );
    }
    let (k, _) = clean_error(dir.path());
    assert!(matches!(k, LoadErrorKind::NotRegularFile("a directory")));
}

#[test]
fn a_piece_listed_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for k in 0..3 {
        let n = format!("pvti_3pieces_binary_{k}.vti");
        std::fs::copy(data(&n), dir.path().join(&n)).unwrap();
    }
    let pvti = std::fs::read_to_string(data("pvti_3pieces_binary.pvti")).unwrap();
    let p = dir.path().join("twice.pvti");
    std::fs::write(
        &p,
        pvti.replacen(
            "pvti_3pieces_binary_1.vti",
            "./pvti_3pieces_binary_0.vti",
            1,
        ),
    )
    .unwrap();
    let (_, msg) = clean_error(&p);
    assert!(msg.contains("listed twice"), "{msg}");
}

// Item 8 ---------------------------------------------------------------------------------------

/// A file cut inside its last number loaded with that number shortened (1.5927 → 1.592).
#[test]
fn legacy_ascii_cut_inside_the_last_number_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "legacy42_ascii_image_T9.vtk",
        "legacy51_ascii_ugrid_cellT6.vtk",
    ] {
        let b = std::fs::read(data(f)).unwrap();
        let last_digit = b.iter().rposition(u8::is_ascii_digit).unwrap();
        // Cut inside the last number, and right after it (it may have had more digits);
        // whitespace after it makes it whole again.
        for (end, ok) in [
            (last_digit, false),
            (last_digit + 1, false),
            (last_digit + 2, true),
        ] {
            let p = dir.path().join(format!("cut{end}_{f}"));
            std::fs::write(&p, &b[..end]).unwrap();
            if ok {
                read_field(&p, &ReadOptions::default()).unwrap();
                continue;
            }
            let (k, msg) = clean_error(&p);
            assert!(matches!(k, LoadErrorKind::Malformed(_)), "{msg}");
            assert!(msg.contains("ends inside the number"), "{msg}");
        }
    }
    // A keyword line cut at the end of the file: 'POINT_DATA 12' may have been 'POINT_DATA 123'.
    let p = dir.path().join("cut_keyword.vtk");
    std::fs::write(
        &p,
        b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 1 1 1\nPOINT_DATA 1",
    )
    .unwrap();
    let (_, msg) = clean_error(&p);
    assert!(msg.contains("ends inside the line 'POINT_DATA 1'"), "{msg}");
}

// Item 2 ---------------------------------------------------------------------------------------

#[test]
fn output_equal_to_the_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.vtk");
    std::fs::copy(data("legacy42_bin_image_T9.vtk"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let hard = dir.path().join("hard.png");
    std::fs::hard_link(&input, &hard).unwrap();
    let soft = dir.path().join("soft.png");
    std::os::unix::fs::symlink(&input, &soft).unwrap();
    for out in [&input, &hard, &soft] {
        let o = bin()
            .arg("render")
            .arg(&input)
            .arg("-o")
            .arg(out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("is the input file"), "{err}");
        assert_eq!(err.matches('\n').count(), 1, "{err}");
    }
    assert_eq!(std::fs::read(&input).unwrap(), before);
}

#[test]
fn outputs_write_through_symlinks_and_refuse_special_files() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("real.vtk");
    std::fs::write(&real, b"old").unwrap();
    let link = dir.path().join("link.vtk");
    std::os::unix::fs::symlink("real.vtk", &link).unwrap();
    let o = bin()
        .args(["demo", "--quiet", "--write-vtk"])
        .arg(&link)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(std::fs::read(&real).unwrap().starts_with(b"# vtk DataFile"));

    let fifo = dir.path().join("out.png");
    if mkfifo(&fifo) {
        for args in [
            vec!["demo", "--quiet", "--write-vtk"],
            vec!["demo", "--quiet", "--size", "8x8", "-o"],
        ] {
            let f = fifo.clone();
            let o = within(60, move || bin().args(&args).arg(&f).output().unwrap());
            assert_eq!(o.status.code(), Some(2));
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(err.contains("a FIFO, not a regular file"), "{err}");
        }
        use std::os::unix::fs::FileTypeExt as _;
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    }
    let o = bin()
        .args(["demo", "--quiet", "--write-vtk", "/dev/null"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("device, not a regular file"));
    use std::os::unix::fs::FileTypeExt as _;
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
}

// The DTI readers (the campaign's NIfTI and NRRD cases) ----------------------------------------

/// A qform whose quaternion has b² + c² + d² = 0.9² + 0.9² > 1 made the nifti crate panic
/// ("should be positive"); the reader's last defence turned that into an internal error.
#[test]
fn nifti_qform_quaternion_over_1_is_a_field_error() {
    let path = regression("nifti_qform_quaternion_over_1.nii");
    let e = tensorglyph::field::read_field(&path, &ReadOptions::default()).expect_err("must fail");
    let msg = e.to_string();
    assert!(
        msg.contains("field 'quatern_b': b² + c² + d² = 1.61999"),
        "{msg}"
    );
    assert!(msg.contains("nifti_qform_quaternion_over_1.nii"), "{msg}");
    assert!(!msg.contains("internal reader error"), "{msg}");
}
