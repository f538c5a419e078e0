//! The test data: `tests/data/<kind>/…` (vtk, dti, scalars, stress, teem, superquadric,
//! regressions; tests/README.md says what each holds and what wrote it).

use std::path::PathBuf;

/// `tests/data/<rel>` in this repository, e.g. `path("vtk/expected.json")`.
pub fn path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}
