//! The mutation campaign of issue 13, on stable Rust and on every `cargo test`.
//!
//! Every file in `tests/data/vtk` and `tests/data/regressions` is mutated structure-aware: cut at
//! structural offsets (line starts, tag boundaries, the appended-data marker, compressed block
//! headers), bit-flipped, header numbers replaced by 0, −1, 2³¹, 2⁶³, NaN and friends, compressed
//! block headers and payloads corrupted, base64 broken, tags nested past the depth cap and
//! repeated, control characters planted in names, `.pvti` pieces pointed at FIFOs, devices and
//! absolute paths. The DTI files of `tests/data/dti` are mutated the same way by their structure:
//! NIfTI-1 header fields at their offsets (inside the gzip stream of `.nii.gz`), NRRD header
//! fields by name (data files pointed at devices, FIFOs, folders), detached NRRD data, and each
//! file of an FSL eigen set read with the other five (by its own name and by the prefix). The
//! BEP016 maps and sidecars, the scalar volumes of `--underlay`/`--mask`, gzip framing and
//! decompression bombs are mutated in `pipeline.rs`; the MRtrix images of `tests/data/mif`
//! (header keys, data, a `.mih`'s detached data, bombs) in `mif.rs`; the SH coefficient files of
//! `tests/data/sh` (NIfTI and MRtrix) with the same mutations, read as `info` reads them (SH or
//! tensors, then the field, its report and a voxel's peaks). Each case is read once,
//! sequentially, and must:
//! - return a consistent field (as many positions as tensors, as the location's count, as the
//!   dimensions say; 6, 7 or 9 components), which must then go through `derive_glyphs` (no
//!   glyph with a non-finite eigenvalue) and the `info` report; or a consistent scalar volume
//!   or mask; or an error whose `Display` is one line without control characters that
//!   names the file;
//! - take at most 2 s and allocate at most 64 MiB + 8× the bytes of the files read (measured by
//!   the counting global allocator below, peak reset per case);
//! - leave the file as it was.
//!
//! Seeded: `TENSORGLYPH_CAMPAIGN_SEED` (default 13) and `TENSORGLYPH_CAMPAIGN_CASES` (per file,
//! default 400) reproduce or widen a run; a failing case is saved under `CARGO_TARGET_TMPDIR`
//! for `tests/data/regressions/`.
//!
//! A test binary of its own (`cargo test --test campaign`): the counting allocator is the
//! `#[global_allocator]`, which holds for a whole binary, and no other test may share the
//! peak it measures.

// The counting allocator needs `unsafe impl GlobalAlloc`; nothing else in this crate is unsafe.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use tensorglyph::field::{
    ComponentOrder, ReadOptions, TensorFrame, read_field, read_scalar_volume,
};

// ---------------------------------------------------------------------------------------------
// Counting allocator: current and peak live bytes of the whole process. The cases run one at a
// time on one thread and the only other thread (the test's) waits on a channel, so the peak
// over a case is that case's.

struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(n: usize) {
    let now = CURRENT.fetch_add(n, Relaxed) + n;
    PEAK.fetch_max(now, Relaxed);
}

fn shrank(n: usize) {
    CURRENT.fetch_sub(n, Relaxed);
}

// SAFETY: every call is forwarded unchanged to `System`; the counters only observe sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                grew(new_size - layout.size());
            } else {
                shrank(layout.size() - new_size);
            }
        }
        p
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Start measuring: the peak from now on, above what is live now.
fn peak_reset() -> usize {
    let now = CURRENT.load(Relaxed);
    PEAK.store(now, Relaxed);
    now
}

#[path = "../common/data.rs"]
mod data;
mod dti;
mod mif;
mod mutate;
mod pipeline;

use mutate::{Rng, mutate, shape_of};

// ---------------------------------------------------------------------------------------------
// Running and judging one case.

const BUDGET_FIXED: usize = 64 << 20;
const BUDGET_PER_BYTE: usize = 8;
const TIME_LIMIT: Duration = Duration::from_secs(2);

/// How a case's file is read: as tensors (`render FILE`), or as the scalar volume of
/// `--underlay FILE` or `--mask FILE`.
#[derive(Clone)]
enum Read {
    Tensors(ReadOptions),
    Scalar,
    Mask,
    /// Every value of an MRtrix image, as a reader of SH coefficients takes them.
    Volumes,
    /// SH coefficients (`info` on an SH file): whether the file holds SH, then the field,
    /// its `info` report and a voxel's peaks.
    Sh(ReadOptions),
}

/// What a case read.
enum Got {
    Field(Box<tensorglyph::TensorField>),
    Volume(tensorglyph::field::ScalarVolume),
    Mask,
    Volumes(tensorglyph::field::mif::Volumes),
    Sh(Box<tensorglyph::field::ShField>),
}

struct Case {
    label: String,
    /// The file to read.
    path: PathBuf,
    /// Bytes of every file the read may open (the file, its pieces).
    input_bytes: usize,
    read: Read,
    /// File names an error may name instead of the file read: the files of an FSL eigen set
    /// (an error names the one at fault).
    names: Vec<String>,
}

#[derive(Default)]
struct Tally {
    cases: usize,
    ok: usize,
    errors: usize,
    worst_peak: (usize, String),
    worst_time: (Duration, String),
}

fn judge(case: &Case, tally: &mut Tally) -> Result<(), String> {
    if std::env::var_os("TENSORGLYPH_CAMPAIGN_VERBOSE").is_some() {
        eprintln!("{}", case.label);
    }
    // Only regular files are snapshotted: reading /dev/zero or a FIFO here would never end.
    let snapshot = || {
        std::fs::symlink_metadata(&case.path)
            .is_ok_and(|m| m.is_file())
            .then(|| std::fs::read(&case.path).ok())
            .flatten()
    };
    let before = snapshot();
    let base = peak_reset();
    let t0 = Instant::now();
    let res = match &case.read {
        Read::Tensors(opts) => read_field(&case.path, opts).map(|f| Got::Field(Box::new(f))),
        Read::Scalar => read_scalar_volume(&case.path).map(Got::Volume),
        Read::Mask => tensorglyph::select::Mask::read(&case.path).map(|_| Got::Mask),
        Read::Volumes => tensorglyph::field::read_mif_volumes_from(
            &tensorglyph::field::Inputs::file_system(),
            &case.path,
        )
        .map(Got::Volumes),
        Read::Sh(opts) => {
            // The decision reads the header; the tensor reader takes what is not SH.
            if tensorglyph::field::FieldKind::of_file(
                &tensorglyph::field::Inputs::file_system(),
                &case.path,
                opts,
            ) == tensorglyph::field::FieldKind::Series
            {
                tensorglyph::field::read_sh_field(&case.path, opts).map(|f| Got::Sh(Box::new(f)))
            } else {
                read_field(&case.path, opts).map(|f| Got::Field(Box::new(f)))
            }
        }
    };
    let elapsed = t0.elapsed();
    let peak = PEAK.load(Relaxed).saturating_sub(base);
    let label = &case.label;
    let budget = BUDGET_FIXED + BUDGET_PER_BYTE * case.input_bytes;
    tally.cases += 1;
    if peak > tally.worst_peak.0 {
        tally.worst_peak = (peak, label.clone());
    }
    if elapsed > tally.worst_time.0 {
        tally.worst_time = (elapsed, label.clone());
    }
    if elapsed > TIME_LIMIT {
        return Err(format!("{label}: took {elapsed:?}"));
    }
    if peak > budget {
        return Err(format!(
            "{label}: allocated {peak} bytes at peak, over the budget of {budget}"
        ));
    }
    if snapshot() != before {
        return Err(format!("{label}: the input file changed"));
    }
    match res {
        Ok(Got::Mask) => {
            tally.ok += 1;
            Ok(())
        }
        Ok(Got::Volumes(v)) => {
            tally.ok += 1;
            let n = v.dims.iter().try_fold(v.volumes, |a, &x| a.checked_mul(x));
            if n != Some(v.values.len())
                || v.voxel_to_world.iter().flatten().any(|x| !x.is_finite())
            {
                return Err(format!(
                    "{label}: inconsistent volumes: dims {:?} × {}, {} values, voxel to world {:?}",
                    v.dims,
                    v.volumes,
                    v.values.len(),
                    v.voxel_to_world
                ));
            }
            Ok(())
        }
        Ok(Got::Sh(f)) => {
            tally.ok += 1;
            let l = &f.layout;
            let n = f.dims.iter().try_fold(l.count, |a, &x| a.checked_mul(x));
            if n != Some(f.coefficients.len())
                || tensorglyph::sh::count_of_lmax(l.lmax) != Ok(l.count)
                || f.frame
                    .voxel_to_world
                    .iter()
                    .flatten()
                    .flatten()
                    .any(|x| !x.is_finite())
            {
                return Err(format!(
                    "{label}: inconsistent SH field: dims {:?}, lmax {}, count {}, {} values",
                    f.dims,
                    l.lmax,
                    l.count,
                    f.coefficients.len()
                ));
            }
            let v = f.voxels();
            let samples: Vec<usize> = if v == 0 { vec![] } else { vec![0, v - 1] };
            let report = tensorglyph::sh_info::report(&f, &samples)
                .map_err(|e| format!("{label}: SH info report failed: {e}"))?;
            serde_json::to_string(&report).map_err(|e| format!("{label}: JSON: {e}"))?;
            Ok(())
        }
        Ok(Got::Volume(v)) => {
            tally.ok += 1;
            let n = v.dims.iter().try_fold(1usize, |a, &x| a.checked_mul(x));
            if n != Some(v.values.len())
                || v.voxel_to_world.iter().flatten().any(|x| !x.is_finite())
            {
                return Err(format!(
                    "{label}: inconsistent volume: dims {:?}, {} values, voxel to world {:?}",
                    v.dims,
                    v.values.len(),
                    v.voxel_to_world
                ));
            }
            Ok(())
        }
        Ok(Got::Field(f)) => {
            tally.ok += 1;
            let n = f.tensors.len();
            let want = match f.array.location {
                tensorglyph::field::Location::Point => f.points,
                tensorglyph::field::Location::Cell => f.cells,
            };
            if f.positions.len() != n
                || want != n
                // 7: NRRD's masked tensors, the confidence first.
                || !matches!(f.array.components, 6 | 7 | 9)
                || f.dims.is_some_and(|d| {
                    d.iter().try_fold(1usize, |a, &x| a.checked_mul(x)) != Some(f.points)
                })
            {
                return Err(format!(
                    "{label}: inconsistent field: {} tensors, {} positions, {} points, {} cells, dims {:?}, {} components",
                    n,
                    f.positions.len(),
                    f.points,
                    f.cells,
                    f.dims,
                    f.array.components
                ));
            }
            let set = tensorglyph::glyph::derive_glyphs(&f, &tensorglyph::progress::Silent);
            // Eigenvalues beyond what a glyph holds are a skipped category, never a glyph.
            if let Some(g) = set
                .glyphs
                .iter()
                .find(|g| g.eigenvalues.iter().any(|v| !v.is_finite()))
            {
                return Err(format!(
                    "{label}: a glyph with eigenvalues {:?}",
                    g.eigenvalues
                ));
            }
            let samples: Vec<usize> = if n == 0 { vec![] } else { vec![0, n - 1] };
            let report = tensorglyph::info::info_report(&f, &set, &samples)
                .map_err(|e| format!("{label}: info report failed: {e}"))?;
            serde_json::to_string(&report).map_err(|e| format!("{label}: JSON: {e}"))?;
            Ok(())
        }
        Err(e) => {
            tally.errors += 1;
            let msg = e.to_string();
            let name = case.path.file_name().unwrap().to_string_lossy();
            let named = msg.contains(name.as_ref()) || case.names.iter().any(|n| msg.contains(n));
            // The reader's last defence turns a panic into this error: still a bug.
            if msg.contains("internal reader error") {
                return Err(format!("{label}: the reader panicked: {msg}"));
            }
            if msg.chars().any(char::is_control) {
                return Err(format!("{label}: error with control characters: {msg:?}"));
            }
            if !named {
                return Err(format!("{label}: error does not name the file: {msg}"));
            }
            if msg.len() > 4096 {
                return Err(format!("{label}: error of {} bytes", msg.len()));
            }
            Ok(())
        }
    }
}

fn data_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<PathBuf> = rd
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.is_file()
                && !p
                    .extension()
                    .is_some_and(|e| e == "py" || e == "json" || e == "md" || e == "sh")
        })
        .collect();
    v.sort();
    v
}

fn env_usize(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// `.pvti` Sources pointed where they must not lead.
fn pvti_cases(dir: &Path, fifo: Option<&Path>) -> Vec<(String, Vec<u8>)> {
    let text = std::fs::read_to_string(data::path("vtk/pvti_3pieces_binary.pvti")).unwrap();
    let first = "pvti_3pieces_binary_0.vti";
    let abs_piece = dir.join(first);
    let mut targets: Vec<String> = vec![
        "/dev/zero".into(),
        "/dev/urandom".into(),
        "/dev/null".into(),
        "/".into(),
        ".".into(),
        "../../../../../../../../etc/hostname".into(),
        "nonexistent.vti".into(),
        abs_piece.display().to_string(),
        "pvti_3pieces_binary_1.vti".into(),
        "case.pvti".into(),
        "\u{1b}[2J\n.vti".into(),
    ];
    if let Some(f) = fifo {
        targets.push(f.display().to_string());
        targets.push(f.file_name().unwrap().to_string_lossy().into_owned());
    }
    targets
        .into_iter()
        .map(|t| {
            let label = format!("pvti Source {t:?}");
            (label, text.replacen(first, &t, 1).into_bytes())
        })
        .collect()
}

/// What is read of `tests/data/dti`: files on their own, detached NRRD headers with their data
/// file, and FSL eigen sets (six files read as one).
enum DtiJob {
    Single(PathBuf),
    Detached { header: PathBuf, data: PathBuf },
    EigenSet { prefix: String, files: Vec<PathBuf> },
}

const EIGEN_MEMBERS: [&str; 6] = ["L1", "L2", "L3", "V1", "V2", "V3"];

fn dti_jobs(dir: &Path) -> Vec<DtiJob> {
    let files = data_files(dir);
    let mut jobs = Vec::new();
    let mut in_sets = Vec::new();
    for p in &files {
        let name = p.file_name().unwrap().to_string_lossy();
        for ext in [".nii.gz", ".nii"] {
            let Some(stem) = name.strip_suffix(&format!("_L1{ext}")) else {
                continue;
            };
            let set: Vec<PathBuf> = EIGEN_MEMBERS
                .iter()
                .map(|m| dir.join(format!("{stem}_{m}{ext}")))
                .collect();
            if set.iter().all(|f| f.is_file()) {
                in_sets.extend(set.iter().cloned());
                jobs.push(DtiJob::EigenSet {
                    prefix: stem.to_string(),
                    files: set,
                });
            }
        }
    }
    for p in files {
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if in_sets.contains(&p) || name.ends_with(".raw") || name.ends_with(".raw.gz") {
            continue;
        }
        let data = name
            .ends_with(".nhdr")
            .then(|| std::fs::read_to_string(&p).ok())
            .flatten()
            .and_then(|t| {
                t.lines()
                    .find_map(|l| l.strip_prefix("data file: ").map(|d| dir.join(d.trim())))
            })
            .filter(|d| d.is_file());
        jobs.push(match data {
            Some(data) => DtiJob::Detached { header: p, data },
            None => DtiJob::Single(p),
        });
    }
    jobs
}

/// Now and then another order or tensor frame, as `--order` and `--tensor-frame` give.
fn dti_options(k: usize) -> ReadOptions {
    ReadOptions {
        order: (k % 17 == 16).then_some(ComponentOrder::Mrtrix),
        tensor_frame: (k % 19 == 18).then_some([TensorFrame::Fsl, TensorFrame::World][k % 2]),
        ..ReadOptions::default()
    }
}

#[test]
fn mutation_campaign() {
    let seed = env_usize("TENSORGLYPH_CAMPAIGN_SEED", 13);
    let per_file = env_usize("TENSORGLYPH_CAMPAIGN_CASES", 400) as usize;
    let root = data::path("vtk");
    let mut files = data_files(&root);
    files.extend(data_files(&data::path("regressions")));
    assert!(files.len() > 90, "{} files", files.len());

    let shm = Path::new("/dev/shm");
    let tmp = tempfile::tempdir_in(shm).unwrap_or_else(|_| tempfile::tempdir().unwrap());
    let dir = tmp.path().to_path_buf();
    let pieces: Vec<PathBuf> = data_files(&root)
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with("pvti_") && n.ends_with(".vti")
        })
        .collect();
    for p in &pieces {
        std::fs::copy(p, dir.join(p.file_name().unwrap())).unwrap();
    }
    let fifo = dir.join("fifo.vti");
    let fifo = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
        .then_some(fifo);

    let dti_root = data::path("dti");
    let dti_jobs = dti_jobs(&dti_root);
    assert!(dti_jobs.len() > 30, "{} DTI jobs", dti_jobs.len());

    let (tx, rx) = mpsc::channel::<Result<String, String>>();
    let worker = std::thread::spawn(move || {
        let mut tally = Tally::default();
        let started = Instant::now();
        let size_of = |p: &Path| std::fs::metadata(p).map_or(0, |m| m.len() as usize);
        let pieces_bytes: usize = pieces.iter().map(|p| size_of(p)).sum();
        let run = |case: Case, tally: &mut Tally| -> bool {
            let msg = judge(&case, tally).map(|()| case.label.clone());
            if let Err(e) = &msg {
                let saved = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
                    "campaign-failure-{}",
                    case.path.file_name().unwrap().to_string_lossy()
                ));
                let _ = std::fs::copy(&case.path, &saved);
                eprintln!("{e}\n(saved as {})", saved.display());
            }
            tx.send(msg).is_ok()
        };

        for (fi, path) in files.iter().enumerate() {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let orig = std::fs::read(path).unwrap();
            let shape = shape_of(&orig);
            let mut rng = Rng(seed ^ (0xA076_1D64_78BD_642F_u64.wrapping_mul(fi as u64 + 1)));
            let target = dir.join(&name);
            let is_piece = name.starts_with("pvti_") && name.ends_with(".vti");
            for k in 0..=per_file {
                // Case 0: the file as it is.
                let (bytes, what) = if k == 0 {
                    (orig.clone(), "original".to_string())
                } else {
                    mutate(&orig, &shape, k % 12, &mut rng)
                };
                std::fs::write(&target, &bytes).unwrap();
                let opts = ReadOptions {
                    // Now and then by name, as `--array` does.
                    array: (k % 17 == 16).then(|| ["stress", "tensors", "x\u{1b}"][k % 3].into()),
                    ..ReadOptions::default()
                };
                let label = format!("seed {seed}: {name} #{k}: {what}");
                let mut cases = vec![Case {
                    label: label.clone(),
                    path: target.clone(),
                    input_bytes: bytes.len()
                        + if name.ends_with(".pvti") {
                            pieces_bytes
                        } else {
                            0
                        },
                    read: Read::Tensors(opts.clone()),
                    names: Vec::new(),
                }];
                if is_piece {
                    let stem = name.strip_suffix(".vti").unwrap();
                    let parent = stem.rsplit_once('_').unwrap().0;
                    let pvti = root.join(format!("{parent}.pvti"));
                    let copy = dir.join(format!("{parent}.pvti"));
                    if !copy.exists() {
                        std::fs::copy(&pvti, &copy).unwrap();
                    }
                    cases.push(Case {
                        label: format!("{label} (via {parent}.pvti)"),
                        path: copy,
                        input_bytes: size_of(&pvti) + pieces_bytes + bytes.len(),
                        read: Read::Tensors(opts),
                        names: Vec::new(),
                    });
                }
                for c in cases {
                    if !run(c, &mut tally) {
                        return;
                    }
                }
            }
            // Pieces are shared by later `.pvti` cases: restore them.
            std::fs::write(&target, &orig).unwrap();
        }

        // The DTI files, each mutated by its structure and read as the program reads it.
        let size_of_all = |ps: &[PathBuf]| ps.iter().map(|p| size_of(p)).sum::<usize>();
        for (ji, job) in dti_jobs.iter().enumerate() {
            let mut rng = Rng(seed ^ (0x5DEE_CE66_D1CE_4E5B_u64.wrapping_mul(ji as u64 + 1)));
            // (the file mutated, its copy, the paths it is read by)
            let mut plans: Vec<(PathBuf, PathBuf, Vec<PathBuf>)> = Vec::new();
            match job {
                DtiJob::Single(p) => {
                    let t = dir.join(p.file_name().unwrap());
                    plans.push((p.clone(), t.clone(), vec![t]));
                }
                DtiJob::Detached { header, data } => {
                    let h = dir.join(header.file_name().unwrap());
                    let d = dir.join(data.file_name().unwrap());
                    std::fs::copy(header, &h).unwrap();
                    std::fs::copy(data, &d).unwrap();
                    plans.push((header.clone(), h.clone(), vec![h.clone()]));
                    plans.push((data.clone(), d, vec![h]));
                }
                DtiJob::EigenSet { prefix, files } => {
                    for f in files {
                        std::fs::copy(f, dir.join(f.file_name().unwrap())).unwrap();
                    }
                    for f in files {
                        let t = dir.join(f.file_name().unwrap());
                        plans.push((f.clone(), t.clone(), vec![t, dir.join(prefix)]));
                    }
                }
            }
            let companions: Vec<PathBuf> = plans.iter().map(|p| p.1.clone()).collect();
            let set_names: Vec<String> = match job {
                DtiJob::EigenSet { .. } => companions
                    .iter()
                    .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
                    .collect(),
                _ => Vec::new(),
            };
            for (orig_path, target, read_by) in &plans {
                let name = orig_path
                    .file_name()
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                let orig = std::fs::read(orig_path).unwrap();
                let nifti = name.ends_with(".nii") || name.ends_with(".nii.gz");
                let header = name.ends_with(".nrrd") || name.ends_with(".nhdr");
                // The six files of a set share the file's budget of cases.
                let cases = if read_by.len() > 1 {
                    per_file / 3
                } else {
                    per_file
                };
                for k in 0..=cases {
                    let (bytes, what) = if k == 0 {
                        (orig.clone(), "original".to_string())
                    } else if nifti {
                        dti::nifti(&orig, k, &mut rng)
                    } else if header {
                        dti::nrrd(&orig, k, &mut rng)
                    } else {
                        mutate(&orig, &shape_of(&orig), [0, 2, 3][k % 3], &mut rng)
                    };
                    std::fs::write(target, &bytes).unwrap();
                    let path = read_by[k % 3 % read_by.len()].clone();
                    let case = Case {
                        label: format!(
                            "seed {seed}: {name} #{k}: {what} (read as {})",
                            path.file_name().unwrap().to_string_lossy()
                        ),
                        path,
                        input_bytes: size_of_all(&companions),
                        read: Read::Tensors(dti_options(k)),
                        names: set_names.clone(),
                    };
                    if !run(case, &mut tally) {
                        return;
                    }
                }
                std::fs::write(target, &orig).unwrap();
            }
        }
        // An eigen set with a member that is a FIFO, a device or a folder.
        if let Some(DtiJob::EigenSet { prefix, files }) = dti_jobs
            .iter()
            .find(|j| matches!(j, DtiJob::EigenSet { .. }))
        {
            let set = dir.join("special");
            let member = |m: usize| set.join(files[m].file_name().unwrap());
            let mut specials: Vec<(usize, Option<PathBuf>)> = vec![(4, None)];
            specials.extend(
                ["/dev/zero", "/dev/urandom"]
                    .iter()
                    .map(|d| (0, Some(PathBuf::from(d))))
                    .filter(|(_, d)| d.as_ref().is_some_and(|d| d.exists())),
            );
            specials.extend(fifo.clone().map(|f| (1, Some(f))));
            for (m, target) in specials {
                let _ = std::fs::remove_dir_all(&set);
                std::fs::create_dir(&set).unwrap();
                for f in files {
                    std::fs::copy(f, set.join(f.file_name().unwrap())).unwrap();
                }
                std::fs::remove_file(member(m)).unwrap();
                let what = match &target {
                    #[cfg(unix)]
                    Some(t) => {
                        std::os::unix::fs::symlink(t, member(m)).unwrap();
                        format!("a link to {}", t.display())
                    }
                    _ => {
                        std::fs::create_dir(member(m)).unwrap();
                        "a folder".to_string()
                    }
                };
                for path in [member(3 - m.min(3)), set.join(prefix)] {
                    let case = Case {
                        label: format!("{prefix}_{} is {what}", EIGEN_MEMBERS[m]),
                        path,
                        input_bytes: size_of_all(files),
                        read: Read::Tensors(ReadOptions::default()),
                        names: files
                            .iter()
                            .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
                            .collect(),
                    };
                    if !run(case, &mut tally) {
                        return;
                    }
                }
            }
        }

        // BEP016 maps and sidecars, scalar volumes, gzip streams and bombs.
        let mut go = true;
        pipeline::run_all(&dir, seed, per_file, fifo.as_deref(), &mut |c| {
            go = go && run(c, &mut tally);
            go
        });
        if !go {
            return;
        }
        // MRtrix images: headers, data, detached data, bombs.
        mif::run_all(
            &data::path("mif"),
            &dir,
            seed,
            per_file,
            fifo.as_deref(),
            &mut |c| {
                go = go && run(c, &mut tally);
                go
            },
        );
        if !go {
            return;
        }
        // SH coefficients (tests/data/sh): NIfTI and MRtrix images mutated as above, read as
        // `info` reads them, now and then with --sh-basis (which makes any count SH) or
        // --tensor-frame.
        for (fi, f) in data_files(&data::path("sh")).iter().enumerate() {
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            let mut rng = Rng(seed ^ (0x9E37_79B9_7F4A_7C15_u64.wrapping_mul(fi as u64 + 1)));
            let orig = std::fs::read(f).unwrap();
            let target = dir.join(&name);
            for k in 0..=per_file / 4 {
                let (bytes, what) = if k == 0 {
                    (orig.clone(), "original".to_string())
                } else if name.contains(".nii") {
                    dti::nifti(&orig, k, &mut rng)
                } else {
                    mif::mif(&orig, k, &mut rng)
                };
                std::fs::write(&target, &bytes).unwrap();
                let opts = ReadOptions {
                    sh_basis: (k % 7 == 6).then(|| tensorglyph::sh::ShBasis::VALUES[k % 3]),
                    tensor_frame: (k % 11 == 10).then_some(TensorFrame::Voxel),
                    ..ReadOptions::default()
                };
                let case = Case {
                    label: format!("seed {seed}: {name} #{k}: {what}"),
                    path: target.clone(),
                    input_bytes: bytes.len(),
                    read: Read::Sh(opts),
                    names: vec![name.clone()],
                };
                if !run(case, &mut tally) {
                    return;
                }
            }
            let _ = std::fs::remove_file(&target);
        }

        for (label, bytes) in pvti_cases(&dir, fifo.as_deref()) {
            let path = dir.join("case.pvti");
            std::fs::write(&path, &bytes).unwrap();
            let case = Case {
                label,
                path,
                input_bytes: bytes.len() + pieces_bytes,
                read: Read::Tensors(ReadOptions::default()),
                names: Vec::new(),
            };
            if !run(case, &mut tally) {
                return;
            }
        }
        // Special files as the input itself.
        let mut specials: Vec<PathBuf> = ["/dev/zero", "/dev/urandom", "/dev/null"]
            .iter()
            .map(PathBuf::from)
            .filter(|p| p.exists())
            .collect();
        specials.extend(fifo.clone());
        specials.push(dir.clone());
        for p in specials {
            let case = Case {
                label: format!("input {}", p.display()),
                path: p,
                input_bytes: 0,
                read: Read::Tensors(ReadOptions::default()),
                names: Vec::new(),
            };
            if !run(case, &mut tally) {
                return;
            }
        }
        let _ = tx.send(Ok(format!(
            "campaign: {} cases ({} read, {} refused) in {:.1} s; largest peak {} bytes ({}); slowest {:?} ({})",
            tally.cases,
            tally.ok,
            tally.errors,
            started.elapsed().as_secs_f64(),
            tally.worst_peak.0,
            tally.worst_peak.1,
            tally.worst_time.0,
            tally.worst_time.1
        )));
    });

    let mut last = String::from("(start)");
    let mut failures = Vec::new();
    loop {
        // Generous: a hang (a FIFO opened for reading) never returns at all.
        match rx.recv_timeout(Duration::from_secs(60)) {
            Ok(Ok(label)) => last = label,
            Ok(Err(problem)) => {
                failures.push(problem);
                if failures.len() >= 20 {
                    break;
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("a read hangs after: {last}"),
        }
    }
    if failures.is_empty() {
        worker.join().unwrap();
        eprintln!("{last}");
        let cases: usize = last
            .strip_prefix("campaign: ")
            .and_then(|s| s.split_whitespace().next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        assert!(cases >= 10_000, "only {cases} cases");
    } else {
        panic!("{} failures:\n{}", failures.len(), failures.join("\n"));
    }
}
