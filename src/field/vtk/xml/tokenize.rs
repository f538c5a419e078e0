//! Tokenising the XML part of a VTK file: start tags with their attributes, parents and text.

use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::vtk::malformed::{Res, malformed};

/// Deepest element nesting accepted. VTK files nest fewer than 10 deep; the cap keeps the
/// open-element stack (and the error path) small whatever the file holds.
pub(super) const MAX_DEPTH: usize = 64;

/// One start tag, with the byte range of the text that follows it (up to the next `<`).
#[derive(Debug)]
pub(super) struct Tag {
    pub name: String,
    /// In file order; a repeated key: the last one counts (as it did with a map).
    pub attrs: Vec<(String, String)>,
    /// Index in [`Doc::tags`] of the enclosing element.
    pub parent: Option<usize>,
    pub text: (usize, usize),
}

impl Tag {
    pub fn get(&self, k: &str) -> Option<&str> {
        self.attrs
            .iter()
            .rev()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.as_str())
    }
}

/// Tokenised XML: start tags in document order, and where appended data starts.
pub(super) struct Doc {
    pub tags: Vec<Tag>,
    /// (first byte after the `_` marker, raw?) of `<AppendedData>`.
    pub appended: Option<(usize, bool)>,
}

impl Doc {
    /// Name of the element enclosing `t` ("" at the root).
    pub fn parent(&self, t: &Tag) -> &str {
        t.parent
            .and_then(|i| self.tags.get(i))
            .map_or("", |p| p.name.as_str())
    }
}

fn find(b: &[u8], from: usize, pat: &[u8]) -> Option<usize> {
    if from >= b.len() {
        return None;
    }
    b[from..]
        .windows(pat.len())
        .position(|w| w == pat)
        .map(|i| i + from)
}

fn unescape(s: &str) -> String {
    if !s.contains('&') {
        return s.to_string();
    }
    s.replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// Start tags in document order, each with its parent's index (not the whole open-element path:
/// copying that into every tag made deep nesting quadratic), up to `<AppendedData>`.
pub(super) fn tokenize(b: &[u8]) -> Res<Doc> {
    let mut tags: Vec<Tag> = Vec::new();
    // Indices in `tags` of the open elements.
    let mut stack: Vec<usize> = Vec::new();
    let mut i = 0;
    let mut appended = None;
    while let Some(lt) = b[i..].iter().position(|&c| c == b'<').map(|p| p + i) {
        let rest = &b[lt..];
        if rest.starts_with(b"<?") {
            i = find(b, lt, b"?>").ok_or_else(|| malformed("unterminated <? ... ?>"))? + 2;
            continue;
        }
        if rest.starts_with(b"<!--") {
            i = find(b, lt, b"-->").ok_or_else(|| malformed("unterminated comment"))? + 3;
            continue;
        }
        if rest.starts_with(b"<!") {
            i = find(b, lt, b">").ok_or_else(|| malformed("unterminated <!"))? + 1;
            continue;
        }
        let gt = find_tag_end(b, lt)?;
        let inner = std::str::from_utf8(&b[lt + 1..gt])
            .map_err(|_| malformed(format!("non-UTF-8 bytes in an XML tag at byte {lt}")))?;
        if let Some(name) = inner.strip_prefix('/') {
            let name = name.trim();
            match stack.pop() {
                Some(open) if tags[open].name == name => {}
                Some(open) => {
                    return Err(malformed(format!(
                        "XML: </{}> closes <{}> at byte {lt}",
                        esc(name),
                        esc(&tags[open].name)
                    )));
                }
                None => return Err(malformed(format!("XML: unmatched </{}>", esc(name)))),
            }
            i = gt + 1;
            continue;
        }
        let self_closing = inner.ends_with('/');
        let inner = inner.trim_end_matches('/');
        let (name, attrs) = parse_attrs(inner)?;
        let parent = stack.last().copied();
        if name == "AppendedData" {
            let tag = Tag {
                name: name.to_string(),
                attrs,
                parent,
                text: (gt + 1, gt + 1),
            };
            let raw = match tag.get("encoding") {
                Some("raw") => true,
                Some("base64") | None => false,
                Some(other) => {
                    return Err(LoadErrorKind::UnsupportedDataset(format!(
                        "appended data encoding '{}'",
                        esc(other)
                    )));
                }
            };
            let us = b[gt + 1..]
                .iter()
                .position(|&c| c == b'_')
                .ok_or_else(|| malformed("AppendedData without the '_' marker"))?;
            appended = Some((gt + 1 + us + 1, raw));
            tags.push(tag);
            // Everything after the marker is data (raw bytes may contain '<').
            return Ok(Doc { tags, appended });
        }
        let text_end = b[gt + 1..]
            .iter()
            .position(|&c| c == b'<')
            .map_or(b.len(), |p| p + gt + 1);
        if !self_closing && stack.len() >= MAX_DEPTH {
            return Err(malformed(format!(
                "XML nests deeper than {MAX_DEPTH} elements at byte {lt}"
            )));
        }
        tags.push(Tag {
            name: name.to_string(),
            attrs,
            parent,
            text: (gt + 1, text_end),
        });
        if !self_closing {
            stack.push(tags.len() - 1);
        }
        i = gt + 1;
    }
    if let Some(&open) = stack.last() {
        return Err(malformed(format!(
            "XML ends inside <{}> (truncated?)",
            esc(&tags[open].name)
        )));
    }
    Ok(Doc { tags, appended })
}

/// The `>` closing the tag that starts at `lt`, skipping quoted attribute values.
fn find_tag_end(b: &[u8], lt: usize) -> Res<usize> {
    let mut quote = None;
    for (k, &c) in b[lt..].iter().enumerate() {
        match (quote, c) {
            (None, b'"') | (None, b'\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, b'>') => return Ok(lt + k),
            _ => {}
        }
    }
    Err(malformed(format!(
        "XML tag at byte {lt} is not closed (truncated?)"
    )))
}

fn parse_attrs(inner: &str) -> Res<(&str, Vec<(String, String)>)> {
    let inner = inner.trim();
    let name_end = inner
        .find(|c: char| c.is_ascii_whitespace())
        .unwrap_or(inner.len());
    let name = &inner[..name_end];
    if name.is_empty() {
        return Err(malformed("XML tag without a name"));
    }
    let mut attrs = Vec::new();
    let mut s = inner[name_end..].trim_start();
    while !s.is_empty() {
        let eq = s
            .find('=')
            .ok_or_else(|| malformed(format!("XML <{}>: attribute without a value", esc(name))))?;
        let key = s[..eq].trim();
        let after = s[eq + 1..].trim_start();
        let q = after
            .chars()
            .next()
            .filter(|c| *c == '"' || *c == '\'')
            .ok_or_else(|| {
                malformed(format!(
                    "XML <{}>: unquoted attribute '{}'",
                    esc(name),
                    esc(key)
                ))
            })?;
        let close = after[1..].find(q).ok_or_else(|| {
            malformed(format!(
                "XML <{}>: unterminated attribute '{}'",
                esc(name),
                esc(key)
            ))
        })?;
        attrs.push((key.to_string(), unescape(&after[1..1 + close])));
        s = after[close + 2..].trim_start();
    }
    Ok((name, attrs))
}
