//! Orbit, pan and zoom around a target; axis views; perspective / orthographic. The result is a
//! plain [`Camera`], the same one `render` and the reference use.

use glam::{DQuat, DVec3};

use crate::camera::{Camera, Framing, Projection, ViewPreset};

/// Radians of orbit per point dragged.
const ORBIT_PER_POINT: f64 = 0.008;

/// An orbiting camera: the eye sits `distance` from `target` along `-forward`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Navigation {
    pub target: DVec3,
    pub distance: f64,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit, orthogonal to `forward`.
    pub up: DVec3,
    pub fov_deg: f64,
    pub ortho: bool,
    /// The scene's bounding sphere, for near/far planes and resets.
    pub scene_centre: DVec3,
    pub scene_radius: f64,
}

impl Navigation {
    /// The view `render --view preset` would give of a scene's bounding sphere.
    pub fn framed(preset: ViewPreset, centre: DVec3, radius: f64, ortho: bool) -> Self {
        let framing = Framing {
            view: preset,
            ortho,
            ..Framing::default()
        };
        Self::from_framing(&framing, centre, radius)
    }

    /// The view `render` gives of a scene's bounding sphere with these camera options.
    pub fn from_framing(framing: &Framing, centre: DVec3, radius: f64) -> Self {
        let ortho = framing.ortho;
        // Perspective framing fixes the distance; orthographic shows the same height there.
        let cam = Camera::frame(framing, centre, radius, 1, 1);
        let forward = cam.forward();
        Self {
            target: cam.target,
            distance: (cam.target - cam.eye).length(),
            forward,
            up: orthonormal_up(forward, cam.up),
            fov_deg: framing.fov_deg,
            ortho,
            scene_centre: centre,
            scene_radius: if radius.is_finite() && radius > 0.0 {
                radius
            } else {
                1.0
            },
        }
    }

    /// Back to an axis view (or iso) of the whole scene, keeping the projection.
    pub fn reset(&mut self, preset: ViewPreset) {
        *self = Self::framed(preset, self.scene_centre, self.scene_radius, self.ortho);
    }

    /// A new scene of the same data (selection changed): keep the view, update the bounds.
    pub fn set_bounds(&mut self, centre: DVec3, radius: f64) {
        self.scene_centre = centre;
        if radius.is_finite() && radius > 0.0 {
            self.scene_radius = radius;
        }
    }

    pub fn eye(&self) -> DVec3 {
        self.target - self.forward * self.distance
    }

    pub fn right(&self) -> DVec3 {
        self.forward.cross(self.up).normalize()
    }

    /// World units per point of the viewport at the target's depth.
    pub fn world_per_point(&self, viewport_height_points: f64) -> f64 {
        self.visible_height() / viewport_height_points.max(1.0)
    }

    /// Height of the view at the target (the orthographic view volume's height).
    pub fn visible_height(&self) -> f64 {
        2.0 * self.distance * (self.fov_deg.to_radians() / 2.0).tan()
    }

    /// Turn around the target by a drag of (dx, dy) points: horizontal about the camera's up,
    /// vertical about its right axis.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        let yaw = DQuat::from_axis_angle(self.up, -dx * ORBIT_PER_POINT);
        let pitch = DQuat::from_axis_angle(self.right(), -dy * ORBIT_PER_POINT);
        let q = pitch * yaw;
        self.forward = (q * self.forward).normalize();
        self.up = orthonormal_up(self.forward, q * self.up);
    }

    /// Move the target with the pointer: a drag of (dx, dy) points in a viewport
    /// `viewport_height` points high.
    pub fn pan(&mut self, dx: f64, dy: f64, viewport_height: f64) {
        let s = self.world_per_point(viewport_height);
        self.target += (-dx * self.right() + dy * self.up) * s;
    }

    /// `factor` > 1 moves closer (perspective) or magnifies (orthographic).
    pub fn zoom(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            let min = self.scene_radius * 1e-4;
            let max = self.scene_radius * 1e4;
            self.distance = (self.distance / factor).clamp(min, max);
        }
    }

    /// Look at `point` from where we are looking now.
    pub fn centre_on(&mut self, point: DVec3) {
        self.target = point;
    }

    /// How much farther (or larger, orthographic) a viewport narrower than it is tall must be
    /// to show what a square one shows: `distance` and the visible height are set for aspect ≥ 1.
    fn portrait_factor(&self, aspect: f64) -> f64 {
        if !(aspect < 1.0 && aspect > 0.0) {
            return 1.0;
        }
        if self.ortho {
            1.0 / aspect
        } else {
            let h = (self.fov_deg.to_radians() / 2.0).clamp(1e-4, 1.55);
            h.sin() / (h.tan() * aspect).atan().sin()
        }
    }

    /// The camera for a viewport of `width` × `height` pixels.
    pub fn camera(&self, width: u32, height: u32) -> Camera {
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let fit = self.portrait_factor(aspect);
        let projection = if self.ortho {
            Projection::Orthographic {
                height: self.visible_height() * fit,
            }
        } else {
            Projection::Perspective {
                fov_y: self.fov_deg.to_radians(),
            }
        };
        let distance = if self.ortho {
            self.distance
        } else {
            self.distance * fit
        };
        let mut cam = Camera {
            eye: self.target - self.forward * distance,
            target: self.target,
            up: self.up,
            projection,
            near: 0.0,
            far: 0.0,
            width: width.max(1),
            height: height.max(1),
            crop: None,
        };
        // Depth range around everything that can be drawn: the scene and the target.
        let reach = self.scene_radius + (self.target - self.scene_centre).length();
        cam.fit_depth_range(self.target, reach);
        cam
    }
}

/// `up` made orthogonal to `forward` and unit (any perpendicular if they are parallel).
fn orthonormal_up(forward: DVec3, up: DVec3) -> DVec3 {
    let u = up - forward * forward.dot(up);
    if u.length_squared() > 1e-12 {
        u.normalize()
    } else {
        forward.any_orthonormal_vector()
    }
}

/// The axis view of keys 1–6: +x, −x, +y, −y, +z, −z (looking along that direction).
pub fn axis_view(key: usize) -> Option<ViewPreset> {
    Some(match key {
        1 => ViewPreset::PosX,
        2 => ViewPreset::NegX,
        3 => ViewPreset::PosY,
        4 => ViewPreset::NegY,
        5 => ViewPreset::PosZ,
        6 => ViewPreset::NegZ,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nav() -> Navigation {
        Navigation::framed(ViewPreset::Iso, DVec3::new(1.0, 2.0, 3.0), 5.0, false)
    }

    #[test]
    fn framing_matches_render() {
        let n = nav();
        let reference = Camera::frame(
            &Framing::default(),
            DVec3::new(1.0, 2.0, 3.0),
            5.0,
            800,
            600,
        );
        let cam = n.camera(800, 600);
        assert!((cam.eye - reference.eye).length() < 1e-9 * 5.0 + 1e-6);
        assert!((cam.target - reference.target).length() < 1e-9);
    }

    #[test]
    fn portrait_viewports_still_show_the_whole_scene() {
        let n = nav();
        let wide = n.camera(800, 600);
        let tall = n.camera(600, 1200);
        let reference = Camera::frame(&Framing::default(), n.scene_centre, 5.0, 600, 1200);
        assert!(
            ((tall.eye - tall.target).length() - (reference.eye - reference.target).length()).abs()
                < 1e-6
        );
        assert!((tall.eye - tall.target).length() > (wide.eye - wide.target).length());
    }

    #[test]
    fn orbit_keeps_distance_and_target() {
        let mut n = nav();
        let (t, d) = (n.target, n.distance);
        n.orbit(120.0, -45.0);
        assert!((n.target - t).length() < 1e-12);
        assert!(((n.eye() - n.target).length() - d).abs() < 1e-9);
        assert!(n.forward.dot(n.up).abs() < 1e-9);
        assert!((n.up.length() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn pan_moves_target_in_the_view_plane_by_pointer_distance() {
        let mut n = nav();
        let before = n.target;
        n.pan(100.0, 0.0, 500.0);
        let moved = n.target - before;
        assert!(moved.dot(n.forward).abs() < 1e-9);
        let expected = 100.0 * n.visible_height() / 500.0;
        assert!((moved.length() - expected).abs() < 1e-9);
        // Dragging right moves the scene right: the target moves left.
        assert!(moved.dot(n.right()) < 0.0);
    }

    #[test]
    fn zoom_and_projection_toggle() {
        let mut n = nav();
        let d = n.distance;
        n.zoom(2.0);
        assert!((n.distance - d / 2.0).abs() < 1e-9);
        n.ortho = true;
        let cam = n.camera(640, 480);
        match cam.projection {
            Projection::Orthographic { height } => {
                assert!((height - n.visible_height()).abs() < 1e-9)
            }
            _ => panic!("orthographic expected"),
        }
        assert!(cam.near >= 0.0 && cam.far > cam.near);
    }

    #[test]
    fn axis_views_look_along_their_axis() {
        let mut n = nav();
        for k in 1..=6 {
            n.reset(axis_view(k).unwrap());
            let (dir, _) = axis_view(k).unwrap().direction_up();
            assert!((n.forward - dir).length() < 1e-9, "key {k}");
        }
        assert!(axis_view(7).is_none());
    }
}
