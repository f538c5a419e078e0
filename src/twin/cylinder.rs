//! The CPU twin of shaders/shape/cylinder.wgsl: the capped cylinder's screen box (the union of
//! its end discs' eq. 5 boxes, sigg-quadric.md §7), the bounding ellipsoid whose quad Gumhold's
//! method draws (√3 along the axis, √(3/2) across, cylinder-capsule.md §5) and its eye rule.

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::{Proxy, QuadricBox, cylinder_boxes};
use crate::scene::GlyphGeometry;

pub struct Twin;

/// `shape_contains`: |x| ≤ 1 and y² + z² ≤ 1 in parameter space.
fn eye_inside(geo: &GlyphGeometry, eye: DVec3) -> bool {
    let e_t = (geo.frame.transpose() * (eye - geo.centre)) / geo.radii;
    e_t.x.abs() <= 1.0 && e_t.y * e_t.y + e_t.z * e_t.z <= 1.0
}

impl ShapeTwin for Twin {
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        if !ortho && eye_inside(geo, eye) {
            return Proxy::Culled;
        }
        let (caps, union) = cylinder_boxes(
            view_proj,
            geo.frame.y_axis * geo.radii.y,
            geo.frame.z_axis * geo.radii.z,
            geo.frame.x_axis * geo.radii.x,
            geo.centre,
        );
        // The hull of the discs is outside a plane iff both discs are.
        if (0..6).any(|k| caps[0].reach[k].max(caps[1].reach[k]) < 0.0) {
            return Proxy::Culled;
        }
        let behind = |q: &QuadricBox| q.r4dr4 < 0.0 && q.w_centre <= 0.0;
        match union {
            Some(b) => Proxy::Box(b),
            None if behind(&caps[0]) && behind(&caps[1]) => Proxy::Culled,
            None => Proxy::Viewport,
        }
    }

    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        (ortho || !eye_inside(geo, eye))
            .then(|| geo.radii * DVec3::new(3f64.sqrt(), 1.5f64.sqrt(), 1.5f64.sqrt()))
    }
}
