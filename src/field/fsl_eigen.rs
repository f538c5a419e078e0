//! FSL `dtifit`'s eigen outputs as one tensor field: `PREFIX_L1`, `_L2`, `_L3` (3-D eigenvalue
//! maps) and `PREFIX_V1`, `_V2`, `_V3` (4-D, the eigenvectors' x, y, z as three volumes), read
//! together and rebuilt as `T = Σ λᵢ vᵢ vᵢᵀ`.
//!
//! Any one of the six names the set, and so does `PREFIX` itself when no file has that name but
//! `PREFIX_V1.nii.gz` (or `.nii`) exists: users have `dtifit -o PREFIX` in their history, and
//! either way the six share one extension. Nothing in the files says they belong together, so
//! they must share their dimensions and voxel-to-world matrix, and an error names the file
//! that differs. `dtifit` computes its vectors in the same voxel frame as its tensors
//! (`--save_tensor`), so the frame and its default are those of 4-D NIfTI tensors.

use std::path::{Path, PathBuf};

use nalgebra::Matrix4;

use super::frame::{Layout, Why};
use super::inputs::Inputs;
use super::nifti::{self, Header};
use super::options::ReadOptions;
use super::tensor_field::{Location, TensorArrayInfo, TensorField};
use crate::error::{LoadError, LoadErrorKind, escape_for_error, escape_path};

const EIGENVALUES: [&str; 3] = ["L1", "L2", "L3"];
const EIGENVECTORS: [&str; 3] = ["V1", "V2", "V3"];
const EXTENSIONS: [&str; 2] = [".nii.gz", ".nii"];

/// Six files `PREFIX_{L1,L2,L3,V1,V2,V3}EXT` in one folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EigenSet {
    /// The path the user gave (read first when it is one of the six).
    given: PathBuf,
    /// `PREFIX`, the folder included.
    prefix: PathBuf,
    stem: String,
    ext: &'static str,
}

impl EigenSet {
    /// The set `path` names among `inputs`: one of its files, or its prefix when nothing has
    /// that name and `PREFIX_V1.nii.gz` or `PREFIX_V1.nii` exists. `None` for any other path
    /// (and for names that are not UTF-8).
    pub fn named_by(path: &Path, inputs: &Inputs) -> Option<Self> {
        let name = path.file_name()?.to_str()?;
        for ext in EXTENSIONS {
            for member in EIGENVALUES.iter().chain(&EIGENVECTORS) {
                if let Some(stem) = name.strip_suffix(&format!("_{member}{ext}"))
                    && !stem.is_empty()
                {
                    return Some(Self::new(path, path.with_file_name(stem), stem, ext));
                }
            }
        }
        if inputs.is_named(path) {
            return None;
        }
        EXTENSIONS
            .into_iter()
            .map(|ext| Self::new(path, path.to_path_buf(), name, ext))
            // Anything by that name, a dangling link or a folder too: reading the set then
            // names the member at fault, where "PREFIX: file not found" would not.
            .find(|set| inputs.is_named(&set.file("V1")))
    }

    fn new(given: &Path, prefix: PathBuf, stem: &str, ext: &'static str) -> Self {
        Self {
            given: given.to_path_buf(),
            prefix,
            stem: stem.to_string(),
            ext,
        }
    }

    /// The path of member `m` (`L1` .. `V3`).
    pub fn file(&self, m: &str) -> PathBuf {
        self.prefix
            .with_file_name(format!("{}_{m}{}", self.stem, self.ext))
    }

    /// The six files, `L1` to `L3`, then `V1` to `V3`.
    pub fn files(&self) -> Vec<PathBuf> {
        EIGENVALUES
            .iter()
            .chain(&EIGENVECTORS)
            .map(|m| self.file(m))
            .collect()
    }

    /// How errors and `info` name the set: `PREFIX_{L1,L2,L3,V1,V2,V3}.nii.gz`.
    fn pattern(&self) -> String {
        format!(
            "{}_{{L1,L2,L3,V1,V2,V3}}{}",
            escape_path(Path::new(&self.stem)),
            self.ext
        )
    }
}

/// Read the set as one tensor field. Errors name the file at fault (the one missing, unreadable
/// or differing from the first), not necessarily the one given.
pub fn read(inputs: &Inputs, set: &EigenSet, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    super::guard::catch_panics(&set.given, || read_set(inputs, set, opts))
}

fn read_set(inputs: &Inputs, set: &EigenSet, opts: &ReadOptions) -> Result<TensorField, LoadError> {
    let files = set.files();
    // The file named is looked at first: if it is missing, that is all there is to say.
    if files.contains(&set.given) && !inputs.exists(&set.given) {
        return Err(LoadError::new(&set.given, LoadErrorKind::Missing));
    }
    if let Some(missing) = files.iter().find(|p| !inputs.exists(p)) {
        return Err(LoadError::new(
            missing,
            LoadErrorKind::SetMemberMissing { set: set.pattern() },
        ));
    }
    let mut opened = Vec::with_capacity(files.len());
    for p in &files {
        opened.push(inputs.open(p).map_err(|k| LoadError::new(p, k))?);
    }
    let mut heads: Vec<Header> = Vec::with_capacity(files.len());
    for (k, (p, b)) in files.iter().zip(&opened).enumerate() {
        let (member, want) = if k < 3 {
            (EIGENVALUES[k], 1)
        } else {
            (EIGENVECTORS[k - 3], 3)
        };
        let head = nifti::read_header(b, |c| member_components(member, want, c))
            .map_err(|e| LoadError::new(p, e))?;
        heads.push(head);
    }
    let dims = heads[0].dims();
    let affine = heads[0]
        .affine()
        .map_err(|e| LoadError::new(&files[0], e))?;
    let first = file_name(&files[0]);
    for (p, h) in files.iter().zip(&heads).skip(1) {
        let at = |e| LoadError::new(p, e);
        if h.dims() != dims {
            let d = h.dims();
            return Err(at(field(
                "dim",
                format!(
                    "{}×{}×{} voxels, {first} has {}×{}×{}: the files of an FSL eigen set share one lattice",
                    d[0], d[1], d[2], dims[0], dims[1], dims[2]
                ),
            )));
        }
        let (a, source) = h.affine().map_err(at)?;
        let off = largest_difference(&a, &affine.0);
        if off > 1e-6 * scale(&affine.0) {
            return Err(at(field(
                source,
                format!(
                    "the voxel-to-world matrix differs from {first}'s (by up to {off:e}): \
                     the files of an FSL eigen set share one lattice"
                ),
            )));
        }
    }
    let n = dims[0] * dims[1] * dims[2];
    // Each member's values are read straight to f64 and added in, one eigenpair at a time; the
    // vectors grow with the values read, never ahead of them (a header asking for more than its
    // data holds allocates nothing for it).
    let mut tensors: Vec<[f64; 9]> = Vec::new();
    for k in 0..3 {
        let mut l: Vec<f64> = Vec::new();
        heads[k]
            .each_value(&opened[k], |_, _, x| l.push(x))
            .map_err(|err| LoadError::new(&files[k], err))?;
        let mut e: Vec<[f64; 3]> = Vec::new();
        heads[3 + k]
            .each_value(&opened[3 + k], |c, v, x| {
                if c == 0 {
                    e.push([x, 0.0, 0.0]);
                } else {
                    e[v][c] = x;
                }
            })
            .map_err(|err| LoadError::new(&files[3 + k], err))?;
        if k == 0 {
            tensors.resize(n, [0.0; 9]);
        }
        for ((t, l), ev) in tensors.iter_mut().zip(&l).zip(&e) {
            for i in 0..3 {
                for j in i..3 {
                    t[3 * i + j] += l * ev[i] * ev[j];
                }
            }
        }
    }
    for t in &mut tensors {
        // Mirrored, not computed twice: the rebuilt tensor is exactly symmetric.
        for i in 0..3 {
            for j in 0..i {
                t[3 * i + j] = t[3 * j + i];
            }
        }
    }
    let array = TensorArrayInfo {
        name: set.pattern(),
        components: 6,
        location: Location::Point,
    };
    let layout = Layout {
        order: "fsl-eigen".into(),
        why: Why::Names,
    };
    nifti::lattice_field(dims, affine, opts, tensors.into(), array, layout)
        .map_err(|e| LoadError::new(&files[0], e))
}

fn field(name: &str, message: String) -> LoadErrorKind {
    LoadErrorKind::Field {
        field: name.into(),
        message,
    }
}

fn file_name(p: &Path) -> String {
    escape_for_error(p.file_name().unwrap_or_default().as_encoded_bytes())
}

/// `_L1` .. `_L3` hold one eigenvalue per voxel, `_V1` .. `_V3` one 3-vector.
fn member_components(member: &str, want: usize, found: usize) -> Result<(), LoadErrorKind> {
    if found == want {
        return Ok(());
    }
    let what = if want == 1 {
        "a 3-D map of one eigenvalue per voxel"
    } else {
        "a 4-D volume of 3 (the eigenvector's x, y, z)"
    };
    let found = if found == 1 {
        "one value".to_string()
    } else {
        format!("{found} values")
    };
    Err(field(
        "dim",
        format!("{found} per voxel; FSL's _{member} is {what}"),
    ))
}

fn largest_difference(a: &Matrix4<f64>, b: &Matrix4<f64>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The matrix's largest entry, at least 1 (a tolerance for float32 header numbers).
fn scale(a: &Matrix4<f64>) -> f64 {
    a.iter().map(|x| x.abs()).fold(1.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_member_or_a_prefix_names_the_set() {
        let fs = Inputs::file_system();
        let named_by = |p: &Path| EigenSet::named_by(p, &fs);
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let set = named_by(&d.join("dti_V2.nii.gz")).unwrap();
        assert_eq!(set.file("L1"), d.join("dti_L1.nii.gz"));
        let set = named_by(&d.join("a_b_L3.nii")).unwrap();
        assert_eq!(set.file("V1"), d.join("a_b_V1.nii"));
        assert_eq!(set.pattern(), "a_b_{L1,L2,L3,V1,V2,V3}.nii");
        // Other names are not sets; a prefix only when its _V1 exists and it does not.
        for other in [
            "dti_tensor.nii.gz",
            "_L1.nii",
            "dti_V4.nii",
            "dti_L1.nrrd",
            "dti",
        ] {
            assert_eq!(named_by(&d.join(other)), None, "{other}");
        }
        std::fs::write(d.join("dti_V1.nii"), b"").unwrap();
        let set = named_by(&d.join("dti")).unwrap();
        assert_eq!(set.file("L2"), d.join("dti_L2.nii"));
        std::fs::write(d.join("dti_V1.nii.gz"), b"").unwrap();
        assert_eq!(
            named_by(&d.join("dti")).unwrap().file("V3"),
            d.join("dti_V3.nii.gz")
        );
        std::fs::write(d.join("dti"), b"").unwrap();
        assert_eq!(named_by(&d.join("dti")), None);
    }
}
