//! Files into fields and glyphs on the CPU, against writers and readers other than ours: VTK's
//! own read-back values, vtkio, numpy, nibabel and DIPY, Teem's `unu`, the shared maths test
//! vectors; and every bad or corrupted file refused in one clean line. tests/README.md is the
//! map. (The mutation campaign is a binary of its own: tests/campaign/.)

#[path = "../common/cli.rs"]
mod cli;
#[path = "../common/data.rs"]
mod data;

mod bep016;
mod corrupted;
mod defects;
mod dipy;
mod dti;
mod mif;
mod peaks;
mod regressions;
mod scalars;
mod sh;
mod tensor_vectors;
mod vtk;
mod vtkio;
