//! A whole-brain-sized DTI volume for `bench --brain`: 128×128×70 voxels of float32 tensors
//! in FSL's 4-D order, gzip-compressed, as `dtifit --save_tensor` writes them, so reading and
//! the first image are timed on the size and encoding researchers open.
//!
//! Written by hand (a 348-byte NIfTI-1 header and the voxels): the `nifti` crate's writer needs
//! its ndarray feature, which this project leaves out. Only the fields the readers use are set.
//!
//! [`report`] times the glyph report of the same volume as a pipeline makes it: written as the
//! one participant of a BIDS derivatives folder in BEP016 form, reported on by the library's
//! [`crate::report::run`], with the process's peak memory measured from the report's start.

use std::io::Write;
use std::path::{Path, PathBuf};

use web_time::Instant;

use crate::backend::Backend;
use crate::progress::Silent;
use crate::report::{Job, Outcome};

use flate2::Compression;
use flate2::write::GzEncoder;

/// Voxels along x, y, z (2 mm, as a typical clinical DTI acquisition).
pub const DIMS: [usize; 3] = [128, 128, 70];
pub const VOXEL_MM: f32 = 2.0;

/// The tensor (xx, xy, xz, yy, yz, zz) of voxel (i, j, k): zero outside an ellipsoidal "brain",
/// isotropic CSF-like tensors in central "ventricles", elsewhere a white-matter-like cigar
/// whose axis turns around the z axis (and tilts with height), so DEC colours vary.
pub fn tensor(i: usize, j: usize, k: usize) -> [f32; 6] {
    let [nx, ny, nz] = DIMS.map(|n| n as f64);
    let x = (i as f64 + 0.5) / nx * 2.0 - 1.0;
    let y = (j as f64 + 0.5) / ny * 2.0 - 1.0;
    let z = (k as f64 + 0.5) / nz * 2.0 - 1.0;
    let r2 = (x / 0.85).powi(2) + (y / 0.95).powi(2) + (z / 0.9).powi(2);
    if r2 > 1.0 {
        return [0.0; 6];
    }
    if (x / 0.15).powi(2) + (y / 0.3).powi(2) + (z / 0.3).powi(2) < 1.0 {
        return [3.0e-3, 0.0, 0.0, 3.0e-3, 0.0, 3.0e-3];
    }
    let r = x.hypot(y).max(1e-6);
    let tilt = 0.6 * z;
    let e1 = [-y / r * tilt.cos(), x / r * tilt.cos(), tilt.sin()];
    let (l1, l2) = (1.7e-3, 0.3e-3 + 0.2e-3 * r2);
    // T = l2 I + (l1 - l2) e1 e1ᵀ
    let t = |a: usize, b: usize| {
        let id = if a == b { l2 } else { 0.0 };
        (id + (l1 - l2) * e1[a] * e1[b]) as f32
    };
    [t(0, 0), t(0, 1), t(0, 2), t(1, 1), t(1, 2), t(2, 2)]
}

/// The 352 bytes before the voxels: header and an empty extension flag.
fn header() -> Vec<u8> {
    let mut h = vec![0u8; 352];
    let put_i16 =
        |h: &mut Vec<u8>, at: usize, v: i16| h[at..at + 2].copy_from_slice(&v.to_le_bytes());
    let put_f32 =
        |h: &mut Vec<u8>, at: usize, v: f32| h[at..at + 4].copy_from_slice(&v.to_le_bytes());
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    let dim = [
        4,
        DIMS[0] as i16,
        DIMS[1] as i16,
        DIMS[2] as i16,
        6,
        1,
        1,
        1,
    ];
    for (n, d) in dim.into_iter().enumerate() {
        put_i16(&mut h, 40 + 2 * n, d);
    }
    put_i16(&mut h, 70, 16); // float32
    put_i16(&mut h, 72, 32);
    let pixdim = [1.0, VOXEL_MM, VOXEL_MM, VOXEL_MM, 1.0, 0.0, 0.0, 0.0];
    for (n, p) in pixdim.into_iter().enumerate() {
        put_f32(&mut h, 76 + 4 * n, p);
    }
    put_f32(&mut h, 108, 352.0);
    h[123] = 2; // millimetres
    put_i16(&mut h, 254, 1); // sform: scanner
    let half = DIMS.map(|n| -(n as f32) * VOXEL_MM / 2.0);
    for (row, at) in [280, 296, 312].into_iter().enumerate() {
        for c in 0..3 {
            put_f32(&mut h, at + 4 * c, if c == row { VOXEL_MM } else { 0.0 });
        }
        put_f32(&mut h, at + 12, half[row]);
    }
    h[344..348].copy_from_slice(b"n+1\0");
    h
}

/// Write the volume as a gzip-compressed NIfTI-1 file (whole or not at all).
pub fn write(path: &Path) -> std::io::Result<()> {
    write_scaled(path, 1.0)
}

/// [`write`], every tensor multiplied by `scale`.
fn write_scaled(path: &Path, scale: f32) -> std::io::Result<()> {
    crate::image_out::write_atomic(path, &[], |file| {
        let mut gz = GzEncoder::new(file, Compression::default());
        write_voxels(&mut gz, scale)?;
        gz.finish()?.flush()
    })
}

fn write_voxels(gz: &mut impl Write, scale: f32) -> std::io::Result<()> {
    gz.write_all(&header())?;
    let [nx, ny, nz] = DIMS;
    // Volume by volume (the 4th index slowest), x fastest within each.
    let mut plane = Vec::with_capacity(nx * ny * 4);
    for c in 0..6 {
        for k in 0..nz {
            plane.clear();
            for j in 0..ny {
                for i in 0..nx {
                    plane.extend_from_slice(&(tensor(i, j, k)[c] * scale).to_le_bytes());
                }
            }
            gz.write_all(&plane)?;
        }
    }
    Ok(())
}

/// The volume as participant `brain` of a BIDS derivatives folder at `root`: its map in BEP016
/// form (FSL's component order is BEP016's; diffusivities in µm²/ms, the tensors above being
/// in mm²/s) with a sidecar whose `ReferenceAxes` is `ijk`. Returns the map's path.
pub fn write_bids(root: &Path) -> std::io::Result<PathBuf> {
    let dwi = root.join("sub-brain").join("dwi");
    std::fs::create_dir_all(&dwi)?;
    std::fs::write(
        root.join("dataset_description.json"),
        "{\"Name\": \"whole-brain test volume\", \"BIDSVersion\": \"1.10.0\", \
         \"DatasetType\": \"derivative\"}\n",
    )?;
    std::fs::write(
        dwi.join("sub-brain_model-DTI_dwimap.json"),
        "{\"OrientationRepresentation\": \"param\", \"ReferenceAxes\": \"ijk\"}\n",
    )?;
    let map = dwi.join("sub-brain_model-DTI_param-tensor_dwimap.nii.gz");
    write_scaled(&map, 1000.0)?;
    Ok(map)
}

/// What the whole-brain report took.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportRun {
    /// Wall-clock time of the report (reading, decomposing, the three figures, the page).
    pub ms: f64,
    /// Peak resident set size of the process during the report: from its start where the
    /// system lets the high-water mark be reset (Linux), else over the whole process.
    pub peak_rss_bytes: Option<u64>,
    /// Whether the high-water mark was reset before the report.
    pub peak_is_the_reports: bool,
    pub figures: usize,
    pub error: Option<String>,
}

/// Write the volume as a BIDS folder under `dir`, then report on it into `dir/qc` with
/// `backend`, timed (the folder is the caller's to remove).
pub fn report(dir: &Path, backend: &Backend) -> ReportRun {
    let mut run = ReportRun {
        ms: 0.0,
        peak_rss_bytes: None,
        peak_is_the_reports: false,
        figures: 0,
        error: None,
    };
    let root = dir.join("derivatives");
    if let Err(e) = write_bids(&root) {
        run.error = Some(format!("writing the volume: {e}"));
        return run;
    }
    run.peak_is_the_reports = crate::mem::reset_peak();
    let t = Instant::now();
    let job = Job::Bids {
        dir: root,
        labels: Vec::new(),
    };
    match crate::report::run(&job, &dir.join("qc"), backend, &Silent) {
        Ok(Outcome { written, failed }) => {
            run.figures = written.iter().map(|w| w.figures.len()).sum();
            run.error = failed.first().map(|f| format!("{}: {}", f.name, f.error));
        }
        Err(e) => run.error = Some(e.to_string()),
    }
    run.ms = crate::staging::ms(t);
    run.peak_rss_bytes = crate::mem::peak_rss_bytes();
    run
}

/// `report`'s run as brain_report.csv holds it.
pub fn report_csv(run: &ReportRun) -> String {
    format!(
        "ms,peak_rss_bytes,peak_is_the_reports,figures,status\n{:.1},{},{},{},{}\n",
        run.ms,
        run.peak_rss_bytes.map_or(String::new(), |b| b.to_string()),
        run.peak_is_the_reports,
        run.figures,
        run.error.as_deref().map_or("ok".into(), |e| format!(
            "\"failed: {}\"",
            e.replace('"', "'")
        )),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{ReadOptions, read_field};

    #[test]
    fn the_bids_folder_holds_one_bep016_map_in_micrometres() {
        let dir = tempfile::tempdir().unwrap();
        let map = write_bids(dir.path()).unwrap();
        let found = crate::bids::participants(dir.path(), &[]).unwrap();
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].label, "brain");
        assert_eq!(found[0].maps[0].path, map);
        let f = read_field(&map, &ReadOptions::default()).unwrap();
        let sidecar = f.meta.sidecar.as_ref().unwrap();
        assert_eq!(sidecar.reference_axes.as_deref(), Some("ijk"));
        let n = 64 + DIMS[0] * (20 + DIMS[1] * 50);
        let [xx, xy, xz, yy, yz, zz] = tensor(64, 20, 50).map(|v| f64::from(v * 1000.0));
        assert_eq!(f.world_tensor(n), [xx, xy, xz, xy, yy, yz, xz, yz, zz]);
    }

    #[test]
    fn the_volume_reads_back_voxel_for_voxel() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("brain.nii.gz");
        write(&path).unwrap();
        let f = read_field(&path, &ReadOptions::default()).unwrap();
        assert_eq!(f.dims, Some(DIMS));
        assert_eq!(f.len(), DIMS.iter().product::<usize>());
        for (i, j, k) in [(64, 64, 35), (10, 64, 35), (64, 20, 50), (0, 0, 0)] {
            let n = i + DIMS[0] * (j + DIMS[1] * k);
            let [xx, xy, xz, yy, yz, zz] = tensor(i, j, k).map(f64::from);
            // Axis-aligned sform with positive determinant: the voxel frame is the world's.
            assert_eq!(f.world_tensor(n), [xx, xy, xz, xy, yy, yz, xz, yz, zz]);
            let p = f.position(n);
            let expect = [i, j, k].map(|v| v as f64 * 2.0);
            for a in 0..3 {
                assert!((p[a] - (expect[a] - DIMS[a] as f64)).abs() < 1e-9);
            }
        }
    }
}
