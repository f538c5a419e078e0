//! The `tensorglyph` command line: demo, info, render, view, bench, stability.

#![forbid(unsafe_code)]

mod commands;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "tensorglyph",
    version,
    about = "Ray-cast glyphs for 3D symmetric tensor fields"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render the built-in 40³ demo field (64,000 glyphs) to a PNG.
    Demo(commands::render::DemoArgs),
    /// Summarise a tensor field: counts, eigenvalue ranges, FA, shape classes, samples.
    Info(commands::info::InfoArgs),
    /// Render a field headless to a PNG.
    Render(commands::render::RenderArgs),
    /// Explore a field interactively: orbit, slice, restyle, pick glyphs, save screenshots.
    View(commands::view::ViewArgs),
    /// Time every method on the same scenes and chart speed against accuracy.
    Bench(commands::bench::BenchArgs),
    /// Adversarial stability suite: every method and glyph against the reference.
    Stability(commands::stability::StabilityArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let result = match cli.command {
        Command::Demo(a) => commands::render::demo(a),
        Command::Info(a) => commands::info::run(a),
        Command::Render(a) => commands::render::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Stability(a) => commands::stability::run(a),
        Command::View(a) => commands::view::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Help and version as clap prints them; any other command-line error as one line (clap's
/// first, with the accepted values where it has them), exit status 2 like every other error.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit();
    }
    let rendered = e.render().to_string();
    let mut line = rendered
        .lines()
        .next()
        .unwrap_or("error: bad arguments")
        .to_string();
    if let Some(ContextValue::Strings(values)) = e.get(ContextKind::ValidValue) {
        line.push_str(&format!(" (one of: {})", values.join(", ")));
    }
    if e.kind() == ErrorKind::MissingRequiredArgument
        && let Some(ContextValue::Strings(args)) = e.get(ContextKind::InvalidArg)
    {
        line.push(' ');
        line.push_str(&args.join(", "));
    }
    eprintln!("{line}");
    ExitCode::from(2)
}
