//! Gumhold's method on the GPU against the exact f64 reference, on small scenes chosen where
//! ray-cast impostors tend to fail (tests/common/scenes.rs). Bounds are stated beside each
//! check with their reason.

mod common;

use common::assert_tight;
use common::scenes::{self, framed};
use tensorglyph::camera::{Camera, Framing};
use tensorglyph::metrics::Accuracy;
use tensorglyph::request::{GlyphKind, Method};
use tensorglyph::scene::Scene;

fn check(name: &str, scene: &Scene, camera: &Camera, glyph: GlyphKind) -> Option<Accuracy> {
    common::check(name, scene, camera, Method::Gumhold, glyph, true)
}

fn tight(name: &str, scene: &Scene, camera: &Camera, glyph: GlyphKind) {
    common::check_tight(name, scene, camera, Method::Gumhold, glyph);
}

#[test]
fn sphere() {
    let scene = scenes::sphere();
    let cam = framed(&scene, Framing::default());
    tight("sphere", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn rotated_cigar() {
    let scene = scenes::cigar();
    let cam = framed(&scene, Framing::default());
    tight("cigar", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn thin_pancake() {
    // 1 : 1 : 0.01 seen obliquely: the normal varies fastest near the rim.
    let scene = scenes::pancake();
    let cam = framed(&scene, Framing::default());
    tight("pancake", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn intersecting_glyphs_need_depth_correction() {
    let scene = scenes::intersecting();
    let cam = framed(&scene, Framing::default());
    let Some(with) = check("intersecting", &scene, &cam, GlyphKind::Ellipsoid) else {
        return;
    };
    assert_tight("intersecting", &with);
    let without = common::check(
        "intersecting flat",
        &scene,
        &cam,
        Method::Gumhold,
        GlyphKind::Ellipsoid,
        false,
    )
    .unwrap();
    // Without correction the quads' own depths decide who is in front: the curve moves.
    assert!(
        without.id_mismatch > 10.0 * with.id_mismatch.max(1e-4),
        "depth correction should matter: {with:?} vs {without:?}"
    );
}

#[test]
fn glyph_in_the_corner_of_a_wide_view() {
    // A 100° field of view with the glyph near the image corner: strong perspective distortion
    // of the quad, where an orthographic-style bounding box would clip the silhouette.
    let (scene, cam) = scenes::corner_of_a_wide_view();
    tight("corner", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn orthographic_view() {
    let (scene, cam) = scenes::ortho_intersecting();
    tight("ortho", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn orthographic_view_along_an_eigenvector() {
    let (scene, cam) = scenes::ortho_along_an_eigenvector();
    tight("ortho axis", &scene, &cam, GlyphKind::Ellipsoid);
}

#[test]
fn cylinders_and_capsules_side_on_end_on_and_oblique() {
    // Cap rims are creases: a pixel centre within f32 rounding of the rim may pick the cap or
    // the side (normal jumps 90°), hence max is not bounded, the p99 is.
    for (glyph, name, scene, cam) in scenes::solid_views() {
        tight(name, &scene, &cam, glyph);
    }
}

#[test]
fn eye_near_a_capsule_end() {
    // Outside the capsule (0.06 beyond the +x ball) but inside its bounding ellipsoid: the
    // proxy becomes the near plane, and the ball fills most of the view.
    let (scene, cam) = scenes::near_a_cap();
    assert_eq!(
        tensorglyph::twin::gumhold_ellipsoid::proxy_shape(&scene, &cam, 0, GlyphKind::Capsule),
        tensorglyph::twin::gumhold_ellipsoid::ProxyShape::Viewport
    );
    tight("near end", &scene, &cam, GlyphKind::Capsule);
}

#[test]
fn eye_near_a_cylinder_cap() {
    // The eye sits 5 % of the half-length above a cap, inside the bounding ellipsoid: the proxy
    // becomes the near plane and the cap fills most of the view.
    let (scene, cam) = scenes::near_a_cap();
    tight("near cap", &scene, &cam, GlyphKind::Cylinder);
}
