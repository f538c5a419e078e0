//! The mutation campaign of issue 13, on stable Rust and on every `cargo test`.
//!
//! Every file in `tests/data` and `tests/data/regressions` is mutated structure-aware: cut at
//! structural offsets (line starts, tag boundaries, the appended-data marker, compressed block
//! headers), bit-flipped, header numbers replaced by 0, −1, 2³¹, 2⁶³, NaN and friends, compressed
//! block headers and payloads corrupted, base64 broken, tags nested past the depth cap and
//! repeated, control characters planted in names, `.pvti` pieces pointed at FIFOs, devices and
//! absolute paths. Each case is read once, sequentially, and must:
//! - return a consistent field (as many positions as tensors, as the location's count, as the
//!   dimensions say; 6 or 9 components), which must then go through `derive_glyphs` and the
//!   `info` report, or an error whose `Display` is one line without control characters that
//!   names the file;
//! - take at most 2 s and allocate at most 64 MiB + 8× the bytes of the files read (measured by
//!   the counting global allocator below, peak reset per case);
//! - leave the file as it was.
//!
//! Seeded: `TENSORGLYPH_CAMPAIGN_SEED` (default 13) and `TENSORGLYPH_CAMPAIGN_CASES` (per file,
//! default 400) reproduce or widen a run; a failing case is saved under `CARGO_TARGET_TMPDIR`
//! for `tests/data/regressions/`.

// The counting allocator needs `unsafe impl GlobalAlloc`; nothing else in this file is unsafe.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use tensorglyph::field::vtk::{ReadOptions, read_field};

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

// ---------------------------------------------------------------------------------------------
// Seeded randomness.

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        // splitmix64
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> Option<&'a T> {
        (!v.is_empty()).then(|| &v[self.below(v.len())])
    }
}

// ---------------------------------------------------------------------------------------------
// What a file looks like, for the structure-aware mutations.

#[derive(Default)]
struct Shape {
    xml: bool,
    /// First byte after `<AppendedData ...>`'s `_` marker; the text part ends there.
    appended: Option<usize>,
    raw_appended: bool,
    header_bytes: usize,
    compressed: bool,
    /// Structural offsets: line starts, `<`, `>`, quotes, the marker, block starts.
    cuts: Vec<usize>,
    /// Numbers in tags and keyword lines (byte ranges).
    header_numbers: Vec<(usize, usize)>,
    /// Every number in the text part.
    numbers: Vec<(usize, usize)>,
    /// Where appended blocks start (marker + each `offset`).
    blocks: Vec<usize>,
    /// Base64 text: inline `format="binary"` arrays and appended base64 blocks.
    base64: Vec<(usize, usize)>,
    /// Whole elements that may be repeated (`<DataArray ...>...</DataArray>`, `<Piece>`...),
    /// or lines for legacy files.
    elements: Vec<(usize, usize)>,
    /// Byte ranges of attribute values and legacy array names, for planted control characters.
    names: Vec<(usize, usize)>,
    /// Ends of start tags (XML), where nesting can be inserted.
    tag_ends: Vec<usize>,
}

fn find_from(b: &[u8], from: usize, pat: &[u8]) -> Option<usize> {
    b.get(from..)?
        .windows(pat.len())
        .position(|w| w == pat)
        .map(|i| i + from)
}

fn is_num_byte(c: u8) -> bool {
    c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E')
}

fn numbers_in(b: &[u8], lo: usize, hi: usize, out: &mut Vec<(usize, usize)>) {
    let mut i = lo;
    while i < hi {
        let starts = (b[i].is_ascii_digit()
            || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)))
            && (i == 0 || !b[i - 1].is_ascii_alphanumeric());
        if starts {
            let s = i;
            i += 1;
            while i < hi && is_num_byte(b[i]) {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
}

fn shape_of(b: &[u8]) -> Shape {
    let mut s = Shape::default();
    let start = b.iter().position(|c| !c.is_ascii_whitespace()).unwrap_or(0);
    s.xml = b.get(start) == Some(&b'<');
    if s.xml {
        xml_shape(b, &mut s);
    } else {
        legacy_shape(b, &mut s);
    }
    s.cuts.sort_unstable();
    s.cuts.dedup();
    s
}

fn xml_shape(b: &[u8], s: &mut Shape) {
    if let Some(ad) = find_from(b, 0, b"<AppendedData")
        && let Some(us) = find_from(b, ad, b"_")
    {
        s.appended = Some(us + 1);
        s.raw_appended = find_from(&b[ad..us], 0, b"encoding=\"raw\"").is_some();
        s.cuts.push(us);
        s.cuts.push(us + 1);
    }
    let text_end = s.appended.unwrap_or(b.len());
    s.header_bytes = if find_from(&b[..text_end], 0, b"header_type=\"UInt64\"").is_some() {
        8
    } else {
        4
    };
    s.compressed = find_from(&b[..text_end], 0, b"compressor=").is_some();
    for (i, &c) in b[..text_end].iter().enumerate() {
        match c {
            b'<' | b'>' | b'"' | b'\n' => s.cuts.push(i),
            _ => {}
        }
    }
    numbers_in(b, 0, text_end, &mut s.numbers);
    // Tags: numbers inside them are header numbers; attribute values are names.
    let mut i = 0;
    while let Some(lt) = find_from(&b[..text_end], i, b"<") {
        let Some(gt) = find_from(&b[..text_end], lt, b">") else {
            break;
        };
        numbers_in(b, lt, gt, &mut s.header_numbers);
        let mut q = lt;
        while let Some(open) = find_from(&b[..gt], q, b"\"") {
            let Some(close) = find_from(&b[..gt], open + 1, b"\"") else {
                break;
            };
            s.names.push((open + 1, close));
            q = close + 1;
        }
        if b[lt + 1] != b'/' && b[lt + 1] != b'?' {
            s.tag_ends.push(gt + 1);
        }
        i = gt + 1;
    }
    // Repeatable elements and inline base64.
    for (open, close) in [
        (&b"<DataArray"[..], &b"</DataArray>"[..]),
        (b"<Piece", b"</Piece>"),
        (b"<PointData", b"</PointData>"),
        (b"<PDataArray", b"/>"),
    ] {
        let mut i = 0;
        while let Some(o) = find_from(&b[..text_end], i, open) {
            let Some(gt) = find_from(b, o, b">") else {
                break;
            };
            let end = if b[gt - 1] == b'/' {
                gt + 1
            } else {
                match find_from(&b[..text_end], gt, close) {
                    Some(c) => c + close.len(),
                    None => break,
                }
            };
            s.elements.push((o, end));
            if open == b"<DataArray" && find_from(&b[o..gt], 0, b"format=\"binary\"").is_some() {
                let text_start = gt + 1;
                let text_stop = find_from(b, text_start, b"<").unwrap_or(text_end);
                s.base64.push((text_start, text_stop));
            }
            i = gt + 1;
        }
    }
    if let Some(data) = s.appended {
        let mut i = 0;
        while let Some(o) = find_from(&b[..text_end], i, b"offset=\"") {
            let v = o + 8;
            let e = find_from(b, v, b"\"").unwrap_or(v);
            if let Some(off) = std::str::from_utf8(&b[v..e])
                .ok()
                .and_then(|t| t.parse::<usize>().ok())
                && data + off < b.len()
            {
                s.blocks.push(data + off);
                s.cuts.push(data + off);
                s.cuts.push(data + off + s.header_bytes);
                s.cuts.push(data + off + 3 * s.header_bytes);
            }
            i = e;
        }
        s.blocks.sort_unstable();
        s.blocks.dedup();
        if !s.raw_appended {
            for (k, &blk) in s.blocks.iter().enumerate() {
                let end = s
                    .blocks
                    .get(k + 1)
                    .copied()
                    .unwrap_or_else(|| find_from(b, blk, b"\n").unwrap_or(b.len()));
                s.base64.push((blk, end));
            }
        }
    }
}

fn legacy_shape(b: &[u8], s: &mut Shape) {
    let binary = find_from(&b[..b.len().min(256)], 0, b"BINARY").is_some();
    let mut i = 0;
    while i < b.len() {
        let end = find_from(b, i, b"\n").unwrap_or(b.len());
        let line = &b[i..end];
        s.cuts.push(i);
        let printable = line
            .iter()
            .all(|c| c.is_ascii_graphic() || *c == b' ' || *c == b'\r');
        if printable {
            s.elements.push((i, (end + 1).min(b.len())));
            numbers_in(b, i, end, &mut s.numbers);
            if line.first().is_some_and(u8::is_ascii_uppercase) {
                numbers_in(b, i, end, &mut s.header_numbers);
                // The array name: the second token of SCALARS/TENSORS/... lines.
                let toks: Vec<usize> = (0..line.len())
                    .filter(|&k| line[k] != b' ' && (k == 0 || line[k - 1] == b' '))
                    .collect();
                if toks.len() >= 3 {
                    let (a, z) = (toks[1], toks[2] - 1);
                    s.names.push((i + a, i + z));
                }
            }
        } else if binary {
            // Into binary data: cut points at a few spots of it.
            s.cuts.push(i + line.len() / 2);
        }
        i = end + 1;
    }
}

// ---------------------------------------------------------------------------------------------
// Mutations.

const EXTREME_NUMBERS: [&str; 12] = [
    "0",
    "-1",
    "1",
    "2147483648",
    "4294967296",
    "9223372036854775808",
    "18446744073709551615",
    "NaN",
    "inf",
    "1e308",
    "-2147483649",
    "99999999999999999999999",
];

fn splice(b: &[u8], at: (usize, usize), with: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(b.len() + with.len());
    out.extend_from_slice(&b[..at.0]);
    out.extend_from_slice(with);
    out.extend_from_slice(&b[at.1..]);
    out
}

fn flip_bits(b: &[u8], rng: &mut Rng, n: usize) -> (Vec<u8>, String) {
    let mut out = b.to_vec();
    let mut what = String::from("flip");
    for _ in 0..n {
        let i = rng.below(out.len());
        let bit = rng.below(8);
        out[i] ^= 1 << bit;
        what += &format!(" {i}:{bit}");
    }
    (out, what)
}

fn encode_uint(v: u64, n: usize) -> Vec<u8> {
    v.to_le_bytes()[..n].to_vec()
}

/// One mutation of `b`; `family` spreads the cases evenly over the kinds.
fn mutate(b: &[u8], s: &Shape, family: usize, rng: &mut Rng) -> (Vec<u8>, String) {
    if b.is_empty() {
        return (b.to_vec(), "empty".into());
    }
    match family {
        0 | 1 => {
            let cut = rng.pick(&s.cuts).copied().unwrap_or(0);
            let cut = (cut + rng.below(2)).min(b.len());
            (b[..cut].to_vec(), format!("cut at {cut}"))
        }
        2 => {
            let cut = rng.below(b.len());
            (b[..cut].to_vec(), format!("cut at {cut} (random)"))
        }
        3 => {
            let n = 1 + rng.below(3);
            flip_bits(b, rng, n)
        }
        4 | 5 => {
            let list = if family == 4 || s.numbers.is_empty() {
                &s.header_numbers
            } else {
                &s.numbers
            };
            let Some(&at) = rng.pick(list) else {
                return flip_bits(b, rng, 1);
            };
            let with = EXTREME_NUMBERS[rng.below(EXTREME_NUMBERS.len())];
            (
                splice(b, at, with.as_bytes()),
                format!("number at {} -> {with}", at.0),
            )
        }
        6 => {
            // A block header word (raw appended) set to an extreme value.
            let Some(&blk) = rng.pick(&s.blocks) else {
                return flip_bits(b, rng, 2);
            };
            if !s.raw_appended {
                return b64_corrupt(b, s, rng);
            }
            let hs = s.header_bytes;
            let words = if s.compressed { 4 } else { 1 };
            let w = rng.below(words);
            let v = [
                0,
                1,
                u32::MAX as u64,
                1 << 31,
                1 << 40,
                u64::MAX,
                64_000 * 72,
                1 << 20,
            ][rng.below(8)];
            let at = blk + w * hs;
            if at + hs > b.len() {
                return flip_bits(b, rng, 1);
            }
            (
                splice(b, (at, at + hs), &encode_uint(v, hs)),
                format!("block at {blk} word {w} = {v}"),
            )
        }
        7 => {
            // The payload after a block header: bytes overwritten (a broken compressed stream).
            let Some(&blk) = rng.pick(&s.blocks) else {
                return flip_bits(b, rng, 3);
            };
            let start = blk + if s.compressed { 4 } else { 1 } * s.header_bytes;
            if start >= b.len() {
                return flip_bits(b, rng, 1);
            }
            let mut out = b.to_vec();
            let n = 1 + rng.below(16);
            for k in 0..n {
                if let Some(x) = out.get_mut(start + k * (1 + rng.below(7))) {
                    *x = rng.next() as u8;
                }
            }
            (out, format!("payload at {start} overwritten ({n} bytes)"))
        }
        8 => b64_corrupt(b, s, rng),
        9 => nest(b, s, rng),
        10 => repeat(b, s, rng),
        _ => plant_controls(b, s, rng),
    }
}

fn b64_corrupt(b: &[u8], s: &Shape, rng: &mut Rng) -> (Vec<u8>, String) {
    let Some(&(lo, hi)) = rng.pick(&s.base64) else {
        return flip_bits(b, rng, 1);
    };
    if hi <= lo {
        return flip_bits(b, rng, 1);
    }
    let at = lo + rng.below(hi - lo);
    let (with, what): (&[u8], &str) = match rng.below(6) {
        0 => (b"!", "invalid char"),
        1 => (b"=", "padding mid-stream"),
        2 => (b"", "deleted char"),
        3 => (b"\n  ", "whitespace"),
        4 => (b"AAAA", "extra quad"),
        _ => (b"\x00", "NUL"),
    };
    let end = if what == "deleted char" { at + 1 } else { at };
    (
        splice(b, (at, end.min(b.len())), with),
        format!("base64 at {at}: {what}"),
    )
}

fn nest(b: &[u8], s: &Shape, rng: &mut Rng) -> (Vec<u8>, String) {
    let depth = [8, 63, 64, 65, 1000, 20_000][rng.below(6)];
    if !s.xml {
        return repeat(b, s, rng);
    }
    let Some(&at) = rng.pick(&s.tag_ends) else {
        return flip_bits(b, rng, 1);
    };
    let closed = rng.below(2) == 0;
    let mut ins = b"<a>".repeat(depth);
    if closed {
        ins.extend(b"</a>".repeat(depth));
    }
    (
        splice(b, (at, at), &ins),
        format!("{depth} nested <a> at {at} (closed: {closed})"),
    )
}

fn repeat(b: &[u8], s: &Shape, rng: &mut Rng) -> (Vec<u8>, String) {
    let Some(&(lo, hi)) = rng.pick(&s.elements) else {
        return flip_bits(b, rng, 1);
    };
    let times = [2, 10, 300, 3000][rng.below(4)];
    let elem = &b[lo..hi];
    // Whole copies only while they stay small: the file grows, and so may its budget.
    let times = times.min((1 << 22) / elem.len().max(1)).max(1);
    let mut ins = Vec::with_capacity(elem.len() * times);
    for _ in 0..times {
        ins.extend_from_slice(elem);
    }
    (
        splice(b, (hi, hi), &ins),
        format!("bytes {lo}..{hi} repeated {times} more times"),
    )
}

fn plant_controls(b: &[u8], s: &Shape, rng: &mut Rng) -> (Vec<u8>, String) {
    let Some(&(lo, hi)) = rng.pick(&s.names) else {
        return flip_bits(b, rng, 1);
    };
    let junk: &[u8] = [
        &b"\x1b[2J"[..],
        b"\x00",
        b"\r\n",
        b"\xc2\x85",
        b"\xe2\x80\xae",
        b"\xff\xfe",
        b"\x07\x08\x7f",
    ][rng.below(7)];
    let at = lo + rng.below(hi - lo + 1);
    let replace = rng.below(2) == 0;
    let end = if replace { hi } else { at };
    (
        splice(b, (at, end), junk),
        format!("control bytes {junk:?} at {at}"),
    )
}

// ---------------------------------------------------------------------------------------------
// Running and judging one case.

const BUDGET_FIXED: usize = 64 << 20;
const BUDGET_PER_BYTE: usize = 8;
const TIME_LIMIT: Duration = Duration::from_secs(2);

struct Case {
    label: String,
    /// The file to read.
    path: PathBuf,
    /// Bytes of every file the read may open (the file, its pieces).
    input_bytes: usize,
    opts: ReadOptions,
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
    let res = read_field(&case.path, &case.opts);
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
        Ok(f) => {
            tally.ok += 1;
            let n = f.tensors.len();
            let want = match f.array.location {
                tensorglyph::field::Location::Point => f.points,
                tensorglyph::field::Location::Cell => f.cells,
            };
            if f.positions.len() != n
                || want != n
                || !matches!(f.array.components, 6 | 9)
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
            if msg.chars().any(char::is_control) {
                return Err(format!("{label}: error with control characters: {msg:?}"));
            }
            if !msg.contains(name.as_ref()) {
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
                    .is_some_and(|e| e == "py" || e == "json" || e == "md")
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
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pvti_3pieces_binary.pvti"),
    )
    .unwrap();
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

#[test]
fn mutation_campaign() {
    let seed = env_usize("TENSORGLYPH_CAMPAIGN_SEED", 13);
    let per_file = env_usize("TENSORGLYPH_CAMPAIGN_CASES", 400) as usize;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut files = data_files(&root);
    files.extend(data_files(&root.join("regressions")));
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
                    opts: opts.clone(),
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
                        opts,
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

        for (label, bytes) in pvti_cases(&dir, fifo.as_deref()) {
            let path = dir.join("case.pvti");
            std::fs::write(&path, &bytes).unwrap();
            let case = Case {
                label,
                path,
                input_bytes: bytes.len() + pieces_bytes,
                opts: ReadOptions::default(),
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
                opts: ReadOptions::default(),
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
