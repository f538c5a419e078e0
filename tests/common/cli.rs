//! Running the `tensorglyph` binary from the command-line tests.

use std::process::{Command, Output};

/// Run the binary with `args` (lavapipe's runtime-dir warning quietened).
pub fn tg(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .expect("run tensorglyph")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The one JSON line a `--json` run prints.
pub fn json(o: &Output) -> serde_json::Value {
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.lines().count(), 1, "exactly one JSON line: {text}");
    serde_json::from_str(&text).expect("valid JSON")
}
