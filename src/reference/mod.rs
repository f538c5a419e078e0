//! The exact reference: an f64 CPU ray caster of the very same glyph instances, camera and
//! lighting as the GPU. Pixel-centre rays, exact ray–ellipsoid intersection
//! (shared/math/sigg-quadric.md §4: glyph-near origin, stable roots), a BVH, rayon.
//!
//! It follows the GPU's documented rules so that differences are rendering error only: glyphs
//! with the eye inside or on them (E² ≤ [`EYE_INSIDE_E2`]) are not drawn, and a hit in front of
//! the near plane (or beyond the far plane) is not drawn.

pub mod bvh;
pub mod shading;

use glam::{DMat3, DMat4, DVec3};
use rayon::prelude::*;

use crate::camera::Camera;
use crate::render::headless::{Frame, FrameRequest};
use crate::scene::{GlyphGeometry, Scene};
use bvh::{Aabb, Bvh};

/// Same constant as `EYE_INSIDE_E2` in shaders/gumhold_ellipsoid.wgsl.
pub const EYE_INSIDE_E2: f64 = 1.00001;

/// One glyph prepared for ray casting (all relative to the scene origin).
struct Prepared {
    centre: DVec3,
    t_inv: DMat3,
    base: DVec3,
    drawn: bool,
}

/// A ray's front-most hit.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub instance: u32,
    /// World point relative to the scene origin.
    pub point: DVec3,
    /// Unit outward normal (world).
    pub normal: DVec3,
    pub t: f64,
}

/// The reference scene: prepared glyphs and their BVH for one camera.
pub struct ReferenceScene<'a> {
    scene: &'a Scene,
    camera: Camera,
    glyphs: Vec<Prepared>,
    bvh: Bvh,
    view: DMat4,
}

impl<'a> ReferenceScene<'a> {
    pub fn new(scene: &'a Scene, camera: &Camera) -> Self {
        let eye = camera.eye - scene.origin;
        let ortho = camera.is_ortho();
        let (glyphs, boxes): (Vec<Prepared>, Vec<Aabb>) = scene
            .instances
            .par_iter()
            .map(|g| {
                let geo = GlyphGeometry::of(g);
                let t_inv = geo.t_inv();
                let e2 = (t_inv * (eye - geo.centre)).length_squared();
                let [r, gg, b, _] = g.color_rgba();
                let h = geo.half_extents();
                (
                    Prepared {
                        centre: geo.centre,
                        t_inv,
                        base: DVec3::new(f64::from(r), f64::from(gg), f64::from(b)) / 255.0,
                        drawn: ortho || e2 > EYE_INSIDE_E2,
                    },
                    Aabb {
                        lo: geo.centre - h,
                        hi: geo.centre + h,
                    },
                )
            })
            .unzip();
        Self {
            scene,
            camera: *camera,
            bvh: Bvh::build(&boxes),
            glyphs,
            view: camera.view(scene.origin),
        }
    }

    /// Glyphs not drawn because the eye is inside or on them.
    pub fn culled_eye_inside(&self) -> usize {
        self.glyphs.iter().filter(|g| !g.drawn).count()
    }

    /// Front-most visible hit of the ray through NDC (x, y).
    pub fn trace_ndc(&self, x: f64, y: f64) -> Option<Hit> {
        let ray = self.camera.ray_ndc(x, y);
        let origin = ray.origin - self.scene.origin;
        let dir = ray.dir;
        let forward = self.camera.forward();
        let eye_rel = self.camera.eye - self.scene.origin;
        let mut best: Option<Hit> = None;
        self.bvh.traverse(origin, dir, |i| {
            let g = &self.glyphs[i as usize];
            if !g.drawn {
                return None;
            }
            let (t, p_t) = intersect_ellipsoid(origin, dir, g.centre, &g.t_inv)?;
            // Depth range: the GPU discards hits outside [near, far].
            let dist = if self.camera.is_ortho() {
                t
            } else {
                (origin + dir * t - eye_rel).dot(forward)
            };
            if dist < self.camera.near || dist > self.camera.far {
                return None;
            }
            if best.is_none_or(|b| t < b.t) {
                best = Some(Hit {
                    instance: i,
                    point: origin + dir * t,
                    normal: (g.t_inv * p_t).normalize(),
                    t,
                });
            }
            Some(t)
        });
        best
    }

    /// Render a whole frame (pixel-centre rays) into the same form the GPU returns.
    pub fn render(&self, req: &FrameRequest) -> Frame {
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        let ortho = self.camera.is_ortho();
        let bg = req.background.map(shading::to_unorm8);
        let start = std::time::Instant::now();
        let rows: Vec<(Vec<u8>, Vec<u32>, Vec<[f32; 4]>)> = (0..h)
            .into_par_iter()
            .map(|j| {
                let mut color = Vec::with_capacity(w * 4);
                let mut ids = Vec::with_capacity(w);
                let mut aux = Vec::with_capacity(w);
                for i in 0..w {
                    let (x, y) = self.camera.pixel_to_ndc(i as f64 + 0.5, j as f64 + 0.5);
                    match self.trace_ndc(x, y) {
                        None => {
                            color.extend_from_slice(&bg);
                            ids.push(0);
                            aux.push([0.0; 4]);
                        }
                        Some(hit) => {
                            let g = &self.glyphs[hit.instance as usize];
                            let p_view = self.view.transform_point3(hit.point);
                            let n_view = self.view.transform_vector3(hit.normal).normalize();
                            let c = shading::shade(&req.lighting, ortho, g.base, n_view, p_view);
                            color.extend_from_slice(&[
                                shading::to_unorm8(c.x),
                                shading::to_unorm8(c.y),
                                shading::to_unorm8(c.z),
                                255,
                            ]);
                            ids.push(hit.instance + 1);
                            aux.push([
                                n_view.x as f32,
                                n_view.y as f32,
                                n_view.z as f32,
                                p_view.z as f32,
                            ]);
                        }
                    }
                }
                (color, ids, aux)
            })
            .collect();
        let elapsed = start.elapsed().as_secs_f64() * 1e3;
        let mut frame = Frame {
            width: self.camera.width,
            height: self.camera.height,
            frame_ms: vec![elapsed],
            ..Frame::default()
        };
        let mut aux = Vec::with_capacity(w * h);
        for (c, i, a) in rows {
            frame.color.extend(c);
            frame.ids.extend(i);
            aux.extend(a);
        }
        frame.aux = req.aux.then_some(aux);
        frame
    }
}

/// Front intersection of the ray `o + t d` (d unit) with the ellipsoid |T⁻¹(p − c)| = 1:
/// `(t, p~)`. The origin is first moved next to the glyph so nothing cancels for distant glyphs.
/// An origin inside gives the exit point (the only forward hit).
pub fn intersect_ellipsoid(o: DVec3, d: DVec3, c: DVec3, t_inv: &DMat3) -> Option<(f64, DVec3)> {
    let t0 = (c - o).dot(d);
    let o_t = *t_inv * ((o - c) + d * t0);
    let v_t = *t_inv * d;
    let alpha = v_t.length_squared();
    let beta = o_t.dot(v_t);
    let gamma = o_t.length_squared() - 1.0;
    let disc = beta * beta - alpha * gamma;
    if !(disc >= 0.0) || alpha <= 0.0 {
        return None;
    }
    let q = -(beta + beta.signum() * disc.sqrt());
    let (r1, r2) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / alpha, gamma / q)
    };
    let (near, far) = (r1.min(r2), r1.max(r2));
    let tp = if t0 + near > 0.0 {
        near
    } else if t0 + far > 0.0 {
        far
    } else {
        return None;
    };
    Some((t0 + tp, o_t + v_t * tp))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v3(v: &serde_json::Value) -> DVec3 {
        DVec3::new(
            v[0].as_f64().unwrap(),
            v[1].as_f64().unwrap(),
            v[2].as_f64().unwrap(),
        )
    }

    fn m3(v: &serde_json::Value) -> DMat3 {
        DMat3::from_cols(v3(&v[0]), v3(&v[1]), v3(&v[2])).transpose()
    }

    #[test]
    fn ellipsoid_hits_match_the_test_vectors() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared/math/test-vectors.json"
        ))
        .unwrap();
        let all: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut checked = 0;
        for case in all["cases"].as_array().unwrap() {
            if case["kind"] != "ellipsoid" {
                continue;
            }
            let id = case["id"].as_str().unwrap();
            let e = &case["expected"];
            let t = m3(&case["glyph"]["T"]);
            let c = v3(&case["glyph"]["c"]);
            let t_inv = t.inverse();
            let o = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let hit = intersect_ellipsoid(o, d, c, &t_inv);
            assert_eq!(hit.is_some(), e["hit"].as_bool().unwrap(), "{id}");
            let Some((tt, p_t)) = hit else { continue };
            let size = case["glyph"]["radii"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .fold(0.0, f64::max);
            let point = o + d * tt;
            // 1e-9 glyph sizes relative to the centre, as test-vectors.md suggests.
            assert!(
                ((point - c) - (v3(&e["point"]) - c)).length() <= 1e-9 * size,
                "{id}: point {point} vs {}",
                v3(&e["point"])
            );
            let n = (t_inv * p_t).normalize();
            let want_n = v3(&e["normal"]);
            let front = e["front_facing"].as_bool().unwrap();
            // For the eye-inside case the vectors give the outward normal of the inner surface.
            assert!(
                (n - want_n).length() <= 1e-9,
                "{id}: normal {n} vs {want_n} ({front})"
            );
            checked += 1;
        }
        assert!(checked >= 9, "only {checked} ellipsoid cases");
    }
}
