//! CPU twins of the shaders, one file per WGSL file and with its name: the same formulas in
//! f64 (with the math notes' names), so each shader's arithmetic can be checked against
//! `shared/math/test-vectors.json` without a GPU, and so the reference and the tests can
//! predict what a shader does (its proxies, its fragment counts, its shading). The exception is
//! `superquadric`, in f32 like its shader: it twins a root finder, whose iterations, caps and
//! answers depend on the precision. Each kind's twin (`<kind>.rs`, of
//! `shaders/shape/<kind>.wgsl`) answers the methods' questions about its shape through
//! [`ShapeTwin`]; it calls `crate::shape` for the exact geometry, never the reference.

pub mod capsule;
pub mod common;
pub mod composite;
pub mod cylinder;
pub mod ellipsoid;
pub mod gumhold_ellipsoid;
pub mod odf;
pub mod principal;
pub mod screen_box;
pub mod sigg;
pub mod superquadric;
pub mod superquadric_finder;

use glam::{DMat4, DVec3};

use crate::scene::{GlyphGeometry, GlyphKind};
use screen_box::Proxy;

/// What the methods' shaders compute from a kind's shape interface, in f64.
pub trait ShapeTwin: Sync {
    /// The proxy sigg.wgsl's vertex stage draws: culled when the eye is inside the glyph
    /// (perspective), else the kind's `shape_box` (`eye` and `view_proj` relative to the scene
    /// origin, like the glyph's centre).
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy;

    /// The semi-axes along the instance frame of the ellipsoid whose quad gumhold_solid.wgsl
    /// draws (`shape_of`'s scale times its bound), or `None` where the eye is inside the glyph
    /// (perspective: not drawn).
    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3>;
}

/// Each kind's twin.
pub fn of(kind: GlyphKind) -> &'static dyn ShapeTwin {
    match kind {
        GlyphKind::Ellipsoid => &ellipsoid::Twin,
        GlyphKind::Cylinder => &cylinder::Twin,
        GlyphKind::Capsule => &capsule::Twin,
        GlyphKind::Superquadric => &superquadric::Twin,
        GlyphKind::Principal => &principal::Twin,
        GlyphKind::Odf => &odf::Twin,
    }
}
