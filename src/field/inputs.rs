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
use std::io::{ErrorKind, Read, Seek, SeekFrom};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use crate::error::{LoadErrorKind, escape_for_error, escape_path};
use crate::files::special_kind;

/// A data file a header names ([`Inputs::detached`]): where it is, and how a message shows it
/// (the user's folder, the file's name escaped as file text is).
#[derive(Debug, Clone, PartialEq)]
pub struct Detached {
    pub path: PathBuf,
    pub shown: String,
}

/// A file name's bytes as a path: any bytes on Unix (as the system takes them), UTF-8 elsewhere.
fn name_path(name: &[u8]) -> Option<PathBuf> {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt as _;
        Some(PathBuf::from(std::ffi::OsStr::from_bytes(name)))
    }
    #[cfg(not(unix))]
    {
        std::str::from_utf8(name).ok().map(PathBuf::from)
    }
}

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

    /// The data file a header `path` names by the bytes `name` (a `.mih`'s `file`, a `.nhdr`'s
    /// `data file`, a `.pvti`'s piece): read from the header's folder or below it, never from
    /// an absolute path or through `..` (a header is file content, and the documentation has
    /// always said the data is read next to it: a `.mih` naming `/proc/self/exe` or
    /// `../secret` must not read it). The name's bytes are the file name's, whatever their
    /// encoding (MRtrix opens a Latin-1 name; on Unix a name is bytes). `Err` says why not.
    pub fn detached(path: &Path, name: &[u8]) -> Result<Detached, String> {
        let shown = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => {
                format!("{}/{}", escape_path(d), escape_for_error(name))
            }
            _ => escape_for_error(name),
        };
        let rel = name_path(name)
            .ok_or_else(|| format!("'{}' is not a file name here", escape_for_error(name)))?;
        let inside = rel
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        if name.is_empty() || !inside || rel.file_name().is_none() {
            return Err(format!(
                "'{}' is not in the header's folder or below it: a header's data file is \
                 read from there (move or link the data beside the header)",
                escape_for_error(name)
            ));
        }
        Ok(Detached {
            path: Self::next_to(path, rel),
            shown,
        })
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

    /// The file at `path`, opened for reading any part of it: on the file system a regular
    /// file (symlinks followed), never read past the size it had when opened.
    ///
    /// Errors: [`LoadErrorKind::Missing`], [`LoadErrorKind::NotRegularFile`] for FIFOs, devices,
    /// sockets and directories, [`LoadErrorKind::Io`] otherwise.
    pub fn open(&self, path: &Path) -> Result<Input<'_>, LoadErrorKind> {
        let src = match &self.store {
            Store::FileSystem => {
                let (file, len) = open_regular_file(path)?;
                Src::File(file, len)
            }
            Store::Named(files) => Src::Bytes(files.get(&key(path)).ok_or(LoadErrorKind::Missing)?),
        };
        self.record(path);
        Ok(Input { src })
    }

    /// The whole content of the file at `path` ([`Self::open`], then [`Input::read_all`]).
    pub fn read(&self, path: &Path) -> Result<Cow<'_, [u8]>, LoadErrorKind> {
        self.open(path)?.read_all()
    }
}

/// One file opened by [`Inputs::open`]: its size, and reads of the parts a reader needs (a
/// header, then the data it says where to find), so that nothing else is read or held.
pub struct Input<'a> {
    src: Src<'a>,
}

enum Src<'a> {
    /// The file and its size when opened.
    File(File, u64),
    Bytes(&'a [u8]),
}

impl<'a> Input<'a> {
    /// Its size in bytes.
    pub fn len(&self) -> u64 {
        match &self.src {
            Src::File(_, len) => *len,
            Src::Bytes(b) => b.len() as u64,
        }
    }

    /// Whether it holds no byte.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Up to `n` bytes from byte `start` on (fewer at the end), allocated with `try_reserve`
    /// (an error, not an abort, if they cannot be had).
    pub fn read_at(&self, start: u64, n: u64) -> Result<Cow<'a, [u8]>, LoadErrorKind> {
        let start = start.min(self.len());
        let n = n.min(self.len() - start);
        match &self.src {
            Src::Bytes(b) => Ok(Cow::Borrowed(&b[start as usize..(start + n) as usize])),
            Src::File(..) => {
                let cap = usize::try_from(n).map_err(|_| {
                    LoadErrorKind::Other(format!("the file is too large ({n} bytes)"))
                })?;
                let mut bytes = Vec::new();
                bytes.try_reserve_exact(cap).map_err(|_| {
                    LoadErrorKind::Other(format!("cannot allocate {n} bytes to read the file into"))
                })?;
                self.reader_at(start)?
                    .take(n)
                    .read_to_end(&mut bytes)
                    .map_err(LoadErrorKind::Io)?;
                Ok(Cow::Owned(bytes))
            }
        }
    }

    /// Everything ([`Self::read_at`] from 0).
    pub fn read_all(&self) -> Result<Cow<'a, [u8]>, LoadErrorKind> {
        self.read_at(0, self.len())
    }

    /// A reader of the bytes from `start` to the end (the size when opened).
    pub fn reader_at(&self, start: u64) -> Result<Box<dyn Read + '_>, LoadErrorKind> {
        let start = start.min(self.len());
        match &self.src {
            Src::Bytes(b) => Ok(Box::new(&b[start as usize..])),
            Src::File(file, len) => {
                let mut f = file;
                f.seek(SeekFrom::Start(start)).map_err(LoadErrorKind::Io)?;
                Ok(Box::new(f.take(len - start)))
            }
        }
    }

    /// The gzip data from byte `start` to the end, inflated on demand within the budget
    /// ([`crate::field::gzip`]); `what` names it in errors.
    pub fn gunzip(
        &self,
        start: u64,
        what: impl Into<String>,
    ) -> Result<crate::field::gzip::Gunzip<'_>, LoadErrorKind> {
        let compressed = self.len() - start.min(self.len());
        Ok(crate::field::gzip::Gunzip::new(
            self.reader_at(start)?,
            compressed,
            what,
        ))
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

/// The regular file at `path` (symlinks followed), opened, and its size.
fn open_regular_file(path: &Path) -> Result<(File, u64), LoadErrorKind> {
    let before = std::fs::metadata(path).map_err(io_error)?;
    if let Some(kind) = special_kind(&before) {
        return Err(LoadErrorKind::NotRegularFile(kind));
    }
    let file = open_nonblocking(path).map_err(io_error)?;
    let meta = file.metadata().map_err(io_error)?;
    if let Some(kind) = special_kind(&meta) {
        return Err(LoadErrorKind::NotRegularFile(kind));
    }
    // A file that grows while it is read is cut at the size it had when opened.
    Ok((file, meta.len()))
}

/// The whole content of the regular file at `path` (symlinks followed), as [`Inputs::read`]
/// reads it from the file system, without recording it.
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, LoadErrorKind> {
    let (file, len) = open_regular_file(path)?;
    Input {
        src: Src::File(file, len),
    }
    .read_all()
    .map(Cow::into_owned)
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

    /// A header's data file is its folder's or below; the rest is refused with the name shown.
    #[test]
    fn a_header_names_data_beside_or_below_it() {
        let h = Path::new("dir/x.mih");
        let ok = Inputs::detached(h, b"sub/./x.dat").unwrap();
        assert_eq!(ok.path, Path::new("dir/sub/./x.dat"));
        assert_eq!(ok.shown, "dir/sub/./x.dat");
        for bad in [
            &b"/proc/self/exe"[..],
            b"/etc/passwd",
            b"../x.dat",
            b"sub/../../x.dat",
            b"",
            b".",
        ] {
            let e = Inputs::detached(h, bad).unwrap_err();
            assert!(e.contains("not in the header's folder"), "{e}");
        }
        // A Latin-1 name (MRtrix opens it) is the file's bytes, shown escaped.
        let latin = Inputs::detached(Path::new("x.mih"), b"caf\xe9.dat").unwrap();
        #[cfg(unix)]
        assert_eq!(
            latin.path.as_os_str().as_encoded_bytes(),
            b"caf\xe9.dat".as_slice()
        );
        assert!(!latin.shown.contains('\u{fffd}'), "{}", latin.shown);
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
