//! The book's links hold, checked without mdbook: every relative link and image of README.md, of
//! the test map (tests/README.md) and of every page of the book's sources (docs/book/src) names a
//! file that exists, every `#anchor`
//! names a heading of the page it points into, and docs/book/src/SUMMARY.md lists every page of
//! docs/book/src and nothing else.
//!
//! # The rules
//!
//! - **Links** are inline links and images (`[text](target)`, `![alt](target "title")`,
//!   `<target>` in the parentheses) and reference definitions (`[name]: target`), outside fenced
//!   code blocks and inline code spans. Targets with a scheme (`https:`, `mailto:`) are not
//!   checked; every other target is a path relative to the page, with an optional `#anchor`.
//! - **A book page's** links must stay inside docs/book/src, since mdBook copies nothing else
//!   into the HTML book (the generated reports are under docs/book/src/generated/, which links to
//!   docs/bench and docs/stability, where the `bench` and `stability` commands write them).
//!   README.md's and tests/README.md's links must stay inside the repository.
//! - **Anchors** follow mdBook's rule for heading ids (`id_from_content` and `unique_id` in
//!   mdbook-html's `utils.rs`): the heading's text (code spans keep their text, links their link
//!   text), trimmed and lower-cased; alphanumerics, `_` and `-` kept, whitespace turned into
//!   `-`, everything else dropped; a repeated id on one page gets `-1`, `-2`, … An explicit
//!   `{#id}` at the end of a heading is its id. Headings are ATX headings (`#` … `######`).
//! - **SUMMARY.md** lists each page once, as a link relative to docs/book/src, and every `.md`
//!   file under docs/book/src (symlinked folders followed) but SUMMARY.md itself is listed.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::fs;
use std::path::{Component, Path, PathBuf};

/// Where the checker reads pages and asks whether files exist: the repository on disk, or a
/// map in memory for the checker's own tests.
trait Files {
    fn exists(&self, path: &Path) -> bool;
    fn read(&self, path: &Path) -> Option<String>;
}

/// The repository on disk, paths relative to its top folder.
struct Disk(PathBuf);

impl Files for Disk {
    fn exists(&self, path: &Path) -> bool {
        self.0.join(path).exists()
    }
    fn read(&self, path: &Path) -> Option<String> {
        fs::read_to_string(self.0.join(path)).ok()
    }
}

/// Pages and other files in memory.
#[derive(Default)]
struct Memory(BTreeMap<PathBuf, String>);

impl Files for Memory {
    fn exists(&self, path: &Path) -> bool {
        self.0.contains_key(path) || self.0.keys().any(|k| k.starts_with(path))
    }
    fn read(&self, path: &Path) -> Option<String> {
        self.0.get(path).cloned()
    }
}

/// `path` with `.` and `..` resolved lexically (symlinks are not followed, so a link through
/// docs/book/src/generated stays under docs/book/src); `None` if it climbs above its root.
fn normalize(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::Normal(n) => out.push(n),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

/// Whether a line opens or closes a fenced code block: its fence characters and their count.
fn fence(line: &str) -> Option<(char, usize)> {
    let indent = line.len() - line.trim_start_matches(' ').len();
    if indent > 3 {
        return None;
    }
    let t = &line[indent..];
    let c = t.chars().next()?;
    if c != '`' && c != '~' {
        return None;
    }
    let n = t.chars().take_while(|&x| x == c).count();
    (n >= 3).then_some((c, n))
}

/// The page with fenced code blocks and inline code spans blanked out (every other character,
/// newlines included, stays where it was), so links are only looked for in prose.
fn prose(md: &str) -> String {
    let mut out = String::with_capacity(md.len());
    let mut open: Option<(char, usize)> = None;
    for line in md.split_inclusive('\n') {
        let f = fence(line.trim_end_matches('\n'));
        let blank = match (open, f) {
            (None, Some(f)) => {
                open = Some(f);
                true
            }
            (Some((c, n)), Some((c2, n2))) if c == c2 && n2 >= n => {
                open = None;
                true
            }
            (Some(_), _) => true,
            (None, None) => false,
        };
        if blank {
            out.extend(line.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
        } else {
            out.push_str(line);
        }
    }
    blank_code_spans(&out)
}

/// Inline code spans blanked: a run of N backticks opens a span that the next run of exactly N
/// closes; an unclosed run is literal text.
fn blank_code_spans(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = chars.clone();
    let run_at = |i: usize| chars[i..].iter().take_while(|&&c| c == '`').count();
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '`' {
            i += 1;
            continue;
        }
        let n = run_at(i);
        let mut j = i + n;
        let mut close = None;
        while j < chars.len() {
            if chars[j] == '`' {
                let m = run_at(j);
                if m == n {
                    close = Some(j);
                    break;
                }
                j += m;
            } else {
                j += 1;
            }
        }
        match close {
            Some(j) => {
                for c in &mut out[i..j + n] {
                    if *c != '\n' {
                        *c = ' ';
                    }
                }
                i = j + n;
            }
            None => i += n,
        }
    }
    out.into_iter().collect()
}

/// A link target as written, and the 1-based line it is on.
#[derive(Debug, PartialEq)]
struct Link {
    line: usize,
    target: String,
}

/// The link and image targets of a page (the rules are in the module documentation).
fn links(md: &str) -> Vec<Link> {
    let text = prose(md);
    let line_of = |byte: usize| text[..byte].matches('\n').count() + 1;
    let mut out = Vec::new();
    // Inline links and images: `](` then the destination up to its closing parenthesis.
    let mut from = 0;
    while let Some(k) = text[from..].find("](") {
        let start = from + k + 2;
        from = start;
        let rest = &text[start..];
        let dest = if let Some(r) = rest.strip_prefix('<') {
            match r.find('>') {
                Some(e) => r[..e].to_string(),
                None => continue,
            }
        } else {
            // Up to the first space (a title follows) or the parenthesis closing the link,
            // parentheses inside the destination balanced.
            let mut depth = 0;
            let mut end = None;
            for (i, c) in rest.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' if depth == 0 => {
                        end = Some(i);
                        break;
                    }
                    ')' => depth -= 1,
                    c if c.is_whitespace() => {
                        end = Some(i);
                        break;
                    }
                    _ => {}
                }
            }
            match end {
                Some(e) => rest[..e].to_string(),
                None => continue,
            }
        };
        out.push(Link {
            line: line_of(start),
            target: dest,
        });
    }
    // Reference definitions: `[name]: target` at the start of a line.
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if line.len() - t.len() <= 3
            && t.starts_with('[')
            && let Some(close) = t.find("]:")
            && !t[1..close].contains(']')
            && let Some(dest) = t[close + 2..].split_whitespace().next()
        {
            let dest = dest.trim_start_matches('<').trim_end_matches('>');
            out.push(Link {
                line: line_of(offset),
                target: dest.to_string(),
            });
        }
        offset += line.len();
    }
    out.sort_by_key(|l| l.line);
    out
}

/// mdBook's id of a heading's text (`id_from_content`).
fn id_from_content(text: &str) -> String {
    text.trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// The text of a heading's inline content: code spans keep their text, links and images their
/// bracketed text, without the destination.
fn heading_text(raw: &str) -> String {
    let mut out = String::new();
    let chars: Vec<char> = raw.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '`' => {}
            ']' if chars.get(i + 1) == Some(&'(') => {
                // Skip the destination of a link or image.
                let mut depth = 0;
                i += 2;
                while i < chars.len() {
                    match chars[i] {
                        '(' => depth += 1,
                        ')' if depth == 0 => break,
                        ')' => depth -= 1,
                        _ => {}
                    }
                    i += 1;
                }
            }
            '[' | ']' => {}
            '!' if chars.get(i + 1) == Some(&'[') => {}
            c => out.push(c),
        }
        i += 1;
    }
    out
}

/// The ids mdBook gives the headings of a page, in order.
fn heading_ids(md: &str) -> Vec<String> {
    let mut used = HashSet::new();
    let mut ids = Vec::new();
    let mut open: Option<(char, usize)> = None;
    for line in md.lines() {
        if let Some(f) = fence(line) {
            open = match open {
                None => Some(f),
                Some((c, n)) if c == f.0 && f.1 >= n => None,
                o => o,
            };
            continue;
        }
        if open.is_some() {
            continue;
        }
        let t = line.trim_start();
        if line.len() - t.len() > 3 {
            continue;
        }
        let level = t.chars().take_while(|&c| c == '#').count();
        if level == 0 || level > 6 {
            continue;
        }
        let rest = &t[level..];
        if !(rest.is_empty() || rest.starts_with(' ') || rest.starts_with('\t')) {
            continue;
        }
        // Closing `#`s (preceded by a space) are not part of the text.
        let mut content = rest.trim();
        let stripped = content.trim_end_matches('#');
        if stripped.is_empty() || stripped.ends_with(' ') {
            content = stripped.trim_end();
        }
        let id = match content
            .strip_suffix('}')
            .and_then(|c| c.rfind("{#").map(|k| (c, k)))
        {
            Some((c, k)) => c[k + 2..]
                .split_whitespace()
                .next()
                .unwrap_or("")
                .to_string(),
            None => id_from_content(&heading_text(content)),
        };
        // unique_id: a repeated id gets the first free suffix -1, -2, …
        let mut unique = id.clone();
        let mut n = 0;
        while !used.insert(unique.clone()) {
            n += 1;
            unique = format!("{id}-{n}");
        }
        ids.push(unique);
    }
    ids
}

/// Whether a link target is outside the repository's files (a URL).
fn is_external(target: &str) -> bool {
    let scheme_len = target.find(':').filter(|&k| {
        k > 0
            && target[..k]
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    });
    scheme_len.is_some() || target.starts_with("//")
}

/// What is wrong with the links of `page` (a path relative to the repository), whose links must
/// stay inside `confine`.
fn link_problems(page: &Path, md: &str, confine: &Path, files: &dyn Files) -> Vec<String> {
    let dir = page.parent().unwrap_or(Path::new(""));
    let mut problems = Vec::new();
    for link in links(md) {
        let shown = format!("{}:{}: `{}`", page.display(), link.line, link.target);
        if link.target.is_empty() {
            problems.push(format!("{shown}: empty link target"));
            continue;
        }
        if is_external(&link.target) {
            continue;
        }
        let (path, anchor) = match link.target.split_once('#') {
            Some((p, a)) => (p, Some(a)),
            None => (link.target.as_str(), None),
        };
        let target = if path.is_empty() {
            Some(page.to_path_buf())
        } else {
            normalize(&dir.join(path))
        };
        let Some(target) = target else {
            problems.push(format!("{shown}: climbs above the repository"));
            continue;
        };
        if !target.starts_with(confine) {
            problems.push(format!(
                "{shown}: {} is outside {} (mdBook would not copy it)",
                target.display(),
                confine.display()
            ));
            continue;
        }
        if !files.exists(&target) {
            problems.push(format!("{shown}: {} does not exist", target.display()));
            continue;
        }
        let Some(anchor) = anchor else { continue };
        if target.extension().is_none_or(|e| e != "md") {
            problems.push(format!("{shown}: an anchor into a file that is not a page"));
            continue;
        }
        let Some(text) = files.read(&target) else {
            problems.push(format!("{shown}: {} cannot be read", target.display()));
            continue;
        };
        let ids = heading_ids(&text);
        if !ids.iter().any(|id| id == anchor) {
            problems.push(format!(
                "{shown}: no heading with id `{anchor}` in {} (ids: {})",
                target.display(),
                ids.join(", ")
            ));
        }
    }
    problems
}

/// The pages SUMMARY.md links, relative to the book's src folder, in order.
fn summary_pages(summary: &str) -> Vec<(usize, String)> {
    links(summary)
        .into_iter()
        .filter(|l| !is_external(&l.target))
        .map(|l| (l.line, l.target))
        .collect()
}

/// What is wrong between SUMMARY.md's list and the pages in src (paths relative to src).
fn summary_problems(summary: &str, pages: &BTreeSet<PathBuf>) -> Vec<String> {
    let mut problems = Vec::new();
    let mut listed = BTreeSet::new();
    for (line, target) in summary_pages(summary) {
        let Some(p) = normalize(Path::new(&target)) else {
            problems.push(format!("SUMMARY.md:{line}: `{target}` climbs out of src"));
            continue;
        };
        if !pages.contains(&p) {
            problems.push(format!("SUMMARY.md:{line}: `{target}` is no page in src"));
        }
        if !listed.insert(p) {
            problems.push(format!("SUMMARY.md:{line}: `{target}` is listed twice"));
        }
    }
    for p in pages.difference(&listed) {
        problems.push(format!("{} is not listed in SUMMARY.md", p.display()));
    }
    problems
}

/// Every `.md` file under `dir` (symlinked folders followed), relative to `dir`.
fn markdown_under(dir: &Path) -> BTreeSet<PathBuf> {
    fn walk(root: &Path, rel: &Path, depth: usize, out: &mut BTreeSet<PathBuf>) {
        assert!(
            depth < 16,
            "folders nested too deep under {}",
            root.display()
        );
        let mut entries: Vec<_> = fs::read_dir(root.join(rel))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        entries.sort();
        for name in entries {
            let r = rel.join(&name);
            let meta = fs::metadata(root.join(&r)).unwrap();
            if meta.is_dir() {
                walk(root, &r, depth + 1, out);
            } else if r.extension().is_some_and(|e| e == "md") {
                out.insert(r);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, Path::new(""), 0, &mut out);
    out
}

const SRC: &str = "docs/book/src";

#[test]
fn every_link_of_the_readme_and_the_book_holds() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = Disk(repo.to_path_buf());
    let src = Path::new(SRC);
    let pages = markdown_under(&repo.join(src));
    let summary = files.read(&src.join("SUMMARY.md")).expect("SUMMARY.md");

    let mut problems = Vec::new();
    let mut in_summary: BTreeSet<PathBuf> = pages.clone();
    in_summary.remove(Path::new("SUMMARY.md"));
    problems.extend(summary_problems(&summary, &in_summary));

    let mut checked = 0;
    for page in ["README.md", "tests/README.md"] {
        let text = files.read(Path::new(page)).expect(page);
        problems.extend(link_problems(Path::new(page), &text, Path::new(""), &files));
        checked += 1;
    }
    for page in &pages {
        let path = src.join(page);
        let text = files.read(&path).unwrap();
        problems.extend(link_problems(&path, &text, src, &files));
        checked += 1;
    }
    eprintln!(
        "{checked} pages checked ({} in SUMMARY.md), {} problems",
        in_summary.len(),
        problems.len()
    );
    assert!(
        pages.len() >= 20,
        "only {} pages found under {SRC}",
        pages.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_finds_broken_links() {
    let mut m = Memory::default();
    let src = Path::new("book/src");
    let page = |s: &str| src.join(s);
    m.0.insert(
        page("a.md"),
        "# Alpha page\n\
         ## `--flag`: what it does\n\
         ## Twice\n\
         ## Twice\n\
         ```sh\n\
         # not a heading\n\
         [not a link](missing.md)\n\
         ```\n\
         See [b](sub/b.md#the-b-heading), [self](#twice-1), `[code](nowhere.md)`,\n\
         ![img](img.png), [web](https://example.org/x.md) and [ok](#--flag-what-it-does).\n\
         [ref]: sub/b.md\n"
            .into(),
    );
    m.0.insert(
        page("sub/b.md"),
        "# The B heading\nBack to [a](../a.md#alpha-page).\n".into(),
    );
    m.0.insert(page("img.png"), String::new());
    m.0.insert(PathBuf::from("outside.md"), "# Outside\n".into());

    assert_eq!(
        heading_ids(&m.0[&page("a.md")]),
        ["alpha-page", "--flag-what-it-does", "twice", "twice-1"]
    );
    let ok = |p: &str| link_problems(&page(p), &m.0[&page(p)], src, &m);
    assert_eq!(ok("a.md"), Vec::<String>::new());
    assert_eq!(ok("sub/b.md"), Vec::<String>::new());
    assert_eq!(
        links(&m.0[&page("a.md")])
            .iter()
            .map(|l| (l.line, l.target.as_str()))
            .collect::<Vec<_>>(),
        [
            (9, "sub/b.md#the-b-heading"),
            (9, "#twice-1"),
            (10, "img.png"),
            (10, "https://example.org/x.md"),
            (10, "#--flag-what-it-does"),
            (11, "sub/b.md"),
        ]
    );

    // Each kind of break is found, with the page and line.
    let broken = "Missing [file](c.md), [anchor](sub/b.md#no-such), [self](#twice-2),\n\
                  ![image](gone.png), [out](../../outside.md), [up](../../../../x.md),\n\
                  [not a page](img.png#top).\n";
    let got = link_problems(&page("a.md"), broken, src, &m);
    let expect = [
        "book/src/a.md:1: `c.md`: book/src/c.md does not exist",
        "book/src/a.md:1: `sub/b.md#no-such`: no heading with id `no-such` in book/src/sub/b.md",
        "book/src/a.md:1: `#twice-2`: no heading with id `twice-2` in book/src/a.md",
        "book/src/a.md:2: `gone.png`: book/src/gone.png does not exist",
        "book/src/a.md:2: `../../outside.md`: outside.md is outside book/src",
        "book/src/a.md:2: `../../../../x.md`: climbs above the repository",
        "book/src/a.md:3: `img.png#top`: an anchor into a file that is not a page",
    ];
    assert_eq!(got.len(), expect.len(), "{got:#?}");
    for (g, e) in got.iter().zip(expect) {
        assert!(g.starts_with(e), "{g}\n  does not start with\n{e}");
    }

    // SUMMARY.md against the pages: one unlisted, one missing, one twice.
    let pages: BTreeSet<PathBuf> = ["a.md", "sub/b.md", "c.md"]
        .iter()
        .map(PathBuf::from)
        .collect();
    let summary = "# Summary\n\n- [A](a.md)\n  - [B](sub/b.md)\n- [D](d.md)\n- [A again](./a.md)\n";
    assert_eq!(
        summary_problems(summary, &pages),
        [
            "SUMMARY.md:5: `d.md` is no page in src",
            "SUMMARY.md:6: `./a.md` is listed twice",
            "c.md is not listed in SUMMARY.md",
        ]
    );
}

#[test]
fn heading_ids_follow_mdbook() {
    // mdbook-html's own examples (utils.rs tests) and the headings of this book.
    let id = |h: &str| id_from_content(&heading_text(h));
    assert_eq!(
        id("`--passes`: add more rustdoc passes"),
        "--passes-add-more-rustdoc-passes"
    );
    assert_eq!(id("Über"), "über");
    assert_eq!(id("  Trim  "), "trim");
    assert_eq!(
        id("6. The GPU shader's root finder, as built"),
        "6-the-gpu-shaders-root-finder-as-built"
    );
    assert_eq!(id("A [link](x.md#y) in it"), "a-link-in-it");
    assert_eq!(id("snake_case and kebab-case"), "snake_case-and-kebab-case");
    assert_eq!(
        heading_ids("# A {#custom}\n# A\n# A\n"),
        ["custom", "a", "a-1"]
    );
}
