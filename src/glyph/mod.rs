//! Tensor → glyph: eigendecomposition of every valid tensor ([`mod@derive`]), then per-glyph radii and
//! colour from user options ([`style`]).

pub mod colormap;
pub mod derive;
pub mod spacing;
pub mod style;
pub mod superquadric;

pub use derive::derive_glyphs;
pub use style::{ColorScheme, GlyphStyle, Normalize, ResolvedStyle, Scale, SizeBy, Spacing};

use serde::Serialize;

/// One glyph: a valid tensor, eigendecomposed.
///
/// Geometry is stored once, compactly; radii and colour depend on user options and are derived
/// from it by [`ResolvedStyle`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Glyph {
    /// World position (f64: fields can sit far from the origin; rendering is camera-relative).
    pub centre: [f64; 3],
    /// Signed eigenvalues, sorted λ1 ≥ λ2 ≥ λ3, of the symmetrised world-space tensor.
    pub eigenvalues: [f32; 3],
    /// Unit quaternion (x, y, z, w) of the right-handed eigenvector frame O = [e1 e2 e3], det +1.
    pub rotation: [f32; 4],
    /// Index of the tensor in file order (points or cells).
    pub index: u32,
}

/// Counts and ranges over a whole field, as `info` reports them.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FieldStats {
    pub tensors: usize,
    pub valid: usize,
    pub skipped_nan: usize,
    pub skipped_inf: usize,
    pub skipped_zero: usize,
    /// Finite tensors whose eigenvalues leave the range a glyph stores (f32, ±3.4e38): entries
    /// within a few orders of f64::MAX give ±inf, and a glyph of 1e300 cannot be drawn.
    pub skipped_overflow: usize,
    /// Non-symmetric tensors replaced by (A + Aᵀ)/2.
    pub symmetrised: usize,
    /// Valid tensors with eigenvalues of both signs, or any negative eigenvalue.
    pub indefinite: usize,
    /// Component-wise minimum and maximum of (λ1, λ2, λ3) over valid tensors.
    pub eigenvalues_min: [f64; 3],
    pub eigenvalues_max: [f64; 3],
    pub fa_min: f64,
    pub fa_mean: f64,
    pub fa_max: f64,
    /// Largest |λ| over valid tensors.
    pub max_abs_eigenvalue: f64,
    pub md_min: f64,
    pub md_max: f64,
    /// Ranges of the von Mises and Tresca stresses ([`crate::tensor::stress`]).
    pub von_mises_min: f64,
    pub von_mises_max: f64,
    pub tresca_min: f64,
    pub tresca_max: f64,
    /// linear, planar, spherical, unclassified (default threshold).
    pub classes: [usize; 4],
}

/// The glyphs of a field and what was counted on the way.
#[derive(Debug, Clone, Default)]
pub struct GlyphSet {
    pub glyphs: Vec<Glyph>,
    pub stats: FieldStats,
}
