//! The checks both GPU ray casters (Gumhold's quads and Sigg's screen boxes) must pass against
//! the exact f64 reference on the hand-made scenes of scenes.rs, where ray-cast impostors tend
//! to fail: each test runs every method of [`RAY_CASTERS`]. What only one method has (its
//! proxy's shape, its own hard cases) is in gumhold.rs and sigg.rs; every kind on a grid, by
//! every method, is kinds.rs.

use crate::check::{assert_tight, check, check_tight};
use crate::scenes::{self, framed};
use tensorglyph::camera::Framing;
use tensorglyph::request::{GlyphKind, Method};
use tensorglyph::scene::Scene;

/// The methods that ray cast the exact surface per pixel.
const RAY_CASTERS: [Method; 2] = [Method::Gumhold, Method::Sigg];

/// One glyph framed by the default camera, held to the tight bounds by every ray caster.
fn framed_tight(name: &str, scene: &Scene) {
    let cam = framed(scene, Framing::default());
    for method in RAY_CASTERS {
        check_tight(name, scene, &cam, method, GlyphKind::Ellipsoid);
    }
}

#[test]
fn sphere() {
    framed_tight("sphere", &scenes::sphere());
}

#[test]
fn rotated_cigar() {
    framed_tight("cigar", &scenes::cigar());
}

/// 1 : 1 : 0.01 seen obliquely: the normal varies fastest near the rim.
#[test]
fn thin_pancake() {
    framed_tight("pancake", &scenes::pancake());
}

/// Two glyphs cutting each other: with depth correction the intersection curve is where the
/// reference has it; without, each proxy's own depth (Gumhold's quad, Sigg's box at its centre's
/// depth) decides who is in front, and the curve moves or is lost.
#[test]
fn intersecting_glyphs_need_depth_correction() {
    let scene = scenes::intersecting();
    let cam = framed(&scene, Framing::default());
    for method in RAY_CASTERS {
        let name = format!("intersecting {method}");
        let Some(with) = check(&name, &scene, &cam, method, GlyphKind::Ellipsoid, true) else {
            return;
        };
        assert_tight(&name, &with);
        let without = check(
            &format!("{name} flat"),
            &scene,
            &cam,
            method,
            GlyphKind::Ellipsoid,
            false,
        )
        .unwrap();
        assert!(
            without.id_mismatch > 10.0 * with.id_mismatch.max(1e-4),
            "{name}: depth correction should matter: {with:?} vs {without:?}"
        );
    }
}

/// A 100° field of view with the glyph near the image corner: strong perspective distortion,
/// where a proxy built as if the projection were orthographic would clip the silhouette.
#[test]
fn glyph_in_the_corner_of_a_wide_view() {
    let (scene, cam) = scenes::corner_of_a_wide_view();
    for method in RAY_CASTERS {
        check_tight("corner", &scene, &cam, method, GlyphKind::Ellipsoid);
    }
}

#[test]
fn orthographic_view() {
    let (scene, cam) = scenes::ortho_intersecting();
    for method in RAY_CASTERS {
        check_tight("ortho", &scene, &cam, method, GlyphKind::Ellipsoid);
    }
}

#[test]
fn orthographic_view_along_an_eigenvector() {
    let (scene, cam) = scenes::ortho_along_an_eigenvector();
    for method in RAY_CASTERS {
        check_tight("ortho axis", &scene, &cam, method, GlyphKind::Ellipsoid);
    }
}

/// Cap rims are creases: a pixel centre within f32 rounding of the rim may pick the cap or the
/// side (the normal jumps 90°), so the tight bounds hold the p99 of the normal, not its max.
#[test]
fn cylinders_and_capsules_side_on_end_on_and_oblique() {
    for (glyph, name, scene, cam) in scenes::solid_views() {
        for method in RAY_CASTERS {
            check_tight(name, &scene, &cam, method, glyph);
        }
    }
}

/// The eye just outside the capsule's +x ball, which fills most of the view.
#[test]
fn eye_near_a_capsule_end() {
    let (scene, cam) = scenes::near_a_cap();
    for method in RAY_CASTERS {
        check_tight("near end", &scene, &cam, method, GlyphKind::Capsule);
    }
}

/// The eye 5 % of the half-length above a cylinder's cap, which fills most of the view.
#[test]
fn eye_near_a_cylinder_cap() {
    let (scene, cam) = scenes::near_a_cap();
    for method in RAY_CASTERS {
        check_tight("near cap", &scene, &cam, method, GlyphKind::Cylinder);
    }
}
