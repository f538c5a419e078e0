//! Glyph kinds. A kind is one unit: its module here holds its f64 geometry once (the instance's
//! frame and parameters from a glyph, the bounds the scene frames, the eye rule, the exact
//! intersection the reference casts, the unit mesh of the mesh baselines) and names its WGSL
//! file (`shaders/shape/<kind>.wgsl`, the shape interface every GPU method calls); its CPU twin
//! is `src/twin/<kind>.rs`. Everything else (the CLI, the viewer, the bench, the stability
//! suite, the GPU pipelines, the tests) enumerates [`GlyphKind::VALUES`] and asks a kind's
//! [`Shape`] and [`Capabilities`] instead of naming kinds. Adding a kind is the checklist in
//! docs/book/src/developer/adding-a-glyph-kind.md.

pub mod capsule;
pub mod cylinder;
pub mod ellipsoid;
pub mod geometry;
pub mod mesh;
pub mod odf;
pub mod principal;
pub mod rules;
pub mod superquadric;

use glam::DVec3;

pub use geometry::{GlyphGeometry, GlyphInstance};
pub use mesh::Mesh;
pub use odf::Payload;

use crate::glyph::{Glyph, ResolvedStyle};

/// The glyph shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum GlyphKind {
    #[default]
    Ellipsoid,
    /// Capped elliptic cylinder along the principal axis (or along e3 for planar tensors).
    Cylinder,
    /// The cylinder's axis with rounded ends: a segment swept by a ball of radius R = the mean
    /// of the cross-section's semi-axes, total half-length max(axis half-length, R); an
    /// isotropic tensor gives a sphere ([`capsule::capsule_of`]).
    Capsule,
    /// Kindlmann's superquadric (Schultz–Kindlmann's for indefinite tensors), shaped by the
    /// tensor and `--sharpness` ([`crate::glyph::superquadric`]).
    Superquadric,
    /// Principal stresses: a bar along each eigenvector, half-length ∝ |σ_i|, coloured by the
    /// sign of σ_i, with arrowheads on request ([`principal`]).
    Principal,
    /// A function on the sphere drawn as the radial surface r(u) = max(f(u), 0): a fibre ODF's
    /// spherical-harmonic series, or a tensor's profile uᵀTu ([`odf`]).
    Odf,
}

crate::names::named_values!(GlyphKind {
    Ellipsoid => "ellipsoid",
    Cylinder => "cylinder",
    Capsule => "capsule",
    Superquadric => "superquadric",
    Principal => "principal",
    Odf => "odf",
});

impl GlyphKind {
    /// The registry: each kind's shape.
    pub fn shape(self) -> &'static dyn Shape {
        match self {
            GlyphKind::Ellipsoid => &ellipsoid::Kind,
            GlyphKind::Cylinder => &cylinder::Kind,
            GlyphKind::Capsule => &capsule::Kind,
            GlyphKind::Superquadric => &superquadric::Kind,
            GlyphKind::Principal => &principal::Kind,
            GlyphKind::Odf => &odf::Kind,
        }
    }

    /// What the kind takes ([`Shape::caps`]).
    pub fn caps(self) -> Capabilities {
        self.shape().caps()
    }

    /// Whether glyphs of this kind can be coloured by `scheme` (amplitude: a kind whose
    /// [`Capabilities::amplitude`] says so).
    pub fn colours(self, scheme: crate::glyph::ColorScheme) -> bool {
        scheme != crate::glyph::ColorScheme::Amplitude || self.caps().amplitude
    }
}

/// One instance of a glyph, as a kind places it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Where the instance's centre is, relative to the glyph's centre (world units).
    pub offset: [f64; 3],
    /// The instance frame (unit quaternion x, y, z, w).
    pub rotation: [f32; 4],
    pub radii: [f32; 3],
    /// The kind's parameter words.
    pub params: [u32; 2],
    pub color: [u8; 4],
}

impl Part {
    /// The whole glyph as one instance at its centre, coloured by `style`.
    pub fn whole(
        g: &Glyph,
        style: &ResolvedStyle,
        (rotation, radii): ([f32; 4], [f32; 3]),
        params: [u32; 2],
    ) -> Self {
        Part {
            offset: [0.0; 3],
            rotation,
            radii,
            params,
            color: style.color(g),
        }
    }
}

/// What a kind can be drawn with, as data: the one table the request's legality checks, the
/// viewer's panel, the bench and the stability suite read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Capabilities {
    /// Gumhold's compute prepass (proxy frames built once per glyph in compute).
    pub prepass: bool,
    /// Splats: glyphs up to a few pixels across ray cast per pixel in compute (needs the
    /// prepass and the ray-cast depth).
    pub splats: bool,
    /// Gumhold's proxy on the glyph's nearest view plane (conservative depth).
    pub conservative_depth: bool,
    /// Shaped by `--sharpness` (the style's sharpness is part of the instance).
    pub sharpness: bool,
    /// Takes `--arrows` (heads on its parts).
    pub arrows: bool,
    /// Measured by `bench` when no `--glyph` is given (the main speed table; other kinds have
    /// bench runs of their own, with `--glyph`).
    pub benched_by_default: bool,
    /// Lobes that cross and necks narrower than a coarse mesh's facets (ODF glyphs): a `mesh:N`
    /// baseline of the kind leaves background pixels inside its outline, which the stability
    /// suite judges as the mesh's coverage error, not as cracks (`box` is still held to them).
    pub mesh_holes: bool,
    /// Coloured by `--color amplitude` (its own radial function's value: ODF glyphs).
    pub amplitude: bool,
}

impl Capabilities {
    /// None of them: a kind names the ones it has (`..Capabilities::NONE`).
    pub const NONE: Capabilities = Capabilities {
        prepass: false,
        splats: false,
        conservative_depth: false,
        sharpness: false,
        arrows: false,
        benched_by_default: false,
        mesh_holes: false,
        amplitude: false,
    };
}

/// A forward hit: distance along the unit ray and the unit outward normal (world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    pub t: f64,
    pub normal: DVec3,
}

/// One glyph as the exact reference casts it (relative to the scene origin), prepared once per
/// frame.
pub trait Exact: Send + Sync {
    fn centre(&self) -> DVec3;
    /// Half-extents of a box about [`Self::centre`] holding the solid (the reference's BVH).
    fn half_extents(&self) -> DVec3;
    /// Whether `p` is inside or on the solid: the rule by which no method draws a glyph around
    /// the eye.
    fn contains(&self, p: DVec3) -> bool;
    /// The first forward crossing of `o + t d` (`d` unit) with the surface (the exit when `o` is
    /// inside).
    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit>;

    /// The colour of the surface point `p` for a glyph of colour `base` (`shape_tint` of the
    /// kind's WGSL: ODF glyphs coloured by direction; most kinds: `base`).
    fn tint(&self, _p: DVec3, base: DVec3) -> DVec3 {
        base
    }
}

/// The f64 geometry of a glyph kind.
pub trait Shape: Send + Sync {
    fn kind(&self) -> GlyphKind;
    fn caps(&self) -> Capabilities;

    /// How many instances a glyph may take at most (most kinds: one; a principal-stress glyph
    /// is three bars and their arrowheads).
    fn parts(&self) -> usize {
        1
    }

    /// Instance `part` (below [`Self::parts`]) of glyph `g` sized and coloured by `style`, or
    /// `None` where the glyph has no such part: its frame, radii, parameter words
    /// ([`GlyphInstance::shape`]) and colour.
    fn place(&self, g: &Glyph, part: usize, style: &ResolvedStyle) -> Option<Part>;

    /// The colour scheme the kind is drawn in when none is asked for (most kinds: the data's
    /// default).
    fn default_color(&self) -> Option<crate::glyph::ColorScheme> {
        None
    }

    /// An instance made without this kind's parameters (a synthetic scene's: its radii taken
    /// as the tensor's eigenvalues) as an instance of this kind. Most kinds take it as it is.
    fn adopt(&self, g: &GlyphInstance) -> GlyphInstance {
        *g
    }

    /// Half-extents of a box about the centre holding the glyph: the scene's bounds, which the
    /// camera frames and the far plane keeps.
    fn bounds(&self, geo: &GlyphGeometry) -> DVec3;

    /// The radius of the sphere the vertex stages cull with (`shape_radius` of the kind's
    /// WGSL); most kinds: the sphere about the glyph as ellipsoid or capped cylinder,
    /// [`geometry::bounding_radius`].
    fn cull_radius(&self, radii: [f32; 3]) -> f64 {
        geometry::bounding_radius(radii)
    }

    /// The glyph as the exact reference casts it.
    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact>;

    /// [`Self::exact`] with the scene's per-glyph values ([`Payload`]), for kinds that keep
    /// some there (ODF series).
    fn exact_with(
        &self,
        geo: &GlyphGeometry,
        _payload: Option<&std::sync::Arc<Payload>>,
    ) -> Box<dyn Exact> {
        self.exact(geo)
    }

    /// The unit mesh `mesh:level` instances for this kind.
    fn unit_mesh(&self, level: u8) -> Mesh;

    /// (vertices, triangles) of [`Self::unit_mesh`], without building it.
    fn mesh_stats(&self, level: u8) -> (usize, usize);

    /// The kind's WGSL: its shader interface and what it needs, composed after common.wgsl
    /// and shaders/shape/screen_box.wgsl.
    fn wgsl(&self) -> &'static [&'static str];

    /// With [`Capabilities::splats`], the WGSL of its splats for Gumhold's solids.
    fn splat_wgsl(&self) -> Option<&'static str> {
        None
    }

    /// The `override` that keeps a general (slower) search in the kind's shaders, and whether
    /// an instance needs it: pipelines of chunks without such instances leave it out.
    fn general_override(&self) -> Option<&'static str> {
        None
    }

    fn is_general(&self, _g: &GlyphInstance) -> bool {
        false
    }
}

/// Where the ray `o + t v` (any length of `v`) crosses the unit sphere |p| = 1 (of the space
/// `o` and `v` span: a cylinder's side passes its axis' components as zeros): both `t`,
/// ascending, or `None` for a miss or `v = 0`. Solved in the distance-to-centre form (Haines
/// et al., "Precision improvements for ray/sphere intersection", Ray Tracing Gems 2019): the
/// point of the ray nearest the centre first, then the half-chord from 1 − its distance². The
/// textbook β² − αγ cancels when the origin is far from that point in these units: a glyph-near
/// origin in world space lies up to k radii away from it in a disc's parameter space (k = its
/// anisotropy), and at k = 1e7 that form misplaced the f64 reference's rims by ~1 % of a
/// radius; here the only loss is |o|·2⁻⁵³ in the nearest point.
pub fn unit_sphere_roots(o: DVec3, v: DVec3) -> Option<(f64, f64)> {
    let a = v.length_squared();
    if !(a > 0.0 && a.is_finite()) {
        return None;
    }
    let s = -o.dot(v) / a;
    let p = o + v * s;
    let h2 = 1.0 - p.length_squared();
    if h2.is_nan() || h2 < 0.0 {
        return None;
    }
    let h = (h2 / a).sqrt();
    Some((s - h, s + h))
}

/// Both roots of `alpha t² + 2 beta t + gamma = 0` with `disc = beta² − alpha gamma ≥ 0`,
/// ascending, without cancellation (sigg-quadric.md §4).
pub fn stable_roots(alpha: f64, beta: f64, gamma: f64, disc: f64) -> (f64, f64) {
    let q = -(beta + beta.signum() * disc.sqrt());
    let (r1, r2) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / alpha, gamma / q)
    };
    (r1.min(r2), r1.max(r2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    /// The registry gives each kind its own shape, and every shape its WGSL.
    #[test]
    fn the_registry_is_one_shape_per_kind() {
        for &k in GlyphKind::VALUES {
            assert_eq!(k.shape().kind(), k);
            assert!(!k.shape().wgsl().is_empty(), "{k}");
            let caps = k.caps();
            assert!(
                !caps.splats || caps.prepass,
                "{k}: splats come from the prepass"
            );
            assert_eq!(
                caps.splats,
                k.shape().splat_wgsl().is_some() || k == GlyphKind::Ellipsoid
            );
        }
    }

    /// Rays built to pass a thin glyph at a known distance from its centre in parameter space,
    /// just inside and just outside its surface (1 ∓ 1e-6 of it, squared), from 5 radii away in
    /// world space: the reference must hit the one and miss the other at every k up to 1e7,
    /// and its hit must lie on the surface. The textbook β² − αγ misjudged these at k = 1e7 (its
    /// discriminant cancels ~k² to one: 1e-2 of the unit sphere's).
    #[test]
    fn thin_glyphs_rims_are_exact_in_the_reference() {
        let frame = DMat3::from_quat(glam::DQuat::from_axis_angle(
            DVec3::new(0.3, -0.8, 0.5).normalize(),
            0.7,
        ));
        let c = DVec3::new(0.4, -0.2, 0.9);
        for k in [1e3, 1e5, 1e6, 1e7] {
            for (radii, cylinder) in [
                (DVec3::new(1.0, 1.0, 1.0 / k), false),
                (DVec3::new(1.0, 1.0 / k, 1.0 / k), false),
                (DVec3::new(1.0, 1.0, 1.0 / k), true),
            ] {
                let m = frame * DMat3::from_diagonal(radii);
                let t_inv = DMat3::from_diagonal(1.0 / radii) * frame.transpose();
                // An oblique world direction, which parameter space turns nearly onto the thin
                // axis; the ray's nearest point to the centre there, p0 ⊥ v (for the cylinder
                // in the y, z of its side).
                let d = frame * DVec3::new(0.3, 0.4, 0.85).normalize();
                let v = t_inv * d;
                let (perp, along) = if cylinder {
                    (DVec3::new(0.0, -v.z, v.y).normalize(), DVec3::X * 0.1)
                } else {
                    (v.cross(DVec3::X).normalize(), DVec3::ZERO)
                };
                for (r2, hits) in [(1.0 - 1e-6, true), (1.0 + 1e-6, false)] {
                    let p0 = perp * f64::sqrt(r2) + along;
                    let o = c + m * p0 - d * 5.0;
                    let (hit, on_surface) = if cylinder {
                        let cyl = cylinder::Cylinder { c, frame, radii };
                        let h = cyl.intersect(o, d);
                        let q = h.map(|h| t_inv * (o + d * h.t - c));
                        (h.is_some(), q.map(|q| q.y * q.y + q.z * q.z))
                    } else {
                        let h = ellipsoid::intersect(o, d, c, &t_inv);
                        (h.is_some(), h.map(|(_, p)| p.length_squared()))
                    };
                    let what = format!("k = {k:e}, radii {radii}, cylinder {cylinder}, |p0|² {r2}");
                    assert_eq!(hit, hits, "{what}");
                    if let Some(q2) = on_surface {
                        assert!((q2 - 1.0).abs() < 1e-7, "{what}: hit at |p|² = {q2}");
                    }
                }
            }
        }
    }
}
