//! Tensor → superquadric glyph shape (docs/book/src/developer/superquadric-derivation.md §2–3).
//!
//! Two published mappings, picked per glyph:
//!
//! - **Kindlmann 2004** ("Superquadric tensor glyphs", VisSym) for *definite* tensors (all
//!   eigenvalues of one sign, zeros allowed): trace-normalised Westin `cl`, `cp` of the magnitudes,
//!   each capped at 0.99 as Teem's `tenGlyphGen` does, and with sharpness γ
//!   `cl ≥ cp`: axis along the major-|λ| eigenvector, `(α, β) = ((1 − cp)^γ, (1 − cl)^γ)`;
//!   `cp > cl`: axis along the minor-|λ| eigenvector, `(α, β) = ((1 − cl)^γ, (1 − cp)^γ)`.
//!   A negative definite tensor gets the shape of its negation, as in Schultz–Kindlmann's design.
//! - **Schultz–Kindlmann 2010** ("Superquadric glyphs for symmetric second-order tensors",
//!   TVCG 16(6)) for *indefinite* tensors: the eigenvalues, normalised by max |λ|, map to a point
//!   `(u, v)` of the unit square (their §4.2), which is split into ten triangles whose corners
//!   carry anchor shapes (ball, cylinder, octahedron, cone, thorn, "funk", half-way); the shape is
//!   the barycentric blend of the corners' `(α, β, c)` (their §4.3). The third exponent `c` is the
//!   profile exponent in the plane of the middle eigenvector, which only the "funk" anchor (the
//!   trace-free `(1, 0, −1)`) sets apart from β.
//!
//! Both are hand-written rather than taken from a library because no Rust crate has them, and
//! because the exact reference and the GPU shader must evaluate the very same shape: the output
//! here is the whole contract between them.
//!
//! Convention of the output: local `z` is the symmetry axis. Local `(x, y, z)` are the frame
//! columns `axes[0..3]` of the glyph's eigenvector frame `O = [e1 e2 e3]` (eigenvalues sorted
//! λ1 ≥ λ2 ≥ λ3, as [`crate::glyph::Glyph`] stores them); `y` is always `e2`, which is where
//! Schultz–Kindlmann put the `c` profile, so the axis choice is `[0, 1, 2]` (axis `e3`) or
//! `[2, 1, 0]` (axis `e1`). The latter is a reflection; the solid is mirror-symmetric in each
//! local coordinate, so it does not matter.

use crate::tensor::shape::{magnitudes_desc, westin_trace};

/// Kindlmann's default sharpness γ, which Teem's `tend glyph -sh` also uses.
pub const DEFAULT_GAMMA: f64 = 3.0;
/// The largest sharpness accepted (`--sharpness`): at γ = 20 the Westin cap already gives
/// exponents of 1e-40, below f32's normal range; the shapes stopped changing visibly long before.
pub const MAX_GAMMA: f64 = 20.0;
/// Schultz–Kindlmann's largest profile exponent, 3 in their tutorial's example code.
pub const DEFAULT_BETA_MAX: f64 = 3.0;
/// Teem caps `cl` and `cp` here: `1 − cl` never reaches 0, so every exponent stays positive and
/// finite powers stay finite.
pub const WESTIN_CAP: f64 = 0.99;
/// Anchors with an exponent of 0 (cylinder, octahedron) are the limits of the family; the
/// exponents are floored here so that `2/α` stays finite (Teem's mesher floors at 1e-5 too).
pub const SK_EXPONENT_FLOOR: f64 = 1e-5;

/// The two sharpness parameters. γ is `--sharpness`; β_max shapes only indefinite tensors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sharpness {
    /// Kindlmann's γ ≥ 0: 0 gives ellipsoids, larger values boxier and sharper glyphs.
    pub gamma: f64,
    /// Schultz–Kindlmann's β_max ≥ 2: how pinched the thorn and funk anchors are.
    pub beta_max: f64,
}

impl Default for Sharpness {
    fn default() -> Self {
        Sharpness {
            gamma: DEFAULT_GAMMA,
            beta_max: DEFAULT_BETA_MAX,
        }
    }
}

/// Which published mapping shaped a glyph.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mapping {
    /// Kindlmann 2004, for definite tensors (and the zero tensor, a sphere).
    Kindlmann,
    /// Schultz–Kindlmann 2010, for indefinite tensors; `zone` is the triangle (0..10) of the
    /// `(u, v)` square, numbered as in Teem.
    SchultzKindlmann { u: f64, v: f64, zone: u8 },
}

/// A glyph's superquadric shape in its local frame.
///
/// The solid, in local unit coordinates `q = (x, y, z)` (before scaling by the radii), is
///
/// ```text
/// |z| ≤ 1  and  (|x| / R_β(z))^(2/α) + (|y| / R_c(z))^(2/α) ≤ 1,   R_e(z) = (1 − |z|^(2/e))^(e/2),
/// ```
///
/// which for `c = β` is Barr's `(|x|^(2/α) + |y|^(2/α))^(α/β) + |z|^(2/β) ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SuperquadricShape {
    /// Cross-section exponent (round at 1, square as it goes to 0).
    pub alpha: f64,
    /// Profile exponent in the local x–z plane (elliptic at 1, boxy towards 0, pinched above 2).
    pub beta: f64,
    /// Profile exponent in the local y–z plane; equal to `beta` except for Schultz–Kindlmann
    /// shapes near the trace-free anchor.
    pub c: f64,
    /// Eigenvector frame columns of local x, y, z; local z is the symmetry axis.
    pub axes: [usize; 3],
    pub mapping: Mapping,
}

impl SuperquadricShape {
    /// The sphere (also the shape of the zero and isotropic tensors).
    pub const SPHERE: SuperquadricShape = SuperquadricShape {
        alpha: 1.0,
        beta: 1.0,
        c: 1.0,
        axes: [0, 1, 2],
        mapping: Mapping::Kindlmann,
    };

    /// Radii in local (x, y, z) order from radii in frame order (`r_i` along `e_i`).
    pub fn local_radii(&self, frame_radii: [f64; 3]) -> [f64; 3] {
        self.axes.map(|i| frame_radii[i])
    }

    /// Index in the frame of the symmetry axis (0 for `e1`, 2 for `e3`).
    pub fn axis(&self) -> usize {
        self.axes[2]
    }
}

/// The superquadric shape of a tensor with signed eigenvalues sorted λ1 ≥ λ2 ≥ λ3.
///
/// Definite tensors (no two eigenvalues of opposite sign) use Kindlmann's mapping, indefinite ones
/// Schultz–Kindlmann's. Non-finite input or sharpness gives the sphere rather than NaN exponents.
pub fn superquadric_shape(eigenvalues: [f64; 3], sharpness: Sharpness) -> SuperquadricShape {
    if !eigenvalues.iter().all(|l| l.is_finite()) {
        return SuperquadricShape::SPHERE;
    }
    let [l1, _, l3] = eigenvalues;
    if l1 > 0.0 && l3 < 0.0 {
        schultz_kindlmann(eigenvalues, sharpness.beta_max)
    } else {
        kindlmann(eigenvalues, sharpness.gamma)
    }
}

/// Kindlmann 2004 on the magnitudes. Also used by [`superquadric_shape`] for definite tensors.
pub fn kindlmann(eigenvalues: [f64; 3], gamma: f64) -> SuperquadricShape {
    let Some(w) = westin_trace(eigenvalues) else {
        return SuperquadricShape::SPHERE;
    };
    if !(gamma.is_finite() && gamma >= 0.0) {
        return SuperquadricShape::SPHERE;
    }
    let cl = w.cl.min(WESTIN_CAP);
    let cp = w.cp.min(WESTIN_CAP);
    // The major-|λ| eigenvector is e1 for a positive tensor and e3 for a negative one.
    let negative = eigenvalues[0] <= 0.0 && eigenvalues[2] < 0.0;
    let (major, minor) = if negative { (2, 0) } else { (0, 2) };
    let (axis, alpha, beta) = if cl >= cp {
        (major, (1.0 - cp).powf(gamma), (1.0 - cl).powf(gamma))
    } else {
        (minor, (1.0 - cl).powf(gamma), (1.0 - cp).powf(gamma))
    };
    SuperquadricShape {
        alpha,
        beta,
        c: beta,
        axes: axes_for(axis),
        mapping: Mapping::Kindlmann,
    }
}

fn axes_for(axis: usize) -> [usize; 3] {
    if axis == 0 { [2, 1, 0] } else { [0, 1, 2] }
}

/// Schultz–Kindlmann's map from eigenvalues to the unit square (their §4.2). `(1, 1)` is the
/// positive isotropic tensor, `(0, 0)` the negative one, `(1/2, 1/2)` the trace-free
/// `(1, 0, −1)`; negation maps `(u, v)` to `(1 − u, 1 − v)`.
pub fn sk_uv(eigenvalues: [f64; 3]) -> (f64, f64) {
    let m = magnitudes_desc(eigenvalues)[0];
    if !(m > 0.0 && m.is_finite()) {
        return (0.0, 0.0);
    }
    let [x, y, z] = eigenvalues.map(|l| l / m);
    let u = (y + 1.0) / 2.0;
    let v = if x > -z {
        (z + 1.0) / 2.0 - u + 1.0
    } else {
        (x - 1.0) / 2.0 - u + 1.0
    };
    (u, v)
}

/// The triangle of the `(u, v)` square, numbered as Teem numbers them: 0, 1 positive definite
/// (linear, planar), 2–4 two positive eigenvalues, 5–7 two negative, 8, 9 negative definite.
pub fn sk_zone(u: f64, v: f64) -> u8 {
    let (upv, tupv) = (u + v, 2.0 * u + v);
    if u > 0.5 {
        if upv > 1.5 {
            if u < v { 0 } else { 1 }
        } else if tupv > 2.0 {
            2
        } else if upv > 1.0 {
            3
        } else {
            4
        }
    } else if upv > 0.5 {
        if upv > 1.0 {
            5
        } else if tupv > 1.0 {
            6
        } else {
            7
        }
    } else if u < v {
        8
    } else {
        9
    }
}

/// Corners of the ten triangles in the `(u, v)` square.
const SK_VERTS: [[f64; 2]; 11] = [
    [1.0, 1.0],
    [0.5, 1.0],
    [0.75, 0.75],
    [1.0, 0.5],
    [1.0, 0.0],
    [0.5, 0.5],
    [0.0, 1.0],
    [0.0, 0.5],
    [0.25, 0.25],
    [0.5, 0.0],
    [0.0, 0.0],
];

#[derive(Clone, Copy)]
enum Anchor {
    Ball,
    Cylinder,
    Half,
    Octahedron,
    Cone,
    Thorn,
    Funk,
}

impl Anchor {
    /// `(α, β, c)`. Teem gives the thorn `c = 3`, which is β only at β_max = 3; the thorn sits at
    /// `(1, 1, −1)`, a tensor symmetric about its axis, so `c = β` is used for every β_max.
    fn abc(self, beta_max: f64) -> [f64; 3] {
        match self {
            Anchor::Ball => [1.0, 1.0, 1.0],
            Anchor::Cylinder => [1.0, 0.0, 0.0],
            Anchor::Half => [0.5, 0.5, 0.5],
            Anchor::Octahedron => [0.0, 2.0, 2.0],
            Anchor::Cone => [1.0, 2.0, 2.0],
            Anchor::Thorn => [1.0, beta_max, beta_max],
            Anchor::Funk => [0.0, beta_max, 2.0],
        }
    }
}

/// Per zone: its three corners (into [`SK_VERTS`]), their anchor shapes, and the symmetry axis
/// (frame column). The axis is not in Teem's mapping code; it follows from the anchors: a thorn
/// (round cross-section) must turn about the eigenvector whose sign is the odd one out, a cone or
/// cylinder at a planar corner about the normal of the disc it flattens to, and a cylinder at a
/// linear corner along its length. Zones 2–4 contain the thorn at `(1, 1, −1)` (axis `e3`),
/// 5–7 the one at `(1, −1, −1)` (axis `e1`). Between them (λ2 = 0) the glyph is flat in `e2`
/// and its `e1`–`e3` section `|x|^(2/β) + |z|^(2/β) ≤ 1` is symmetric under the swap, so the
/// change of axis is seamless.
const SK_ZONES: [([usize; 3], [Anchor; 3], usize); 10] = {
    use Anchor::*;
    [
        ([0, 1, 2], [Ball, Cylinder, Half], 0),
        ([0, 2, 3], [Ball, Half, Cylinder], 2),
        ([1, 3, 4], [Octahedron, Cone, Thorn], 2),
        ([1, 4, 5], [Octahedron, Thorn, Funk], 2),
        ([4, 5, 9], [Thorn, Funk, Cone], 2),
        ([1, 5, 6], [Cone, Funk, Thorn], 0),
        ([5, 6, 9], [Funk, Thorn, Octahedron], 0),
        ([6, 7, 9], [Thorn, Cone, Octahedron], 0),
        ([7, 8, 10], [Cylinder, Half, Ball], 0),
        ([8, 9, 10], [Half, Cylinder, Ball], 2),
    ]
};

/// Schultz–Kindlmann 2010 for any tensor (used by [`superquadric_shape`] for indefinite ones).
/// The zero tensor is the ball.
pub fn schultz_kindlmann(eigenvalues: [f64; 3], beta_max: f64) -> SuperquadricShape {
    let beta_max = if beta_max.is_finite() && beta_max > 0.0 {
        beta_max
    } else {
        DEFAULT_BETA_MAX
    };
    let (u, v) = sk_uv(eigenvalues);
    let zone = sk_zone(u, v);
    let (verts, anchors, axis) = SK_ZONES[zone as usize];
    let bary = barycentric([u, v], verts.map(|i| SK_VERTS[i]));
    let mut abc = [0.0; 3];
    for (w, a) in bary.iter().zip(anchors) {
        for (o, x) in abc.iter_mut().zip(a.abc(beta_max)) {
            *o += w * x;
        }
    }
    let [alpha, beta, c] = abc.map(|e| e.max(SK_EXPONENT_FLOOR));
    SuperquadricShape {
        alpha,
        beta,
        c,
        axes: axes_for(axis),
        mapping: Mapping::SchultzKindlmann { u, v, zone },
    }
}

/// Barycentric coordinates of `p` in the triangle `t`, clamped to the triangle: the zone test and
/// the rounding of `(u, v)` can put `p` an ulp outside.
fn barycentric(p: [f64; 2], t: [[f64; 2]; 3]) -> [f64; 3] {
    let area = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
    };
    let w = [
        area(p, t[1], t[2]),
        area(p, t[0], t[2]),
        area(p, t[0], t[1]),
    ];
    let s: f64 = w.iter().sum();
    if s > 0.0 {
        w.map(|x| x / s)
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// Exponents below this are raised to it: `2/e` must stay finite for the powers to.
pub const EXPONENT_MIN: f64 = 1e-300;

/// The solid's inside–outside function (docs/book/src/developer/superquadric-derivation.md §1,
/// §4) of exponents `e = (α, β, c)` at absolute local coordinates `a = (|x|, |y|, |z|)`:
/// `N_α(|x| / R_β(z), |y| / R_c(z))`, ≤ 1 exactly on the solid, non-decreasing in each
/// argument, ∞ beyond `|z| = 1`.
pub fn gauge(e: [f64; 3], a: [f64; 3]) -> f64 {
    let [ax, ay, az] = a;
    if az >= 1.0 {
        return if az == 1.0 && ax == 0.0 && ay == 0.0 {
            1.0
        } else {
            f64::INFINITY
        };
    }
    let u = scaled(ax, profile(az, e[1]));
    let w = scaled(ay, profile(az, e[2]));
    pnorm(u, w, e[0])
}

/// `a / r` with `0 / 0 = 0`: an axis point stays on the axis where the profile closes.
fn scaled(a: f64, r: f64) -> f64 {
    if a == 0.0 { 0.0 } else { a / r }
}

/// The profile radius `R_e(z) = (1 − z^(2/e))^(e/2)` for `0 ≤ z ≤ 1`, accurate near the tips
/// (`1 − z^q` by `expm1`) and for extreme exponents (no intermediate overflows).
pub fn profile(z: f64, e: f64) -> f64 {
    let q = 2.0 / e.max(EXPONENT_MIN);
    let rest = -(q * z.ln()).exp_m1();
    (rest.ln() / q).exp()
}

/// `N_e(a, b) = (a^(2/e) + b^(2/e))^(e/2)` for `a, b ≥ 0`, scaled by the larger so that nothing
/// overflows: `max(a, b)` in the limit `e → 0`.
pub fn pnorm(a: f64, b: f64, e: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    if hi == 0.0 || hi.is_infinite() {
        return hi;
    }
    let p = 2.0 / e.max(EXPONENT_MIN);
    let r = (lo / hi).powf(p);
    hi * (r.ln_1p() / p).exp()
}

/// The radius, in local unit coordinates, of the smallest ball about the centre that holds the
/// solid of exponents `e = (α, β, c)`: the proxies' bound (a ball of radius s in local unit
/// coordinates is the ellipsoid of semi-axes s·radii), 1 for the ellipsoid, √2 for the
/// cylinder, √3 at most (the unit box's corner).
///
/// For Barr's solid (c = β) write ρ = N_α(x, y): the cross-section's farthest point from the
/// axis is on its diagonal for α ≤ 2 (x² + y² = 2^(1−α) ρ²) and on an axis beyond (ρ²), so
/// |q|² ≤ m ρ² + z² with m = max(2^(1−α), 1), over the profile ρ^(2/β) + z^(2/β) = 1. With
/// U = ρ², V = z² that profile is U^(1/β) + V^(1/β) = 1 and m U + V a linear function: for
/// β < 1 Hölder's inequality gives its maximum ‖(m, 1)‖ in the dual norm of 1/β, (m^(1/(1−β)) +
/// 1)^(1−β), written as m (1 + m^(−1/(1−β)))^(1−β) so that nothing overflows; for β ≥ 1 the
/// curve lies inside U + V ≤ 1 and the maximum is m. The bound is attained. Schultz–Kindlmann's
/// c ≠ β solids lie inside the Barr solid of exponent min(β, c) (R_e(z) grows as e shrinks).
pub fn bounding_scale(e: [f64; 3]) -> f64 {
    let [alpha, beta, c] = e;
    let beta = beta.min(c);
    let m = (1.0 - alpha).exp2().max(1.0);
    let s2 = if beta < 1.0 {
        let k = 1.0 - beta;
        m * (1.0 + m.powf(-1.0 / k)).powf(k)
    } else {
        m
    };
    s2.sqrt().min(3f64.sqrt())
}

/// A hair beyond the farthest point ([`bounding_scale`] times this), so that f32 rounding
/// cannot put the surface outside a proxy built from the bound (`SQ_BOUND_MARGIN` in
/// shaders/superquadric.wgsl).
pub const BOUND_MARGIN: f64 = 1.0001;

/// Whether the solid of exponents `e = (α, β, c)` is convex with Barr's norm as gauge (α, β ≤ 2,
/// c = β: every Kindlmann glyph), the shader's fast finder (`sq_convex` in
/// shaders/superquadric.wgsl).
pub fn is_convex(e: [f32; 3]) -> bool {
    e[0] <= 2.0 && e[1] <= 2.0 && e[2] == e[1]
}

/// Bits kept of an exponent: an f32 without its sign and its 10 lowest mantissa bits (8
/// exponent bits, 13 mantissa bits; relative rounding error ≤ 2⁻¹⁴). Three fit in 64 bits, the
/// superquadric's whole per-glyph shape: α and β change a glyph's surface by far less than the
/// rounding moves it (≤ 6e-5 of an exponent), and the reference reads the same rounded values.
const EXPONENT_BITS: u32 = 21;
const EXPONENT_DROP: u32 = 31 - EXPONENT_BITS;

/// `(α, β, c)` packed in two words, as the GPU reads them (`load_exponents` in
/// shaders/common.wgsl): α in bits 0..21 of word 0, β in bits 21..32 of word 0 and 0..10 of
/// word 1, c in bits 10..31 of word 1. Each is rounded to nearest and clamped to
/// `[1e-30, f32::MAX]`; non-finite exponents become the sphere's 1.
pub fn pack_exponents(e: [f64; 3]) -> [u32; 2] {
    let [a, b, c] = e.map(|x| {
        let x = if x.is_finite() { x } else { 1.0 };
        let x = x.clamp(EXPONENT_LOWEST, f64::from(f32::MAX)) as f32;
        let bits = x.to_bits() + (1 << (EXPONENT_DROP - 1));
        (bits >> EXPONENT_DROP).min((1 << EXPONENT_BITS) - 1)
    });
    [
        a | (b << EXPONENT_BITS),
        (b >> (32 - EXPONENT_BITS)) | (c << 10),
    ]
}

/// The exponents [`pack_exponents`] stored (exactly what the shaders decode).
pub fn unpack_exponents(w: [u32; 2]) -> [f32; 3] {
    let mask = (1u32 << EXPONENT_BITS) - 1;
    let a = w[0] & mask;
    let b = (w[0] >> EXPONENT_BITS) | ((w[1] & 0x3ff) << (32 - EXPONENT_BITS));
    let c = (w[1] >> 10) & mask;
    [a, b, c].map(|x| f32::from_bits(x << EXPONENT_DROP))
}

/// The smallest exponent stored: far below any mapping's (Kindlmann's γ = 10 gives 1e-20), and
/// a normal f32, so `2/e` stays finite.
const EXPONENT_LOWEST: f64 = 1e-30;

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_vectors::superquadric_vectors as vectors;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn mapping_matches_the_vectors() {
        let all = vectors();
        let cases = all["mapping"].as_array().unwrap();
        for case in cases {
            let id = case["id"].as_str().unwrap();
            let ev: Vec<f64> = case["eigenvalues"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            let sharp = Sharpness {
                gamma: case["gamma"].as_f64().unwrap(),
                beta_max: case["beta_max"].as_f64().unwrap(),
            };
            let s = superquadric_shape([ev[0], ev[1], ev[2]], sharp);
            let e = &case["expected"];
            for (name, got) in [("alpha", s.alpha), ("beta", s.beta), ("c", s.c)] {
                let want = e[name].as_f64().unwrap();
                assert!(close(got, want, 1e-12), "{id}: {name} {got} vs {want}");
            }
            assert_eq!(s.axis(), e["axis"].as_u64().unwrap() as usize, "{id}: axis");
            let sk = e["mapping"] == "schultz_kindlmann";
            match s.mapping {
                Mapping::Kindlmann => assert!(!sk, "{id}: mapping"),
                Mapping::SchultzKindlmann { u, v, zone } => {
                    assert!(sk, "{id}: mapping");
                    assert!(close(u, e["u"].as_f64().unwrap(), 1e-12), "{id}: u");
                    assert!(close(v, e["v"].as_f64().unwrap(), 1e-12), "{id}: v");
                    assert_eq!(u64::from(zone), e["zone"].as_u64().unwrap(), "{id}: zone");
                }
            }
        }
        assert!(cases.len() >= 12, "only {} mapping cases", cases.len());
    }

    /// The bound holds every point of the surface and is reached (sampled on Kindlmann's
    /// parametric surface, and on the c ≠ β form through the gauge).
    #[test]
    fn bounding_scale_is_the_farthest_surface_point() {
        assert!((bounding_scale([1.0, 1.0, 1.0]) - 1.0).abs() < 1e-12);
        assert!((bounding_scale([1.0, 1e-20, 1e-20]) - 2f64.sqrt()).abs() < 1e-12);
        assert!((bounding_scale([1e-20, 1e-20, 1e-20]) - 3f64.sqrt()).abs() < 1e-12);
        let sp = |c: f64, e: f64| c.signum() * c.abs().powf(e);
        for e in [
            [1.0, 0.216, 0.216],
            [0.3, 0.8, 0.8],
            [0.55, 2.75, 2.3],
            [1.0, 3.0, 3.0],
            [1e-5, 3.0, 2.0],
            [0.5, 0.5, 0.5],
            [1.0, 0.999, 0.999],
        ] {
            let bound = bounding_scale(e);
            let mut far = 0.0f64;
            let n = 400;
            for i in 0..=n {
                let theta = std::f64::consts::FRAC_PI_2 * f64::from(i) / f64::from(n);
                for j in 0..=n {
                    let phi = std::f64::consts::FRAC_PI_2 * f64::from(j) / f64::from(n);
                    // Barr's surface of exponents (α, β), then y stretched to the c profile.
                    let z = sp(phi.cos(), e[1]);
                    let x = sp(theta.cos(), e[0]) * sp(phi.sin(), e[1]);
                    let mut y = sp(theta.sin(), e[0]) * sp(phi.sin(), e[1]);
                    let (rb, rc) = (profile(z, e[1]), profile(z, e[2]));
                    if rb > 0.0 {
                        y *= rc / rb;
                    }
                    let g = gauge(e, [x, y, z]);
                    assert!((g - 1.0).abs() < 1e-6 || rb == 0.0, "{e:?}: gauge {g}");
                    far = far.max((x * x + y * y + z * z).sqrt());
                }
            }
            assert!(far <= bound * (1.0 + 1e-12), "{e:?}: {far} beyond {bound}");
            if e[1] == e[2] {
                assert!(
                    far >= bound * (1.0 - 1e-3),
                    "{e:?}: {far} well inside {bound}"
                );
            }
        }
    }

    /// Packing keeps each exponent to 2⁻¹⁴ relative, the three apart, and the round trip is
    /// a fixed point (what the scene stores is exactly what the GPU decodes).
    #[test]
    fn exponents_pack_to_21_bits_each() {
        for e in [
            [1.0, 0.216, 0.216],
            [1e-20, 3.0, 2.0],
            [1e-5, 1e-5, 1e-5],
            [0.55, 2.75, 2.3],
            [5.0, 1e-3, 0.5],
        ] {
            let got = unpack_exponents(pack_exponents(e));
            for k in 0..3 {
                let rel = (f64::from(got[k]) - e[k]).abs() / e[k];
                assert!(rel <= 2f64.powi(-14), "{e:?} → {got:?}");
            }
            let again = unpack_exponents(pack_exponents(got.map(f64::from)));
            assert_eq!(again, got);
        }
        assert_eq!(
            unpack_exponents(pack_exponents([f64::NAN, 1.0, 1.0]))[0],
            1.0
        );
        assert!(unpack_exponents(pack_exponents([0.0, 1.0, 1.0]))[0] > 0.0);
    }

    #[test]
    fn hand_checked_anchors() {
        let sh = Sharpness::default();
        // Isotropic and zero: spheres.
        for ev in [[2.0, 2.0, 2.0], [0.0; 3], [-1.0, -1.0, -1.0]] {
            let s = superquadric_shape(ev, sh);
            assert_eq!((s.alpha, s.beta, s.c), (1.0, 1.0, 1.0), "{ev:?}");
        }
        // (1, 1, −1): the thorn about e3; (1, −1, −1): the thorn about e1.
        let s = superquadric_shape([1.0, 1.0, -1.0], sh);
        assert_eq!((s.alpha, s.beta, s.c, s.axis()), (1.0, 3.0, 3.0, 2));
        let s = superquadric_shape([1.0, -1.0, -1.0], sh);
        assert_eq!((s.alpha, s.beta, s.c, s.axis()), (1.0, 3.0, 3.0, 0));
        // Trace-free (1, 0, −1): the funk, the only anchor with c ≠ β.
        let s = superquadric_shape([1.0, 0.0, -1.0], sh);
        assert_eq!((s.alpha, s.beta, s.c), (SK_EXPONENT_FLOOR, 3.0, 2.0));
        // Kindlmann's linear (3, 1, 1): trace form cl = 2/5, cp = 0.
        let s = superquadric_shape([3.0, 1.0, 1.0], sh);
        assert_eq!(s.axes, [2, 1, 0]);
        assert!(close(s.alpha, 1.0, 1e-15) && close(s.beta, 0.6f64.powi(3), 1e-15));
        // A negative definite tensor has the shape of its negation, about the same eigenvector.
        let p = superquadric_shape([3.0, 1.0, 1.0], sh);
        let n = superquadric_shape([-1.0, -1.0, -3.0], sh);
        assert_eq!((p.alpha, p.beta), (n.alpha, n.beta));
        assert_eq!((p.axis(), n.axis()), (0, 2));
        // Negation maps (u, v) to (1 − u, 1 − v) and keeps the shape.
        let a = schultz_kindlmann([2.0, -0.6, -1.5], 3.0);
        let b = schultz_kindlmann([1.5, 0.6, -2.0], 3.0);
        assert!(close(a.alpha, b.alpha, 1e-14) && close(a.beta, b.beta, 1e-14));
        assert!(close(a.c, b.c, 1e-14));
        assert_eq!(a.axis(), 2 - b.axis());
    }

    #[test]
    fn never_nan() {
        let sh = Sharpness {
            gamma: 10.0,
            beta_max: 3.0,
        };
        for ev in [
            [f64::NAN, 1.0, 0.0],
            [1e300, 1e-300, -1e300],
            [f64::MAX, 0.0, -f64::MAX],
            [5e-324, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
        ] {
            let s = superquadric_shape(ev, sh);
            for e in [s.alpha, s.beta, s.c] {
                assert!(e.is_finite() && e > 0.0, "{ev:?}: {s:?}");
            }
        }
    }
}
