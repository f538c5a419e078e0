//! The GPU cases: each a small scene and camera per value of a swept parameter.

use glam::{DMat3, DQuat, DVec3};

use super::Row;
use crate::camera::{Camera, Projection};
use crate::glyph::superquadric::{Sharpness, pack_exponents, superquadric_shape};
use crate::request::GlyphKind;
use crate::scene::{GlyphInstance, GlyphSpec, Scene, superquadric_frame};

pub const W: u32 = 256;
pub const H: u32 = 192;

/// One scene and camera of a case.
#[derive(Debug, Clone)]
pub struct Probe {
    pub case: &'static str,
    pub parameter: &'static str,
    pub value: f64,
    pub label: String,
    pub scene: Scene,
    pub camera: Camera,
    pub depth_correction: bool,
    /// The one glyph this case is about (e.g. ellipsoid parameter space, superquadric
    /// exponents), or `None` for every glyph.
    pub only: Option<GlyphKind>,
}

fn probe(
    case: &'static str,
    parameter: &'static str,
    value: f64,
    scene: Scene,
    camera: Camera,
) -> Probe {
    Probe {
        case,
        parameter,
        value,
        label: format!("{value:e}"),
        scene,
        camera,
        depth_correction: true,
        only: None,
    }
}

fn spec(centre: DVec3, rotation: DQuat, radii: DVec3, color: [u8; 4]) -> GlyphSpec {
    GlyphSpec {
        centre,
        rotation,
        radii,
        color,
        glyph: 0,
    }
}

/// An oblique rotation, so no axis lines up with the view.
pub fn oblique() -> DQuat {
    DQuat::from_axis_angle(DVec3::new(0.3, -0.5, 0.8).normalize(), 1.1)
}

/// A camera of the probes' size from `eye` towards `target`, its depth planes fitted to the scene.
fn fitted(scene: &Scene, eye: DVec3, target: DVec3, up: DVec3, projection: Projection) -> Camera {
    let mut cam = Camera {
        eye,
        target,
        up,
        projection,
        near: 0.0,
        far: 0.0,
        width: W,
        height: H,
        crop: None,
    };
    cam.fit_depth_range(scene.centre, scene.radius);
    cam
}

/// A perspective camera looking from `eye` at `target` with depth planes fitted to the scene.
fn look(scene: &Scene, eye: DVec3, target: DVec3, fov_deg: f64) -> Camera {
    let fwd = (target - eye).normalize();
    let up = if fwd.cross(DVec3::Z).length() > 1e-3 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let fov_y = fov_deg.to_radians();
    fitted(scene, eye, target, up, Projection::Perspective { fov_y })
}

fn ortho(scene: &Scene, dir: DVec3, up: DVec3, height: f64) -> Camera {
    let eye = scene.centre - dir * 10.0 * scene.radius;
    let projection = Projection::Orthographic { height };
    fitted(scene, eye, scene.centre, up, projection)
}

fn sweep(quick: bool, full: &[f64], subset: &[f64]) -> Vec<f64> {
    if quick {
        subset.to_vec()
    } else {
        full.to_vec()
    }
}

/// Case 1: distance / glyph size from 10 to 10⁶, the field of view narrowed so the glyph keeps
/// its size on screen (what changes is precision only).
pub fn distance(quick: bool) -> Vec<Probe> {
    let radii = DVec3::new(1.0, 0.6, 0.35);
    let scene = Scene::from_specs(&[spec(DVec3::ZERO, oblique(), radii, [220, 120, 60, 255])]);
    let dir = DVec3::new(-1.0, 1.0, -0.7).normalize();
    sweep(quick, &[10.0, 100.0, 1e3, 1e4, 1e5, 1e6], &[10.0, 1e6])
        .into_iter()
        .map(|d| {
            let fov = 2.0 * (1.3 / d).atan().to_degrees();
            let cam = look(&scene, -dir * d, DVec3::ZERO, fov);
            probe("1-distance", "distance/size", d, scene.clone(), cam)
        })
        .collect()
}

/// Case 2: anisotropy with no min-radius clamp: cigars k:1:1 and pancakes 1:1:1/k (largest
/// radius 1), oblique.
pub fn anisotropy(quick: bool) -> Vec<Probe> {
    let ks = sweep(
        quick,
        &[1.0, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8],
        &[1.0, 1e6],
    );
    let mut out = Vec::new();
    for (case, cigar) in [
        ("2-anisotropy-cigar", true),
        ("2-anisotropy-pancake", false),
    ] {
        for &k in &ks {
            let radii = if cigar {
                DVec3::new(1.0, 1.0 / k, 1.0 / k)
            } else {
                DVec3::new(1.0, 1.0, 1.0 / k)
            };
            let scene =
                Scene::from_specs(&[spec(DVec3::ZERO, oblique(), radii, [60, 200, 90, 255])]);
            let dir = DVec3::new(-1.0, 1.0, -1.0).normalize();
            let cam = look(&scene, -dir * 4.0, DVec3::ZERO, 40.0);
            out.push(probe(case, "anisotropy k", k, scene, cam));
        }
    }
    out
}

/// Case 3: grazing rays. Orthographic views of spheres whose radius is a whole number of pixels
/// times (1 + δ), centred on a pixel centre: the rim passes through pixel centres (q̃² = 1 ± δ).
/// Perspective too: the same with a sphere far away, where q̃² rounds hardest.
pub fn grazing(quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    let px = 2.0 / f64::from(H); // ortho height 2: pixel size
    for &delta in &sweep(quick, &[-1e-7, -1e-8, 0.0, 1e-8, 1e-7], &[-1e-7, 0.0, 1e-7]) {
        // Pixel centres: the image centre lies on a pixel corner (even size); shift by half a pixel.
        let c = DVec3::new(px / 2.0, px / 2.0, 0.0);
        let r = 40.0 * px * (1.0 + delta);
        let specs: Vec<GlyphSpec> = vec![
            spec(c, DQuat::IDENTITY, DVec3::splat(r), [200, 200, 60, 255]),
            // A second sphere touching the first exactly at a pixel centre row.
            spec(
                c + DVec3::new(2.0 * r, 0.0, 0.0),
                DQuat::IDENTITY,
                DVec3::splat(r),
                [60, 120, 220, 255],
            ),
        ];
        let scene = Scene::from_specs(&specs);
        let eye = DVec3::new(0.0, 0.0, 10.0);
        let projection = Projection::Orthographic { height: 2.0 };
        let cam = fitted(&scene, eye, DVec3::ZERO, DVec3::Y, projection);
        let mut p = probe(
            "3-grazing",
            "rim offset δ (ortho)",
            delta,
            scene.clone(),
            cam,
        );
        p.label = format!("ortho δ={delta:e}");
        out.push(p);
        let mut cam = look(
            &scene,
            DVec3::new(0.0, 0.0, 1e4),
            DVec3::ZERO,
            2.0 * (1.0f64 / 1e4).atan().to_degrees(),
        );
        cam.up = DVec3::Y;
        let mut p = probe(
            "3-grazing-persp",
            "rim offset δ (persp, 1e4 away)",
            delta,
            scene,
            cam,
        );
        p.label = format!("persp δ={delta:e}");
        out.push(p);
    }
    out
}

/// Case 4: the eye approaching a unit sphere's surface: |ẽ| from 2 to 1 + 1e-6, on it, inside.
pub fn eye_approach(quick: bool) -> Vec<Probe> {
    let full = [
        2.0,
        1.5,
        1.1,
        1.01,
        1.0 + 1e-3,
        1.0 + 1e-4,
        1.0 + 1e-5,
        1.0 + 1e-6,
        1.0,
        0.5,
    ];
    let scene = Scene::from_specs(&[spec(
        DVec3::ZERO,
        oblique(),
        DVec3::new(1.0, 0.7, 0.5),
        [200, 90, 200, 255],
    )]);
    let geo = scene.geometry(0);
    // Eye along a fixed parameter-space direction: ẽ = E ŵ, e = c + T ẽ.
    let w = DVec3::new(-0.4, 0.8, 0.45).normalize();
    sweep(quick, &full, &[2.0, 1.01, 1.0 + 1e-6, 0.5])
        .into_iter()
        .map(|e| {
            let eye = scene.origin + geo.centre + geo.t() * (w * e);
            let mut cam = look(&scene, eye, scene.origin + geo.centre, 90.0);
            // Near plane well in front of the surface (1/10 of the gap, at least 1e-7).
            let gap = (geo.t() * (w * (e - 1.0).abs())).length();
            cam.near = (gap * 0.1).max(1e-7);
            cam.far = 4.0;
            let mut p = probe("4-eye-approach", "|ẽ|", e, scene.clone(), cam);
            p.label = match e {
                1.0 => "on surface".into(),
                0.5 => "inside".into(),
                _ => format!("1+{:.0e}", e - 1.0),
            };
            p
        })
        .collect()
}

/// Case 5: near-plane crossing, behind the camera, corner of a 120° view.
pub fn camera_edges(_quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    let radii = DVec3::new(1.0, 0.6, 0.4);
    let scene = Scene::from_specs(&[spec(DVec3::ZERO, oblique(), radii, [90, 200, 220, 255])]);
    // The near plane through the glyph centre.
    let mut cam = look(&scene, DVec3::new(0.0, -5.0, 0.0), DVec3::ZERO, 30.0);
    cam.near = 5.0;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 0.0, scene.clone(), cam);
    p.label = "near plane through centre".into();
    out.push(p);
    // Behind the camera (and a visible one in front).
    let scene2 = Scene::from_specs(&[
        spec(
            DVec3::new(0.0, 5.0, 0.0),
            oblique(),
            radii,
            [90, 200, 220, 255],
        ),
        spec(
            DVec3::new(0.0, -3.0, 0.0),
            oblique(),
            radii,
            [220, 90, 90, 255],
        ),
    ]);
    let mut cam = look(&scene2, DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0), 60.0);
    cam.near = 0.05;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 1.0, scene2, cam);
    p.label = "one glyph behind the camera".into();
    out.push(p);
    // A glyph in the corner of a 120° view.
    let fov: f64 = 120.0;
    let t = (fov.to_radians() / 2.0).tan();
    let aspect = f64::from(W) / f64::from(H);
    // Direction of NDC (0.8, 0.8), 6 units away (camera looks along +y, up +z).
    let d = DVec3::new(0.8 * t * aspect, 1.0, 0.8 * t).normalize();
    let scene3 = Scene::from_specs(&[spec(d * 6.0, oblique(), radii * 0.8, [220, 220, 90, 255])]);
    let mut cam = look(&scene3, DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0), fov);
    cam.near = 0.1;
    cam.far = 20.0;
    let mut p = probe("5-camera", "setting", 2.0, scene3, cam);
    p.label = "corner of a 120° view".into();
    out.push(p);
    out
}

/// Case 6: orthographic, oblique and exactly along an eigenvector (±z, x).
pub fn orthographic(_quick: bool) -> Vec<Probe> {
    let radii = DVec3::new(1.0, 0.6, 0.3);
    let mut out = Vec::new();
    let views: [(&str, DQuat, DVec3, DVec3); 4] = [
        (
            "oblique",
            oblique(),
            DVec3::new(-1.0, 1.0, -1.0).normalize(),
            DVec3::Z,
        ),
        ("along e3 (−z)", DQuat::IDENTITY, DVec3::NEG_Z, DVec3::Y),
        ("along −e3 (+z)", DQuat::IDENTITY, DVec3::Z, DVec3::Y),
        ("along e1 (x)", DQuat::IDENTITY, DVec3::X, DVec3::Z),
    ];
    for (k, (label, rot, dir, up)) in views.into_iter().enumerate() {
        let scene = Scene::from_specs(&[spec(DVec3::ZERO, rot, radii, [150, 220, 120, 255])]);
        let cam = ortho(&scene, dir, up, 2.6);
        let mut p = probe("6-orthographic", "view", k as f64, scene, cam);
        p.label = label.into();
        out.push(p);
    }
    out
}

/// Case 7: the whole field translated by up to 10⁹ (camera-relative rendering).
pub fn large_world(quick: bool) -> Vec<Probe> {
    sweep(quick, &[0.0, 1e3, 1e6, 1e9], &[0.0, 1e6])
        .into_iter()
        .map(|off| {
            let shift = DVec3::new(off, -0.5 * off, 0.25 * off);
            let specs: Vec<GlyphSpec> = (0..3)
                .map(|i| {
                    let x = f64::from(i) - 1.0;
                    spec(
                        shift + DVec3::new(1.1 * x, 0.2 * x, 0.0),
                        DQuat::from_axis_angle(DVec3::new(1.0, x, 0.5).normalize(), 0.7 + x),
                        DVec3::new(0.6, 0.35, 0.2),
                        [200, 80 + 60 * i as u8, 60, 255],
                    )
                })
                .collect();
            let scene = Scene::from_specs(&specs);
            let dir = DVec3::new(-1.0, 1.0, -0.8).normalize();
            let cam = look(&scene, scene.centre - dir * 5.0, scene.centre, 40.0);
            probe("7-large-world", "translation", off, scene, cam)
        })
        .collect()
}

/// Case 8: sub-pixel glyphs: a 12×9 grid of spheres of projected diameter s px, at
/// irrational sub-pixel offsets.
pub fn sub_pixel(quick: bool) -> Vec<Probe> {
    sweep(quick, &[0.1, 0.25, 0.5, 1.0, 2.0], &[0.5, 2.0])
        .into_iter()
        .map(|s| {
            let px = 2.0 / f64::from(H); // ortho height 2
            let mut specs = Vec::new();
            for j in 0..9 {
                for i in 0..12 {
                    let f = f64::from(i * 9 + j);
                    let x = (f64::from(i) - 5.5) * 20.0 * px + (f * 0.618_034).fract() * px;
                    let y = (f64::from(j) - 4.0) * 20.0 * px + (f * 0.414_214).fract() * px;
                    specs.push(spec(
                        DVec3::new(x, y, 0.0),
                        oblique(),
                        DVec3::new(1.0, 0.8, 0.6) * (s * px / 2.0),
                        [230, 230, 230, 255],
                    ));
                }
            }
            let scene = Scene::from_specs(&specs);
            let eye = DVec3::new(0.0, 0.0, 5.0);
            let projection = Projection::Orthographic { height: 2.0 };
            let cam = fitted(&scene, eye, DVec3::ZERO, DVec3::Y, projection);
            probe("8-sub-pixel", "projected size px", s, scene, cam)
        })
        .collect()
}

/// Case 9: two interpenetrating glyphs; the intersection curve with and without depth correction.
pub fn intersecting(_quick: bool) -> Vec<Probe> {
    let specs = [
        spec(
            DVec3::ZERO,
            oblique(),
            DVec3::new(1.0, 0.4, 0.4),
            [220, 60, 60, 255],
        ),
        spec(
            DVec3::new(0.3, 0.1, 0.0),
            DQuat::from_axis_angle(DVec3::new(0.2, 0.9, -0.3).normalize(), 0.6),
            DVec3::new(0.9, 0.5, 0.3),
            [60, 60, 220, 255],
        ),
    ];
    let scene = Scene::from_specs(&specs);
    let dir = DVec3::new(-1.0, 1.0, -0.6).normalize();
    let cam = look(&scene, scene.centre - dir * 5.0, scene.centre, 35.0);
    [true, false]
        .into_iter()
        .map(|dc| {
            let mut p = probe(
                "9-intersecting",
                "depth correction",
                f64::from(u8::from(dc)),
                scene.clone(),
                cam,
            );
            p.depth_correction = dc;
            p.label = if dc { "depth corrected" } else { "proxy depth" }.into();
            p
        })
        .collect()
}

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
        glyph: 0,
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

/// Instance `g` as a superquadric of the signed `eigenvalues` along its frame's columns (any
/// order): the mapping of `--glyph superquadric` applied to them, the frame and radii reordered
/// as the scene builder does.
pub fn superquadric_instance(
    g: &GlyphInstance,
    eigenvalues: [f64; 3],
    sharpness: Sharpness,
) -> GlyphInstance {
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigenvalues[b].total_cmp(&eigenvalues[a]));
    let shape = superquadric_shape(order.map(|i| eigenvalues[i]), sharpness);
    let axes = shape.axes.map(|i| order[i]);
    let (rotation, radii) = superquadric_frame(g.rotation, g.radii, axes);
    GlyphInstance {
        rotation,
        radii,
        shape: pack_exponents([shape.alpha, shape.beta, shape.c]),
        ..*g
    }
}

/// The superquadric version of a case's scene, each glyph's radii taken as its eigenvalues
/// (positive definite: Kindlmann's shapes at the default sharpness). Scenes that already carry
/// exponents are kept.
pub fn as_superquadrics(scene: &Scene) -> Scene {
    if scene.instances.iter().any(|g| g.shape != [0; 2]) {
        return scene.clone();
    }
    let instances = scene
        .instances
        .iter()
        .map(|g| superquadric_instance(g, g.radii.map(f64::from), Sharpness::default()))
        .collect();
    let mut out = Scene::from_instances_as(scene.origin, instances, GlyphKind::Superquadric);
    // Keep the case's framing (a degenerate case frames its healthy part on purpose).
    (out.centre, out.radius, out.half) = (scene.centre, scene.radius, scene.half);
    out
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
    Scene::from_instances_as(scene.origin, instances, GlyphKind::Superquadric)
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
    p.only = Some(GlyphKind::Superquadric);
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

/// Every GPU probe of the suite.
pub fn all(quick: bool) -> Vec<Probe> {
    let mut v = Vec::new();
    v.extend(distance(quick));
    v.extend(anisotropy(quick));
    v.extend(grazing(quick));
    v.extend(eye_approach(quick));
    v.extend(camera_edges(quick));
    v.extend(orthographic(quick));
    v.extend(large_world(quick));
    v.extend(sub_pixel(quick));
    v.extend(intersecting(quick));
    v.extend(degenerate(quick));
    v.extend(sharpness(quick));
    v.extend(class_boundary(quick));
    v.extend(indefinite(quick));
    v
}

/// A documented inherent limit that covers this row, if any (the reasons are in
/// docs/book/src/results/stability.md).
pub fn documented_limit(row: &Row) -> Option<&'static str> {
    match row.case {
        "9-intersecting" if !row.depth_correction => Some(
            "without depth correction the proxy's depth decides visibility, so the intersection curve of interpenetrating glyphs is wrong",
        ),
        "3-grazing" | "3-grazing-persp" => Some(
            "pixel centres within f32 rounding of a silhouette or of a contact between glyphs are ties and may flip; at the rim the hit moves infinitely fast with the ray, so f32 rounding of q̃ shows in the depth p99 of small glyphs",
        ),
        "2-anisotropy-cigar" | "2-anisotropy-pancake" if row.value >= 1e4 => Some(
            "T⁻¹ in f32 has condition k = r_max/r_min: normal and depth errors grow ∝ 2⁻²⁴·k (about 1° normal p99 at k = 1e5); at k ≥ 1e6 the glyph is thinner than a pixel and at k > 2²⁴ it is culled",
        ),
        // Only when depth is the sole excess: coverage of sub-pixel glyphs is held to the bounds.
        "8-sub-pixel" if row.reason.starts_with("depth_err") && !row.reason.contains(';') => Some(
            "instances are f32 relative to the scene origin: a glyph of radius r at distance D from it is placed to ~2⁻²⁴·D, i.e. depth error ~2⁻²⁴·D/r radii (1.4e-4 radii for 1 px superquadrics)",
        ),
        _ => None,
    }
}
