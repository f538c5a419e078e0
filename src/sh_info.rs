//! The `info` report of a file of SH coefficients ([`ShField`]): the series' shape and basis
//! and why, the lattice, and requested voxels with their peaks, as JSON ([`ShInfoReport`]) or
//! as text ([`human_summary`]).

use std::fmt::Write as _;

use serde::Serialize;

use crate::field::frame::FrameInfo;
use crate::field::{ShField, ShLayout};
use crate::sh::{PeakFinder, PeakOptions};

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShInfoReport {
    pub format: String,
    /// `sh`: what sets this report apart from a tensor file's.
    pub kind: &'static str,
    pub dims: [usize; 3],
    pub voxels: usize,
    /// `float32` or `float64`, as stored.
    pub datatype: &'static str,
    pub sh: ShLayout,
    /// The lattice's placement; `tensor_frame` is the axes the series' directions are in.
    pub frame: FrameInfo,
    /// Voxels whose coefficients are all zero (outside a fit's mask).
    pub zero: usize,
    pub samples: Vec<ShSample>,
}

/// One requested voxel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShSample {
    pub index: usize,
    pub position: [f64; 3],
    /// As stored, in the field's basis.
    pub coefficients: Vec<f64>,
    /// The peaks with DIPY's `peaks_from_model` settings (relative threshold 0.5, 25° apart,
    /// at most 5), largest first, in the directions' axes (`frame.tensor_frame`).
    pub peaks: Vec<ShPeak>,
    /// The smallest and largest value on the sphere (min–max normalisation); null for a
    /// voxel of zeros.
    pub range: Option<[f64; 2]>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShPeak {
    pub direction: [f64; 3],
    pub value: f64,
}

/// Build the report. `samples` are voxel indices (x fastest); one out of range is an error
/// naming the valid range.
pub fn report(field: &ShField, samples: &[usize]) -> Result<ShInfoReport, String> {
    let n = field.voxels();
    let zero = n - field.series();
    let mut c = vec![0.0; field.layout.count];
    let mut finder =
        PeakFinder::new(field.layout.lmax, field.layout.basis).map_err(|e| format!("{e}"))?;
    let samples = samples
        .iter()
        .map(|&index| {
            if index >= n {
                return Err(format!(
                    "sample index {index} out of range: the field has {n} voxels (0..={})",
                    n.saturating_sub(1)
                ));
            }
            field.coefficients_of(index, &mut c);
            let flat = c.iter().all(|&x| x == 0.0);
            Ok(ShSample {
                index,
                position: field.position(index),
                coefficients: c.clone(),
                peaks: finder
                    .peaks(&c, &PeakOptions::default())
                    .into_iter()
                    .map(|p| ShPeak {
                        direction: p.direction,
                        value: p.value,
                    })
                    .collect(),
                range: (!flat)
                    .then(|| finder.range(&c).map(|(a, b)| [a, b]))
                    .flatten(),
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ShInfoReport {
        format: field.format.clone(),
        kind: "sh",
        dims: field.dims,
        voxels: n,
        datatype: field.coefficients.type_name(),
        sh: field.layout.clone(),
        frame: field.frame.clone(),
        zero,
        samples,
    })
}

/// A readable multi-line summary for the terminal.
pub fn human_summary(r: &ShInfoReport) -> String {
    let mut o = String::new();
    let [a, b, c] = r.dims;
    let s = &r.sh;
    let _ = writeln!(
        o,
        "SH coefficients ({} {a}×{b}×{c}): {} voxels, {} zero, {}",
        r.format, r.voxels, r.zero, r.datatype
    );
    let _ = writeln!(
        o,
        "series: lmax {}, {} coefficients ({})",
        s.lmax, s.count, s.recognised
    );
    let _ = writeln!(o, "basis: {} ({})", s.basis, s.reason);
    frame_lines(&mut o, &r.frame);
    sample_lines(&mut o, &r.samples);
    o
}

/// The frame's lines of [`human_summary`] (a peaks file's too).
pub(crate) fn frame_lines(o: &mut String, f: &FrameInfo) {
    let _ = writeln!(
        o,
        "frame: directions in {} axes, world {} from {}",
        f.tensor_frame.name(),
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

/// The samples' lines of [`human_summary`] (a peaks file's too).
pub(crate) fn sample_lines(o: &mut String, samples: &[ShSample]) {
    for smp in samples {
        let p = smp.position;
        let _ = writeln!(
            o,
            "voxel {} at ({}, {}, {}): {} peaks{}",
            smp.index,
            g(p[0]),
            g(p[1]),
            g(p[2]),
            smp.peaks.len(),
            match smp.range {
                Some([lo, hi]) => format!(", values {} to {}", g(lo), g(hi)),
                None => String::new(),
            }
        );
        for pk in &smp.peaks {
            let d = pk.direction;
            let _ = writeln!(
                o,
                "  peak ({}, {}, {}) value {}",
                g(d[0]),
                g(d[1]),
                g(d[2]),
                g(pk.value)
            );
        }
    }
}

pub(crate) fn g(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
