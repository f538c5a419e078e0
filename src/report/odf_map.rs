//! An ODF map's part of a report: the map read once (its header confirming it holds SH series:
//! a name only proposes), the peaks of an even sample of its voxels, and its three figures
//! ([`super::odf`]).
//!
//! **Peaks** are found as `info` finds them ([`crate::sh::PeakFinder`], checked against DIPY's
//! `peak_directions_nl` and MRtrix's `sh2peaks` within 1°) with DIPY's `peaks_from_model`
//! settings (a peak at least half the largest, 25° apart, at most five), in up to
//! [`PEAK_SAMPLES`] voxels: every k-th voxel holding a series, in storage order, k the
//! smallest that keeps the count within it. A whole brain holds hundreds of thousands of
//! voxels at about 0.2 ms each, which a report's budget does not have; 4096 voxels put the
//! shares within about ±1.5 % (95 %) of the map's.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;
use web_time::Instant;

use super::mosaic::ORIENTATIONS;
use super::{FigureReport, Options, UnitError, figure, file_stem, odf};
use crate::backend::Backend;
use crate::field::{FieldKind, Inputs, ReadOptions, ShField};
use crate::progress::Progress;
use crate::sh::{PeakFinder, PeakOptions};
use crate::staging;

/// The most voxels whose peaks a report finds.
pub const PEAK_SAMPLES: usize = 4096;

/// How many peaks the voxels of a sample have.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeakStats {
    /// Voxels sampled, of `of` holding a series.
    pub sampled: usize,
    pub of: usize,
    /// Mean peaks per voxel.
    pub mean: f64,
    /// The share of the sampled voxels with no peak, one, two, and three or more.
    pub shares: [f64; 4],
}

impl PeakStats {
    /// The share of voxels with two peaks or more: crossing (or fanning) fibres.
    pub fn crossing_share(&self) -> f64 {
        self.shares[2] + self.shares[3]
    }
}

/// The peak counts of the voxels of `field` that `held` marks, sampled as the module doc says;
/// `None` where none is held or the basis has no peak finder.
pub fn peak_stats(field: &ShField, held: &[bool], max: usize) -> Option<PeakStats> {
    let voxels: Vec<usize> = (0..held.len()).filter(|&v| held[v]).collect();
    let of = voxels.len();
    let step = of.div_ceil(max.max(1)).max(1);
    let sample: Vec<usize> = voxels.into_iter().step_by(step).collect();
    let finder = PeakFinder::new(field.layout.lmax, field.layout.basis).ok()?;
    let opts = PeakOptions::default();
    // One finder (its seed table is 3.7 MB at lmax 8) per chunk, a chunk per thread.
    let chunk = sample.len().div_ceil(rayon::current_num_threads()).max(1);
    let counts: Vec<usize> = sample
        .par_chunks(chunk)
        .flat_map_iter(|part| {
            let (mut finder, mut c) = (finder.clone(), vec![0.0; field.layout.count]);
            part.iter()
                .map(|&v| {
                    field.coefficients_of(v, &mut c);
                    finder.peaks(&c, &opts).len()
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let n = counts.len();
    if n == 0 {
        return None;
    }
    let mut shares = [0.0; 4];
    for &k in &counts {
        shares[k.min(3)] += 1.0 / n as f64;
    }
    Some(PeakStats {
        sampled: n,
        of,
        mean: counts.iter().sum::<usize>() as f64 / n as f64,
        shares,
    })
}

/// An ODF map's part of a report.
pub struct OdfReport {
    pub name: String,
    pub path: String,
    pub session: Option<String>,
    pub format: String,
    pub lmax: u32,
    /// Coefficients per voxel.
    pub count: usize,
    pub basis: String,
    /// Why that basis (`field.layout.reason`), and why the file was read as SH.
    pub basis_reason: String,
    pub recognised: String,
    /// The axes the series' directions are in, and the world and its source.
    pub frame: String,
    pub anatomical: bool,
    pub dims: [usize; 3],
    /// Voxels whose series is not all zero (those drawn).
    pub held: usize,
    pub normalize: crate::scene::odf::OdfNormalize,
    /// How the glyphs are coloured (`--color`: direction or amplitude).
    pub coloring: crate::shape::odf::OdfColoring,
    /// The peaks of a sample of the voxels holding a series; `None` where the basis has no
    /// peak finder.
    pub peaks: Option<PeakStats>,
    pub read_ms: f64,
    pub peaks_ms: f64,
    pub figures: Vec<FigureReport>,
}

/// Read the ODF map at `path` once (confirmed by its header to hold SH series: a name proposes
/// only) and draw its figures.
pub(super) fn map(
    path: &Path,
    session: Option<String>,
    options: &Options,
    backend: &Backend,
    progress: &dyn Progress,
    read: &mut Vec<PathBuf>,
) -> Result<OdfReport, UnitError> {
    let inputs = Inputs::file_system();
    let opts = ReadOptions {
        sh_basis: options.sh_basis,
        ..ReadOptions::default()
    };
    let t = Instant::now();
    // Its count says whether it holds series, as for the report's files; --sh-basis only names
    // their basis.
    let sh = FieldKind::of_file(&inputs, path, &ReadOptions::default()) == FieldKind::Series;
    let field: ShField = crate::field::read_sh_field_from(&inputs, path, &opts)?;
    // The reader takes any SH count (6 is lmax 2); the probe, as `render`, reads 6 as tensors.
    if !sh {
        return Err(UnitError::NotSh {
            path: path.to_path_buf(),
            count: field.layout.count,
        });
    }
    let read_ms = staging::ms(t);
    read.extend(inputs.paths_read());
    let held_voxels = odf::held(&field);
    let held = held_voxels.iter().filter(|h| **h).count();
    if held == 0 {
        return Err(UnitError::NoOdf(path.to_path_buf()));
    }
    let t = Instant::now();
    let peaks = peak_stats(&field, &held_voxels, PEAK_SAMPLES);
    let peaks_ms = staging::ms(t);
    let anatomical = field.frame.world == "RAS";
    let normalize = options.odf_normalize;
    let stem = file_stem(path);
    let mut figures = Vec::new();
    for o in ORIENTATIONS {
        let m = odf::render(
            &field,
            &held_voxels,
            o,
            anatomical,
            options,
            backend,
            progress,
        )?;
        figures.push(figure(path, &stem, o.name, m)?);
    }
    let f = &field.frame;
    Ok(OdfReport {
        name: path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        path: path.display().to_string(),
        session,
        format: field.format.clone(),
        lmax: field.layout.lmax,
        count: field.layout.count,
        basis: field.layout.basis.name().to_string(),
        basis_reason: field.layout.reason.clone(),
        recognised: field.layout.recognised.clone(),
        frame: format!(
            "directions in {} axes; world {} from {}",
            f.tensor_frame.name(),
            f.world,
            f.source
        ),
        anatomical,
        dims: field.dims,
        held,
        normalize,
        coloring: options.odf_color,
        peaks,
        read_ms,
        peaks_ms,
        figures,
    })
}
