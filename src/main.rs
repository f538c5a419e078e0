//! The `tensorglyph` command line: demo, info, render, view, bench, stability
//! (`tensorglyph::cli`, where the arguments are parsed and the commands run).

#![forbid(unsafe_code)]

use std::process::ExitCode;

fn main() -> ExitCode {
    let status = tensorglyph::cli::main(std::env::args_os());
    ExitCode::from(u8::try_from(status).unwrap_or(2))
}
