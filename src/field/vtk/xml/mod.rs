//! VTK XML files (`.vti`, `.vtr`, `.vts`, `.vtu`, `.vtp`) and parallel image data (`.pvti`).
//!
//! vtkio 0.7.0-rc2 limitations this replaces: appended *raw* data is rejected (the file is read
//! as text), compressed `.vtp` files panic on the empty `Verts`/`Lines`/`Strips` sections VTK
//! always writes, an array that fails to decode can be dropped without an error, the image
//! `Direction` attribute is ignored, and declared sizes are trusted before allocation. This
//! reader tokenises the XML up to `<AppendedData>` (which may hold raw bytes), then decodes only
//! the arrays it needs: ascii, inline base64, appended base64 or raw; uncompressed or
//! zlib/lz4/lzma blocks; UInt32 or UInt64 headers; either byte order.

//!
//! Layout: `tokenize` (start tags and where appended data begins), `decode` (the encoding the
//! root element states, one DataArray's bytes and values), `attrs` (numbers in attributes),
//! `serial` (one `.vti/.vtr/.vts/.vtu/.vtp` dataset), `pvti` (pieces merged into the whole
//! extent).

mod attrs;
mod decode;
mod pvti;
mod serial;
mod tokenize;

use std::path::Path;

use super::assemble::assemble;
use super::dataset::Parsed;
use super::malformed::Res;
use crate::error::{LoadErrorKind, escape_for_error as esc};
use crate::field::inputs::Inputs;
use crate::field::options::ReadOptions;
use crate::field::tensor_field::TensorField;
use decode::header_ctx;

/// Read an XML file.
pub(crate) fn read(
    inputs: &Inputs,
    path: &Path,
    bytes: &[u8],
    opts: &ReadOptions,
) -> Res<TensorField> {
    let doc = tokenize::tokenize(bytes)?;
    let (ctx, ty) = header_ctx(bytes, &doc)?;
    if ty == "PImageData" {
        return pvti::read_pvti(inputs, path, &doc, opts);
    }
    let parsed = serial::parse_serial(&ctx, &doc, &ty)?;
    assemble(parsed, opts)
}

/// One serial XML dataset, handed to `f` as parsed (its arrays load on demand). Parallel files
/// are refused: their pieces are merged by the tensor reader only.
pub(crate) fn with_serial<T>(bytes: &[u8], f: impl FnOnce(Parsed<'_>) -> Res<T>) -> Res<T> {
    let doc = tokenize::tokenize(bytes)?;
    let (ctx, ty) = header_ctx(bytes, &doc)?;
    if ty.starts_with('P') {
        return Err(LoadErrorKind::UnsupportedDataset(format!(
            "parallel XML file ('{}'); give one of its pieces",
            esc(&ty)
        )));
    }
    f(serial::parse_serial(&ctx, &doc, &ty)?)
}
