//! Case 10: degenerate tensors (zero, low rank, repeated eigenvalues, NaN, Inf, extreme
//! magnitudes) as the glyph builder makes them, and raw degenerate instances.

use glam::{DMat3, DQuat, DVec3};

use super::probe::{Probe, look, oblique, probe, spec};
use crate::scene::{GlyphSpec, Scene};

/// A tensor's glyph as users would get it without a min-radius clamp: eigen frame from the
/// project's solver (`tensor::eigen`), radii |λ| normalised by the largest |λ| (so 10³⁰ and 10⁻³⁰ both become unit
/// glyphs), `None` (absent) for non-finite or all-zero tensors.
pub fn glyph_from_tensor(t: &[f64; 9], centre: DVec3, color: [u8; 4]) -> Option<GlyphSpec> {
    let e = symmetric_eigen(t)?;
    let scale = e.values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut frame = DMat3::from_cols(
        DVec3::from(e.vectors[0]),
        DVec3::from(e.vectors[1]),
        DVec3::from(e.vectors[2]),
    );
    if frame.determinant() < 0.0 {
        frame.z_axis = -frame.z_axis;
    }
    Some(GlyphSpec {
        centre,
        rotation: DQuat::from_mat3(&frame).normalize(),
        radii: DVec3::from(e.values.map(|v| v.abs() / scale)),
        color,
    })
}

/// `tensor::eigen::symmetric_eigen` (the production Jacobi solver), `None` for non-finite input.
pub fn symmetric_eigen(t: &[f64; 9]) -> Option<Eigen> {
    if t.iter().any(|x| !x.is_finite()) {
        return None;
    }
    Some(crate::tensor::eigen::symmetric_eigen(t))
}

pub use crate::tensor::eigen::Eigen;

/// The degenerate tensors of case 10, by name.
pub fn degenerate_tensors() -> Vec<(&'static str, [f64; 9])> {
    let r = DMat3::from_quat(oblique());
    let rot = |d: [f64; 3]| {
        let m = r * DMat3::from_diagonal(DVec3::from(d)) * r.transpose();
        m.transpose().to_cols_array()
    };
    vec![
        ("zero", [0.0; 9]),
        ("rank 1", rot([1.0, 0.0, 0.0])),
        ("rank 2", rot([1.0, 0.6, 0.0])),
        ("repeated λ2=λ3", rot([1.0, 0.5, 0.5])),
        ("isotropic", rot([0.7, 0.7, 0.7])),
        ("negative definite", rot([-1.0, -0.6, -0.3])),
        ("indefinite", rot([1.0, -0.6, 0.3])),
        ("NaN entry", {
            let mut t = rot([1.0, 0.6, 0.3]);
            t[4] = f64::NAN;
            t
        }),
        ("Inf entry", {
            let mut t = rot([1.0, 0.6, 0.3]);
            t[0] = f64::INFINITY;
            t
        }),
        ("magnitude 1e30", rot([1e30, 0.6e30, 0.3e30])),
        ("magnitude 1e-30", rot([1e-30, 0.6e-30, 0.3e-30])),
    ]
}

/// Case 10 on the GPU: each degenerate tensor as glyphs built with [`glyph_from_tensor`], and
/// the same raw instances with zero / NaN radii fed straight to the renderers (what a caller
/// bypassing the CPU checks would upload).
pub fn degenerate(quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    let list = degenerate_tensors();
    for (k, (name, t)) in list.iter().enumerate() {
        if quick && !matches!(*name, "zero" | "rank 1" | "NaN entry") {
            continue;
        }
        // The tensor's glyph next to a healthy reference glyph (so the scene is never empty).
        let mut specs = vec![spec(
            DVec3::new(-1.2, 0.0, 0.0),
            oblique(),
            DVec3::new(0.5, 0.35, 0.25),
            [120, 120, 120, 255],
        )];
        let built = glyph_from_tensor(t, DVec3::new(1.0, 0.0, 0.0), [230, 150, 40, 255]);
        specs.extend(built);
        let scene = Scene::from_specs(&specs);
        let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
        let cam = look(&scene, scene.centre - dir * 6.0, scene.centre, 40.0);
        let mut p = probe("10-degenerate", "tensor", k as f64, scene, cam);
        p.label = if built.is_some() {
            (*name).into()
        } else {
            format!("{name} (absent)")
        };
        out.push(p);
    }
    // Raw degenerate instances: radii 0, NaN, Inf, 1e-30 in f32.
    let raw: [(&str, [f32; 3]); 5] = [
        ("raw radii 0,0,0", [0.0; 3]),
        ("raw radii 1,0,0", [1.0, 0.0, 0.0]),
        ("raw radii 1,1,0", [1.0, 1.0, 0.0]),
        ("raw radii NaN", [f32::NAN, 0.5, 0.5]),
        ("raw radii 1e-30", [1e-30, 1e-30, 1e-30]),
    ];
    for (k, (name, radii)) in raw.into_iter().enumerate() {
        if quick && k > 1 {
            continue;
        }
        let good = spec(
            DVec3::new(-1.2, 0.0, 0.0),
            oblique(),
            DVec3::new(0.5, 0.35, 0.25),
            [120, 120, 120, 255],
        );
        let mut scene = Scene::from_specs(&[
            good,
            spec(
                DVec3::new(1.0, 0.0, 0.0),
                oblique(),
                DVec3::ONE,
                [230, 150, 40, 255],
            ),
        ]);
        scene.instances[1].radii = radii;
        let scene = Scene::from_instances(scene.origin, scene.instances);
        let mut scene = scene;
        // Frame the healthy part: a NaN radius must not poison the bounds.
        scene.centre = scene.origin;
        scene.radius = 2.0;
        let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
        let cam = look(&scene, scene.centre - dir * 6.0, scene.centre, 40.0);
        let mut p = probe(
            "10-degenerate",
            "tensor",
            (list.len() + k) as f64,
            scene,
            cam,
        );
        p.label = name.into();
        out.push(p);
    }
    out
}
