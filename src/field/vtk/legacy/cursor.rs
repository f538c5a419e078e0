//! Reading a legacy file: lines, tokens, and counted runs of ASCII or big-endian binary values.

use super::super::binary::{Scalar, decode_into, parse_number, try_vec};
use super::super::malformed::{Res, malformed};
use crate::error::{LoadErrorKind, escape_for_error as esc};

/// Element type of a legacy array; `Bit` is packed in binary files.
#[derive(Debug, Clone, Copy)]
pub(super) enum LType {
    Num(Scalar),
    Bit,
    /// `string` / `utf8_string` (FIELD arrays): skipped, never a tensor.
    Str,
}

pub(super) fn ltype(s: &str) -> Res<LType> {
    Ok(LType::Num(match s.to_ascii_lowercase().as_str() {
        "bit" => return Ok(LType::Bit),
        "string" | "utf8_string" => return Ok(LType::Str),
        "char" | "signed_char" | "vtktypeint8" => Scalar::I8,
        "unsigned_char" | "vtktypeuint8" => Scalar::U8,
        "short" | "vtktypeint16" => Scalar::I16,
        "unsigned_short" | "vtktypeuint16" => Scalar::U16,
        // VTK writes vtkIdType arrays as 32-bit ints in legacy files.
        "int" | "vtkidtype" | "vtktypeint32" => Scalar::I32,
        "unsigned_int" | "vtktypeuint32" => Scalar::U32,
        "long" | "vtktypeint64" => Scalar::I64,
        "unsigned_long" | "vtktypeuint64" => Scalar::U64,
        "float" | "vtktypefloat32" => Scalar::F32,
        "double" | "vtktypefloat64" => Scalar::F64,
        other => {
            return Err(LoadErrorKind::UnsupportedDataset(format!(
                "legacy data type '{}' is not supported",
                esc(other)
            )));
        }
    }))
}

/// Tokens kept from a keyword line (more than any keyword line has).
const MAX_LINE_TOKENS: usize = 16;

pub(super) struct Cursor<'a> {
    pub b: &'a [u8],
    pub pos: usize,
    pub binary: bool,
}

impl<'a> Cursor<'a> {
    pub fn remaining(&self) -> usize {
        self.b.len() - self.pos
    }

    /// The next raw line (without its end-of-line), or None at end of file.
    pub fn raw_line(&mut self) -> Option<&'a [u8]> {
        if self.pos >= self.b.len() {
            return None;
        }
        let rest = &self.b[self.pos..];
        let end = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
        self.pos += (end + 1).min(rest.len());
        let mut line = &rest[..end];
        if line.last() == Some(&b'\r') {
            line = &line[..line.len() - 1];
        }
        Some(line)
    }

    /// Tokens of the next non-blank line, or None at end of file. A last line without its
    /// newline is an error: VTK ends every line, so the file was cut inside it.
    pub fn line(&mut self) -> Res<Option<Vec<&'a str>>> {
        while let Some(l) = self.raw_line() {
            // Keyword lines have at most 10 tokens (DIRECTION); a data line read here by
            // mistake (a corrupted file) must not cost a vector as long as itself.
            let toks: Vec<&[u8]> = l
                .split(|c| c.is_ascii_whitespace())
                .filter(|t| !t.is_empty())
                .take(MAX_LINE_TOKENS)
                .collect();
            if toks.is_empty() {
                continue;
            }
            if self.pos == self.b.len() && self.b.last() != Some(&b'\n') {
                return Err(malformed(format!(
                    "the file ends inside the line '{}' (truncated?)",
                    esc(l)
                )));
            }
            let mut out = Vec::with_capacity(toks.len());
            for t in toks {
                out.push(std::str::from_utf8(t).map_err(|_| {
                    malformed(format!(
                        "unexpected binary data near byte {} where a keyword was expected",
                        self.pos
                    ))
                })?);
            }
            return Ok(Some(out));
        }
        Ok(None)
    }

    pub fn token(&mut self) -> Option<&'a [u8]> {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        (self.pos > start).then(|| &self.b[start..self.pos])
    }

    /// Read `n` values of type `ty`; returns them if `keep`, else skips them.
    pub fn values(&mut self, n: usize, ty: LType, keep: bool, what: &str) -> Res<Option<Vec<f64>>> {
        if let LType::Str = ty {
            self.skip_strings(n, what)?;
            return Ok(None);
        }
        if self.binary {
            let nbytes = match ty {
                LType::Bit => n.div_ceil(8),
                LType::Str => 0,
                LType::Num(s) => n
                    .checked_mul(s.size())
                    .ok_or_else(|| malformed(format!("{what}: {n} values overflow")))?,
            };
            if nbytes > self.remaining() {
                return Err(malformed(format!(
                    "{what}: {n} values need {nbytes} bytes but only {} remain (truncated?)",
                    self.remaining()
                )));
            }
            let bytes = &self.b[self.pos..self.pos + nbytes];
            self.pos += nbytes;
            if !keep {
                return Ok(None);
            }
            let mut out = try_vec(n)?;
            match ty {
                LType::Bit => {
                    out.extend((0..n).map(|i| ((bytes[i / 8] >> (7 - i % 8)) & 1) as f64));
                }
                LType::Num(s) => decode_into(bytes, s, true, &mut out),
                LType::Str => {}
            }
            Ok(Some(out))
        } else {
            if n > self.remaining() / 2 + 1 {
                return Err(malformed(format!(
                    "{what}: {n} values declared but only {} bytes remain (truncated?)",
                    self.remaining()
                )));
            }
            let mut out = if keep { Some(try_vec(n)?) } else { None };
            for _ in 0..n {
                let tok = self.token().ok_or_else(|| {
                    malformed(format!("{what}: file ends before {n} values were read"))
                })?;
                // A number running into the end of the file may have lost digits
                // (1.5927 cut to 1.592): VTK ends every file with a newline.
                if self.pos == self.b.len() {
                    return Err(malformed(format!(
                        "{what}: the file ends inside the number '{}' (truncated?)",
                        esc(tok)
                    )));
                }
                let v = parse_number(tok, what)?;
                if let Some(o) = out.as_mut() {
                    o.push(match ty {
                        LType::Num(s) => s.round_text(v),
                        LType::Bit | LType::Str => v,
                    });
                }
            }
            Ok(out)
        }
    }

    /// Skip `n` strings: one per line in ASCII files; in binary files each has a big-endian
    /// length prefix whose two top bits give its size (11: 1 byte, 10: 2, 01: 4, 00: 8).
    pub fn skip_strings(&mut self, n: usize, what: &str) -> Res<()> {
        let short = || malformed(format!("{what}: file ends inside the strings"));
        if n > self.remaining() {
            return Err(short());
        }
        for _ in 0..n {
            if !self.binary {
                self.raw_line().ok_or_else(short)?;
                continue;
            }
            let first = *self.b.get(self.pos).ok_or_else(short)?;
            let width = match first >> 6 {
                3 => 1,
                2 => 2,
                1 => 4,
                _ => 8,
            };
            let head = self.b.get(self.pos..self.pos + width).ok_or_else(short)?;
            let mut len = (first & 0x3F) as u64;
            for &b in &head[1..] {
                len = (len << 8) | b as u64;
            }
            let end = usize::try_from(len)
                .ok()
                .and_then(|l| (self.pos + width).checked_add(l))
                .filter(|&e| e <= self.b.len())
                .ok_or_else(short)?;
            self.pos = end;
        }
        Ok(())
    }

    /// Skip a METADATA block: lines up to the first blank one.
    pub fn skip_metadata(&mut self) {
        while let Some(l) = self.raw_line() {
            if l.iter().all(|c| c.is_ascii_whitespace()) {
                break;
            }
        }
    }
}

impl Cursor<'_> {
    /// Whether the next non-blank line starts with `kw` (only its first token is looked at).
    pub fn peek_keyword(&mut self, kw: &str) -> bool {
        let save = self.pos;
        let mut r = false;
        while let Some(l) = self.raw_line() {
            if let Some(first) = l.split(|c| c.is_ascii_whitespace()).find(|t| !t.is_empty()) {
                r = first == kw.as_bytes();
                break;
            }
        }
        self.pos = save;
        r
    }
}
