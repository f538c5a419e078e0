//! VTK reading: legacy `.vtk` (ASCII and binary, 4.2 and 5.1), XML `.vti/.vtr/.vts/.vtu/.vtp`
//! and parallel `.pvti`, into a [`TensorField`].
//!
//! The parsers here are our own, strict and allocation-safe: every count is checked against the
//! bytes actually present before anything is allocated, and only the picked tensor array (plus
//! the geometry) is decoded. `vtkio` 0.7.0-rc2 is not used for reading, because on files VTK 9.1
//! itself writes it (`tests/readers/vtkio.rs` checks each of these, and that vtkio agrees
//! with us on every other file):
//! - rejects legacy `TENSORS6` with `Parse(Tag)` (12 of our 40 legacy files), and legacy FIELD
//!   data holding a string array;
//! - rejects XML point/cell data with a `<Array type="String">` among the data arrays
//!   ("duplicate field `DataArray`");
//! - rejects XML appended *raw* data ("unknown variant `raw`"; 20 of 52 XML files, and a `.pvti`
//!   whose pieces use it);
//! - panics on compressed `.vtp` files (the empty `Verts`/`Lines`/`Strips` sections);
//! - drops attributes it fails to decode and still returns `Ok` (`filter_map(.. .ok())` in its
//!   XML import);
//! - concatenates `.pvti` pieces instead of placing them in the whole extent (shared points
//!   appear twice);
//! - ignores the image `Direction` and keeps origin/spacing as f32;
//! - trusts declared counts when allocating.
//!
//! Working around all of that would have needed a pre-parser about as large as a parser.
//!
//! Layout: `legacy` and `xml` turn bytes into a `Parsed` dataset (`dataset`: geometry, cells,
//! array descriptors and a way to load one array); `assemble` picks the tensor array, checks its
//! component and tuple counts and computes the positions (points, or cell centres as VTK's
//! vtkCellCenters does); `binary` decodes numbers shared by both readers. `family` tells the
//! two kinds of file apart by their first bytes, and `malformed` is how every parser says what
//! is wrong, below them all.

mod assemble;
mod binary;
mod dataset;
mod family;
mod legacy;
mod malformed;
mod scalars;
mod xml;

use std::path::Path;

use super::guard::guarded;
use super::inputs::Inputs;
pub use super::options::ReadOptions;
use super::tensor_field::TensorField;
use crate::error::LoadError;
use assemble::assemble;
use family::{Family, family};
use malformed::Res;
pub(crate) use scalars::parse_scalar_bytes;

/// Read a tensor field from a VTK file (format detected from the content).
///
/// Only regular files are read (symlinks followed; FIFOs, devices and directories are refused),
/// never past the size they had when opened. Never panics on bad input: every count is
/// validated before allocation, and as a last line of defence a panic inside the reader is
/// turned into a [`LoadErrorKind::Other`].
///
/// [`LoadErrorKind::Other`]: crate::error::LoadErrorKind::Other
pub fn read_field(path: &Path, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    read_field_from(&Inputs::file_system(), path, opts)
}

/// [`read_field`] of the file `path` among `inputs` (its `.pvti` pieces too).
pub fn read_field_from(
    inputs: &Inputs,
    path: &Path,
    opts: &ReadOptions,
) -> Result<TensorField, LoadError> {
    guarded(path, || {
        let bytes = inputs.read(path)?;
        parse_bytes(inputs, path, &bytes, opts)
    })
}

/// Read a tensor field from bytes already in memory, as [`read_field`] would from a file
/// holding them. `path` only names the data in errors and places `.pvti` pieces (they are
/// looked up beside it); it is not read. The entry point of the fuzz targets (`fuzz/`).
pub fn read_field_bytes(
    path: &Path,
    bytes: &[u8],
    opts: &ReadOptions,
) -> Result<TensorField, LoadError> {
    guarded(path, || {
        parse_bytes(&Inputs::file_system(), path, bytes, opts)
    })
}

fn parse_bytes(inputs: &Inputs, path: &Path, bytes: &[u8], opts: &ReadOptions) -> Res<TensorField> {
    match family(bytes)? {
        Family::Legacy => {
            let parsed = legacy::parse(bytes, opts.array.as_deref())?;
            assemble(parsed, opts)
        }
        Family::Xml => xml::read(inputs, path, bytes, opts),
    }
}
