//! The checks every GPU ray caster must pass against the exact reference on the shared scenes
//! (scenes.rs), written once as functions of the method. `ray_caster_cases!(method)` makes each a
//! `#[test]` of the file that calls it (tests/gpu_vs_reference.rs for Gumhold's method,
//! tests/gpu_sigg.rs for Sigg's); what only one method has (its proxy's shape, its own hard
//! cases) stays in that file.

use super::scenes::{self, framed};
use super::{assert_tight, check, check_tight};
use tensorglyph::camera::Framing;
use tensorglyph::request::{GlyphKind, Method};
use tensorglyph::scene::Scene;

/// One glyph framed by the default camera, held to the tight bounds.
fn framed_tight(name: &str, scene: &Scene, method: Method) {
    let cam = framed(scene, Framing::default());
    check_tight(name, scene, &cam, method, GlyphKind::Ellipsoid);
}

pub fn sphere(method: Method) {
    framed_tight("sphere", &scenes::sphere(), method);
}

pub fn rotated_cigar(method: Method) {
    framed_tight("cigar", &scenes::cigar(), method);
}

/// 1 : 1 : 0.01 seen obliquely: the normal varies fastest near the rim.
pub fn thin_pancake(method: Method) {
    framed_tight("pancake", &scenes::pancake(), method);
}

/// Two glyphs cutting each other: with depth correction the intersection curve is where the
/// reference has it; without, each proxy's own depth (Gumhold's quad, Sigg's box at its centre's
/// depth) decides who is in front, and the curve moves or is lost.
pub fn intersecting_glyphs_need_depth_correction(method: Method) {
    let scene = scenes::intersecting();
    let cam = framed(&scene, Framing::default());
    let Some(with) = check(
        "intersecting",
        &scene,
        &cam,
        method,
        GlyphKind::Ellipsoid,
        true,
    ) else {
        return;
    };
    assert_tight("intersecting", &with);
    let without = check(
        "intersecting flat",
        &scene,
        &cam,
        method,
        GlyphKind::Ellipsoid,
        false,
    )
    .unwrap();
    assert!(
        without.id_mismatch > 10.0 * with.id_mismatch.max(1e-4),
        "depth correction should matter: {with:?} vs {without:?}"
    );
}

/// A 100° field of view with the glyph near the image corner: strong perspective distortion,
/// where a proxy built as if the projection were orthographic would clip the silhouette.
pub fn glyph_in_the_corner_of_a_wide_view(method: Method) {
    let (scene, cam) = scenes::corner_of_a_wide_view();
    check_tight("corner", &scene, &cam, method, GlyphKind::Ellipsoid);
}

pub fn orthographic_view(method: Method) {
    let (scene, cam) = scenes::ortho_intersecting();
    check_tight("ortho", &scene, &cam, method, GlyphKind::Ellipsoid);
}

pub fn orthographic_view_along_an_eigenvector(method: Method) {
    let (scene, cam) = scenes::ortho_along_an_eigenvector();
    check_tight("ortho axis", &scene, &cam, method, GlyphKind::Ellipsoid);
}

/// Cap rims are creases: a pixel centre within f32 rounding of the rim may pick the cap or the
/// side (the normal jumps 90°), so the tight bounds hold the p99 of the normal, not its max.
pub fn cylinders_and_capsules_side_on_end_on_and_oblique(method: Method) {
    for (glyph, name, scene, cam) in scenes::solid_views() {
        check_tight(name, &scene, &cam, method, glyph);
    }
}

/// The eye just outside the capsule's +x ball, which fills most of the view.
pub fn eye_near_a_capsule_end(method: Method) {
    let (scene, cam) = scenes::near_a_cap();
    check_tight("near end", &scene, &cam, method, GlyphKind::Capsule);
}

/// The eye 5 % of the half-length above a cylinder's cap, which fills most of the view.
pub fn eye_near_a_cylinder_cap(method: Method) {
    let (scene, cam) = scenes::near_a_cap();
    check_tight("near cap", &scene, &cam, method, GlyphKind::Cylinder);
}

/// Every function above as a `#[test]` of the calling file, for `method`. (Every test file
/// compiles this module; only the ray casters' call the macro.)
#[allow(unused_macros)]
macro_rules! ray_caster_cases {
    ($method:expr) => {
        $crate::common::cases::ray_caster_cases!(
            $method;
            sphere,
            rotated_cigar,
            thin_pancake,
            intersecting_glyphs_need_depth_correction,
            glyph_in_the_corner_of_a_wide_view,
            orthographic_view,
            orthographic_view_along_an_eigenvector,
            cylinders_and_capsules_side_on_end_on_and_oblique,
            eye_near_a_capsule_end,
            eye_near_a_cylinder_cap
        );
    };
    ($method:expr; $($case:ident),+) => {
        $(
            #[test]
            fn $case() {
                $crate::common::cases::$case($method);
            }
        )+
    };
}
#[allow(unused_imports)]
pub(crate) use ray_caster_cases;
