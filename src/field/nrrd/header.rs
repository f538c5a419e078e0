//! A NRRD header: its lines as `field: value` pairs (comments and `key:=value` pairs skipped, a
//! field given twice refused), and the numbers and vectors in the values.

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::error::{LoadErrorKind, escape_for_error};

pub(super) type Res<T> = Result<T, LoadErrorKind>;

pub(super) fn field(name: &str, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.to_string(),
        message: message.into(),
    }
}

/// The header's fields, as text (the value after `: `; bytes that are not UTF-8 become U+FFFD,
/// and are escaped wherever a value is shown).
pub(super) struct Header {
    fields: HashMap<String, String>,
    /// Where the data begins when it is attached.
    pub(super) data_start: usize,
}

impl Header {
    pub(super) fn get(&self, key: &str) -> Option<&str> {
        self.fields.get(key).map(String::as_str)
    }

    pub(super) fn need(&self, key: &str) -> Res<&str> {
        self.get(key)
            .ok_or_else(|| field(key, "missing; the reader needs it"))
    }
}

/// Where the header in `bytes` ends: just after its first empty line (the first line, the
/// magic, not counted), `None` if it runs to the end.
pub(super) fn header_end(bytes: &[u8]) -> Option<usize> {
    let mut pos = bytes.iter().position(|&b| b == b'\n')? + 1;
    loop {
        let end = pos + bytes[pos..].iter().position(|&b| b == b'\n')?;
        if matches!(&bytes[pos..end], b"" | b"\r") {
            return Some(end + 1);
        }
        pos = end + 1;
    }
}

/// The header's fields. Comments and `key:=value` pairs are skipped as bytes (Teem writes
/// Latin-1 into them); a field given twice is refused.
pub(super) fn parse_header(bytes: &[u8]) -> Res<Header> {
    if !bytes.starts_with(b"NRRD000") {
        return Err(LoadErrorKind::Malformed(
            "not a NRRD file (no 'NRRD000' magic)".into(),
        ));
    }
    let mut fields = HashMap::new();
    let mut pos = 0;
    let mut first = true;
    loop {
        if pos >= bytes.len() {
            break;
        }
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |e| pos + e);
        let raw = &bytes[pos..end];
        pos = (end + 1).min(bytes.len());
        let line = raw.strip_suffix(b"\r").unwrap_or(raw);
        if first {
            first = false;
            continue;
        }
        if line.is_empty() {
            break;
        }
        if line.starts_with(b"#") || line.windows(2).any(|w| w == b":=") {
            continue;
        }
        let Some(colon) = line.windows(2).position(|w| w == b": ") else {
            return Err(LoadErrorKind::Malformed(format!(
                "header line '{}' is not 'field: value'",
                escape_for_error(line)
            )));
        };
        let key = String::from_utf8_lossy(&line[..colon])
            .trim()
            .to_ascii_lowercase()
            .replace("datafile", "data file");
        let value = String::from_utf8_lossy(&line[colon + 2..])
            .trim()
            .to_string();
        // A map, not a list: 100,000 fields are as quick to check as ten.
        if fields.contains_key(&key) {
            return Err(field(&key, "given twice"));
        }
        fields.insert(key, value);
    }
    Ok(Header {
        fields,
        data_start: pos,
    })
}

pub(super) fn number<T: std::str::FromStr>(key: &str, s: &str) -> Res<T> {
    s.parse()
        .map_err(|_| field(key, format!("'{}' is not a number", escape_for_error(s))))
}

/// `(a,b,c)` as a vector; `None` for `none`.
pub(super) fn vector(key: &str, s: &str) -> Res<Option<Vector3<f64>>> {
    if s == "none" {
        return Ok(None);
    }
    let inner = s
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or_else(|| {
            field(
                key,
                format!("'{}' is not a vector (x,y,z)", escape_for_error(s)),
            )
        })?;
    let v: Vec<f64> = inner
        .split(',')
        .map(|x| number::<f64>(key, x.trim()))
        .collect::<Res<_>>()?;
    if v.len() != 3 || !v.iter().all(|x| x.is_finite()) {
        return Err(field(
            key,
            format!("'{}' is not a finite 3-vector", escape_for_error(s)),
        ));
    }
    Ok(Some(Vector3::new(v[0], v[1], v[2])))
}

pub(super) fn vectors(key: &str, s: &str) -> Res<Vec<Option<Vector3<f64>>>> {
    s.split_whitespace().map(|w| vector(key, w)).collect()
}

/// The `n` sizes of `sizes`, all positive.
pub(super) fn sizes(h: &Header, n: usize) -> Res<Vec<usize>> {
    let sizes: Vec<usize> = h
        .need("sizes")?
        .split_whitespace()
        .map(|s| number("sizes", s))
        .collect::<Res<_>>()?;
    if sizes.len() != n || sizes.contains(&0) {
        return Err(field("sizes", format!("needs {n} positive sizes")));
    }
    Ok(sizes)
}
