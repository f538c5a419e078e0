//! The CPU twin of shaders/shape/superquadric.wgsl: the kind's screen box (the hull of its local
//! unit box's projected corners, clipped to its bounding ellipsoid's eq. 5 box) and the ball
//! whose quad Gumhold's method draws. The root finder's twin is
//! [`crate::twin::superquadric_finder`].

use glam::{DMat4, DVec2, DVec3, DVec4};

use super::ShapeTwin;
use super::screen_box::{NdcBox, Proxy, quadric_box};
use crate::glyph::superquadric::{BOUND_MARGIN, bounding_scale};
use crate::scene::GlyphGeometry;
use crate::shape::superquadric::Superquadric;

pub struct Twin;

impl ShapeTwin for Twin {
    /// The hull of the local unit box's projected corners, clipped to the box of the bounding
    /// ellipsoid s·radii.
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        if !ortho && Superquadric::of(geo).contains(eye) {
            return Proxy::Culled;
        }
        let axes = [
            geo.frame.x_axis * geo.radii.x,
            geo.frame.y_axis * geo.radii.y,
            geo.frame.z_axis * geo.radii.z,
        ];
        let clip = |p: DVec3, w: f64| *view_proj * p.extend(w);
        let (mc, m_axes) = (clip(geo.centre, 1.0), axes.map(|a| clip(a, 0.0)));
        let planes: [fn(DVec4) -> f64; 6] = [
            |p| p.w + p.x,
            |p| p.w - p.x,
            |p| p.w + p.y,
            |p| p.w - p.y,
            |p| p.z,
            |p| p.w - p.z,
        ];
        if planes
            .iter()
            .any(|f| f(mc) + m_axes.iter().map(|&a| f(a).abs()).sum::<f64>() < 0.0)
        {
            return Proxy::Culled;
        }
        let corners: Vec<DVec4> = (0..8)
            .map(|k| {
                let s = |bit: usize| if k & bit != 0 { 1.0 } else { -1.0 };
                mc + m_axes[0] * s(1) + m_axes[1] * s(2) + m_axes[2] * s(4)
            })
            .filter(|p| p.w > 0.0)
            .collect();
        match corners.len() {
            0 => Proxy::Culled,
            8 => {
                let ndc = corners.iter().map(|p| DVec2::new(p.x, p.y) / p.w);
                let mut lo = ndc.clone().fold(DVec2::splat(f64::INFINITY), DVec2::min);
                let mut hi = ndc.fold(DVec2::splat(f64::NEG_INFINITY), DVec2::max);
                let s = bounding_scale(geo.exponents.to_array()) * BOUND_MARGIN;
                let [u, v, w] = axes.map(|a| a * s);
                if let Some(b) = quadric_box(view_proj, u, v, w, geo.centre).bbox {
                    (lo, hi) = (lo.max(b.lo), hi.min(b.hi));
                }
                Proxy::Box(NdcBox { lo, hi })
            }
            _ => Proxy::Viewport,
        }
    }

    /// The smallest ball about the centre holding the solid (`sq_bound`).
    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        (ortho || !Superquadric::of(geo).contains(eye))
            .then(|| geo.radii * (bounding_scale(geo.exponents.to_array()) * BOUND_MARGIN))
    }
}
