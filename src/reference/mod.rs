//! The exact reference: an f64 CPU ray caster of the very same glyph instances, camera and
//! lighting as the GPU. Pixel-centre rays, each kind's exact intersection
//! ([`crate::shape::Shape::exact`]: glyph-near origins, stable roots), a BVH, rayon.
//!
//! It follows the GPU's documented rules so that differences are rendering error only: glyphs
//! with the eye inside or on them ([`crate::shape::Exact::contains`]; ellipsoids: E² ≤
//! [`crate::shape::rules::EYE_INSIDE_E2`]) are not drawn, and a hit in front of the near plane
//! (or beyond the far plane) is not drawn.

pub mod bvh;

use glam::{DMat4, DVec3};
use rayon::prelude::*;

use crate::camera::Camera;
use crate::effects::outline::{Sample, outline_mask};
use crate::effects::{ao, light};
use crate::frame::Frame;
use crate::request::FrameRequest;
use crate::scene::underlay::grey;
use crate::scene::{GlyphGeometry, Scene};
use crate::shape::rules::drawable_radii;
use crate::shape::{Exact, RayHit};
use crate::twin::common::{shade, to_unorm8};
use crate::twin::composite::{Key, composite};
use bvh::{Aabb, Bvh};

/// One image row: colour, ids, aux, and the geometry deferred shading needs.
type Row = (Vec<u8>, Vec<u32>, Vec<[f32; 4]>, Vec<Option<Surface>>);

/// What a pixel's ray found, for deferred shading: the exact f64 geometry buffer.
#[derive(Debug, Clone, Copy)]
struct Surface {
    base: DVec3,
    n_view: DVec3,
    p_view: DVec3,
    /// World point (relative to the scene origin) and unit normal, for shadow rays.
    point: DVec3,
    normal: DVec3,
}

/// One glyph prepared for ray casting (all relative to the scene origin).
struct Prepared {
    shape: Box<dyn Exact>,
    base: DVec3,
    drawn: bool,
    /// Drawable: casts shadows whether or not the eye is inside it.
    casts: bool,
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
    /// Each underlay plane's corner as placed for this camera, relative to the scene origin.
    underlay_corners: Vec<DVec3>,
}

impl<'a> ReferenceScene<'a> {
    /// The scene's glyphs, each drawn as its kind ([`Scene::kind_of`]), for one camera.
    pub fn new(scene: &'a Scene, camera: &Camera) -> Self {
        let eye = camera.eye - scene.origin;
        let ortho = camera.is_ortho();
        let (glyphs, boxes): (Vec<Prepared>, Vec<Aabb>) = scene
            .instances
            .par_iter()
            .enumerate()
            .map(|(i, g)| {
                let geo = GlyphGeometry::of(g);
                let [r, gg, b, _] = g.color_rgba();
                let shape = scene
                    .kind_of(i)
                    .shape()
                    .exact_with(&geo, scene.payload.as_ref());
                let (h, eye_inside) = (shape.half_extents(), shape.contains(eye));
                let drawable = drawable_radii(g.radii);
                // An undrawn glyph's box may be NaN: keep the BVH finite.
                let h = if drawable { h } else { DVec3::ZERO };
                (
                    Prepared {
                        shape,
                        base: DVec3::new(f64::from(r), f64::from(gg), f64::from(b)) / 255.0,
                        drawn: (ortho || !eye_inside) && drawable,
                        casts: drawable,
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
            underlay_corners: scene
                .underlay
                .iter()
                .flat_map(|u| &u.planes)
                .map(|p| p.geometry.placed_corner(camera) - scene.origin)
                .collect(),
        }
    }

    /// Whether a hit at ray parameter `t` of the ray from `origin` along `dir` (relative to
    /// the scene origin) is within the depth range the GPU keeps.
    fn in_depth_range(&self, origin: DVec3, dir: DVec3, t: f64) -> bool {
        let dist = if self.camera.is_ortho() {
            t
        } else {
            (origin + dir * t - (self.camera.eye - self.scene.origin)).dot(self.camera.forward())
        };
        dist >= self.camera.near && dist <= self.camera.far
    }

    /// The nearest underlay texel the ray through NDC (x, y) meets: (t, grey level).
    pub fn trace_underlay(&self, x: f64, y: f64, window: [f32; 2]) -> Option<(f64, f32)> {
        let underlay = self.scene.underlay.as_ref()?;
        let ray = self.camera.ray_ndc(x, y);
        let origin = ray.origin - self.scene.origin;
        let mut best: Option<(f64, f32)> = None;
        for (p, &corner) in underlay.planes.iter().zip(&self.underlay_corners) {
            let Some((t, s, r)) = p.geometry.intersect(corner, origin, ray.dir) else {
                continue;
            };
            if !self.in_depth_range(origin, ray.dir, t) || best.is_some_and(|b| b.0 <= t) {
                continue;
            }
            if let Some(g) = grey(p.texel(s, r), window) {
                best = Some((t, g));
            }
        }
        best
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
        let mut best: Option<Hit> = None;
        self.bvh.traverse(origin, dir, |i| {
            let g = &self.glyphs[i as usize];
            if !g.drawn {
                return None;
            }
            let RayHit { t, normal } = g.shape.intersect(origin, dir)?;
            // Depth range: the GPU discards hits outside [near, far].
            if !self.in_depth_range(origin, dir, t) {
                return None;
            }
            if best.is_none_or(|b| t < b.t) {
                best = Some(Hit {
                    instance: i,
                    point: origin + dir * t,
                    normal,
                    t,
                });
            }
            Some(t)
        });
        best
    }

    /// The depth-buffer value (standard Z, [`Camera::ndc_depth`]) at which the ray through the
    /// centre of pixel (i, j) meets instance `instance`, as drawn here: `None` where it misses,
    /// the glyph is not drawn or the hit lies outside the depth range. The metrics' tie test
    /// ([`crate::metrics::Accuracy::with_ties`]).
    pub fn depth_of(&self, instance: usize, i: u32, j: u32) -> Option<f64> {
        let g = self.glyphs.get(instance).filter(|g| g.drawn)?;
        let (x, y) = self
            .camera
            .pixel_to_ndc(f64::from(i) + 0.5, f64::from(j) + 0.5);
        let ray = self.camera.ray_ndc(x, y);
        let origin = ray.origin - self.scene.origin;
        let t = g.shape.intersect(origin, ray.dir)?.t;
        if !self.in_depth_range(origin, ray.dir, t) {
            return None;
        }
        let dist = if self.camera.is_ortho() {
            t
        } else {
            (origin + ray.dir * t - (self.camera.eye - self.scene.origin))
                .dot(self.camera.forward())
        };
        Some(self.camera.ndc_depth(dist))
    }

    /// Render a whole frame (pixel-centre rays) into the same form the GPU returns.
    pub fn render(&self, req: &FrameRequest) -> Frame {
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        let ortho = self.camera.is_ortho();
        let bg = req.background.map(to_unorm8);
        let window = self
            .scene
            .underlay
            .as_ref()
            .filter(|_| req.underlay.shown)
            .map(|u| req.underlay.window.unwrap_or(u.window));
        let deferred = req.effects.deferred();
        let start = web_time::Instant::now();
        let rows: Vec<Row> = (0..h)
            .into_par_iter()
            .map(|j| {
                let mut color = Vec::with_capacity(w * 4);
                let mut ids = Vec::with_capacity(w);
                let mut aux = Vec::with_capacity(w);
                let mut surfaces = Vec::with_capacity(if deferred { w } else { 0 });
                for i in 0..w {
                    let (x, y) = self.camera.pixel_to_ndc(i as f64 + 0.5, j as f64 + 0.5);
                    let hit = self.trace_ndc(x, y);
                    // The underlay is drawn where it is nearer than the glyph (or there is none).
                    let under = window
                        .and_then(|w| self.trace_underlay(x, y, w))
                        .filter(|(t, _)| hit.is_none_or(|h| *t < h.t));
                    if deferred {
                        surfaces.push(None);
                    }
                    if let Some((_, g)) = under {
                        let g = to_unorm8(f64::from(g));
                        color.extend_from_slice(&[g, g, g, 255]);
                        ids.push(0);
                        aux.push([0.0; 4]);
                        continue;
                    }
                    match hit {
                        None => {
                            color.extend_from_slice(&bg);
                            ids.push(0);
                            aux.push([0.0; 4]);
                        }
                        Some(hit) => {
                            let g = &self.glyphs[hit.instance as usize];
                            let p_view = self.view.transform_point3(hit.point);
                            let c_view = self.view.transform_point3(g.shape.centre());
                            let n_view = self.view.transform_vector3(hit.normal).normalize();
                            let base = g.shape.tint(hit.point, g.base);
                            let c = shade(&req.lighting, ortho, base, n_view, p_view);
                            if let Some(last) = surfaces.last_mut() {
                                *last = Some(Surface {
                                    base,
                                    n_view,
                                    p_view,
                                    point: hit.point,
                                    normal: hit.normal,
                                });
                            }
                            color.extend_from_slice(&[
                                to_unorm8(c.x),
                                to_unorm8(c.y),
                                to_unorm8(c.z),
                                255,
                            ]);
                            ids.push(hit.instance + 1);
                            aux.push([
                                n_view.x as f32,
                                n_view.y as f32,
                                n_view.z as f32,
                                (p_view.z - c_view.z) as f32,
                            ]);
                        }
                    }
                }
                (color, ids, aux, surfaces)
            })
            .collect();
        let mut frame = Frame {
            width: self.camera.width,
            height: self.camera.height,
            ..Frame::default()
        };
        let mut aux = Vec::with_capacity(w * h);
        let mut surfaces = Vec::with_capacity(if deferred { w * h } else { 0 });
        for (c, i, a, g) in rows {
            frame.color.extend(c);
            frame.ids.extend(i);
            aux.extend(a);
            surfaces.extend(g);
        }
        if deferred {
            self.apply_effects(req, &surfaces, &mut frame);
        }
        frame.aux = req.aux.then_some(aux);
        frame.frame_ms = vec![start.elapsed().as_secs_f64() * 1e3];
        frame
    }

    /// Deferred shading of a rendered frame from its exact geometry: the outline filter over
    /// the f64 buffers, hard shadows from exact shadow rays, ambient occlusion from exact
    /// hemisphere rays ([`crate::effects::ao`]), and the shading of
    /// [`crate::twin::composite::composite`]. Pixels without a surface (background, underlay)
    /// keep their colour.
    fn apply_effects(&self, req: &FrameRequest, surfaces: &[Option<Surface>], frame: &mut Frame) {
        let fx = &req.effects;
        let ortho = self.camera.is_ortho();
        let (w, h) = (frame.width, frame.height);
        let outlines = fx.outlines.map(|o| {
            let samples: Vec<Sample> = surfaces
                .iter()
                .zip(&frame.ids)
                .map(|(s, &id)| match s {
                    Some(s) => Sample {
                        id,
                        normal: s.n_view,
                        distance: -s.p_view.z,
                    },
                    None => Sample {
                        id: 0,
                        normal: DVec3::ZERO,
                        distance: 0.0,
                    },
                })
                .collect();
            (o, outline_mask(&samples, w, h, o.width))
        });
        let ao = fx.ao.map(|a| {
            let r = ao::reach(self.scene, &a);
            (a, r, ao::hemisphere(ao::REFERENCE_DIRECTIONS))
        });
        let key = fx.shadows.map(|s| {
            (
                light::view_direction(s.light).unwrap_or(DVec3::Z),
                light::world_direction(&self.camera, &s),
            )
        });
        let shaded: Vec<([u8; 4], [f32; 3])> = surfaces
            .par_iter()
            .enumerate()
            .map(|(k, s)| {
                let old = &frame.color[4 * k..4 * k + 4];
                let Some(s) = s else {
                    return ([old[0], old[1], old[2], old[3]], [1.0, 0.0, 1.0]);
                };
                let open = ao
                    .as_ref()
                    .map(|(_, reach, dirs)| self.open_fraction(s.point, s.normal, *reach, dirs));
                let factor = match (&ao, open) {
                    (Some((a, _, _)), Some(open)) => a.factor(open),
                    _ => 1.0,
                };
                // A surface facing away from the light is in its own (attached) shadow.
                let lit = key.map(|(l_view, l_world)| Key {
                    light: l_view,
                    lit: if s.n_view.dot(l_view) <= 0.0
                        || self.in_shadow(s.point, s.normal, l_world)
                    {
                        0.0
                    } else {
                        1.0
                    },
                });
                let edge = outlines.as_ref().filter(|(_, m)| m[k]).map(|(o, _)| o);
                let c = composite(
                    &req.lighting,
                    ortho,
                    s.base,
                    s.n_view,
                    s.p_view,
                    lit,
                    factor,
                    edge,
                );
                (
                    [to_unorm8(c.x), to_unorm8(c.y), to_unorm8(c.z), 255],
                    [
                        lit.map_or(1.0, |k| k.lit as f32),
                        if edge.is_some() { 1.0 } else { 0.0 },
                        open.map_or(1.0, |o| o as f32),
                    ],
                )
            })
            .collect();
        let mut effects = Vec::with_capacity(shaded.len());
        for (k, (c, e)) in shaded.into_iter().enumerate() {
            frame.color[4 * k..4 * k + 4].copy_from_slice(&c);
            effects.push(e);
        }
        frame.effects = (req.aux && fx.any()).then_some(effects);
    }

    /// The exact open fraction of the sky at `point` (normal `normal`, both relative to the
    /// scene origin): the share of `dirs` (about +z, turned to the normal) whose ray meets no
    /// glyph within `reach`.
    fn open_fraction(&self, point: DVec3, normal: DVec3, reach: f64, dirs: &[DVec3]) -> f64 {
        let scale = point.abs().max_element().max(self.scene.radius).max(1e-300);
        let origin = point + normal * (scale * 1e-9);
        let [a, b, n] = ao::frame(normal);
        let open = dirs
            .iter()
            .filter(|d| {
                let dir = a * d.x + b * d.y + n * d.z;
                let mut hit = false;
                self.bvh.traverse(origin, dir, |i| {
                    if hit {
                        return Some(0.0);
                    }
                    let g = &self.glyphs[i as usize];
                    if !g.casts {
                        return None;
                    }
                    let t = g.shape.intersect(origin, dir)?.t;
                    (t > 0.0 && t < reach).then(|| {
                        hit = true;
                        0.0
                    })
                });
                !hit
            })
            .count();
        open as f64 / dirs.len().max(1) as f64
    }

    /// Whether a glyph lies between the surface point `point` (normal `normal`, both relative to
    /// the scene origin) and a directional light towards `to_light`: the exact hard shadow.
    /// The ray starts a hair off the surface, so that it leaves the glyph it starts on where the
    /// surface faces the light and enters it where it faces away.
    fn in_shadow(&self, point: DVec3, normal: DVec3, to_light: DVec3) -> bool {
        let scale = point.abs().max_element().max(self.scene.radius).max(1e-300);
        let origin = point + normal * (scale * 1e-9);
        let mut hit = false;
        self.bvh.traverse(origin, to_light, |i| {
            if hit {
                return Some(0.0);
            }
            let g = &self.glyphs[i as usize];
            if !g.casts {
                return None;
            }
            let t = g.shape.intersect(origin, to_light)?.t;
            (t > 0.0).then(|| {
                hit = true;
                0.0
            })
        });
        hit
    }
}
