//! What every case is made of: a [`Probe`] (one scene and camera), the image size, and the
//! helpers the cases build their glyphs and cameras with.

use glam::{DQuat, DVec3};

use crate::camera::{Camera, Projection};
use crate::request::GlyphKind;
use crate::scene::{GlyphSpec, Scene};

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
    /// Draw it through every preset each method takes ([`crate::request::Preset::applies_to`]),
    /// not only the baseline (and Gumhold's default splats).
    pub presets: bool,
}

pub(super) fn probe(
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
        presets: false,
    }
}

pub(super) fn spec(centre: DVec3, rotation: DQuat, radii: DVec3, color: [u8; 4]) -> GlyphSpec {
    GlyphSpec {
        centre,
        rotation,
        radii,
        color,
    }
}

/// An oblique rotation, so no axis lines up with the view.
pub fn oblique() -> DQuat {
    DQuat::from_axis_angle(DVec3::new(0.3, -0.5, 0.8).normalize(), 1.1)
}

/// A camera of the probes' size from `eye` towards `target`, its depth planes fitted to the scene.
pub(super) fn fitted(
    scene: &Scene,
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    projection: Projection,
) -> Camera {
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
pub(super) fn look(scene: &Scene, eye: DVec3, target: DVec3, fov_deg: f64) -> Camera {
    let fwd = (target - eye).normalize();
    let up = if fwd.cross(DVec3::Z).length() > 1e-3 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let fov_y = fov_deg.to_radians();
    fitted(scene, eye, target, up, Projection::Perspective { fov_y })
}

pub(super) fn ortho(scene: &Scene, dir: DVec3, up: DVec3, height: f64) -> Camera {
    let eye = scene.centre - dir * 10.0 * scene.radius;
    let projection = Projection::Orthographic { height };
    fitted(scene, eye, scene.centre, up, projection)
}

pub(super) fn sweep(quick: bool, full: &[f64], subset: &[f64]) -> Vec<f64> {
    if quick {
        subset.to_vec()
    } else {
        full.to_vec()
    }
}
