//! The defaults a researcher expects of each kind of data: a DTI volume opens as mrview,
//! FSLeyes or Slicer show it (direction-encoded colour on black, glyph shapes readable, the
//! middle axial slice seen face-on); a stress field or the demo as ParaView shows it (the
//! whole field on white from an oblique view, in shape classes, or for a stress field, whose
//! tensors are mostly indefinite, in von Mises stress: [`ColorScheme::Auto`]).
//! (The table of them for users: docs/book/src/user-guide/dti.md, "Defaults for DTI files".)
//!
//! The kind is told by the file format, not guessed from the tensors: NIfTI, NRRD and MRtrix are the
//! formats diffusion tools write; VTK files, where stress and DTI fields both occur, keep the
//! general defaults. A field handed over in memory says which it is (the Python package: a
//! lattice of tensors, a DIPY fit or a nibabel image is diffusion data, tensors at points are
//! not). Every default is an option's default only: a flag given wins.

use crate::glyph::{ColorScheme, SizeBy};
use crate::staging::Source;

/// What kind of data a source holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataKind {
    /// Diffusion tensors: NIfTI (`.nii`, `.nii.gz`), NRRD (`.nrrd`, `.nhdr`) and MRtrix
    /// (`.mif`, `.mif.gz`, `.mih`) files.
    Diffusion,
    /// VTK files and the built-in demo.
    General,
}

/// The defaults of a kind of data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Defaults {
    pub color: ColorScheme,
    /// Linear RGBA in [0, 1].
    pub background: [f64; 4],
    pub size_by: SizeBy,
    /// One slice shown is seen face-on (unless a view is asked for).
    pub face_on: bool,
    /// With no slice asked for, the middle axial slice is shown (not the whole volume).
    pub middle_slice: bool,
}

impl DataKind {
    pub fn of(source: &Source) -> Self {
        match source {
            Source::File(p)
                if crate::field::nifti::is_nifti_path(p)
                    || crate::field::nrrd::is_nrrd_path(p)
                    || crate::field::mif::is_mif_path(p) =>
            {
                DataKind::Diffusion
            }
            Source::Field(f) if f.diffusion => DataKind::Diffusion,
            Source::Bytes(b)
                if crate::field::nifti::is_nifti_path(std::path::Path::new(&b.name))
                    || crate::field::mif::is_mif_path(std::path::Path::new(&b.name)) =>
            {
                DataKind::Diffusion
            }
            _ => DataKind::General,
        }
    }

    pub fn defaults(self) -> Defaults {
        match self {
            // DEC on black as the DTI tools show it; every glyph the same size so its shape
            // reads even where CSF-like tensors set the scale (MD has its own colour scheme and
            // underlay).
            DataKind::Diffusion => Defaults {
                color: ColorScheme::Dec,
                background: [0.0, 0.0, 0.0, 1.0],
                size_by: SizeBy::None,
                face_on: true,
                middle_slice: true,
            },
            DataKind::General => Defaults {
                color: ColorScheme::Auto,
                background: [1.0, 1.0, 1.0, 1.0],
                size_by: SizeBy::Auto,
                face_on: false,
                middle_slice: false,
            },
        }
    }
}
