//! The readers' last line of defence: a panic inside one becomes an error naming the file.

use std::path::Path;

use crate::error::{LoadError, LoadErrorKind, escape_for_error};

/// `f()` reading the file at `path`: its error, or a panic inside it, as an error naming `path`.
pub(crate) fn guarded<T>(
    path: &Path,
    f: impl FnOnce() -> Result<T, LoadErrorKind>,
) -> Result<T, LoadError> {
    catch_panics(path, || f().map_err(|kind| LoadError::new(path, kind)))
}

/// `f()`, with a panic inside it turned into an error naming `path` (readers of several files
/// name the one at fault themselves).
pub(crate) fn catch_panics<T>(
    path: &Path,
    f: impl FnOnce() -> Result<T, LoadError>,
) -> Result<T, LoadError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|payload| {
        let msg = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Err(LoadError::new(
            path,
            LoadErrorKind::Other(format!(
                "internal reader error (please report this file): {}",
                escape_for_error(msg)
            )),
        ))
    })
}
