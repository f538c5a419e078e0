//! A greyscale scalar image under the glyphs: a measure of the tensors (FA, MD, a stress
//! measure: [`Measure`]), or any scalar volume, on each lattice plane the selection shows
//! (`--underlay`).
//!
//! The image lies on its plane but is drawn [`PlaneGeometry::behind`] further from the camera:
//! the largest extent of that plane's glyphs along its normal. The glyphs of the plane then stay
//! whole and in front of it from either side, without a depth bias that would differ between
//! the GPU and the reference: both place the image with [`PlaneGeometry::placed_corner`].
//! Texels are shown nearest-neighbour (one texel per tensor voxel for FA and MD), so the voxel
//! grid the tensors came from stays visible, as in mrview or FSLeyes.

use std::path::PathBuf;
use std::str::FromStr;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use crate::camera::{Camera, ViewPreset};
use crate::field::TensorField;
use crate::field::scalar::ScalarVolume;
use crate::glyph::GlyphSet;
use crate::percentile::{DEFAULT_RANGE, percentiles};
use crate::scene::{GlyphGeometry, Scene};
use crate::select::Plane;
use crate::tensor::measure::Measure;

/// The largest side of an image resampled from a scalar volume, in texels.
pub const MAX_TEXELS: usize = 4096;
/// The default window: these percentiles of the underlay's finite values.
pub const WINDOW_PERCENTILES: [f64; 2] = DEFAULT_RANGE;

/// What the underlay shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UnderlaySource {
    /// A measure of each tensor: FA, MD, von Mises …
    Measure(Measure),
    /// A scalar volume (NIfTI, NRRD or VTK image), sampled through its own voxel-to-world matrix.
    File(PathBuf),
    /// A scalar volume handed over in memory (the Python package's arrays), sampled the same way.
    Volume(NamedVolume),
}

/// A scalar volume in memory and what messages call it.
#[derive(Debug, Clone)]
pub struct NamedVolume {
    pub name: String,
    pub volume: Arc<ScalarVolume>,
}

/// The same volume (one allocation) and name: a volume is never changed once made.
impl PartialEq for NamedVolume {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.volume, &other.volume) && self.name == other.name
    }
}

impl Eq for NamedVolume {}

impl FromStr for UnderlaySource {
    type Err = String;
    /// A measure's name (`fa`, `md`, `von-mises` …, any case), else a file's path (write `./fa`
    /// for a file named `fa`).
    fn from_str(s: &str) -> Result<Self, String> {
        if s.is_empty() {
            return Err(format!(
                "--underlay takes {} or a scalar volume's file",
                Measure::NAMES.join(", ")
            ));
        }
        Ok(match s.to_ascii_lowercase().parse::<Measure>() {
            Ok(m) => Self::Measure(m),
            Err(_) => Self::File(PathBuf::from(s)),
        })
    }
}

impl std::fmt::Display for UnderlaySource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Measure(m) => write!(f, "{}", m.label()),
            Self::File(p) => write!(f, "{}", p.display()),
            Self::Volume(v) => write!(f, "{}", v.name),
        }
    }
}

/// Why an underlay cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnderlayError {
    #[error(
        "--underlay needs a lattice (image, rectilinear or structured data); this field has none"
    )]
    NoLattice,
    #[error(
        "--underlay needs a regular lattice: the positions of plane {plane} are not evenly spaced"
    )]
    Irregular { plane: Plane },
    #[error("--underlay: the field has no valid tensor to compute {what} from")]
    NoValue { what: String },
    #[error("--underlay {what}: the volume holds no finite value to show")]
    EmptyVolume { what: String },
}

/// Where a plane's image is, before it is moved behind its glyphs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneGeometry {
    /// World position of the image's corner at texel coordinates (0, 0).
    pub corner: DVec3,
    /// The image's edges (texel columns along `u`, rows along `v`), world.
    pub u: DVec3,
    pub v: DVec3,
    /// Unit normal of the plane.
    pub normal: DVec3,
    /// How far behind the plane (from the camera) the image is drawn.
    pub behind: f64,
}

impl PlaneGeometry {
    /// The corner the image is drawn at for `camera`: moved along the normal, away from the
    /// camera, by [`Self::behind`].
    pub fn placed_corner(&self, camera: &Camera) -> DVec3 {
        let toward_eye = if camera.is_ortho() {
            -camera.forward()
        } else {
            camera.eye - self.corner
        };
        let side = if self.normal.dot(toward_eye) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        self.corner - self.normal * (side * self.behind)
    }

    /// Where the ray `origin + t dir` crosses the image whose corner is `corner`: (t, s, r)
    /// with (s, r) in [0, 1)² the image coordinates along `u` and `v`.
    pub fn intersect(&self, corner: DVec3, origin: DVec3, dir: DVec3) -> Option<(f64, f64, f64)> {
        let n = self.u.cross(self.v);
        let denom = n.dot(dir);
        if denom == 0.0 || !denom.is_finite() {
            return None;
        }
        let t = n.dot(corner - origin) / denom;
        let w = origin + dir * t - corner;
        // Coordinates in the (u, v) basis, by the dual basis of the plane.
        let uu = self.u.dot(self.u);
        let uv = self.u.dot(self.v);
        let vv = self.v.dot(self.v);
        let det = uu * vv - uv * uv;
        let (wu, wv) = (w.dot(self.u), w.dot(self.v));
        let s = (vv * wu - uv * wv) / det;
        let r = (uu * wv - uv * wu) / det;
        ((0.0..1.0).contains(&s) && (0.0..1.0).contains(&r) && t > 0.0).then_some((t, s, r))
    }
}

/// One plane's image.
#[derive(Debug, Clone, PartialEq)]
pub struct UnderlayPlane {
    pub plane: Plane,
    pub geometry: PlaneGeometry,
    /// Texels along `u` and `v`.
    pub size: [u32; 2],
    /// `size[0] * size[1]` values, `u` fastest; NaN where there is nothing to show.
    pub values: Vec<f32>,
}

impl UnderlayPlane {
    /// The texel at image coordinates (s, r) in [0, 1)², nearest-neighbour.
    pub fn texel(&self, s: f64, r: f64) -> f32 {
        let [w, h] = self.size.map(|n| n as usize);
        let i = ((s * w as f64) as usize).min(w - 1);
        let j = ((r * h as f64) as usize).min(h - 1);
        self.values[i + w * j]
    }
}

/// The images of every shown plane, and the window that maps their values to grey.
#[derive(Debug, Clone, PartialEq)]
pub struct Underlay {
    pub planes: Vec<UnderlayPlane>,
    /// Values at or below `window[0]` are black, at or above `window[1]` white.
    pub window: [f32; 2],
    /// What it shows (`FA`, `MD` or the file's name).
    pub label: String,
}

/// The grey level of `value` in `window` (None: not drawn).
pub fn grey(value: f32, [lo, hi]: [f32; 2]) -> Option<f32> {
    if value.is_nan() {
        return None;
    }
    Some(if hi > lo {
        ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else if value >= hi {
        1.0
    } else {
        0.0
    })
}

/// What the values come from, once read.
pub enum Values<'a> {
    Measure(Measure),
    Volume(&'a ScalarVolume),
}

/// Where the lattice positions are: `p(i, j, k) = origin + i steps[0] + j steps[1] + k steps[2]`.
struct Lattice {
    dims: [usize; 3],
    origin: DVec3,
    steps: [DVec3; 3],
}

impl Lattice {
    fn of(field: &TensorField) -> Result<Self, UnderlayError> {
        let dims = field.lattice_dims().ok_or(UnderlayError::NoLattice)?;
        if dims.iter().product::<usize>() != field.positions.len() {
            return Err(UnderlayError::NoLattice);
        }
        let at = |i: usize, j: usize, k: usize| {
            DVec3::from(field.position(i + dims[0] * (j + dims[1] * k)))
        };
        let origin = at(0, 0, 0);
        let last = [
            at(dims[0] - 1, 0, 0),
            at(0, dims[1] - 1, 0),
            at(0, 0, dims[2] - 1),
        ];
        let mut steps: [Option<DVec3>; 3] = std::array::from_fn(|a| {
            (dims[a] > 1).then(|| (last[a] - origin) / (dims[a] - 1) as f64)
        });
        // A single-voxel axis has no step in the positions: take it from the voxel-to-world
        // matrix, else the image direction and spacing, else square to the known ones.
        for a in 0..3 {
            if steps[a].is_some() {
                continue;
            }
            let from_matrix = field
                .meta
                .frame
                .as_ref()
                .and_then(|f| f.voxel_to_world)
                .map(|m| DVec3::new(m[0][a], m[1][a], m[2][a]));
            let from_direction = field.direction.and_then(|d| {
                field
                    .spacing
                    .map(|s| DVec3::new(d[0][a], d[1][a], d[2][a]) * s)
            });
            steps[a] = from_matrix.or(from_direction);
        }
        let known: Vec<DVec3> = steps.iter().flatten().copied().collect();
        let fallback = |a: usize| {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let len = known
                .iter()
                .map(|s| s.length())
                .fold(f64::INFINITY, f64::min);
            let len = if len.is_finite() && len > 0.0 {
                len
            } else {
                field.spacing.unwrap_or(1.0)
            };
            match (steps[b], steps[c]) {
                (Some(x), Some(y)) if x.cross(y).length() > 0.0 => x.cross(y).normalize() * len,
                _ => [DVec3::X, DVec3::Y, DVec3::Z][a] * len,
            }
        };
        let steps = std::array::from_fn(|a| steps[a].unwrap_or_else(|| fallback(a)));
        Ok(Self {
            dims,
            origin,
            steps,
        })
    }

    /// The plane's corner and edges (half a voxel beyond its outer centres), checked against
    /// every position on it.
    fn plane(
        &self,
        field: &TensorField,
        plane: Plane,
    ) -> Result<(usize, usize, PlaneGeometry), UnderlayError> {
        let axis = plane.axis.min(2);
        let (a, b) = in_plane_axes(axis);
        let (sa, sb, sn) = (self.steps[a], self.steps[b], self.steps[axis]);
        let centre0 = self.origin + sn * plane.index as f64;
        let scale = sa.length().max(sb.length()).max(sn.length());
        let tol = 1e-6 * scale + 1e-9 * centre0.abs().max_element();
        let dims = self.dims;
        let irregular = (0..dims[b]).into_par_iter().any(|jb| {
            (0..dims[a]).any(|ia| {
                let mut ijk = [0; 3];
                ijk[axis] = plane.index;
                ijk[a] = ia;
                ijk[b] = jb;
                let p = DVec3::from(field.position(ijk[0] + dims[0] * (ijk[1] + dims[1] * ijk[2])));
                let expect = centre0 + sa * ia as f64 + sb * jb as f64;
                let off = (p - expect).length();
                // NaN positions count as irregular too.
                off.is_nan() || off > tol
            })
        });
        if irregular {
            return Err(UnderlayError::Irregular { plane });
        }
        let normal = sa.cross(sb).normalize_or_zero();
        Ok((
            a,
            b,
            PlaneGeometry {
                corner: centre0 - 0.5 * (sa + sb),
                u: sa * dims[a] as f64,
                v: sb * dims[b] as f64,
                normal,
                behind: 0.0,
            },
        ))
    }
}

/// The two lattice axes spanning a plane perpendicular to `axis`, in order.
fn in_plane_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The view (direction, up) that sees lattice plane `plane` face-on: along its normal, from
/// the side and with the up of the anatomical preset nearest to it (axial for a plane whose
/// normal is mostly z, coronal for y, sagittal for x). `None` without a lattice.
pub fn face_on(field: &TensorField, plane: Plane) -> Option<(DVec3, DVec3)> {
    face_on_steps(Lattice::of(field).ok()?.steps, plane)
}

/// [`face_on`] for a lattice of voxel steps `steps` (world).
pub fn face_on_steps(steps: [DVec3; 3], plane: Plane) -> Option<(DVec3, DVec3)> {
    let (a, b) = in_plane_axes(plane.axis.min(2));
    let n = steps[a].cross(steps[b]).normalize_or_zero();
    if n == DVec3::ZERO || !n.is_finite() {
        return None;
    }
    let preset = match n.abs().max_position() {
        0 => ViewPreset::Sagittal,
        1 => ViewPreset::Coronal,
        _ => ViewPreset::Axial,
    };
    let (d, up) = preset.direction_up();
    let dir = if n.dot(d) >= 0.0 { n } else { -n };
    let up = (up - dir * up.dot(dir)).normalize_or_zero();
    let up = if up == DVec3::ZERO {
        dir.any_orthonormal_vector()
    } else {
        up
    };
    Some((dir, up))
}

/// The underlay of `planes`, drawn behind the glyphs of `scene` that lie on each.
pub fn build(
    field: &TensorField,
    set: &GlyphSet,
    values: &Values<'_>,
    label: String,
    planes: &[Plane],
    scene: &Scene,
    max_side: usize,
) -> Result<Underlay, UnderlayError> {
    let lattice = Lattice::of(field)?;
    let per_voxel = match values {
        Values::Measure(m) => Some(voxel_values(field, set, *m)),
        Values::Volume(_) => None,
    };
    let mut out = Vec::with_capacity(planes.len());
    for &plane in planes {
        let (a, b, mut geometry) = lattice.plane(field, plane)?;
        geometry.behind = behind(scene, &geometry, lattice.steps[plane.axis.min(2)]);
        let dims = lattice.dims;
        let (size, texels) = match (values, &per_voxel) {
            (Values::Volume(volume), _) => resample(volume, &geometry, &lattice, (a, b), max_side),
            (_, Some(voxels)) => {
                let texels = (0..dims[b])
                    .flat_map(|jb| {
                        (0..dims[a]).map(move |ia| {
                            let mut ijk = [0; 3];
                            ijk[plane.axis.min(2)] = plane.index;
                            ijk[a] = ia;
                            ijk[b] = jb;
                            ijk[0] + dims[0] * (ijk[1] + dims[1] * ijk[2])
                        })
                    })
                    .map(|n| voxels[n])
                    .collect();
                ([dims[a] as u32, dims[b] as u32], texels)
            }
            _ => unreachable!("per-voxel values are made for the measures"),
        };
        out.push(UnderlayPlane {
            plane,
            geometry,
            size,
            values: texels,
        });
    }
    let all: Vec<f32> = match (values, &per_voxel) {
        (Values::Volume(v), _) => v.values.iter().copied().filter(|x| x.is_finite()).collect(),
        (_, Some(voxels)) => voxels.iter().copied().filter(|x| x.is_finite()).collect(),
        _ => Vec::new(),
    };
    let window =
        percentiles(all, WINDOW_PERCENTILES, f32::total_cmp).ok_or_else(|| match values {
            Values::Volume(_) => UnderlayError::EmptyVolume {
                what: label.clone(),
            },
            _ => UnderlayError::NoValue {
                what: label.clone(),
            },
        })?;
    Ok(Underlay {
        planes: out,
        window,
        label,
    })
}

/// The measure per tensor in file order, NaN where there is no glyph (or no finite value: a
/// hydrostatic state's triaxiality).
fn voxel_values(field: &TensorField, set: &GlyphSet, measure: Measure) -> Vec<f32> {
    let mut out = vec![f32::NAN; field.len()];
    for g in &set.glyphs {
        let v = measure.of(g.eigenvalues.map(f64::from));
        let v = if v.is_finite() { v } else { f64::NAN };
        if let Some(slot) = out.get_mut(g.index as usize) {
            *slot = v as f32;
        }
    }
    out
}

/// The largest extent along the plane's normal of the glyphs centred within half a lattice step
/// of it (a hair more, so the image never touches them).
fn behind(scene: &Scene, geometry: &PlaneGeometry, step: DVec3) -> f64 {
    let n = geometry.normal;
    let half = 0.5 * step.dot(n).abs();
    let point = geometry.corner + 0.5 * (geometry.u + geometry.v) - scene.origin;
    let extent = (0..scene.instances.len())
        .into_par_iter()
        .map(|i| (scene.kind_of(i), scene.geometry(i)))
        .filter(|(_, g): &(_, GlyphGeometry)| (g.centre - point).dot(n).abs() <= half)
        .map(|(kind, g)| kind.shape().bounds(&g).dot(n.abs()))
        .filter(|e| e.is_finite())
        .reduce(|| 0.0, f64::max);
    extent * (1.0 + 1e-3) + 1e-6 * step.length()
}

/// A volume sampled (trilinearly) at the texel centres of a grid over the plane, texels no
/// larger than the finer of the volume's voxels and the lattice step, and no more than
/// `max_side` along a side (the image's pixels: a volume of 1 µm voxels under a small image
/// needs no more texels than the image has pixels).
fn resample(
    volume: &ScalarVolume,
    g: &PlaneGeometry,
    lattice: &Lattice,
    (a, b): (usize, usize),
    max_side: usize,
) -> ([u32; 2], Vec<f32>) {
    let m = volume.voxel_to_world;
    let voxel = (0..3)
        .map(|c| DVec3::new(m[0][c], m[1][c], m[2][c]).length())
        .filter(|l| l.is_finite() && *l > 0.0)
        .fold(f64::INFINITY, f64::min);
    let step = lattice.steps[a].length().min(lattice.steps[b].length());
    let texel = voxel.min(step);
    let count = |edge: DVec3| {
        let n = (edge.length() / texel).ceil();
        if n.is_finite() {
            (n as usize).clamp(1, max_side.clamp(1, MAX_TEXELS))
        } else {
            1
        }
    };
    let (w, h) = (count(g.u), count(g.v));
    let values = (0..w * h)
        .into_par_iter()
        .map(|n| {
            let (i, j) = (n % w, n / w);
            let p = g.corner
                + g.u * ((i as f64 + 0.5) / w as f64)
                + g.v * ((j as f64 + 0.5) / h as f64);
            volume.trilinear(p).unwrap_or(f32::NAN)
        })
        .collect();
    ([w as u32, h as u32], values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_maps_the_window_and_skips_nan() {
        assert_eq!(grey(0.5, [0.0, 1.0]), Some(0.5));
        assert_eq!(grey(-3.0, [0.0, 1.0]), Some(0.0));
        assert_eq!(grey(9.0, [0.0, 1.0]), Some(1.0));
        assert_eq!(grey(1.0, [1.0, 1.0]), Some(1.0));
        assert_eq!(grey(f32::NAN, [0.0, 1.0]), None);
    }

    #[test]
    fn a_ray_meets_the_image_where_the_plane_is() {
        let g = PlaneGeometry {
            corner: DVec3::new(-1.0, -2.0, 3.0),
            u: DVec3::new(4.0, 0.0, 0.0),
            v: DVec3::new(0.0, 2.0, 0.0),
            normal: DVec3::Z,
            behind: 0.5,
        };
        let (t, s, r) = g
            .intersect(g.corner, DVec3::new(0.0, -1.0, 10.0), DVec3::NEG_Z)
            .expect("hits");
        assert!((t - 7.0).abs() < 1e-12 && (s - 0.25).abs() < 1e-12 && (r - 0.5).abs() < 1e-12);
        assert!(
            g.intersect(g.corner, DVec3::new(5.0, 0.0, 10.0), DVec3::NEG_Z)
                .is_none()
        );
    }
}
