//! Superquadric glyphs as a user renders them (`render --glyph superquadric --reference-check`)
//! on the scenes issue 16 names — the demo grid whole and close, an orthographic view, and two
//! indefinite stress fields (VTK's point load, Schultz–Kindlmann's shapes with a non-convex
//! search, and the FEM beam) — held to the release bounds against the exact f64 reference:
//! coverage ≤ 1e-4, id ≤ 5e-4, depth p99 ≤ 1e-4 of the radius, normal p99 ≤ 0.5°.

use crate::cli::{json, stderr, tg};

struct Bounds {
    coverage: f64,
    id: f64,
    depth: f64,
    normal_deg: f64,
}

const RELEASE: Bounds = Bounds {
    coverage: 1e-4,
    id: 5e-4,
    depth: 1e-4,
    normal_deg: 0.5,
};

/// `render`'s default path for `method` (Gumhold's: splats from the compute prepass), or
/// `preset`.
fn check(scene: &[&str], method: &str, preset: Option<&str>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sq.png");
    let mut args = vec!["render"];
    args.extend_from_slice(scene);
    if let Some(p) = preset {
        args.extend_from_slice(&["--preset", p]);
    }
    args.extend_from_slice(&[
        "--glyph",
        "superquadric",
        "--method",
        method,
        "--size",
        "320x240",
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--reference-check",
        "-q",
    ]);
    let r = tg(&args);
    assert!(r.status.success(), "{args:?}: {}", stderr(&r));
    let j = json(&r);
    let name = format!("{scene:?} {method} {preset:?}");
    assert_eq!(j["glyph"], "superquadric", "{name}");
    assert!(j["covered_pixels"].as_u64().unwrap() > 2000, "{name}: {j}");
    let v = |k: &str| j[k].as_f64().unwrap_or(f64::NAN);
    for (key, bound) in [
        ("coverage_mismatch", RELEASE.coverage),
        ("id_mismatch", RELEASE.id),
        ("depth_err_rel_p99", RELEASE.depth),
        ("normal_err_deg_p99", RELEASE.normal_deg),
    ] {
        assert!(v(key) <= bound, "{name}: {key} {} > {bound}", v(key));
    }
}

/// Every scene with both ray casters meets the release bounds (orthographic included: Gumhold's
/// solids form that ray from the fragment's position, not from the interpolated quad point),
/// Gumhold's both as `render` draws by default (splats) and with every glyph drawn.
#[test]
fn superquadrics_meet_the_release_bounds() {
    if crate::check::gpu().is_none() {
        return;
    }
    let scenes: [&[&str]; 5] = [
        &["--demo", "grid40"],
        &["--demo", "grid40", "--zoom", "4"],
        &["--demo", "grid40", "--ortho"],
        &["tests/data/stress/pointload.vti"],
        &["tests/data/stress/beam.vtu"],
    ];
    for scene in scenes {
        check(scene, "sigg", None);
        check(scene, "gumhold", None);
        check(scene, "gumhold", Some("baseline"));
    }
}

/// γ = 0 is the ellipsoid: under one camera the reference draws the same glyph in every pixel
/// but rim ties; γ = 3 draws boxier glyphs (more pixels); and the tessellated superquadrics at
/// Teem's resolution are further from the reference than the ray casters.
#[test]
fn sharpness_zero_is_the_ellipsoid_and_meshes_trail() {
    use tensorglyph::camera::{Camera, Framing};
    use tensorglyph::glyph::superquadric::Sharpness;
    use tensorglyph::glyph::{GlyphStyle, derive_glyphs};
    use tensorglyph::metrics::compare;
    use tensorglyph::reference::ReferenceScene;
    use tensorglyph::request::{FrameRequest, GlyphKind, Method};
    use tensorglyph::scene::Scene;
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let field = tensorglyph::field::synthetic::grid(6);
    let set = derive_glyphs(&field, &tensorglyph::progress::Silent);
    let spacing = tensorglyph::staging::field_spacing(&field);
    let style = |gamma| {
        GlyphStyle {
            sharpness: Sharpness {
                gamma,
                ..Sharpness::default()
            },
            ..GlyphStyle::default()
        }
        .resolve(&set, spacing.clone())
    };
    let ellipsoids = Scene::build(&set, &style(3.0), GlyphKind::Ellipsoid);
    let camera = Camera::frame(
        &Framing::default(),
        ellipsoids.centre,
        ellipsoids.radius,
        320,
        240,
    );
    let req = |method| FrameRequest {
        aux: true,
        ..FrameRequest::new(method)
    };
    let reference =
        |scene: &Scene| ReferenceScene::new(scene, &camera).render(&req(Method::Reference));
    let e = reference(&ellipsoids);
    let round = Scene::build(&set, &style(0.0), GlyphKind::Superquadric);
    let r = reference(&round);
    let differ = e.ids.iter().zip(&r.ids).filter(|(a, b)| a != b).count();
    assert!(
        differ <= 3,
        "{differ} pixels differ between γ = 0 and ellipsoids"
    );
    let sharp = Scene::build(&set, &style(3.0), GlyphKind::Superquadric);
    let s = reference(&sharp);
    assert!(
        s.covered_pixels() > r.covered_pixels() + 100,
        "{} vs {}",
        s.covered_pixels(),
        r.covered_pixels()
    );
    let accuracy = |method| {
        let f = gpu.render(&sharp, &camera, &req(method)).unwrap();
        compare(&f, &s, &sharp)
    };
    let sigg = accuracy(Method::Sigg);
    // mesh:1 is below Teem's default resolution (20 × 10 steps), mesh:2 above it.
    for level in [1, 2] {
        let mesh = accuracy(Method::Mesh(level));
        assert!(
            sigg.depth_err_rel_p99 * 10.0 < mesh.depth_err_rel_p99
                && sigg.normal_err_deg_p99 < mesh.normal_err_deg_p99,
            "sigg {sigg:?} vs mesh:{level} {mesh:?}"
        );
    }
}
