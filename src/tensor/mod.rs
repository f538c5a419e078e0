//! Per-tensor mathematics: eigendecomposition and shape measures.

pub mod eigen;
pub mod shape;
