//! Eigendecomposition.
