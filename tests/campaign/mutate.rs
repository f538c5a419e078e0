//! The campaign's seeded, structure-aware mutations (see `main.rs`).

// ---------------------------------------------------------------------------------------------
// Seeded randomness.

pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        // splitmix64
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> Option<&'a T> {
        (!v.is_empty()).then(|| &v[self.below(v.len())])
    }
}

// ---------------------------------------------------------------------------------------------
// What a file looks like, for the structure-aware mutations.

#[derive(Default)]
pub struct Shape {
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

pub fn find_from(b: &[u8], from: usize, pat: &[u8]) -> Option<usize> {
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

pub fn shape_of(b: &[u8]) -> Shape {
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
pub fn mutate(b: &[u8], s: &Shape, family: usize, rng: &mut Rng) -> (Vec<u8>, String) {
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
