//! The test data: `tests/data/<kind>/…` (vtk, dti, scalars, stress, teem, superquadric,
//! regressions; tests/README.md says what each holds and what wrote it).

use std::path::{Path, PathBuf};

/// `tests/data/<rel>` in this repository, e.g. `path("vtk/expected.json")`.
pub fn path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// Every file below `dir` (not the folders), sorted.
#[allow(dead_code)] // not every test binary that includes this file walks a folder
pub fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}
