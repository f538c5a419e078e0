//! Gumhold's method on the GPU against the exact f64 reference, on small scenes chosen where
//! ray-cast impostors tend to fail (tests/common/scenes.rs; the checks, shared with Sigg's
//! method, in tests/common/cases.rs). Bounds are stated beside each check with their reason.

mod common;

use common::scenes;
use tensorglyph::request::{GlyphKind, Method};
use tensorglyph::twin::gumhold_ellipsoid::{ProxyShape, proxy_shape};

common::cases::ray_caster_cases!(Method::Gumhold);

#[test]
fn near_a_cap_the_proxy_is_the_near_plane() {
    // The eye is outside the solids (just beyond the capsule's +x ball, 5 % of the half-length
    // above the cylinder's cap) but inside their bounding ellipsoids: the quad would not hold
    // the silhouette, so the proxy becomes the near plane (eye_near_a_* check the pixels).
    let (scene, cam) = scenes::near_a_cap();
    for glyph in [GlyphKind::Capsule, GlyphKind::Cylinder] {
        assert_eq!(
            proxy_shape(&scene.drawn_as(glyph), &cam, 0),
            ProxyShape::Viewport,
            "{glyph:?}"
        );
    }
}
