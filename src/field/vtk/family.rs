//! Legacy or XML: the two VTK file families, told apart by their first bytes.

use super::malformed::Res;
use crate::error::LoadErrorKind;

/// The two VTK file families, told apart by their first bytes.
pub(super) enum Family {
    Legacy,
    Xml,
}

pub(super) fn family(bytes: &[u8]) -> Res<Family> {
    let head = &bytes[skip_bom_ws(bytes)..];
    if head.starts_with(b"# vtk DataFile") || head.starts_with(b"# VTK DataFile") {
        Ok(Family::Legacy)
    } else if head.starts_with(b"<") {
        Ok(Family::Xml)
    } else if bytes.is_empty() {
        Err(LoadErrorKind::NotVtk("the file is empty".into()))
    } else {
        Err(LoadErrorKind::NotVtk(
            "neither a legacy VTK header ('# vtk DataFile Version') nor XML".into(),
        ))
    }
}

fn skip_bom_ws(b: &[u8]) -> usize {
    let mut i = if b.starts_with(&[0xEF, 0xBB, 0xBF]) {
        3
    } else {
        0
    };
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}
