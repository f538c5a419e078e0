//! The numeric element types the file formats store (VTK's `type`, NRRD's `type`, NIfTI's
//! `datatype`) and reading them from bytes: one vocabulary for every reader. Each format names
//! the types its own way, next to its reader.

/// A numeric element type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

macro_rules! each_type {
    ($ty:expr, $go:ident) => {
        match $ty {
            Scalar::I8 => $go!(i8, 1),
            Scalar::U8 => $go!(u8, 1),
            Scalar::I16 => $go!(i16, 2),
            Scalar::U16 => $go!(u16, 2),
            Scalar::I32 => $go!(i32, 4),
            Scalar::U32 => $go!(u32, 4),
            Scalar::I64 => $go!(i64, 8),
            Scalar::U64 => $go!(u64, 8),
            Scalar::F32 => $go!(f32, 4),
            Scalar::F64 => $go!(f64, 8),
        }
    };
}

impl Scalar {
    /// Bytes per element.
    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    /// Whether the type's values (and their scaled values, to float32's relative precision) are
    /// held by float32: what the file gives is kept at the file's precision, and float32 is
    /// enough for every type up to 16 bits (a field of int8 values kept as float64 cost 8x its
    /// bytes).
    pub fn fits_f32(self) -> bool {
        matches!(
            self,
            Scalar::I8 | Scalar::U8 | Scalar::I16 | Scalar::U16 | Scalar::F32
        )
    }

    /// One element from the first [`Self::size`] bytes of `b` (zero if `b` is shorter), as
    /// f64; 64-bit integers beyond 2^53 lose their last bits.
    pub fn read(self, b: &[u8], big_endian: bool) -> f64 {
        macro_rules! one {
            ($t:ty, $n:expr) => {{
                let a: [u8; $n] = b
                    .get(..$n)
                    .and_then(|s| s.try_into().ok())
                    .unwrap_or_default();
                (if big_endian {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }};
        }
        each_type!(self, one)
    }
}

/// A vector with room for `n` elements, or an error instead of an allocation failure (a file
/// whose header asks for more than the machine has gets one clean line, not an abort).
pub(crate) fn try_vec<T>(n: usize) -> Result<Vec<T>, crate::error::LoadErrorKind> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        crate::error::LoadErrorKind::Malformed(format!("cannot allocate {n} values"))
    })?;
    Ok(v)
}

/// Append the values in `bytes` (a whole number of elements) to `out`, converting to f64.
pub(crate) fn decode_into(bytes: &[u8], ty: Scalar, big_endian: bool, out: &mut Vec<f64>) {
    macro_rules! all {
        ($t:ty, $n:expr) => {
            out.extend(bytes.chunks_exact($n).map(|c| {
                let a: [u8; $n] = c.try_into().expect("chunk size");
                (if big_endian {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }))
        };
    }
    each_type!(ty, all)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_element_and_many_read_alike_in_both_byte_orders() {
        let cases: [(Scalar, Vec<u8>, f64); 4] = [
            (Scalar::I16, (-300i16).to_be_bytes().to_vec(), -300.0),
            (Scalar::U32, 4_000_000_000u32.to_be_bytes().to_vec(), 4e9),
            (Scalar::F32, 1.5f32.to_be_bytes().to_vec(), 1.5),
            (Scalar::F64, (-2.25f64).to_be_bytes().to_vec(), -2.25),
        ];
        for (ty, be, want) in cases {
            assert_eq!(ty.size(), be.len());
            assert_eq!(ty.read(&be, true), want);
            let le: Vec<u8> = be.iter().rev().copied().collect();
            assert_eq!(ty.read(&le, false), want);
            let mut out = Vec::new();
            decode_into(&[be.clone(), be].concat(), ty, true, &mut out);
            assert_eq!(out, [want, want]);
        }
        assert_eq!(Scalar::I8.read(&[0xff], false), -1.0);
        assert_eq!(Scalar::U64.read(&[1], false), 0.0, "too short: zero");
    }
}
