//! What a file holds: its field kind, as [`crate::shape::GlyphKind`] names the glyph kinds. The
//! header decides ([`FieldKind::of_file`], the one probe), before anything is read; the readers
//! then read that kind, and every front end asks the kind rather than probing the file itself.
//! What each kind offers the front ends (the glyphs it is drawn as, its options) is
//! [`crate::staging::Offers`], beside the staging that builds its scenes.
//!
//! Adding a kind: the docs/book's developer guide has the checklist (Layout → "Adding a field
//! kind").

use std::path::Path;

use super::{Inputs, ReadOptions, fsl_eigen, guard, mif, nifti, sh_field};

/// A kind of field a file can hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FieldKind {
    /// Symmetric 3×3 tensors (DTI, stress), one per point.
    Tensors,
    /// Spherical-harmonic series (fibre ODFs), one per voxel.
    Series,
    /// Fibre directions, a few per voxel (`sh2peaks`' images).
    Peaks,
}

crate::names::named_values!(FieldKind {
    Tensors => "tensors",
    Series => "series",
    Peaks => "peaks",
});

impl FieldKind {
    /// How messages say what a file of this kind holds.
    pub fn holds(self) -> &'static str {
        match self {
            FieldKind::Tensors => "tensors",
            FieldKind::Series => "SH series",
            FieldKind::Peaks => "fibre peaks",
        }
    }

    /// The kind of the file `path` among `inputs`: the one `opts.holds` names, else from its
    /// header: peaks for an MRtrix image whose `command_history` says `sh2peaks` wrote it and for
    /// a NIfTI file laid out as DIPY's `X×Y×Z×N×3` ([`super::peaks`]); SH series for a
    /// NIfTI-1 or MRtrix image of an SH count of volumes other than 6 (`field::sh_field` gives
    /// the rule), or of any count when `opts.sh_basis` is given; else tensors. A file whose
    /// header cannot be read is taken as tensors, whose reader then says what is wrong with it.
    pub fn of_file(inputs: &Inputs, path: &Path, opts: &ReadOptions) -> Self {
        if let Some(kind) = opts.holds {
            return kind;
        }
        let nifti = nifti::is_nifti_path(path);
        if !(nifti || mif::is_mif_path(path))
            || fsl_eigen::EigenSet::named_by(path, inputs).is_some()
        {
            return FieldKind::Tensors;
        }
        let probe = || -> Result<FieldKind, crate::error::LoadErrorKind> {
            let series = |yes: bool| {
                if yes || opts.sh_basis.is_some() {
                    FieldKind::Series
                } else {
                    FieldKind::Tensors
                }
            };
            Ok(if nifti {
                match nifti::peaks::kind_probe(&inputs.open(path)?) {
                    Ok((_, true)) => FieldKind::Peaks,
                    _ => series(sh_field::is_sh_count(nifti::sh_probe(&inputs.open(path)?)?)),
                }
            } else {
                let p = mif::kind_probe(inputs, path)?;
                if p.peaks {
                    FieldKind::Peaks
                } else {
                    series(!p.dwi && sh_field::is_sh_count(p.count))
                }
            })
        };
        guard::guarded(path, probe).unwrap_or(if opts.sh_basis.is_some() {
            FieldKind::Series
        } else {
            FieldKind::Tensors
        })
    }
}
