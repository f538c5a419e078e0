//! The BEP016 tensor and ODF maps of a BIDS derivatives folder, participant by participant, as a
//! BIDS App finds its inputs (`bids_dir output_dir participant [--participant-label L …]`).
//!
//! A participant is a `sub-<label>` folder; its maps are files of `dwi/` (and of each
//! `ses-<label>/dwi/`):
//! - **tensor maps**, named `…_model-DTI[_param-tensor]_dwimap.nii[.gz]`, or `…_param-tensor_…`
//!   of any model ([`crate::field::bep016`] reads them);
//! - **ODF maps** (SH coefficients: a CSD fit's fibre ODFs), any name with the entity
//!   `param-fod` or `param-sh` (of any model) that ends `_dwimap.nii[.gz]` or is an MRtrix
//!   image (`.mif[.gz]`), e.g. `sub-01_model-CSD_param-fod_dwimap.nii.gz`,
//!   `sub-01_model-CSD_param-fod.mif`. Both spellings are taken
//!   because pipelines differ in which they write. The name only proposes: the report confirms
//!   each by its header ([`crate::field::FieldKind::of_file`]) and fails on one that holds no SH series,
//!   naming it, rather than passing it over in silence.
//! - **peaks maps** (fibre directions, 3 values a peak), named with the entity `param-peaks` (of
//!   any model) as ODF maps are (`sub-01_model-CSD_param-peaks_dwimap.nii.gz`, `…_param-peaks.mif`):
//!   the spelling pipelines write beside their `param-fod` maps. Here the name says what a NIfTI
//!   header cannot (9 volumes are three peaks or a 3×3 tensor): the map is read as peaks.
//!
//! No file is two of these (each has its own `param-`). Nothing is read but folder listings;
//! the order is the labels' (sorted), then per folder its tensor maps, its ODF maps and its
//! peaks maps, each by name, so that a run is the same on every machine.

use std::path::{Path, PathBuf};

use crate::error::escape_path;
use crate::field::FieldKind;
use crate::field::bep016::is_bep016_name;

/// One map found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Map {
    /// The session label (without `ses-`), if the map is in a session folder.
    pub session: Option<String>,
    pub path: PathBuf,
    pub kind: FieldKind,
}

/// A participant and its maps (none: the participant is there but has nothing to report on).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Participant {
    /// The label, without `sub-`.
    pub label: String,
    pub maps: Vec<Map>,
}

/// Why the folder gives no participants to report on.
#[derive(Debug, thiserror::Error)]
pub enum FindError {
    #[error("{}: not a folder", escape_path(.0))]
    NotAFolder(PathBuf),
    #[error("{}: {error}", escape_path(.path))]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{}: no participant {label} (no folder sub-{label})", escape_path(.root))]
    NoParticipant { root: PathBuf, label: String },
    #[error("{}: no participant (no sub-<label> folder)", escape_path(.0))]
    Empty(PathBuf),
}

/// The participants of the derivatives folder `root` (those of `labels` when it names some,
/// with or without their `sub-` prefix, as BIDS Apps take them), each with its tensor maps.
pub fn participants(root: &Path, labels: &[String]) -> Result<Vec<Participant>, FindError> {
    if !root.is_dir() {
        return Err(FindError::NotAFolder(root.to_path_buf()));
    }
    let mut found: Vec<String> = entries(root)?
        .into_iter()
        .filter(|(_, dir)| *dir)
        .filter_map(|(name, _)| name.strip_prefix("sub-").map(str::to_string))
        .filter(|l| !l.is_empty())
        .collect();
    found.sort();
    let chosen: Vec<String> = if labels.is_empty() {
        if found.is_empty() {
            return Err(FindError::Empty(root.to_path_buf()));
        }
        found
    } else {
        let mut chosen = Vec::new();
        for l in labels {
            let l = l.strip_prefix("sub-").unwrap_or(l).to_string();
            if !found.contains(&l) {
                return Err(FindError::NoParticipant {
                    root: root.to_path_buf(),
                    label: crate::error::escape_for_error(&l),
                });
            }
            if !chosen.contains(&l) {
                chosen.push(l);
            }
        }
        chosen.sort();
        chosen
    };
    chosen
        .into_iter()
        .map(|label| {
            let folder = root.join(format!("sub-{label}"));
            let mut maps = maps_in(&folder.join("dwi"), None)?;
            let mut sessions: Vec<String> = entries(&folder)?
                .into_iter()
                .filter(|(_, dir)| *dir)
                .filter_map(|(n, _)| n.strip_prefix("ses-").map(str::to_string))
                .collect();
            sessions.sort();
            for s in sessions {
                let dwi = folder.join(format!("ses-{s}")).join("dwi");
                maps.extend(maps_in(&dwi, Some(s))?);
            }
            Ok(Participant { label, maps })
        })
        .collect()
}

/// Whether a BEP016 map's name says it holds tensors.
fn is_tensor_map(name: &str) -> bool {
    let entities: Vec<&str> = name.split('_').collect();
    let param = entities.iter().find_map(|e| e.strip_prefix("param-"));
    let model = entities.iter().find_map(|e| e.strip_prefix("model-"));
    match param {
        Some(p) => p == "tensor",
        None => model == Some("DTI"),
    }
}

/// Whether a name is an ODF map's ([module doc](self)).
pub fn is_odf_map(name: &str) -> bool {
    map_entities(name).is_some_and(|b| b.split('_').any(|e| e == "param-fod" || e == "param-sh"))
}

/// Whether a name is a peaks map's ([module doc](self)).
pub fn is_peaks_map(name: &str) -> bool {
    map_entities(name).is_some_and(|b| b.split('_').any(|e| e == "param-peaks"))
}

/// A map's name without its `_dwimap.nii[.gz]` or `.mif[.gz]` ending; `None` for another.
fn map_entities(name: &str) -> Option<&str> {
    [".nii.gz", ".nii"]
        .iter()
        .find_map(|e| name.strip_suffix(e)?.strip_suffix("_dwimap"))
        .or_else(|| {
            [".mif.gz", ".mif"]
                .iter()
                .find_map(|e| name.strip_suffix(e))
        })
}

/// The maps in the folder `dwi` (none if it is not there): its tensor maps, then its ODF maps,
/// each sorted by name.
fn maps_in(dwi: &Path, session: Option<String>) -> Result<Vec<Map>, FindError> {
    if !dwi.is_dir() {
        return Ok(Vec::new());
    }
    // Sorted by kind (tensors, ODFs, peaks), then by name.
    let order = |k: FieldKind| match k {
        FieldKind::Tensors => 0,
        FieldKind::Series => 1,
        FieldKind::Peaks => 2,
    };
    let mut names: Vec<(u8, FieldKind, String)> = entries(dwi)?
        .into_iter()
        .filter(|(_, dir)| !dir)
        .filter_map(|(n, _)| {
            let kind = if is_bep016_name(Path::new(&n)) && is_tensor_map(&n) {
                FieldKind::Tensors
            } else if is_odf_map(&n) {
                FieldKind::Series
            } else if is_peaks_map(&n) {
                FieldKind::Peaks
            } else {
                return None;
            };
            Some((order(kind), kind, n))
        })
        .collect();
    names.sort_by(|a, b| (a.0, &a.2).cmp(&(b.0, &b.2)));
    Ok(names
        .into_iter()
        .map(|(_, kind, n)| Map {
            session: session.clone(),
            path: dwi.join(n),
            kind,
        })
        .collect())
}

/// The names in `dir` (those that are UTF-8: BIDS names are ASCII) and whether each is a folder
/// (symlinks followed).
fn entries(dir: &Path) -> Result<Vec<(String, bool)>, FindError> {
    let io = |error| FindError::Io {
        path: dir.to_path_buf(),
        error,
    };
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).map_err(io)? {
        let e = e.map_err(io)?;
        if let Ok(name) = e.file_name().into_string() {
            out.push((name, e.path().is_dir()));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bids() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bids/derivatives")
    }

    fn names(p: &Participant) -> Vec<String> {
        p.maps
            .iter()
            .map(|m| m.path.file_name().unwrap().to_string_lossy().into_owned())
            .collect()
    }

    #[test]
    fn every_participant_and_session_of_the_test_folder() {
        let all = participants(&bids(), &[]).unwrap();
        let labels: Vec<&str> = all.iter().map(|p| p.label.as_str()).collect();
        assert_eq!(labels, ["01", "02", "03", "04", "05"]);
        assert_eq!(
            names(&all[2]),
            [
                "sub-03_ses-1_model-DTI_param-tensor_dwimap.nii.gz",
                "sub-03_ses-2_model-DTI_param-tensor_dwimap.nii.gz"
            ]
        );
        assert_eq!(all[2].maps[1].session.as_deref(), Some("2"));
        assert_eq!(all[0].maps.len(), 1);
        assert_eq!(all[0].maps[0].session, None);
    }

    #[test]
    fn labels_with_or_without_their_prefix_and_unknown_ones() {
        let some = participants(&bids(), &["sub-05".into(), "02".into(), "05".into()]).unwrap();
        let labels: Vec<&str> = some.iter().map(|p| p.label.as_str()).collect();
        assert_eq!(labels, ["02", "05"]);
        let e = participants(&bids(), &["99".into()])
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("no participant 99 (no folder sub-99)"), "{e}");
        let e = participants(&bids().join("dataset_description.json"), &[])
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("not a folder"), "{e}");
    }

    #[test]
    fn only_tensor_maps_are_taken() {
        let dir = tempfile::tempdir().unwrap();
        let dwi = dir.path().join("sub-a").join("dwi");
        std::fs::create_dir_all(&dwi).unwrap();
        for n in [
            "sub-a_model-DTI_param-tensor_dwimap.nii.gz",
            "sub-a_model-DTI_dwimap.nii",
            "sub-a_model-DKI_param-tensor_dwimap.nii.gz",
            "sub-a_model-DTI_param-fa_dwimap.nii.gz",
            "sub-a_model-DTI_dwimap.json",
            "sub-a_dwi.nii.gz",
        ] {
            std::fs::write(dwi.join(n), b"").unwrap();
        }
        let p = participants(dir.path(), &[]).unwrap();
        assert_eq!(
            names(&p[0]),
            [
                "sub-a_model-DKI_param-tensor_dwimap.nii.gz",
                "sub-a_model-DTI_dwimap.nii",
                "sub-a_model-DTI_param-tensor_dwimap.nii.gz"
            ]
        );
        let e = participants(&dwi, &[]).unwrap_err().to_string();
        assert!(e.ends_with("no participant (no sub-<label> folder)"), "{e}");
    }

    #[test]
    fn odf_and_peaks_maps_by_name_after_the_tensor_maps() {
        let dir = tempfile::tempdir().unwrap();
        let dwi = dir.path().join("sub-a").join("dwi");
        std::fs::create_dir_all(&dwi).unwrap();
        for n in [
            "sub-a_model-CSD_param-fod_dwimap.nii.gz",
            "sub-a_model-DTI_param-tensor_dwimap.nii.gz",
            "sub-a_model-msmt_param-sh_dwimap.nii",
            "sub-a_model-CSD_param-fod.mif",
            "sub-a_model-CSD_param-fod.mif.gz",
            "sub-a_model-CSD_param-peaks_dwimap.nii.gz",
            "sub-a_model-CSD_param-peaks.mif",
            // Not maps: no parameter of one, no map suffix, a sidecar.
            "sub-a_model-CSD_param-peaksx_dwimap.nii.gz",
            "sub-a_model-CSD_param-fod_dwi.nii.gz",
            "sub-a_model-CSD_param-fod_dwimap.json",
            "sub-a_model-CSD_dwimap.mif",
            "sub-a_model-CSD_param-fodx_dwimap.nii.gz",
        ] {
            std::fs::write(dwi.join(n), b"").unwrap();
        }
        let p = participants(dir.path(), &[]).unwrap();
        assert_eq!(
            names(&p[0]),
            [
                "sub-a_model-DTI_param-tensor_dwimap.nii.gz",
                "sub-a_model-CSD_param-fod.mif",
                "sub-a_model-CSD_param-fod.mif.gz",
                "sub-a_model-CSD_param-fod_dwimap.nii.gz",
                "sub-a_model-msmt_param-sh_dwimap.nii",
                "sub-a_model-CSD_param-peaks.mif",
                "sub-a_model-CSD_param-peaks_dwimap.nii.gz",
            ]
        );
        let kinds: Vec<FieldKind> = p[0].maps.iter().map(|m| m.kind).collect();
        assert_eq!(kinds[0], FieldKind::Tensors);
        assert!(kinds[1..5].iter().all(|k| *k == FieldKind::Series));
        assert!(kinds[5..].iter().all(|k| *k == FieldKind::Peaks));
    }
}
