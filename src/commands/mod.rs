//! One module per subcommand; `args` holds the options they share, `progress` the terminal's
//! progress bars.

pub mod args;
pub mod bench;
pub mod info;
pub mod progress;
pub mod render;
pub mod stability;
pub mod stdout;
pub mod view;
