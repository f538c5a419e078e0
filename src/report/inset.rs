//! A figure's zoomed inset: a square region of one slice drawn at ≥ 8 pixels per voxel, so that
//! a glyph's shape (its anisotropy, its turn from its neighbours) can be read and not only its
//! colour, which is all a whole-brain slice in an overview tile (about 2 pixels per voxel)
//! shows.
//!
//! The region is chosen by the caller (`--zoom-region I,J,K:SIZE`: a voxel and a side in
//! voxels) or, by default, is where FA summed over the region is highest on the row's middle
//! slice: white matter, where a reviewer checks the glyphs. Its glyphs are drawn from the
//! report's one decomposition, under the same FA underlay and window as the overview.

use std::fmt;
use std::str::FromStr;

use glam::{DVec3, DVec4, Vec4Swizzles as _};

use crate::camera::{Camera, Framing};
use crate::glyph::GlyphSet;
use crate::select::lattice_coords;
use crate::tensor::shape::fa;

/// The region's side, in voxels, when none is asked for.
pub const DEFAULT_SIZE: usize = 48;
/// The largest side a region may have, in voxels (at ≥ 8 px per voxel, a 1 300-px inset).
pub const MAX_SIZE: usize = 128;
/// The overview tiles' side, in pixels, when none is asked for.
pub const DEFAULT_TILE: u32 = 256;
/// The smallest and largest overview tile: the labels need 128 px; 1024-px tiles make a row
/// of five 5 000 px wide.
pub const TILE_RANGE: (u32, u32) = (128, 1024);
/// The inset's smallest side, in pixels.
const MIN_SIDE: u32 = 400;
/// The largest: a region of long, thin voxels is drawn at fewer pixels per voxel rather than
/// in an image no page shows.
const MAX_SIDE: u32 = 2048;
/// The pixels per voxel the inset's side is chosen for (8 asked, some to spare for rounding).
pub const PX_PER_VOXEL: f64 = 8.5;
/// The share of the inset's side the region fills: the rest is room for its labels.
pub const FILL: f64 = 0.9;
/// [`Camera::frame_box`]'s margin around what it frames.
const FRAME_MARGIN: f64 = 1.03;

/// A report option with a value it cannot take; the front end names the option.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    #[error("'{0}' is not I,J,K:SIZE (a voxel's three lattice indices, a colon, a side in voxels)")]
    RegionSyntax(String),
    #[error("'{0}': the side must be 2 to {MAX_SIZE} voxels")]
    RegionSize(String),
    #[error("{0}: the tile side must be {min} to {max} pixels", min = TILE_RANGE.0, max = TILE_RANGE.1)]
    Tile(u32),
}

/// The voxel an inset is centred on and its side, in voxels (`I,J,K:SIZE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ZoomRegion {
    pub centre: [usize; 3],
    pub size: usize,
}

impl FromStr for ZoomRegion {
    type Err = OptionError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let syntax = || OptionError::RegionSyntax(s.to_string());
        let (centre, size) = s.split_once(':').ok_or_else(syntax)?;
        let centre: Vec<usize> = centre
            .split(',')
            .map(|v| v.trim().parse::<usize>())
            .collect::<Result<_, _>>()
            .map_err(|_| syntax())?;
        let centre: [usize; 3] = centre.try_into().map_err(|_| syntax())?;
        let size: usize = size.trim().parse().map_err(|_| syntax())?;
        if !(2..=MAX_SIZE).contains(&size) {
            return Err(OptionError::RegionSize(s.to_string()));
        }
        Ok(Self { centre, size })
    }
}

impl fmt::Display for ZoomRegion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [i, j, k] = self.centre;
        write!(f, "{i},{j},{k}:{}", self.size)
    }
}

/// `px` if an overview tile may be that many pixels wide.
pub fn check_tile(px: u32) -> Result<u32, OptionError> {
    if (TILE_RANGE.0..=TILE_RANGE.1).contains(&px) {
        Ok(px)
    } else {
        Err(OptionError::Tile(px))
    }
}

/// A centre asked for outside the volume.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "zoom region {region}: voxel {i},{j},{k} is outside the lattice ({nx}×{ny}×{nz} voxels)",
    i = region.centre[0], j = region.centre[1], k = region.centre[2],
    nx = dims[0], ny = dims[1], nz = dims[2]
)]
pub struct OutsideLattice {
    pub region: ZoomRegion,
    pub dims: [usize; 3],
}

/// The voxels an inset shows: `lo[a]..hi[a]` along each lattice axis, one slice thick along
/// `axis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    pub axis: usize,
    pub lo: [usize; 3],
    pub hi: [usize; 3],
}

impl Region {
    pub fn slice(&self) -> usize {
        self.lo[self.axis]
    }

    pub fn contains(&self, ijk: [usize; 3]) -> bool {
        (0..3).all(|a| (self.lo[a]..self.hi[a]).contains(&ijk[a]))
    }

    /// The two lattice axes across the slice, in order.
    pub fn across(&self) -> [usize; 2] {
        across(self.axis)
    }

    /// `i 40–87, j 60–107, k = 35` (inclusive ranges).
    pub fn describe(&self) -> String {
        let name = ["i", "j", "k"];
        let [a, b] = self.across();
        format!(
            "{} {}–{}, {} {}–{}, {} = {}",
            name[a],
            self.lo[a],
            self.hi[a] - 1,
            name[b],
            self.lo[b],
            self.hi[b] - 1,
            name[self.axis],
            self.slice()
        )
    }
}

fn across(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// The `n` consecutive indices of `0..dim` centred on `c` as nearly as the lattice allows.
fn span(c: usize, n: usize, dim: usize) -> (usize, usize) {
    let n = n.min(dim);
    let lo = c.saturating_sub(n / 2).min(dim - n);
    (lo, lo + n)
}

/// The region `zoom` asks for on the slices along lattice `axis` (a side longer than the
/// lattice is cut to it; one that overhangs an edge is moved inside).
pub fn given(zoom: ZoomRegion, dims: [usize; 3], axis: usize) -> Result<Region, OutsideLattice> {
    if (0..3).any(|a| zoom.centre[a] >= dims[a]) {
        return Err(OutsideLattice { region: zoom, dims });
    }
    let (mut lo, mut hi) = ([0; 3], [0; 3]);
    lo[axis] = zoom.centre[axis];
    hi[axis] = zoom.centre[axis] + 1;
    for a in across(axis) {
        (lo[a], hi[a]) = span(zoom.centre[a], zoom.size, dims[a]);
    }
    Ok(Region { axis, lo, hi })
}

/// The `size`-voxel square (cut to the lattice) of slice `slice` along `axis` whose glyphs'
/// FA sums highest (the first such in storage order): white matter.
pub fn brightest(
    set: &GlyphSet,
    dims: [usize; 3],
    axis: usize,
    slice: usize,
    size: usize,
) -> Region {
    let fa_of = set.glyphs.iter().map(|g| {
        (
            lattice_coords(g.index as usize, dims),
            fa(g.eigenvalues.map(f64::from)),
        )
    });
    brightest_of(fa_of, dims, axis, slice, size)
}

/// The `size`-voxel square (cut to the lattice) of slice `slice` along `axis` where `values`
/// (a voxel's lattice coordinates and its value; other slices' are passed over) sum highest,
/// the first such in storage order.
pub fn brightest_of(
    values: impl IntoIterator<Item = ([usize; 3], f64)>,
    dims: [usize; 3],
    axis: usize,
    slice: usize,
    size: usize,
) -> Region {
    let [a, b] = across(axis);
    let (na, nb) = (dims[a], dims[b]);
    // A summed-area table over the slice: every square's sum in four look-ups.
    let mut sum = vec![0.0f64; (na + 1) * (nb + 1)];
    for (ijk, value) in values {
        if ijk[axis] == slice && value.is_finite() {
            sum[(ijk[b] + 1) * (na + 1) + ijk[a] + 1] += value;
        }
    }
    for y in 1..=nb {
        for x in 1..=na {
            sum[y * (na + 1) + x] += sum[(y - 1) * (na + 1) + x] + sum[y * (na + 1) + x - 1]
                - sum[(y - 1) * (na + 1) + x - 1];
        }
    }
    let (sa, sb) = (size.min(na), size.min(nb));
    let at = |x: usize, y: usize| sum[y * (na + 1) + x];
    let mut best = (f64::NEG_INFINITY, 0, 0);
    for y in 0..=nb - sb {
        for x in 0..=na - sa {
            let s = at(x + sa, y + sb) - at(x, y + sb) - at(x + sa, y) + at(x, y);
            if s > best.0 {
                best = (s, x, y);
            }
        }
    }
    let (mut lo, mut hi) = ([0; 3], [0; 3]);
    (lo[axis], hi[axis]) = (slice, slice + 1);
    (lo[a], hi[a]) = (best.1, best.1 + sa);
    (lo[b], hi[b]) = (best.2, best.2 + sb);
    Region { axis, lo, hi }
}

/// The world position of voxel (i, j, k) of a lattice: what the inset's geometry needs of a
/// field (a tensor field's `lattice::position_in`, an SH field's affine).
pub type At<'a> = &'a dyn Fn([usize; 3]) -> DVec3;

/// The world position of the voxel centre `ijk` (indices as reals: half-way points too).
fn world(at: At<'_>, dims: [usize; 3], ijk: [f64; 3]) -> DVec3 {
    let origin = at([0; 3]);
    let mut p = origin;
    for (a, &v) in ijk.iter().enumerate() {
        if dims[a] > 1 {
            let mut c = [0; 3];
            c[a] = 1;
            p += (at(c) - origin) * v;
        }
    }
    p
}

/// The region's outline on its slice: the four corners of its voxels' cells (half a voxel
/// beyond the outer centres), in order around it.
pub fn corners(at: At<'_>, dims: [usize; 3], region: &Region) -> [DVec3; 4] {
    let [a, b] = region.across();
    let mut c = [region.slice() as f64; 3];
    let lo = |x: usize| region.lo[x] as f64 - 0.5;
    let hi = |x: usize| region.hi[x] as f64 - 0.5;
    [
        (lo(a), lo(b)),
        (hi(a), lo(b)),
        (hi(a), hi(b)),
        (lo(a), hi(b)),
    ]
    .map(|(u, v)| {
        c[a] = u;
        c[b] = v;
        world(at, dims, c)
    })
}

/// The world range `[min, max]` along x, y and z of the region's voxel centres.
pub fn world_range(at: At<'_>, dims: [usize; 3], region: &Region) -> [[f64; 2]; 3] {
    let mut out = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
    for k in 0..8 {
        let c: [f64; 3] = std::array::from_fn(|x| {
            if k >> x & 1 == 1 {
                (region.hi[x] - 1) as f64
            } else {
                region.lo[x] as f64
            }
        });
        let p = world(at, dims, c);
        for w in 0..3 {
            out[w] = [out[w][0].min(p[w]), out[w][1].max(p[w])];
        }
    }
    out
}

/// The lengths of one step along each lattice axis, world units.
fn steps(at: At<'_>, dims: [usize; 3]) -> [f64; 3] {
    let origin = world(at, dims, [0.0; 3]);
    std::array::from_fn(|a| {
        let mut c = [0.0; 3];
        c[a] = 1.0;
        (world(at, dims, c) - origin).length()
    })
}

/// The inset's side in pixels: the region's longer side at [`PX_PER_VOXEL`] of its shorter
/// voxel step, the region filling [`FILL`] of it.
pub fn side(at: At<'_>, dims: [usize; 3], region: &Region) -> u32 {
    let step = steps(at, dims);
    let [a, b] = region.across();
    let extent = ((region.hi[a] - region.lo[a]) as f64 * step[a])
        .max((region.hi[b] - region.lo[b]) as f64 * step[b]);
    let voxel = [step[a], step[b]]
        .into_iter()
        .filter(|s| *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    let px = (PX_PER_VOXEL * FRAME_MARGIN / FILL * extent / voxel).ceil();
    let px = if px.is_finite() { px as u32 } else { MIN_SIDE };
    px.next_multiple_of(8).clamp(MIN_SIDE, MAX_SIDE)
}

/// The camera that shows `region` face-on (`toward`: view direction and up) filling [`FILL`]
/// of a `side`-pixel square.
pub fn camera(
    at: At<'_>,
    dims: [usize; 3],
    region: &Region,
    toward: (DVec3, DVec3),
    side: u32,
) -> Camera {
    let c = corners(at, dims, region);
    let lo = c.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
    let hi = c.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
    let framing = Framing {
        toward: Some(toward),
        ortho: true,
        zoom: FILL,
        ..Framing::default()
    };
    Camera::frame_box(&framing, (lo + hi) / 2.0, (hi - lo) / 2.0, side, side)
}

/// Where world point `p` lands in `camera`'s image, in pixels from its top-left corner.
pub fn to_pixel(camera: &Camera, p: DVec3) -> [f64; 2] {
    let clip = camera.projection_matrix() * camera.view(DVec3::ZERO) * DVec4::from((p, 1.0));
    let ndc = clip.xyz() / clip.w;
    let (w, h) = (f64::from(camera.width), f64::from(camera.height));
    [(ndc.x + 1.0) / 2.0 * w, (1.0 - ndc.y) / 2.0 * h]
}

/// Pixels per voxel along the slice in `camera`'s image: of the shorter step across it (the
/// one that shows the fewest pixels per voxel).
pub fn px_per_voxel(at: At<'_>, dims: [usize; 3], axis: usize, camera: &Camera) -> f64 {
    let step = steps(at, dims);
    let per_unit = camera.pixels_per_unit();
    across(axis)
        .into_iter()
        .filter(|&a| dims[a] > 1)
        .map(|a| step[a] * per_unit)
        .fold(f64::INFINITY, f64::min)
}

/// The glyphs of `set` in `region` (the whole set's statistics kept: their sizes are the
/// overview's).
pub fn glyphs_in(set: &GlyphSet, dims: [usize; 3], region: &Region) -> GlyphSet {
    GlyphSet {
        glyphs: set
            .glyphs
            .iter()
            .filter(|g| region.contains(lattice_coords(g.index as usize, dims)))
            .copied()
            .collect(),
        stats: set.stats.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_parse_and_bad_ones_say_what_is_wrong() {
        let z: ZoomRegion = "64,70,35:48".parse().unwrap();
        assert_eq!((z.centre, z.size), ([64, 70, 35], 48));
        assert_eq!(z.to_string(), "64,70,35:48");
        assert_eq!(
            " 1, 2 ,3 : 4".parse::<ZoomRegion>().unwrap().centre,
            [1, 2, 3]
        );
        for bad in [
            "64,70:48",
            "64,70,35",
            "a,b,c:4",
            "1,2,3,4:5",
            "-1,2,3:4",
            "1,2,3:x",
        ] {
            assert_eq!(
                bad.parse::<ZoomRegion>(),
                Err(OptionError::RegionSyntax(bad.into()))
            );
        }
        for bad in ["1,2,3:1", "1,2,3:0", "1,2,3:129"] {
            assert_eq!(
                bad.parse::<ZoomRegion>(),
                Err(OptionError::RegionSize(bad.into()))
            );
        }
        assert_eq!(check_tile(256), Ok(256));
        assert_eq!(check_tile(127), Err(OptionError::Tile(127)));
        assert_eq!(check_tile(1025), Err(OptionError::Tile(1025)));
    }

    #[test]
    fn a_given_region_stays_inside_the_lattice() {
        let dims = [128, 128, 70];
        let z = |centre, size| ZoomRegion { centre, size };
        // Axial (k): i and j across, centred; at an edge, moved inside; longer than the
        // lattice along k for a sagittal slice, cut to it.
        let r = given(z([64, 64, 35], 48), dims, 2).unwrap();
        assert_eq!((r.lo, r.hi), ([40, 40, 35], [88, 88, 36]));
        let r = given(z([2, 127, 35], 48), dims, 2).unwrap();
        assert_eq!((r.lo, r.hi), ([0, 80, 35], [48, 128, 36]));
        let r = given(z([64, 64, 35], 100), dims, 0).unwrap();
        assert_eq!((r.lo, r.hi), ([64, 14, 0], [65, 114, 70]));
        assert_eq!(r.describe(), "j 14–113, k 0–69, i = 64");
        let e = given(z([64, 64, 70], 8), dims, 2).unwrap_err();
        assert_eq!(
            e.to_string(),
            "zoom region 64,64,70:8: voxel 64,64,70 is outside the lattice (128×128×70 voxels)"
        );
    }
}
