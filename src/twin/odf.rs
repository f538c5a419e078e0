//! The CPU twin of shaders/shape/odf.wgsl: the box of the bounding ball (radius R, the largest
//! radius) that Sigg's vertex stage draws, and the ball Gumhold's quad is built on, with the
//! eye rule. The marcher's f64 form is [`crate::shape::odf::first_crossing`].
//!
//! The eye rule of a series glyph needs its scene's series; without them the twin takes a
//! series glyph as not holding the eye (the GPU and the reference test the series itself).

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::{Proxy, quadric_box};
use crate::scene::GlyphGeometry;
use crate::shape::Exact;
use crate::shape::odf::Odf;

pub struct Twin;

impl ShapeTwin for Twin {
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        if !ortho && Odf::of(geo, None).contains(eye) {
            return Proxy::Culled;
        }
        let r = geo.max_radius();
        let b = quadric_box(
            view_proj,
            geo.frame.x_axis * r,
            geo.frame.y_axis * r,
            geo.frame.z_axis * r,
            geo.centre,
        );
        if b.outside_frustum() {
            return Proxy::Culled;
        }
        match b.bbox {
            Some(bbox) => Proxy::Box(bbox),
            None if b.r4dr4 < 0.0 => Proxy::Culled,
            None => Proxy::Viewport,
        }
    }

    /// The bounding ball: `shape_of`'s scale R times its bound 1.
    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        (ortho || !Odf::of(geo, None).contains(eye)).then_some(DVec3::splat(geo.max_radius()))
    }
}
