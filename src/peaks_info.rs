//! The `info` report of a file of peaks ([`PeakField`]): the lattice, how many voxels hold how
//! many peaks, the largest amplitude, and requested voxels with their peaks, as JSON
//! ([`PeaksInfoReport`]) or as text ([`human_summary`]), in the shape of an SH file's
//! ([`crate::sh_info`]).

use std::fmt::Write as _;

use serde::Serialize;

use crate::field::PeakField;
use crate::field::frame::FrameInfo;
use crate::sh_info::{ShPeak, ShSample};

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeaksInfoReport {
    pub format: String,
    /// `peaks`: what sets this report apart from a tensor or SH file's.
    pub kind: &'static str,
    pub dims: [usize; 3],
    pub voxels: usize,
    /// Peaks a voxel can hold.
    pub per_voxel: usize,
    /// Voxels holding 0, 1, … `per_voxel` peaks.
    pub counts: Vec<usize>,
    /// The longest peak's length (its amplitude).
    pub largest: f64,
    /// The lattice's placement; `tensor_frame` is the axes the file stored the directions in.
    pub frame: FrameInfo,
    /// Requested voxels: their peaks as unit directions and amplitudes (`coefficients` empty,
    /// `range` null).
    pub samples: Vec<ShSample>,
}

/// Build the report. `samples` are voxel indices (x fastest); one out of range is an error
/// naming the valid range.
pub fn report(field: &PeakField, samples: &[usize]) -> Result<PeaksInfoReport, String> {
    let n = field.voxels();
    let samples = samples
        .iter()
        .map(|&index| {
            if index >= n {
                return Err(format!(
                    "sample index {index} out of range: the field has {n} voxels (0..={})",
                    n.saturating_sub(1)
                ));
            }
            Ok(ShSample {
                index,
                position: field.position(index),
                coefficients: Vec::new(),
                peaks: field
                    .peaks_of(index)
                    .map(|x| {
                        let x = glam::Vec3::from(x).as_dvec3();
                        ShPeak {
                            direction: x.normalize().into(),
                            value: x.length(),
                        }
                    })
                    .collect(),
                range: None,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(PeaksInfoReport {
        format: field.format.clone(),
        kind: "peaks",
        dims: field.dims,
        voxels: n,
        per_voxel: field.per_voxel,
        counts: field.counts(),
        largest: field.largest(),
        frame: field.frame.clone(),
        samples,
    })
}

/// The report as text, a fact a line.
pub fn human_summary(r: &PeaksInfoReport) -> String {
    let mut o = String::new();
    let [a, b, c] = r.dims;
    let _ = writeln!(
        o,
        "fibre peaks ({} {a}×{b}×{c}): {} voxels, up to {} peaks each, the largest {}",
        r.format,
        r.voxels,
        r.per_voxel,
        crate::sh_info::g(r.largest)
    );
    let counts: Vec<String> = r
        .counts
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{n} with {k}"))
        .collect();
    let _ = writeln!(o, "voxels: {}", counts.join(", "));
    crate::sh_info::frame_lines(&mut o, &r.frame);
    if r.frame.tensor_frame != crate::field::TensorFrame::World {
        // The reader turns them into world axes: the samples are shown so.
        let _ = writeln!(
            o,
            "  turned into world axes when read; the peaks below are in world"
        );
    }
    crate::sh_info::sample_lines(&mut o, &r.samples);
    o
}
