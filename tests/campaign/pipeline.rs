//! The campaign's cases for what a pipeline feeds besides tensor files (see `main.rs`): BEP016
//! maps with their JSON sidecars, the scalar volumes of `--underlay` and `--mask`, and gzip
//! streams themselves (members, trailers, header flags, bombs).

use std::path::{Path, PathBuf};

use super::dti::{self, gunzip};
use super::mutate::{Rng, mutate, shape_of};
use super::{Case, Read, data_files};

/// `run` takes each case; it returns false when the campaign must stop.
pub type Run<'a> = dyn FnMut(Case) -> bool + 'a;

fn size_of(p: &Path) -> usize {
    std::fs::metadata(p).map_or(0, |m| m.len() as usize)
}

fn name_of(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

// ---------------------------------------------------------------------------------------------
// BEP016 maps and sidecars.

/// One mutation of a BEP016 sidecar: its two required keys set to wrong types and values,
/// removed, the JSON cut, nested, padded past the size cap, made not UTF-8.
fn sidecar(orig: &str, k: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    const AXES: [&str; 14] = [
        "\"xyz\"",
        "\"ijk\"",
        "\"IJK\"",
        "\"\"",
        "\"ijk \"",
        "\"zyx\"",
        "\"ras\"",
        "1",
        "null",
        "true",
        "[]",
        "{}",
        "\"\\u001b[2J\\n\"",
        "\"\\ud800\"",
    ];
    let set = |key: &str, value: &str| -> Vec<u8> {
        let mut v: serde_json::Map<String, serde_json::Value> = serde_json::from_str(orig).unwrap();
        match serde_json::from_str(value) {
            Ok(value) => {
                v.insert(key.into(), value);
                serde_json::to_vec(&v).unwrap()
            }
            // Not JSON serde can hold (a lone surrogate): spliced as text.
            Err(_) => orig
                .replacen("\"ijk\"", value, 1)
                .replacen("\"xyz\"", value, 1)
                .into_bytes(),
        }
    };
    match k % 10 {
        0 | 1 => {
            let v = AXES[rng.below(AXES.len())];
            (set("ReferenceAxes", v), format!("ReferenceAxes = {v}"))
        }
        2 => {
            let v = ["\"param\"", "\"vec\"", "\"\"", "5", "null", "[\"param\"]"][rng.below(6)];
            (
                set("OrientationRepresentation", v),
                format!("OrientationRepresentation = {v}"),
            )
        }
        3 => {
            let key = ["ReferenceAxes", "OrientationRepresentation"][rng.below(2)];
            let mut v: serde_json::Map<String, serde_json::Value> =
                serde_json::from_str(orig).unwrap();
            v.remove(key);
            (serde_json::to_vec(&v).unwrap(), format!("{key} removed"))
        }
        4 => {
            let cut = rng.below(orig.len());
            (orig.as_bytes()[..cut].to_vec(), format!("cut at {cut}"))
        }
        5 => {
            let depth = [100, 10_000, 200_000][rng.below(3)];
            let nested = format!("{}{}", "[".repeat(depth), "]".repeat(depth));
            (
                orig.replacen('{', &format!("{{\"Deep\": {nested},"), 1)
                    .into_bytes(),
                format!("nested {depth} deep"),
            )
        }
        6 => {
            // Around the 1 MiB cap on sidecars.
            let pad = [(1 << 20) - 300, (1 << 20) + 1, 3 << 20][rng.below(3)];
            let mut b = orig.as_bytes().to_vec();
            b.extend(std::iter::repeat_n(b' ', pad));
            (b, format!("padded by {pad} spaces"))
        }
        7 => {
            let mut b = orig.as_bytes().to_vec();
            let i = rng.below(b.len());
            b[i] = [0xff, 0x00, 0xc3, 0x80][rng.below(4)];
            (b, format!("byte {i} not UTF-8 / NUL"))
        }
        8 => {
            // Duplicate keys that contradict each other; a BOM.
            let dup = orig.replacen('{', "{\"ReferenceAxes\": \"xyz\",", 1);
            if rng.below(2) == 0 {
                (dup.into_bytes(), "ReferenceAxes twice".into())
            } else {
                let mut b = vec![0xef, 0xbb, 0xbf];
                b.extend(orig.as_bytes());
                (b, "BOM".into())
            }
        }
        _ => {
            let whole = ["", "null", "[]", "123", "\"ijk\"", "{", "}", "{\"a\":}"][rng.below(8)];
            (
                whole.as_bytes().to_vec(),
                format!("the whole sidecar is {whole:?}"),
            )
        }
    }
}

/// Every map of `bids` with its sidecar, mutated in turn; the sidecar also missing, a folder,
/// a FIFO or a device. Read by the map's name, as everywhere.
fn bep016(bids: &Path, dir: &Path, seed: u64, per_file: usize, fifo: Option<&Path>, run: &mut Run) {
    let maps: Vec<PathBuf> = super::data::files_below(bids)
        .into_iter()
        .filter(|p| name_of(p).ends_with("_dwimap.nii.gz"))
        .collect();
    assert!(maps.len() >= 5, "{} BEP016 maps", maps.len());
    let work = dir.join("bep016");
    for (mi, map) in maps.iter().enumerate() {
        let mut rng = Rng(seed ^ (0x2545_F491_4F6C_DD1D_u64.wrapping_mul(mi as u64 + 1)));
        let name = name_of(map);
        let side_name = name
            .replace("_param-tensor", "")
            .replace(".nii.gz", ".json");
        let side_orig = std::fs::read_to_string(map.with_file_name(&side_name)).unwrap();
        let map_orig = std::fs::read(map).unwrap();
        let _ = std::fs::remove_dir_all(&work);
        std::fs::create_dir_all(&work).unwrap();
        let (m, s) = (work.join(&name), work.join(&side_name));
        let case = |label: String, bytes: usize| Case {
            label,
            path: m.clone(),
            input_bytes: bytes,
            read: Read::Tensors(Default::default()),
            names: vec![side_name.clone()],
        };
        for k in 0..=per_file / 4 {
            // Half the cases mutate the sidecar, half the map under a good sidecar.
            let (map_bytes, side_bytes, what) = if k == 0 {
                (
                    map_orig.clone(),
                    side_orig.as_bytes().to_vec(),
                    "original".into(),
                )
            } else if k % 2 == 1 {
                let (b, w) = sidecar(&side_orig, k / 2, &mut rng);
                (map_orig.clone(), b, format!("sidecar: {w}"))
            } else {
                let (b, w) = dti::nifti(&map_orig, k / 2, &mut rng);
                (b, side_orig.as_bytes().to_vec(), format!("map: {w}"))
            };
            std::fs::write(&m, &map_bytes).unwrap();
            std::fs::write(&s, &side_bytes).unwrap();
            let label = format!("seed {seed}: {name} #{k}: {what}");
            if !run(case(label, map_bytes.len() + side_bytes.len())) {
                return;
            }
        }
        // The sidecar is no regular file, or absent.
        std::fs::write(&m, &map_orig).unwrap();
        let mut specials: Vec<(String, Option<PathBuf>)> = vec![
            ("absent".into(), None),
            ("a folder".into(), None),
            ("a dangling link".into(), Some(work.join("nowhere.json"))),
        ];
        for d in ["/dev/zero", "/dev/urandom"] {
            if Path::new(d).exists() {
                specials.push((format!("a link to {d}"), Some(PathBuf::from(d))));
            }
        }
        if let Some(f) = fifo {
            specials.push(("a link to a FIFO".into(), Some(f.to_path_buf())));
        }
        for (what, target) in specials {
            let _ = std::fs::remove_file(&s);
            let _ = std::fs::remove_dir(&s);
            match (&target, what.as_str()) {
                (Some(t), _) => std::os::unix::fs::symlink(t, &s).unwrap(),
                (None, "a folder") => std::fs::create_dir(&s).unwrap(),
                _ => {}
            }
            let label = format!("{name}: the sidecar is {what}");
            if !run(case(label, map_orig.len())) {
                return;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&work);
}

// ---------------------------------------------------------------------------------------------
// Scalar volumes (`--underlay`, `--mask`).

/// Every file of `tests/data/scalars` (a detached `.nhdr` with its data), mutated by its
/// structure and read as an underlay (the volume) or a mask, alternately.
fn scalars(root: &Path, dir: &Path, seed: u64, per_file: usize, run: &mut Run) {
    let files = data_files(root);
    assert!(files.len() >= 20, "{} scalar files", files.len());
    let work = dir.join("scalars");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    for f in &files {
        std::fs::copy(f, work.join(name_of(f))).unwrap();
    }
    let all_bytes: usize = files.iter().map(|f| size_of(f)).sum();
    for (fi, f) in files.iter().enumerate() {
        let name = name_of(f);
        let mut rng = Rng(seed ^ (0x9FB2_1C65_1E98_DF25_u64.wrapping_mul(fi as u64 + 1)));
        let orig = std::fs::read(f).unwrap();
        let target = work.join(&name);
        // A detached data file is read through its header.
        let read_by = if name.ends_with(".raw") {
            let header = files
                .iter()
                .find(|h| {
                    name_of(h).ends_with(".nhdr")
                        && std::fs::read_to_string(h).is_ok_and(|t| t.contains(&name))
                })
                .map(|h| work.join(name_of(h)));
            let Some(header) = header else { continue };
            header
        } else {
            target.clone()
        };
        for k in 0..=per_file / 2 {
            let (bytes, what) = if k == 0 {
                (orig.clone(), "original".to_string())
            } else if name.ends_with(".nii") || name.ends_with(".nii.gz") {
                dti::nifti(&orig, k, &mut rng)
            } else if name.ends_with(".nrrd") || name.ends_with(".nhdr") {
                dti::nrrd(&orig, k, &mut rng)
            } else {
                mutate(&orig, &shape_of(&orig), k % 12, &mut rng)
            };
            std::fs::write(&target, &bytes).unwrap();
            let read = if k % 2 == 0 { Read::Scalar } else { Read::Mask };
            let case = Case {
                label: format!(
                    "seed {seed}: {name} #{k}: {what} (as {})",
                    if k % 2 == 0 { "an underlay" } else { "a mask" }
                ),
                path: read_by.clone(),
                input_bytes: all_bytes + bytes.len(),
                read,
                names: vec![name.clone()],
            };
            if !run(case) {
                return;
            }
        }
        std::fs::write(&target, &orig).unwrap();
    }
    let _ = std::fs::remove_dir_all(&work);
}

// ---------------------------------------------------------------------------------------------
// Gzip streams.

/// One mutation of the gzip framing of `gz` (one member): its trailer, header flags, members
/// after it, bytes after it, cuts and flips of the deflate data.
fn gzip_stream(gz: &[u8], k: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    let n = gz.len();
    let mut b = gz.to_vec();
    let what = match k % 10 {
        0 => {
            let i = n - 8 + rng.below(4);
            b[i] ^= 1 << rng.below(8);
            format!("CRC-32 byte {i} flipped")
        }
        1 => {
            let v: u32 = [0, 1, u32::MAX][rng.below(3)];
            let size = u32::from_le_bytes(b[n - 4..].try_into().unwrap());
            let v = if v == 1 { size.wrapping_add(1) } else { v };
            b[n - 4..].copy_from_slice(&v.to_le_bytes());
            format!("ISIZE {v}")
        }
        2 => {
            let tail: Vec<u8> = match rng.below(4) {
                0 => vec![0],
                1 => vec![0; 100],
                2 => vec![0x1f, 0x8b],
                _ => (0..1 + rng.below(64)).map(|_| rng.next() as u8).collect(),
            };
            let what = format!("{} bytes after the member", tail.len());
            b.extend(tail);
            what
        }
        3 => {
            b.extend_from_slice(gz);
            "the member twice".into()
        }
        4 => {
            let junk: Vec<u8> = (0..1 + rng.below(4096)).map(|_| rng.next() as u8).collect();
            b.extend(dti::gzip(&junk));
            format!("a second member of {} random bytes", junk.len())
        }
        5 => {
            let cut = [10, 11, n - 8, n - 4, n - 1][rng.below(5)].min(n);
            let cut = if rng.below(2) == 0 { cut } else { rng.below(n) };
            b.truncate(cut);
            format!("cut at {cut}")
        }
        6 => {
            // FLG: FHCRC, FEXTRA, FNAME, FCOMMENT, reserved; the bytes after are then read
            // as what the flag announces.
            let bit = [1, 2, 3, 4, 5, 6, 7][rng.below(7)];
            b[3] ^= 1 << bit;
            if bit == 2 && rng.below(2) == 0 {
                // FEXTRA with the largest XLEN.
                b.splice(10..10, [0xff, 0xff]);
            }
            format!("FLG bit {bit}")
        }
        7 => {
            let i = 10 + rng.below(n.saturating_sub(18).max(1));
            b[i.min(n - 1)] ^= 1 << rng.below(8);
            format!("deflate bit flip at {i}")
        }
        8 => {
            let (i, v) = [(0, 0x1e), (1, 0x8c), (2, 7), (2, 0)][rng.below(4)];
            b[i] = v;
            format!("header byte {i} = {v}")
        }
        _ => {
            let empty = dti::gzip(b"");
            let first = rng.below(2) == 0;
            b = if first {
                [&empty[..], gz].concat()
            } else {
                [gz, &empty[..]].concat()
            };
            format!("an empty member {}", if first { "first" } else { "last" })
        }
    };
    (b, what)
}

/// A `header` (a NIfTI-1 one of 352 bytes, or an MRtrix one, uncompressed) whose data are
/// `data_bytes` of zeros, as gzip
/// made cheaply: one deflated MiB of zeros ending on a full flush (byte-aligned, restartable)
/// repeated, then a final empty block. The trailer's CRC and size are right.
pub fn bomb(header: &[u8], data_bytes: u64) -> Vec<u8> {
    const CHUNK: usize = 1 << 20;
    let zeros = vec![0u8; CHUNK];
    let mut c = flate2::Compress::new(flate2::Compression::best(), false);
    let mut head = Vec::with_capacity(1 << 16);
    c.compress_vec(header, &mut head, flate2::FlushCompress::Full)
        .unwrap();
    let mut unit = Vec::with_capacity(1 << 16);
    c.compress_vec(&zeros, &mut unit, flate2::FlushCompress::Full)
        .unwrap();
    assert_eq!(
        c.total_in() as usize,
        header.len() + CHUNK,
        "grow the buffer"
    );
    let mut crc = flate2::Crc::new();
    crc.update(header);
    let whole = data_bytes / CHUNK as u64;
    let rest = (data_bytes % CHUNK as u64) as usize;
    for _ in 0..whole {
        crc.update(&zeros);
    }
    let mut out = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255];
    out.extend(&head);
    for _ in 0..whole {
        out.extend(&unit);
    }
    let mut tail = Vec::with_capacity(1 << 16);
    let mut c2 = flate2::Compress::new(flate2::Compression::best(), false);
    c2.compress_vec(&zeros[..rest], &mut tail, flate2::FlushCompress::Finish)
        .unwrap();
    crc.update(&zeros[..rest]);
    out.extend(&tail);
    out.extend(crc.sum().to_le_bytes());
    out.extend(((header.len() as u64 + data_bytes) as u32).to_le_bytes());
    out
}

/// `header` (a NIfTI-1 header of 352 bytes) with its dimensions set to `dims`.
fn with_dims(header: &[u8], dims: &[i16]) -> Vec<u8> {
    let mut h = header[..352].to_vec();
    h[40..42].copy_from_slice(&(dims.len() as i16).to_le_bytes());
    for i in 0..7 {
        let v = dims.get(i).copied().unwrap_or(1);
        h[42 + 2 * i..44 + 2 * i].copy_from_slice(&v.to_le_bytes());
    }
    // vox_offset 352, no extension.
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h[348..352].copy_from_slice(&[0; 4]);
    h
}

/// Gzip framing of every `.nii.gz` tensor map and scalar volume, then bombs: honest headers
/// whose zeros deflate up to 1000×, as tensors, underlay and mask.
fn gzip(files: &[PathBuf], dir: &Path, seed: u64, per_file: usize, run: &mut Run) {
    let work = dir.join("gzip");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    for (fi, f) in files.iter().enumerate() {
        let name = name_of(f);
        let orig = std::fs::read(f).unwrap();
        // One member, as our test files are: the mutations assume it.
        if gunzip(&orig).is_none() {
            continue;
        }
        let scalar = f.parent().is_some_and(|p| p.ends_with("scalars"));
        let mut rng = Rng(seed ^ (0xD6E8_FEB8_6659_FD93_u64.wrapping_mul(fi as u64 + 1)));
        let target = work.join(&name);
        for k in 1..=per_file / 8 {
            let (bytes, what) = gzip_stream(&orig, k, &mut rng);
            std::fs::write(&target, &bytes).unwrap();
            let read = match (scalar, k % 2) {
                (false, _) => Read::Tensors(Default::default()),
                (true, 0) => Read::Scalar,
                (true, _) => Read::Mask,
            };
            let case = Case {
                label: format!("seed {seed}: {name} #{k}: gzip {what}"),
                path: target.clone(),
                input_bytes: bytes.len(),
                read,
                names: vec![name.clone()],
            };
            if !run(case) {
                return;
            }
        }
        let _ = std::fs::remove_file(&target);
    }

    // Bombs. A tensor header from a map, a scalar one from a volume.
    let header_of = |suffix: &str| {
        files
            .iter()
            .filter(|f| name_of(f).ends_with(suffix))
            .find_map(|f| gunzip(&std::fs::read(f).ok()?))
            .filter(|h| h.len() >= 352)
            .expect("a gzip NIfTI to take a header from")
    };
    let tensor = header_of("_dwimap.nii.gz");
    let scalar = header_of("u8.nii.gz");
    let mib = 1u64 << 20;
    // (what, header, data bytes)
    let mut bombs: Vec<(String, Vec<u8>, u64)> = Vec::new();
    for (x, y, z) in [
        (64i16, 64, 64),
        (128, 128, 70),
        (256, 256, 128),
        (512, 512, 256),
    ] {
        let dims = [4, x, y, z, 6];
        let bytes = [x, y, z].iter().map(|&v| v as u64).product::<u64>() * 6 * 4;
        bombs.push((
            format!("tensors {x}×{y}×{z}×6 f32"),
            with_dims(&tensor, &dims),
            bytes,
        ));
    }
    for (x, y, z) in [(256i16, 256, 256), (1024, 1024, 512)] {
        let bytes = [x, y, z].iter().map(|&v| v as u64).product::<u64>();
        let mut h = with_dims(&scalar, &[3, x, y, z]);
        // uint8
        h[70..72].copy_from_slice(&2i16.to_le_bytes());
        h[72..74].copy_from_slice(&8i16.to_le_bytes());
        bombs.push((format!("scalars {x}×{y}×{z} u8"), h, bytes));
    }
    for (what, header, bytes) in bombs {
        // Past 1 GiB the zeros are not written out: the stream is cut there (the header still
        // asks for all of it).
        let written = bytes.min(1024 * mib);
        let gz = bomb(&header, written);
        let path = work.join("bomb.nii.gz");
        std::fs::write(&path, &gz).unwrap();
        let reads: &[Read] = if what.starts_with("tensors") {
            &[Read::Tensors(Default::default())]
        } else {
            &[Read::Scalar, Read::Mask]
        };
        for read in reads {
            let case = Case {
                label: format!(
                    "bomb: {what}, {} compressed bytes inflating to {written}",
                    gz.len()
                ),
                path: path.clone(),
                input_bytes: gz.len(),
                read: read.clone(),
                names: vec!["bomb.nii.gz".into()],
            };
            if !run(case) {
                return;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&work);
}

/// All of the above.
pub fn run_all(dir: &Path, seed: u64, per_file: usize, fifo: Option<&Path>, run: &mut Run) {
    let data = |p: &str| super::data::path(p);
    bep016(&data("bids/derivatives"), dir, seed, per_file, fifo, run);
    scalars(&data("scalars"), dir, seed, per_file, run);
    let mut gz: Vec<PathBuf> = data_files(&data("dti"));
    gz.extend(data_files(&data("scalars")));
    gz.extend(super::data::files_below(&data("bids/derivatives")));
    // Not the members of an FSL eigen set: alone they are refused for the missing five.
    let member = |n: &str| {
        ["L1", "L2", "L3", "V1", "V2", "V3"]
            .iter()
            .any(|m| n.ends_with(&format!("_{m}.nii.gz")))
    };
    gz.retain(|p| name_of(p).ends_with(".nii.gz") && !member(&name_of(p)));
    gz.sort();
    gzip(&gz, dir, seed, per_file, run);
}
