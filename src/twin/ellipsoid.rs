//! The CPU twin of shaders/shape/ellipsoid.wgsl: the ellipsoid's screen box (eq. 5 with T's
//! columns r_i O_i) and its eye rule, as Sigg's vertex stage applies them. Gumhold's method
//! draws ellipsoids with their own exact quad ([`crate::twin::gumhold_ellipsoid`]).

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::{Proxy, ellipsoid_proxy};
use crate::scene::GlyphGeometry;
use crate::shape::rules::EYE_INSIDE_E2;

pub struct Twin;

impl ShapeTwin for Twin {
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        let e_t = (geo.frame.transpose() * (eye - geo.centre)) / geo.radii;
        // `!(E² > bound)` as in the shader: NaN counts as inside.
        let outside = e_t.length_squared() > EYE_INSIDE_E2;
        if !ortho && !outside {
            return Proxy::Culled;
        }
        ellipsoid_proxy(view_proj, geo, geo.radii)
    }

    /// The glyph's own ellipsoid.
    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        let e_t = (geo.frame.transpose() * (eye - geo.centre)) / geo.radii;
        (ortho || e_t.length_squared() > EYE_INSIDE_E2).then_some(geo.radii)
    }
}
