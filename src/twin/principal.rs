//! The CPU twin of shaders/shape/principal.wgsl: a bar's or a head's eye rule and the screen
//! box and bounding ellipsoid of the cylinder that holds both (the cylinder kind's).

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::Proxy;
use crate::scene::GlyphGeometry;
use crate::shape::principal::HEAD;

pub struct Twin;

/// `shape_contains` at the eye.
fn eye_inside(geo: &GlyphGeometry, eye: DVec3) -> bool {
    let p = (geo.frame.transpose() * (eye - geo.centre)) / geo.radii;
    let r = if geo.params[0] == HEAD {
        0.5 * (1.0 - p.x)
    } else {
        1.0
    };
    p.x.abs() <= 1.0 && p.y * p.y + p.z * p.z <= r * r
}

impl ShapeTwin for Twin {
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        if !ortho && eye_inside(geo, eye) {
            return Proxy::Culled;
        }
        // The cylinder's box, with the eye test done (the eye outside the head may be inside
        // its cylinder).
        super::cylinder::Twin.sigg_proxy(view_proj, geo, eye, true)
    }

    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        (ortho || !eye_inside(geo, eye))
            .then(|| geo.radii * DVec3::new(3f64.sqrt(), 1.5f64.sqrt(), 1.5f64.sqrt()))
    }
}
