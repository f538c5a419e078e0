//! The CPU twin of the vertex stage of shaders/method/sigg.wgsl: the eye test and the kind's
//! screen box (`shape_box`, twinned per kind in `src/twin/<kind>.rs`), giving the proxy Sigg's
//! method draws for a glyph. The GPU tests use it to predict how many fragments a glyph's box
//! shades.

use glam::{DMat4, DVec3};

use crate::camera::Camera;
use crate::scene::{GlyphGeometry, GlyphKind, Scene};
use crate::twin::screen_box::Proxy;

/// The proxy sigg.wgsl's vertex stage draws for one glyph of `kind` (`eye` and `view_proj`
/// relative to the scene origin, like the glyph's centre).
pub fn glyph_proxy(
    view_proj: &DMat4,
    geo: &GlyphGeometry,
    eye: DVec3,
    ortho: bool,
    kind: GlyphKind,
) -> Proxy {
    crate::twin::of(kind).sigg_proxy(view_proj, geo, eye, ortho)
}

/// [`glyph_proxy`] for instance `i` of `scene` seen by `camera`, its box widened by the margin
/// the vertex stage adds ([`PROXY_MARGIN_PX`](crate::shape::rules::PROXY_MARGIN_PX)).
pub fn scene_proxy(scene: &Scene, camera: &Camera, i: usize) -> Proxy {
    let view_proj = camera.projection_matrix() * camera.view(scene.origin);
    let proxy = glyph_proxy(
        &view_proj,
        &scene.geometry(i),
        camera.eye - scene.origin,
        camera.is_ortho(),
        scene.kind,
    );
    match proxy {
        Proxy::Box(b) => Proxy::Box(b.widened(
            crate::shape::rules::PROXY_MARGIN_PX,
            camera.width,
            camera.height,
        )),
        p => p,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proxies_box_cross_and_cull() {
        use glam::DMat3;
        // 30° vertical field of view at 3:2, eye at the origin looking down −z.
        let mut cam = Camera::frame(&Default::default(), DVec3::ZERO, 1.0, 300, 200);
        cam.eye = DVec3::ZERO;
        cam.target = DVec3::NEG_Z;
        cam.up = DVec3::Y;
        cam.near = 0.1;
        cam.far = 100.0;
        let vp = cam.projection_matrix() * cam.view(DVec3::ZERO);
        // Superquadric exponents of the sphere (the other glyphs ignore them).
        let sphere = |c: DVec3| GlyphGeometry {
            centre: c,
            frame: DMat3::IDENTITY,
            radii: DVec3::splat(0.5),
            exponents: DVec3::ONE,
            params: [0; 2],
        };
        let proxy = |c: DVec3, kind| glyph_proxy(&vp, &sphere(c), DVec3::ZERO, false, kind);
        for &kind in GlyphKind::VALUES {
            // In front: a box around the projected centre.
            let Proxy::Box(b) = proxy(DVec3::new(0.0, 0.0, -5.0), kind) else {
                panic!("{kind}: no box in front");
            };
            assert!(b.lo.x < 0.0 && b.hi.x > 0.0 && b.lo.y < 0.0 && b.hi.y > 0.0);
            // Crossing the camera plane, in view: the viewport.
            assert_eq!(proxy(DVec3::new(0.55, 0.0, -0.2), kind), Proxy::Viewport);
            // Crossing it beside the eye, outside the left frustum plane; behind; around the eye.
            assert_eq!(proxy(DVec3::new(-2.0, 0.0, 0.1), kind), Proxy::Culled);
            assert_eq!(proxy(DVec3::new(0.0, 0.0, 5.0), kind), Proxy::Culled);
            assert_eq!(proxy(DVec3::new(0.1, 0.0, 0.0), kind), Proxy::Culled);
            // Beyond the far plane.
            assert_eq!(proxy(DVec3::new(0.0, 0.0, -101.0), kind), Proxy::Culled);
        }
    }
}
