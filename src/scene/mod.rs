//! What the renderers draw: GPU-ready glyph instances of one kind around a scene origin (and,
//! over them, glyphs of a second kind: [`Overlay`]), and the bounds the camera frames. Built on
//! the CPU, uploaded by the renderer, ray cast by the reference.

use glam::{DQuat, DVec3};

pub use crate::shape::{GlyphGeometry, GlyphInstance, GlyphKind};

pub mod odf;
pub mod underlay;

pub use underlay::{Underlay, UnderlaySource};

/// Glyph instances of one kind relative to `origin`, plus a bounding sphere in world space.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// The kind the instances were made for: every back end draws them as this kind (those
    /// from [`Overlay::first`] on as the overlay's).
    pub kind: GlyphKind,
    /// World point that instance centres are relative to (keeps f32 precise far from 0).
    pub origin: DVec3,
    pub instances: Vec<GlyphInstance>,
    /// Bounding sphere of all glyphs (world): the box `centre ± half` and its circumsphere.
    pub centre: DVec3,
    pub radius: f64,
    pub half: DVec3,
    /// A scalar image under the glyphs (`--underlay`), if asked for.
    pub underlay: Option<Underlay>,
    /// Per-glyph values the instances' parameter words index (ODF series), if the kind keeps
    /// any ([`crate::shape::Payload`]).
    pub payload: Option<std::sync::Arc<crate::shape::Payload>>,
    /// Glyphs of a second kind in the same frame (peaks over ODFs), if any.
    pub overlay: Option<Overlay>,
}

/// The instances of a scene from `first` on, drawn as `kind`: glyphs of a second kind in the same
/// frame, where depth decides between any two glyphs whatever their kinds (`render --peaks`: the
/// sticks of the peaks over the ODF glyphs). Ids name instances across both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Overlay {
    pub kind: GlyphKind,
    pub first: usize,
}

/// One glyph given directly by world centre, frame and radii (tests, synthetic scenes).
#[derive(Debug, Clone, Copy)]
pub struct GlyphSpec {
    pub centre: DVec3,
    pub rotation: DQuat,
    pub radii: DVec3,
    pub color: [u8; 4],
}

impl Scene {
    /// A scene from world-space glyphs; the origin is the centre of their bounding box.
    pub fn from_specs(specs: &[GlyphSpec]) -> Self {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for s in specs {
            let r = s.radii.max_element();
            lo = lo.min(s.centre - r);
            hi = hi.max(s.centre + r);
        }
        let origin = if specs.is_empty() {
            DVec3::ZERO
        } else {
            (lo + hi) / 2.0
        };
        let instances = specs
            .iter()
            .zip(0u32..)
            .map(|(s, glyph)| {
                let c = s.centre - origin;
                let q = s.rotation.normalize();
                GlyphInstance {
                    centre: [c.x as f32, c.y as f32, c.z as f32],
                    color: GlyphInstance::pack_color(s.color),
                    rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                    radii: [s.radii.x as f32, s.radii.y as f32, s.radii.z as f32],
                    glyph,
                    shape: [0; 2],
                }
            })
            .collect();
        Self::from_instances(origin, instances)
    }

    /// Wrap ready instances as ellipsoids; computes the bounding sphere (holding the glyphs as
    /// ellipsoids or as cylinders, so framing and the far plane never cut a glyph).
    pub fn from_instances(origin: DVec3, instances: Vec<GlyphInstance>) -> Self {
        Self::from_instances_as(origin, instances, GlyphKind::Ellipsoid)
    }

    /// [`Self::from_instances`] as glyphs of `kind`, with bounds holding them
    /// ([`crate::shape::Shape::bounds`]).
    pub fn from_instances_as(
        origin: DVec3,
        instances: Vec<GlyphInstance>,
        kind: GlyphKind,
    ) -> Self {
        let shape = kind.shape();
        let mut instances = instances;
        {
            use rayon::prelude::*;
            instances.par_iter_mut().for_each(|g| *g = g.stored());
        }
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for g in &instances {
            let geo = GlyphGeometry::of(g);
            let h = shape.bounds(&geo);
            lo = lo.min(geo.centre - h);
            hi = hi.max(geo.centre + h);
        }
        let (centre, half) = if instances.is_empty() {
            (origin, DVec3::splat(1.0 / 3f64.sqrt()))
        } else {
            ((lo + hi) / 2.0 + origin, (hi - lo) / 2.0)
        };
        Self {
            kind,
            origin,
            instances,
            centre,
            radius: half.length(),
            half,
            underlay: None,
            payload: None,
            overlay: None,
        }
    }

    /// The same glyphs drawn as `kind` ([`crate::shape::Shape::adopt`]: instances made
    /// without a kind's parameters get them), keeping this scene's framing: a synthetic scene
    /// frames what it means to show.
    /// An overlay's instances keep their kind.
    pub fn drawn_as(&self, kind: GlyphKind) -> Scene {
        let shape = kind.shape();
        let own = self.parts()[0].1.clone();
        let mut instances = self.instances.clone();
        for g in &mut instances[own] {
            *g = shape.adopt(g).stored();
        }
        Scene {
            kind,
            instances,
            ..self.clone()
        }
    }

    pub fn geometry(&self, instance: usize) -> GlyphGeometry {
        GlyphGeometry::of(&self.instances[instance])
    }

    /// The kind instance `i` is drawn as.
    pub fn kind_of(&self, i: usize) -> GlyphKind {
        match self.overlay {
            Some(o) if i >= o.first => o.kind,
            _ => self.kind,
        }
    }

    /// The scene's runs of instances by kind, in order: its own kind's, then the overlay's (both
    /// present even when empty).
    pub fn parts(&self) -> Vec<(GlyphKind, std::ops::Range<usize>)> {
        let n = self.instances.len();
        match self.overlay {
            Some(o) => {
                let first = o.first.min(n);
                vec![(self.kind, 0..first), (o.kind, first..n)]
            }
            None => vec![(self.kind, 0..n)],
        }
    }

    /// This scene with `over`'s glyphs drawn over it as an [`Overlay`] of `over`'s kind: its
    /// instances moved to this scene's origin, the bounds holding both. `over` brings nothing
    /// else (no underlay, payload or overlay of its own are kept): its kind must keep no
    /// per-glyph values.
    pub fn with_overlay(mut self, over: Scene) -> Scene {
        debug_assert!(over.payload.is_none() && over.overlay.is_none());
        let shift = (over.origin - self.origin).as_vec3();
        let first = self.instances.len();
        let over_empty = over.instances.is_empty();
        self.instances
            .extend(over.instances.into_iter().map(|mut g| {
                g.centre = (glam::Vec3::from(g.centre) + shift).into();
                g
            }));
        if !over_empty {
            let (lo, hi) = if first == 0 {
                (over.centre - over.half, over.centre + over.half)
            } else {
                (
                    (self.centre - self.half).min(over.centre - over.half),
                    (self.centre + self.half).max(over.centre + over.half),
                )
            };
            self.centre = (lo + hi) / 2.0;
            self.half = (hi - lo) / 2.0;
            self.radius = self.half.length();
        }
        self.overlay = Some(Overlay {
            kind: over.kind,
            first,
        });
        self
    }
}

impl Scene {
    /// Instances for every glyph of `set`, sized and coloured by `style`, around the centre of
    /// the glyph centres' bounding box (camera-relative precision).
    pub fn build(
        set: &crate::glyph::GlyphSet,
        style: &crate::glyph::ResolvedStyle,
        glyph: GlyphKind,
    ) -> Self {
        Self::build_with_progress(set, style, glyph, &crate::progress::Silent)
    }

    /// [`Self::build`], advancing `progress` by the number of instances made (in steps of
    /// [`PROGRESS_STEP`]).
    pub fn build_with_progress(
        set: &crate::glyph::GlyphSet,
        style: &crate::glyph::ResolvedStyle,
        glyph: GlyphKind,
        progress: &dyn crate::progress::Progress,
    ) -> Self {
        use rayon::prelude::*;
        let shape = glyph.shape();
        let origin = centre_box_middle(set);
        let n = set.glyphs.len();
        let instances = set
            .glyphs
            .par_iter()
            .enumerate()
            .flat_map_iter(|(k, g)| {
                if (k + 1) % PROGRESS_STEP == 0 {
                    progress.advance(PROGRESS_STEP as u64);
                }
                instances(g, k, origin, style, shape)
            })
            .collect();
        progress.advance((n % PROGRESS_STEP) as u64);
        Self::from_instances_as(origin, instances, glyph)
    }

    /// The bounding box (centre, half extents) that [`Self::build`] would give the scene of
    /// `set`, without making the instances: to frame the whole field while drawing a selection
    /// of it. Equal to the built scene's up to rounding.
    pub fn bounding_box(
        set: &crate::glyph::GlyphSet,
        style: &crate::glyph::ResolvedStyle,
        glyph: GlyphKind,
    ) -> (DVec3, DVec3) {
        use rayon::prelude::*;
        let shape = glyph.shape();
        let origin = centre_box_middle(set);
        if set.glyphs.is_empty() {
            return (origin, DVec3::splat(1.0 / 3f64.sqrt()));
        }
        let empty = || (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (lo, hi) = set
            .glyphs
            .par_iter()
            .enumerate()
            .fold(empty, |(lo, hi), (k, g)| {
                instances(g, k, origin, style, shape).fold((lo, hi), |(lo, hi), inst| {
                    let geo = GlyphGeometry::of(&inst.stored());
                    let h = shape.bounds(&geo);
                    (lo.min(geo.centre - h), hi.max(geo.centre + h))
                })
            })
            .reduce(empty, |a, b| (a.0.min(b.0), a.1.max(b.1)));
        ((lo + hi) / 2.0 + origin, (hi - lo) / 2.0)
    }

    /// How many glyphs the camera cannot draw: eye inside or on them (Gumhold's quad does not
    /// exist there), entirely behind the near plane, or with degenerate radii; and how many the
    /// vertex stage culls (outside the frustum when `frustum`, projected smaller than
    /// `min_pixel_radius`): the f64 twin of `skip_glyph` in common.wgsl.
    pub fn visibility(
        &self,
        camera: &crate::camera::Camera,
        frustum: bool,
        min_pixel_radius: f32,
    ) -> Visibility {
        self.visibility_of(0..self.instances.len(), camera, frustum, min_pixel_radius)
    }

    /// [`Self::visibility`] of the instances in `run` (one kind's: [`Self::parts`]).
    pub fn visibility_of(
        &self,
        run: std::ops::Range<usize>,
        camera: &crate::camera::Camera,
        frustum: bool,
        min_pixel_radius: f32,
    ) -> Visibility {
        let eye = camera.eye - self.origin;
        let f = camera.forward();
        let culling = Culling::new(camera, self.origin, frustum, min_pixel_radius);
        let mut v = Visibility::default();
        for (i, g) in self
            .instances
            .iter()
            .enumerate()
            .take(run.end)
            .skip(run.start)
        {
            let shape = self.kind_of(i).shape();
            if !crate::shape::rules::drawable_radii(g.radii) {
                v.degenerate += 1;
                continue;
            }
            let geo = GlyphGeometry::of(g);
            let r = geo.max_radius();
            if (geo.centre - eye).dot(f) + r < camera.near {
                v.behind_camera += 1;
            } else if culling.skips(geo.centre, shape.cull_radius(g.radii)) {
                v.culled += 1;
            } else if !camera.is_ortho()
                && shape.exact_with(&geo, self.payload.as_ref()).contains(eye)
            {
                v.eye_inside += 1;
            }
        }
        v
    }
}

/// Instances between two progress-bar updates of [`Scene::build_with_progress`].
pub const PROGRESS_STEP: usize = 1 << 16;

/// The middle of the glyph centres' bounding box (the scene origin), 0 for no glyphs.
fn centre_box_middle(set: &crate::glyph::GlyphSet) -> DVec3 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for g in &set.glyphs {
        let c = DVec3::from(g.centre);
        lo = lo.min(c);
        hi = hi.max(c);
    }
    if set.glyphs.is_empty() {
        DVec3::ZERO
    } else {
        (lo + hi) / 2.0
    }
}

/// The GPU instances of glyph `g` (glyph index `k`) around `origin`: one per part its kind
/// places ([`crate::shape::Shape::place`]).
fn instances<'a>(
    g: &'a crate::glyph::Glyph,
    k: usize,
    origin: DVec3,
    style: &'a crate::glyph::ResolvedStyle,
    shape: &'a dyn crate::shape::Shape,
) -> impl Iterator<Item = GlyphInstance> + 'a {
    (0..shape.parts()).filter_map(move |part| {
        let p = shape.place(g, part, style)?;
        let mut c = DVec3::from(g.centre) - origin;
        if p.offset != [0.0; 3] {
            c += DVec3::from(p.offset);
        }
        Some(GlyphInstance {
            centre: [c.x as f32, c.y as f32, c.z as f32],
            color: GlyphInstance::pack_color(p.color),
            rotation: p.rotation,
            radii: p.radii,
            glyph: k as u32,
            shape: p.params,
        })
    })
}

/// Glyphs that are not drawn for a camera, and why.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Visibility {
    pub eye_inside: usize,
    pub behind_camera: usize,
    /// Radii not all finite, positive and ≥ 2⁻²⁴ of the largest: no method draws these.
    pub degenerate: usize,
    /// Culled in the vertex stage: outside the view frustum or below the pixel size asked for.
    pub culled: usize,
}

/// The culling test of `skip_glyph` in common.wgsl, in f64.
struct Culling<'c> {
    camera: &'c crate::camera::Camera,
    origin: DVec3,
    /// The frustum planes, when culling by frustum.
    planes: Option<[glam::DVec4; 6]>,
    min_px: f64,
}

impl<'c> Culling<'c> {
    fn new(camera: &'c crate::camera::Camera, origin: DVec3, frustum: bool, min_px: f32) -> Self {
        Self {
            camera,
            origin,
            planes: frustum.then(|| camera.frustum_planes(origin)),
            min_px: f64::from(min_px),
        }
    }

    /// `c` relative to the scene origin.
    fn skips(&self, c: DVec3, r: f64) -> bool {
        let h = c.extend(1.0);
        self.planes
            .is_some_and(|planes| planes.iter().any(|p| p.dot(h) < -r))
            || (self.min_px > 0.0 && self.camera.pixel_radius(c + self.origin, r) < self.min_px)
    }
}

/// Thickness of [`Scene::sort_front_to_back`]'s depth layers, in mean glyph diameters: 2–5
/// measured alike on grid40's splats, 8 slower (nearer glyphs come later within a layer).
pub const LAYER_DIAMETERS: f32 = 3.0;

/// The mean of the instances' largest diameters (finite ones; 0 for none).
fn mean_diameter(instances: &[GlyphInstance]) -> f32 {
    use rayon::prelude::*;
    let (sum, n) = instances
        .par_iter()
        .map(|g| 2.0 * f64::from(g.radii[0].max(g.radii[1]).max(g.radii[2])))
        .filter(|d| d.is_finite())
        .map(|d| (d, 1u64))
        .reduce(|| (0.0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    if n == 0 { 0.0 } else { (sum / n as f64) as f32 }
}

impl Scene {
    /// Reorder the instances front to back in depth layers [`LAYER_DIAMETERS`] mean glyph
    /// diameters thick (by the view depth of their centres), file order within a layer. Nearer
    /// glyphs then come first: with early depth testing they hide later ones before those are
    /// shaded, and the splats' compute pass skips the pixels a nearer splat has already won.
    /// Layers rather than exact depths because consecutive glyphs of an exact order lie on one
    /// plane across the whole image, which a CPU device pays for in lanes and caches: grid40's
    /// superquadric splats took 150 ms in exact order, 133 ms in layers and 160 ms in file
    /// order (lavapipe, before their skip-ahead).
    /// Ids and picking follow `GlyphInstance::glyph`.
    pub fn sort_front_to_back(&mut self, camera: &crate::camera::Camera) {
        use rayon::prelude::*;
        let eye = (camera.eye - self.origin).as_vec3();
        let f = camera.forward().as_vec3();
        let depth = |g: &GlyphInstance| (glam::Vec3::from(g.centre) - eye).dot(f);
        let thickness = LAYER_DIAMETERS * mean_diameter(&self.instances);
        let nearest = self
            .instances
            .par_iter()
            .map(depth)
            .reduce(|| f32::INFINITY, f32::min);
        // Each kind's run is sorted within itself ([`Self::parts`]).
        for (_, run) in self.parts() {
            let run = &mut self.instances[run];
            if thickness > 0.0 && thickness.is_finite() && nearest.is_finite() {
                // Saturating: a NaN depth goes to the front layer, an overflow to the last.
                run.par_sort_by_key(|g| ((depth(g) - nearest) / thickness) as u32);
            } else {
                run.par_sort_by(|a, b| depth(a).total_cmp(&depth(b)));
            }
        }
    }

    /// Whether Gumhold's ellipsoid shader moves every drawable glyph's proxy to its nearest
    /// plane for this camera (its centre is more than 1.5 radii beyond the near plane), so the
    /// depth it writes is never less than the rasterised depth and may be declared so.
    pub fn conservative_depth_holds(&self, camera: &crate::camera::Camera) -> bool {
        let eye = camera.eye - self.origin;
        let f = camera.forward();
        self.instances.iter().all(|g| {
            !crate::shape::rules::drawable_radii(g.radii) || {
                let geo = GlyphGeometry::of(g);
                (geo.centre - eye).dot(f) - 1.5 * geo.max_radius() > camera.near * (1.0 + 1e-6)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::{GlyphStyle, derive_glyphs};
    use crate::staging::field_spacing;
    use std::sync::atomic::{AtomicU64, Ordering};

    /// The synthetic n³ grid's glyphs with the default style.
    fn grid_scene(n: usize, glyph: GlyphKind) -> Scene {
        let field = crate::field::synthetic::grid(n);
        let set = derive_glyphs(&field, &crate::progress::Silent);
        let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
        Scene::build(&set, &style, glyph)
    }
    /// Front to back in layers: every glyph's layer (its view depth past the nearest centre,
    /// in layer thicknesses computed here from the radii) is at most the next one's, file order
    /// within a layer, and the instances are the same ones.
    #[test]
    fn front_to_back_goes_by_layers_in_file_order() {
        for &kind in GlyphKind::VALUES {
            front_to_back_by_layers(grid_scene(9, kind));
        }
    }

    fn front_to_back_by_layers(scene: Scene) {
        let framing = crate::camera::Framing {
            azimuth: 37.0,
            elevation: 21.0,
            ..Default::default()
        };
        let cam = crate::camera::Camera::frame(&framing, scene.centre, scene.radius, 320, 240);
        let mut sorted = scene.clone();
        sorted.sort_front_to_back(&cam);
        let depth = |g: &GlyphInstance| {
            (DVec3::from(g.centre.map(f64::from)) + scene.origin - cam.eye).dot(cam.forward())
        };
        let diameters: Vec<f64> = scene
            .instances
            .iter()
            .map(|g| 2.0 * f64::from(g.radii.into_iter().fold(0.0, f32::max)))
            .collect();
        let thickness =
            f64::from(LAYER_DIAMETERS) * diameters.iter().sum::<f64>() / diameters.len() as f64;
        let nearest = scene
            .instances
            .iter()
            .map(depth)
            .fold(f64::INFINITY, f64::min);
        let layer = |g: &GlyphInstance| (depth(g) - nearest) / thickness;
        let mut layers_seen = 0;
        for w in sorted.instances.windows(2) {
            let (a, b) = (layer(&w[0]), layer(&w[1]));
            // The sort's f32 depths: a glyph within 1e-4 of a layer's boundary may fall on
            // either side of it.
            let clear = |x: f64| (1e-4..1.0 - 1e-4).contains(&x.fract());
            assert!(a.floor() <= b.floor() || a - b < 1e-4, "{a} then {b}");
            if a.floor() == b.floor() && clear(a) && clear(b) {
                // (A glyph's parts share its index and keep their order.)
                assert!(w[0].glyph <= w[1].glyph, "file order within a layer");
            } else {
                layers_seen += 1;
            }
        }
        assert!(layers_seen >= 3, "{layers_seen} layer changes");
        let ids = |s: &Scene| {
            let mut ids: Vec<u32> = s.instances.iter().map(|g| g.glyph).collect();
            ids.sort_unstable();
            ids
        };
        assert_eq!(ids(&sorted), ids(&scene));
        // Glyphs of no size have no layers: exact depth order.
        let mut flat = scene.clone();
        for g in &mut flat.instances {
            g.radii = [0.0; 3];
        }
        flat.sort_front_to_back(&cam);
        assert!(
            flat.instances
                .windows(2)
                .all(|w| depth(&w[0]) <= depth(&w[1]) + 1e-9)
        );
    }

    #[test]
    fn bounding_box_is_the_built_scenes() {
        let field = crate::field::synthetic::grid(7);
        let set = derive_glyphs(&field, &crate::progress::Silent);
        let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
        for &glyph in GlyphKind::VALUES {
            let scene = Scene::build(&set, &style, glyph);
            let (c, half) = Scene::bounding_box(&set, &style, glyph);
            assert!((half - scene.half).length() <= 1e-9 * scene.radius);
            let r = half.length();
            assert!(
                (c - scene.centre).length() <= 1e-9 * scene.radius,
                "{c} vs {}",
                scene.centre
            );
            assert!(
                (r - scene.radius).abs() <= 1e-9 * scene.radius,
                "{r} vs {}",
                scene.radius
            );
        }
        let empty = crate::glyph::GlyphSet::default();
        let scene = Scene::build(&empty, &style, GlyphKind::Ellipsoid);
        assert_eq!(
            Scene::bounding_box(&empty, &style, GlyphKind::Ellipsoid),
            (scene.centre, scene.half)
        );
    }

    #[derive(Default)]
    struct Counter(AtomicU64);

    impl crate::progress::Progress for Counter {
        fn advance(&self, n: u64) {
            self.0.fetch_add(n, Ordering::Relaxed);
        }
    }

    #[test]
    fn progress_counts_every_instance() {
        let field = crate::field::synthetic::grid(41); // 68,921: one full step and a remainder
        let set = derive_glyphs(&field, &crate::progress::Silent);
        let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
        let counted = Counter::default();
        let scene = Scene::build_with_progress(&set, &style, GlyphKind::Ellipsoid, &counted);
        assert_eq!(
            counted.0.load(Ordering::Relaxed),
            scene.instances.len() as u64
        );
        assert_eq!(
            scene.instances,
            Scene::build(&set, &style, GlyphKind::Ellipsoid).instances
        );
    }

    /// An overlay keeps both scenes' glyphs where they were (world centres), each drawn as its
    /// kind, the box holding both; sorting and `drawn_as` keep each kind's instances in its run.
    #[test]
    fn an_overlay_keeps_its_glyphs_and_kind() {
        let spec = |x: f64, r: f64| GlyphSpec {
            centre: DVec3::new(x, 0.0, 0.0),
            rotation: DQuat::IDENTITY,
            radii: DVec3::splat(r),
            color: [255; 4],
        };
        let base = Scene::from_specs(&[spec(0.0, 1.0), spec(20.0, 1.0)]);
        let over = Scene::from_specs(&[spec(-30.0, 0.5), spec(30.0, 0.5), spec(10.0, 0.5)])
            .drawn_as(GlyphKind::Cylinder);
        let world = |s: &Scene| -> Vec<DVec3> {
            (0..s.instances.len())
                .map(|i| s.geometry(i).centre + s.origin)
                .collect()
        };
        let want: Vec<DVec3> = world(&base).into_iter().chain(world(&over)).collect();
        let s = base.clone().with_overlay(over.clone());
        for (got, want) in world(&s).iter().zip(&want) {
            assert!(got.distance(*want) < 1e-6, "{got} {want}");
        }
        assert_eq!(s.kind_of(1), GlyphKind::Ellipsoid);
        assert_eq!(s.kind_of(2), GlyphKind::Cylinder);
        assert_eq!(
            s.parts(),
            vec![(GlyphKind::Ellipsoid, 0..2), (GlyphKind::Cylinder, 2..5)]
        );
        // The box from x = −30.5 to 30.5 (the overlay's), y and z ±1 (the base's).
        let (lo, hi) = (s.centre - s.half, s.centre + s.half);
        assert!(lo.distance(DVec3::new(-30.5, -1.0, -1.0)) < 1e-5, "{lo}");
        assert!(hi.distance(DVec3::new(30.5, 1.0, 1.0)) < 1e-5, "{hi}");
        // Sorted front to back from the iso view (+x nearer): each run in itself.
        let mut sorted = s.clone();
        let framing = crate::camera::Framing::default();
        let camera = crate::camera::Camera::frame(&framing, s.centre, s.radius, 64, 48);
        sorted.sort_front_to_back(&camera);
        let xs: Vec<f64> = world(&sorted).iter().map(|c| c.x.round()).collect();
        assert_eq!(xs, [20.0, 0.0, 30.0, 10.0, -30.0]);
        let shapes = s.drawn_as(GlyphKind::Superquadric);
        assert_eq!(shapes.kind_of(0), GlyphKind::Superquadric);
        assert_eq!(shapes.kind_of(4), GlyphKind::Cylinder);
        assert_eq!(shapes.instances[2..], s.instances[2..]);
    }
}
