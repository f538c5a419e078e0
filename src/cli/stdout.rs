//! Standard output for reports: a reader that stops early (`| head`) is not an error, so a
//! closed pipe ends the write quietly instead of panicking as `println!` does.

use std::io::{ErrorKind, Write};

/// Write `text` to stdout; a closed pipe is fine, any other failure is an error.
pub fn print(text: &str) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}
