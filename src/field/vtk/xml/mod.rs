//! VTK XML files (`.vti`, `.vtr`, `.vts`, `.vtu`, `.vtp`) and parallel image data (`.pvti`).
//!
//! vtkio 0.7.0-rc2 limitations this replaces: appended *raw* data is rejected (the file is read
//! as text), compressed `.vtp` files panic on the empty `Verts`/`Lines`/`Strips` sections VTK
//! always writes, an array that fails to decode can be dropped without an error, the image
//! `Direction` attribute is ignored, and declared sizes are trusted before allocation. This
//! reader tokenises the XML up to `<AppendedData>` (which may hold raw bytes), then decodes only
//! the arrays it needs: ascii, inline base64, appended base64 or raw; uncompressed or
//! zlib/lz4/lzma blocks; UInt32 or UInt64 headers; either byte order.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as B64;

use super::binary::{Scalar, decode_into, parse_ascii, parse_number, to_indices, try_vec};
use super::{
    ArrayDesc, Cells, Geometry, Parsed, ReadOptions, Res, assemble, malformed, pick, point_dims,
    read_bytes,
};
use crate::error::LoadErrorKind;
use crate::field::{DatasetKind, Location, TensorField};

/// One start tag, with the byte range of the text that follows it (up to the next `<`).
#[derive(Debug)]
struct Tag {
    name: String,
    attrs: HashMap<String, String>,
    /// Parent element names, outermost first.
    path: Vec<String>,
    text: (usize, usize),
}

impl Tag {
    fn get(&self, k: &str) -> Option<&str> {
        self.attrs.get(k).map(String::as_str)
    }

    fn parent(&self) -> &str {
        self.path.last().map_or("", String::as_str)
    }
}

/// Tokenised XML: start tags in document order, and where appended data starts.
struct Doc {
    tags: Vec<Tag>,
    /// (first byte after the `_` marker, raw?) of `<AppendedData>`.
    appended: Option<(usize, bool)>,
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

fn tokenize(b: &[u8]) -> Res<Doc> {
    let mut tags = Vec::new();
    let mut stack: Vec<String> = Vec::new();
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
                Some(open) if open == name => {}
                Some(open) => {
                    return Err(malformed(format!(
                        "XML: </{name}> closes <{open}> at byte {lt}"
                    )));
                }
                None => return Err(malformed(format!("XML: unmatched </{name}>"))),
            }
            i = gt + 1;
            continue;
        }
        let self_closing = inner.ends_with('/');
        let inner = inner.trim_end_matches('/');
        let (name, attrs) = parse_attrs(inner)?;
        let text_end = b[gt + 1..]
            .iter()
            .position(|&c| c == b'<')
            .map_or(b.len(), |p| p + gt + 1);
        if name == "AppendedData" {
            let raw = match attrs.get("encoding").map(String::as_str) {
                Some("raw") => true,
                Some("base64") | None => false,
                Some(other) => {
                    return Err(LoadErrorKind::UnsupportedDataset(format!(
                        "appended data encoding '{other}'"
                    )));
                }
            };
            let us = b[gt + 1..]
                .iter()
                .position(|&c| c == b'_')
                .ok_or_else(|| malformed("AppendedData without the '_' marker"))?;
            appended = Some((gt + 1 + us + 1, raw));
            tags.push(Tag {
                name: name.to_string(),
                attrs,
                path: stack.clone(),
                text: (gt + 1, gt + 1),
            });
            // Everything after the marker is data (raw bytes may contain '<').
            return Ok(Doc { tags, appended });
        }
        tags.push(Tag {
            name: name.to_string(),
            attrs,
            path: stack.clone(),
            text: (gt + 1, text_end),
        });
        if !self_closing {
            stack.push(name.to_string());
        }
        i = gt + 1;
    }
    if let Some(open) = stack.last() {
        return Err(malformed(format!("XML ends inside <{open}> (truncated?)")));
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

fn parse_attrs(inner: &str) -> Res<(&str, HashMap<String, String>)> {
    let inner = inner.trim();
    let name_end = inner
        .find(|c: char| c.is_ascii_whitespace())
        .unwrap_or(inner.len());
    let name = &inner[..name_end];
    if name.is_empty() {
        return Err(malformed("XML tag without a name"));
    }
    let mut attrs = HashMap::new();
    let mut s = inner[name_end..].trim_start();
    while !s.is_empty() {
        let eq = s
            .find('=')
            .ok_or_else(|| malformed(format!("XML <{name}>: attribute without a value")))?;
        let key = s[..eq].trim();
        let after = s[eq + 1..].trim_start();
        let q = after
            .chars()
            .next()
            .filter(|c| *c == '"' || *c == '\'')
            .ok_or_else(|| malformed(format!("XML <{name}>: unquoted attribute '{key}'")))?;
        let close = after[1..]
            .find(q)
            .ok_or_else(|| malformed(format!("XML <{name}>: unterminated attribute '{key}'")))?;
        attrs.insert(key.to_string(), unescape(&after[1..1 + close]));
        s = after[close + 2..].trim_start();
    }
    Ok((name, attrs))
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Compressor {
    None,
    Zlib,
    Lz4,
    Lzma,
}

/// File-wide decoding settings.
struct Ctx<'a> {
    b: &'a [u8],
    header: usize,
    big_endian: bool,
    compressor: Compressor,
    appended: Option<(usize, bool)>,
}

/// Where encoded bytes come from.
#[derive(Clone, Copy)]
enum Src<'a> {
    Raw(&'a [u8]),
    /// Base64 text with the header and the payload encoded as separate chunks (VTK does this
    /// for compressed data).
    B64(&'a [u8]),
    /// Base64 text with header and payload encoded as one stream (VTK does this for
    /// uncompressed data).
    Joint(&'a [u8]),
}

fn b64_len(nbytes: usize) -> usize {
    nbytes.div_ceil(3).saturating_mul(4)
}

fn b64_decode(chars: &[u8], what: &str) -> Res<Vec<u8>> {
    B64.decode(chars)
        .map_err(|e| malformed(format!("{what}: bad base64 data ({e})")))
}

impl Ctx<'_> {
    fn uint(&self, b: &[u8]) -> u64 {
        let mut v = 0u64;
        for k in 0..self.header {
            let byte = if self.big_endian {
                b[k]
            } else {
                b[self.header - 1 - k]
            };
            v = (v << 8) | byte as u64;
        }
        v
    }

    fn to_usize(&self, v: u64, what: &str) -> Res<usize> {
        usize::try_from(v).map_err(|_| malformed(format!("{what}: size {v} too large")))
    }

    /// The decoded (uncompressed) bytes of a binary or appended array.
    fn bytes(&self, src: Src<'_>, what: &str) -> Res<Vec<u8>> {
        let hs = self.header;
        // Header and payload, each either raw bytes or a separately encoded base64 chunk.
        let take = |src: &Src<'_>, pos: usize, n: usize, label: &str| -> Res<(Vec<u8>, usize)> {
            match src {
                Src::Raw(b) => {
                    let end = pos
                        .checked_add(n)
                        .filter(|&e| e <= b.len())
                        .ok_or_else(|| {
                            malformed(format!(
                                "{what}: {label} of {n} bytes runs past the end of the file (truncated?)"
                            ))
                        })?;
                    Ok((b[pos..end].to_vec(), end))
                }
                Src::B64(c) => {
                    let len = b64_len(n);
                    let end = pos.checked_add(len).filter(|&e| e <= c.len()).ok_or_else(|| {
                        malformed(format!(
                            "{what}: {label} of {n} bytes runs past the end of the data (truncated?)"
                        ))
                    })?;
                    let mut d = b64_decode(&c[pos..end], what)?;
                    if d.len() < n {
                        return Err(malformed(format!("{what}: short {label}")));
                    }
                    d.truncate(n);
                    Ok((d, end))
                }
                Src::Joint(c) => {
                    let end = pos
                        .checked_add(n)
                        .ok_or_else(|| malformed(format!("{what}: size overflow")))?;
                    let len = b64_len(end);
                    if len > c.len() {
                        return Err(malformed(format!(
                            "{what}: {label} of {n} bytes runs past the end of the data (truncated?)"
                        )));
                    }
                    let d = b64_decode(&c[..len], what)?;
                    if d.len() < end {
                        return Err(malformed(format!("{what}: short {label}")));
                    }
                    Ok((d[pos..end].to_vec(), end))
                }
            }
        };
        if self.compressor == Compressor::None {
            let (h, pos) = take(&src, 0, hs, "header")?;
            let n = self.to_usize(self.uint(&h), what)?;
            let (d, _) = take(&src, pos, n, "data")?;
            return Ok(d);
        }
        let (h3, _) = take(&src, 0, 3 * hs, "compression header")?;
        let nb = self.to_usize(self.uint(&h3[..hs]), what)?;
        let bs = self.to_usize(self.uint(&h3[hs..2 * hs]), what)?;
        let lbs = self.to_usize(self.uint(&h3[2 * hs..]), what)?;
        let hlen = nb
            .checked_add(3)
            .and_then(|v| v.checked_mul(hs))
            .ok_or_else(|| malformed(format!("{what}: block count {nb} overflows")))?;
        let avail = match &src {
            Src::Raw(b) => b.len(),
            Src::B64(c) | Src::Joint(c) => c.len() / 4 * 3,
        };
        if hlen > avail {
            return Err(malformed(format!(
                "{what}: {nb} compressed blocks declared but the data is only {avail} bytes (truncated?)"
            )));
        }
        let (h, pos) = take(&src, 0, hlen, "compression header")?;
        let mut csizes = try_vec::<usize>(nb)?;
        for k in 0..nb {
            let at = (3 + k) * hs;
            csizes.push(self.to_usize(self.uint(&h[at..at + hs]), what)?);
        }
        let ctotal = csizes
            .iter()
            .try_fold(0usize, |a, &c| a.checked_add(c))
            .ok_or_else(|| malformed(format!("{what}: compressed sizes overflow")))?;
        let (comp, _) = take(&src, pos, ctotal, "compressed data")?;
        let mut out = Vec::new();
        let mut at = 0;
        for (k, &cs) in csizes.iter().enumerate() {
            let usize_k = if k + 1 == nb && lbs != 0 { lbs } else { bs };
            // A real block cannot expand more than ~1000x (zlib's limit is 1032).
            if usize_k > cs.saturating_mul(1100).saturating_add(1 << 16) {
                return Err(malformed(format!(
                    "{what}: block {k} claims {usize_k} bytes from {cs} compressed bytes"
                )));
            }
            let block = &comp[at..at + cs];
            at += cs;
            let before = out.len();
            out.try_reserve(usize_k)
                .map_err(|_| malformed(format!("{what}: cannot allocate {usize_k} bytes")))?;
            let res = match self.compressor {
                Compressor::Zlib => flate2::read::ZlibDecoder::new(block)
                    .take(usize_k as u64 + 1)
                    .read_to_end(&mut out)
                    .map(|_| ())
                    .map_err(|e| e.to_string()),
                Compressor::Lzma => xz2::read::XzDecoder::new(block)
                    .take(usize_k as u64 + 1)
                    .read_to_end(&mut out)
                    .map(|_| ())
                    .map_err(|e| e.to_string()),
                Compressor::Lz4 => {
                    out.resize(before + usize_k, 0);
                    lz4_flex::block::decompress_into(block, &mut out[before..])
                        .map(|n| out.truncate(before + n))
                        .map_err(|e| e.to_string())
                }
                Compressor::None => unreachable!("handled above"),
            };
            res.map_err(|e| malformed(format!("{what}: block {k} does not decompress ({e})")))?;
            if out.len() - before != usize_k {
                return Err(malformed(format!(
                    "{what}: block {k} decompresses to {} bytes, expected {usize_k}",
                    out.len() - before
                )));
            }
        }
        Ok(out)
    }

    /// Decode a DataArray into f64 values.
    fn values(&self, a: &Tag, what: &str) -> Res<Vec<f64>> {
        let ty_name = a.get("type").unwrap_or("");
        let ty = Scalar::from_xml(ty_name).ok_or_else(|| {
            LoadErrorKind::UnsupportedDataset(format!("{what}: data type '{ty_name}'"))
        })?;
        let format = a.get("format").unwrap_or("ascii");
        let bytes = match format {
            "ascii" => {
                let text = &self.b[a.text.0..a.text.1];
                let n = text
                    .split(|c| c.is_ascii_whitespace())
                    .filter(|t| !t.is_empty())
                    .count();
                return parse_ascii(text, n, ty, what);
            }
            "binary" => {
                let text: Vec<u8> = self.b[a.text.0..a.text.1]
                    .iter()
                    .copied()
                    .filter(|c| !c.is_ascii_whitespace())
                    .collect();
                self.b64_bytes(&text, what)?
            }
            "appended" => {
                let (start, raw) = self.appended.ok_or_else(|| {
                    malformed(format!("{what}: appended array but no AppendedData"))
                })?;
                let off: usize = a
                    .get("offset")
                    .and_then(|o| o.trim().parse().ok())
                    .ok_or_else(|| malformed(format!("{what}: missing or bad offset")))?;
                let from = start
                    .checked_add(off)
                    .filter(|&f| f <= self.b.len())
                    .ok_or_else(|| {
                        malformed(format!("{what}: offset {off} is past the end of the file"))
                    })?;
                let data = &self.b[from..];
                if raw {
                    self.bytes(Src::Raw(data), what)?
                } else {
                    let end = data
                        .iter()
                        .position(|&c| {
                            !(c.is_ascii_alphanumeric() || c == b'+' || c == b'/' || c == b'=')
                        })
                        .unwrap_or(data.len());
                    self.b64_bytes(&data[..end], what)?
                }
            }
            other => {
                return Err(LoadErrorKind::UnsupportedDataset(format!(
                    "{what}: data format '{other}'"
                )));
            }
        };
        if bytes.len() % ty.size() != 0 {
            return Err(malformed(format!(
                "{what}: {} bytes is not a whole number of {ty_name} values",
                bytes.len()
            )));
        }
        let mut out = try_vec(bytes.len() / ty.size())?;
        decode_into(&bytes, ty, self.big_endian, &mut out);
        Ok(out)
    }

    /// Decode base64 data, telling separately encoded header chunks (padded, as VTK writes
    /// compressed data) from one joint stream (as VTK writes uncompressed data).
    fn b64_bytes(&self, text: &[u8], what: &str) -> Res<Vec<u8>> {
        let hs = self.header;
        let padded_at = |nbytes: usize| text.get(b64_len(nbytes).wrapping_sub(1)) == Some(&b'=');
        match self.compressor {
            Compressor::None => {
                if padded_at(hs) {
                    self.bytes(Src::B64(text), what)
                } else {
                    self.bytes(Src::Joint(text), what)
                }
            }
            _ => {
                // The first 3 header values (a multiple of 3 bytes) decode alike either way.
                let first = b64_decode(text.get(..4 * hs).unwrap_or(text), what)?;
                if first.len() < 3 * hs {
                    return Err(malformed(format!("{what}: truncated compression header")));
                }
                let nb = self.uint(&first[..hs]);
                let hlen = nb.saturating_add(3).saturating_mul(hs as u64);
                if !hlen.is_multiple_of(3) {
                    let hlen = usize::try_from(hlen).unwrap_or(usize::MAX);
                    if padded_at(hlen) {
                        self.bytes(Src::B64(text), what)
                    } else {
                        self.bytes(Src::Joint(text), what)
                    }
                } else {
                    self.bytes(Src::B64(text), what)
                        .or_else(|e| self.bytes(Src::Joint(text), what).map_err(|_| e))
                }
            }
        }
    }
}

fn floats<const N: usize>(s: Option<&str>, what: &str) -> Res<Option<[f64; N]>> {
    let Some(s) = s else { return Ok(None) };
    let v: Vec<f64> = s
        .split_ascii_whitespace()
        .map(|t| parse_number(t.as_bytes(), what))
        .collect::<Res<_>>()?;
    v.try_into()
        .map(Some)
        .map_err(|_| malformed(format!("{what}: expected {N} numbers")))
}

fn extent(s: Option<&str>, what: &str) -> Res<[i64; 6]> {
    let s = s.ok_or_else(|| malformed(format!("missing {what}")))?;
    let v: Vec<i64> = s
        .split_ascii_whitespace()
        .map(|t| t.parse::<i64>())
        .collect::<Result<_, _>>()
        .map_err(|_| malformed(format!("{what}: not integers")))?;
    let e: [i64; 6] = v
        .try_into()
        .map_err(|_| malformed(format!("{what}: expected 6 integers")))?;
    if e.iter().any(|x| x.unsigned_abs() > 1 << 40) {
        return Err(malformed(format!("{what}: implausible extent {e:?}")));
    }
    point_dims(&e)?;
    Ok(e)
}

fn direction(s: Option<&str>) -> Res<Option<[[f64; 3]; 3]>> {
    Ok(floats::<9>(s, "Direction")?
        .map(|d| [[d[0], d[1], d[2]], [d[3], d[4], d[5]], [d[6], d[7], d[8]]]))
}

fn header_ctx<'a>(b: &'a [u8], doc: &Doc) -> Res<(Ctx<'a>, String)> {
    let root = doc
        .tags
        .first()
        .filter(|t| t.name == "VTKFile")
        .ok_or_else(|| LoadErrorKind::NotVtk("XML without a <VTKFile> root element".into()))?;
    let header = match root.get("header_type").unwrap_or("UInt32") {
        "UInt32" => 4,
        "UInt64" => 8,
        other => return Err(malformed(format!("header_type '{other}'"))),
    };
    let big_endian = match root.get("byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => false,
        "BigEndian" => true,
        other => return Err(malformed(format!("byte_order '{other}'"))),
    };
    let compressor = match root.get("compressor").unwrap_or("") {
        "" => Compressor::None,
        "vtkZLibDataCompressor" => Compressor::Zlib,
        "vtkLZ4DataCompressor" => Compressor::Lz4,
        "vtkLZMADataCompressor" => Compressor::Lzma,
        other => {
            return Err(LoadErrorKind::UnsupportedDataset(format!(
                "compressor '{other}'"
            )));
        }
    };
    let ty = root
        .get("type")
        .ok_or_else(|| malformed("<VTKFile> without a type"))?
        .to_string();
    Ok((
        Ctx {
            b,
            header,
            big_endian,
            compressor,
            appended: doc.appended,
        },
        ty,
    ))
}

/// Read an XML file.
pub(crate) fn read(path: &Path, bytes: &[u8], opts: &ReadOptions) -> Res<TensorField> {
    let doc = tokenize(bytes)?;
    let (ctx, ty) = header_ctx(bytes, &doc)?;
    if ty == "PImageData" {
        return read_pvti(path, &doc, opts);
    }
    let parsed = parse_serial(&ctx, &doc, &ty)?;
    assemble(parsed, opts)
}

fn count_attr(t: &Tag, k: &str) -> Res<usize> {
    match t.get(k) {
        None => Ok(0),
        Some(v) => v
            .trim()
            .parse()
            .map_err(|_| malformed(format!("<{}> {k}='{v}' is not a count", t.name))),
    }
}

/// Rows of one piece's array that go, in order, into the merged array: (piece, first row, rows).
type Segments = Vec<(usize, usize, usize)>;

fn parse_serial<'a>(ctx: &'a Ctx<'a>, doc: &'a Doc, ty: &str) -> Res<Parsed<'a>> {
    let (kind, format) = match ty {
        "ImageData" => (DatasetKind::ImageData, "vti"),
        "RectilinearGrid" => (DatasetKind::RectilinearGrid, "vtr"),
        "StructuredGrid" => (DatasetKind::StructuredGrid, "vts"),
        "UnstructuredGrid" => (DatasetKind::UnstructuredGrid, "vtu"),
        "PolyData" => (DatasetKind::PolyData, "vtp"),
        other => {
            return Err(LoadErrorKind::UnsupportedDataset(format!(
                "XML dataset type '{other}'"
            )));
        }
    };
    let ds = doc
        .tags
        .iter()
        .find(|t| t.name == ty)
        .ok_or_else(|| malformed(format!("no <{ty}> element")))?;
    // Each piece's tags: from its <Piece> to the next one (tags are in document order).
    let starts: Vec<usize> = doc
        .tags
        .iter()
        .enumerate()
        .filter(|(_, t)| t.name == "Piece" && t.parent() == ty)
        .map(|(i, _)| i)
        .collect();
    if starts.is_empty() {
        return Err(malformed(format!("<{ty}> has no <Piece>")));
    }
    let structured = matches!(
        kind,
        DatasetKind::ImageData | DatasetKind::RectilinearGrid | DatasetKind::StructuredGrid
    );
    if structured && starts.len() > 1 {
        return Err(LoadErrorKind::UnsupportedDataset(format!(
            "{} pieces in one serial {ty} file",
            starts.len()
        )));
    }
    let ranges: Vec<(usize, usize)> = starts
        .iter()
        .enumerate()
        .map(|(k, &s)| (s, starts.get(k + 1).copied().unwrap_or(doc.tags.len())))
        .collect();
    let slices: Vec<&'a [Tag]> = ranges.iter().map(|&(s, e)| &doc.tags[s + 1..e]).collect();
    let slices2 = slices.clone();
    let arrays_in = move |k: usize, section: &str| -> Vec<&'a Tag> {
        slices[k]
            .iter()
            .filter(|t| t.name == "DataArray" && t.parent() == section)
            .collect()
    };
    let section = move |k: usize, name: &str| slices2[k].iter().find(|t| t.name == name);
    let piece = &doc.tags[starts[0]];

    let mut point_segments: Segments = Vec::new();
    let mut cell_segments: Segments = Vec::new();
    let geometry = match kind {
        DatasetKind::ImageData => Geometry::Image {
            extent: extent(piece.get("Extent"), "Piece Extent")?,
            origin: floats::<3>(ds.get("Origin"), "Origin")?.unwrap_or([0.0; 3]),
            spacing: floats::<3>(ds.get("Spacing"), "Spacing")?.unwrap_or([1.0; 3]),
            direction: direction(ds.get("Direction"))?,
        },
        DatasetKind::RectilinearGrid => {
            let e = extent(piece.get("Extent"), "Piece Extent")?;
            let d = point_dims(&e)?;
            let c = arrays_in(0, "Coordinates");
            if c.len() != 3 {
                return Err(malformed(format!(
                    "<Coordinates> has {} arrays, not 3",
                    c.len()
                )));
            }
            let mut coords: [Vec<f64>; 3] = Default::default();
            for a in 0..3 {
                let axis = ["x", "y", "z"][a];
                coords[a] = ctx.values(c[a], &format!("{axis} coordinates"))?;
                if coords[a].len() != d[a] {
                    return Err(malformed(format!(
                        "{axis} coordinates: {} values for extent {e:?}",
                        coords[a].len()
                    )));
                }
            }
            Geometry::Rectilinear { coords }
        }
        DatasetKind::StructuredGrid => {
            let points = piece_points(ctx, &arrays_in(0, "Points"))?;
            let d = point_dims(&extent(piece.get("Extent"), "Piece Extent")?)?;
            if d[0].checked_mul(d[1]).and_then(|v| v.checked_mul(d[2])) != Some(points.len()) {
                return Err(malformed(format!(
                    "{} points for point dimensions {d:?}",
                    points.len()
                )));
            }
            Geometry::Points {
                points,
                dims: Some(d),
                cells: None,
            }
        }
        DatasetKind::UnstructuredGrid | DatasetKind::PolyData => {
            let mut points: Vec<[f64; 3]> = Vec::new();
            // Unstructured: one category; polydata: verts, lines, polys, strips, each gathered
            // over all pieces (the order of VTK's merged output).
            let ncat = if kind == DatasetKind::PolyData { 4 } else { 1 };
            let mut cats: Vec<Vec<(usize, usize, Cells)>> = vec![Vec::new(); ncat];
            for (k, &start) in starts.iter().enumerate() {
                let p = &doc.tags[start];
                let pts = piece_points(ctx, &arrays_in(k, "Points"))?;
                let declared = count_attr(p, "NumberOfPoints")?;
                if declared != pts.len() {
                    return Err(malformed(format!(
                        "piece {k}: NumberOfPoints={declared} but <Points> holds {}",
                        pts.len()
                    )));
                }
                let base = points.len();
                point_segments.push((k, 0, pts.len()));
                points.extend_from_slice(&pts);
                let secs: &[(&str, &str)] = if kind == DatasetKind::PolyData {
                    &[
                        ("Verts", "NumberOfVerts"),
                        ("Lines", "NumberOfLines"),
                        ("Polys", "NumberOfPolys"),
                        ("Strips", "NumberOfStrips"),
                    ]
                } else {
                    &[("Cells", "NumberOfCells")]
                };
                let mut row = 0;
                for (cat, (sec, attr)) in secs.iter().enumerate() {
                    let mut c = match section(k, sec) {
                        None => Cells {
                            offsets: vec![0],
                            ..Cells::default()
                        },
                        Some(_) => read_cells(ctx, &arrays_in(k, sec), sec, pts.len(), ncat == 1)?,
                    };
                    let declared = count_attr(p, attr)?;
                    if c.len() != declared {
                        return Err(malformed(format!(
                            "piece {k}: {attr}={declared} but <{sec}> holds {}",
                            c.len()
                        )));
                    }
                    for id in &mut c.conn {
                        *id += base;
                    }
                    let n = c.len();
                    cats[cat].push((k, row, c));
                    row += n;
                }
            }
            let mut all = Cells {
                offsets: vec![0],
                ..Cells::default()
            };
            for (cat, list) in cats.into_iter().enumerate() {
                for (k, row, c) in list {
                    cell_segments.push((k, row, c.len()));
                    all.append(c, (ncat == 4).then_some(cat));
                }
            }
            Geometry::Points {
                points,
                dims: None,
                cells: Some(all),
            }
        }
    };
    if structured {
        point_segments = vec![(0, 0, usize::MAX)];
        cell_segments = vec![(0, 0, usize::MAX)];
    }

    // Arrays, as declared in the first piece.
    let mut arrays = Vec::new();
    for (sec, loc) in [("PointData", Location::Point), ("CellData", Location::Cell)] {
        let active = section(0, sec)
            .and_then(|s| s.get("Tensors"))
            .map(str::to_string);
        for t in arrays_in(0, sec) {
            let name = t.get("Name").unwrap_or("").to_string();
            let ncomp = count_attr(t, "NumberOfComponents")?.max(1);
            let declared = t
                .get("NumberOfTuples")
                .map(|_| count_attr(t, "NumberOfTuples"))
                .transpose()?;
            arrays.push(ArrayDesc {
                active: active.as_deref() == Some(name.as_str()),
                name,
                ncomp,
                ntuples: declared,
                location: Some(loc),
            });
        }
    }
    let descs = arrays.clone();
    let npieces = starts.len();
    Ok(Parsed {
        format,
        kind,
        geometry,
        arrays,
        load: Box::new(move |i| {
            let d = &descs[i];
            let (sec, segments) = match d.location {
                Some(Location::Cell) => ("CellData", &cell_segments),
                _ => ("PointData", &point_segments),
            };
            let what = format!("array '{}'", d.name);
            let mut per_piece = Vec::with_capacity(npieces);
            for k in 0..npieces {
                let t = arrays_in(k, sec)
                    .into_iter()
                    .find(|t| t.get("Name").unwrap_or("") == d.name)
                    .ok_or_else(|| malformed(format!("piece {k} has no {what}")))?;
                per_piece.push(ctx.values(t, &what)?);
            }
            if npieces == 1 && segments.len() <= 1 {
                return Ok(per_piece.pop().unwrap_or_default());
            }
            let nc = d.ncomp;
            let mut out = Vec::new();
            for &(k, row, n) in segments {
                let v = &per_piece[k];
                let rows = v.get(row * nc..(row + n) * nc).ok_or_else(|| {
                    malformed(format!(
                        "piece {k}: {what} has {} tuples, fewer than its {}s",
                        v.len() / nc,
                        sec.trim_end_matches("Data").to_lowercase()
                    ))
                })?;
                out.extend_from_slice(rows);
            }
            for (k, v) in per_piece.iter().enumerate() {
                let used: usize = segments.iter().filter(|s| s.0 == k).map(|s| s.2).sum();
                if v.len() != used * nc {
                    return Err(malformed(format!(
                        "piece {k}: {what} has {} tuples, expected {used}",
                        v.len() / nc
                    )));
                }
            }
            Ok(out)
        }),
    })
}

fn piece_points(ctx: &Ctx, arrays: &[&Tag]) -> Res<Vec<[f64; 3]>> {
    let t = arrays
        .first()
        .ok_or_else(|| malformed("no <Points> array"))?;
    let v = ctx.values(t, "Points")?;
    if v.len() % 3 != 0 {
        return Err(malformed("Points: not a multiple of 3 values"));
    }
    Ok(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Connectivity and offsets (and types for unstructured grids) of one cell section.
fn read_cells(ctx: &Ctx, arr: &[&Tag], sec: &str, npoints: usize, with_types: bool) -> Res<Cells> {
    let by_name = |nm: &str| arr.iter().find(|t| t.get("Name") == Some(nm));
    let (Some(conn), Some(off)) = (by_name("connectivity"), by_name("offsets")) else {
        return Ok(Cells {
            offsets: vec![0],
            ..Cells::default()
        });
    };
    let conn = ctx.values(conn, &format!("{sec} connectivity"))?;
    let conn = to_indices(&conn, "point id", npoints)?;
    let off = ctx.values(off, &format!("{sec} offsets"))?;
    let off = to_indices(&off, "cell offset", conn.len())?;
    let mut c = Cells::from_offsets(off, conn)?;
    if with_types {
        let t = by_name("types").ok_or_else(|| malformed("<Cells> without types"))?;
        let t = ctx.values(t, "cell types")?;
        if t.len() != c.len() {
            return Err(malformed(format!(
                "{} cell types for {} cells",
                t.len(),
                c.len()
            )));
        }
        c.types = t.iter().map(|&x| x.clamp(0.0, 255.0) as u8).collect();
    }
    Ok(c)
}

/// Read a `.pvti` and merge its pieces into one field in whole-extent order.
fn read_pvti(path: &Path, doc: &Doc, opts: &ReadOptions) -> Res<TensorField> {
    let ds = doc
        .tags
        .iter()
        .find(|t| t.name == "PImageData")
        .ok_or_else(|| malformed("no <PImageData> element"))?;
    let whole = extent(ds.get("WholeExtent"), "WholeExtent")?;
    let origin = floats::<3>(ds.get("Origin"), "Origin")?.unwrap_or([0.0; 3]);
    let spacing = floats::<3>(ds.get("Spacing"), "Spacing")?.unwrap_or([1.0; 3]);
    let dir = direction(ds.get("Direction"))?;
    let mut arrays = Vec::new();
    for (sec, loc) in [
        ("PPointData", Location::Point),
        ("PCellData", Location::Cell),
    ] {
        let active = doc
            .tags
            .iter()
            .find(|t| t.name == sec)
            .and_then(|s| s.get("Tensors"));
        for t in doc
            .tags
            .iter()
            .filter(|t| t.name == "PDataArray" && t.parent() == sec)
        {
            let name = t.get("Name").unwrap_or("").to_string();
            arrays.push(ArrayDesc {
                active: active == Some(name.as_str()),
                ncomp: count_attr(t, "NumberOfComponents")?.max(1),
                name,
                ntuples: None,
                location: Some(loc),
            });
        }
    }
    let idx = pick(&arrays, opts.array.as_deref())?;
    let want = arrays[idx].clone();
    let loc = want.location.unwrap_or(Location::Point);
    let ncomp = want.ncomp;
    let lattice = |e: &[i64; 6]| -> [i64; 6] {
        // Cell extents: one fewer per non-flat axis.
        match loc {
            Location::Point => *e,
            Location::Cell => {
                let mut c = *e;
                for a in 0..3 {
                    if c[2 * a + 1] > c[2 * a] {
                        c[2 * a + 1] -= 1;
                    }
                }
                c
            }
        }
    };
    let wl = lattice(&whole);
    let wd = point_dims(&wl)?;
    let dir_path = path.parent().unwrap_or(Path::new("."));
    let mut pieces: Vec<([i64; 6], Vec<f64>)> = Vec::new();
    let mut total = 0usize;
    for t in doc.tags.iter().filter(|t| t.name == "Piece") {
        let src = t
            .get("Source")
            .ok_or_else(|| malformed("<Piece> without Source"))?;
        let ppath = dir_path.join(src);
        let piece_err = |k: LoadErrorKind| malformed(format!("piece '{src}': {k}"));
        let bytes = read_bytes(&ppath).map_err(piece_err)?;
        let pdoc = tokenize(&bytes).map_err(piece_err)?;
        let (pctx, pty) = header_ctx(&bytes, &pdoc).map_err(piece_err)?;
        if pty != "ImageData" {
            return Err(piece_err(LoadErrorKind::UnsupportedDataset(format!(
                "piece type '{pty}', expected ImageData"
            ))));
        }
        let mut parsed = parse_serial(&pctx, &pdoc, &pty).map_err(piece_err)?;
        let Geometry::Image { extent: pe, .. } = parsed.geometry else {
            return Err(piece_err(malformed("not image data")));
        };
        let i = parsed
            .arrays
            .iter()
            .position(|a| a.name == want.name && a.location == want.location)
            .ok_or_else(|| {
                piece_err(LoadErrorKind::ArrayNotFound {
                    name: want.name.clone(),
                    available: parsed
                        .arrays
                        .iter()
                        .map(|a| a.name.clone())
                        .collect::<Vec<_>>()
                        .join(", "),
                })
            })?;
        if parsed.arrays[i].ncomp != ncomp {
            return Err(piece_err(LoadErrorKind::ComponentCount {
                name: want.name.clone(),
                components: parsed.arrays[i].ncomp,
            }));
        }
        let v = (parsed.load)(i).map_err(piece_err)?;
        let pl = lattice(&pe);
        for a in 0..3 {
            if pl[2 * a] < wl[2 * a] || pl[2 * a + 1] > wl[2 * a + 1] {
                return Err(piece_err(malformed(format!(
                    "extent {pe:?} is outside the whole extent {whole:?}"
                ))));
            }
        }
        let pd = point_dims(&pl)?;
        let n = pd[0] * pd[1] * pd[2];
        if v.len() != n * ncomp {
            return Err(piece_err(LoadErrorKind::TupleCount {
                name: want.name.clone(),
                found: v.len() / ncomp,
                expected: n,
                location: loc.as_str(),
            }));
        }
        total += n;
        pieces.push((pl, v));
    }
    let wn = wd[0]
        .checked_mul(wd[1])
        .and_then(|v| v.checked_mul(wd[2]))
        .ok_or_else(|| malformed("WholeExtent overflows"))?;
    if total < wn {
        return Err(malformed(format!(
            "the pieces hold {total} {}s but the whole extent has {wn}",
            loc.as_str()
        )));
    }
    let mut merged = try_vec::<f64>(wn * ncomp)?;
    merged.resize(wn * ncomp, f64::NAN);
    let mut covered = vec![false; wn];
    for (pl, v) in &pieces {
        let pd = point_dims(pl)?;
        let mut s = 0;
        for k in 0..pd[2] {
            for j in 0..pd[1] {
                for i in 0..pd[0] {
                    let wi = (pl[0] - wl[0]) as usize + i;
                    let wj = (pl[2] - wl[2]) as usize + j;
                    let wk = (pl[4] - wl[4]) as usize + k;
                    let w = wi + wd[0] * (wj + wd[1] * wk);
                    merged[w * ncomp..(w + 1) * ncomp]
                        .copy_from_slice(&v[s * ncomp..(s + 1) * ncomp]);
                    covered[w] = true;
                    s += 1;
                }
            }
        }
    }
    if let Some(gap) = covered.iter().position(|c| !c) {
        return Err(malformed(format!(
            "the pieces do not cover the whole extent ({} {gap} missing)",
            loc.as_str()
        )));
    }
    let mut merged = Some(merged);
    let parsed = Parsed {
        format: "pvti",
        kind: DatasetKind::ImageData,
        geometry: Geometry::Image {
            extent: whole,
            origin,
            spacing,
            direction: dir,
        },
        arrays,
        load: Box::new(move |_| merged.take().ok_or_else(|| malformed("merged twice"))),
    };
    assemble(parsed, opts)
}
