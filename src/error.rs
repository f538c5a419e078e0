//! Typed library errors. The binary adds context with anyhow and maps them to exit status 2.
//!
//! Every error prints as one line: text taken from a file (names, keywords, attribute values)
//! goes through [`escape_for_error`], and [`LoadError`]'s `Display` escapes whatever control
//! characters remain, so a crafted file can neither break the line nor drive the terminal.

use std::fmt;
use std::path::{Path, PathBuf};

/// How many characters of a file-derived string an error shows.
pub const ERROR_TEXT_MAX: usize = 80;

/// `s` made safe for a one-line message: control characters (C0, DEL, C1, and the Unicode
/// line/paragraph separators and bidirectional overrides that reorder what a terminal shows)
/// become `\n`, `\r`, `\t`, `\xNN` or `\u{NNNN}`, bytes that are not UTF-8 become `\xNN`, and
/// the result is cut to [`ERROR_TEXT_MAX`] characters with an ellipsis.
pub fn escape_for_error(s: impl AsRef<[u8]>) -> String {
    escape_bytes(s.as_ref(), ERROR_TEXT_MAX)
}

/// A path for an error message: escaped like [`escape_for_error`] but never shortened (the user
/// needs all of it to find the file).
pub fn escape_path(p: &Path) -> String {
    escape_bytes(p.as_os_str().as_encoded_bytes(), usize::MAX)
}

fn is_unsafe_char(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{2028}' | '\u{2029}' | '\u{200E}' | '\u{200F}')
        || ('\u{202A}'..='\u{202E}').contains(&c)
        || ('\u{2066}'..='\u{2069}').contains(&c)
}

fn escape_bytes(mut b: &[u8], max: usize) -> String {
    use fmt::Write as _;
    // Every shown character takes at most 4 bytes: the ellipsis is reached before this cut, and
    // a huge input costs nothing beyond it.
    let cut = max.saturating_add(2).saturating_mul(4);
    if b.len() > cut {
        b = &b[..cut];
    }
    let mut out = String::new();
    let mut shown = 0usize;
    let mut push = |out: &mut String, piece: &str| -> bool {
        let n = piece.chars().count();
        if shown.saturating_add(n) > max {
            out.push('…');
            return false;
        }
        shown += n;
        out.push_str(piece);
        true
    };
    while !b.is_empty() {
        let (valid, bad) = match std::str::from_utf8(b) {
            Ok(s) => (s, &b[b.len()..]),
            Err(e) => {
                let (v, rest) = b.split_at(e.valid_up_to());
                let v = std::str::from_utf8(v).unwrap_or_default();
                let n = e.error_len().unwrap_or(rest.len()).max(1);
                (v, &rest[..n])
            }
        };
        let consumed = valid.len() + bad.len();
        let mut buf = String::new();
        for c in valid.chars() {
            buf.clear();
            match c {
                '\n' => buf.push_str("\\n"),
                '\r' => buf.push_str("\\r"),
                '\t' => buf.push_str("\\t"),
                c if (c as u32) < 0x100 && is_unsafe_char(c) => {
                    let _ = write!(buf, "\\x{:02X}", c as u32);
                }
                c if is_unsafe_char(c) => {
                    let _ = write!(buf, "\\u{{{:04X}}}", c as u32);
                }
                c => buf.push(c),
            }
            if !push(&mut out, &buf) {
                return out;
            }
        }
        for &x in bad {
            buf.clear();
            let _ = write!(buf, "\\x{x:02X}");
            if !push(&mut out, &buf) {
                return out;
            }
        }
        b = &b[consumed..];
    }
    out
}

/// Escape the control characters left in an already formatted message (defence in depth: every
/// site escapes its file text, this keeps the line whole if one is missed).
fn one_line(s: &str) -> String {
    if s.chars().any(is_unsafe_char) {
        escape_bytes(s.as_bytes(), usize::MAX)
    } else {
        s.to_string()
    }
}

/// A tensor field could not be loaded. Always names the file; always one line.
#[derive(Debug)]
pub struct LoadError {
    pub path: PathBuf,
    pub kind: LoadErrorKind,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {}",
            escape_path(&self.path),
            one_line(&self.kind.to_string())
        )
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.kind.source()
    }
}

impl LoadError {
    pub fn new(path: impl Into<PathBuf>, kind: LoadErrorKind) -> Self {
        Self {
            path: path.into(),
            kind,
        }
    }
}

/// What went wrong while loading, with the place where it is known. String payloads hold text
/// from the file only through [`escape_for_error`]; the `name` fields hold the raw array name
/// and are escaped when displayed.
#[derive(Debug, thiserror::Error)]
pub enum LoadErrorKind {
    #[error("file not found")]
    Missing,
    #[error("cannot read file: {0}")]
    Io(#[from] std::io::Error),
    /// A FIFO, device, socket or directory: reading it could block forever or never end.
    #[error("not a regular file ({0}); only regular files are read")]
    NotRegularFile(&'static str),
    #[error("not a VTK file: {0}")]
    NotVtk(String),
    #[error("truncated or malformed file: {0}")]
    Malformed(String),
    #[error("no tensor array found (looked for 9- or 6-component point or cell data){0}")]
    NoTensorArray(String),
    /// `available` is already escaped (each name in it).
    #[error("array '{}' not found; available arrays: {available}", escape_for_error(.name))]
    ArrayNotFound { name: String, available: String },
    #[error(
        "array '{}' has {components} components; a tensor array needs 9 or 6",
        escape_for_error(.name)
    )]
    ComponentCount { name: String, components: usize },
    #[error(
        "array '{}' has {found} tuples but the dataset has {expected} {location}s",
        escape_for_error(.name)
    )]
    TupleCount {
        name: String,
        found: usize,
        expected: usize,
        location: &'static str,
    },
    /// A header field (NIfTI, NRRD) that cannot be used; `field` is the field's name as the
    /// format spells it, `message` already escaped.
    #[error("field '{}': {message}", escape_for_error(.field))]
    Field { field: String, message: String },
    /// A file of a set read as one field (FSL's eigen set) is missing: the error's path is that
    /// file, `set` names them all (already escaped).
    #[error("file not found; the files of an FSL eigen set are read together: {set}")]
    SetMemberMissing { set: String },
    #[error("unsupported dataset: {0}")]
    UnsupportedDataset(String),
    #[error("{0}")]
    Other(String),
}

/// Rendering failed (no usable adapter, bad size, GPU error, output not writable).
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("no GPU adapter available")]
    NoAdapter,
    #[error("invalid image size {width}x{height}: {reason}")]
    BadSize {
        width: u32,
        height: u32,
        reason: String,
    },
    #[error("GPU error: {0}")]
    Gpu(String),
    #[error("unsupported: {0}")]
    Unsupported(String),
    #[error("{}: cannot write output: {source}", path.display())]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_controls_and_bad_utf8() {
        assert_eq!(escape_for_error("plain name"), "plain name");
        assert_eq!(escape_for_error("a\nb\r\tc"), "a\\nb\\r\\tc");
        assert_eq!(escape_for_error(b"\x1b[2J\x00\x7f"), "\\x1B[2J\\x00\\x7F");
        assert_eq!(escape_for_error(b"ok\xff\xfeok"), "ok\\xFF\\xFEok");
        assert_eq!(escape_for_error("é ü 张"), "é ü 张");
        assert_eq!(escape_for_error("\u{85}\u{202E}x"), "\\x85\\u{202E}x");
    }

    #[test]
    fn truncates_with_an_ellipsis() {
        let long = "x".repeat(500);
        let e = escape_for_error(&long);
        assert_eq!(e.chars().count(), ERROR_TEXT_MAX + 1);
        assert!(e.ends_with('…'));
        // An escape is never cut in half.
        let e = escape_for_error(vec![0u8; 100]);
        assert!(e.ends_with("\\x00…"), "{e}");
        assert_eq!(
            escape_for_error("x".repeat(ERROR_TEXT_MAX)),
            "x".repeat(ERROR_TEXT_MAX)
        );
        // Found by tests/readers/corrupted.rs: lengths just above 4 × the limit were cut past the end.
        for n in 4 * ERROR_TEXT_MAX - 4..4 * ERROR_TEXT_MAX + 16 {
            let e = escape_for_error("y".repeat(n));
            assert_eq!(e.chars().count(), ERROR_TEXT_MAX + 1, "{n}");
        }
    }

    #[test]
    fn load_error_is_one_line() {
        let e = LoadError::new(
            "dir/bad\nname.vtk",
            LoadErrorKind::Malformed("left\x1b[2Jover".into()),
        );
        assert_eq!(
            e.to_string(),
            "dir/bad\\nname.vtk: truncated or malformed file: left\\x1B[2Jover"
        );
        let e = LoadError::new(
            "a.vtk",
            LoadErrorKind::ArrayNotFound {
                name: "t\n".into(),
                available: "none".into(),
            },
        );
        assert_eq!(
            e.to_string(),
            "a.vtk: array 't\\n' not found; available arrays: none"
        );
    }
}
