//! Writing outputs whole or not at all, and never over what must not be replaced.
//!
//! [`write_atomic`] is the one way files are written: into a temporary file beside the target,
//! synced, then renamed over it. Before that it settles what "the target" is:
//! - a symlink is written *through*: the temporary file goes beside the file the link points
//!   to (following every link, dangling ones too), and the link itself stays;
//! - an existing target that is not a regular file (FIFO, device, socket, directory) is refused:
//!   renaming over it would replace the node (as root, `-o /dev/null` would replace /dev/null),
//!   and writing into it directly would not be whole-or-nothing;
//! - a target that is the same file as an input (same device and inode: the path itself, a
//!   symlink or a hard link to it) is refused, so an input is never overwritten; the inputs are
//!   every file the readers read (the `Inputs` record), not only the one named.
//!
//! The replaced file's permission bits are kept.

use std::fs::{File, Metadata};
use std::io::{BufWriter, Error, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::files::special_kind;

/// Symlinks followed before giving up (Linux's own limit is 40).
const MAX_LINKS: usize = 40;

/// The path `path` finally names once every symlink is followed, with its metadata if it exists.
fn resolve(path: &Path) -> std::io::Result<(PathBuf, Option<Metadata>)> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&p)?;
                p = if target.is_absolute() {
                    target
                } else {
                    parent_dir(&p).join(target)
                };
            }
            Ok(m) => return Ok((p, Some(m))),
            Err(e) if e.kind() == ErrorKind::NotFound => return Ok((p, None)),
            Err(e) => return Err(e),
        }
    }
    Err(Error::other(format!(
        "more than {MAX_LINKS} levels of symbolic links"
    )))
}

fn parent_dir(p: &Path) -> &Path {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

#[cfg(unix)]
fn same_file(a: &Metadata, b: &Metadata) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(_: &Metadata, _: &Metadata) -> bool {
    false
}

/// Where `path` will really be written, after the checks in the module docs. Call it before
/// expensive work to fail early; [`write_atomic`] calls it again right before writing.
pub fn check_output(path: &Path, inputs: &[&Path]) -> std::io::Result<PathBuf> {
    if path.file_name().is_none() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "output path has no file name",
        ));
    }
    let (target, meta) = resolve(path)?;
    let Some(meta) = meta else {
        return Ok(target);
    };
    if let Some(kind) = special_kind(&meta) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("the output is {kind}, not a regular file; refusing to replace it"),
        ));
    }
    for (k, input) in inputs.iter().enumerate() {
        if let Ok(m) = std::fs::metadata(input)
            && same_file(&m, &meta)
        {
            // The first input is the one the user named; the others (a mask, a detached data
            // file, a piece) are named, as the user may not know they were read.
            let which = if k == 0 {
                String::new()
            } else {
                format!(" {}", crate::error::escape_path(input))
            };
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("the output is the input file{which}; refusing to overwrite it"),
            ));
        }
    }
    Ok(target)
}

/// Temporary names are unique within the process too (two writers may target one folder).
static TMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Write `path` whole or not at all: `write` fills a buffered temporary file beside the
/// (symlink-resolved) target, which is synced and renamed into place; on any error the
/// temporary file is removed and the target is untouched. `inputs` are files the output must not
/// be (see the module docs).
pub fn write_atomic<F>(path: &Path, inputs: &[&Path], write: F) -> std::io::Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let target = check_output(path, inputs)?;
    let keep_mode = std::fs::metadata(&target).ok().map(|m| m.permissions());
    let dir = parent_dir(&target);
    let name = target
        .file_name()
        .ok_or_else(|| Error::new(ErrorKind::InvalidInput, "output path has no file name"))?;
    let (file, tmp) = loop {
        let tmp = dir.join(format!(
            ".{}.{}-{}.tmp",
            name.to_string_lossy(),
            std::process::id(),
            TMP_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        // create_new: never open (or follow a symlink planted at) an existing name.
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(f) => break (f, tmp),
            Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    };
    let result = (|| {
        let mut w = BufWriter::with_capacity(1 << 20, file);
        write(&mut w)?;
        w.flush()?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        if let Some(p) = keep_mode {
            file.set_permissions(p)?;
        }
        file.sync_all()?;
        // Closed before the rename (the web build has no files: there closing is nothing).
        #[cfg_attr(target_arch = "wasm32", allow(clippy::drop_non_drop))]
        drop(file);
        std::fs::rename(&tmp, &target)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Write an RGBA8 image as PNG with [`write_atomic`] (no inputs to protect).
pub fn write_png_atomic(path: &Path, width: u32, height: u32, rgba: &[u8]) -> std::io::Result<()> {
    write_png(path, &[], width, height, rgba)
}

/// Write an RGBA8 image as PNG with [`write_atomic`], refusing to overwrite any of `inputs`.
pub fn write_png(
    path: &Path,
    inputs: &[&Path],
    width: u32,
    height: u32,
    rgba: &[u8],
) -> std::io::Result<()> {
    write_png_dpi(path, inputs, width, height, rgba, None)
}

/// [`write_png`] with the resolution `dpi` (dots per inch) in the PNG's pHYs chunk, so page
/// layout programs place the figure at its intended size.
pub fn write_png_dpi(
    path: &Path,
    inputs: &[&Path],
    width: u32,
    height: u32,
    rgba: &[u8],
    dpi: Option<f64>,
) -> std::io::Result<()> {
    write_atomic(path, inputs, |w| encode_png(w, width, height, rgba, dpi))
}

/// An RGBA8 image as PNG bytes into `w`, as [`write_png_dpi`] writes them (for images kept in
/// memory: the Python package's notebook display).
pub fn encode_png(
    w: &mut impl Write,
    width: u32,
    height: u32,
    rgba: &[u8],
    dpi: Option<f64>,
) -> std::io::Result<()> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    if let Some(dpi) = dpi {
        let per_metre = (dpi / 0.0254).round() as u32;
        enc.set_pixel_dims(Some(png::PixelDimensions {
            xppu: per_metre,
            yppu: per_metre,
            unit: png::Unit::Meter,
        }));
    }
    let mut writer = enc.write_header().map_err(Error::other)?;
    writer.write_image_data(rgba).map_err(Error::other)?;
    writer.finish().map_err(Error::other)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_whole_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        write_atomic(&p, &[], |w| w.write_all(b"one")).unwrap();
        write_atomic(&p, &[], |w| w.write_all(b"two")).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(names(dir.path()), ["out.txt"]);
    }

    #[test]
    fn a_failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        std::fs::write(&p, b"old").unwrap();
        let e = write_atomic(&p, &[], |w| {
            w.write_all(b"partial")?;
            Err(Error::other("boom"))
        })
        .unwrap_err();
        assert_eq!(e.to_string(), "boom");
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(names(dir.path()), ["out.txt"]);
    }

    #[cfg(unix)]
    #[test]
    fn writes_through_symlinks_even_dangling_and_chained() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("sub/real.txt");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::fs::write(&real, b"old").unwrap();
        // link1 -> link2 -> sub/real.txt (relative targets)
        symlink("sub/real.txt", dir.path().join("link2")).unwrap();
        symlink("link2", dir.path().join("link1")).unwrap();
        write_atomic(&dir.path().join("link1"), &[], |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert!(
            std::fs::symlink_metadata(dir.path().join("link1"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        // Dangling: the link's target is created, the link stays a link.
        symlink("sub/made.txt", dir.path().join("dangling")).unwrap();
        write_atomic(&dir.path().join("dangling"), &[], |w| w.write_all(b"x")).unwrap();
        assert_eq!(
            std::fs::read(dir.path().join("sub/made.txt")).unwrap(),
            b"x"
        );
        assert_eq!(names(&dir.path().join("sub")), ["made.txt", "real.txt"]);
        // A loop is an error, not a hang.
        symlink("loop_b", dir.path().join("loop_a")).unwrap();
        symlink("loop_a", dir.path().join("loop_b")).unwrap();
        assert!(write_atomic(&dir.path().join("loop_a"), &[], |_| Ok(())).is_err());
    }

    #[cfg(unix)]
    #[test]
    fn refuses_special_files_and_inputs() {
        use std::os::unix::fs::{PermissionsExt as _, symlink};
        let dir = tempfile::tempdir().unwrap();
        let e = write_atomic(dir.path(), &[], |_| Ok(())).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidInput);
        if Path::new("/dev/null").exists() {
            let e = write_atomic(Path::new("/dev/null"), &[], |_| Ok(())).unwrap_err();
            assert!(e.to_string().contains("device"), "{e}");
        }
        let input = dir.path().join("in.vtk");
        std::fs::write(&input, b"data").unwrap();
        std::fs::set_permissions(&input, std::fs::Permissions::from_mode(0o640)).unwrap();
        let e = write_atomic(&input, &[&input], |w| w.write_all(b"x")).unwrap_err();
        assert!(e.to_string().contains("is the input file"), "{e}");
        symlink(&input, dir.path().join("alias.png")).unwrap();
        std::fs::hard_link(&input, dir.path().join("hard.png")).unwrap();
        for alias in ["alias.png", "hard.png"] {
            assert!(write_atomic(&dir.path().join(alias), &[&input], |_| Ok(())).is_err());
        }
        assert_eq!(std::fs::read(&input).unwrap(), b"data");
        // Not an input: replaced, keeping its permission bits.
        write_atomic(&input, &[], |w| w.write_all(b"new")).unwrap();
        let mode = std::fs::metadata(&input).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o640);
    }
}
