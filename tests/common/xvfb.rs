//! A virtual X server for the tests that open windows (the viewer, the README's `view` lines).

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The running server; killed when dropped.
pub struct Xvfb(Child);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Start Xvfb on a free display from `base` on (test binaries run at once: give each its own
/// range); `None` when it cannot be started.
pub fn start_xvfb(base: u32) -> Option<(Xvfb, String)> {
    for n in 0..20 {
        let display = base + (std::process::id() % 50) + n;
        let socket = format!("/tmp/.X11-unix/X{display}");
        if Path::new(&socket).exists() {
            continue;
        }
        let child = Command::new("Xvfb")
            .args([
                &format!(":{display}"),
                "-screen",
                "0",
                "1400x900x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .ok()?;
        let mut x = Xvfb(child);
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(10) {
            if Path::new(&socket).exists() {
                return Some((x, format!(":{display}")));
            }
            if let Ok(Some(_)) = x.0.try_wait() {
                break; // display taken meanwhile: try the next one
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    None
}
