//! The fast subset of `tensorglyph stability` as regression tests: no method shows NaN, cracks
//! or garbage in any case, and the exact impostors (Gumhold, Sigg) pass every case except the
//! documented inherent limits (rows say which, and are at worst `degraded`).

use tensorglyph::request::{GlyphKind, Method, Preset};
use tensorglyph::stability::{self, Options, Status};

fn show(rows: &[stability::Row]) -> String {
    rows.iter()
        .map(|r| {
            format!(
                "{} {} {} {} {}: {}",
                r.case, r.label, r.method, r.glyph, r.status, r.reason
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn quick_suite_has_no_failures() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let opts = Options {
        methods: vec![Method::Gumhold, Method::Sigg, Method::Mesh(2), Method::Box],
        glyphs: GlyphKind::VALUES.to_vec(),
        quick: true,
        cases: Vec::new(),
    };
    let rows = stability::run(Some(&gpu), &opts, |_| {});
    assert!(rows.len() > 100, "{} rows", rows.len());
    let failed: Vec<_> = rows
        .iter()
        .filter(|r| r.status == Status::Fail)
        .cloned()
        .collect();
    assert!(failed.is_empty(), "failures:\n{}", show(&failed));
    for r in &rows {
        for k in ["nan_px", "garbage_px", "crack_px"] {
            assert_eq!(
                r.metrics.get(k).copied().unwrap_or(0.0),
                0.0,
                "{k}: {}",
                show(std::slice::from_ref(r))
            );
        }
    }
    // Gumhold: pass, or degraded only under a documented limit.
    let bad: Vec<_> = rows
        .iter()
        .filter(|r| {
            r.method == "gumhold"
                && r.status != Status::Pass
                && !r.reason.contains("documented limit")
        })
        .cloned()
        .collect();
    assert!(
        bad.is_empty(),
        "gumhold outside its documented limits:\n{}",
        show(&bad)
    );
}

/// Issue 37's end: case 2's sweeps of crossing pancakes (k = 1 … 10⁸, perspective and
/// orthographic) pass for both ray casters with no documented limit (k = 10⁷ used to differ from
/// the reference, whose discriminant cancelled there), and the `box` baseline of ODF cigars
/// keeps every box whole (its far corners were clipped: a crack at k = 10).
#[test]
fn thin_glyphs_pass_without_limits() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let run = |methods: Vec<Method>, glyphs: Vec<GlyphKind>, case: &str| {
        let opts = Options {
            methods,
            glyphs,
            quick: false,
            cases: vec![case.to_string()],
        };
        stability::run(Some(&gpu), &opts, |_| {})
    };
    let rows = run(
        vec![Method::Gumhold, Method::Sigg],
        vec![GlyphKind::Ellipsoid, GlyphKind::Cylinder],
        "2-anisotropy-pancake-pair",
    );
    assert!(rows.len() >= 72, "{} rows", rows.len());
    let bad: Vec<_> = rows
        .iter()
        .filter(|r| r.metrics.contains_key("crack_px") && r.status != Status::Pass)
        .cloned()
        .collect();
    assert!(bad.is_empty(), "not passing:\n{}", show(&bad));
    let rows = run(
        vec![Method::Box],
        vec![GlyphKind::Odf],
        "2-anisotropy-cigar",
    );
    let bad: Vec<_> = rows
        .iter()
        .filter(|r| {
            r.method == "box"
                && (r.status == Status::Fail || r.metrics.get("crack_px") != Some(&0.0))
        })
        .cloned()
        .collect();
    assert!(bad.is_empty(), "boxes:\n{}", show(&bad));
}

/// Issue 55: case 15's random lattices of needles, discs and a mixed field (k = 1e3 … 1e7,
/// neighbours passing through each other), near, far and orthographic, pass through every
/// preset of both ray casters and every kind, held to the bounds (coverage and ids
/// 1e-4, depth p99 1e-5 radii, normals 0.05°) with no documented limit. Before, the default
/// preset's splats kept 6 of 28 pixels of k = 1e3 needles seen from afar and lost whole discs
/// at 1e5 (coverage 4e-2, ids 0.16); the reference hit k = 1e7 arrowheads beside their edges;
/// the triangle proxy's capsule rays slid far along nearly crossing rays and drew a false hit.
#[test]
fn lattices_pass_through_every_preset() {
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let opts = Options {
        methods: vec![Method::Gumhold, Method::Sigg],
        glyphs: GlyphKind::VALUES.to_vec(),
        quick: false,
        cases: vec!["15-lattice".to_string()],
    };
    let rows = stability::run(Some(&gpu), &opts, |_| {});
    let bad: Vec<_> = rows
        .iter()
        .filter(|r| r.case.starts_with("15-lattice") && r.status != Status::Pass)
        .cloned()
        .collect();
    assert!(bad.is_empty(), "not passing:\n{}", show(&bad));
    // Every preset was drawn: the default's splats among them.
    for preset in &Preset::VALUES[1..] {
        let label = format!("gumhold+{preset}");
        assert!(
            rows.iter()
                .any(|r| r.method == label && r.glyph == "ellipsoid"),
            "no {label} rows"
        );
    }
    assert!(
        rows.iter()
            .any(|r| r.method == "sigg" && r.glyph == "principal")
    );
}

#[test]
fn cpu_probes() {
    let mut rows = stability::cpu::mu_form(true);
    rows.extend(stability::cpu::degeneracy(true));
    rows.extend(stability::cpu::eigensolver(true));
    let failed: Vec<_> = rows
        .iter()
        .filter(|r| r.status == Status::Fail)
        .cloned()
        .collect();
    assert!(failed.is_empty(), "{}", show(&failed));
    // The κ form the shader uses stays accurate at 10⁶ glyph sizes; the µ form does not.
    let at = |m: &str| {
        rows.iter()
            .find(|r| r.case == "1-distance-mu" && r.value == 1e6 && r.method.contains(m))
            .map(|r| r.metrics["normal_err_deg_p99"])
            .unwrap()
    };
    assert!(
        at("κ") < 0.1 && at("µ") > 1.0,
        "κ {} µ {}",
        at("κ"),
        at("µ")
    );
}

#[test]
fn degenerate_tensors_give_sane_glyphs_or_none() {
    use glam::DVec3;
    for (name, t) in stability::cases::degenerate_tensors() {
        let g = stability::cases::glyph_from_tensor(&t, DVec3::ZERO, [0; 4]);
        match name {
            "zero" | "NaN entry" | "Inf entry" => assert!(g.is_none(), "{name}"),
            _ => {
                let g = g.unwrap_or_else(|| panic!("{name}: no glyph"));
                assert!(
                    g.radii.is_finite() && g.rotation.is_finite(),
                    "{name}: {g:?}"
                );
                assert!((g.radii.max_element() - 1.0).abs() < 1e-12, "{name}: {g:?}");
            }
        }
    }
    // Zero or NaN radii are not drawable; 1e-30 of a unit glyph is (ratio 1).
    use tensorglyph::shape::rules::drawable_radii;
    assert!(!drawable_radii([0.0; 3]));
    assert!(!drawable_radii([1.0, 1.0, 0.0]));
    assert!(!drawable_radii([f32::NAN, 1.0, 1.0]));
    assert!(!drawable_radii([1.0, 1e-8, 1.0]));
    assert!(drawable_radii([1e-30; 3]));
    assert!(drawable_radii([1.0, 1e-6, 1e-6]));
}
