//! Per-tensor mathematics: eigendecomposition, shape measures, stress measures, and the scalar
//! measures a colouring or an underlay shows.

pub mod eigen;
pub mod measure;
pub mod shape;
pub mod stress;
