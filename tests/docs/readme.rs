//! Everything the README and the book show works: run every `tensorglyph` command line of
//! README.md and then of every page of the book (docs/book/src, in the order SUMMARY.md lists
//! them), with the binary this build made, and check that each exits 0 and writes the files it
//! names.
//!
//! # Which lines
//!
//! The same rules for README.md and every book page:
//!
//! - **Fenced blocks**: every line inside a ```` ```sh ```` block that starts with `tensorglyph `.
//!   Each is split into words as a POSIX shell would (the `shlex` crate: quotes and backslashes,
//!   and a word starting with `#` begins a comment, so trailing `# …` comments go).
//! - **Inline code spans** (single backticks, outside fenced blocks; a span may continue on the
//!   next line of its paragraph, the line break counting as a space) that are a complete command:
//!   the first word is `tensorglyph` (or `xvfb-run`, followed later by a `tensorglyph` word:
//!   `xvfb-run` and its own options are dropped, the test's Xvfb stands in for it), followed by
//!   a subcommand and at least one argument (a bare `tensorglyph bench` names a command, it is
//!   not one), and no word is a placeholder. A placeholder is a word containing one of
//!   `[ ] < > | …` or `...`, or a metavariable: a word, the part of it after `=` or the part
//!   before its first `.`, made of ASCII letters only with at least one upper-case letter
//!   (`FILE`, `N`, `WxH`, `DEG`, `--size=WxH`, `OUT.png`).
//!
//! At least [`MIN_COMMANDS`] lines must be found, so the test cannot pass by matching nothing. A
//! line that repeats one already run (the same words: the README's examples reappear in the
//! book) is reported and not run again.
//!
//! # How they run
//!
//! In a temporary directory whose `tests` entry is a symlink to the repository's `tests/` (the
//! commands read `tests/data/…`, and `grid40.vtk`, which the README's first `demo` line writes
//! there; the book's *Getting started* page writes it again). Each command has [`TIME_LIMIT`] to exit with status 0 (it is killed
//! otherwise). Every file or folder it names as an output (`-o`/`--output`, `--out`,
//! `--screenshot`, `--diff`, `--write-vtk`, and `grid40.png` for `demo` without `-o` or
//! `--write-vtk`, as the book says) is removed before the command runs and must exist after
//! it: a PNG must start with the PNG signature, a folder must not be empty. A `--json` run must
//! print JSON objects on stdout (exactly one for `info`, `render` and `demo`; one per line for
//! `stability`). All commands run and every failure is listed at the end.
//!
//! `view` lines run under an Xvfb the test starts (as `tests/cli/viewer.rs` does: `DISPLAY`
//! set, `WAYLAND_DISPLAY` removed, `WGPU_BACKEND=vulkan`). A `view` line without
//! `--screenshot` would open a window and wait for a user, so it gets `--frames 2 --screenshot
//! view-K.png` appended (K counts the commands from 1); lines already in scripted mode run as
//! printed. When no X server can be started the `view` lines are skipped with a message, unless
//! `CI` is set: then the test fails.
//!
//! # What is not run verbatim
//!
//! Apart from the scripted mode added to `view` lines, the lines in [`SUBSTITUTIONS`] run with a
//! smaller workload than the page prints, because this test runs the debug build inside
//! `cargo test` and CI's whole run must stay well within its time limit. Each entry says why.
//! The options kept are the page's, so the command line is still checked by clap and the
//! same code paths run; only the volume size, the image size, the frame count and the frame
//! budget shrink. A substitution that matches no line fails the test, so the table cannot go
//! stale. Every other line runs
//! exactly as printed.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// At least this many command lines must be found. README.md and the book show 98 as of this
/// test (14 in the README, 84 in the book's pages; 86 distinct); a few fewer are allowed, so that
/// a page may lose a line without editing this.
const MIN_COMMANDS: usize = 93;

/// How long one command may run before it is killed and counted as a failure.
const TIME_LIMIT: Duration = Duration::from_secs(180);

/// When a substitution applies to a command line.
enum When {
    /// The option is given with this value.
    Value(&'static str, &'static str),
    /// The option is not given.
    Lacks(&'static str),
}

/// A heavy command line run with a smaller workload.
struct Substitution {
    /// The subcommand it applies to.
    subcommand: &'static str,
    when: When,
    /// Options set: the value replaces the one given (clap refuses a repeated option), or the
    /// option is added; `None` adds a flag.
    set: &'static [(&'static str, Option<&'static str>)],
    reason: &'static str,
}

/// Every heavy line and what runs instead. The times are of the debug build on a 2-core
/// machine with lavapipe, measured when this table was written.
const SUBSTITUTIONS: &[Substitution] = &[
    Substitution {
        subcommand: "render",
        when: When::Value("--demo", "grid:256"),
        set: &[("--demo", Some("grid:16"))],
        reason: "grid:256 (16.8 M tensors) took 13 s and peaked at 2.4 GiB resident memory; \
                 grid:16 runs the same staged pipeline",
    },
    Substitution {
        subcommand: "bench",
        when: When::Value("--large", "256"),
        set: &[("--large", Some("8"))],
        reason: "the same 16.8 M-tensor volume through bench --large: 12 s and 2.6 GiB for each \
                 of the three lines; --large 8 runs the same stages and writes the same table",
    },
    Substitution {
        subcommand: "bench",
        when: When::Lacks("--size"),
        set: &[
            ("--size", Some("64x48")),
            ("--frames", Some("1")),
            ("--budget", Some("0.25")),
        ],
        reason: "the whole bench (every method, glyph and path in three views, 5 frames each and \
                 a reference image, at 1024x768) was killed unfinished after 300 s; at 64x48 \
                 with one frame it still took 52 s with the 20 s budget (mesh levels of the whole \
                 field take ~1 s a frame even at that size) and 21 s with a 0.25 s budget, which \
                 skips the finer mesh levels in the whole-field views",
    },
    Substitution {
        subcommand: "bench",
        when: When::Value("--size", "640x480"),
        set: &[("--size", Some("64x48")), ("--frames", Some("1"))],
        reason: "as printed it took 100 s (mesh:2, 20 M triangles for grid40, five frames in \
                 three views); 23 s at 64x48 with one frame. No budget added: mesh:2 is what the \
                 line is about",
    },
    Substitution {
        subcommand: "bench",
        when: When::Lacks("--scene"),
        set: &[("--scene", Some("grid:16"))],
        reason: "the default scene, grid40 (64,000 glyphs): the six bench lines without --scene \
                 took 16, 38, 59, 16.5, 15 and 39 s (184 s of this test's 469 s) even at 64x48 \
                 with the frame and budget cuts above, and take 3.8, 15.8, 8.9, 8.1, 3.3 and 21 s \
                 on grid:16 (4,096 glyphs), which runs the same methods, glyphs, views, tables \
                 and brain report (the test: 329 s)",
    },
    Substitution {
        subcommand: "stability",
        when: When::Lacks("--glyph"),
        set: &[("--quick", None), ("--case", Some("1-distance"))],
        reason: "the whole suite was killed unfinished after 180 s once case 2 grew to ten \
                 anisotropy sweeps, and --quick took 155-164 s (each of the two lines); the \
                 quick suite runs in full, every method and glyph, in the GPU tests \
                 (tests/gpu/stability.rs), so here one case (8 s) runs the same command and \
                 writes the same report files and JSON lines",
    },
];

/// One command line of the README or a book page.
#[derive(Debug)]
struct ReadmeCommand {
    /// The page, relative to the repository (README.md, docs/book/src/…).
    file: String,
    /// 1-based line of the page where it starts.
    line: usize,
    /// The words after `tensorglyph`, as printed.
    args: Vec<String>,
}

/// A word that stands for a value the reader fills in (`FILE`, `N`, `WxH`, `[OPTIONS]`, `…`).
fn is_placeholder(word: &str) -> bool {
    let meta = |w: &str| {
        !w.is_empty()
            && w.chars().all(|c| c.is_ascii_alphabetic())
            && w.chars().any(|c| c.is_ascii_uppercase())
    };
    word.contains(['[', ']', '<', '>', '|', '…'])
        || word.contains("...")
        || meta(word)
        || word.split_once('=').is_some_and(|(_, v)| meta(v))
        || word.split_once('.').is_some_and(|(stem, _)| meta(stem))
}

fn split(text: &str, file: &str, line: usize) -> Vec<String> {
    shlex::split(text).unwrap_or_else(|| panic!("{file}:{line}: cannot split {text:?}"))
}

/// The command lines of `readme`, the text of `file`, in order (the rules are in the module
/// documentation).
fn extract(file: &str, readme: &str) -> Vec<ReadmeCommand> {
    let mut out = Vec::new();
    // None: outside a fence; Some(is_sh): inside one.
    let mut fence: Option<bool> = None;
    // The current paragraph outside fences: (first line number, text).
    let mut para: Option<(usize, String)> = None;
    for (i, text) in readme.lines().enumerate() {
        let line = i + 1;
        let trimmed = text.trim_start();
        if trimmed.starts_with("```") {
            if let Some((l, p)) = para.take() {
                inline_commands(file, &p, l, &mut out);
            }
            fence = match fence {
                Some(_) => None,
                None => Some(trimmed.trim_start_matches('`').trim() == "sh"),
            };
            continue;
        }
        match fence {
            Some(true) => {
                if text.starts_with("tensorglyph ") {
                    let mut words = split(text, file, line);
                    words.remove(0);
                    out.push(ReadmeCommand {
                        file: file.to_string(),
                        line,
                        args: words,
                    });
                }
            }
            Some(false) => {}
            None if text.trim().is_empty() => {
                if let Some((l, p)) = para.take() {
                    inline_commands(file, &p, l, &mut out);
                }
            }
            None => match &mut para {
                Some((_, p)) => {
                    p.push('\n');
                    p.push_str(text);
                }
                None => para = Some((line, text.to_string())),
            },
        }
    }
    if let Some((l, p)) = para.take() {
        inline_commands(file, &p, l, &mut out);
    }
    out
}

/// The book's pages in the order SUMMARY.md lists them, relative to the repository.
fn book_pages(repo: &Path) -> Vec<String> {
    let src = "docs/book/src";
    let summary = fs::read_to_string(repo.join(src).join("SUMMARY.md")).expect("SUMMARY.md");
    let mut pages = Vec::new();
    let mut rest = summary.as_str();
    while let Some(k) = rest.find("](") {
        rest = &rest[k + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].trim_start_matches("./");
        if target.ends_with(".md") {
            pages.push(format!("{src}/{target}"));
        }
        rest = &rest[end..];
    }
    assert!(!pages.is_empty(), "SUMMARY.md lists no page");
    pages
}

/// The complete commands among the inline code spans of one paragraph starting at `first_line`.
fn inline_commands(file: &str, para: &str, first_line: usize, out: &mut Vec<ReadmeCommand>) {
    let mut rest = para;
    let mut offset = 0;
    while let Some(open) = rest.find('`') {
        let after = &rest[open + 1..];
        let Some(close) = after.find('`') else { break };
        let span = after[..close].replace('\n', " ");
        let line = first_line + para[..offset + open].matches('\n').count();
        offset += open + close + 2;
        rest = &after[close + 1..];

        // Split only candidates: other spans may hold a lone quote.
        if !span.starts_with("tensorglyph ") && !span.starts_with("xvfb-run ") {
            continue;
        }
        let words = split(&span, file, line);
        let start = match words.first().map(String::as_str) {
            Some("tensorglyph") => 1,
            Some("xvfb-run") => match words.iter().position(|w| w == "tensorglyph") {
                Some(p) => p + 1,
                None => continue,
            },
            _ => continue,
        };
        let args = &words[start..];
        if args.len() >= 2 && !args.iter().any(|w| is_placeholder(w)) {
            out.push(ReadmeCommand {
                file: file.to_string(),
                line,
                args: args.to_vec(),
            });
        }
    }
}

/// The value of `option` (`--opt V` or `--opt=V`); the last one if repeated.
fn value_of<'a>(args: &'a [String], option: &str) -> Option<&'a str> {
    let mut found = None;
    for (i, a) in args.iter().enumerate() {
        if a == option {
            found = args.get(i + 1).map(String::as_str);
        } else if let Some(v) = a.strip_prefix(option).and_then(|r| r.strip_prefix('=')) {
            found = Some(v);
        }
    }
    found
}

fn has_option(args: &[String], option: &str) -> bool {
    args.iter()
        .any(|a| a == option || a.starts_with(&format!("{option}=")))
}

/// Set `option` to `value` (replacing a value given) or add the flag.
fn set_option(args: &mut Vec<String>, option: &str, value: Option<&str>) {
    match value {
        None => {
            if !has_option(args, option) {
                args.push(option.to_string());
            }
        }
        Some(v) => {
            if let Some(i) = args.iter().position(|a| a == option) {
                args[i + 1] = v.to_string();
            } else if let Some(i) = args
                .iter()
                .position(|a| a.starts_with(&format!("{option}=")))
            {
                args[i] = format!("{option}={v}");
            } else {
                args.push(option.to_string());
                args.push(v.to_string());
            }
        }
    }
}

/// Apply every matching substitution; returns the reasons of those that applied (by index).
fn substitute(args: &mut Vec<String>, used: &mut [bool]) -> Vec<&'static str> {
    let mut reasons = Vec::new();
    for (k, s) in SUBSTITUTIONS.iter().enumerate() {
        if args.first().map(String::as_str) != Some(s.subcommand) {
            continue;
        }
        let applies = match s.when {
            When::Value(o, v) => value_of(args, o) == Some(v),
            When::Lacks(o) => !has_option(args, o),
        };
        if applies {
            for (o, v) in s.set {
                set_option(args, o, *v);
            }
            used[k] = true;
            reasons.push(s.reason);
        }
    }
    reasons
}

/// The files and folders a command names as its outputs.
fn outputs(args: &[String]) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = [
        "-o",
        "--output",
        "--out",
        "--screenshot",
        "--diff",
        "--write-vtk",
    ]
    .iter()
    .filter_map(|o| value_of(args, o))
    .map(PathBuf::from)
    .collect();
    if args[0] == "demo" && out.is_empty() {
        out.push(PathBuf::from("grid40.png"));
    }
    out
}

/// What is wrong with an output after the command ran, if anything.
fn check_output(path: &Path) -> Option<String> {
    let shown = path.display();
    let Ok(meta) = fs::metadata(path) else {
        return Some(format!("{shown} was not written"));
    };
    if meta.is_dir() {
        let empty = fs::read_dir(path).map_or(true, |mut d| d.next().is_none());
        return empty.then(|| format!("folder {shown} is empty"));
    }
    if path.extension().is_some_and(|e| e == "png") {
        let bytes = fs::read(path).unwrap_or_default();
        if !bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            return Some(format!("{shown} is not a PNG ({} bytes)", bytes.len()));
        }
    } else if meta.len() == 0 {
        return Some(format!("{shown} is empty"));
    }
    None
}

/// What is wrong with the stdout of a `--json` run, if anything: `info`, `render` and `demo`
/// print exactly one JSON object, `stability` one per line (JSON lines).
fn check_json(subcommand: &str, stdout: &Path) -> Option<String> {
    let text = fs::read_to_string(stdout).unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    if lines.is_empty() {
        return Some("--json printed nothing on stdout".into());
    }
    if subcommand != "stability" && lines.len() != 1 {
        return Some(format!(
            "--json printed {} lines on stdout, not one JSON object",
            lines.len()
        ));
    }
    lines.iter().enumerate().find_map(
        |(i, l)| match serde_json::from_str::<serde_json::Value>(l) {
            Ok(v) if v.is_object() => None,
            _ => Some(format!(
                "stdout line {} is not a JSON object: {l:.200}",
                i + 1
            )),
        },
    )
}

/// The X server for the `view` lines: started at the first one, kept for the others.
enum Display {
    NotTried,
    Running {
        _server: crate::xvfb::Xvfb,
        display: String,
    },
    Unavailable,
}

impl Display {
    fn get(&mut self) -> Option<&str> {
        if let Display::NotTried = self {
            *self = match crate::xvfb::start_xvfb(150) {
                Some((server, display)) => Display::Running {
                    _server: server,
                    display,
                },
                None => {
                    if std::env::var_os("CI").is_some() {
                        panic!(
                            "CI is set but Xvfb could not be started for the view lines \
                             (is the xvfb package installed?)"
                        );
                    }
                    eprintln!(
                        "no X server could be started (install xvfb): the view lines \
                         are skipped"
                    );
                    Display::Unavailable
                }
            };
        }
        match self {
            Display::Running { display, .. } => Some(display),
            _ => None,
        }
    }
}

/// A command line for the log: `tensorglyph` and the words, quoted only where a shell needs it.
fn show(args: &[String]) -> String {
    let mut line = String::from("tensorglyph");
    for a in args {
        let plain = !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_=+.,:/@%".contains(c) || !c.is_ascii());
        line.push(' ');
        if plain {
            line.push_str(a);
        } else {
            line.push_str(&shlex::try_quote(a).expect("no NUL in a command line"));
        }
    }
    line
}

/// The last `n` lines of a captured output file.
fn tail(path: &Path, n: usize) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

#[test]
fn every_readme_and_book_command_line_works() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut pages = vec!["README.md".to_string()];
    pages.extend(book_pages(repo));
    let mut commands = Vec::new();
    for page in &pages {
        let text = fs::read_to_string(repo.join(page)).unwrap_or_else(|e| panic!("{page}: {e}"));
        commands.extend(extract(page, &text));
    }
    assert!(
        commands.len() >= MIN_COMMANDS,
        "only {} command lines found in README.md and the book (expected at least \
         {MIN_COMMANDS}): {commands:#?}",
        commands.len()
    );

    let dir = tempfile::tempdir().unwrap();
    let work = dir.path();
    std::os::unix::fs::symlink(repo.join("tests"), work.join("tests")).unwrap();
    let logs = work.join(".logs");
    fs::create_dir(&logs).unwrap();

    let mut display = Display::NotTried;
    let mut used = vec![false; SUBSTITUTIONS.len()];
    let mut failures = Vec::new();
    let mut skipped = 0;
    let mut repeated = 0;
    // Each distinct command line and where it was first shown.
    let mut seen: Vec<(&[String], String)> = Vec::new();
    let total = commands.len();
    let started = Instant::now();
    eprintln!(
        "{total} command lines from README.md and {} book pages, run in {}",
        pages.len() - 1,
        work.display()
    );

    for (k, cmd) in commands.iter().enumerate() {
        let k = k + 1;
        let at = format!("{}:{}", cmd.file, cmd.line);
        let printed = show(&cmd.args);
        let mut args = cmd.args.clone();
        let reasons = substitute(&mut args, &mut used);
        if let Some((_, first)) = seen.iter().find(|(a, _)| *a == cmd.args.as_slice()) {
            eprintln!("[{k}/{total}] {at}: {printed}\n    the same line as {first}: not run again");
            repeated += 1;
            continue;
        }
        seen.push((&cmd.args, at.clone()));
        let view = args[0] == "view";
        if view && !has_option(&args, "--screenshot") {
            set_option(&mut args, "--frames", Some("2"));
            set_option(&mut args, "--screenshot", Some(&format!("view-{k}.png")));
        }
        let run = show(&args);
        eprintln!("[{k}/{total}] {at}: {printed}");
        if run != printed {
            eprintln!("    runs as: {run}");
            for r in &reasons {
                eprintln!("    (substituted: {r})");
            }
        }

        let mut command = Command::new(env!("CARGO_BIN_EXE_tensorglyph"));
        command
            .args(&args)
            .current_dir(work)
            .env("XDG_RUNTIME_DIR", work)
            .stdin(Stdio::null());
        if view {
            let Some(d) = display.get() else {
                eprintln!("    skipped: no X server");
                skipped += 1;
                continue;
            };
            command
                .env("DISPLAY", d)
                .env_remove("WAYLAND_DISPLAY")
                .env("WGPU_BACKEND", "vulkan");
        }

        let outs = outputs(&args);
        for o in &outs {
            let p = work.join(o);
            if p.is_dir() {
                fs::remove_dir_all(&p).unwrap();
            } else if p.exists() {
                fs::remove_file(&p).unwrap();
            }
        }
        let stdout = logs.join(format!("{k}.stdout"));
        let stderr = logs.join(format!("{k}.stderr"));
        command
            .stdout(fs::File::create(&stdout).unwrap())
            .stderr(fs::File::create(&stderr).unwrap());

        let t0 = Instant::now();
        let mut child = command.spawn().expect("run tensorglyph");
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break Some(s);
            }
            if t0.elapsed() > TIME_LIMIT {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let secs = t0.elapsed().as_secs_f64();
        let mut problems = Vec::new();
        match status {
            None => problems.push(format!("killed after {} s", TIME_LIMIT.as_secs())),
            Some(s) if !s.success() => problems.push(format!("exited with {s}")),
            Some(_) => {
                problems.extend(outs.iter().filter_map(|o| check_output(&work.join(o))));
                if has_option(&args, "--json") {
                    problems.extend(check_json(&args[0], &stdout));
                }
            }
        }
        if problems.is_empty() {
            eprintln!("    ok in {secs:.1} s");
        } else {
            let report = format!(
                "{at}: {printed}\n    ran: {run}\n    {}\n    stderr (last lines):\n{}",
                problems.join("; "),
                tail(&stderr, 15)
            );
            eprintln!("    FAILED in {secs:.1} s: {}", problems.join("; "));
            failures.push(report);
        }
    }

    let stale: Vec<String> = SUBSTITUTIONS
        .iter()
        .zip(&used)
        .filter(|(_, u)| !**u)
        .map(|(s, _)| format!("{} ({})", s.subcommand, s.reason))
        .collect();
    eprintln!(
        "{} command lines ({} distinct) in {:.0} s: {} failed, {skipped} skipped",
        total,
        total - repeated,
        started.elapsed().as_secs_f64(),
        failures.len()
    );
    assert!(
        stale.is_empty(),
        "substitutions that match no line of the README or the book (remove them): {stale:#?}"
    );
    assert!(
        failures.is_empty(),
        "{} command lines of the README and the book failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn extraction_rules() {
    let md = "Run `tensorglyph render` or `tensorglyph render --demo grid40 -o a.png`.\n\
              A span over two lines: `tensorglyph info\n\
              grid40.vtk --json`; placeholders: `tensorglyph render FILE -o OUT.png`,\n\
              `tensorglyph bench --size WxH`, `tensorglyph view [OPTIONS]`, `'`.\n\
              \n\
              ```sh\n\
              tensorglyph demo -o 'a b.png'   # comment\n\
              cargo test\n\
              ```\n\
              ```\n\
              tensorglyph not-sh\n\
              ```\n\
              Under X: `xvfb-run -s \"-screen 0 8x8x24\" tensorglyph view --demo grid40`.\n";
    let got: Vec<(usize, Vec<String>)> = extract("page.md", md)
        .into_iter()
        .map(|c| (c.line, c.args))
        .collect();
    let w = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert_eq!(
        got,
        vec![
            (1, w(&["render", "--demo", "grid40", "-o", "a.png"])),
            (2, w(&["info", "grid40.vtk", "--json"])),
            (7, w(&["demo", "-o", "a b.png"])),
            (13, w(&["view", "--demo", "grid40"])),
        ]
    );

    let mut args = w(&["bench", "--frames", "9", "--budget=30"]);
    let mut used = vec![false; SUBSTITUTIONS.len()];
    substitute(&mut args, &mut used);
    assert_eq!(
        args,
        w(&[
            "bench",
            "--frames",
            "1",
            "--budget=0.25",
            "--size",
            "64x48",
            "--scene",
            "grid:16"
        ])
    );
}
