//! Real spherical harmonics (SH) of even order in f64: the fibre orientation distributions
//! (ODFs) that MRtrix's `dwi2fod` and DIPY's CSD write, one series per voxel.
//!
//! Our own code rather than a crate's: the ODF glyph's GPU twin must evaluate the very same
//! series term by term (the same recurrence, the same signs, the same order of coefficients),
//! and no crate offers the three bases below with a gradient. `basis` holds the bases and the
//! coefficient order, `legendre` the associated Legendre functions, `eval` the series and its
//! gradient, `peaks` the maxima and the range.
//!
//! # 1. The bases
//!
//! Coefficients come in even orders l = 0, 2, …, lmax, and within an order m = −l … l, so that
//! coefficient (l, m) is at `l(l+1)/2 + m` (MRtrix's `Math::SH::index`, DIPY's
//! `sph_harm_ind_list`): lmax 2, 4, …, 12 hold 6, 15, 28, 45, 66, 91 ([`count_of_lmax`];
//! any other count is [`ShError::Count`]). With θ the polar angle from +z, φ the azimuth from
//! +x towards +y, and Λ_l^m (0 ≤ m ≤ l) the orthonormalised associated Legendre function
//! *without* the Condon–Shortley phase,
//!
//! ```text
//! Λ_l^m(θ) = √((2l+1)/(4π) · (l−m)!/(l+m)!) · P_l^m(cos θ),   P_l^m(x) = (1−x²)^(m/2) dᵐ/dxᵐ P_l(x),
//! ```
//!
//! every basis function is `Λ_l^0(θ)` for m = 0, else `±√2 Λ_l^|m|(θ) cos(|m|φ)` or
//! `±√2 Λ_l^|m|(θ) sin(|m|φ)`. Which trig factor a coefficient multiplies, and the sign, is all
//! that sets the bases apart (`cs` = (−1)^|m|, the Condon–Shortley phase):
//!
//! | basis | m > 0 | m < 0 |
//! |---|---|---|
//! | `tournier07` | `cs · √2 Λ cos(mφ)` | `cs · √2 Λ sin(|m|φ)` |
//! | `descoteaux07` | `cs · √2 Λ sin(mφ)` | `√2 Λ cos(|m|φ)` |
//! | `descoteaux07-legacy` | `cs · √2 Λ sin(mφ)` | `cs · √2 Λ cos(|m|φ)` |
//!
//! Where the signs come from:
//! - **descoteaux07** (DIPY's `real_sh_descoteaux_from_index`): `√2 Im Y_l^m` for m > 0,
//!   `√2 Re Y_l^m` for m < 0, with the complex `Y_l^m` of scipy's `sph_harm`, which carries the
//!   Condon–Shortley phase. For m < 0, `Y_l^m = (−1)^m conj(Y_l^|m|)` cancels that phase, hence
//!   the plain sign. With `legacy=True` (DIPY's default, and what `shm_coeff` is in unless DIPY
//!   was told otherwise) DIPY takes `Y_l^|m|` for m < 0 instead, which keeps the phase.
//! - **tournier07** (MRtrix3's basis, its documentation's "spherical harmonics" page, and
//!   DIPY's `real_sh_tournier_from_index` with `legacy=False`): `√2 Re Y_l^m` for m > 0 and
//!   `√2 Im Y_l^|m|` for m < 0, both with the phase. (DIPY's legacy tournier07, without the √2,
//!   is MRtrix 0.2's and is not read.)
//!
//! The tests check these against DIPY's `sh_to_sf` and MRtrix's `sh2amp` on files each wrote
//! (tests/data/sh), and the unit tests below against the closed forms at l ≤ 2 (`Y_0^0 =
//! 1/(2√π)`; at l = 2 `√(15/4π)·xz`, `√(15/4π)·yz`, `√(15/16π)·(x²−y²)`, `√(15/4π)·xy`,
//! `√(5/16π)·(3z²−1)` with the signs of the table) and orthonormality by exact quadrature.
//! Since each function of one basis is ± one of another's, [`convert`] between bases moves and
//! negates coefficients and is exact.
//!
//! # 2. The Legendre functions
//!
//! By the standard recurrences on the normalised functions, which need no factorials (nothing
//! overflows at l = 12, or 30) and are stable for increasing l: with z = cos θ, s = sin θ,
//!
//! ```text
//! Λ_0^0 = 1/√(4π),   Λ_m^m = √((2m+1)/(2m)) · s · Λ_{m−1}^{m−1},   Λ_{m+1}^m = √(2m+3) · z · Λ_m^m,
//! Λ_l^m = a_lm (z Λ_{l−1}^m − b_lm Λ_{l−2}^m),  a_lm = √((4l²−1)/(l²−m²)),  b_lm = √(((l−1)²−m²)/(4(l−1)²−1)).
//! ```
//!
//! Each column m ≥ 1 is also run from the seed divided by s, giving Λ_l^m / s without a
//! division (finite at the poles). The θ-derivative follows from the ladder operators:
//! `dΛ_l^m/dθ = ½ [√((l+m)(l−m+1)) Λ_l^(m−1) − √((l−m)(l+m+1)) Λ_l^(m+1)]` for m ≥ 1 and
//! `−√(l(l+1)) Λ_l^1` for m = 0. s is taken as `hypot(x, y)`, not `√(1−z²)`, so that it keeps
//! its digits near the poles.
//!
//! # 3. Value and gradient
//!
//! f(u) = Σ_j c_j Y_j(u) for u of any non-zero length (normalised first). Its gradient on the
//! sphere is `∂f/∂θ ê_θ + (1/s) ∂f/∂φ ê_φ` with `ê_θ = (z cos φ, z sin φ, −s)`, `ê_φ =
//! (−sin φ, cos φ, 0)`; the φ-part uses Λ/s, so it is finite at the poles, where φ = 0 is taken
//! and the frame is the limit along that meridian (f is smooth, any meridian gives the same
//! vector).
//!
//! # 4. Peaks and range
//!
//! f is sampled on a geodesic sphere (the icosahedron subdivided 5 times: 10242 vertices, ≤ 2.4°
//! apart); each vertex (of the z ≥ 0 half: f is even) not below its neighbours seeds a Newton
//! ascent in the tangent plane (the tangent Hessian from central differences of the exact
//! gradient; gradient steps where it is not negative definite; a trust radius), which stops
//! when a step is under 1e-10 rad. Maxima within [`SAME_PEAK_DEG`] along either direction of
//! the axis are one. Then, as DIPY's `peak_directions_nl` does: largest first, a maximum below
//! `relative_threshold` × the largest is dropped, and one within `min_separation_deg` of a kept
//! one. The range (min, max) for min–max normalisation is found the same way on ±f. A maximum
//! whose basin falls between seeds is missed: fibre lobes are far wider than the seed spacing,
//! but the ringing of a truncated series can have maxima of a few thousandths of the largest
//! whose basins are narrower than a degree.

mod basis;
mod eval;
mod legendre;
mod peaks;

pub use basis::{
    MAX_LMAX, ShBasis, ShError, convert, count_of_lmax, degrees, index, lmax_of_count,
};
pub use eval::{ShEval, value};
pub use peaks::{Peak, PeakFinder, PeakOptions, SAME_PEAK_DEG, min_max};
