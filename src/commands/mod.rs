//! One module per subcommand; `scene` holds the options they share.

pub mod bench;
pub mod info;
pub mod path;
pub mod pipeline;
pub mod render;
pub mod scene;
pub mod stability;
pub mod view;
