//! Radii and colour of glyphs from user options (tensor-shape.md, sections 4-6).
//!
//! [`GlyphStyle`] holds the options; [`GlyphStyle::resolve`] fixes the field-dependent numbers
//! (global scale `k`, normalisation, each glyph's room, the colour scheme and range of a scalar
//! colouring) once, and the returned [`ResolvedStyle`] gives each glyph's radii and RGBA8 colour.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use super::colormap::{diverging, scale_color, to_rgba8};
use super::superquadric::{Sharpness, SuperquadricShape, superquadric_shape};
use super::{Glyph, GlyphSet};
use crate::percentile::{DEFAULT_RANGE, MAX_SAMPLES, percentiles};
use crate::tensor::eigen::quat_to_frame;
use crate::tensor::measure::Measure;
use crate::tensor::shape::{self, DEFAULT_CLASS_THRESHOLD};

pub use super::spacing::{local_spacing, median_nn_distance};

/// How glyphs are coloured.
///
/// The scalar colourings ([`ColorScheme::measure`]) map a [`Measure`] over a range (`--color-range`,
/// else the field's 2nd–98th percentiles; FA: 0–1): the signed ones through a diverging map
/// centred on zero, the others through viridis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorScheme {
    /// Resolved per field: [`ColorScheme::VonMises`] for stress-like fields (more than half of
    /// the tensors indefinite), else [`ColorScheme::Shape`].
    Auto,
    /// Gumhold's shape classes: cigar red, pancake green, ball blue, unclassified magenta.
    #[default]
    Shape,
    /// Directional encoding `min(FA, 1) · |e1|`, `e1` the eigenvector of the largest |λ|.
    Dec,
    /// Fractional anisotropy through viridis (0 → dark, 1 → yellow).
    Fa,
    /// Mean diffusivity through viridis.
    Md,
    /// The von Mises stress through viridis.
    VonMises,
    /// The Tresca stress σ1 − σ3 through viridis.
    Tresca,
    /// The largest principal stress, diverging about zero.
    Sigma1,
    /// The middle principal stress, diverging about zero.
    Sigma2,
    /// The smallest principal stress, diverging about zero.
    Sigma3,
    /// The mean stress tr σ / 3, diverging about zero.
    Mean,
    /// The stress triaxiality mean / von Mises, diverging about zero.
    Triaxiality,
    /// Sign of the eigenvalue of largest magnitude: tension red, compression blue, zero white.
    Sign,
    /// One colour for all glyphs.
    Solid,
    /// ODF glyphs (`--glyph odf`, files of SH series) only: each point by the ODF's value in
    /// its direction, as a share of the glyph's full radius, through viridis.
    Amplitude,
}

crate::names::named_values!(ColorScheme {
    Auto => "auto",
    Shape => "shape",
    Dec => "dec",
    Fa => "fa",
    Md => "md",
    VonMises => "von-mises",
    Tresca => "tresca",
    Sigma1 => "sigma1",
    Sigma2 => "sigma2",
    Sigma3 => "sigma3",
    Mean => "mean",
    Triaxiality => "triaxiality",
    Sign => "sign",
    Solid => "solid",
    Amplitude => "amplitude",
});

impl ColorScheme {
    /// The measure a scalar colouring shows.
    pub fn measure(self) -> Option<Measure> {
        Some(match self {
            ColorScheme::Fa => Measure::Fa,
            ColorScheme::Md => Measure::Md,
            ColorScheme::VonMises => Measure::VonMises,
            ColorScheme::Tresca => Measure::Tresca,
            ColorScheme::Sigma1 => Measure::Sigma1,
            ColorScheme::Sigma2 => Measure::Sigma2,
            ColorScheme::Sigma3 => Measure::Sigma3,
            ColorScheme::Mean => Measure::Mean,
            ColorScheme::Triaxiality => Measure::Triaxiality,
            _ => return None,
        })
    }
}

/// The room glyphs have, which `--scale auto` fits them to.
#[derive(Debug, Clone, PartialEq)]
pub enum Spacing {
    /// A lattice's step (or one distance for the whole field): every glyph the same room.
    Uniform(f64),
    /// Each tensor's own spacing ([`local_spacing`]), in file order: unstructured data.
    Local(Arc<[f32]>),
}

impl From<f64> for Spacing {
    fn from(s: f64) -> Self {
        Spacing::Uniform(s)
    }
}

impl Spacing {
    /// The spacing the global scale is fitted to: the lattice step, or the local spacing of the
    /// glyphs that fill half of the volume (the median of the local spacings weighted by the
    /// room each glyph stands for, ∝ h³; non-positive or non-finite: 1). On a graded mesh the
    /// plain median is the fine cells' spacing, which the many small cells near a hole or a
    /// notch set and which leaves the glyphs of the coarse cells, most of the image, specks;
    /// weighted, it is the coarse cells', and the fine cells' glyphs keep to their own room
    /// ([`LOCAL_ROOM`]).
    pub fn typical(&self) -> f64 {
        let s = match self {
            Spacing::Uniform(s) => *s,
            Spacing::Local(h) => {
                let step = h.len().div_ceil(MAX_SAMPLES).max(1);
                let mut v: Vec<f64> = h
                    .iter()
                    .step_by(step)
                    .map(|&x| f64::from(x))
                    .filter(|x| x.is_finite() && *x > 0.0)
                    .collect();
                v.sort_by(f64::total_cmp);
                // Relative to the largest, so that the cubes stay finite.
                let top = v.last().copied().unwrap_or(1.0);
                let total: f64 = v.iter().map(|x| (x / top).powi(3)).sum();
                let mut acc = 0.0;
                v.iter()
                    .copied()
                    .find(|x| {
                        acc += (x / top).powi(3);
                        acc >= 0.5 * total
                    })
                    .unwrap_or(1.0)
            }
        };
        if s.is_finite() && s > 0.0 { s } else { 1.0 }
    }
}

/// Global scale of the radii.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Scale {
    /// The largest radius over the field equals half the grid spacing.
    #[default]
    Auto,
    /// `r = f · |λ|` (after normalisation).
    Factor(f64),
}

impl FromStr for Scale {
    type Err = String;

    /// `auto` (case-insensitive) or a positive finite number.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("auto") {
            return Ok(Scale::Auto);
        }
        match s.parse::<f64>() {
            Ok(f) if f.is_finite() && f > 0.0 => Ok(Scale::Factor(f)),
            Ok(_) => Err(format!(
                "scale must be a positive finite number or 'auto', got '{s}'"
            )),
            Err(_) => Err(format!("scale must be 'auto' or a number, got '{s}'")),
        }
    }
}

impl fmt::Display for Scale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Scale::Auto => write!(f, "auto"),
            Scale::Factor(x) => write!(f, "{x}"),
        }
    }
}

/// Normalisation of |λ| before scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Normalize {
    /// Radii proportional to |λ| across the field.
    #[default]
    None,
    /// Divide by the field's largest |λ|.
    Max,
    /// Divide by each glyph's own largest |λ| (all glyphs the same size; shape only).
    PerGlyph,
}

crate::names::named_values!(Normalize {
    None => "none",
    Max => "max",
    PerGlyph => "per-glyph",
});

/// How a glyph's radii follow its eigenvalues, before the global scale: the choices MRtrix,
/// SCIRun and ParaView users ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SizeBy {
    /// With `--scale auto`, [`SizeBy::Log`] for stress-like fields (more than half of the
    /// tensors indefinite), else [`SizeBy::Linear`] (diffusion tensors, positive definite); with
    /// a scale factor, [`SizeBy::Linear`] (the factor is exact).
    #[default]
    Auto,
    /// `r_i ∝ |λ_i|`: the tensor's own ellipsoid.
    Linear,
    /// `r_i ∝ √|λ_i|` (for diffusion: the displacement's standard deviation), a gentler spread.
    Sqrt,
    /// `r_i ∝ ln(1 + |λ_i| / λ_ref)`, λ_ref the 10th percentile of the largest |λ|: for fields spanning
    /// orders of magnitude (stress near a load).
    Log,
    /// The glyph's shape (`|λ_i| / max |λ|`) at a size ∝ its FA (clamped to 1).
    Fa,
    /// The glyph's shape only: every glyph the same size.
    None,
}

crate::names::named_values!(SizeBy {
    Auto => "auto",
    Linear => "linear",
    Sqrt => "sqrt",
    Log => "log",
    Fa => "fa",
    None => "none",
});

/// `--scale auto` sizes glyphs from this percentile of their largest mapped radius (nearest
/// rank), so that a few outliers — a singularity, CSF in a brain — do not shrink every other
/// glyph to a speck; the glyphs above it are clamped to its size and counted.
pub const AUTO_PERCENTILE: f64 = 0.98;

/// `--size-by log`: λ_ref is this percentile of the glyphs' largest |λ|.
pub const LOG_REF_PERCENTILE: f64 = 0.1;

/// The smallest radius, relative to the glyph's largest, by default.
pub const DEFAULT_MIN_RADIUS: f64 = 0.01;
/// The default for stress-like fields: their common uniaxial states (a beam in bending) are
/// needles otherwise, too thin to see; at most 4:1, the principal direction still reads.
pub const STRESS_MIN_RADIUS: f64 = 0.25;

/// A principal-stress bar's radius, as a fraction of the robust largest half-length (the glyph
/// size `--scale auto` gives): thin enough that three bars read as axes, thick enough to shade.
pub const BAR_WIDTH: f64 = 0.07;

/// A principal stress within this fraction of its glyph's largest |σ| of zero is drawn in the
/// neutral colour.
pub const NEUTRAL_FRACTION: f64 = 0.05;

/// A glyph's largest radius under `--scale auto` is at most this fraction of its own spacing
/// ([`Spacing::Local`]): half the way to its neighbours.
pub const LOCAL_ROOM: f64 = 0.5;

/// User options for glyph geometry and colour.
#[derive(Debug, Clone, PartialEq)]
pub struct GlyphStyle {
    pub color: ColorScheme,
    /// The range a scalar colouring maps (`--color-range`); `None`: the measure's own (FA's
    /// 0–1) or the field's 2nd–98th percentiles.
    pub color_range: Option<[f64; 2]>,
    /// The tensors' units, for the legend (`--units`); `None`: from the array's name, e.g.
    /// `stress (MPa)` ([`units_in_name`]).
    pub units: Option<String>,
    pub scale: Scale,
    pub normalize: Normalize,
    pub size_by: SizeBy,
    /// Relative minimum radius ε: `r_i ← max(r_i, ε · r_max)` per glyph. `None`: 0.01, or
    /// [`STRESS_MIN_RADIUS`] where `--size-by auto` picks `log` (stress-like fields).
    pub min_radius: Option<f64>,
    /// Shape-class threshold τ (default 0.5).
    pub class_threshold: f64,
    /// Colour of [`ColorScheme::Solid`].
    pub solid_color: [u8; 3],
    /// How sharp superquadric glyphs are (`--sharpness`).
    pub sharpness: Sharpness,
    /// Principal-stress glyphs: cone heads on the bars, outward for tension, inward for
    /// compression (`--arrows`).
    pub arrows: bool,
    /// Principal-stress glyphs: bars whose |σ| is below this are hidden (`--min-stress`; the
    /// selection hides whole glyphs below it).
    pub min_stress: f64,
}

impl Default for GlyphStyle {
    fn default() -> Self {
        GlyphStyle {
            color: ColorScheme::Shape,
            color_range: None,
            units: None,
            scale: Scale::Auto,
            normalize: Normalize::None,
            size_by: SizeBy::Auto,
            min_radius: None,
            class_threshold: DEFAULT_CLASS_THRESHOLD,
            solid_color: [200, 200, 200],
            sharpness: Sharpness::default(),
            arrows: false,
            min_stress: 0.0,
        }
    }
}

/// Units longer than this in an array's name are taken for something else.
const MAX_UNITS: usize = 24;

/// The units in a tensor array's name: the text of a final `(…)` or `[…]`, as in
/// `stress (MPa)` or `sigma [Pa]` (at most 24 printable characters).
pub fn units_in_name(name: &str) -> Option<String> {
    let name = name.trim_end();
    let (open, close) = match name.chars().last()? {
        ')' => ('(', ')'),
        ']' => ('[', ']'),
        _ => return None,
    };
    let inner = &name[..name.len() - close.len_utf8()];
    let at = inner.rfind(open)?;
    let units = inner[at + open.len_utf8()..].trim();
    let fits = !units.is_empty()
        && units.chars().count() <= MAX_UNITS
        && !units.contains([open, close])
        && !units.chars().any(char::is_control);
    fits.then(|| units.to_string())
}

impl GlyphStyle {
    /// Fix the field-dependent parameters. `spacing` is the room glyphs have ([`Spacing`]: the
    /// grid spacing, or each glyph's own), used by [`Scale::Auto`]; a non-positive or
    /// non-finite spacing is treated as 1.
    pub fn resolve(&self, set: &GlyphSet, spacing: impl Into<Spacing>) -> ResolvedStyle {
        let spacing = spacing.into();
        let stats = &set.stats;
        let field_max = stats.max_abs_eigenvalue;
        let norm_div = match self.normalize {
            Normalize::Max if field_max > 0.0 => field_max,
            _ => 1.0,
        };
        let stress_like = 2 * stats.indefinite > stats.valid;
        let color = match self.color {
            ColorScheme::Auto if stress_like => ColorScheme::VonMises,
            ColorScheme::Auto => ColorScheme::Shape,
            c => c,
        };
        let color_range = match color.measure() {
            Some(m) => self
                .color_range
                .or(m.natural_range())
                .unwrap_or_else(|| measure_range(set, m)),
            None => [0.0, 0.0],
        };
        // `--scale F` stays exact (r = F·|λ|) unless a map is asked for by name.
        let size_by = match (self.size_by, self.scale) {
            (SizeBy::Auto, Scale::Auto) if stress_like => SizeBy::Log,
            (SizeBy::Auto, _) => SizeBy::Linear,
            (s, _) => s,
        };
        let mut style = ResolvedStyle {
            k: 1.0,
            norm_div,
            normalize: self.normalize,
            size_by,
            log_ref: 1.0,
            cap: f64::INFINITY,
            min_radius: match self.min_radius {
                Some(e) if e.is_finite() => e.max(0.0),
                Some(_) => 0.0,
                None if self.size_by == SizeBy::Auto && size_by == SizeBy::Log => STRESS_MIN_RADIUS,
                None => DEFAULT_MIN_RADIUS,
            },
            local: None,
            color,
            color_range,
            units: self.units.clone(),
            class_threshold: self.class_threshold,
            solid_color: self.solid_color,
            sharpness: self.sharpness,
            arrows: self.arrows,
            min_stress: self.min_stress,
            bar_width: 0.0,
        };
        if size_by == SizeBy::Log {
            // λ_ref: a low percentile of the largest |λ|, so that most glyphs sit where the
            // logarithm compresses (a singular field's far glyphs stay visible).
            let linear = ResolvedStyle {
                size_by: SizeBy::Linear,
                ..style.clone()
            };
            let r = percentile_largest(set, &linear, LOG_REF_PERCENTILE);
            style.log_ref = if r > 0.0 { r } else { 1.0 };
        }
        match self.scale {
            Scale::Factor(f) => style.k = f,
            Scale::Auto => {
                let typical = spacing.typical();
                // The robust largest radius at k = 1 becomes half the spacing; larger glyphs
                // are clamped to that size, and each glyph to its own room.
                let largest = percentile_largest(set, &style, AUTO_PERCENTILE);
                if largest > 0.0 {
                    style.k = 0.5 * typical / largest;
                    style.cap = 0.5 * typical;
                }
                if let Spacing::Local(h) = spacing {
                    style.local = Some(h);
                }
            }
        }
        // Bars one width for the whole field: a fraction of the robust largest half-length.
        let reference = if style.cap.is_finite() {
            style.cap
        } else {
            percentile_largest(set, &style, AUTO_PERCENTILE)
        };
        style.bar_width = if reference > 0.0 {
            BAR_WIDTH * reference
        } else {
            1.0
        };
        style
    }
}

/// The default range of a colouring by `m`: the field's 2nd and 98th percentiles of it (of at
/// most [`MAX_SAMPLES`] glyphs, evenly spread); `[0, 0]` without a finite value.
fn measure_range(set: &GlyphSet, m: Measure) -> [f64; 2] {
    let step = set.glyphs.len().div_ceil(MAX_SAMPLES).max(1);
    let values: Vec<f64> = set
        .glyphs
        .iter()
        .step_by(step)
        .map(|g| m.of(g.eigenvalues.map(f64::from)))
        .filter(|v| v.is_finite())
        .collect();
    percentiles(values, DEFAULT_RANGE, f64::total_cmp).unwrap_or([0.0, 0.0])
}

/// The `p`-quantile (nearest rank) of the glyphs' largest radius under `style` (at its `k`).
fn percentile_largest(set: &GlyphSet, style: &ResolvedStyle, p: f64) -> f64 {
    let n = set.glyphs.len();
    if n == 0 {
        return 0.0;
    }
    let step = n.div_ceil(MAX_SAMPLES);
    let mut sizes: Vec<f64> = set
        .glyphs
        .iter()
        .step_by(step)
        .map(|g| style.unclamped(g).into_iter().fold(0.0, f64::max))
        .filter(|r| r.is_finite())
        .collect();
    if sizes.is_empty() {
        return 0.0;
    }
    let rank = ((p * sizes.len() as f64).ceil() as usize).clamp(1, sizes.len()) - 1;
    let (_, r, _) = sizes.select_nth_unstable_by(rank, f64::total_cmp);
    *r
}

/// A [`GlyphStyle`] with its field-dependent numbers fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedStyle {
    /// Global scale `k` (radius = k · normalised |λ|).
    pub k: f64,
    /// Field-wide divisor (field max |λ| for [`Normalize::Max`], else 1).
    pub norm_div: f64,
    pub normalize: Normalize,
    pub size_by: SizeBy,
    /// λ_ref of [`SizeBy::Log`].
    pub log_ref: f64,
    /// The largest radius a glyph may have (`--scale auto`; infinite with a factor): larger
    /// glyphs are scaled down to it, shape kept.
    pub cap: f64,
    /// With `--scale auto` on unstructured data, each tensor's own spacing (file order): a
    /// glyph's largest radius is at most [`LOCAL_ROOM`] of it as well.
    pub local: Option<Arc<[f32]>>,
    pub min_radius: f64,
    /// The scheme in effect (never [`ColorScheme::Auto`]).
    pub color: ColorScheme,
    /// The range a scalar colouring maps (lo, hi); `[0, 0]` for the others.
    pub color_range: [f64; 2],
    /// The tensors' units, for the legend.
    pub units: Option<String>,
    pub class_threshold: f64,
    pub solid_color: [u8; 3],
    pub sharpness: Sharpness,
    /// Principal-stress glyphs: cone heads (`--arrows`).
    pub arrows: bool,
    /// Principal-stress glyphs: bars below this |σ| are hidden.
    pub min_stress: f64,
    /// Principal-stress glyphs: the bars' radius (world units), [`BAR_WIDTH`] of the robust
    /// largest half-length.
    pub bar_width: f64,
}

impl ResolvedStyle {
    /// Radii in the glyph's frame order (`r_i` along `e_i`): `r_i = k · s(|λ_i|) / n` with `s`
    /// the [`SizeBy`] map and `n` the normalisation, clamped to [`Self::cap`] (shape kept), then
    /// `r_i ← max(r_i, ε · r_max)`. A zero glyph gives zero radii.
    pub fn radii(&self, g: &Glyph) -> [f32; 3] {
        let mut r = self.unclamped(g);
        let largest = r[0].max(r[1]).max(r[2]);
        let cap = self.cap_of(g);
        if largest > cap {
            r = r.map(|x| x * (cap / largest));
        }
        let floor = self.min_radius * r[0].max(r[1]).max(r[2]);
        r.map(|x| x.max(floor) as f32)
    }

    /// Half-lengths along the glyph's frame order: [`Self::radii`] without the minimum radius
    /// (a principal stress's bar is as long as its stress says, however short).
    pub fn lengths(&self, g: &Glyph) -> [f32; 3] {
        let mut r = self.unclamped(g);
        let largest = r[0].max(r[1]).max(r[2]);
        let cap = self.cap_of(g);
        if largest > cap {
            r = r.map(|x| x * (cap / largest));
        }
        r.map(|x| x as f32)
    }

    /// The colour of a principal stress σ of a glyph whose largest |σ| is `largest`: tension
    /// red, compression blue, and white within [`NEUTRAL_FRACTION`] of `largest` of zero.
    pub fn sign_color(sigma: f64, largest: f64) -> [u8; 4] {
        let s = if sigma.abs() <= NEUTRAL_FRACTION * largest {
            0.0
        } else {
            sigma.signum()
        };
        to_rgba8(diverging(s))
    }

    /// The superquadric this glyph is drawn as (`--glyph superquadric`): its shape follows
    /// the signed eigenvalues, whatever the radii's size map.
    pub fn superquadric(&self, g: &Glyph) -> SuperquadricShape {
        superquadric_shape(g.eigenvalues.map(f64::from), self.sharpness)
    }

    /// Whether [`Self::radii`] scales this glyph down to the cap (the field's, or its own room).
    pub fn clamps(&self, g: &Glyph) -> bool {
        self.unclamped(g).into_iter().fold(0.0, f64::max) > self.cap_of(g)
    }

    /// The largest radius glyph `g` may have: the field's cap, and with local spacings
    /// [`LOCAL_ROOM`] of its own spacing.
    fn cap_of(&self, g: &Glyph) -> f64 {
        let own = self
            .local
            .as_ref()
            .and_then(|h| h.get(g.index as usize))
            .map(|&h| LOCAL_ROOM * f64::from(h))
            .filter(|c| c.is_finite() && *c > 0.0);
        own.map_or(self.cap, |c| self.cap.min(c))
    }

    /// `k · s(|λ_i|) / n`, before the cap and the minimum radius.
    fn unclamped(&self, g: &Glyph) -> [f64; 3] {
        let m = g.eigenvalues.map(|l| f64::from(l).abs());
        let glyph_max = m[0].max(m[1]).max(m[2]);
        let shape = |x: f64| if glyph_max > 0.0 { x / glyph_max } else { 0.0 };
        let mapped = match self.size_by {
            // Resolved to Linear or Log by `GlyphStyle::resolve`.
            SizeBy::Auto | SizeBy::Linear => m,
            SizeBy::Sqrt => m.map(f64::sqrt),
            SizeBy::Log => m.map(|x| (x / self.log_ref).ln_1p()),
            SizeBy::Fa => {
                let fa = shape::fa(g.eigenvalues.map(f64::from)).min(1.0);
                m.map(|x| fa * shape(x))
            }
            SizeBy::None => m.map(shape),
        };
        let div = match (self.normalize, self.size_by) {
            // Fa and None are per-glyph already.
            (_, SizeBy::Fa | SizeBy::None) => 1.0,
            (Normalize::PerGlyph, _) => {
                let mx = mapped[0].max(mapped[1]).max(mapped[2]);
                if mx > 0.0 { mx } else { 1.0 }
            }
            (Normalize::Max, SizeBy::Auto | SizeBy::Linear) => self.norm_div,
            (Normalize::Max, SizeBy::Sqrt) => self.norm_div.sqrt(),
            (Normalize::Max, SizeBy::Log) => (self.norm_div / self.log_ref)
                .ln_1p()
                .max(f64::MIN_POSITIVE),
            (Normalize::None, _) => 1.0,
        };
        mapped.map(|x| self.k * x / div)
    }

    /// RGBA8 colour of a glyph by the chosen scheme (alpha 255).
    pub fn color(&self, g: &Glyph) -> [u8; 4] {
        let ev = g.eigenvalues.map(f64::from);
        if let Some(m) = self.color.measure() {
            return to_rgba8(scale_color(m.of(ev), self.color_range, m.signed()));
        }
        match self.color {
            // Resolved by `GlyphStyle::resolve`; a style made by hand reads it as shape.
            ColorScheme::Auto | ColorScheme::Shape => {
                to_rgba8(shape::classify(ev, self.class_threshold).color())
            }
            ColorScheme::Dec => {
                let frame = quat_to_frame(g.rotation);
                to_rgba8(shape::dec_color(ev, frame[shape::major_index(ev)]))
            }
            ColorScheme::Sign => {
                let l = ev[shape::major_index(ev)];
                let s = if l > 0.0 {
                    1.0
                } else if l < 0.0 {
                    -1.0
                } else {
                    0.0
                };
                to_rgba8(diverging(s))
            }
            ColorScheme::Solid => {
                let [r, g, b] = self.solid_color;
                [r, g, b, 255]
            }
            // Coloured per pixel (shape::odf::AMPLITUDE_COLOUR); the instance's is unused.
            ColorScheme::Amplitude => [200, 200, 200, 255],
            _ => unreachable!("scalar colourings are mapped above"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::FieldStats;
    use crate::glyph::colormap::viridis;

    fn glyph(ev: [f32; 3]) -> Glyph {
        Glyph {
            centre: [0.0; 3],
            eigenvalues: ev,
            rotation: [0.0, 0.0, 0.0, 1.0],
            index: 0,
        }
    }

    fn set(glyphs: Vec<Glyph>) -> GlyphSet {
        let evs: Vec<[f64; 3]> = glyphs
            .iter()
            .map(|g| g.eigenvalues.map(f64::from))
            .collect();
        let mx = evs
            .iter()
            .flat_map(|e| e.iter())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let mds: Vec<f64> = evs.iter().map(|e| shape::md(*e)).collect();
        GlyphSet {
            stats: FieldStats {
                valid: glyphs.len(),
                max_abs_eigenvalue: mx,
                md_min: mds.iter().cloned().fold(f64::INFINITY, f64::min),
                md_max: mds.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
                ..FieldStats::default()
            },
            glyphs,
        }
    }

    #[test]
    fn auto_scale_sizes_from_the_robust_largest_and_clamps_outliers() {
        // 200 unit glyphs and 2 outliers a thousand times larger (1 % of the field).
        let mut glyphs = vec![glyph([1.0, 0.5, 0.25]); 200];
        glyphs.extend([glyph([1000.0, 10.0, 10.0]), glyph([2000.0, 1.0, 1.0])]);
        let s = set(glyphs);
        let style = GlyphStyle::default().resolve(&s, 2.0);
        // The 98th percentile is a unit glyph: its largest radius is half the spacing.
        assert_eq!(style.radii(&s.glyphs[0]), [1.0, 0.5, 0.25]);
        assert!(!style.clamps(&s.glyphs[0]));
        // The outliers are scaled down to that size, shape kept.
        for g in &s.glyphs[200..] {
            assert!(style.clamps(g));
            let r = style.radii(g);
            assert_eq!(r[0], 1.0);
        }
        assert!((style.radii(&s.glyphs[200])[1] - 0.01).abs() < 1e-7);
        // A factor is exact: nothing is clamped.
        let exact = GlyphStyle {
            scale: Scale::Factor(0.5),
            ..GlyphStyle::default()
        }
        .resolve(&s, 2.0);
        assert_eq!(exact.radii(&s.glyphs[201]), [1000.0, 10.0, 10.0]);
        assert!(s.glyphs.iter().all(|g| !exact.clamps(g)));
    }

    #[test]
    fn size_maps() {
        let s = set(vec![glyph([4.0, 1.0, -0.25])]);
        let with = |size_by| {
            GlyphStyle {
                scale: Scale::Factor(1.0),
                size_by,
                min_radius: Some(0.0),
                ..GlyphStyle::default()
            }
            .resolve(&s, 1.0)
            .radii(&s.glyphs[0])
        };
        assert_eq!(with(SizeBy::Linear), [4.0, 1.0, 0.25]);
        assert_eq!(with(SizeBy::Sqrt), [2.0, 1.0, 0.5]);
        assert_eq!(with(SizeBy::None), [1.0, 0.25, 0.0625]);
        let fa = shape::fa([4.0, 1.0, -0.25]).min(1.0);
        for (r, want) in with(SizeBy::Fa).iter().zip([fa, 0.25 * fa, 0.0625 * fa]) {
            assert!((f64::from(*r) - want).abs() < 1e-6);
        }
        // Log: λ_ref is the 10th percentile of the largest |λ| (4 here, the only glyph):
        // ln(1 + |λ| / 4).
        let log = with(SizeBy::Log);
        for (r, l) in log.iter().zip([4.0f64, 1.0, 0.25]) {
            assert!((f64::from(*r) - (l / 4.0).ln_1p()).abs() < 1e-6, "{log:?}");
        }
    }

    #[test]
    fn auto_size_is_log_for_stress_like_fields() {
        let mut s = set(vec![glyph([2.0, 1.0, -1.0]), glyph([8.0, -1.0, -3.0])]);
        assert_eq!(
            GlyphStyle::default().resolve(&s, 1.0).size_by,
            SizeBy::Linear
        );
        s.stats.indefinite = 2;
        assert_eq!(GlyphStyle::default().resolve(&s, 1.0).size_by, SizeBy::Log);
    }

    #[test]
    fn scale_from_str() {
        assert_eq!("auto".parse::<Scale>(), Ok(Scale::Auto));
        assert_eq!("AUTO".parse::<Scale>(), Ok(Scale::Auto));
        assert_eq!("2.5".parse::<Scale>(), Ok(Scale::Factor(2.5)));
        assert!("0".parse::<Scale>().is_err());
        assert!("-1".parse::<Scale>().is_err());
        assert!("inf".parse::<Scale>().is_err());
        assert!("nan".parse::<Scale>().is_err());
        assert!("big".parse::<Scale>().is_err());
    }

    #[test]
    fn value_names() {
        assert_eq!(
            ColorScheme::NAMES,
            [
                "auto",
                "shape",
                "dec",
                "fa",
                "md",
                "von-mises",
                "tresca",
                "sigma1",
                "sigma2",
                "sigma3",
                "mean",
                "triaxiality",
                "sign",
                "solid",
                "amplitude"
            ]
        );
        // Each scalar colouring's measure has the colouring's name.
        for &c in ColorScheme::VALUES {
            if let Some(m) = c.measure() {
                assert_eq!(m.name(), c.name());
            }
        }
        assert_eq!(Normalize::NAMES, ["none", "max", "per-glyph"]);
        for (v, n) in Normalize::VALUES.iter().zip(Normalize::NAMES) {
            assert_eq!(n.parse::<Normalize>(), Ok(*v));
        }
        assert!("per_glyph".parse::<Normalize>().is_err());
    }

    #[test]
    fn radii_modes() {
        let a = glyph([4.0, 2.0, 0.0]);
        let b = glyph([1.0, -0.5, -2.0]);
        let s = set(vec![a, b]);
        // auto, none: largest radius = spacing/2 = 1 → k = 1/4
        let st = GlyphStyle::default().resolve(&s, 2.0);
        assert_eq!(st.radii(&a), [1.0, 0.5, 0.01]);
        assert_eq!(st.radii(&b), [0.25, 0.125, 0.5]);
        // factor 2, max: divide by 4
        let st = GlyphStyle {
            scale: Scale::Factor(2.0),
            normalize: Normalize::Max,
            min_radius: Some(1e-3),
            ..GlyphStyle::default()
        }
        .resolve(&s, 1.0);
        assert_eq!(st.radii(&a), [2.0, 1.0, 0.002]);
        // per glyph, auto: every glyph's largest radius is spacing/2
        let st = GlyphStyle {
            normalize: Normalize::PerGlyph,
            ..GlyphStyle::default()
        }
        .resolve(&s, 1.0);
        assert_eq!(st.radii(&a), [0.5, 0.25, 0.005]);
        assert_eq!(st.radii(&b), [0.25, 0.125, 0.5]);
        // degenerate spacing falls back to 1
        let st = GlyphStyle::default().resolve(&s, 0.0);
        assert_eq!(st.radii(&a)[0], 0.5);
    }

    #[test]
    fn colours() {
        let cigar = glyph([3.0, 1.0, 1.0]);
        let comp = glyph([0.5, -0.1, -3.0]);
        let s = set(vec![cigar, comp]);
        let with = |color| {
            GlyphStyle {
                color,
                solid_color: [1, 2, 3],
                ..GlyphStyle::default()
            }
            .resolve(&s, 1.0)
        };
        assert_eq!(with(ColorScheme::Shape).color(&cigar), [255, 0, 0, 255]);
        assert_eq!(with(ColorScheme::Sign).color(&cigar)[0], 204);
        assert_eq!(with(ColorScheme::Sign).color(&comp)[2], 204);
        assert_eq!(
            with(ColorScheme::Sign).color(&glyph([0.0; 3])),
            [255, 255, 255, 255]
        );
        assert_eq!(with(ColorScheme::Solid).color(&comp), [1, 2, 3, 255]);
        // identity rotation: e1 = x, FA of (3,1,1) = 0.603
        let dec = with(ColorScheme::Dec).color(&cigar);
        assert_eq!(
            dec,
            [(0.6030226891555271f64 * 255.0).round() as u8, 0, 0, 255]
        );
        // compression: the major eigenvector is e3 = z, FA capped at 1
        let dec = with(ColorScheme::Dec).color(&comp);
        assert_eq!(dec[0..2], [0, 0]);
        assert!(dec[2] > 200);
        // MD range endpoints map to the viridis ends
        let md = with(ColorScheme::Md);
        assert_eq!(md.color(&cigar), to_rgba8(viridis(1.0)));
        assert_eq!(md.color(&comp), to_rgba8(viridis(0.0)));
        assert_eq!(
            with(ColorScheme::Fa).color(&glyph([1.0, 1.0, 1.0])),
            to_rgba8(viridis(0.0))
        );
    }

    #[test]
    fn auto_colour_is_von_mises_for_stress_and_shape_otherwise() {
        let auto = GlyphStyle {
            color: ColorScheme::Auto,
            ..GlyphStyle::default()
        };
        let mut s = set(vec![glyph([2.0, 1.0, -1.0]), glyph([8.0, -1.0, -3.0])]);
        assert_eq!(auto.resolve(&s, 1.0).color, ColorScheme::Shape);
        s.stats.indefinite = 2;
        assert_eq!(auto.resolve(&s, 1.0).color, ColorScheme::VonMises);
    }

    /// A scalar colouring maps its measure over the 2nd–98th percentiles of the field, or the
    /// range asked for; signed measures diverge about zero.
    #[test]
    fn stress_colourings_and_their_ranges() {
        // 101 uniaxial tensions 0, 1, …, 100: von Mises = σ1 = the tension.
        let glyphs: Vec<Glyph> = (0..=100).map(|t| glyph([t as f32, 0.0, 0.0])).collect();
        let s = set(glyphs);
        let with = |color, color_range| {
            GlyphStyle {
                color,
                color_range,
                ..GlyphStyle::default()
            }
            .resolve(&s, 1.0)
        };
        let vm = with(ColorScheme::VonMises, None);
        assert_eq!(vm.color_range, [2.0, 98.0]);
        assert_eq!(vm.color(&s.glyphs[2]), to_rgba8(viridis(0.0)));
        assert_eq!(vm.color(&s.glyphs[100]), to_rgba8(viridis(1.0)));
        assert_eq!(vm.color(&s.glyphs[50]), to_rgba8(viridis(0.5)));
        let fixed = with(ColorScheme::Tresca, Some([0.0, 200.0]));
        assert_eq!(fixed.color_range, [0.0, 200.0]);
        assert_eq!(fixed.color(&s.glyphs[100]), to_rgba8(viridis(0.5)));
        // σ3 of a tension is 0: white on the diverging map; mean = t / 3 is red.
        let s3 = with(ColorScheme::Sigma3, Some([-10.0, 10.0]));
        assert_eq!(s3.color(&s.glyphs[40]), [255, 255, 255, 255]);
        let mean = with(ColorScheme::Mean, None);
        assert_eq!(mean.color(&s.glyphs[100]), to_rgba8(diverging(1.0)));
        // FA keeps its own 0–1; a hydrostatic glyph's triaxiality (−∞) takes the range's end.
        assert_eq!(with(ColorScheme::Fa, None).color_range, [0.0, 1.0]);
        let tri = with(ColorScheme::Triaxiality, Some([-0.5, 0.5]));
        assert_eq!(
            tri.color(&glyph([-3.0, -3.0, -3.0])),
            to_rgba8(diverging(-1.0))
        );
    }

    /// With local spacings, a glyph's largest radius is at most half its own spacing; the
    /// global scale comes from their median.
    #[test]
    fn local_spacing_caps_each_glyph() {
        let mut glyphs: Vec<Glyph> = (0..5).map(|_| glyph([1.0, 1.0, 1.0])).collect();
        for (i, g) in glyphs.iter_mut().enumerate() {
            g.index = i as u32;
        }
        let s = set(glyphs);
        let h: Arc<[f32]> = Arc::from(vec![2.0f32, 2.0, 2.0, 0.5, f32::NAN]);
        let style = GlyphStyle {
            size_by: SizeBy::Linear,
            ..GlyphStyle::default()
        }
        .resolve(&s, Spacing::Local(h.clone()));
        assert_eq!(Spacing::Local(h).typical(), 2.0);
        // A graded mesh: 90 fine cells (spacing 1) fill less of the volume than 10 coarse ones
        // (spacing 4, each 64 times the room): the scale fits the coarse ones.
        let graded: Vec<f32> = [vec![1.0; 90], vec![4.0; 10]].concat();
        assert_eq!(Spacing::Local(Arc::from(graded)).typical(), 4.0);
        let even: Vec<f32> = [vec![1.0; 99], vec![4.0; 1]].concat();
        assert_eq!(Spacing::Local(Arc::from(even)).typical(), 1.0);
        assert_eq!(Spacing::Local(Arc::from(vec![f32::NAN; 3])).typical(), 1.0);
        assert_eq!(style.radii(&s.glyphs[0]), [1.0; 3]);
        assert!(!style.clamps(&s.glyphs[0]));
        assert_eq!(style.radii(&s.glyphs[3]), [0.25; 3]);
        assert!(style.clamps(&s.glyphs[3]));
        // No spacing of its own: the field's cap.
        assert_eq!(style.radii(&s.glyphs[4]), [1.0; 3]);
        // A factor is exact.
        let exact = GlyphStyle {
            scale: Scale::Factor(3.0),
            ..GlyphStyle::default()
        }
        .resolve(&s, Spacing::Local(Arc::from(vec![0.1f32; 5])));
        assert_eq!(exact.radii(&s.glyphs[3]), [3.0; 3]);
    }

    #[test]
    fn units_from_array_names() {
        assert_eq!(units_in_name("stress (MPa)"), Some("MPa".into()));
        assert_eq!(units_in_name("sigma [Pa] "), Some("Pa".into()));
        assert_eq!(units_in_name("stress"), None);
        assert_eq!(units_in_name("s ()"), None);
        assert_eq!(units_in_name("(x)"), Some("x".into()));
        assert_eq!(units_in_name("a (b (c))"), None);
        assert_eq!(units_in_name(")"), None);
        assert_eq!(units_in_name("s (a\u{1b}[31m)"), None);
        assert_eq!(units_in_name(&format!("s ({})", "x".repeat(25))), None);
    }
}
