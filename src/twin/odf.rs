//! The CPU twin of shaders/shape/odf.wgsl: the box of the bounding ellipsoid that Sigg's vertex
//! stage draws and the ellipsoid Gumhold's quad is built on (a series glyph's radii are its
//! semi-axes, [`crate::shape::odf::bounding_ellipsoid`]; a tensor's profile keeps the ball of its
//! largest radius), with the eye rule. The crossing's f64 form is
//! [`crate::shape::odf::plane_crossing`].
//!
//! The eye rule of a series glyph needs its scene's series; without them the twin takes a
//! series glyph as not holding the eye (the GPU and the reference test the series itself).

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::{Proxy, ellipsoid_proxy};
use crate::scene::GlyphGeometry;
use crate::shape::Exact;
use crate::shape::odf::Odf;

pub struct Twin;

impl ShapeTwin for Twin {
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        if !ortho && Odf::of(geo, None).contains(eye) {
            return Proxy::Culled;
        }
        let r = bound(geo);
        ellipsoid_proxy(view_proj, geo, r)
    }

    /// The bounding ellipsoid: `shape_of`'s scale R times its bound.
    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        (ortho || !Odf::of(geo, None).contains(eye)).then_some(bound(geo))
    }
}

/// The semi-axes of the proxy's ellipsoid: a series glyph's radii, a profile's ball.
fn bound(geo: &GlyphGeometry) -> DVec3 {
    if geo.params[0] != 0 {
        geo.radii
    } else {
        DVec3::splat(geo.max_radius())
    }
}
