//! Corrupted inputs: truncated, bit-flipped and count-inflated variants of every test file must
//! give an error or a consistent field, never a panic, a hang or an abort.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use tensorglyph::field::vtk::{ReadOptions, read_field};

/// Variants per file (a third truncations, the rest bit flips and digit insertions); fewer when
/// there is no RAM-backed temp directory, to stay well under a minute.
const VARIANTS: usize = 3000;
const VARIANTS_ON_DISK: usize = 600;

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn data_files(pred: impl Fn(&str) -> bool) -> Vec<PathBuf> {
    let dir = crate::data::path("vtk");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            !name.ends_with(".py") && !name.ends_with(".json") && pred(&name)
        })
        .collect();
    v.sort();
    v
}

fn variant(orig: &[u8], k: usize, rng: &mut XorShift) -> (Vec<u8>, String) {
    let mut b = orig.to_vec();
    match k % 3 {
        0 => {
            let len = if k < 3 * 64 {
                orig.len() * (k / 3) / 64
            } else {
                rng.below(orig.len())
            };
            b.truncate(len);
            (b, format!("truncated to {len}"))
        }
        1 => {
            let flips = 1 + rng.below(3);
            let mut what = String::from("flipped");
            for _ in 0..flips {
                let i = rng.below(b.len());
                let bit = rng.below(8);
                b[i] ^= 1 << bit;
                what += &format!(" byte {i} bit {bit}");
            }
            (b, what)
        }
        _ => {
            // Inflate a number: insert digits after a digit (counts, sizes, offsets).
            let digits: Vec<usize> = (0..b.len()).filter(|&i| b[i].is_ascii_digit()).collect();
            if digits.is_empty() {
                return (b, "unchanged".into());
            }
            let i = digits[rng.below(digits.len())];
            let ins: &[u8] = [&b"0"[..], b"9", b"99999", b"0000000000", b"-1"][rng.below(5)];
            b.splice(i + 1..i + 1, ins.iter().copied());
            (
                b,
                format!("inserted {:?} at {i}", String::from_utf8_lossy(ins)),
            )
        }
    }
}

fn run(files: Vec<PathBuf>, seed: u64) {
    assert!(!files.is_empty());
    // A RAM-backed directory when there is one: the test writes ~100k small files.
    let shm = Path::new("/dev/shm");
    let (tmp, variants) = match tempfile::tempdir_in(shm) {
        Ok(t) => (t, VARIANTS),
        Err(_) => (tempfile::tempdir().unwrap(), VARIANTS_ON_DISK),
    };
    // Pieces of .pvti files next to the variants, so that a corrupted .pvti still finds them.
    for p in data_files(|n| n.starts_with("pvti_") && n.ends_with(".vti")) {
        std::fs::copy(&p, tmp.path().join(p.file_name().unwrap())).unwrap();
    }
    let (tx, rx) = mpsc::channel::<Result<String, String>>();
    let dir = tmp.path().to_path_buf();
    let worker = std::thread::spawn(move || {
        let opts = ReadOptions::default();
        for (fi, path) in files.iter().enumerate() {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let orig = std::fs::read(path).unwrap();
            let mut rng = XorShift(seed ^ (0x9E37_79B9_7F4A_7C15u64.wrapping_mul(fi as u64 + 1)));
            let target = dir.join(&name);
            for k in 0..variants {
                let (bytes, what) = variant(&orig, k, &mut rng);
                std::fs::write(&target, &bytes).unwrap();
                let label = format!("{name}: {what}");
                let mut reads = vec![target.clone()];
                if let Some(stem) = name.strip_suffix(".vti")
                    && stem.starts_with("pvti_")
                {
                    let parent = stem.rsplit_once('_').unwrap().0;
                    reads.push(dir.join(format!("{parent}.pvti")));
                }
                for r in &reads {
                    let res = catch_unwind(AssertUnwindSafe(|| read_field(r, &opts)));
                    let msg = match res {
                        Err(_) => Err(format!("{label}: panicked reading {}", r.display())),
                        Ok(Ok(f)) if f.tensors.len() != f.positions.len() => Err(format!(
                            "{label}: {} tensors but {} positions",
                            f.tensors.len(),
                            f.positions.len()
                        )),
                        Ok(Ok(f)) if f.array.components != 6 && f.array.components != 9 => {
                            Err(format!("{label}: {} components", f.array.components))
                        }
                        Ok(Ok(_)) => Ok(label.clone()),
                        Ok(Err(e)) => {
                            let s = e.to_string();
                            // read_field's catch_unwind turns a panic into this error.
                            if s.contains("internal reader error") {
                                Err(format!("{label}: the reader panicked: {s}"))
                            } else if s.contains(r.file_name().unwrap().to_str().unwrap()) {
                                Ok(label.clone())
                            } else {
                                Err(format!("{label}: error does not name the file: {s}"))
                            }
                        }
                    };
                    if tx.send(msg).is_err() {
                        return;
                    }
                }
            }
            // Restore the original (pieces are shared by later .pvti variants).
            std::fs::write(&target, &orig).unwrap();
        }
    });
    let mut last = String::from("(start)");
    loop {
        match rx.recv_timeout(Duration::from_secs(20)) {
            Ok(Ok(label)) => last = label,
            Ok(Err(problem)) => panic!("{problem}"),
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("read hangs after: {last}"),
        }
    }
    worker.join().unwrap();
}

#[test]
fn corrupted_legacy_ascii() {
    run(
        data_files(|n| n.ends_with(".vtk") && n.contains("_ascii_")),
        1,
    );
}

#[test]
fn corrupted_legacy_binary() {
    run(
        data_files(|n| n.ends_with(".vtk") && n.contains("_bin_")),
        2,
    );
}

#[test]
fn corrupted_xml_image_and_pvti() {
    run(
        data_files(|n| n.ends_with(".vti") || n.ends_with(".pvti")),
        3,
    );
}

#[test]
fn corrupted_xml_grids() {
    run(
        data_files(|n| n.ends_with(".vtr") || n.ends_with(".vts")),
        4,
    );
}

#[test]
fn corrupted_xml_unstructured() {
    run(
        data_files(|n| n.ends_with(".vtu") || n.ends_with(".vtp")),
        5,
    );
}
