//! The `info` report: what a field contains, as JSON ([`InfoReport`]) or as text
//! ([`human_summary`]).

use std::fmt::Write as _;

use serde::Serialize;

use crate::field::bep016::Sidecar;
use crate::field::frame::{FrameInfo, Layout, Why};
use crate::field::{TensorArrayInfo, TensorField};
use crate::glyph::GlyphSet;
use crate::tensor::eigen::{symmetric_eigen, symmetrise};
use crate::tensor::stress;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InfoReport {
    pub format: String,
    pub dataset: String,
    pub dims: Option<[usize; 3]>,
    pub points: usize,
    pub cells: usize,
    pub tensor_array: TensorArrayInfo,
    /// How 6 components were ordered and why (the file, `--order` or the default).
    pub layout: Option<Layout>,
    /// The frames positions and tensors were read in.
    pub frame: Option<FrameInfo>,
    /// A BEP016 map's sidecar: its name and the `ReferenceAxes` that decided the frame (null
    /// when the default was used: see `notes`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bep016_sidecar: Option<Sidecar>,
    /// What the reader assumed, one line each.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    pub tensors: usize,
    pub valid: usize,
    pub skipped: Skipped,
    pub symmetrised: usize,
    pub indefinite: usize,
    pub eigenvalues: EigenRange,
    pub fa: FaStats,
    /// Ranges of the stress measures over valid tensors (the principal stresses' are
    /// `eigenvalues`).
    pub stress: StressRanges,
    pub classes: Classes,
    pub samples: Vec<Sample>,
}

/// A measure's range over valid tensors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Range {
    pub min: f64,
    pub max: f64,
}

/// The stress measures' ranges ([`crate::tensor::stress`]; definitions as VTK's
/// `vtkYieldCriteria`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StressRanges {
    pub von_mises: Range,
    pub tresca: Range,
    /// tr σ / 3 (the MD of diffusion tensors).
    pub mean: Range,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Skipped {
    pub nan: usize,
    pub inf: usize,
    pub zero: usize,
    /// Eigenvalues beyond the f32 range a glyph stores (±3.4e38).
    pub overflow: usize,
    /// Confidence below 0.5 (NRRD masked tensors); not counted in `zero`.
    pub masked: usize,
}

/// Component-wise range of (λ1, λ2, λ3) over valid tensors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EigenRange {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaStats {
    pub min: f64,
    pub mean: f64,
    pub max: f64,
}

/// Shape-class counts with the default threshold τ = 0.5.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Classes {
    pub linear: usize,
    pub planar: usize,
    pub spherical: usize,
    pub unclassified: usize,
}

/// One requested tensor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sample {
    pub index: usize,
    pub position: [f64; 3],
    /// Row-major, exactly as stored in the file (before rotation and symmetrisation).
    pub tensor: [f64; 9],
    /// Eigenvalues of the symmetrised world tensor, descending. For NaN/Inf tensors these are
    /// not finite numbers and serialise as `null`.
    pub eigenvalues: [f64; 3],
    /// Rows e1, e2, e3 (world space), each unit with its largest-magnitude component positive.
    pub eigenvectors: [[f64; 3]; 3],
    /// σ1 ≥ σ2 ≥ σ3 (the eigenvalues, as VTK's `vtkTensorPrincipalInvariants` orders them).
    pub principal_stresses: [f64; 3],
    /// √(½((σ1 − σ2)² + (σ2 − σ3)² + (σ3 − σ1)²)).
    pub von_mises: f64,
    /// σ1 − σ3.
    pub tresca: f64,
    /// tr σ / 3.
    pub mean: f64,
}

/// Build the report. `samples` are tensor indices in file order; an index out of range is an
/// error naming the valid range.
pub fn info_report(
    field: &TensorField,
    set: &GlyphSet,
    samples: &[usize],
) -> Result<InfoReport, String> {
    let s = &set.stats;
    let samples = samples
        .iter()
        .map(|&i| sample(field, i))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(InfoReport {
        format: field.format.clone(),
        dataset: field.dataset.as_str().to_string(),
        dims: field.dims,
        points: field.points,
        cells: field.cells,
        tensor_array: field.array.clone(),
        layout: field.meta.layout.clone(),
        frame: field.meta.frame.clone(),
        bep016_sidecar: field.meta.sidecar.clone(),
        notes: field.meta.notes.clone(),
        tensors: s.tensors,
        valid: s.valid,
        skipped: Skipped {
            nan: s.skipped_nan,
            inf: s.skipped_inf,
            // Masked voxels are held as zero tensors so that the lattice stays whole.
            zero: s.skipped_zero.saturating_sub(field.meta.masked),
            masked: field.meta.masked,
            overflow: s.skipped_overflow,
        },
        symmetrised: s.symmetrised,
        indefinite: s.indefinite,
        eigenvalues: EigenRange {
            min: s.eigenvalues_min,
            max: s.eigenvalues_max,
        },
        fa: FaStats {
            min: s.fa_min,
            mean: s.fa_mean,
            max: s.fa_max,
        },
        stress: StressRanges {
            von_mises: Range {
                min: s.von_mises_min,
                max: s.von_mises_max,
            },
            tresca: Range {
                min: s.tresca_min,
                max: s.tresca_max,
            },
            mean: Range {
                min: s.md_min,
                max: s.md_max,
            },
        },
        classes: Classes {
            linear: s.classes[0],
            planar: s.classes[1],
            spherical: s.classes[2],
            unclassified: s.classes[3],
        },
        samples,
    })
}

fn sample(field: &TensorField, index: usize) -> Result<Sample, String> {
    let n = field.len();
    if index >= n {
        return Err(if n == 0 {
            format!("sample index {index} out of range: the field has no tensors")
        } else {
            format!(
                "sample index {index} out of range: the field has {n} tensors (0..={})",
                n - 1
            )
        });
    }
    let world = field.world_tensor(index);
    let (values, vectors) = if world.iter().all(|x| x.is_finite()) {
        let e = symmetric_eigen(&symmetrise(&world).0);
        (e.values, e.vectors.map(canonical_sign))
    } else {
        ([f64::NAN; 3], [[f64::NAN; 3]; 3])
    };
    Ok(Sample {
        index,
        position: field.position(index),
        tensor: field.tensor(index),
        eigenvalues: values,
        eigenvectors: vectors,
        principal_stresses: stress::principal(values),
        von_mises: stress::von_mises(values),
        tresca: stress::tresca(values),
        mean: stress::mean(values),
    })
}

/// Flip `v` so that its largest-magnitude component is positive (first such component on ties).
pub fn canonical_sign(v: [f64; 3]) -> [f64; 3] {
    let mut k = 0;
    for i in 1..3 {
        if v[i].abs() > v[k].abs() {
            k = i;
        }
    }
    if v[k] < 0.0 { v.map(|x| -x) } else { v }
}

/// Where a layout came from, as the summary and the report say it.
pub fn why_text(why: Why) -> &'static str {
    match why {
        Why::File => "from the file",
        Why::Flag => "from --order",
        Why::Default => "the default",
        Why::Names => "from the file names",
        Why::Sidecar => "from the BEP016 sidecar",
    }
}

/// A readable multi-line summary for the terminal.
pub fn human_summary(r: &InfoReport) -> String {
    let mut o = String::new();
    let dims = match r.dims {
        Some([a, b, c]) => format!(" {a}×{b}×{c}"),
        None => String::new(),
    };
    let pct = |x: usize| {
        if r.valid == 0 {
            0.0
        } else {
            100.0 * x as f64 / r.valid as f64
        }
    };
    let _ = writeln!(
        o,
        "{} ({}{dims}): {} points, {} cells",
        r.dataset, r.format, r.points, r.cells
    );
    let _ = writeln!(
        o,
        "tensor array '{}': {} components, {} data",
        // From the file: a name must not drive the terminal.
        crate::error::escape_for_error(&r.tensor_array.name),
        r.tensor_array.components,
        r.tensor_array.location.as_str()
    );
    if let Some(l) = &r.layout {
        let _ = writeln!(o, "layout: {} ({})", l.order, why_text(l.why));
    }
    if let Some(f) = &r.frame {
        let _ = writeln!(
            o,
            "frame: tensors in {} axes{}, world {} from {}",
            f.tensor_frame.name(),
            match r
                .bep016_sidecar
                .as_ref()
                .and_then(|s| s.reference_axes.as_ref())
            {
                Some(axes) => format!(" (ReferenceAxes {axes}, from the BEP016 sidecar)"),
                None => String::new(),
            },
            f.world,
            f.source
        );
        if let Some(m) = &f.voxel_to_world {
            for row in m {
                let _ = writeln!(
                    o,
                    "  voxel to world [{}, {}, {}, {}]",
                    g(row[0]),
                    g(row[1]),
                    g(row[2]),
                    g(row[3])
                );
            }
        }
    }
    let masked = if r.skipped.masked > 0 {
        format!(", {} masked (confidence < 0.5)", r.skipped.masked)
    } else {
        String::new()
    };
    let overflow = if r.skipped.overflow > 0 {
        format!(
            ", {} beyond ±3.4e38 (the glyphs' f32 range)",
            r.skipped.overflow
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        o,
        "tensors: {} total, {} valid; skipped {} NaN, {} Inf, {} zero{masked}{overflow}",
        r.tensors, r.valid, r.skipped.nan, r.skipped.inf, r.skipped.zero
    );
    let _ = writeln!(
        o,
        "symmetrised: {}   indefinite: {}",
        r.symmetrised, r.indefinite
    );
    let _ = writeln!(
        o,
        "eigenvalues: λ1 [{}, {}]  λ2 [{}, {}]  λ3 [{}, {}]",
        g(r.eigenvalues.min[0]),
        g(r.eigenvalues.max[0]),
        g(r.eigenvalues.min[1]),
        g(r.eigenvalues.max[1]),
        g(r.eigenvalues.min[2]),
        g(r.eigenvalues.max[2]),
    );
    let _ = writeln!(
        o,
        "FA: min {:.4}  mean {:.4}  max {:.4}",
        r.fa.min, r.fa.mean, r.fa.max
    );
    // Stress measures mean something for stress fields (mostly indefinite tensors) only.
    if 2 * r.indefinite > r.valid {
        let st = &r.stress;
        let _ = writeln!(
            o,
            "stress: von Mises [{}, {}]  Tresca [{}, {}]  mean [{}, {}]",
            g(st.von_mises.min),
            g(st.von_mises.max),
            g(st.tresca.min),
            g(st.tresca.max),
            g(st.mean.min),
            g(st.mean.max),
        );
    }
    let c = &r.classes;
    let _ = writeln!(
        o,
        "classes (τ = 0.5): linear {} ({:.1}%)  planar {} ({:.1}%)  spherical {} ({:.1}%)  unclassified {} ({:.1}%)",
        c.linear,
        pct(c.linear),
        c.planar,
        pct(c.planar),
        c.spherical,
        pct(c.spherical),
        c.unclassified,
        pct(c.unclassified)
    );
    for s in &r.samples {
        let _ = writeln!(
            o,
            "sample #{} at ({}, {}, {}):",
            s.index,
            g(s.position[0]),
            g(s.position[1]),
            g(s.position[2])
        );
        for row in 0..3 {
            let t = &s.tensor[3 * row..3 * row + 3];
            let _ = writeln!(o, "  T[{row}] = [{}, {}, {}]", g(t[0]), g(t[1]), g(t[2]));
        }
        for k in 0..3 {
            let e = s.eigenvectors[k];
            let _ = writeln!(
                o,
                "  λ{} = {}   e{} = ({:.6}, {:.6}, {:.6})",
                k + 1,
                g(s.eigenvalues[k]),
                k + 1,
                e[0],
                e[1],
                e[2]
            );
        }
        if 2 * r.indefinite > r.valid {
            let _ = writeln!(
                o,
                "  von Mises {}   Tresca {}   mean {}",
                g(s.von_mises),
                g(s.tresca),
                g(s.mean)
            );
        }
    }
    o
}

/// Compact number formatting: up to 6 significant digits.
fn g(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if (1e-4..1e6).contains(&a) {
        let decimals = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.5e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::synthetic;
    use crate::glyph::derive_glyphs;

    #[test]
    fn report_keys_and_samples() {
        let f = synthetic::grid(6);
        let set = derive_glyphs(&f, &crate::progress::Silent);
        let r = info_report(&f, &set, &[0, 7]).unwrap();
        let v = serde_json::to_value(&r).unwrap();
        let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        for k in [
            "format",
            "dataset",
            "dims",
            "points",
            "cells",
            "tensor_array",
            "layout",
            "frame",
            "tensors",
            "valid",
            "skipped",
            "symmetrised",
            "indefinite",
            "eigenvalues",
            "fa",
            "stress",
            "classes",
            "samples",
        ] {
            assert!(keys.contains(&k), "missing {k}");
        }
        assert_eq!(keys.len(), 18);
        assert_eq!(v["dataset"], "ImageData");
        assert_eq!(v["format"], "synthetic");
        assert_eq!(v["dims"], serde_json::json!([6, 6, 6]));
        assert_eq!(v["tensor_array"]["location"], "point");
        assert_eq!(v["tensor_array"]["name"], "tensors");
        assert_eq!(v["tensor_array"]["components"], 9);
        assert_eq!(v["skipped"]["nan"], 0);
        assert!(v["eigenvalues"]["min"].as_array().unwrap().len() == 3);
        assert!(v["fa"]["mean"].as_f64().unwrap() > 0.0);
        assert_eq!(v["classes"].as_object().unwrap().len(), 4);
        let s = &v["samples"][1];
        assert_eq!(s["index"], 7);
        assert_eq!(s["position"], serde_json::json!([1.0, 1.0, 0.0]));
        assert_eq!(s["tensor"].as_array().unwrap().len(), 9);
        assert_eq!(s["eigenvectors"].as_array().unwrap().len(), 3);
        assert_eq!(s["principal_stresses"], s["eigenvalues"]);
        for k in ["von_mises", "tresca", "mean"] {
            assert!(s[k].is_number(), "{k}");
        }
        assert!(v["stress"]["von_mises"]["max"].as_f64().unwrap() >= 0.0);
        // eigenvectors canonical and consistent with the tensor
        let smp = &r.samples[1];
        for k in 0..3 {
            let e = smp.eigenvectors[k];
            let big = e
                .iter()
                .cloned()
                .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
            assert!(big > 0.0);
            let t = smp.tensor;
            let te: [f64; 3] = std::array::from_fn(|r| (0..3).map(|c| t[3 * r + c] * e[c]).sum());
            for r in 0..3 {
                assert!((te[r] - smp.eigenvalues[k] * e[r]).abs() < 1e-12);
            }
        }
        let text = human_summary(&r);
        assert!(text.contains("64") || text.contains("216"));
        assert!(text.contains("sample #7"));
    }

    #[test]
    fn out_of_range_sample() {
        let f = synthetic::grid(2);
        let set = derive_glyphs(&f, &crate::progress::Silent);
        let e = info_report(&f, &set, &[8]).unwrap_err();
        assert!(e.contains("8") && e.contains("0..=7"), "{e}");
    }

    #[test]
    fn formatting() {
        assert_eq!(g(1.5), "1.5");
        assert_eq!(g(-0.000123456789), "-0.000123457");
        assert_eq!(g(1.0 / 3.0), "0.333333");
        assert_eq!(g(1e-9), "1.00000e-9");
        assert_eq!(g(123456.0), "123456");
    }
}
