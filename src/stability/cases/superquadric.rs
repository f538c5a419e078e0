//! Cases 11, 12 and 13: superquadric glyphs — sharpness up to knife edges, the class
//! boundary where the symmetry axis swaps, and indefinite tensors.

use glam::{DQuat, DVec3};

use super::probe::{Probe, look, oblique, probe, spec, sweep};
use crate::glyph::superquadric::Sharpness;
use crate::scene::{GlyphKind, GlyphSpec, Scene};
use crate::shape::superquadric::superquadric_instance;

/// The kind these cases are about: the one `--sharpness` shapes.
fn sharp_kind() -> GlyphKind {
    *GlyphKind::VALUES
        .iter()
        .find(|k| k.caps().sharpness)
        .expect("a kind takes --sharpness")
}

/// Superquadric glyphs from signed eigenvalues along the columns of `rotation`, radii |λ| with
/// the stress default floor (0.2 of the largest, `--min-radius` for stress-like fields).
fn superquadric_scene(glyphs: &[(DVec3, DQuat, [f64; 3])], sharpness: Sharpness) -> Scene {
    let colors = [[220, 90, 70, 255], [80, 170, 90, 255], [70, 110, 220, 255]];
    let specs: Vec<GlyphSpec> = glyphs
        .iter()
        .enumerate()
        .map(|(k, &(centre, rotation, l))| {
            let m = l.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let radii = DVec3::from(l.map(|x| x.abs().max(0.2 * m)));
            spec(centre, rotation, radii, colors[k % colors.len()])
        })
        .collect();
    let scene = Scene::from_specs(&specs);
    let instances = scene
        .instances
        .iter()
        .zip(glyphs)
        .map(|(g, &(_, _, l))| superquadric_instance(g, l, sharpness))
        .collect();
    Scene::from_instances_as(scene.origin, instances, sharp_kind())
}

/// A superquadric case: `glyphs` side by side, seen obliquely in perspective.
fn superquadric_probe(
    case: &'static str,
    parameter: &'static str,
    value: f64,
    label: String,
    glyphs: &[(DVec3, DQuat, [f64; 3])],
    sharpness: Sharpness,
) -> Probe {
    let scene = superquadric_scene(glyphs, sharpness);
    let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
    let cam = look(
        &scene,
        scene.centre - dir * 4.0 * scene.radius,
        scene.centre,
        35.0,
    );
    let mut p = probe(case, parameter, value, scene, cam);
    p.label = label;
    p.only = Some(sharp_kind());
    p
}

/// Three glyphs in a row at `x = −2.2, 0, 2.2`, each turned its own way.
fn row_of(eigenvalues: [[f64; 3]; 3]) -> Vec<(DVec3, DQuat, [f64; 3])> {
    (0..3)
        .map(|k| {
            let x = 2.2 * (k as f64 - 1.0);
            let turn = DQuat::from_axis_angle(
                DVec3::new(0.4, 1.0 - 0.3 * k as f64, 0.2 * k as f64).normalize(),
                0.5 + 0.7 * k as f64,
            );
            (DVec3::new(x, 0.0, 0.0), turn * oblique(), eigenvalues[k])
        })
        .collect()
}

/// Case 11: superquadric sharpness γ from 0 (ellipsoids) to 15 (exponents down to 1e-30:
/// near-boxes and near-cylinders with knife edges), on a linear, an intermediate and a planar
/// tensor.
pub fn sharpness(quick: bool) -> Vec<Probe> {
    let glyphs = row_of([[1.0, 0.3, 0.25], [1.0, 0.6, 0.3], [1.0, 0.9, 0.2]]);
    sweep(quick, &[0.0, 1.0, 3.0, 6.0, 10.0, 15.0], &[3.0, 10.0])
        .into_iter()
        .map(|gamma| {
            let sharpness = Sharpness {
                gamma,
                ..Sharpness::default()
            };
            superquadric_probe(
                "11-sq-sharpness",
                "γ",
                gamma,
                format!("γ={gamma}"),
                &glyphs,
                sharpness,
            )
        })
        .collect()
}

/// Case 12: superquadrics across Kindlmann's class boundary cl = cp (λ = (1, 0.6 + δ, 0.4)),
/// where the symmetry axis swaps from e1 to e3: the shapes either side must meet.
pub fn class_boundary(quick: bool) -> Vec<Probe> {
    sweep(quick, &[-0.02, -1e-3, 0.0, 1e-3, 0.02], &[-1e-3, 0.0, 1e-3])
        .into_iter()
        .map(|d| {
            let l = [1.0, 0.6 + d, 0.4];
            superquadric_probe(
                "12-sq-class-boundary",
                "δ (cl = cp at 0)",
                d,
                format!("δ={d:e}"),
                &row_of([l, l, l]),
                Sharpness::default(),
            )
        })
        .collect()
}

/// The indefinite (and boundary) tensors of case 13, by name: Schultz–Kindlmann's pinched and
/// c ≠ β shapes, a zero eigenvalue, and λ2 on either side of 0 where the symmetry axis jumps.
pub fn indefinite_tensors() -> Vec<(&'static str, [f64; 3])> {
    vec![
        ("trace-free (1, 0, −1)", [1.0, 0.0, -1.0]),
        ("(1, 0, −0.5)", [1.0, 0.0, -0.5]),
        ("(0.5, 0, −1)", [0.5, 0.0, -1.0]),
        ("λ2 = +1e-3", [1.0, 1e-3, -1.0]),
        ("λ2 = −1e-3", [1.0, -1e-3, -1.0]),
        ("thorn (1, 1, −1)", [1.0, 1.0, -1.0]),
        ("thorn (1, −1, −1)", [1.0, -1.0, -1.0]),
        ("zone 5 (2, −0.6, −1.5)", [2.0, -0.6, -1.5]),
        ("λ3 = 0 (1, 0.5, 0)", [1.0, 0.5, 0.0]),
        ("λ1 = 0 (0, −0.5, −1)", [0.0, -0.5, -1.0]),
    ]
}

/// Case 13: indefinite tensors, each as a row of three differently turned glyphs.
pub fn indefinite(quick: bool) -> Vec<Probe> {
    indefinite_tensors()
        .into_iter()
        .enumerate()
        .filter(|(k, _)| !quick || matches!(k, 0 | 3 | 5))
        .map(|(k, (name, l))| {
            superquadric_probe(
                "13-sq-indefinite",
                "tensor",
                k as f64,
                name.into(),
                &row_of([l, l, l]),
                Sharpness::default(),
            )
        })
        .collect()
}
