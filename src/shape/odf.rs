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
//! **The series as the GPU evaluates it** ("plain" basis): Ỹ_l^m(u) = Q_l^|m|(z) · Re (x + iy)^m
//! for m ≥ 0 and Q_l^|m|(z) · Im (x + iy)^|m| for m < 0, with Q_l^m = Λ_l^m / sin^m θ, a
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
//! **The crossing** ([`first_crossing`], the same algorithm in odf.wgsl): along the ray inside
//! the unit ball, h(s) = r~(u(s)) − |q(s)| changes sign at the surface. h is Lipschitz along
//! the ray with K = 1 + G·b/m², b the ray's distance from the centre and m a lower bound of
//! |q| over the step, so a step of |h|/K cannot pass a crossing; steps are at least `eps`, so a
//! lobe thinner than `eps` along the ray can be stepped over (the stated bound), and the first
//! sign change is bisected to the precision of the arithmetic. The reference runs it in f64
//! with eps = 1e-7 (of R) and no step cap; the shader in f32 with eps = 2⁻¹³, a cap, and its
//! steps over-relaxed (1.5 safe steps, kept only where the new point's safe radius reaches
//! back over the gap; Keinert et al. 2014), which passes no crossing either.

use std::sync::Arc;

use glam::{DMat3, DVec3};

use super::ellipsoid::icosphere;
use super::mesh::Mesh;
use super::{Capabilities, Exact, GlyphGeometry, GlyphKind, Part, RayHit, Shape};
use crate::glyph::{ColorScheme, Glyph, ResolvedStyle};
use crate::sh::{ShBasis, ShError, convert, degrees, lmax_of_count};

pub const WGSL: &str = include_str!("../../shaders/shape/odf.wgsl");

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

/// The marcher's smallest step, in units of R: the reference's and the shader's.
pub const REFERENCE_EPS: f64 = 1e-7;
pub const GPU_EPS: f64 = 1.0 / 8192.0;

/// Per-glyph values too large for an instance's two parameter words, which a scene keeps beside
/// its instances and the GPU reads from the same storage binding as the words: for ODF glyphs,
/// each series' G and plain coefficients ([`Self::series`]). An instance's word 0 is its series
/// index plus one (0: no series).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Payload {
    pub lmax: u32,
    /// Coefficients per series.
    pub count: usize,
    /// Per series, `stride()` floats: G, then the `count` plain coefficients of r~, then its
    /// amplitude scale, then zeros.
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
        (self.count + 2).div_ceil(4) * 4
    }

    pub fn len(&self) -> usize {
        self.values.len() / self.stride().max(1)
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Series `k`: G, then the plain coefficients.
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

    /// Append a series of r~ (plain coefficients, f64) with its gradient bound and amplitude
    /// scale; its index.
    pub fn push(&mut self, plain: &[f64], g: f64, amplitude_scale: f64) -> usize {
        let k = self.len();
        self.values.push(g as f32);
        self.values.extend(plain.iter().map(|&c| c as f32));
        self.values.push(amplitude_scale as f32);
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
            prepass: false,
            splats: false,
            conservative_depth: false,
            sharpness: false,
            benched_by_default: false,
            mesh_holes: true,
            arrows: false,
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
}

/// r~ as a function on the unit sphere of parameter space.
#[derive(Debug, Clone)]
pub enum Profile {
    /// Σ aᵢ uᵢ² (a tensor's profile, aᵢ = rᵢ / R).
    Quadratic([f64; 3]),
    /// Plain coefficients of order `lmax`, as the GPU reads them (f32 values, exactly).
    Series { lmax: u32, plain: Vec<f64> },
}

impl Profile {
    /// f~(u) and its gradient ∇F of the polynomial extension F (u unit; r~ = max(f~, 0)).
    pub fn value_gradient(&self, u: DVec3) -> (f64, DVec3) {
        match self {
            Profile::Quadratic(a) => {
                let a = DVec3::from(*a);
                ((a * u * u).element_sum(), 2.0 * a * u)
            }
            Profile::Series { lmax, plain } => plain_value_gradient(plain, *lmax, u),
        }
    }

    pub fn value(&self, u: DVec3) -> f64 {
        match self {
            Profile::Quadratic(a) => (DVec3::from(*a) * u * u).element_sum(),
            Profile::Series { lmax, plain } => plain_value(plain, *lmax, u),
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
                    let plain = s[1..].iter().map(|&c| f64::from(c)).collect();
                    (
                        Profile::Series {
                            lmax: p.lmax,
                            plain,
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
        let (s, n) = first_crossing(
            &|u| self.profile.value_gradient(u),
            o_t,
            v_t / vl,
            self.g,
            0.0,
            REFERENCE_EPS,
            usize::MAX,
        )?;
        let normal = (self.frame * n).normalize();
        normal.is_finite().then_some(RayHit { t: s / vl, normal })
    }
}

/// The first crossing of the ray `o + s d` (parameter space, `d` unit) with r~ = max(f~, 0)
/// at s > `s_min`, by the module doc's marcher: (s, outward normal, not unit). `f` gives f~
/// and the gradient of its extension at a unit u; `g` bounds |∇_S f~|.
pub fn first_crossing(
    f: &dyn Fn(DVec3) -> (f64, DVec3),
    o: DVec3,
    d: DVec3,
    g: f64,
    s_min: f64,
    eps: f64,
    max_steps: usize,
) -> Option<(f64, DVec3)> {
    // The unit ball, from the point of the line nearest the centre (nothing cancels).
    let sc = -o.dot(d);
    let near = o + sc * d;
    let b2 = near.length_squared();
    if b2.is_nan() || b2 >= 1.0 {
        return None;
    }
    let b = b2.sqrt();
    let half = (1.0 - b2).sqrt();
    let (s0, s1) = (sc - half, sc + half);
    let mut s = s0.max(s_min);
    if s >= s1 {
        return None;
    }
    let h = |s: f64| -> f64 {
        let q = near + (s - sc) * d;
        let n = q.length();
        if n == 0.0 {
            return f(d).0.max(0.0);
        }
        f(q / n).0.max(0.0) - n
    };
    let mut hv = h(s);
    // On the ball (no glyph point lies beyond it) the ray starts outside: h ≥ 0 there is a
    // glyph touching its ball (a ball of a tensor profile is its own bound), met at once.
    let on_ball = s == s0;
    if on_ball && hv >= 0.0 {
        return Some((s, normal_at(f, near + (s - sc) * d)));
    }
    let inside = !on_ball && hv > 0.0;
    let mut steps = 0;
    while s < s1 && steps < max_steps {
        steps += 1;
        let q = near + (s - sc) * d;
        let a = hv.abs();
        // Lipschitz bound over the step: |q| ≥ max(b, |q(s)| − Δ).
        let k = |m: f64| {
            1.0 + if m > 0.0 {
                g * b / (m * m)
            } else {
                f64::INFINITY
            }
        };
        let d0 = a / k(q.length());
        let step = (a / k(b.max(q.length() - d0))).max(eps);
        let s_next = (s + step).min(s1);
        let h_next = h(s_next);
        if (h_next > 0.0) != inside {
            let (mut lo, mut hi) = (s, s_next);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if (h(mid) > 0.0) == inside {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let sh = if inside { lo } else { hi };
            let q = near + (sh - sc) * d;
            return Some((sh, normal_at(f, q)));
        }
        if s_next >= s1 {
            break;
        }
        s = s_next;
        hv = h_next;
    }
    None
}

/// The outward normal (not unit) of r~ = f~ at the surface point q: r u − ∇_S f~, which is the
/// gradient of |q| − f~(q/|q|) times |q| (no division by a radius that may be 0).
pub fn normal_at(f: &dyn Fn(DVec3) -> (f64, DVec3), q: DVec3) -> DVec3 {
    let n = q.length();
    if n == 0.0 {
        return DVec3::Z;
    }
    let u = q / n;
    let (v, grad) = f(u);
    let tangential = grad - grad.dot(u) * u;
    v.max(0.0) * u - tangential
}

/// The plain coefficients of a series (`basis`, any lmax) scaled by `k`: r~ = k·f.
pub fn plain_of(c: &[f64], basis: ShBasis, k: f64) -> Result<Vec<f64>, ShError> {
    let t = convert(c, basis, ShBasis::Tournier07)?;
    let lmax = lmax_of_count(c.len())?;
    Ok(degrees(lmax)
        .zip(t)
        .map(|((_, m), v)| k * v * plain_factor(m))
        .collect())
}

/// plain = tournier07 × this.
fn plain_factor(m: i32) -> f64 {
    if m == 0 {
        1.0
    } else if m % 2 == 0 {
        std::f64::consts::SQRT_2
    } else {
        -std::f64::consts::SQRT_2
    }
}

/// Σₗ ‖cₗ‖ √((2l+1)/4π) and Σₗ ‖cₗ‖ √(l(l+1)(2l+1)/4π) for plain coefficients: bounds of |f|
/// and of |∇_S f| on the sphere (module doc).
pub fn series_bounds(plain: &[f64], lmax: u32) -> (f64, f64) {
    let mut norms = vec![0.0; lmax as usize + 1];
    for ((l, m), &p) in degrees(lmax).zip(plain) {
        let c = p / plain_factor(m);
        norms[l as usize] += c * c;
    }
    let four_pi = 4.0 * std::f64::consts::PI;
    norms
        .iter()
        .enumerate()
        .fold((0.0, 0.0), |(v, g), (l, &n2)| {
            let l = l as f64;
            let n = n2.sqrt();
            (
                v + n * ((2.0 * l + 1.0) / four_pi).sqrt(),
                g + n * (l * (l + 1.0) * (2.0 * l + 1.0) / four_pi).sqrt(),
            )
        })
}

/// Directions on which a series is sampled, and their covering radius: every direction lies
/// within `cover` (rad) of one of them.
pub struct Sphere {
    pub directions: Vec<DVec3>,
    pub cover: f64,
}

/// The geodesic sphere of icosphere level 4 (2562 directions) for lmax ≤ 8, of level 5 (10242)
/// above: fine enough that Bernstein's bound below stays tight. The covering radius is the
/// largest circumradius of the triangles (each point of a triangle lies within it of a
/// corner), computed, with 1 % to spare.
pub fn sphere_for(lmax: u32) -> &'static Sphere {
    static SPHERES: [std::sync::OnceLock<Sphere>; 2] =
        [std::sync::OnceLock::new(), std::sync::OnceLock::new()];
    let k = usize::from(lmax > 8);
    SPHERES[k].get_or_init(|| {
        let mesh = icosphere(4 + k as u8);
        let directions: Vec<DVec3> = mesh
            .vertices
            .iter()
            .map(|v| DVec3::from(v.position.map(f64::from)).normalize())
            .collect();
        let cover = mesh
            .indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|i| directions[t[i] as usize]);
                let n = (b - a).cross(c - a).normalize();
                let n = if n.dot(a) < 0.0 { -n } else { n };
                n.dot(a).clamp(-1.0, 1.0).acos()
            })
            .fold(0.0, f64::max);
        Sphere {
            directions,
            cover: cover * 1.01,
        }
    })
}

/// The smallest and largest value of a series on [`sphere_for`] its lmax: a dot product per
/// direction with [`basis_table`]'s row (a scene's build spent nearly all its time here when
/// each direction ran the recurrence: 1.9 ms of CPU a voxel at lmax 8).
pub fn sampled_range(plain: &[f64], lmax: u32) -> (f64, f64) {
    let rows = sphere_for(lmax).directions.len();
    let Some(table) = basis_table(lmax).filter(|t| t.len() == rows * plain.len()) else {
        return sphere_for(lmax)
            .directions
            .iter()
            .map(|&u| plain_value(plain, lmax, u))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
    };
    table
        .chunks_exact(plain.len())
        .map(|row| dot(row, plain))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// Σ aᵢbᵢ in four running sums (which the compiler keeps in vector lanes).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (a4, a1) = a.split_at(a.len() / 4 * 4);
    let (b4, b1) = b.split_at(a4.len().min(b.len()));
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = a1.iter().zip(b1).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// The plain basis functions at each direction of [`sphere_for`] `lmax`, a row of
/// `count_of_lmax(lmax)` per direction, made once per lmax (lmax 8: 0.9 MB; lmax 12: 7.5 MB);
/// `None` for an lmax with no SH count.
pub fn basis_table(lmax: u32) -> Option<&'static [f64]> {
    const KEPT: usize = 16;
    static TABLES: [std::sync::OnceLock<Vec<f64>>; KEPT] =
        [const { std::sync::OnceLock::new() }; KEPT];
    let n = crate::sh::count_of_lmax(lmax).ok()?;
    let slot = TABLES.get((lmax / 2) as usize)?;
    Some(slot.get_or_init(|| {
        let dirs = &sphere_for(lmax).directions;
        let mut t = vec![0.0; dirs.len() * n];
        for (row, &u) in t.chunks_exact_mut(n).zip(dirs) {
            plain_basis(lmax, u, row);
        }
        t
    }))
}

/// Each plain basis function at unit `u`, in the plain order (`out`: `count_of_lmax(lmax)`
/// values): [`plain_value_gradient`]'s terms without their coefficients.
fn plain_basis(lmax: u32, u: DVec3, out: &mut [f64]) {
    let (x, y, z) = (u.x, u.y, u.z);
    let (mut c, mut s) = (1.0, 0.0);
    let mut seed = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    for m in 0..=lmax {
        let mf = f64::from(m);
        if m > 0 {
            seed *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let (mut q2, mut q1) = (0.0, seed);
        for l in m..=lmax {
            if l > m {
                let lf = f64::from(l);
                let q0 = if l == m + 1 {
                    (2.0 * mf + 3.0).sqrt() * z * q1
                } else {
                    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                    let bb = (((lf - 1.0) * (lf - 1.0) - mf * mf)
                        / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0))
                        .sqrt();
                    a * (z * q1 - bb * q2)
                };
                (q2, q1) = (q1, q0);
            }
            if l % 2 != 0 {
                continue;
            }
            let base = (l * (l + 1) / 2) as usize;
            out[base + m as usize] = q1 * c;
            if m > 0 {
                out[base - m as usize] = q1 * s;
            }
        }
    }
}

/// Rigorous bounds of a series whose sampled range ([`sampled_range`]) is `(min, max)`: G ≥
/// |∇_S f| and R ≥ f everywhere. G is the smaller of the addition theorem's bound
/// ([`series_bounds`]) and Bernstein's inequality for spherical polynomials of degree L,
/// |∇_S f| ≤ L ‖f‖∞ (along any great circle f is a trigonometric polynomial of degree ≤ L),
/// with ‖f‖∞ ≤ max(|min|, |max|) / (1 − L·cover) (the sample nearest any point is within
/// `cover` of it); R the smaller of the addition theorem's and max + G·cover.
pub fn rigorous_bounds(plain: &[f64], lmax: u32, (min, max): (f64, f64)) -> (f64, f64) {
    let cover = sphere_for(lmax).cover;
    let (vb, g_cs) = series_bounds(plain, lmax);
    let shrink = 1.0 - f64::from(lmax) * cover;
    let g_bernstein = if shrink > 0.0 {
        f64::from(lmax) * min.abs().max(max.abs()) / shrink
    } else {
        f64::INFINITY
    };
    let g = g_cs.min(g_bernstein);
    (g, vb.min(max + g * cover))
}

/// The plain series at unit `u`.
pub fn plain_value(plain: &[f64], lmax: u32, u: DVec3) -> f64 {
    plain_value_gradient(plain, lmax, u).0
}

/// The plain series at unit `u` and the gradient of its polynomial extension.
pub fn plain_value_gradient(plain: &[f64], lmax: u32, u: DVec3) -> (f64, DVec3) {
    let (x, y, z) = (u.x, u.y, u.z);
    let mut f = 0.0;
    let mut grad = DVec3::ZERO;
    // (x + iy)^m = c + i s, and (x + iy)^(m−1).
    let (mut c, mut s) = (1.0, 0.0);
    let (mut c1, mut s1) = (0.0, 0.0);
    let mut seed = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    for m in 0..=lmax {
        if m > 0 {
            let mf = f64::from(m);
            seed *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (c1, s1) = (c, s);
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let mf = f64::from(m);
        // ∂/∂x, ∂/∂y of Re and Im (x + iy)^m.
        let (cx, cy) = (mf * c1, -mf * s1);
        let (sx, sy) = (mf * s1, mf * c1);
        // Q_l^m and dQ/dz for l = m, m + 1, …
        let (mut q2, mut d2) = (0.0, 0.0);
        let (mut q1, mut d1) = (seed, 0.0);
        for l in m..=lmax {
            if l > m {
                let lf = f64::from(l);
                let (q0, d0) = if l == m + 1 {
                    let a = (2.0 * mf + 3.0).sqrt();
                    (a * z * q1, a * q1)
                } else {
                    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                    let bb = (((lf - 1.0) * (lf - 1.0) - mf * mf)
                        / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0))
                        .sqrt();
                    (a * (z * q1 - bb * q2), a * (q1 + z * d1 - bb * d2))
                };
                (q2, d2) = (q1, d1);
                (q1, d1) = (q0, d0);
            }
            if l % 2 != 0 {
                continue;
            }
            let base = (l * (l + 1) / 2) as usize;
            let pc = plain[base + m as usize];
            f += pc * q1 * c;
            grad += pc * DVec3::new(q1 * cx, q1 * cy, d1 * c);
            if m > 0 {
                let ps = plain[base - m as usize];
                f += ps * q1 * s;
                grad += ps * DVec3::new(q1 * sx, q1 * sy, d1 * s);
            }
        }
    }
    (f, grad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::ShEval;

    /// The table's rows are the plain series' terms: a series' value at each sampled direction
    /// is its dot product with the row, to rounding, at every lmax the reader takes to 12.
    #[test]
    fn basis_table_rows_evaluate_the_plain_series() {
        let mut seed = 7;
        for lmax in [2, 4, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let plain: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            let table = basis_table(lmax).unwrap();
            let dirs = &sphere_for(lmax).directions;
            assert_eq!(table.len(), dirs.len() * n);
            for (k, &u) in dirs.iter().enumerate().step_by(97) {
                let want = plain_value(&plain, lmax, u);
                let got = dot(&table[k * n..(k + 1) * n], &plain);
                assert!(
                    (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "lmax {lmax}"
                );
            }
            let (lo, hi) = sampled_range(&plain, lmax);
            let direct = dirs.iter().map(|&u| plain_value(&plain, lmax, u));
            let (dlo, dhi) = direct.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
            assert!(
                (lo - dlo).abs() <= 1e-12 && (hi - dhi).abs() <= 1e-12,
                "lmax {lmax}"
            );
        }
        assert!(basis_table(3).is_none());
    }

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }

    fn random_dir(seed: &mut u64) -> DVec3 {
        loop {
            let v = DVec3::new(lcg(seed), lcg(seed), lcg(seed));
            if v.length_squared() > 0.01 && v.length_squared() < 1.0 {
                return v.normalize();
            }
        }
    }

    /// The plain series is the tournier07 series (and so, by the SH tests, DIPY's and MRtrix's)
    /// in every basis, and its gradient's tangential part is ShEval's sphere gradient.
    #[test]
    fn plain_series_is_each_basis_series() {
        let mut seed = 7;
        for lmax in [0, 2, 4, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            for basis in [
                ShBasis::Tournier07,
                ShBasis::Descoteaux07,
                ShBasis::Descoteaux07Legacy,
            ] {
                let plain = plain_of(&c, basis, 1.0).unwrap();
                let mut ev = ShEval::new(lmax, basis).unwrap();
                for _ in 0..50 {
                    let u = random_dir(&mut seed);
                    let (want, wg) = ev.value_gradient(&c, u.to_array());
                    let (got, grad) = plain_value_gradient(&plain, lmax, u);
                    let tangential = grad - grad.dot(u) * u;
                    assert!(
                        (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                        "{lmax} {basis:?}"
                    );
                    let e = (tangential - DVec3::from(wg)).length();
                    assert!(e <= 1e-11 * (1.0 + DVec3::from(wg).length()), "{lmax} {e}");
                }
                // At the poles too (ShEval takes φ = 0 there).
                for u in [DVec3::Z, -DVec3::Z] {
                    let want = ev.value(&c, u.to_array());
                    assert!(
                        (plain_value(&plain, lmax, u) - want).abs() < 1e-12 * (1.0 + want.abs())
                    );
                }
            }
        }
    }

    /// The bounds hold: no sampled value or gradient exceeds them.
    #[test]
    fn series_bounds_bound() {
        let mut seed = 11;
        for lmax in [2, 8, 12] {
            let n = crate::sh::count_of_lmax(lmax).unwrap();
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
            let (vb, gb) = series_bounds(&plain, lmax);
            for _ in 0..2000 {
                let u = random_dir(&mut seed);
                let (v, grad) = plain_value_gradient(&plain, lmax, u);
                assert!(v.abs() <= vb);
                assert!((grad - grad.dot(u) * u).length() <= gb);
            }
            let (min, max) = sampled_range(&plain, lmax);
            assert!(max <= vb && -min <= vb);
            // The rigorous bounds hold on directions far denser than the samples'.
            let (g, r) = rigorous_bounds(&plain, lmax, (min, max));
            for _ in 0..20000 {
                let u = random_dir(&mut seed);
                let (v, grad) = plain_value_gradient(&plain, lmax, u);
                assert!(v <= r);
                assert!((grad - grad.dot(u) * u).length() <= g, "{lmax}");
            }
        }
    }

    /// The covering radius holds: no random direction is farther from every sample.
    #[test]
    fn every_direction_is_within_the_cover_of_a_sample() {
        let mut seed = 19;
        for lmax in [8, 12] {
            let s = sphere_for(lmax);
            for _ in 0..300 {
                let u = random_dir(&mut seed);
                let nearest = s
                    .directions
                    .iter()
                    .map(|d| d.dot(u).clamp(-1.0, 1.0).acos())
                    .fold(f64::INFINITY, f64::min);
                assert!(nearest <= s.cover, "{nearest} {}", s.cover);
            }
            assert!(s.cover < 0.05 && s.cover > 0.005, "{}", s.cover);
        }
    }

    /// Brute force: the first sign change of h along the ray on a grid of 200,000 steps, then
    /// bisection. Independent of the marcher's step rule.
    fn brute(p: &Profile, o: DVec3, d: DVec3) -> Option<f64> {
        let sc = -o.dot(d);
        let b2 = (o + sc * d).length_squared();
        if b2 >= 1.0 {
            return None;
        }
        let half = (1.0 - b2).sqrt();
        let (s0, s1) = ((sc - half).max(0.0), sc + half);
        let h = |s: f64| {
            let q = o + s * d;
            p.value(q.normalize()).max(0.0) - q.length()
        };
        let inside = h(s0) > 0.0;
        let n = 200_000;
        let mut prev = s0;
        for i in 1..=n {
            let s = s0 + (s1 - s0) * f64::from(i) / f64::from(n);
            if (h(s) > 0.0) != inside {
                let (mut lo, mut hi) = (prev, s);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (h(mid) > 0.0) == inside {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            prev = s;
        }
        None
    }

    /// The marcher finds the brute-force crossing on tensor profiles and random lmax-8 series
    /// (positive, as a CSD fit's lobes), to the bisection's precision; its normal is the
    /// gradient of |q| − r~(q/|q|).
    #[test]
    fn first_crossing_matches_brute_force() {
        let mut seed = 3;
        let mut profiles = vec![Profile::Quadratic([1.0, 0.3, 0.05])];
        for _ in 0..3 {
            let n = crate::sh::count_of_lmax(8).unwrap();
            let mut c: Vec<f64> = (0..n).map(|_| 0.3 * lcg(&mut seed)).collect();
            c[0] = 1.5;
            let plain = plain_of(&c, ShBasis::Tournier07, 1.0).unwrap();
            let (vb, _) = series_bounds(&plain, 8);
            let plain: Vec<f64> = plain.iter().map(|v| v / vb).collect();
            profiles.push(Profile::Series { lmax: 8, plain });
        }
        let (mut hits, mut misses) = (0, 0);
        for p in &profiles {
            let g = match p {
                Profile::Quadratic(a) => a[0] - a[2],
                Profile::Series { lmax, plain } => series_bounds(plain, *lmax).1,
            };
            let f = |u: DVec3| p.value_gradient(u);
            for _ in 0..150 {
                let o = random_dir(&mut seed) * 3.0;
                let target = random_dir(&mut seed) * 0.6 * lcg(&mut seed).abs();
                let d = (target - o).normalize();
                let got = first_crossing(&f, o, d, g, 0.0, REFERENCE_EPS, usize::MAX);
                let want = brute(p, o, d);
                match (got, want) {
                    (Some((s, n)), Some(w)) => {
                        hits += 1;
                        assert!((s - w).abs() < 1e-9, "{s} {w}");
                        // The normal by central differences of F(q) = |q| − r~(q/|q|).
                        let q = o + s * d;
                        let big_f = |q: DVec3| q.length() - p.value(q.normalize()).max(0.0);
                        let e = 1e-6;
                        let fd = DVec3::new(
                            big_f(q + DVec3::X * e) - big_f(q - DVec3::X * e),
                            big_f(q + DVec3::Y * e) - big_f(q - DVec3::Y * e),
                            big_f(q + DVec3::Z * e) - big_f(q - DVec3::Z * e),
                        );
                        let angle = n.normalize().dot(fd.normalize()).clamp(-1.0, 1.0).acos();
                        assert!(angle.to_degrees() < 1e-3, "{}", angle.to_degrees());
                    }
                    (None, None) => misses += 1,
                    (got, want) => panic!("{got:?} against {want:?}"),
                }
            }
        }
        assert!(hits > 100 && misses > 20, "{hits} {misses}");
    }

    /// A ball's own profile is its bounding ball: every ray meets it where it enters (the
    /// entry's h = 1 − |q| rounds to either sign; it is not taken for being inside).
    #[test]
    fn a_glyph_filling_its_ball_is_met_on_entry() {
        let p = Profile::Quadratic([1.0; 3]);
        let f = |u: DVec3| p.value_gradient(u);
        let mut seed = 5;
        for _ in 0..2000 {
            let o = random_dir(&mut seed) * 3.0;
            let d = (random_dir(&mut seed) * 0.9 * lcg(&mut seed).abs() - o).normalize();
            let (s, n) = first_crossing(&f, o, d, 0.0, 0.0, REFERENCE_EPS, usize::MAX).unwrap();
            let sc = -o.dot(d);
            let want = sc - (1.0 - (o + sc * d).length_squared()).sqrt();
            assert!((s - want).abs() < 1e-12, "{s} {want}");
            assert!((n.normalize() - (o + s * d)).length() < 1e-9);
        }
    }

    /// lmax 0: a ball of radius c₀Y₀⁰, exactly.
    #[test]
    fn lmax_zero_is_a_ball() {
        let y00 = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
        let plain = vec![0.5 / y00];
        let f = |u: DVec3| plain_value_gradient(&plain, 0, u);
        let (s, n) = first_crossing(
            &f,
            DVec3::new(0.1, 0.2, -3.0),
            DVec3::Z,
            0.0,
            0.0,
            1e-7,
            usize::MAX,
        )
        .unwrap();
        let want = 3.0 - (0.25f64 - 0.05).sqrt();
        assert!((s - want).abs() < 1e-12, "{s} {want}");
        assert!((n.normalize() - DVec3::new(0.1, 0.2, -(0.2f64).sqrt()) / 0.5).length() < 1e-9);
    }
}
