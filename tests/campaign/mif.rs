//! The campaign's cases for MRtrix images (`tests/data/mif`, see `main.rs`): header keys
//! (`dim`, `vox`, `layout`, `datatype`, `transform`, `scaling`, `file`, `END`) set to extreme
//! values, deleted, repeated or added, with the data kept at its offset where the header still
//! fits before it; the data cut and flipped; inside the gzip stream of `.mif.gz` and now and
//! then of the compressed bytes; a `.mih`'s detached data mutated and pointed at devices,
//! FIFOs and folders; and gzip bombs with honest headers. Tensor images are read as tensors,
//! scalar images as underlay and mask, and every image now and then as the volumes a later
//! reader (SH coefficients) takes.

use std::path::{Path, PathBuf};

use super::dti::{gunzip, gzip};
use super::mutate::{Rng, find_from, mutate, shape_of};
use super::pipeline::{Run, bomb};
use super::{Case, Read, data_files};

/// Values a header key is set to, by key.
fn values(key: &str) -> &'static [&'static str] {
    match key {
        "dim" => &[
            "5,4,3,6",
            "5,4,3,7",
            "5,4,3,9",
            "5,4,3,1",
            "0,4,3,6",
            "5,4,3",
            "5",
            "5,4,3,6,2",
            "65536,65536,65536,6",
            "18446744073709551615,2,1,6",
            "4294967296,4294967296,1,6",
            "-5,4,3,6",
            "1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1",
            "",
        ],
        "vox" => &[
            "2,2,2,1",
            "0,0,0",
            "nan,2,2",
            "-1,2,2",
            "inf,1,1",
            "1e308,1e308,1e308,1",
            "1e-308,1e-308,1e-308",
            "2",
            "2,2,2,2,2,2,2,2,2,2,2,2,2,2,2,2,2,2",
        ],
        "layout" => &[
            "+0,+1,+2,+3",
            "-0,-1,-2,-3",
            "+3,+2,+1,+0",
            "+1,+2,+3,+0",
            "-2,+0,-3,+1",
            "+0,+0,+1,+2",
            "+0,+1,+2",
            "+0,+1,+2,+4",
            "0,1,2,3",
            "+-0,+1,+2,+3",
            "+99999999999999999999,+1,+2,+3",
            "+0,+1",
        ],
        "datatype" => &[
            "Float32LE",
            "Float32BE",
            "Float64LE",
            "Float64BE",
            "Int8",
            "UInt8",
            "Int16BE",
            "UInt16LE",
            "Int32",
            "UInt64BE",
            "Bit",
            "CFloat32LE",
            "CFloat64",
            "Float16",
            "",
            "\u{1b}[2J",
        ],
        "transform" => &[
            "1,0,0,0",
            "0,0,0,0",
            "nan,0,0,0",
            "inf,0,0,0",
            "1e308,1e308,1e308,1e308",
            "1,0,0",
            "1,0,0,0,5",
            "1e-300,0,0,0",
        ],
        "scaling" => &["0,1", "nan,1", "0,0", "1e308,1e308", "1", "0,1,2", "-1,2"],
        "file" => &[
            ". 0",
            ". 1",
            ". 18446744073709551615",
            ". 18446744073709551616",
            ". -1",
            ". x",
            "/dev/zero 0",
            "/dev/urandom",
            "/ 0",
            "nonexistent.dat",
            "fifo.vti",
            "../../../../../../../../etc/hostname",
            ". 100 5",
            "tensor_detached.dat 0",
            "tensor_detached.dat 18446744073709551615",
        ],
        _ => &["", "\u{1b}[2J", "0", "x: y"],
    }
}

/// The header of an MRtrix image: its lines (without the first) up to `END`, and where the
/// data begins (`file: . OFFSET`, or the header's end).
fn split(b: &[u8]) -> Option<(Vec<String>, usize, usize)> {
    let end = find_from(b, 0, b"\nEND\n")? + 5;
    let text = std::str::from_utf8(&b[..end]).ok()?;
    let offset = text
        .lines()
        .find_map(|l| l.strip_prefix("file: . "))
        .and_then(|o| o.trim().parse().ok())
        .unwrap_or(end);
    let lines = text
        .lines()
        .skip(1)
        .filter(|l| *l != "END")
        .map(String::from)
        .collect();
    Some((lines, end, offset))
}

/// One mutation of the header of `b` (an uncompressed MRtrix image, or a `.mih`).
fn header(b: &[u8], rng: &mut Rng) -> Option<(Vec<u8>, String)> {
    let (mut lines, end, offset) = split(b)?;
    if lines.is_empty() {
        return None;
    }
    let keys = [
        "dim",
        "vox",
        "layout",
        "datatype",
        "transform",
        "scaling",
        "file",
    ];
    let what = match rng.below(6) {
        0..=2 => {
            let i = rng.below(lines.len());
            let key = lines[i].split(':').next().unwrap_or("").to_string();
            let v = values(&key);
            let v = v[rng.below(v.len())];
            lines[i] = format!("{key}: {v}");
            format!("'{key}' = {v:?}")
        }
        3 => {
            let i = rng.below(lines.len());
            let l = lines.remove(i);
            format!("'{l}' deleted")
        }
        4 => {
            let key = keys[rng.below(keys.len())];
            let v = values(key);
            let v = v[rng.below(v.len())];
            let at = rng.below(lines.len() + 1);
            lines.insert(at, format!("{key}: {v}"));
            format!("'{key}: {v}' added")
        }
        _ => {
            // No END: the header runs on into the data.
            let mut out = b"mrtrix image\n".to_vec();
            out.extend(lines.join("\n").bytes());
            out.push(b'\n');
            out.extend_from_slice(b.get(offset..).unwrap_or_default());
            return Some((out, "END deleted".into()));
        }
    };
    let mut out = format!("mrtrix image\n{}\nEND\n", lines.join("\n")).into_bytes();
    // The data stays at its offset where the header still ends before it.
    let data = b.get(offset.max(end)..).unwrap_or_default();
    if out.len() <= offset && offset <= b.len() {
        out.resize(offset, 0);
    }
    out.extend_from_slice(data);
    Some((out, what))
}

/// One mutation of the MRtrix image `orig` (`.mif`, `.mif.gz` inside its stream, now and
/// then its compressed bytes, or a `.mih`).
pub fn mif(orig: &[u8], k: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    let gz = orig.starts_with(&[0x1f, 0x8b]);
    let inner = if gz {
        gunzip(orig)
    } else {
        Some(orig.to_vec())
    };
    let Some(inner) = inner else {
        return mutate(orig, &shape_of(orig), k % 4, rng);
    };
    let (b, what) = match k % 8 {
        0..=4 => {
            header(&inner, rng).unwrap_or_else(|| mutate(&inner, &shape_of(&inner), k % 12, rng))
        }
        5 => {
            let (b, w) = header(&inner, rng).unwrap_or_else(|| (inner.clone(), String::new()));
            let (b, w2) = header(&b, rng).unwrap_or_else(|| (b, String::new()));
            (b, format!("{w}, {w2}"))
        }
        6 => {
            if gz && rng.below(2) == 0 {
                let (b, w) = mutate(orig, &shape_of(orig), [0, 2, 3][rng.below(3)], rng);
                return (b, format!("gzip stream: {w}"));
            }
            let cut = rng.below(inner.len() + 1);
            (inner[..cut].to_vec(), format!("cut at {cut}"))
        }
        _ => {
            let mut out = inner.clone();
            let mut what = String::from("flip");
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(out.len().max(1));
                let bit = rng.below(8);
                if let Some(x) = out.get_mut(i) {
                    *x ^= 1 << bit;
                }
                what += &format!(" {i}:{bit}");
            }
            (out, what)
        }
    };
    if gz { (gzip(&b), what) } else { (b, what) }
}

fn name_of(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// How the case's file is read, by what it holds and the case number.
fn read_as(name: &str, k: usize) -> Read {
    if k % 5 == 4 {
        return Read::Volumes;
    }
    if name.starts_with("scalar_") {
        return if k.is_multiple_of(2) {
            Read::Scalar
        } else {
            Read::Mask
        };
    }
    if name.starts_with("dwi_") {
        return Read::Volumes;
    }
    Read::Tensors(super::dti_options(k))
}

/// Every file of `root` mutated `per_file` times (`.mih` with its data file, each in turn),
/// the detached data pointed at special files, then bombs.
pub fn run_all(
    root: &Path,
    dir: &Path,
    seed: u64,
    per_file: usize,
    fifo: Option<&Path>,
    run: &mut Run,
) {
    let work = dir.join("mif");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    // `file: fifo.vti` leads to the FIFO.
    #[cfg(unix)]
    if let Some(f) = fifo {
        let _ = std::os::unix::fs::symlink(f, work.join("fifo.vti"));
    }
    #[cfg(not(unix))]
    let _ = fifo;
    let files: Vec<PathBuf> = data_files(root)
        .into_iter()
        .filter(|p| {
            let n = name_of(p);
            n.ends_with(".mif") || n.ends_with(".mif.gz") || n.ends_with(".mih")
        })
        .collect();
    assert!(files.len() >= 14, "{} MRtrix images", files.len());
    for (fi, f) in files.iter().enumerate() {
        let name = name_of(f);
        let mut rng = Rng(seed ^ (0x2545_F491_4F6C_DD1D_u64.wrapping_mul(fi as u64 + 1)));
        let orig = std::fs::read(f).unwrap();
        let target = work.join(&name);
        // A `.mih`'s data file: mutated in turn (the odd cases), read through the header.
        let detached = name.ends_with(".mih").then(|| {
            let d = root.join(name.replace(".mih", ".dat"));
            let t = work.join(name_of(&d));
            std::fs::copy(&d, &t).unwrap();
            (std::fs::read(&d).unwrap(), t)
        });
        for k in 0..=per_file {
            let (header, what) = match (&detached, k) {
                (_, 0) => (orig.clone(), "original".to_string()),
                (Some((data, t)), k) if k % 2 == 1 => {
                    let (b, w) = mutate(data, &shape_of(data), [0, 2, 3][k % 3], &mut rng);
                    std::fs::write(t, &b).unwrap();
                    (orig.clone(), format!("data file: {w}"))
                }
                _ => mif(&orig, k, &mut rng),
            };
            std::fs::write(&target, &header).unwrap();
            let data_bytes = detached.as_ref().map_or(0, |(_, t)| {
                std::fs::metadata(t).map_or(0, |m| m.len() as usize)
            });
            let case = Case {
                label: format!("seed {seed}: {name} #{k}: {what}"),
                path: target.clone(),
                input_bytes: header.len() + data_bytes,
                read: read_as(&name, k),
                names: vec![name.clone()],
            };
            if let Some((data, t)) = &detached
                && k % 2 == 1
            {
                let go = run(case);
                std::fs::write(t, data).unwrap();
                if !go {
                    return;
                }
                continue;
            }
            if !run(case) {
                return;
            }
        }
        let _ = std::fs::remove_file(&target);
    }

    // Bombs: honest headers whose zeros deflate about 1000 times, as tensors, as volumes and as
    // SH coefficients (`--sh-basis`, so that six volumes are SH too):
    // read within the budget, or refused by the gzip budget before anything is allocated. (A
    // field holds 96 bytes a voxel, positions and tensors, for the 24 its six float32 values
    // take: an image the budget lets inflate to more than about 16 MiB of tensors, such as
    // 128×128×70, is read whole and passes 64 MiB + 8× its 27 kB, in NIfTI as here.)
    let mib = 1u64 << 20;
    for (x, y, z, v) in [
        (64u64, 64, 64, 6),
        (96, 96, 48, 6),
        (256, 256, 128, 6),
        (96, 96, 60, 45),
        (512, 512, 256, 1),
    ] {
        let mut h = format!(
            "mrtrix image\ndim: {x},{y},{z},{v}\nvox: 2,2,2,1\nlayout: +3,+0,+1,+2\n\
             datatype: Float32LE\nfile: . 256\nEND\n"
        )
        .into_bytes();
        h.resize(256, 0);
        let bytes = (x * y * z * v * 4).min(1024 * mib);
        let gz = bomb(&h, bytes);
        let path = work.join("bomb.mif.gz");
        std::fs::write(&path, &gz).unwrap();
        let sh = tensorglyph::field::ReadOptions {
            sh_basis: Some(tensorglyph::sh::ShBasis::Tournier07),
            ..Default::default()
        };
        for read in [
            Read::Tensors(Default::default()),
            Read::Volumes,
            Read::Sh(sh),
        ] {
            let case = Case {
                label: format!(
                    "bomb: {x}×{y}×{z}×{v} f32, {} compressed bytes inflating to {bytes}",
                    gz.len()
                ),
                path: path.clone(),
                input_bytes: gz.len(),
                read,
                names: vec!["bomb.mif.gz".into()],
            };
            if !run(case) {
                return;
            }
        }
    }
    // Headers as large as allowed (16 MiB, in a few KB of gzip): one line, and a million
    // `transform` rows (issue 56's cases: 5–8 s to refuse the first, 71 MB for the second).
    let line = [
        b"mrtrix image\ncomment: ".as_slice(),
        &vec![b'x'; 16 << 20],
        b"\n",
    ]
    .concat();
    let row = b"transform: 1,0,0,0\n";
    let rows = [
        b"mrtrix image\ndim: 2,2,2,6\nvox: 1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n"
            .as_slice(),
        &row.repeat((16 << 20) / row.len() - 8),
        b"file: . 99999999\nEND\n",
    ]
    .concat();
    for (what, text) in [
        ("one 16 MiB line", line),
        ("16 MiB of transform rows", rows),
    ] {
        let gz = super::dti::gzip(&text);
        let path = work.join("header.mif.gz");
        std::fs::write(&path, &gz).unwrap();
        let case = Case {
            label: format!("header of {what}, {} compressed bytes", gz.len()),
            path: path.clone(),
            input_bytes: gz.len(),
            read: Read::Tensors(Default::default()),
            names: vec!["header.mif.gz".into()],
        };
        if !run(case) {
            return;
        }
    }
    let _ = std::fs::remove_dir_all(&work);
}
