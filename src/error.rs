//! Typed library errors. The binary adds context with anyhow and maps them to exit status 2.

use std::path::PathBuf;

/// A tensor field could not be loaded. Always names the file.
#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", path.display())]
pub struct LoadError {
    pub path: PathBuf,
    pub kind: LoadErrorKind,
}

impl LoadError {
    pub fn new(path: impl Into<PathBuf>, kind: LoadErrorKind) -> Self {
        Self {
            path: path.into(),
            kind,
        }
    }
}

/// What went wrong while loading, with the place where it is known.
#[derive(Debug, thiserror::Error)]
pub enum LoadErrorKind {
    #[error("file not found")]
    Missing,
    #[error("cannot read file: {0}")]
    Io(#[from] std::io::Error),
    #[error("not a VTK file: {0}")]
    NotVtk(String),
    #[error("truncated or malformed file: {0}")]
    Malformed(String),
    #[error("no tensor array found (looked for 9- or 6-component point or cell data){0}")]
    NoTensorArray(String),
    #[error("array '{name}' not found; available arrays: {available}")]
    ArrayNotFound { name: String, available: String },
    #[error("array '{name}' has {components} components; a tensor array needs 9 or 6")]
    ComponentCount { name: String, components: usize },
    #[error("array '{name}' has {found} tuples but the dataset has {expected} {location}s")]
    TupleCount {
        name: String,
        found: usize,
        expected: usize,
        location: &'static str,
    },
    #[error("unsupported dataset: {0}")]
    UnsupportedDataset(String),
    #[error("{0}")]
    Other(String),
}

/// Rendering failed (no usable adapter, bad size, GPU error, output not writable).
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("no GPU adapter available")]
    NoAdapter,
    #[error("invalid image size {width}x{height}: {reason}")]
    BadSize {
        width: u32,
        height: u32,
        reason: String,
    },
    #[error("GPU error: {0}")]
    Gpu(String),
    #[error("unsupported: {0}")]
    Unsupported(String),
    #[error("{}: cannot write output: {source}", path.display())]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
}
