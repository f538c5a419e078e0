//! `report` and `render` as a pipeline's container runs them: no display, no runtime folder, no
//! Vulkan driver, a `HOME` nothing can be written under, a read-only input tree and an empty
//! temporary folder. Truth: the same run with lavapipe (the GPU path, checked against the exact
//! reference by tests/gpu) gives the same figures to the GPU tests' colour bound; stderr holds
//! only the lines tensorglyph itself prints; the inputs' bytes are unchanged.

use std::collections::BTreeMap;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::cli::stderr;

/// How every line tensorglyph writes to stderr begins (src/cli: `error:` for failures and usage,
/// `warning:` and `notice:` for what was assumed, `wrote` for an output written).
const OWN_PREFIXES: [&str; 4] = ["error: ", "warning: ", "notice: ", "wrote "];

/// What Mesa's device-select layer prints without `XDG_RUNTIME_DIR` (src/main.rs turns it off).
const MESA_LINE: &str = "XDG_RUNTIME_DIR is invalid";

/// The variables that would bring the device-select layer back or pick a display; the runs
/// below start without them, whatever the test's own environment holds.
const CLEARED: [&str; 7] = [
    "NODEVICE_SELECT",
    "MESA_VK_DEVICE_SELECT",
    "MESA_VK_DEVICE_SELECT_FORCE_DEFAULT_DEVICE",
    "XDG_RUNTIME_DIR",
    "DISPLAY",
    "WAYLAND_DISPLAY",
    "XDG_CACHE_HOME",
];

/// The process's effective uid, read from a file it creates (root ignores permission bits, so
/// read-only folders prove nothing there).
fn uid(dir: &Path) -> u32 {
    let probe = dir.join("uid-probe");
    std::fs::write(&probe, b"").unwrap();
    let uid = std::fs::metadata(&probe).unwrap().uid();
    std::fs::remove_file(&probe).unwrap();
    uid
}

/// A bare container's surroundings, in `root`: a copy of the BIDS folder made read-only, a
/// `HOME` nothing can be created under (a read-only folder; a plain file for root), an empty
/// `TMPDIR`.
struct Bare {
    input: PathBuf,
    home: PathBuf,
    tmp: PathBuf,
    root_user: bool,
}

impl Bare {
    fn new(root: &Path) -> Self {
        let input = root.join("derivatives");
        copy_tree(&crate::data::path("bids/derivatives"), &input);
        let root_user = uid(root) == 0;
        let home = root.join("home");
        if root_user {
            eprintln!("running as root: permissions do not bind; HOME is a plain file instead");
            std::fs::write(&home, b"").unwrap();
        } else {
            std::fs::create_dir(&home).unwrap();
        }
        let tmp = root.join("tmp");
        std::fs::create_dir(&tmp).unwrap();
        set_read_only(&input);
        set_read_only(&home);
        Self {
            input,
            home,
            tmp,
            root_user,
        }
    }

    /// `tensorglyph args` with no driver, display, runtime or cache folder, in these surroundings.
    fn run(&self, args: &[&str]) -> Output {
        let mut cmd = command(args);
        cmd.env("VK_ICD_FILENAMES", "/nonexistent.json")
            .env("HOME", &self.home)
            .env("TMPDIR", &self.tmp);
        cmd.output().expect("run tensorglyph")
    }
}

impl Drop for Bare {
    /// Writable again, so that the temporary folder can be removed.
    fn drop(&mut self) {
        for p in [&self.input, &self.home] {
            let _ = Command::new("chmod").args(["-R", "u+w"]).arg(p).status();
        }
    }
}

/// `tensorglyph args` with the test's environment less [`CLEARED`].
fn command(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tensorglyph"));
    cmd.args(args);
    for v in CLEARED {
        cmd.env_remove(v);
    }
    cmd
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let dest = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &dest);
        } else {
            std::fs::copy(e.path(), &dest).unwrap();
        }
    }
}

fn set_read_only(path: &Path) {
    if path.is_dir() {
        for e in std::fs::read_dir(path).unwrap() {
            set_read_only(&e.unwrap().path());
        }
    }
    let mode = if path.is_dir() { 0o555 } else { 0o444 };
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// Every file under `dir` with its bytes, by path relative to `dir`.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(base, &p, out);
            } else {
                let rel = p.strip_prefix(base).unwrap().to_path_buf();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Every line of `o`'s stderr is one of tensorglyph's own.
fn assert_own_lines(what: &str, o: &Output) {
    let err = stderr(o);
    for line in err.lines() {
        assert!(
            OWN_PREFIXES.iter().any(|p| line.starts_with(p)),
            "{what}: a line that is not tensorglyph's: {line:?}\n{err}"
        );
    }
    assert!(!err.contains(MESA_LINE), "{what}: {err}");
}

/// Whether the normal run used the GPU (`used`): `false` (skip the comparison) when this
/// machine has no adapter and CI is unset; under CI a missing adapter fails.
fn gpu_present(used: bool) -> bool {
    if used {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "CI is set but the normal run found no GPU adapter"
    );
    eprintln!("skipping the GPU comparison: no adapter");
    false
}

/// The same figure from the GPU (lavapipe) and from the exact reference: the GPU tests' colour
/// bound (tests/gpu/check.rs, PSNR ≥ 40 dB), and at least 99.9 % of pixels within 3/255 on every
/// channel (rim pixels whose centres lie within f32 rounding of a silhouette may flip).
fn assert_same_figure(what: &str, gpu_png: &[u8], reference_png: &[u8]) {
    let a = image::load_from_memory(gpu_png).unwrap().to_rgba8();
    let b = image::load_from_memory(reference_png).unwrap().to_rgba8();
    assert_eq!(a.dimensions(), b.dimensions(), "{what}");
    let psnr = tensorglyph::metrics::psnr(a.as_raw(), b.as_raw());
    let close = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).all(|(x, y)| x.abs_diff(y) <= 3))
        .count();
    let share = close as f64 / f64::from(a.width() * a.height());
    eprintln!(
        "{what}: PSNR {psnr:.1} dB, {:.4} % within 3/255",
        100.0 * share
    );
    assert!(psnr >= 40.0, "{what}: PSNR {psnr} dB");
    assert!(share >= 0.999, "{what}: {share} of pixels within 3/255");
}

#[test]
fn a_bare_container_gives_the_gpus_figures_from_the_reference_with_a_clean_stderr() {
    let root = tempfile::tempdir().unwrap();
    let bare = Bare::new(root.path());
    let before = files(&bare.input);
    let input = bare.input.to_str().unwrap();
    let (normal, contained) = (root.path().join("normal"), root.path().join("contained"));
    let report = |out: &Path| {
        [
            "report",
            input,
            out.to_str().unwrap(),
            "participant",
            "--participant-label",
            "01",
            "02",
        ]
        .map(str::to_string)
    };
    // (a) a normal machine, but without XDG_RUNTIME_DIR: Mesa's lines must not come.
    let args = report(&normal);
    let a = command(&args.each_ref().map(String::as_str))
        .output()
        .unwrap();
    assert_eq!(a.status.code(), Some(0), "{}", stderr(&a));
    assert_own_lines("report, normal", &a);
    // (b) the bare container.
    let args = report(&contained);
    let b = bare.run(&args.each_ref().map(String::as_str));
    assert_eq!(b.status.code(), Some(0), "{}", stderr(&b));
    assert_own_lines("report, bare", &b);
    assert_eq!(
        stderr(&b).trim_end(),
        "notice: no GPU adapter found; rendering with the CPU reference instead"
    );

    let (fa, fb) = (files(&normal), files(&contained));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "the same files"
    );
    assert!(fa.keys().any(|k| k.ends_with("sub-02.html")));
    for label in ["01", "02"] {
        let page = |files: &BTreeMap<PathBuf, Vec<u8>>| {
            String::from_utf8(files[Path::new(&format!("sub-{label}.html"))].clone()).unwrap()
        };
        assert!(
            page(&fb).contains("rendered with the exact CPU reference"),
            "sub-{label}: the page names the reference"
        );
        if !gpu_present(!page(&fa).contains("rendered with the exact CPU reference")) {
            continue;
        }
        for (name, png) in fa.iter().filter(|(k, _)| {
            k.starts_with(format!("sub-{label}")) && k.extension().is_some_and(|e| e == "png")
        }) {
            assert_same_figure(&name.display().to_string(), png, &fb[name]);
        }
    }

    // A render of the read-only input, the same way.
    let map = bare
        .input
        .join("sub-01/dwi/sub-01_model-DTI_param-tensor_dwimap.nii.gz");
    let render = |png: &Path| {
        [
            "render",
            map.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            "320x240",
            "--underlay",
            "fa",
            "--slice",
            "z=5",
        ]
        .map(str::to_string)
    };
    let (pa, pb) = (root.path().join("a.png"), root.path().join("b.png"));
    let args = render(&pa);
    let a = command(&args.each_ref().map(String::as_str))
        .output()
        .unwrap();
    assert!(a.status.success(), "{}", stderr(&a));
    assert_own_lines("render, normal", &a);
    let args = render(&pb);
    let b = bare.run(&args.each_ref().map(String::as_str));
    assert!(b.status.success(), "{}", stderr(&b));
    assert_own_lines("render, bare", &b);
    assert!(stderr(&b).contains("CPU reference"), "{}", stderr(&b));
    if gpu_present(!stderr(&a).contains("CPU reference")) {
        assert_same_figure(
            "render",
            &std::fs::read(&pa).unwrap(),
            &std::fs::read(&pb).unwrap(),
        );
    }

    // Nothing changed or added in the input, nothing left in TMPDIR or under HOME.
    assert_eq!(files(&bare.input), before, "the input tree is unchanged");
    assert_eq!(std::fs::read_dir(&bare.tmp).unwrap().count(), 0, "TMPDIR");
    if bare.root_user {
        assert_eq!(std::fs::read(&bare.home).unwrap(), b"", "HOME");
    } else {
        assert_eq!(std::fs::read_dir(&bare.home).unwrap().count(), 0, "HOME");
    }
}

/// `render --json` of grid:2 with `args` and the environment `env`: the report and the image.
fn render_json(out: &Path, args: &[&str], env: &[(&str, &Path)]) -> (serde_json::Value, Vec<u8>) {
    let png = out.join("grid.png");
    let mut all = vec!["render", "--demo", "grid:2", "-o", png.to_str().unwrap()];
    all.extend(["--size", "320x240", "--json", "-q"]);
    all.extend(args);
    let mut cmd = command(&all);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "nothing on stderr: {}", stderr(&o));
    (crate::cli::json(&o), std::fs::read(&png).unwrap())
}

/// The pipeline cache on disk: written on the first run, loaded on the next, refused (and the
/// frame the same) when a byte of it changed, off by `TENSORGLYPH_PIPELINE_CACHE=0` and,
/// silently, where no folder can be made.
#[test]
fn the_pipeline_cache_is_stored_loaded_checked_and_off_where_it_cannot_be() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let env = [("TENSORGLYPH_PIPELINE_CACHE", cache.as_path())];
    let (first, image) = render_json(dir.path(), &[], &env);
    let Some(state) = first["pipeline_cache"].as_str() else {
        assert!(std::env::var_os("CI").is_none(), "CI is set but no GPU");
        eprintln!("skipping: no GPU adapter");
        return;
    };
    if state.contains("PIPELINE_CACHE") {
        // An adapter without the feature: off, and the report says so.
        assert!(
            state.starts_with("off: the adapter has no PIPELINE_CACHE"),
            "{state}"
        );
        return;
    }
    assert!(state.starts_with("empty, kept in "), "{state}");
    let files: Vec<PathBuf> = std::fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len(), 1, "one file, no temporary left: {files:?}");
    let file = &files[0];
    let stored = std::fs::read(file).unwrap();
    assert!(stored.starts_with(b"TGPIPE1\n"));

    let (second, again) = render_json(dir.path(), &[], &env);
    let loaded = second["pipeline_cache"].as_str().unwrap();
    assert!(loaded.starts_with("loaded "), "{loaded}");
    assert_eq!(again, image, "the cache changes no pixel");

    let mut corrupt = stored.clone();
    *corrupt.last_mut().unwrap() ^= 0x40;
    std::fs::write(file, &corrupt).unwrap();
    let (third, refused) = render_json(dir.path(), &[], &env);
    let state = third["pipeline_cache"].as_str().unwrap();
    assert!(state.starts_with("empty, kept in "), "{state}");
    assert_eq!(refused, image);

    let off = [("TENSORGLYPH_PIPELINE_CACHE", Path::new("0"))];
    let (j, _) = render_json(dir.path(), &[], &off);
    assert_eq!(j["pipeline_cache"], "off: TENSORGLYPH_PIPELINE_CACHE=0");

    // A HOME and a cache folder nothing can be made under (a plain file stands for both, as
    // root ignores permissions): the cache is off, stderr stays empty, the image the same.
    let plain = dir.path().join("plain");
    std::fs::write(&plain, b"").unwrap();
    let nowhere = plain.join("cache");
    for env in [
        vec![("HOME", plain.as_path())],
        vec![
            ("HOME", plain.as_path()),
            ("TENSORGLYPH_PIPELINE_CACHE", nowhere.as_path()),
        ],
    ] {
        let (j, img) = render_json(dir.path(), &[], &env);
        let state = j["pipeline_cache"].as_str().unwrap();
        assert!(state.starts_with("off: no cache folder at "), "{state}");
        assert_eq!(img, image);
    }
}

/// A run builds the pipelines its frames draw with and no others: the baseline one strip
/// pipeline, a mesh method one of its four variants, the underlay its own on top.
#[test]
fn only_the_pipelines_a_frame_uses_are_built() {
    let dir = tempfile::tempdir().unwrap();
    let off = [("TENSORGLYPH_PIPELINE_CACHE", Path::new("0"))];
    let built = |args: &[&str]| {
        let (j, _) = render_json(dir.path(), args, &off);
        j["pipelines_built"].as_u64()
    };
    let Some(baseline) = built(&["--preset", "baseline"]) else {
        assert!(std::env::var_os("CI").is_none(), "CI is set but no GPU");
        return;
    };
    assert_eq!(baseline, 1);
    assert_eq!(built(&["--method", "mesh:1"]), Some(1));
    assert_eq!(built(&["--method", "box"]), Some(1));
    assert_eq!(
        built(&["--preset", "baseline", "--underlay", "fa"]),
        Some(2)
    );
}
