//! Where the readers get their bytes, and the record of every file they read.
//!
//! Every reader asks an [`Inputs`] for its files: the file system, or a set of named in-memory
//! buffers (files a browser was handed, data a Python program holds: a `.nhdr` with its
//! detached `.raw`, the six files of an FSL eigen set). A reader never names a place on its
//! own: a file that comes with another is "the file next to it named X" ([`Inputs::next_to`]),
//! which is the same question in a folder and in a set of names.
//!
//! Every file opened is recorded ([`Inputs::paths_read`]), so that a front end can refuse to
//! write an output over any of them: the `.pvti` pieces, a `.nhdr`'s data file, every member of
//! an eigen set, not only the file named on the command line.
//!
//! On the file system only regular files are read. A FIFO would block the reader forever (or
//! until some other process writes), and `/dev/zero` or `/dev/urandom` never end; neither can be
//! a tensor field. So the path is checked before opening (following symlinks, as opening does),
//! opened without blocking, checked again through the open handle (the path may have been
//! replaced in between), and read no further than the size that handle reports.

use std::borrow::Cow;
use std::collections::HashMap;
use std::fs::File;
use std::io::{ErrorKind, Read};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use crate::error::LoadErrorKind;
use crate::files::special_kind;

/// Where files come from: the file system, or buffers by name.
enum Store {
    FileSystem,
    /// Names normalised by [`key`].
    Named(HashMap<PathBuf, Vec<u8>>),
}

/// The files the readers may read, and which of them they did.
pub struct Inputs {
    store: Store,
    read: Mutex<Vec<PathBuf>>,
}

impl Default for Inputs {
    fn default() -> Self {
        Self::file_system()
    }
}

impl std::fmt::Debug for Inputs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("Inputs");
        if let Store::Named(files) = &self.store {
            let mut names: Vec<_> = files.keys().collect();
            names.sort();
            d.field("named", &names);
        }
        d.field("read", &self.paths_read()).finish()
    }
}

/// A name as a set of buffers is looked up by: without `.` components, so that `./d.raw` next
/// to `d.nhdr` is `d.raw`.
fn key(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| *c != Component::CurDir)
        .collect()
}

impl Inputs {
    /// Files on the file system.
    pub fn file_system() -> Self {
        Self {
            store: Store::FileSystem,
            read: Mutex::new(Vec::new()),
        }
    }

    /// Buffers by name (`"dwi.nhdr"`, `"dwi.raw"`, or with folders: `"sub-01/dwi.nii.gz"`); the
    /// file system is never touched.
    pub fn named(files: impl IntoIterator<Item = (String, Vec<u8>)>) -> Self {
        Self {
            store: Store::Named(
                files
                    .into_iter()
                    .map(|(name, bytes)| (key(Path::new(&name)), bytes))
                    .collect(),
            ),
            read: Mutex::new(Vec::new()),
        }
    }

    /// The file named `name` next to the file `path` (in its folder; a name with folders
    /// is taken from there).
    pub fn next_to(path: &Path, name: impl AsRef<Path>) -> PathBuf {
        path.parent().unwrap_or(Path::new(".")).join(name)
    }

    /// Every file opened so far, in the order first opened, as the readers named them.
    pub fn paths_read(&self) -> Vec<PathBuf> {
        self.read.lock().map(|r| r.clone()).unwrap_or_default()
    }

    fn record(&self, path: &Path) {
        if let Ok(mut r) = self.read.lock()
            && !r.iter().any(|p| p == path)
        {
            r.push(path.to_path_buf());
        }
    }

    /// Whether `path` is a file that can be opened (symlinks followed).
    pub fn is_file(&self, path: &Path) -> bool {
        match &self.store {
            Store::FileSystem => path.is_file(),
            Store::Named(files) => files.contains_key(&key(path)),
        }
    }

    /// Whether anything at all exists at `path` (symlinks followed).
    pub fn exists(&self, path: &Path) -> bool {
        match &self.store {
            Store::FileSystem => path.exists(),
            Store::Named(files) => files.contains_key(&key(path)),
        }
    }

    /// Whether anything has the name `path`, a dangling symlink included.
    pub fn is_named(&self, path: &Path) -> bool {
        match &self.store {
            Store::FileSystem => std::fs::symlink_metadata(path).is_ok(),
            Store::Named(files) => files.contains_key(&key(path)),
        }
    }

    /// What tells two names of one file apart from two files: device and inode on the file
    /// system (a symlink or hard link is the file it leads to), the name among buffers; `None`
    /// where the platform does not say or the file cannot be inspected.
    pub(crate) fn identity(&self, path: &Path) -> Option<Identity> {
        match &self.store {
            Store::FileSystem => file_identity(path).map(|(dev, ino)| Identity::Inode(dev, ino)),
            Store::Named(files) => {
                let k = key(path);
                files.contains_key(&k).then_some(Identity::Name(k))
            }
        }
    }

    /// The whole content of the file at `path`: on the file system a regular file (symlinks
    /// followed), read no further than the size it had when opened.
    ///
    /// Errors: [`LoadErrorKind::Missing`], [`LoadErrorKind::NotRegularFile`] for FIFOs, devices,
    /// sockets and directories, [`LoadErrorKind::Io`] otherwise. The bytes are allocated with
    /// `try_reserve` (an error, not an abort, if they cannot be had).
    pub fn read(&self, path: &Path) -> Result<Cow<'_, [u8]>, LoadErrorKind> {
        match &self.store {
            Store::FileSystem => {
                let bytes = read_regular_file(path)?;
                self.record(path);
                Ok(Cow::Owned(bytes))
            }
            Store::Named(files) => {
                let bytes = files.get(&key(path)).ok_or(LoadErrorKind::Missing)?;
                self.record(path);
                Ok(Cow::Borrowed(bytes))
            }
        }
    }
}

/// See [`Inputs::identity`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Identity {
    Inode(u64, u64),
    Name(PathBuf),
}

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

/// The whole content of the regular file at `path` (symlinks followed), as [`Inputs::read`]
/// reads it from the file system, without recording it.
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
fn file_identity(path: &Path) -> Option<(u64, u64)> {
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

    #[test]
    fn records_what_it_read_once_and_not_what_it_could_not() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.raw");
        std::fs::write(&a, b"a").unwrap();
        let inputs = Inputs::file_system();
        assert_eq!(&*inputs.read(&a).unwrap(), b"a");
        assert_eq!(&*inputs.read(&a).unwrap(), b"a");
        assert!(inputs.read(&dir.path().join("none")).is_err());
        assert!(inputs.read(dir.path()).is_err());
        assert_eq!(inputs.paths_read(), vec![a]);
    }

    #[test]
    fn named_buffers_are_found_next_to_each_other_and_never_on_disk() {
        let inputs = Inputs::named([
            ("d.nhdr".to_string(), b"header".to_vec()),
            ("sub/d.raw".to_string(), b"data".to_vec()),
        ]);
        let next = Inputs::next_to(Path::new("sub/x.nhdr"), "./d.raw");
        assert_eq!(&*inputs.read(&next).unwrap(), b"data");
        assert!(inputs.is_file(Path::new("./d.nhdr")));
        assert!(!inputs.exists(Path::new("sub")));
        // A file on disk by that name is not among the buffers.
        assert!(matches!(
            inputs.read(Path::new("Cargo.toml")),
            Err(LoadErrorKind::Missing)
        ));
        assert_eq!(
            inputs.identity(Path::new("./sub/d.raw")),
            inputs.identity(&next)
        );
        assert_eq!(inputs.paths_read(), vec![next]);
    }
}
