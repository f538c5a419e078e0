//! Opening input files: regular files only, read whole with a bound.
//!
//! Every reader goes through [`read_regular_file`]. A FIFO would block the reader forever (or
//! until some other process writes), and `/dev/zero` or `/dev/urandom` never end; neither can be
//! a tensor field. So the path is checked before opening (following symlinks, as opening does),
//! opened without blocking, checked again through the open handle (the path may have been
//! replaced in between), and read no further than the size that handle reports.

use std::fs::File;
use std::io::{ErrorKind, Read};
use std::path::Path;

use crate::error::LoadErrorKind;
use crate::files::special_kind;

fn io_error(e: std::io::Error) -> LoadErrorKind {
    if e.kind() == ErrorKind::NotFound {
        LoadErrorKind::Missing
    } else {
        LoadErrorKind::Io(e)
    }
}

/// Open `path` for reading without ever blocking on it: `O_NONBLOCK` makes opening a FIFO
/// return at once (it is then refused); it has no effect on regular files.
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    let mut o = std::fs::OpenOptions::new();
    o.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        o.custom_flags(libc::O_NONBLOCK);
    }
    o.open(path)
}

/// The whole content of the regular file at `path` (symlinks followed).
///
/// Errors: [`LoadErrorKind::Missing`], [`LoadErrorKind::NotRegularFile`] for FIFOs, devices,
/// sockets and directories, [`LoadErrorKind::Io`] otherwise. Never reads more than the size the
/// open file reports, and allocates that size with `try_reserve` (an error, not an abort, if it
/// cannot be had).
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, LoadErrorKind> {
    let before = std::fs::metadata(path).map_err(io_error)?;
    if let Some(kind) = special_kind(&before) {
        return Err(LoadErrorKind::NotRegularFile(kind));
    }
    let file = open_nonblocking(path).map_err(io_error)?;
    let meta = file.metadata().map_err(io_error)?;
    if let Some(kind) = special_kind(&meta) {
        return Err(LoadErrorKind::NotRegularFile(kind));
    }
    let len = meta.len();
    let cap = usize::try_from(len)
        .map_err(|_| LoadErrorKind::Other(format!("the file is too large ({len} bytes)")))?;
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(cap).map_err(|_| {
        LoadErrorKind::Other(format!("cannot allocate {len} bytes to read the file into"))
    })?;
    // A file that grows while it is read is cut at the size it had when opened.
    file.take(len)
        .read_to_end(&mut bytes)
        .map_err(LoadErrorKind::Io)?;
    Ok(bytes)
}

/// Deflate cannot expand data more than about 1032 times, so a gzip stream of `n` bytes
/// never holds more than this many: a header asking for more is refused before inflating.
const DEFLATE_MAX_RATIO: u64 = 1032;

/// The first `want` bytes that the gzip data `gz` holds (all its members, as `gzip -d` reads
/// them), fewer if it holds fewer.
///
/// Memory grows only with the bytes actually inflated, and `want` beyond what `gz` could
/// possibly expand to is an error before anything is inflated; `what` names the data in it.
pub fn gunzip_prefix(gz: &[u8], want: u64, what: &str) -> Result<Vec<u8>, LoadErrorKind> {
    let most = (gz.len() as u64).saturating_mul(DEFLATE_MAX_RATIO);
    if want > most {
        return Err(LoadErrorKind::Malformed(format!(
            "{what} needs {want} bytes, more than {} gzip-compressed bytes can hold",
            gz.len()
        )));
    }
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(gz)
        .take(want)
        .read_to_end(&mut out)
        .map_err(|e| {
            LoadErrorKind::Malformed(format!("{what}: gzip data is corrupt or truncated ({e})"))
        })?;
    Ok(out)
}

/// Device and inode of the file `path` names (symlinks followed), to tell when two names are
/// one file; `None` where the platform does not say or the file cannot be inspected.
pub(crate) fn file_identity(path: &Path) -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_regular_file_through_a_symlink() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.vtk");
        std::fs::write(&p, b"hello").unwrap();
        assert_eq!(read_regular_file(&p).unwrap(), b"hello");
        #[cfg(unix)]
        {
            let l = dir.path().join("link.vtk");
            std::os::unix::fs::symlink(&p, &l).unwrap();
            assert_eq!(read_regular_file(&l).unwrap(), b"hello");
        }
    }

    #[test]
    fn refuses_directories_and_reports_missing() {
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(
            read_regular_file(dir.path()),
            Err(LoadErrorKind::NotRegularFile("a directory"))
        ));
        assert!(matches!(
            read_regular_file(&dir.path().join("none")),
            Err(LoadErrorKind::Missing)
        ));
    }

    #[cfg(unix)]
    #[test]
    fn refuses_devices() {
        for dev in ["/dev/zero", "/dev/urandom", "/dev/null"] {
            if Path::new(dev).exists() {
                assert!(
                    matches!(
                        read_regular_file(Path::new(dev)),
                        Err(LoadErrorKind::NotRegularFile("a character device"))
                    ),
                    "{dev}"
                );
            }
        }
    }
}
