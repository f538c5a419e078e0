//! Spherical-harmonic coefficient volumes (fibre ODFs): [`ShField`], read from NIfTI-1 (DIPY's
//! `shm_coeff`, MRtrix's `mrconvert` of `dwi2fod` output) and MRtrix images (`dwi2fod`).
//!
//! **SH or tensors.** A 4-D file whose values per voxel are an SH count (15, 28, 45, 66, 91, …:
//! lmax 4 to 12 and beyond) is SH; 6 is read as tensors (a tensor file far more often than a
//! lmax 2 series) unless `--sh-basis` is given, which makes any file SH. An MRtrix image with a
//! `dw_scheme` (a DWI series, whose volume count can be anything) is SH only when asked.
//!
//! **The basis.** `--sh-basis` if given; else an MRtrix image, or a NIfTI file MRtrix wrote
//! (its `descrip` says `MRtrix version: …`, which `mrconvert` always writes), is `tournier07`,
//! MRtrix's only basis; any other NIfTI file is `descoteaux07-legacy`, the basis DIPY's
//! `shm_coeff` is in unless DIPY was told otherwise. [`ShLayout`] records which and why, as
//! `info` prints it.
//!
//! **The directions' axes.** An SH series is a function of direction, in the axes its
//! gradient directions were given in: MRtrix's scanner axes (world, RAS), DIPY's voxel axes
//! (the bvecs as given). `--tensor-frame` overrides it, as for tensors: the same question.
//!
//! Values are kept as stored (float32 or float64; float64 where a scaling was applied), a
//! coefficient's volume after volume as NIfTI stores them, so that nothing is held but the
//! values themselves (and NIfTI's grow with the bytes read, never ahead of them). A NaN or
//! infinite coefficient is refused with its voxel: a CSD fit writes none, even outside its mask.

use serde::Serialize;

use super::frame::{FrameInfo, TensorFrame, Why};
use super::tensor_field::{Location, TensorArrayInfo, TensorField};
use crate::error::LoadErrorKind;
use crate::sh::{ShBasis, ShError, ShEval, lmax_of_count};

/// The values of an SH volume, as stored: coefficient `c` of voxel `v` at `c * voxels + v`.
#[derive(Debug, Clone, PartialEq)]
pub enum Coefficients {
    F32(Vec<f32>),
    F64(Vec<f64>),
}

impl Coefficients {
    pub fn len(&self) -> usize {
        match self {
            Coefficients::F32(v) => v.len(),
            Coefficients::F64(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value `i` (coefficient c of voxel v at c · voxels + v) as f64.
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Coefficients::F32(v) => v[i] as f64,
            Coefficients::F64(v) => v[i],
        }
    }

    /// `"float32"` or `"float64"`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Coefficients::F32(_) => "float32",
            Coefficients::F64(_) => "float64",
        }
    }
}

/// The series' shape and basis, and why that basis, as `info` reports them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShLayout {
    pub lmax: u32,
    /// Coefficients per voxel: (lmax + 1)(lmax + 2)/2.
    pub count: usize,
    pub basis: ShBasis,
    /// `flag` (`--sh-basis`), `file` (MRtrix wrote it) or `default` (DIPY's default).
    pub why: Why,
    /// The reason in words, one line.
    pub reason: String,
    /// Why the file was read as SH rather than tensors, one line.
    pub recognised: String,
}

/// A lattice of SH series, one per voxel.
#[derive(Debug, Clone, PartialEq)]
pub struct ShField {
    /// `nifti` or `mif`.
    pub format: String,
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    pub layout: ShLayout,
    /// `count` per voxel, coefficient-major ([`Coefficients`]).
    pub coefficients: Coefficients,
    /// The voxel-to-world matrix and, as `tensor_frame`, the axes the series' directions are in.
    pub frame: FrameInfo,
}

impl ShField {
    pub fn voxels(&self) -> usize {
        self.dims.iter().product()
    }

    /// The coefficients of voxel `v` (x fastest) as f64, into `out` (`layout.count` long).
    pub fn coefficients_of(&self, v: usize, out: &mut [f64]) {
        let n = self.voxels();
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.coefficients.get(c * n + v);
        }
    }

    /// Voxels holding a series (some coefficient not zero; a fit's mask leaves zeros outside).
    pub fn series(&self) -> usize {
        let n = self.voxels();
        let mut c = vec![0.0; self.layout.count];
        (0..n)
            .filter(|&v| {
                self.coefficients_of(v, &mut c);
                c.iter().any(|&x| x != 0.0)
            })
            .count()
    }

    /// The world position of voxel `v`'s centre.
    pub fn position(&self, v: usize) -> [f64; 3] {
        self.frame.voxel_position(self.dims, v)
    }

    /// The smallest voxel step in world units (1 without a usable voxel-to-world matrix).
    pub fn spacing(&self) -> f64 {
        self.frame.smallest_step()
    }

    /// The lattice as a field holding no tensors: what the viewer slices and frames (voxel
    /// centres, dims, spacing and frame), the series staying here.
    pub fn geometry(&self) -> TensorField {
        let array = TensorArrayInfo {
            name: format!("SH series (lmax {})", self.layout.lmax),
            components: self.layout.count,
            location: Location::Point,
        };
        TensorField::lattice_only(&self.format, self.dims, &self.frame, array)
    }

    /// An evaluator of this field's series.
    pub fn evaluator(&self) -> ShEval {
        // lmax and basis were checked when the field was read.
        ShEval::new(self.layout.lmax, self.layout.basis).expect("a checked lmax")
    }
}

/// Who wrote an SH file, as far as the file says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Writer {
    /// An MRtrix image.
    MrtrixImage,
    /// A NIfTI file whose `descrip` says MRtrix wrote it.
    MrtrixNifti,
    /// Anything else (DIPY, nibabel, …).
    Other,
}

/// The end of a tensor reader's error for `count` values per voxel: where SH coefficients are
/// read, for a count that is one.
pub(crate) fn tensor_hint(count: usize) -> String {
    match lmax_of_count(count) {
        Ok(lmax) if is_sh_count(count) => format!(
            " ({count} is the SH count of lmax {lmax}: SH coefficients, which `info` reads and \
             `render` draws as ODF glyphs)"
        ),
        _ => String::new(),
    }
}

/// Whether `count` values per voxel are read as SH without being asked: an SH count other than
/// 1 (a scalar volume) and 6 (tensors, far more often than lmax 2).
pub(crate) fn is_sh_count(count: usize) -> bool {
    count != 1 && count != 6 && lmax_of_count(count).is_ok()
}

/// Why a file of `count` values per voxel is read as SH (`asked`: `--sh-basis` was given).
pub(crate) fn recognised(count: usize, asked: bool) -> String {
    if asked && !is_sh_count(count) {
        format!("{count} values per voxel, read as SH because --sh-basis was given")
    } else {
        format!("{count} values per voxel: an SH count, not a tensor's 6 or 9")
    }
}

/// The layout of `count` coefficients from `writer`, the basis `asked` for winning.
pub(crate) fn layout(
    count: usize,
    writer: Writer,
    asked: Option<ShBasis>,
) -> Result<ShLayout, LoadErrorKind> {
    if count == 1 {
        return Err(LoadErrorKind::Field {
            field: "dim".into(),
            message: "a scalar volume (one value per voxel), not SH coefficients".into(),
        });
    }
    let lmax = lmax_of_count(count).map_err(|e: ShError| LoadErrorKind::Field {
        field: "dim".into(),
        message: e.to_string(),
    })?;
    let (basis, why, reason) = match (asked, writer) {
        (Some(b), _) => (b, Why::Flag, "from --sh-basis"),
        (None, Writer::MrtrixImage) => (
            ShBasis::Tournier07,
            Why::File,
            "an MRtrix image, and MRtrix writes tournier07",
        ),
        (None, Writer::MrtrixNifti) => (
            ShBasis::Tournier07,
            Why::File,
            "its descrip says MRtrix wrote it, and MRtrix writes tournier07",
        ),
        (None, Writer::Other) => (
            ShBasis::Descoteaux07Legacy,
            Why::Default,
            "the default for a NIfTI file MRtrix did not write: DIPY's basis for shm_coeff",
        ),
    };
    Ok(ShLayout {
        lmax,
        count,
        basis,
        why,
        reason: reason.into(),
        recognised: recognised(count, asked.is_some()),
    })
}

/// The axes of the directions: `asked` (`--tensor-frame`), else world for MRtrix, voxel for
/// the others.
pub(crate) fn direction_frame(writer: Writer, asked: Option<TensorFrame>) -> TensorFrame {
    asked.unwrap_or(match writer {
        Writer::MrtrixImage | Writer::MrtrixNifti => TensorFrame::World,
        Writer::Other => TensorFrame::Voxel,
    })
}

/// The first coefficient that is not finite, as an error naming its voxel and place.
pub(crate) fn check_finite(c: &Coefficients, dims: [usize; 3]) -> Result<(), LoadErrorKind> {
    let n: usize = dims.iter().product();
    let bad = match c {
        Coefficients::F32(v) => v.iter().position(|x| !x.is_finite()),
        Coefficients::F64(v) => v.iter().position(|x| !x.is_finite()),
    };
    let Some(i) = bad else { return Ok(()) };
    let (k, v) = (i / n.max(1), i % n.max(1));
    let ijk = [v % dims[0], v / dims[0] % dims[1], v / dims[0] / dims[1]];
    Err(LoadErrorKind::Malformed(format!(
        "SH coefficient {k} of voxel ({}, {}, {}) is {}: the series has no value there",
        ijk[0],
        ijk[1],
        ijk[2],
        c.get(i)
    )))
}
