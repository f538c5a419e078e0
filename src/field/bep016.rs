//! BIDS BEP016 diffusion-model derivatives: which axes a tensor file's tensors are in, from its
//! JSON sidecar.
//!
//! BEP016 (bids-standard/bids-bep016, `src/derivatives/05-diffusion-derivatives.md`) stores a
//! tensor fit as `sub-<label>[_ses-<label>]_model-<label>[_param-tensor]_dwimap.nii[.gz]`: six
//! volumes Dxx, Dxy, Dxz, Dyy, Dyz, Dzz (FSL's upper-triangle order), with a sidecar
//! `…_model-<label>_dwimap.json` (or the file's own name with `.json`) whose REQUIRED
//! `ReferenceAxes` is `ijk` (the image axes: tensors rotated to world by the affine, our
//! `voxel` frame) or `xyz` (scanner axes: our `world` frame), and whose
//! `OrientationRepresentation` is `param`.
//!
//! A file named so without a usable sidecar is read with the NIfTI default (image axes, FSL's
//! order: what `ijk` means) and the field carries one line saying why ([`ReadMeta::notes`]).
//!
//! [`ReadMeta::notes`]: super::ReadMeta::notes

use std::path::Path;

pub use super::frame::Sidecar;
use super::frame::TensorFrame;
use super::inputs::Inputs;
use crate::error::{LoadErrorKind, escape_for_error};

/// A sidecar larger than this is not read (real ones are a few hundred bytes).
pub const SIDECAR_MAX_BYTES: u64 = 1 << 20;

/// How a BEP016 file is to be read.
pub(crate) struct Decision {
    pub sidecar: Sidecar,
    /// The frame the sidecar gives (`None`: the default).
    pub frame: Option<TensorFrame>,
    /// Why the default is used, when it is.
    pub note: Option<String>,
}

/// Whether `path` is named as a BEP016 diffusion-model map: `…_dwimap.nii[.gz]` with a
/// `model-<label>` entity.
pub fn is_bep016_name(path: &Path) -> bool {
    stem(path).is_some_and(|s| {
        s.ends_with("_dwimap") && s.split('_').any(|e| e.starts_with("model-") && e.len() > 6)
    })
}

/// The name without `.nii` or `.nii.gz`.
fn stem(path: &Path) -> Option<String> {
    let name = path.file_name()?.to_str()?;
    let lower = name.to_ascii_lowercase();
    let cut = if lower.ends_with(".nii.gz") {
        7
    } else if lower.ends_with(".nii") {
        4
    } else {
        return None;
    };
    Some(name[..name.len() - cut].to_string())
}

/// The sidecars that may describe `path`, nearest first: its own name with `.json`, then the
/// name without its `param-` entity (one sidecar per model, as BEP016 writes it).
fn candidates(path: &Path) -> Vec<String> {
    let Some(s) = stem(path) else {
        return Vec::new();
    };
    let own = format!("{s}.json");
    let model: Vec<&str> = s.split('_').filter(|e| !e.starts_with("param-")).collect();
    let model = format!("{}.json", model.join("_"));
    if model == own {
        vec![own]
    } else {
        vec![own, model]
    }
}

/// Read the sidecar of the BEP016 file `path` from `inputs` (recorded as read) and decide.
pub(crate) fn decide(inputs: &Inputs, path: &Path) -> Decision {
    let names = candidates(path);
    let found = names
        .iter()
        .find(|n| inputs.is_named(&Inputs::next_to(path, n)));
    let Some(name) = found else {
        let name = names.last().cloned().unwrap_or_default();
        let note = format!("no BEP016 sidecar ({})", escape_for_error(&name));
        return default(name, note);
    };
    let p = Inputs::next_to(path, name);
    match read_sidecar(inputs, &p) {
        Ok(axes) => Decision {
            frame: Some(if axes == "ijk" {
                TensorFrame::Voxel
            } else {
                TensorFrame::World
            }),
            sidecar: Sidecar {
                name: name.clone(),
                reference_axes: Some(axes.to_string()),
            },
            note: None,
        },
        Err(why) => {
            let note = format!("BEP016 sidecar {}: {why}", escape_for_error(name));
            default(name.clone(), note)
        }
    }
}

fn default(name: String, why: String) -> Decision {
    Decision {
        sidecar: Sidecar {
            name,
            reference_axes: None,
        },
        frame: None,
        note: Some(format!(
            "{why}; read with the default: tensors in the image axes (ReferenceAxes ijk), \
             Dxx Dxy Dxz Dyy Dyz Dzz"
        )),
    }
}

/// `ijk` or `xyz` from the sidecar at `p`, or why it cannot say.
fn read_sidecar(inputs: &Inputs, p: &Path) -> Result<&'static str, String> {
    let input = inputs.open(p).map_err(|e| e.to_string())?;
    if input.len() > SIDECAR_MAX_BYTES {
        return Err(format!(
            "{} bytes, more than a sidecar's {SIDECAR_MAX_BYTES}",
            input.len()
        ));
    }
    let bytes = input.read_all().map_err(|e: LoadErrorKind| e.to_string())?;
    let json: serde_json::Value =
        serde_json::from_slice(&bytes).map_err(|e| format!("not valid JSON ({e})"))?;
    let obj = json.as_object().ok_or("not a JSON object")?;
    if let Some(rep) = obj.get("OrientationRepresentation")
        && rep.as_str() != Some("param")
    {
        return Err(format!(
            "OrientationRepresentation is {}, not \"param\"",
            shown(rep)
        ));
    }
    match obj.get("ReferenceAxes") {
        None => Err("no ReferenceAxes (REQUIRED)".into()),
        Some(v) => match v.as_str() {
            Some("ijk") => Ok("ijk"),
            Some("xyz") => Ok("xyz"),
            _ => Err(format!("ReferenceAxes is {}, not ijk or xyz", shown(v))),
        },
    }
}

/// A JSON value from the file, escaped and cut as file text is shown.
fn shown(v: &serde_json::Value) -> String {
    escape_for_error(v.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decide_with(sidecar: Option<&str>) -> Decision {
        let nii = "d/sub-01_model-DTI_param-tensor_dwimap.nii.gz";
        let mut files = vec![(nii.to_string(), Vec::new())];
        if let Some(s) = sidecar {
            files.push((
                "d/sub-01_model-DTI_dwimap.json".into(),
                s.as_bytes().to_vec(),
            ));
        }
        let inputs = Inputs::named(files);
        let d = decide(&inputs, Path::new(nii));
        if sidecar.is_some() {
            assert_eq!(
                inputs.paths_read(),
                [Path::new("d/sub-01_model-DTI_dwimap.json")]
            );
        }
        d
    }

    #[test]
    fn names_of_bep016_maps() {
        for yes in [
            "sub-01_model-DTI_param-tensor_dwimap.nii.gz",
            "sub-01_ses-2_model-DTI_dwimap.nii",
        ] {
            assert!(is_bep016_name(Path::new(yes)), "{yes}");
        }
        for no in [
            "sub-01_dwi.nii.gz",
            "sub-01_model-_dwimap.nii.gz",
            "sub-01_model-DTI_dwimap.json",
            "tensors.nii.gz",
        ] {
            assert!(!is_bep016_name(Path::new(no)), "{no}");
        }
        assert_eq!(
            candidates(Path::new("sub-01_model-DTI_param-tensor_dwimap.nii.gz")),
            [
                "sub-01_model-DTI_param-tensor_dwimap.json",
                "sub-01_model-DTI_dwimap.json"
            ]
        );
    }

    #[test]
    fn the_sidecar_decides_the_frame_or_says_why_not() {
        let ok = |axes: &str| {
            format!(r#"{{"ReferenceAxes": "{axes}", "OrientationRepresentation": "param"}}"#)
        };
        let d = decide_with(Some(&ok("ijk")));
        assert_eq!(d.frame, Some(TensorFrame::Voxel));
        assert!(d.note.is_none());
        assert_eq!(d.sidecar.reference_axes.as_deref(), Some("ijk"));
        assert_eq!(
            decide_with(Some(&ok("xyz"))).frame,
            Some(TensorFrame::World)
        );
        for (sidecar, why) in [
            (None, "no BEP016 sidecar (sub-01_model-DTI_dwimap.json)"),
            (Some("{"), "not valid JSON"),
            (Some("[1]"), "not a JSON object"),
            (Some("{}"), "no ReferenceAxes (REQUIRED)"),
            (
                Some(r#"{"ReferenceAxes": "lps"}"#),
                "ReferenceAxes is \"lps\"",
            ),
            (
                Some(r#"{"ReferenceAxes": "ijk", "OrientationRepresentation": "dec"}"#),
                "OrientationRepresentation is \"dec\"",
            ),
        ] {
            let d = decide_with(sidecar);
            assert_eq!(d.frame, None);
            let note = d.note.unwrap();
            assert!(note.contains(why), "{note}");
            assert!(note.contains("read with the default"), "{note}");
            assert_eq!(note.lines().count(), 1);
        }
    }
}
