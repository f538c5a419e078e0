//! Scalar types and byte decoding shared by the legacy and XML readers.

use super::malformed::{Res, malformed};
use crate::error::escape_for_error as esc;

pub(crate) use crate::field::number::{Scalar, decode_into, try_vec};

impl Scalar {
    /// XML `type` attribute (VTK ≥ 5 names and the old `Int`/`Float` ones are not used by VTK).
    pub fn from_xml(s: &str) -> Option<Scalar> {
        Some(match s {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Round a value parsed from text to what an array of this type holds.
    pub fn round_text(self, v: f64) -> f64 {
        match self {
            Scalar::F32 => v as f32 as f64,
            _ => v,
        }
    }
}

/// Convert decoded index values (offsets, connectivity) to `usize`, rejecting negatives,
/// fractions and values above `limit`.
pub(crate) fn to_indices(v: &[f64], what: &str, limit: usize) -> Res<Vec<usize>> {
    let mut out = try_vec(v.len())?;
    for &x in v {
        if !(x >= 0.0 && x.fract() == 0.0 && x <= limit as f64) {
            return Err(malformed(format!("invalid {what} value {x}")));
        }
        out.push(x as usize);
    }
    Ok(out)
}

/// Parse whitespace-separated numbers; exactly `n` are expected.
pub(crate) fn parse_ascii(text: &[u8], n: usize, ty: Scalar, what: &str) -> Res<Vec<f64>> {
    // Every number needs at least one character and one separator.
    if n > text.len() / 2 + 1 {
        return Err(malformed(format!(
            "{what}: {n} values declared but the data holds at most {}",
            text.len() / 2 + 1
        )));
    }
    let mut out = try_vec(n)?;
    for tok in text
        .split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
    {
        if out.len() == n {
            return Err(malformed(format!("{what}: more than {n} values")));
        }
        out.push(ty.round_text(parse_number(tok, what)?));
    }
    if out.len() != n {
        return Err(malformed(format!(
            "{what}: {} values, expected {n}",
            out.len()
        )));
    }
    Ok(out)
}

pub(crate) fn parse_number(tok: &[u8], what: &str) -> Res<f64> {
    std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .ok_or_else(|| malformed(format!("{what}: '{}' is not a number", esc(tok))))
}
