//! The campaign's structure-aware mutations of the DTI files in `tests/data/dti` (see
//! `main.rs`): NIfTI-1 header fields by their offsets (inside the gzip stream for
//! `.nii.gz`), NRRD header fields by name, detached data and FIFO, device and folder targets.

use super::mutate::{Rng, find_from, mutate, shape_of};

// ---------------------------------------------------------------------------------------------
// NIfTI-1.

/// Header fields: name, byte offset, kind (`s` i16, `i` i32, `f` f32, `m` the 4-byte magic,
/// `x` the extension flag), count.
const NIFTI_FIELDS: [(&str, usize, char, usize); 18] = [
    ("sizeof_hdr", 0, 'i', 1),
    ("dim", 40, 's', 8),
    ("intent_code", 68, 's', 1),
    ("datatype", 70, 's', 1),
    ("bitpix", 72, 's', 1),
    ("pixdim", 76, 'f', 8),
    ("vox_offset", 108, 'f', 1),
    ("scl_slope", 112, 'f', 1),
    ("scl_inter", 116, 'f', 1),
    ("qform_code", 252, 's', 1),
    ("sform_code", 254, 's', 1),
    ("quatern", 256, 'f', 3),
    ("qoffset", 268, 'f', 3),
    ("srow_x", 280, 'f', 4),
    ("srow_y", 296, 'f', 4),
    ("srow_z", 312, 'f', 4),
    ("magic", 344, 'm', 1),
    ("extension", 348, 'x', 1),
];

const I16S: [i16; 16] = [
    0,
    -1,
    1,
    2,
    3,
    4,
    5,
    6,
    7,
    9,
    16,
    64,
    1005,
    1007,
    i16::MAX,
    i16::MIN,
];
const I32S: [i32; 6] = [0, -1, 348, 540, i32::MAX, 0x5c01_0000];
const F32S: [f32; 14] = [
    0.0,
    -1.0,
    1.0,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MAX,
    -f32::MAX,
    1e-38,
    352.0,
    4096.0,
    2147483648.0,
    1e30,
    0.5,
];
const MAGICS: [&[u8; 4]; 5] = [b"ni1\0", b"n+2\0", b"\0\0\0\0", b"n+1\n", b"\xff+1\0"];

pub fn gunzip(b: &[u8]) -> Option<Vec<u8>> {
    use std::io::Read as _;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(b)
        .read_to_end(&mut out)
        .ok()?;
    Some(out)
}

pub fn gzip(b: &[u8]) -> Vec<u8> {
    use std::io::Write as _;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(b).unwrap();
    e.finish().unwrap()
}

/// One header field of `b` (a whole `.nii`) set to an extreme value.
fn nifti_field(b: &[u8], rng: &mut Rng) -> (Vec<u8>, String) {
    let mut out = b.to_vec();
    let (name, off, kind, count) = NIFTI_FIELDS[rng.below(NIFTI_FIELDS.len())];
    let i = rng.below(count);
    let what = match kind {
        's' => {
            let v = I16S[rng.below(I16S.len())];
            put(&mut out, off + 2 * i, &v.to_le_bytes());
            format!("{name}[{i}] = {v}")
        }
        'i' => {
            let v = I32S[rng.below(I32S.len())];
            put(&mut out, off, &v.to_le_bytes());
            format!("{name} = {v}")
        }
        'f' => {
            let v = F32S[rng.below(F32S.len())];
            put(&mut out, off + 4 * i, &v.to_le_bytes());
            format!("{name}[{i}] = {v}")
        }
        'm' => {
            let v = MAGICS[rng.below(MAGICS.len())];
            put(&mut out, off, v);
            format!("{name} = {v:?}")
        }
        _ => {
            // An extension flagged, with a size that may run past the data.
            let size = [0i32, 8, 16, -8, 1 << 20][rng.below(5)];
            put(&mut out, off, &[1, 0, 0, 0]);
            let mut ext = size.to_le_bytes().to_vec();
            ext.extend_from_slice(&4i32.to_le_bytes());
            out.splice(352.min(out.len())..352.min(out.len()), ext);
            format!("extension of {size} bytes")
        }
    };
    (out, what)
}

fn put(out: &mut [u8], at: usize, v: &[u8]) {
    if let Some(s) = out.get_mut(at..at + v.len()) {
        s.copy_from_slice(v);
    }
}

/// The data of a `.nii` swapped to big-endian in its header only (sizeof_hdr, dims, type...),
/// so that every other field is read as a byte-swapped number.
fn nifti_swapped(b: &[u8]) -> Vec<u8> {
    let mut out = b.to_vec();
    if let Some(s) = out.get_mut(0..4) {
        s.reverse();
    }
    out
}

/// One mutation of the NIfTI file `orig` (`.nii` or `.nii.gz`): header fields, cuts, flips;
/// for `.nii.gz` mostly inside the stream, now and then of the compressed bytes.
pub fn nifti(orig: &[u8], k: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    let gz = orig.starts_with(&[0x1f, 0x8b]);
    let inner = if gz {
        gunzip(orig)
    } else {
        Some(orig.to_vec())
    };
    let Some(inner) = inner.filter(|b| b.len() >= 352) else {
        return mutate(orig, &shape_of(orig), k % 4, rng);
    };
    let (b, what) = match k % 8 {
        0..=3 => nifti_field(&inner, rng),
        4 => {
            let (b, w) = nifti_field(&inner, rng);
            let (b, w2) = nifti_field(&b, rng);
            (b, format!("{w}, {w2}"))
        }
        5 => {
            let cuts = [0, 4, 40, 100, 347, 348, 351, 352, 353, inner.len() - 1];
            let cut = if rng.below(2) == 0 {
                cuts[rng.below(cuts.len())]
            } else {
                rng.below(inner.len())
            };
            (inner[..cut].to_vec(), format!("cut at {cut}"))
        }
        6 => (nifti_swapped(&inner), "sizeof_hdr byte-swapped".into()),
        _ => {
            if gz && rng.below(2) == 0 {
                // The compressed bytes themselves: cuts and flips of the stream.
                let (b, w) = mutate(orig, &shape_of(orig), [0, 2, 3][rng.below(3)], rng);
                return (b, format!("gzip stream: {w}"));
            }
            let mut out = inner.clone();
            let n = 1 + rng.below(4);
            let mut what = String::from("flip");
            for _ in 0..n {
                let i = rng.below(out.len());
                let bit = rng.below(8);
                out[i] ^= 1 << bit;
                what += &format!(" {i}:{bit}");
            }
            (out, what)
        }
    };
    if gz { (gzip(&b), what) } else { (b, what) }
}

// ---------------------------------------------------------------------------------------------
// NRRD.

/// Values a NRRD field can be set to, by field.
fn nrrd_values(key: &str) -> &'static [&'static str] {
    match key {
        "type" => &["float", "double", "int", "uchar", "float64", "block", ""],
        "dimension" => &["0", "1", "3", "4", "5", "-1", "18446744073709551616"],
        "sizes" => &[
            "6 5 4 3",
            "7 5 4 3",
            "9 5 4 3",
            "6 0 4 3",
            "6 5 4",
            "6 65536 65536 65536",
            "6 18446744073709551615 2 1",
            "6 4294967296 4294967296 1",
            "-6 5 4 3",
        ],
        "kinds" => &[
            "3D-symmetric-matrix space space space",
            "3D-masked-symmetric-matrix space space space",
            "3D-matrix space space space",
            "3D-tensor space space space",
            "space space space",
            "\u{1b}[2J space space space",
        ],
        "encoding" => &["raw", "gzip", "ascii", "bzip2", "hex", "text"],
        "endian" => &["big", "little", "middle", ""],
        "byte skip" => &["-1", "0", "1", "4", "-2", "4096", "9223372036854775807"],
        "line skip" => &["0", "1", "2", "1000000", "-1"],
        "space" => &[
            "left-posterior-superior",
            "right-anterior-superior",
            "scanner-xyz",
            "3D-right-handed-time",
        ],
        "space directions" => &[
            "none (1,0,0) (0,1,0) (0,0,1)",
            "none (0,0,0) (0,0,0) (0,0,0)",
            "none (nan,0,0) (0,1,0) (0,0,1)",
            "(1,0,0) (0,1,0) (0,0,1) none",
            "none (1,0) (0,1,0) (0,0,1)",
            "none (1e308,1e308,0) (0,1e308,0) (0,0,1e308)",
        ],
        "space origin" => &["(0,0,0)", "none", "(inf,0,0)", "(1,2)"],
        "measurement frame" => &[
            "(1,0,0) (0,1,0) (0,0,1)",
            "(0,0,0) (0,0,0) (0,0,0)",
            "none none none",
            "(1,0,0) (0,1,0)",
        ],
        "data file" => &[
            "/dev/zero",
            "/dev/urandom",
            "/",
            ".",
            "nonexistent.raw",
            "LIST",
            "fifo.vti",
            "../../../../../../../../etc/hostname",
            "d.raw 1 2 1",
        ],
        _ => &["", "none", "0", "\u{1b}[2J"],
    }
}

/// Header lines of a NRRD (`key: value`), as byte ranges of the value, with the key.
fn nrrd_fields(b: &[u8]) -> Vec<(String, usize, usize)> {
    let end = find_from(b, 0, b"\n\n").unwrap_or(b.len());
    let mut out = Vec::new();
    let mut i = 0;
    while i < end {
        let e = find_from(b, i, b"\n").unwrap_or(end).min(end);
        if let Some(c) = find_from(&b[..e], i, b": ") {
            let key = String::from_utf8_lossy(&b[i..c]).to_ascii_lowercase();
            out.push((key, c + 2, e));
        }
        i = e + 1;
    }
    out
}

/// One mutation of the NRRD header or attached file `orig`.
pub fn nrrd(orig: &[u8], k: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    let fields = nrrd_fields(orig);
    if fields.is_empty() || k.is_multiple_of(3) {
        return mutate(orig, &shape_of(orig), k % 12, rng);
    }
    let splice = |at: (usize, usize), with: &[u8]| [&orig[..at.0], with, &orig[at.1..]].concat();
    let (key, lo, hi) = &fields[rng.below(fields.len())];
    match rng.below(5) {
        0 => (
            splice((*lo - key.len() - 2, (*hi + 1).min(orig.len())), b""),
            format!("'{key}' deleted"),
        ),
        1 => {
            // A field the file does not have, added.
            let add = [
                "data file",
                "byte skip",
                "line skip",
                "measurement frame",
                "space",
                "endian",
            ][rng.below(6)];
            let v = nrrd_values(add);
            let v = v[rng.below(v.len())];
            let line = format!("{add}: {v}\n");
            let at = (*hi + 1).min(orig.len());
            (
                splice((at, at), line.as_bytes()),
                format!("'{add}: {v}' added"),
            )
        }
        _ => {
            let v = nrrd_values(key);
            let v = v[rng.below(v.len())];
            (splice((*lo, *hi), v.as_bytes()), format!("'{key}' = {v:?}"))
        }
    }
}
