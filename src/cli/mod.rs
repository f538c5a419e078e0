//! The `tensorglyph` command line: demo, info, render, view, bench, stability, report. [`main`] parses
//! the arguments and runs the command; the binary (`src/main.rs`) and any other front end that
//! offers the same command line call it.
//!
//! One module per subcommand; `args` holds the options they share, `progress` the terminal's
//! progress bars.

pub mod args;
pub mod bench;
pub mod info;
pub mod progress;
pub mod render;
pub mod report;
pub mod stability;
pub mod stdout;
pub mod view;

use std::ffi::OsString;

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
    Demo(render::DemoArgs),
    /// Summarise a tensor field: counts, eigenvalue ranges, FA, shape classes, samples.
    Info(info::InfoArgs),
    /// Render a field headless to a PNG.
    Render(render::RenderArgs),
    /// Explore a field interactively: orbit, slice, restyle, pick glyphs, save screenshots.
    View(view::ViewArgs),
    /// Time every method on the same scenes and chart speed against accuracy.
    Bench(bench::BenchArgs),
    /// Adversarial stability suite: every method and glyph against the reference.
    Stability(stability::StabilityArgs),
    /// Glyph mosaics and an HTML page per tensor file (FILE... -o OUT_DIR) or per participant of
    /// a BIDS derivatives folder of BEP016 tensor maps (exit status 1 when some report failed).
    Report(report::ReportArgs),
}

/// Run the command line `args` (the program's name first, as `std::env::args_os` gives it)
/// and return the process's exit status: 0, or 2 for any error, which is printed as one line
/// on stderr. Help and version print as clap prints them.
pub fn main<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let result = match cli.command {
        Command::Demo(a) => render::demo(a),
        Command::Info(a) => info::run(a),
        Command::Render(a) => render::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Stability(a) => stability::run(a),
        Command::View(a) => view::run(a),
        Command::Report(a) => match report::run(a) {
            // Each failed participant was named on its own line.
            Ok(false) => return 1,
            Ok(true) => Ok(()),
            Err(e) => Err(e),
        },
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e:#}");
            2
        }
    }
}

/// Options of one group `A` of the command line's (`SceneArgs`, `render::FrameArgs`, …)
/// parsed from arguments spelled as on the command line, for front ends that bring their own
/// data (the Python package): the same defaults and checks; an error says which option and
/// value it is about, so a front end can name them as its users spell them.
pub fn parse_options<A: clap::Args>(
    args: impl IntoIterator<Item = impl Into<OsString> + Clone>,
) -> Result<A, Box<OptionError>> {
    #[derive(Parser)]
    #[command(name = "tensorglyph", no_binary_name = true)]
    struct Options<A: clap::Args> {
        #[command(flatten)]
        options: A,
    }
    Options::<A>::try_parse_from(args)
        .map(|o| o.options)
        .map_err(|e| Box::new(OptionError::of(&e)))
}

/// A front end's option that the command line's parser refused: the command line's one line
/// (its `Display`), and where clap says so, the option (`--glyph`), the value given and why
/// it was refused, for a front end that spells options its own way (`glyph='banana'`).
#[derive(Debug, Clone)]
pub struct OptionError {
    line: String,
    /// The option as the command line spells it, without its value name: `--glyph`.
    pub option: Option<String>,
    /// The value given, as given.
    pub value: Option<String>,
    /// Why, without the option and value: `not one of: ellipsoid, cylinder` or the
    /// validator's reason.
    pub reason: String,
    /// The option meant, where the one given is unknown and clap has a guess (`--glyph`).
    pub suggested: Option<String>,
    /// The option given before that this one cannot go with (`--method`).
    pub conflicts_with: Option<String>,
}

impl OptionError {
    fn of(e: &clap::Error) -> Self {
        use clap::error::{ContextKind, ContextValue, ErrorKind};
        let value = match e.get(ContextKind::InvalidValue) {
            Some(ContextValue::String(v)) => Some(v.clone()),
            _ => None,
        };
        let reason = match (e.kind(), e.get(ContextKind::ValidValue)) {
            (_, Some(ContextValue::Strings(values))) => {
                format!("not one of: {}", values.join(", "))
            }
            (ErrorKind::ValueValidation, _) => std::error::Error::source(e)
                .map(|s| s.to_string())
                .unwrap_or_else(|| "invalid value".to_string()),
            (ErrorKind::UnknownArgument, _) => "no such option".to_string(),
            (ErrorKind::ArgumentConflict, _) => "cannot be used with the options given".to_string(),
            _ => usage_line(e).trim_start_matches("error: ").to_string(),
        };
        let flag = |kind| match e.get(kind) {
            Some(ContextValue::String(arg)) => arg.split([' ', '=']).next().map(str::to_string),
            Some(ContextValue::Strings(args)) => args
                .first()
                .and_then(|a| a.split([' ', '=']).next())
                .map(str::to_string),
            _ => None,
        };
        OptionError {
            line: usage_line(e),
            option: flag(ContextKind::InvalidArg),
            value,
            reason,
            suggested: flag(ContextKind::SuggestedArg),
            conflicts_with: flag(ContextKind::PriorArg),
        }
    }
}

impl std::fmt::Display for OptionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.line)
    }
}

impl std::error::Error for OptionError {}

/// Help and version as clap prints them; any other command-line error as one line (clap's
/// first, with the accepted values where it has them), exit status 2 like every other error.
fn usage_error(e: clap::Error) -> i32 {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        // What `e.exit()` does, without ending the process: print, then its status.
        let _ = e.print();
        return e.exit_code();
    }
    eprintln!("{}", usage_line(&e));
    2
}

/// A command-line error as one line: clap's first, with the accepted values where it has them.
fn usage_line(e: &clap::Error) -> String {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
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
    line
}
