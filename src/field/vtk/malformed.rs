//! How the VTK parsers report bad input: a result whose error is a [`LoadErrorKind`], and the
//! shorthand for a malformed file.

use crate::error::LoadErrorKind;

pub(super) type Res<T> = Result<T, LoadErrorKind>;

pub(crate) fn malformed(msg: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Malformed(msg.into())
}
