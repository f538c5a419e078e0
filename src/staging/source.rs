//! Where a scene comes from: a file, a built-in demo field, a field already in memory, or a
//! file's bytes in memory ([`Source`]), and what reading one gives.

use std::path::PathBuf;
use std::str::FromStr;
use std::sync::Arc;

use crate::error::LoadError;
use crate::field::{FieldKind, Inputs, ReadOptions, TensorField, read_field_from};

/// A built-in analytic field: `grid40` (the canonical 64,000-glyph demo) or `grid:N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Demo {
    pub n: usize,
}

impl Demo {
    /// The largest `grid:N`: its field and glyphs together (128 bytes per tensor while the
    /// eigendecomposition runs, its positions implied) take about 4.3 GB, within this
    /// project's 24 GB machines; grid:512 would need 17 GB.
    pub const MAX_N: usize = 320;
}

impl FromStr for Demo {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let n = match s {
            "grid40" => 40,
            _ => s
                .strip_prefix("grid:")
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|&n| (1..=Demo::MAX_N).contains(&n))
                .ok_or_else(|| {
                    format!(
                        "unknown demo '{s}': use grid40 or grid:N (1 ≤ N ≤ {})",
                        Demo::MAX_N
                    )
                })?,
        };
        Ok(Demo { n })
    }
}

impl std::fmt::Display for Demo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.n == 40 {
            write!(f, "grid40")
        } else {
            write!(f, "grid:{}", self.n)
        }
    }
}

/// Where a scene comes from: a file, a built-in demo field, a field already in memory, or a
/// file's bytes in memory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    File(PathBuf),
    Demo(Demo),
    Field(InMemory),
    Bytes(InMemoryFile),
}

/// A file held in memory under its name, read as the file of that name is (the Python
/// package's DIPY fits in spherical harmonics, made a NIfTI file in memory by nibabel: tensors
/// or SH series, whatever the bytes hold).
#[derive(Debug, Clone)]
pub struct InMemoryFile {
    /// Its name, whose extension says the format (`fit.nii`), and what messages call it.
    pub name: String,
    pub bytes: Arc<Vec<u8>>,
}

impl InMemoryFile {
    /// The file as the readers' inputs, and its path among them.
    pub fn inputs(&self) -> (Inputs, PathBuf) {
        (
            Inputs::named([(self.name.clone(), self.bytes.to_vec())]),
            PathBuf::from(&self.name),
        )
    }
}

/// The same bytes (one allocation) under the same name.
impl PartialEq for InMemoryFile {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.bytes, &other.bytes) && self.name == other.name
    }
}

impl Eq for InMemoryFile {}

/// A field the caller made or read itself (the Python package's arrays), shared: staging
/// copies it, the caller keeps it for the next image.
#[derive(Debug, Clone)]
pub struct InMemory {
    pub field: Arc<TensorField>,
    /// What messages and the legend call it.
    pub name: String,
    /// Diffusion data (a lattice from a DTI fit): the DTI defaults, as NIfTI and NRRD files
    /// get them ([`crate::defaults`]).
    pub diffusion: bool,
}

/// The same field (one allocation), name and kind: a field is never changed once made.
impl PartialEq for InMemory {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.field, &other.field)
            && self.name == other.name
            && self.diffusion == other.diffusion
    }
}

impl Eq for InMemory {}

impl Source {
    /// The field, read (the read options apply to files only: an in-memory field was read
    /// or made with its own).
    pub fn load(&self, opts: &ReadOptions) -> Result<TensorField, LoadError> {
        self.load_from(&Inputs::file_system(), opts)
    }

    /// [`Self::load`], a file read from `inputs` (which record the files read).
    pub fn load_from(&self, inputs: &Inputs, opts: &ReadOptions) -> Result<TensorField, LoadError> {
        match self {
            Source::File(p) => read_field_from(inputs, p, opts),
            Source::Demo(d) => Ok(crate::field::synthetic::grid(d.n)),
            Source::Field(f) => Ok((*f.field).clone()),
            Source::Bytes(b) => {
                let (inputs, path) = b.inputs();
                read_field_from(&inputs, &path, opts)
            }
        }
    }

    /// What the source holds ([`FieldKind::of_file`] for a file on disk or in memory; a demo
    /// and a field built in code hold tensors).
    pub fn kind(&self, opts: &ReadOptions) -> FieldKind {
        self.kind_in(&Inputs::file_system(), opts)
    }

    /// [`Self::kind`], a file looked for among `inputs` (the page's files).
    pub fn kind_in(&self, inputs: &Inputs, opts: &ReadOptions) -> FieldKind {
        match self {
            Source::File(p) => FieldKind::of_file(inputs, p, opts),
            Source::Bytes(b) => {
                let (inputs, path) = b.inputs();
                FieldKind::of_file(&inputs, &path, opts)
            }
            Source::Demo(_) | Source::Field(_) => FieldKind::Tensors,
        }
    }

    /// The file's path, `demo grid40`, or the in-memory field's name.
    pub fn name(&self) -> String {
        match self {
            Source::File(p) => p.display().to_string(),
            Source::Demo(d) => format!("demo {d}"),
            Source::Field(f) => f.name.clone(),
            Source::Bytes(b) => b.name.clone(),
        }
    }
}
