//! ODF glyphs: the radial surface r(u) = max(f(u), 0) of a function f on the sphere, ray cast
//! per pixel. Two sources of f:
//!
//! - a spherical-harmonic series (a fibre ODF of `dwi2fod` or DIPY's CSD, [`crate::field::ShField`]),
//!   whose coefficients a scene keeps in its [`Payload`] (too many for an instance's two words);
//! - a tensor's own profile, r(u) = Σ rᵢ (u·eᵢ)² with the glyph's radii rᵢ and eigenvectors eᵢ
//!   (the lmax-2 series of uᵀTu: the ADC profile, a "peanut"), from the instance alone.
//!
//! **Parameter space.** p~ = Oᵀ (p − c) / R with R a bound of r over the sphere, so the glyph
//! lies in the unit ball (Gumhold's quad and Sigg's box are the ball's) and r~ = r / R ≤ 1.
//!
//! **The series as the GPU evaluates it**: up to lmax 12 as a homogeneous polynomial in x, y, z
//! ([`monomial`], converted from the plain basis once per glyph); above, in the "plain" basis:
//! Ỹ_l^m(u) = Q_l^|m|(z) · Re (x + iy)^m for m ≥ 0 and Q_l^|m|(z) · Im (x + iy)^|m| for m < 0, with Q_l^m = Λ_l^m / sin^m θ, a
//! polynomial in z by the recurrences of [`crate::sh`] §2 (the same in l at fixed m for Λ and
//! Λ/sinᵐθ). No trigonometry, no division, and the gradient of the polynomial extension comes
//! with it. A tournier07 coefficient is the plain one divided by (−1)^m √2 (m ≠ 0); any basis
//! is first converted to tournier07 ([`crate::sh::convert`], exact). [`plain_value`] is checked
//! against [`crate::sh::ShEval`] (itself checked against DIPY and MRtrix) in the tests.
//!
//! **Bounds, rigorous** ([`rigorous_bounds`]). G bounds |∇_S r~| and R bounds r: G is the
//! smaller of the addition theorem's Σₗ ‖cₗ‖ √(l(l+1)(2l+1)/4π) (Cauchy–Schwarz with
//! Σₘ |∇_S Yₗᵐ|² = l(l+1)(2l+1)/4π, cₗ the orthonormal coefficients of order l) and Bernstein's
//! L·‖f‖∞ for a series of degree L, with ‖f‖∞ from the values on a geodesic sphere and its
//! covering radius; R the smaller of Σₗ ‖cₗ‖ √((2l+1)/4π) and the sampled maximum plus G times
//! the covering radius. A tensor profile has G = (r₁ − r₃)/R.
//!
//! **The crossing** ([`plane_crossing`], the same algorithm in odf.wgsl; [`crossing`]'s module
//! doc): the series on the great circle of the ray's plane is a trigonometric polynomial of
//! degree L, found from L + 1 of its values; the surface is where g(φ) sin φ − b changes sign,
//! a trigonometric polynomial of degree L + 1 in the angle φ of the ray's points, whose first
//! crossing is approached by steps that a bound of its second derivative makes safe. The
//! reference runs it in f64, the shader in f32; the safe-step marcher along the ray
//! ([`first_crossing`]) stays as the tests' independent check.

use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};

use super::ellipsoid::icosphere;
use super::mesh::Mesh;
use super::{Capabilities, Exact, GlyphGeometry, GlyphInstance, GlyphKind, Part, RayHit, Shape};
use crate::glyph::{ColorScheme, Glyph, ResolvedStyle};
use crate::sh::ShError;

pub mod bound;
pub mod crossing;
pub mod monomial;
mod series;

pub use bound::{Ellipsoid, bounding_ellipsoid};
pub use monomial::SeriesForm;

pub use crossing::{first_crossing, normal_at, plane_crossing};
pub use series::{
    Sphere, basis_table, plain_of, plain_value, plain_value_gradient, range_of, rigorous_bounds,
    sampled_range, sampled_values, sampled_values_many, series_bounds, sphere_for,
};

pub const WGSL: &str = include_str!("../../../shaders/shape/odf.wgsl");

/// The parameter word flag (word 1, bit 0) by which a series glyph is coloured per pixel by the
/// direction of its surface point from its centre (DEC, as mrview colours ODFs).
pub const DIRECTION_COLOUR: u32 = 1;
/// The parameter word flag (word 1, bit 1) by which a glyph is coloured per pixel by its
/// amplitude: r~(u) times the series' amplitude scale ([`Payload::amplitude_scale`]; 1 for a
/// tensor's profile) through viridis, as DIPY's `odf_slicer` colours by the normalised values.
pub const AMPLITUDE_COLOUR: u32 = 2;

/// How an ODF glyph is coloured per pixel (its parameter word 1's flags).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OdfColoring {
    /// The instance's own colour.
    Base,
    /// The direction of the point from the centre (DEC).
    Direction,
    /// The amplitude at the point's direction through viridis.
    Amplitude,
}

impl OdfColoring {
    /// The flags of parameter word 1.
    pub fn flags(self) -> u32 {
        match self {
            OdfColoring::Base => 0,
            OdfColoring::Direction => DIRECTION_COLOUR,
            OdfColoring::Amplitude => AMPLITUDE_COLOUR,
        }
    }

    /// The colouring of parameter word 1 `word` (direction wins over amplitude).
    pub fn of_flags(word: u32) -> Self {
        if word & DIRECTION_COLOUR != 0 {
            OdfColoring::Direction
        } else if word & AMPLITUDE_COLOUR != 0 {
            OdfColoring::Amplitude
        } else {
            OdfColoring::Base
        }
    }
}

/// The marcher's smallest step, in units of R (the tests' independent check).
pub const REFERENCE_EPS: f64 = 1e-7;
/// The smallest step in the ray plane's angle φ (rad), of the reference and of odf.wgsl
/// (`ODF_STEP`): what can be stepped over is a bump of H no higher than K₂·step²/8
/// ([`crossing`]'s module doc).
pub const REFERENCE_STEP: f64 = 1e-12;
pub const GPU_STEP: f64 = 1.0 / 32768.0;

/// Per-glyph values too large for an instance's two parameter words, which a scene keeps beside
/// its instances and the GPU reads from the same storage binding as the words: for ODF glyphs,
/// each series' G and coefficients ([`Self::series`], in [`Self::form`]), and the glyph's own axes and
/// bounding ellipsoid ([`Self::rotation`], [`Self::bound`]). An instance's word 0 is its series
/// index plus one (0: no series).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Payload {
    pub lmax: u32,
    /// Coefficients per series.
    pub count: usize,
    /// Per series, `stride()` floats: G, then the `count` coefficients of r~ in
    /// [`Self::form`] (in the series' axes), its amplitude scale, the rotation from the glyph's axes to the series'
    /// (a quaternion x, y, z, w), the bounding ellipsoid's semi-axes over R, then zeros.
    pub values: Vec<f32>,
}

impl Payload {
    pub fn new(lmax: u32) -> Result<Self, ShError> {
        Ok(Self {
            lmax,
            count: crate::sh::count_of_lmax(lmax)?,
            values: Vec::new(),
        })
    }

    /// Floats per series: a multiple of 4 (a series starts on a 16-byte boundary).
    pub fn stride(&self) -> usize {
        (self.count + 9).div_ceil(4) * 4
    }

    pub fn len(&self) -> usize {
        self.values.len() / self.stride().max(1)
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// How the series are held: monomials up to [`monomial::MAX_MONOMIAL_LMAX`], plain above.
    pub fn form(&self) -> SeriesForm {
        SeriesForm::for_lmax(self.lmax)
    }

    /// Series `k`: G, then its coefficients in [`Self::form`].
    pub fn series(&self, k: usize) -> &[f32] {
        let s = self.stride();
        &self.values[k * s..k * s + 1 + self.count]
    }

    /// What r~ is multiplied by for the amplitude colouring of series `k`: R over the glyph's
    /// full radius, so that the colour's 1 is the normalisation's 1 (the voxel's largest value,
    /// or the field's with no normalisation) and not the series' own bound.
    pub fn amplitude_scale(&self, k: usize) -> f32 {
        self.values[k * self.stride() + 1 + self.count]
    }

    /// The rotation taking a direction in the axes of glyph `k` (its instance's rotation) to
    /// the axes its series is written in, as the GPU reads it (quat_to_mat3 in common.wgsl).
    pub fn rotation(&self, k: usize) -> DMat3 {
        let at = k * self.stride() + 2 + self.count;
        let q = &self.values[at..at + 4];
        let [x, y, z, w] = [0, 1, 2, 3].map(|i| f64::from(q[i]));
        super::geometry::quat_to_mat3_unnormalised(DQuat::from_xyzw(x, y, z, w))
    }

    /// The semi-axes of glyph `k`'s bounding ellipsoid along its axes, over its R.
    pub fn bound(&self, k: usize) -> DVec3 {
        let at = k * self.stride() + 6 + self.count;
        DVec3::from(std::array::from_fn::<f64, 3, _>(|i| {
            f64::from(self.values[at + i])
        }))
    }

    /// Append a series of r~ (plain coefficients in the series' axes, f64; kept in
    /// [`Self::form`]) with its gradient bound, amplitude scale, the rotation from the glyph's axes to the series' and the
    /// bounding ellipsoid's semi-axes over R; its index.
    pub fn push(
        &mut self,
        plain: &[f64],
        g: f64,
        amplitude_scale: f64,
        rotation: DQuat,
        bound: DVec3,
    ) -> usize {
        let k = self.len();
        self.values.push(g as f32);
        let coefficients = self.form().coefficients(plain, self.lmax);
        self.values.extend(coefficients.iter().map(|&c| c as f32));
        self.values.push(amplitude_scale as f32);
        let q = rotation.normalize();
        self.values
            .extend([q.x, q.y, q.z, q.w, bound.x, bound.y, bound.z].map(|v| v as f32));
        self.values.resize((k + 1) * self.stride(), 0.0);
        k
    }
}

/// The ODF kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Odf
    }

    fn caps(&self) -> Capabilities {
        Capabilities {
            mesh_holes: true,
            amplitude: true,
            ..Capabilities::NONE
        }
    }

    /// A tensor's profile: the eigenvector frame and the style's radii, no series; coloured by
    /// amplitude when the style says so.
    fn place(&self, g: &Glyph, _part: usize, style: &ResolvedStyle) -> Option<Part> {
        let flags = if style.color == ColorScheme::Amplitude {
            AMPLITUDE_COLOUR
        } else {
            0
        };
        Some(Part::whole(
            g,
            style,
            (g.rotation, style.radii(g)),
            [0, flags],
        ))
    }

    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        DVec3::splat(geo.max_radius())
    }

    fn cull_radius(&self, radii: [f32; 3]) -> f64 {
        f64::from(radii[0].max(radii[1]).max(radii[2]))
    }

    /// A tensor profile; a series glyph needs its scene's payload ([`Self::exact_with`]).
    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        self.exact_with(geo, None)
    }

    fn exact_with(&self, geo: &GlyphGeometry, payload: Option<&Arc<Payload>>) -> Box<dyn Exact> {
        Box::new(Odf::of(geo, payload))
    }

    fn unit_mesh(&self, level: u8) -> Mesh {
        icosphere(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let f = 1usize << (2 * u32::from(level));
        (10 * f + 2, 20 * f)
    }

    /// odf.wgsl after the amplitude colouring's viridis.
    fn wgsl(&self) -> &'static [&'static str] {
        static PARTS: std::sync::LazyLock<[&'static str; 2]> =
            std::sync::LazyLock::new(|| [crate::glyph::colormap::viridis_wgsl(), WGSL]);
        &*PARTS
    }

    /// `ODF_GENERAL` keeps the paths of tensors' profiles and of plain series (lmax above
    /// [`monomial::MAX_MONOMIAL_LMAX`]) in odf.wgsl: a chunk of monomial series draws without.
    fn general_override(&self) -> Option<&'static str> {
        Some("ODF_GENERAL")
    }

    /// A profile (word 0 names no series) or a series past the monomials (lmax in word 1's
    /// second byte, as odf.wgsl reads it).
    fn is_general(&self, g: &GlyphInstance) -> bool {
        g.shape[0] == 0 || (g.shape[1] >> 8) & 0xff > monomial::MAX_MONOMIAL_LMAX
    }
}

/// r~ as a function on the unit sphere of parameter space.
#[derive(Debug, Clone)]
pub enum Profile {
    /// Σ aᵢ uᵢ² (a tensor's profile, aᵢ = rᵢ / R).
    Quadratic([f64; 3]),
    /// Coefficients of order `lmax` in `form`, as the GPU reads them (f32 values, exactly), in
    /// the axes that `rotation` turns the glyph's axes into.
    Series {
        lmax: u32,
        form: SeriesForm,
        coefficients: Vec<f64>,
        rotation: DMat3,
    },
}

impl Profile {
    /// The degree of f~ as a polynomial on the sphere.
    pub fn degree(&self) -> u32 {
        match self {
            Profile::Quadratic(_) => 2,
            Profile::Series { lmax, .. } => *lmax,
        }
    }

    /// f~(u) and its gradient ∇F of the polynomial extension F (u unit; r~ = max(f~, 0)).
    pub fn value_gradient(&self, u: DVec3) -> (f64, DVec3) {
        match self {
            Profile::Quadratic(a) => {
                let a = DVec3::from(*a);
                ((a * u * u).element_sum(), 2.0 * a * u)
            }
            Profile::Series {
                lmax,
                form,
                coefficients,
                rotation,
            } => {
                let (v, g) = form.value_gradient(coefficients, *lmax, *rotation * u);
                (v, rotation.transpose() * g)
            }
        }
    }

    pub fn value(&self, u: DVec3) -> f64 {
        match self {
            Profile::Quadratic(a) => (DVec3::from(*a) * u * u).element_sum(),
            Profile::Series {
                lmax,
                form,
                coefficients,
                rotation,
            } => form.value(coefficients, *lmax, *rotation * u),
        }
    }
}

/// An ODF glyph as the reference casts it (world, relative to the scene origin).
#[derive(Debug, Clone)]
pub struct Odf {
    pub centre: DVec3,
    /// Columns: the local axes (world).
    pub frame: DMat3,
    /// R: world units per parameter-space unit.
    pub scale: f64,
    pub profile: Profile,
    /// G: the gradient bound of r~ on the sphere.
    pub g: f64,
    /// How each point is coloured ([`OdfColoring::of_flags`]).
    pub coloring: OdfColoring,
    /// [`Payload::amplitude_scale`] (1 for a profile).
    pub amplitude_scale: f64,
}

impl Odf {
    /// The glyph of `geo`, its series (if any) from `payload`. A series glyph without a payload,
    /// or past its end, is drawn as nothing (r~ = 0): the scene builder writes both together.
    pub fn of(geo: &GlyphGeometry, payload: Option<&Arc<Payload>>) -> Self {
        let scale = geo.max_radius();
        let (profile, g, amplitude_scale) = match geo.params[0] {
            0 => {
                let a = (geo.radii / scale).to_array();
                let (hi, lo) = (a[0].max(a[1]).max(a[2]), a[0].min(a[1]).min(a[2]));
                (Profile::Quadratic(a), hi - lo, 1.0)
            }
            k => match payload.filter(|p| (k as usize) <= p.len()) {
                Some(p) => {
                    let s = p.series(k as usize - 1);
                    let coefficients = s[1..].iter().map(|&c| f64::from(c)).collect();
                    (
                        Profile::Series {
                            lmax: p.lmax,
                            form: p.form(),
                            coefficients,
                            rotation: p.rotation(k as usize - 1),
                        },
                        f64::from(s[0]),
                        f64::from(p.amplitude_scale(k as usize - 1)),
                    )
                }
                None => (Profile::Quadratic([0.0; 3]), 0.0, 1.0),
            },
        };
        Self {
            centre: geo.centre,
            frame: geo.frame,
            scale,
            profile,
            g,
            coloring: OdfColoring::of_flags(geo.params[1]),
            amplitude_scale,
        }
    }

    fn local(&self, p: DVec3) -> DVec3 {
        self.frame.transpose() * (p - self.centre) / self.scale
    }
}

impl Exact for Odf {
    fn centre(&self) -> DVec3 {
        self.centre
    }

    fn half_extents(&self) -> DVec3 {
        DVec3::splat(self.scale)
    }

    fn contains(&self, p: DVec3) -> bool {
        let q = self.local(p);
        let n = q.length();
        n == 0.0 || n <= self.profile.value(q / n)
    }

    /// As odf.wgsl's `shape_tint`: |w| / ‖w‖ for the direction w of `p` from the centre (DEC),
    /// or viridis at the amplitude in that direction (r~ in the glyph's axes times its scale).
    fn tint(&self, p: DVec3, base: DVec3) -> DVec3 {
        let w = p - self.centre;
        if w.length() == 0.0 {
            return base;
        }
        match self.coloring {
            OdfColoring::Base => base,
            OdfColoring::Direction => w.abs() / w.length(),
            OdfColoring::Amplitude => {
                let u = self.frame.transpose() * w / w.length();
                let t = self.profile.value(u).max(0.0) * self.amplitude_scale;
                DVec3::from(crate::glyph::colormap::viridis(t))
            }
        }
    }

    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let ot = self.frame.transpose();
        let o_t = ot * (o - self.centre) / self.scale;
        let v_t = ot * d / self.scale;
        let vl = v_t.length();
        if vl.is_nan() || vl <= 0.0 {
            return None;
        }
        let (s, n) = plane_crossing(
            &|u| self.profile.value_gradient(u),
            self.profile.degree(),
            o_t,
            v_t / vl,
            0.0,
            REFERENCE_STEP,
        )?;
        let normal = (self.frame * n).normalize();
        normal.is_finite().then_some(RayHit { t: s / vl, normal })
    }
}

#[cfg(test)]
pub(crate) mod test_util {
    use glam::DVec3;

    pub fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }

    pub fn random_dir(seed: &mut u64) -> DVec3 {
        loop {
            let v = DVec3::new(lcg(seed), lcg(seed), lcg(seed));
            if v.length_squared() > 0.01 && v.length_squared() < 1.0 {
                return v.normalize();
            }
        }
    }
}
