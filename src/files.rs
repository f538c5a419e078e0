//! What kind of file a path is: inputs and outputs alike must be regular files (a FIFO blocks,
//! a device never ends or swallows everything), and both say so in the same words.

use std::fs::Metadata;

/// What a non-regular file is, for the error message; `None` for a regular file.
pub fn special_kind(m: &Metadata) -> Option<&'static str> {
    let t = m.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a file")
}
