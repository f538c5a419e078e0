//! MRtrix images (`.mif`, `.mif.gz`, `.mih`) written by MRtrix3 itself
//! (`tests/data/mif/make_mif.py`): every layout, datatype and scaling read to what MRtrix reads
//! back from the same file (`expected.json`), at the same world positions; a tensor image opens
//! as its NIfTI twin does (the same glyphs, the same `info`); every bad header or data is one
//! clean line.

use std::path::{Path, PathBuf};

use serde_json::Value;
use tensorglyph::field::{
    ComponentOrder, Inputs, ReadOptions, TensorField, TensorFrame, read_field,
    read_mif_volumes_from, read_scalar_volume,
};
use tensorglyph::tensor::eigen::{symmetric_eigen, symmetrise};

use crate::cli::{json, stderr, tg};

fn mif(name: &str) -> PathBuf {
    crate::data::path("mif").join(name)
}

fn expected() -> Value {
    let text = std::fs::read_to_string(mif("expected.json")).expect("tests/data/mif/expected.json");
    serde_json::from_str(&text).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn world(m: &[[f64; 4]; 4], ijk: [usize; 3]) -> [f64; 3] {
    std::array::from_fn(|r| {
        m[r][0] * ijk[0] as f64 + m[r][1] * ijk[1] as f64 + m[r][2] * ijk[2] as f64 + m[r][3]
    })
}

fn dist(a: [f64; 3], b: &[f64]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// For each voxel of the truth (x fastest in MRtrix's own axes), ours at the same world
/// position. MRtrix's NIfTI stores its affine in float32: positions agree to 1e-3 mm (voxels
/// are 2 mm and more apart), and each of ours is matched once.
fn matching(ours: &[[f64; 3]], truth: &[Value]) -> Vec<usize> {
    assert_eq!(ours.len(), truth.len());
    let mut taken = vec![false; ours.len()];
    truth
        .iter()
        .enumerate()
        .map(|(t, p)| {
            let p = floats(p);
            let (i, d) = ours
                .iter()
                .enumerate()
                .map(|(i, o)| (i, dist(*o, &p)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            assert!(
                d < 1e-3,
                "truth voxel {t} at {p:?}: nearest of ours {d} mm away"
            );
            assert!(
                !std::mem::replace(&mut taken[i], true),
                "voxel {i} matched twice"
            );
            i
        })
        .collect()
}

#[test]
fn every_layout_datatype_and_scaling_reads_what_mrtrix_reads() {
    let exp = expected();
    let files = exp.as_object().unwrap();
    assert_eq!(files.len(), 19);
    for (name, t) in files {
        let v = read_mif_volumes_from(&Inputs::file_system(), &mif(name))
            .unwrap_or_else(|e| panic!("{e}"));
        let dims: Vec<usize> = t["dims"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(
            v.dims.iter().product::<usize>(),
            dims.iter().product::<usize>(),
            "{name}"
        );
        assert_eq!(v.volumes as u64, t["volumes"].as_u64().unwrap(), "{name}");
        let n = v.dims.iter().product::<usize>();
        let positions: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let ijk = [
                    i % v.dims[0],
                    i / v.dims[0] % v.dims[1],
                    i / v.dims[0] / v.dims[1],
                ];
                world(&v.voxel_to_world, ijk)
            })
            .collect();
        let at = matching(&positions, t["positions"].as_array().unwrap());
        let kept: Vec<usize> = t["kept_volumes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap() as usize)
            .collect();
        for (ti, values) in t["values"].as_array().unwrap().iter().enumerate() {
            for (k, want) in floats(values).into_iter().enumerate() {
                let c = kept[k];
                // MRtrix's double, ours float32 of the same double: equal as float32.
                assert_eq!(
                    v.values[at[ti] * v.volumes + c],
                    want as f32,
                    "{name}: voxel {ti} volume {c}"
                );
            }
        }
        // Every volume, kept or not, sums as MRtrix's does.
        for (c, want) in floats(&t["volume_sums"]).into_iter().enumerate() {
            let sum: f64 = (0..n).map(|i| v.values[i * v.volumes + c] as f64).sum();
            assert!(
                (sum - want).abs() <= 1e-6 * want.abs().max(1.0),
                "{name}: volume {c} sums to {sum}, MRtrix's to {want}"
            );
        }
        // The datatype and strides of each file are the ones the script asked MRtrix for.
        if name.starts_with("scalar_") {
            let ty = name
                .trim_start_matches("scalar_")
                .split(['_', '.'])
                .next()
                .unwrap();
            let said = t["datatype"].as_str().unwrap().to_ascii_lowercase();
            assert_eq!(said, ty, "{name}");
            // Scalar files read as underlays hold the same values.
            let s = read_scalar_volume(&mif(name)).unwrap();
            assert_eq!(s.values.len(), n);
            assert_eq!(s.voxel_to_world, v.voxel_to_world);
            assert!(
                s.values
                    .iter()
                    .zip(&v.values)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            );
        }
    }
}

/// The world tensor `i` of a field, eigen-decomposed.
fn world_eigen(f: &TensorField, i: usize) -> ([f64; 3], [f64; 3]) {
    let e = symmetric_eigen(&symmetrise(&f.world_tensor(i)).0);
    (e.values, e.vectors[0])
}

fn twin_options() -> ReadOptions {
    ReadOptions {
        order: Some(ComponentOrder::Mrtrix),
        tensor_frame: Some(TensorFrame::World),
        ..ReadOptions::default()
    }
}

/// Every tensor of `f` and of `twin` at the same world position: the same world tensor.
fn same_glyphs(name: &str, f: &TensorField, twin: &TensorField) {
    assert_eq!(f.len(), twin.len(), "{name}");
    let truth: Vec<Value> = twin
        .positions
        .iter()
        .map(|p| serde_json::json!(p))
        .collect();
    let at = matching(&f.positions.to_vec(), &truth);
    for (i, &j) in at.iter().enumerate() {
        let (a, b) = (twin.world_tensor(i), f.world_tensor(j));
        let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..9 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-12 * scale,
                "{name} voxel {i}: {b:?} vs the twin's {a:?}"
            );
        }
        let (va, ea) = world_eigen(twin, i);
        let (vb, eb) = world_eigen(f, j);
        for k in 0..3 {
            assert!((va[k] - vb[k]).abs() <= 1e-12 * scale, "{name} voxel {i}");
        }
        let dot: f64 = (0..3).map(|k| ea[k] * eb[k]).sum();
        assert!(
            dot.abs() > 1.0 - 1e-9 || va[0] - va[1] < 1e-9 * scale,
            "{name} voxel {i}"
        );
    }
}

#[test]
fn tensor_images_open_as_their_nifti_twins_do() {
    let dti = |n: &str| crate::data::path("dti").join(n);
    // The twin of every converted file: numpy's tensors (tests/data/dti/expected.json).
    let twin = read_field(&dti("mrtrix_oblique.nii.gz"), &twin_options()).unwrap();
    for name in [
        "tensor_oblique.mif",
        "tensor_volume_contiguous.mif",
        "tensor_reversed_f64be.mif.gz",
        "tensor_detached.mih",
    ] {
        // No flags: MRtrix's order and scanner axes are the format's defaults.
        let f = read_field(&mif(name), &ReadOptions::default()).unwrap();
        assert_eq!(f.format, "mif");
        assert_eq!(f.dims, Some([5, 4, 3]), "{name}");
        same_glyphs(name, &f, &twin);
    }
    // dwi2tensor's own output and mrconvert's NIfTI of it.
    let f = read_field(&mif("dwi2tensor_small101.mif"), &ReadOptions::default()).unwrap();
    let twin = read_field(&mif("dwi2tensor_small101.nii.gz"), &twin_options()).unwrap();
    same_glyphs("dwi2tensor_small101.mif", &f, &twin);
    // Its x axis is stored reversed (DIPY's lattice has a negative determinant): the file is
    // not read in the NIfTI's voxel order, yet holds the same glyphs.
    assert_ne!(f.positions, twin.positions);
    // The same `info`: statistics of the same glyphs.
    let info = |p: &Path, flags: &[&str]| {
        let mut args = vec!["info", "--json", "--quiet", p.to_str().unwrap()];
        args.extend_from_slice(flags);
        let o = tg(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        json(&o)
    };
    let a = info(&mif("dwi2tensor_small101.mif"), &[]);
    let b = info(
        &mif("dwi2tensor_small101.nii.gz"),
        &["--order", "mrtrix", "--tensor-frame", "world"],
    );
    for key in ["tensors", "valid", "skipped", "indefinite", "classes"] {
        assert_eq!(a[key], b[key], "{key}");
    }
    for k in ["min", "max"] {
        for i in 0..3 {
            let (x, y) = (
                a["eigenvalues"][k][i].as_f64().unwrap(),
                b["eigenvalues"][k][i].as_f64().unwrap(),
            );
            assert!(
                (x - y).abs() <= 1e-12 * y.abs().max(1e-30),
                "{k}[{i}]: {x} {y}"
            );
        }
    }
    assert_eq!(a["format"], "mif");
    assert_eq!(a["layout"]["order"], "mrtrix");
    assert_eq!(a["layout"]["why"], "default");
    assert_eq!(a["frame"]["tensor_frame"], "world");
    assert_eq!(a["frame"]["source"], "transform");
    assert_eq!(a["frame"]["world"], "RAS");
}

#[test]
fn permuted_axes_are_placed_by_the_transform_as_mrtrix_places_them() {
    // mrconvert -axes 1,0,2,3 swaps the first two axes' sizes and voxel sizes: the image is
    // another lattice (its truth is MRtrix's, checked above); its tensors are the twin's in
    // scanner axes, so every value is one of the twin's.
    let f = read_field(&mif("tensor_permuted_f32be.mif"), &ReadOptions::default()).unwrap();
    assert_eq!(f.dims, Some([4, 5, 3]));
    let twin = read_field(
        &crate::data::path("dti").join("mrtrix_oblique.nii.gz"),
        &twin_options(),
    )
    .unwrap();
    let mut ours: Vec<[f64; 9]> = f.tensors.iter().collect();
    let mut theirs: Vec<[f64; 9]> = twin.tensors.iter().collect();
    let key = |t: &[f64; 9]| t.map(f64::to_bits);
    ours.sort_by_key(key);
    theirs.sort_by_key(key);
    assert_eq!(ours, theirs);
}

#[test]
fn info_says_where_the_layout_and_frame_came_from() {
    let p = mif("tensor_oblique.mif");
    let o = tg(&["info", "--quiet", p.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("(mif 5×4×3)"), "{text}");
    assert!(text.contains("layout: mrtrix (the default)"), "{text}");
    assert!(
        text.contains("frame: tensors in world axes, world RAS from transform"),
        "{text}"
    );
    let o = tg(&[
        "info",
        "--json",
        "--quiet",
        p.to_str().unwrap(),
        "--order",
        "fsl",
        "--tensor-frame",
        "voxel",
    ]);
    let j = json(&o);
    assert_eq!(j["layout"]["order"], "fsl");
    assert_eq!(j["layout"]["why"], "flag");
    assert_eq!(j["frame"]["tensor_frame"], "voxel");
    // The transform with the voxel sizes applied: column 0 is 2 mm along (cos 30°, sin 30°, 0).
    let m = &j["frame"]["voxel_to_world"];
    assert!(
        (m[0][0].as_f64().unwrap() - 2.0 * 0.866_025_4).abs() < 1e-6,
        "{m}"
    );
    assert!((m[1][0].as_f64().unwrap() - 1.0).abs() < 1e-6, "{m}");
    assert_eq!(m[0][3].as_f64().unwrap(), -10.0);
}

// ---------------------------------------------------------------------------------------------
// Bad files: each rejection path, one line.

/// `tensor_oblique.mif` split into its header lines (without `file:` and `END`) and its data.
fn parts() -> (Vec<String>, Vec<u8>) {
    let b = std::fs::read(mif("tensor_oblique.mif")).unwrap();
    let end = b.windows(5).position(|w| w == b"\nEND\n").unwrap() + 5;
    let text = String::from_utf8(b[..end].to_vec()).unwrap();
    let offset: usize = text
        .lines()
        .find_map(|l| l.strip_prefix("file: . "))
        .unwrap()
        .parse()
        .unwrap();
    let lines = text
        .lines()
        .filter(|l| !l.starts_with("file:") && *l != "END")
        .map(String::from)
        .collect();
    (lines, b[offset..].to_vec())
}

/// A `.mif` of `lines`, the data after them at a fresh offset (`file` line given, or made).
fn remake(lines: &[String], data: &[u8], file_line: Option<&str>) -> Vec<u8> {
    let mut text = lines.join("\n") + "\n";
    let off = text.len() + 32;
    text += &match file_line {
        Some(f) => format!("{f}\nEND\n"),
        None => format!("file: . {off}\nEND\n"),
    };
    let mut b = text.into_bytes();
    b.resize(off.max(b.len()), 0);
    b.extend_from_slice(data);
    b
}

fn edited(from: &str, to: &str) -> Vec<u8> {
    let (lines, data) = parts();
    let lines: Vec<String> = lines
        .iter()
        .map(|l| {
            if l.starts_with(from) {
                to.to_string()
            } else {
                l.clone()
            }
        })
        .collect();
    remake(&lines, &data, None)
}

/// `tensorglyph info` on `bytes` written as `name` fails with status 2 and one line naming
/// the file and `what`, without control characters.
fn refused(dir: &Path, name: &str, bytes: &[u8], what: &str) {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    let o = tg(&["info", "--quiet", p.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
    assert!(err.contains(name), "{err}");
    assert!(err.contains(what), "expected '{what}' in: {err}");
    assert!(!err.trim_end().chars().any(char::is_control), "{err:?}");
}

fn gz(b: &[u8]) -> Vec<u8> {
    use std::io::Write as _;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(b).unwrap();
    e.finish().unwrap()
}

#[test]
fn bad_headers_and_data_fail_with_one_line_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (lines, data) = parts();
    // The untouched remake reads: the failures below are the edits'.
    let good = remake(&lines, &data, None);
    std::fs::write(d.join("good.mif"), &good).unwrap();
    read_field(&d.join("good.mif"), &ReadOptions::default()).unwrap();

    refused(d, "magic.mif", &good[1..], "not an MRtrix image");
    let cut = good.windows(4).position(|w| w == b"END\n").unwrap();
    refused(d, "no_end.mif", &good[..cut], "ends with a line 'END'");
    refused(
        d,
        "dim0.mif",
        &edited("dim:", "dim: 5,0,3,6"),
        "field 'dim': a size is 0",
    );
    refused(
        d,
        "dim5.mif",
        &edited("dim:", "dim: 5,4,3,5"),
        "field 'dim': 5 values per voxel",
    );
    refused(
        d,
        "scalar.mif",
        &edited("dim:", "dim: 5,4,3,1"),
        "field 'dim': a scalar volume",
    );
    refused(
        d,
        "layout.mif",
        &edited("layout:", "layout: +0,+1,+1,+3"),
        "field 'layout': '+0,+1,+1,+3': rank 1 given twice",
    );
    refused(
        d,
        "bit.mif",
        &edited("datatype:", "datatype: Bit"),
        "one bit per value",
    );
    refused(
        d,
        "complex.mif",
        &edited("datatype:", "datatype: CFloat32LE"),
        "complex values",
    );
    refused(
        d,
        "escape.mif",
        &edited("datatype:", "datatype: \u{1b}[2J"),
        "field 'datatype': '\\x1B[2J'",
    );
    refused(
        d,
        "vox.mif",
        &edited("vox:", "vox: 2,0,3"),
        "field 'vox': voxel size 0 on axis 1",
    );
    refused(
        d,
        "transform.mif",
        &edited("transform: 0, 0.342", "transform: 0, 0.342, nan, 3"),
        "field 'transform': row 2",
    );
    refused(
        d,
        "singular.mif",
        &edited("transform: 0, 0.342", "transform: 0, 0, 0, 3"),
        "field 'transform': its 3x3 part is singular",
    );
    let mut scaled = lines.clone();
    scaled.push("scaling: 0,inf".into());
    refused(
        d,
        "scaling.mif",
        &remake(&scaled, &data, None),
        "field 'scaling'",
    );
    refused(
        d,
        "inside.mif",
        &remake(&lines, &data, Some("file: . 10")),
        "field 'file': data offset 10 is inside the header",
    );
    refused(
        d,
        "twice.mif",
        &remake(&lines, &data, Some("file: . 900\nfile: . 900")),
        "field 'file': given twice",
    );
    refused(
        d,
        "short.mif",
        &good[..good.len() - 1],
        &format!(
            "field 'dim': dim and datatype need 1440 bytes of data from byte {}, the file holds {}",
            good.len() - data.len(),
            data.len() - 1
        ),
    );
    refused(
        d,
        "missing.mif",
        &remake(&lines, &data, Some("file: gone.dat 0")),
        "field 'file':",
    );
    refused(
        d,
        "cut.mif.gz",
        &gz(&good)[..600],
        "gzip data is corrupt or truncated",
    );
    refused(
        d,
        "detached.mif.gz",
        &gz(&remake(&lines, &data, Some("file: x.dat 0"))),
        "a .mif.gz holds its own data",
    );
    // A header of 17 MiB of empty lines, raw and compressed: looked through once, to 16 MiB.
    let endless = [&b"mrtrix image\n"[..], &vec![b'\n'; 17 << 20]].concat();
    refused(
        d,
        "endless.mif",
        &endless,
        "none in the first 16777216 bytes",
    );
    refused(
        d,
        "endless.mif.gz",
        &gz(&endless),
        "none in the first 16777216 bytes",
    );
    let e = read_scalar_volume(&mif("tensor_oblique.mif"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("6 values per voxel: a tensor image, not a scalar volume"),
        "{e}"
    );
}

#[test]
fn a_detached_data_file_is_read_next_to_its_header_and_only_as_far_as_it_goes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (lines, data) = parts();
    // An offset into the data file, and a data file one byte short.
    std::fs::write(d.join("x.dat"), [&[7u8; 12][..], &data].concat()).unwrap();
    std::fs::write(d.join("y.dat"), &data[..data.len() - 1]).unwrap();
    std::fs::write(d.join("x.mih"), remake(&lines, &[], Some("file: x.dat 12"))).unwrap();
    let f = read_field(&d.join("x.mih"), &ReadOptions::default()).unwrap();
    let g = read_field(&mif("tensor_oblique.mif"), &ReadOptions::default()).unwrap();
    assert_eq!(f.tensors, g.tensors);
    refused(
        d,
        "y.mih",
        &remake(&lines, &[], Some("file: y.dat")),
        "y.dat holds 1439",
    );
}

/// What a header may name (issue 56): a data file in its folder or below it, by the bytes of
/// its name whatever their encoding (a Latin-1 name, which MRtrix 3.0.3 opens); never an
/// absolute path or one through `..`. Refused in one line naming the header, before any read.
#[test]
fn a_header_names_its_data_beside_or_below_it_only() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (lines, data) = parts();
    let want = read_field(&mif("tensor_oblique.mif"), &ReadOptions::default()).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::write(d.join("sub/x.dat"), &data).unwrap();
    std::fs::write(
        d.join("below.mih"),
        remake(&lines, &[], Some("file: sub/x.dat")),
    )
    .unwrap();
    let f = read_field(&d.join("below.mih"), &ReadOptions::default()).unwrap();
    assert_eq!(f.tensors, want.tensors);
    for (name, target) in [
        ("abs.mih", "/etc/passwd"),
        ("proc.mih", "/proc/self/exe"),
        ("up.mih", "../x.dat"),
        ("down_up.mih", "sub/../../x.dat"),
    ] {
        refused(
            &d.join("sub"),
            name,
            &remake(&lines, &[], Some(&format!("file: {target}"))),
            "is not in the header's folder or below it",
        );
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt as _;
        let latin = std::ffi::OsStr::from_bytes(b"caf\xe9.dat");
        std::fs::write(d.join(latin), &data).unwrap();
        let mut header = remake(&lines, &[], Some("file: caf\u{e9}.dat"));
        // The name's bytes as a Latin-1 writer leaves them: é is one byte, 0xE9.
        let at = header.windows(2).position(|w| w == "é".as_bytes()).unwrap();
        header.splice(at..at + 2, [0xE9u8]);
        std::fs::write(d.join("latin.mih"), &header).unwrap();
        let f = read_field(&d.join("latin.mih"), &ReadOptions::default()).unwrap();
        assert_eq!(f.tensors, want.tensors);
    }
}

/// `scaling` applies to integer data only, as MRtrix 3.0.3 reads it (`mrdump` of a Float32
/// image with `scaling: 10,3` prints the stored values; of an Int16 one, 10 + 3·stored).
#[test]
fn float_data_is_read_as_stored_whatever_its_scaling() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (mut lines, data) = parts();
    lines.push("scaling: 10,3".into());
    std::fs::write(d.join("scaled.mif"), remake(&lines, &data, None)).unwrap();
    let f = read_field(&d.join("scaled.mif"), &ReadOptions::default()).unwrap();
    let want = read_field(&mif("tensor_oblique.mif"), &ReadOptions::default()).unwrap();
    assert_eq!(f.tensors, want.tensors);
}

/// An image MRtrix's `sh2peaks` wrote (`tests/data/sh/make_peaks.sh`: 9 volumes, three peaks
/// of 3 values) was read silently as a field of full 3×3 tensors; its header says what it is
/// (`command_history` ends with sh2peaks), so the tensor reader refuses it in one line naming
/// that, its field kind is peaks, and the peaks reader reads what sh2peaks found: the
/// directions and amplitudes `make_sh.py` read back through nibabel (expected.json, MRtrix's
/// fit), voxel by voxel. `info` describes it (kind `peaks`, every voxel with three).
#[test]
fn an_sh2peaks_image_is_read_as_peaks_not_tensors() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/sh/sh2peaks_lmax8.mif");
    let opts = ReadOptions::default();
    let e = read_field(&p, &opts).unwrap_err().to_string();
    assert!(
        e.contains("'command_history'") && e.contains("sh2peaks") && e.contains("not tensors"),
        "{e}"
    );
    let inputs = tensorglyph::field::Inputs::file_system();
    assert_eq!(
        tensorglyph::field::FieldKind::of_file(&inputs, &p, &opts),
        tensorglyph::field::FieldKind::Peaks
    );
    let field = tensorglyph::field::read_peak_field_from(&inputs, &p, &opts).unwrap();
    assert_eq!((field.dims, field.per_voxel), ([4, 4, 4], 3));
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/sh/expected.json"),
    )
    .unwrap();
    let all: Value = serde_json::from_str(&text).unwrap();
    let want = &all["files"]["mrtrix_lmax8.mif"];
    let peaks = want["peaks"].as_object().unwrap();
    assert_eq!(peaks.len(), 64);
    for (v, pk) in peaks {
        let v: usize = v.parse().unwrap();
        let got: Vec<[f32; 3]> = field.peaks_of(v).collect();
        let dirs = pk["directions"].as_array().unwrap();
        let values = floats(&pk["values"]);
        assert_eq!(got.len(), dirs.len(), "voxel {v}");
        let at = floats(&want["positions"][v]);
        for (a, b) in field.position(v).iter().zip(&at) {
            assert!(
                (a - b).abs() < 1e-4,
                "voxel {v}: {:?} {at:?}",
                field.position(v)
            );
        }
        for ((g, d), value) in got.iter().zip(dirs).zip(&values) {
            let d = floats(d);
            let len = g.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>().sqrt();
            assert!(
                (len - value).abs() < 1e-5 * value,
                "voxel {v}: {len} {value}"
            );
            for c in 0..3 {
                assert!(
                    (f64::from(g[c]) / len - d[c]).abs() < 1e-5,
                    "voxel {v}: {g:?} {d:?}"
                );
            }
        }
    }
    let o = tg(&["info", p.to_str().unwrap(), "--json", "--sample", "21"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j = json(&o);
    assert_eq!(j["kind"], "peaks");
    assert_eq!(j["counts"], serde_json::json!([0, 0, 0, 64]));
    assert_eq!(
        j["samples"][0]["peaks"][0]["value"].as_f64().unwrap() as f32,
        floats(&peaks["21"]["values"])[0] as f32
    );
}
