//! One camera for the GPU and the CPU reference alike: view, projection, viewport and pixel rays.
//!
//! Conventions (see `shared/math/README.md`): right-handed, the camera looks down −Z with +Y up in
//! view space; glam `look_at_rh`, `perspective_rh` / `orthographic_rh`; WebGPU depth in [0, 1].
//! Everything is f64 here. The GPU gets f32 matrices built *relative to a scene origin* near the
//! glyphs, so fields far from the world origin keep their precision.

use glam::dcamera::rh::{proj::directx as proj, view};
use glam::{DMat4, DVec3};

/// How the camera projects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Vertical field of view in radians.
    Perspective { fov_y: f64 },
    /// Height of the view volume in world units.
    Orthographic { height: f64 },
}

/// A camera with its viewport.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub target: DVec3,
    pub up: DVec3,
    pub projection: Projection,
    pub near: f64,
    pub far: f64,
    pub width: u32,
    pub height: u32,
    /// `Some`: the camera renders only a `width`×`height` window of a larger image (a tile),
    /// with that image's projection; see [`Camera::cropped`].
    pub crop: Option<Crop>,
}

/// Where a cropped camera's pixels lie in the whole image: its pixel (i, j) is the image's
/// pixel (`x` + i, `y` + j), and it casts the very same ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crop {
    pub x: u32,
    pub y: u32,
    pub full_width: u32,
    pub full_height: u32,
}

/// A pixel's viewing ray in world space (unit direction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

/// The axis-aligned view presets, named like ParaView's "set view direction" buttons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ViewPreset {
    /// Looking at the field from the (+x, −y, +z) octant, +z up.
    #[default]
    Iso,
    PosX,
    NegX,
    PosY,
    NegY,
    PosZ,
    NegZ,
    /// In an anatomical (RAS) world: from superior, anterior up (−z), the subject's right on
    /// the right (neurological convention).
    Axial,
    /// From posterior, superior up (+y), the subject's right on the right.
    Coronal,
    /// From the subject's left, superior up (+x), anterior on the left.
    Sagittal,
}

crate::names::named_values!(ViewPreset {
    Iso => "iso",
    PosX => "+x",
    NegX => "-x",
    PosY => "+y",
    NegY => "-y",
    PosZ => "+z",
    NegZ => "-z",
    Axial => "axial",
    Coronal => "coronal",
    Sagittal => "sagittal",
});

impl ViewPreset {
    /// (view direction, up), both unit: the camera looks along the direction.
    pub fn direction_up(self) -> (DVec3, DVec3) {
        match self {
            ViewPreset::Iso => (DVec3::new(-1.0, 1.0, -1.0).normalize(), DVec3::Z),
            ViewPreset::PosX => (DVec3::X, DVec3::Z),
            ViewPreset::NegX => (DVec3::NEG_X, DVec3::Z),
            ViewPreset::PosY => (DVec3::Y, DVec3::Z),
            ViewPreset::NegY => (DVec3::NEG_Y, DVec3::Z),
            ViewPreset::PosZ => (DVec3::Z, DVec3::Y),
            ViewPreset::NegZ | ViewPreset::Axial => (DVec3::NEG_Z, DVec3::Y),
            ViewPreset::Coronal => ViewPreset::PosY.direction_up(),
            ViewPreset::Sagittal => ViewPreset::PosX.direction_up(),
        }
    }
}

/// How to frame a scene: the user's camera options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Framing {
    pub view: ViewPreset,
    /// Degrees about the up axis, applied after the preset (as ParaView's Azimuth).
    pub azimuth: f64,
    /// Degrees about the camera's right axis (as ParaView's Elevation).
    pub elevation: f64,
    /// > 1 moves closer.
    pub zoom: f64,
    /// Vertical field of view in degrees (perspective).
    pub fov_deg: f64,
    pub ortho: bool,
    /// (view direction, up) replacing the preset's, both unit: a slice seen face-on.
    pub toward: Option<(DVec3, DVec3)>,
}

impl Default for Framing {
    fn default() -> Self {
        Self {
            view: ViewPreset::Iso,
            azimuth: 0.0,
            elevation: 0.0,
            zoom: 1.0,
            fov_deg: 30.0,
            ortho: false,
            toward: None,
        }
    }
}

impl Camera {
    /// A camera that shows the whole bounding sphere (`centre`, `radius`) of a scene.
    pub fn frame(framing: &Framing, centre: DVec3, radius: f64, width: u32, height: u32) -> Self {
        let radius = if radius.is_finite() && radius > 0.0 {
            radius
        } else {
            1.0
        };
        let (mut dir, mut up) = framing
            .toward
            .unwrap_or_else(|| framing.view.direction_up());
        let az = glam::DQuat::from_axis_angle(up, framing.azimuth.to_radians());
        dir = az * dir;
        let right = dir.cross(up).normalize();
        let el = glam::DQuat::from_axis_angle(right, framing.elevation.to_radians());
        dir = el * dir;
        up = el * up;
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let zoom = if framing.zoom > 0.0 {
            framing.zoom
        } else {
            1.0
        };
        let fov_y = framing.fov_deg.to_radians().clamp(1e-3, 3.1);
        // The narrower of the two fields of view decides the fit.
        let half_min = (fov_y / 2.0).tan().min((fov_y / 2.0).tan() * aspect).atan();
        let distance = radius / half_min.sin() / zoom;
        let eye = centre - dir * distance;
        let projection = if framing.ortho {
            let fit_h = 2.0 * radius * (1.0f64).max(1.0 / aspect);
            Projection::Orthographic {
                height: fit_h / zoom,
            }
        } else {
            Projection::Perspective { fov_y }
        };
        let mut cam = Self {
            eye,
            target: centre,
            up,
            projection,
            near: 0.0,
            far: 0.0,
            width,
            height,
            crop: None,
        };
        cam.fit_depth_range(centre, radius);
        cam
    }

    /// A camera that shows the box `centre ± half` (axis-aligned, world) as large as the image
    /// allows: oriented as [`Self::frame`] but with the box's projection, not its bounding
    /// sphere's, fitted to the image (with a 3 % margin), so an elongated field (a beam, a
    /// slice) fills the frame. `--zoom` divides the distance as in [`Self::frame`].
    pub fn frame_box(
        framing: &Framing,
        centre: DVec3,
        half: DVec3,
        width: u32,
        height: u32,
    ) -> Self {
        let radius = half.length();
        let mut cam = Self::frame(framing, centre, radius, width, height);
        if !(radius.is_finite() && radius > 0.0) {
            return cam;
        }
        let dir = cam.forward();
        let up = (cam.up - dir * cam.up.dot(dir)).normalize();
        let right = dir.cross(up).normalize();
        let corners = (0..8).map(|k| {
            let s = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
            DVec3::new(s(0) * half.x, s(1) * half.y, s(2) * half.z)
        });
        let aspect = cam.aspect();
        let zoom = if framing.zoom > 0.0 {
            framing.zoom
        } else {
            1.0
        };
        const MARGIN: f64 = 1.03;
        match cam.projection {
            Projection::Perspective { fov_y } => {
                let ty = (fov_y / 2.0).tan();
                let tx = ty * aspect;
                let d = corners
                    .map(|o| (o.dot(right).abs() / tx).max(o.dot(up).abs() / ty) - o.dot(dir))
                    .fold(0.0f64, f64::max);
                if d.is_finite() && d > 0.0 {
                    cam.eye = centre - dir * (d * MARGIN / zoom);
                }
            }
            Projection::Orthographic { .. } => {
                let (hx, hy) = corners.fold((0.0f64, 0.0f64), |(hx, hy), o| {
                    (hx.max(o.dot(right).abs()), hy.max(o.dot(up).abs()))
                });
                let h = (2.0 * hy).max(2.0 * hx / aspect) * MARGIN / zoom;
                if h.is_finite() && h > 0.0 {
                    cam.projection = Projection::Orthographic { height: h };
                }
            }
        }
        cam.fit_depth_range(centre, radius);
        cam
    }

    /// Near and far planes tight around a bounding sphere, so depth keeps its resolution.
    /// An eye inside the sphere gets a near plane of 1e-4 of the radius (glyphs cut by it are
    /// clipped, as in any rasteriser).
    pub fn fit_depth_range(&mut self, centre: DVec3, radius: f64) {
        let d = (centre - self.eye).dot(self.forward());
        match self.projection {
            Projection::Perspective { .. } => {
                self.far = (d + radius).max(radius * 1e-3) * 1.01;
                self.near = (d - radius).max(radius * 1e-4).min(self.far * 0.5);
            }
            Projection::Orthographic { .. } => {
                // Rays start on the camera plane; move it back if the scene reaches behind it.
                let behind = (radius - d).max(0.0);
                self.eye -= self.forward() * (behind + radius * 0.01);
                let d = (centre - self.eye).dot(self.forward());
                self.near = (d - radius).max(0.0);
                self.far = d + radius * 1.01;
            }
        }
    }

    /// Move the near and far planes `margin` further apart (the near plane at most to a tenth
    /// of its distance in perspective, where it must stay in front of the eye).
    pub fn widen_depth_range(&mut self, margin: f64) {
        if margin.is_nan() || margin <= 0.0 {
            return;
        }
        self.far += margin;
        self.near = match self.projection {
            Projection::Perspective { .. } => (self.near - margin).max(self.near * 0.1),
            Projection::Orthographic { .. } => self.near - margin,
        };
    }

    pub fn forward(&self) -> DVec3 {
        (self.target - self.eye).normalize()
    }

    /// Width over height of the whole image (a crop keeps the image's projection).
    pub fn aspect(&self) -> f64 {
        let (w, h) = self.full_size();
        f64::from(w.max(1)) / f64::from(h.max(1))
    }

    /// The size of the whole image: the camera's own, or the one it is a crop of.
    pub fn full_size(&self) -> (u32, u32) {
        match self.crop {
            Some(c) => (c.full_width, c.full_height),
            None => (self.width, self.height),
        }
    }

    /// The camera of the whole image this one is a crop of (itself when it is not cropped).
    pub fn full(&self) -> Camera {
        let (width, height) = self.full_size();
        Camera {
            width,
            height,
            crop: None,
            ..*self
        }
    }

    /// The `width`×`height` window at pixel (`x`, `y`) of this camera's whole image, as a camera
    /// of its own: same eye and projection, so its pixel (i, j) sees exactly what pixel
    /// (`x` + i, `y` + j) of the whole image sees. The window is clamped to the image (at least
    /// one pixel).
    pub fn cropped(&self, x: u32, y: u32, width: u32, height: u32) -> Camera {
        let (full_width, full_height) = self.full_size();
        let x = x.min(full_width.saturating_sub(1));
        let y = y.min(full_height.saturating_sub(1));
        Camera {
            width: width.clamp(1, (full_width - x).max(1)),
            height: height.clamp(1, (full_height - y).max(1)),
            crop: Some(Crop {
                x,
                y,
                full_width,
                full_height,
            }),
            ..*self
        }
    }

    /// Where the whole image's centre (its principal point) lies in this camera's pixels: the
    /// viewport's centre unless cropped.
    pub fn image_centre_px(&self) -> (f64, f64) {
        match self.crop {
            Some(c) => (
                0.5 * f64::from(c.full_width) - f64::from(c.x),
                0.5 * f64::from(c.full_height) - f64::from(c.y),
            ),
            None => (0.5 * f64::from(self.width), 0.5 * f64::from(self.height)),
        }
    }

    pub fn is_ortho(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// View matrix with `origin` moved to (0, 0, 0): world points must be given relative to it.
    pub fn view(&self, origin: DVec3) -> DMat4 {
        view::look_at_mat4(self.eye - origin, self.target - origin, self.up)
    }

    /// The six clip planes (left, right, bottom, top, near, far) relative to `origin`, as unit
    /// normals pointing inwards with their offsets: a point p is inside when n·p + d ≥ 0.
    pub fn frustum_planes(&self, origin: DVec3) -> [glam::DVec4; 6] {
        let m = self.projection_matrix() * self.view(origin);
        let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
        // Gribb–Hartmann, with clip z in [0, w].
        [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2].map(|p| p / p.truncate().length())
    }

    /// Pixels per world unit of a length across the view at view distance 1 (perspective), or
    /// at any distance (orthographic).
    pub fn pixels_per_unit(&self) -> f64 {
        let full = self.full();
        full.projection_matrix().y_axis.y * 0.5 * f64::from(full.height)
    }

    /// Projected radius in pixels of a sphere of radius `r` whose centre is `c` (world).
    pub fn pixel_radius(&self, c: DVec3, r: f64) -> f64 {
        let w = if self.is_ortho() {
            1.0
        } else {
            (c - self.eye).dot(self.forward()).max(1e-30)
        };
        r * self.pixels_per_unit() / w
    }

    /// Clip space of this camera's own viewport: a crop's is the whole image's followed by the
    /// affine map that takes the window's NDC rectangle to [−1, 1]² (an off-centre frustum).
    pub fn projection_matrix(&self) -> DMat4 {
        let full = self.full_projection();
        let Some(c) = self.crop else {
            return full;
        };
        // Window NDC x' = (W x + W − w − 2 x0) / w of the image's NDC x; y likewise, downwards.
        let (fw, fh) = (f64::from(c.full_width), f64::from(c.full_height));
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let sx = fw / w;
        let sy = fh / h;
        let tx = (fw - w - 2.0 * f64::from(c.x)) / w;
        let ty = -(fh - h - 2.0 * f64::from(c.y)) / h;
        let window = DMat4::from_cols(
            glam::DVec4::new(sx, 0.0, 0.0, 0.0),
            glam::DVec4::new(0.0, sy, 0.0, 0.0),
            glam::DVec4::new(0.0, 0.0, 1.0, 0.0),
            glam::DVec4::new(tx, ty, 0.0, 1.0),
        );
        window * full
    }

    /// The whole image's (symmetric) projection.
    fn full_projection(&self) -> DMat4 {
        match self.projection {
            Projection::Perspective { fov_y } => {
                proj::perspective(fov_y, self.aspect(), self.near, self.far)
            }
            Projection::Orthographic { height } => {
                let h = height / 2.0;
                let w = h * self.aspect();
                proj::orthographic(-w, w, -h, h, self.near, self.far)
            }
        }
    }

    /// NDC of a position in this camera's viewport (pixel centres at +0.5).
    pub fn pixel_to_ndc(&self, px: f64, py: f64) -> (f64, f64) {
        (
            2.0 * px / f64::from(self.width) - 1.0,
            1.0 - 2.0 * py / f64::from(self.height),
        )
    }

    /// The ray through NDC (x, y) of this camera's viewport, in world space.
    pub fn ray_ndc(&self, x: f64, y: f64) -> Ray {
        let (x, y) = match self.crop {
            // Through the whole image's pixel coordinates, as its own pixel_to_ndc forms them.
            Some(c) => {
                let px = f64::from(c.x) + (x + 1.0) * 0.5 * f64::from(self.width);
                let py = f64::from(c.y) + (1.0 - y) * 0.5 * f64::from(self.height);
                (
                    2.0 * px / f64::from(c.full_width) - 1.0,
                    1.0 - 2.0 * py / f64::from(c.full_height),
                )
            }
            None => (x, y),
        };
        let f = self.forward();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (fov_y / 2.0).tan();
                let dir = (f + s * (x * t * self.aspect()) + u * (y * t)).normalize();
                Ray {
                    origin: self.eye,
                    dir,
                }
            }
            Projection::Orthographic { height } => {
                let h = height / 2.0;
                Ray {
                    origin: self.eye + s * (x * h * self.aspect()) + u * (y * h),
                    dir: f,
                }
            }
        }
    }

    /// The ray through the centre of pixel (i, j), (0, 0) top-left.
    pub fn pixel_ray(&self, i: u32, j: u32) -> Ray {
        let (x, y) = self.pixel_to_ndc(f64::from(i) + 0.5, f64::from(j) + 0.5);
        self.ray_ndc(x, y)
    }

    /// Standard-Z depth of a point at view distance `d` (perspective) or view depth `d` (ortho).
    pub fn ndc_depth(&self, d: f64) -> f64 {
        match self.projection {
            Projection::Perspective { .. } => {
                self.far * (d - self.near) / (d * (self.far - self.near))
            }
            Projection::Orthographic { .. } => (d - self.near) / (self.far - self.near),
        }
    }
}

impl Camera {
    /// Height of the orthographic view volume, or the height of the view at unit distance.
    pub fn projection_height(&self) -> f64 {
        match self.projection {
            Projection::Perspective { fov_y } => 2.0 * (fov_y / 2.0).tan(),
            Projection::Orthographic { height } => height,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, v3};

    /// Build the test vector's camera exactly (no framing) at a 1000-pixel-high viewport.
    pub(crate) fn camera_of(case: &serde_json::Value) -> Camera {
        let c = &case["camera"];
        let aspect = c["aspect"].as_f64().unwrap_or_else(|| {
            (c["right"].as_f64().unwrap() - c["left"].as_f64().unwrap())
                / (c["top"].as_f64().unwrap() - c["bottom"].as_f64().unwrap())
        });
        // 1800 rows make every aspect of the vectors a whole number of columns.
        let height = 1800u32;
        let width = (aspect * f64::from(height)).round() as u32;
        let projection = if c["projection"] == "orthographic" {
            let t = c["top"].as_f64().unwrap();
            let b = c["bottom"].as_f64().unwrap();
            Projection::Orthographic { height: t - b }
        } else {
            Projection::Perspective {
                fov_y: c["fov_y_deg"].as_f64().unwrap().to_radians(),
            }
        };
        Camera {
            eye: v3(&c["eye"]),
            target: v3(&c["target"]),
            up: v3(&c["up"]),
            projection,
            near: c["near"].as_f64().unwrap(),
            far: c["far"].as_f64().unwrap(),
            width,
            height,
            crop: None,
        }
    }

    #[test]
    fn matrices_and_rays_match_the_test_vectors() {
        for case in &cases() {
            let id = case["id"].as_str().unwrap();
            let cam = camera_of(case);
            let e = &case["expected"];
            let view = cam.view(DVec3::ZERO).to_cols_array();
            let proj = cam.projection_matrix().to_cols_array();
            for (k, x) in e["view_cols"].as_array().unwrap().iter().enumerate() {
                assert!(
                    (view[k] - x.as_f64().unwrap()).abs() < 1e-12,
                    "{id}: view[{k}]"
                );
            }
            for (k, x) in e["proj_cols"].as_array().unwrap().iter().enumerate() {
                let want = x.as_f64().unwrap();
                assert!(
                    (proj[k] - want).abs() <= 1e-9 * want.abs().max(1.0),
                    "{id}: proj[{k}] {} vs {want}",
                    proj[k]
                );
            }
            let p = &case["pixel_ndc"];
            let ray = cam.ray_ndc(p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
            assert!(
                (ray.origin - v3(&e["ray"]["origin"])).length() < 1e-9,
                "{id}: origin"
            );
            let err = (ray.dir - v3(&e["ray"]["dir"])).length();
            // 1e-9: the vectors build rays from (P View)⁻¹, which near = 1e-6 conditions badly.
            assert!(err < 1e-9, "{id}: dir error {err}");
        }
    }

    #[test]
    fn a_crop_casts_the_rays_of_the_whole_images_pixels() {
        for ortho in [false, true] {
            let framing = Framing {
                ortho,
                azimuth: 30.0,
                elevation: 20.0,
                ..Framing::default()
            };
            let full = Camera::frame(&framing, DVec3::new(30.0, -10.0, 20.0), 1.5, 200, 150);
            let scale = 1.0 + full.eye.length();
            let vp_full = full.projection_matrix() * full.view(DVec3::ZERO);
            let mid = 0.5 * (full.near + full.far);
            // A point at mid depth on the ray through the whole image's position (px, py).
            let at = |px: f64, py: f64| {
                let (x, y) = full.pixel_to_ndc(px, py);
                let r = full.ray_ndc(x, y);
                r.origin + r.dir * (mid / r.dir.dot(full.forward()))
            };
            for (x, y, w, h) in [
                (0, 0, 200, 150),
                (37, 21, 50, 40),
                (136, 86, 64, 64),
                (0, 149, 200, 1),
            ] {
                let tile = full.cropped(x, y, w, h);
                assert_eq!((tile.width, tile.height), (w, h));
                assert_eq!(tile.full(), full);
                assert_eq!(tile.pixels_per_unit(), full.pixels_per_unit());
                for j in 0..h {
                    for i in 0..w {
                        let (a, b) = (tile.pixel_ray(i, j), full.pixel_ray(x + i, y + j));
                        let (eo, ed) = ((a.origin - b.origin).length(), (a.dir - b.dir).length());
                        assert!(
                            eo <= 1e-13 * scale && ed <= 1e-14,
                            "{ortho} ({i}, {j}) {eo} {ed}"
                        );
                    }
                }
                // The tile's clip space: a point lands on the same pixel position, offset by
                // (x, y), at the same depth.
                let vp_tile = tile.projection_matrix() * tile.view(DVec3::ZERO);
                for (px, py) in [
                    (x as f64 + 0.3, y as f64 + 0.7),
                    (120.25, 80.5),
                    (-3.0, 160.0),
                ] {
                    let p = at(px, py).extend(1.0);
                    let (cf, ct) = (vp_full * p, vp_tile * p);
                    let (nf, nt) = (cf.truncate() / cf.w, ct.truncate() / ct.w);
                    let tile_px = (nt.x + 1.0) * 0.5 * f64::from(w) + f64::from(x);
                    let tile_py = (1.0 - nt.y) * 0.5 * f64::from(h) + f64::from(y);
                    assert!((tile_px - px).abs() < 1e-9 && (tile_py - py).abs() < 1e-9);
                    assert!((nt.z - nf.z).abs() < 1e-12);
                }
                // Its frustum holds its own pixels and not its neighbours'.
                let planes = tile.frustum_planes(DVec3::ZERO);
                let inside = |p: DVec3| planes.iter().all(|q| q.truncate().dot(p) + q.w >= 0.0);
                let (x0, y0) = (f64::from(x), f64::from(y));
                let (x1, y1) = (x0 + f64::from(w), y0 + f64::from(h));
                assert!(inside(at(x0 + 0.01, y0 + 0.01)) && inside(at(x1 - 0.01, y1 - 0.01)));
                assert!(!inside(at(x0 - 0.01, y0 + 0.5)) && !inside(at(x1 + 0.01, y0 + 0.5)));
                assert!(!inside(at(x0 + 0.5, y0 - 0.01)) && !inside(at(x0 + 0.5, y1 + 0.01)));
                let (cx, cy) = tile.image_centre_px();
                assert_eq!((cx + x0, cy + y0), (100.0, 75.0));
            }
        }
    }

    #[test]
    fn framing_shows_the_whole_sphere() {
        for view in [ViewPreset::Iso, ViewPreset::PosX, ViewPreset::NegZ] {
            for ortho in [false, true] {
                let framing = Framing {
                    view,
                    ortho,
                    azimuth: 20.0,
                    elevation: -10.0,
                    ..Framing::default()
                };
                let c = DVec3::new(5.0, -3.0, 2.0);
                let cam = Camera::frame(&framing, c, 2.0, 640, 480);
                let vp = cam.projection_matrix() * cam.view(DVec3::ZERO);
                // Points on the sphere project inside the viewport and the depth range.
                for k in 0..200 {
                    let a = f64::from(k) * 0.7;
                    let b = f64::from(k) * 1.3;
                    let d = DVec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos());
                    let p = vp * (c + d * 2.0).extend(1.0);
                    let ndc = p.truncate() / p.w;
                    assert!(
                        ndc.x.abs() <= 1.0 + 1e-9 && ndc.y.abs() <= 1.0 + 1e-9,
                        "{ndc}"
                    );
                    assert!(
                        (0.0..=1.0).contains(&ndc.z),
                        "{view:?} {ortho} depth {}",
                        ndc.z
                    );
                }
            }
        }
    }
}
