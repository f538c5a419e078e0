//! What the renderers draw: GPU-ready glyph instances around a scene origin, and the bounds the
//! camera frames. Built on the CPU, uploaded by the renderer, ray cast by the reference.

use glam::{DMat3, DQuat, DVec3};

use crate::request::GlyphKind;

pub mod rules;
pub mod underlay;

pub use underlay::{Underlay, UnderlaySource};

/// One glyph instance at full f32 precision, as built on the CPU: the reference ray casts these,
/// the GPU reads them packed ([`crate::render::gpu_data::GpuGlyph`], 32 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GlyphInstance {
    /// Centre relative to the scene origin.
    pub centre: [f32; 3],
    /// RGBA8 (R in the lowest byte).
    pub color: u32,
    /// Unit quaternion (x, y, z, w) of the eigenvector frame.
    pub rotation: [f32; 4],
    /// Semi-axes along the frame's columns.
    pub radii: [f32; 3],
    /// Index into the glyph list the scene was built from (instances may be reordered).
    pub glyph: u32,
    /// A superquadric's exponents (α, β, c) as the GPU reads them
    /// ([`crate::glyph::superquadric::pack_exponents`]); `[0, 0]` for the other glyphs. The
    /// frame's third column is then the symmetry axis and `radii` are in local (x, y, z) order.
    pub shape: [u32; 2],
}

impl GlyphInstance {
    /// The superquadric exponents (α, β, c) stored in [`Self::shape`].
    pub fn exponents(&self) -> [f32; 3] {
        crate::glyph::superquadric::unpack_exponents(self.shape)
    }

    pub fn pack_color(rgba: [u8; 4]) -> u32 {
        u32::from_le_bytes(rgba)
    }

    pub fn color_rgba(&self) -> [u8; 4] {
        self.color.to_le_bytes()
    }
}

/// Glyph instances relative to `origin`, plus a bounding sphere in world space.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// World point that instance centres are relative to (keeps f32 precise far from 0).
    pub origin: DVec3,
    pub instances: Vec<GlyphInstance>,
    /// Bounding sphere of all glyphs (world): the box `centre ± half` and its circumsphere.
    pub centre: DVec3,
    pub radius: f64,
    pub half: DVec3,
    /// A scalar image under the glyphs (`--underlay`), if asked for.
    pub underlay: Option<Underlay>,
}

/// A glyph instance's geometry in f64, as both the reference and the tests need it.
#[derive(Debug, Clone, Copy)]
pub struct GlyphGeometry {
    /// Centre relative to the scene origin.
    pub centre: DVec3,
    /// Eigenvector frame O (columns).
    pub frame: DMat3,
    pub radii: DVec3,
    /// Superquadric exponents (α, β, c) ([`GlyphInstance::exponents`]; 0 for other glyphs).
    pub exponents: DVec3,
}

impl GlyphGeometry {
    pub fn of(g: &GlyphInstance) -> Self {
        let q = DQuat::from_xyzw(
            f64::from(g.rotation[0]),
            f64::from(g.rotation[1]),
            f64::from(g.rotation[2]),
            f64::from(g.rotation[3]),
        );
        Self {
            centre: DVec3::from(g.centre.map(f64::from)),
            // The shader normalises nothing: use the quaternion exactly as stored, like it does.
            frame: quat_to_mat3_unnormalised(q),
            radii: DVec3::from(g.radii.map(f64::from)),
            exponents: DVec3::from(g.exponents().map(f64::from)),
        }
    }

    /// T = O diag(r) Oᵀ.
    pub fn t(&self) -> DMat3 {
        self.frame * DMat3::from_diagonal(self.radii) * self.frame.transpose()
    }

    /// T⁻¹ = O diag(1/r) Oᵀ, from the eigen data (never by inverting T).
    pub fn t_inv(&self) -> DMat3 {
        self.frame * DMat3::from_diagonal(self.radii.recip()) * self.frame.transpose()
    }

    /// Half-extents of the axis-aligned box around the ellipsoid: |row i of T|.
    pub fn half_extents(&self) -> DVec3 {
        let t = self.t();
        DVec3::new(t.row(0).length(), t.row(1).length(), t.row(2).length())
    }

    /// Half-extents of a box holding the glyph drawn as an ellipsoid or as a capped cylinder
    /// (axis = first column): the cylinder's box, which contains the ellipsoid's.
    pub fn glyph_half_extents(&self) -> DVec3 {
        let a = self.frame.x_axis * self.radii.x;
        let u = self.frame.y_axis * self.radii.y;
        let v = self.frame.z_axis * self.radii.z;
        a.abs() + DVec3::new(u.x.hypot(v.x), u.y.hypot(v.y), u.z.hypot(v.z))
    }

    /// Half-extents of a box holding the glyph drawn as `glyph`: [`Self::glyph_half_extents`]
    /// for ellipsoids and cylinders, the box of the segment swept by the ball for capsules
    /// (which may reach beyond the cylinder's: its radius is the cross-section's mean).
    pub fn half_extents_as(&self, glyph: GlyphKind) -> DVec3 {
        match glyph {
            GlyphKind::Ellipsoid | GlyphKind::Cylinder => self.glyph_half_extents(),
            GlyphKind::Capsule => {
                let (h, r) = capsule_of(self.radii);
                (self.frame.x_axis * h).abs() + r
            }
            // The local unit box scaled by the radii holds every superquadric.
            GlyphKind::Superquadric => {
                (self.frame.x_axis * self.radii.x).abs()
                    + (self.frame.y_axis * self.radii.y).abs()
                    + (self.frame.z_axis * self.radii.z).abs()
            }
        }
    }

    /// Whether `p` (relative to the scene origin) is inside or on the glyph drawn as `glyph`:
    /// the rule by which the methods do not draw a glyph around the eye (ellipsoids: E² ≤
    /// [`rules::EYE_INSIDE_E2`]).
    pub fn contains_as(&self, glyph: GlyphKind, p: DVec3) -> bool {
        let local = self.frame.transpose() * (p - self.centre);
        match glyph {
            GlyphKind::Ellipsoid => {
                (self.t_inv() * (p - self.centre)).length_squared() <= rules::EYE_INSIDE_E2
            }
            GlyphKind::Cylinder => {
                let q = local / self.radii;
                q.x.abs() <= 1.0 && q.y * q.y + q.z * q.z <= 1.0
            }
            GlyphKind::Capsule => {
                let (h, r) = capsule_of(self.radii);
                let q = local / r;
                (q - DVec3::new(q.x.clamp(-h / r, h / r), 0.0, 0.0)).length_squared() <= 1.0
            }
            GlyphKind::Superquadric => {
                let q = (local / self.radii).abs();
                crate::glyph::superquadric::gauge(self.exponents.to_array(), q.to_array()) <= 1.0
            }
        }
    }

    pub fn max_radius(&self) -> f64 {
        self.radii.max_element()
    }
}

/// The capsule drawn for an instance's radii `r` (axis along the frame's first column, as the
/// cylinder's; cylinder-capsule.md §4, §6): `(h, R)` with the ball's radius R = (r2 + r3)/2, the
/// circular cross-section between the cylinder's semi-axes, and the straight segment's half-length
/// h = max(r1 − R, 0). The capsule reaches r1 along its axis when r1 ≥ R, so an isotropic tensor
/// (r1 = r2 = r3) is a sphere of that radius; when R > r1 (planar tensors, whose cylinder axis is
/// e3) it is the sphere of radius R. Mirrored by `capsule_of` in shaders/capsule.wgsl.
pub fn capsule_of(r: DVec3) -> (f64, f64) {
    let radius = 0.5 * (r.y + r.z);
    ((r.x - radius).max(0.0), radius)
}

/// The same formula as `quat_to_mat3` in common.wgsl.
fn quat_to_mat3_unnormalised(q: DQuat) -> DMat3 {
    let (x2, y2, z2) = (q.x + q.x, q.y + q.y, q.z + q.z);
    let (xx, xy, xz) = (q.x * x2, q.x * y2, q.x * z2);
    let (yy, yz, zz) = (q.y * y2, q.y * z2, q.z * z2);
    let (wx, wy, wz) = (q.w * x2, q.w * y2, q.w * z2);
    DMat3::from_cols(
        DVec3::new(1.0 - (yy + zz), xy + wz, xz - wy),
        DVec3::new(xy - wz, 1.0 - (xx + zz), yz + wx),
        DVec3::new(xz + wy, yz - wx, 1.0 - (xx + yy)),
    )
}

/// One glyph given directly by world centre, frame and radii (tests, synthetic scenes).
#[derive(Debug, Clone, Copy)]
pub struct GlyphSpec {
    pub centre: DVec3,
    pub rotation: DQuat,
    pub radii: DVec3,
    pub color: [u8; 4],
    pub glyph: u32,
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
            .map(|s| {
                let c = s.centre - origin;
                let q = s.rotation.normalize();
                GlyphInstance {
                    centre: [c.x as f32, c.y as f32, c.z as f32],
                    color: GlyphInstance::pack_color(s.color),
                    rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                    radii: [s.radii.x as f32, s.radii.y as f32, s.radii.z as f32],
                    glyph: s.glyph,
                    shape: [0; 2],
                }
            })
            .collect();
        Self::from_instances(origin, instances)
    }

    /// Wrap ready instances; computes the bounding sphere (holding the glyphs as ellipsoids or
    /// as cylinders, so framing and the far plane never cut a glyph).
    pub fn from_instances(origin: DVec3, instances: Vec<GlyphInstance>) -> Self {
        Self::from_instances_as(origin, instances, GlyphKind::Cylinder)
    }

    /// [`Self::from_instances`] with bounds holding the glyphs drawn as `glyph`
    /// ([`GlyphGeometry::half_extents_as`]).
    pub fn from_instances_as(
        origin: DVec3,
        instances: Vec<GlyphInstance>,
        glyph: GlyphKind,
    ) -> Self {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for g in &instances {
            let geo = GlyphGeometry::of(g);
            let h = geo.half_extents_as(glyph);
            lo = lo.min(geo.centre - h);
            hi = hi.max(geo.centre + h);
        }
        let (centre, half) = if instances.is_empty() {
            (origin, DVec3::splat(1.0 / 3f64.sqrt()))
        } else {
            ((lo + hi) / 2.0 + origin, (hi - lo) / 2.0)
        };
        Self {
            origin,
            instances,
            centre,
            radius: half.length(),
            half,
            underlay: None,
        }
    }

    pub fn geometry(&self, instance: usize) -> GlyphGeometry {
        GlyphGeometry::of(&self.instances[instance])
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
        let origin = centre_box_middle(set);
        let n = set.glyphs.len();
        let instances = set
            .glyphs
            .par_iter()
            .enumerate()
            .map(|(k, g)| {
                if (k + 1) % PROGRESS_STEP == 0 {
                    progress.advance(PROGRESS_STEP as u64);
                }
                instance(g, k, origin, style, glyph)
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
                let geo = GlyphGeometry::of(&instance(g, k, origin, style, glyph));
                let h = geo.half_extents_as(glyph);
                (lo.min(geo.centre - h), hi.max(geo.centre + h))
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
        glyph: GlyphKind,
        frustum: bool,
        min_pixel_radius: f32,
    ) -> Visibility {
        let eye = camera.eye - self.origin;
        let f = camera.forward();
        let culling = Culling::new(camera, self.origin, frustum, min_pixel_radius);
        let mut v = Visibility::default();
        for g in &self.instances {
            if !crate::scene::rules::drawable_radii(g.radii) {
                v.degenerate += 1;
                continue;
            }
            let geo = GlyphGeometry::of(g);
            let r = geo.max_radius();
            if (geo.centre - eye).dot(f) + r < camera.near {
                v.behind_camera += 1;
            } else if culling.skips(geo.centre, bounding_radius_as(g.radii, glyph)) {
                v.culled += 1;
            } else if !camera.is_ortho() && geo.contains_as(glyph, eye) {
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

/// The GPU instance of glyph `g` (instance index `k`) around `origin`.
fn instance(
    g: &crate::glyph::Glyph,
    k: usize,
    origin: DVec3,
    style: &crate::glyph::ResolvedStyle,
    glyph: GlyphKind,
) -> GlyphInstance {
    let c = DVec3::from(g.centre) - origin;
    let (rotation, radii, shape) = match glyph {
        GlyphKind::Ellipsoid => (g.rotation, style.radii(g), [0; 2]),
        GlyphKind::Cylinder | GlyphKind::Capsule => {
            let (rotation, radii) = cylinder_frame(g.rotation, style.radii(g));
            (rotation, radii, [0; 2])
        }
        GlyphKind::Superquadric => {
            let sq = style.superquadric(g);
            let (rotation, radii) = superquadric_frame(g.rotation, style.radii(g), sq.axes);
            let exponents = crate::glyph::superquadric::pack_exponents([sq.alpha, sq.beta, sq.c]);
            (rotation, radii, exponents)
        }
    };
    GlyphInstance {
        centre: [c.x as f32, c.y as f32, c.z as f32],
        color: GlyphInstance::pack_color(style.color(g)),
        rotation,
        radii,
        glyph: k as u32,
        shape,
    }
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

/// `bounding_radius` of common.wgsl: a sphere around the glyph as ellipsoid or capped cylinder.
pub fn bounding_radius(r: [f32; 3]) -> f64 {
    f64::from(r[0]).hypot(f64::from(r[1].max(r[2])))
}

/// The radius the vertex stage of `glyph`'s methods culls with: [`bounding_radius`], or for
/// superquadrics the corner of their local box (`length(radii)`).
pub fn bounding_radius_as(r: [f32; 3], glyph: GlyphKind) -> f64 {
    match glyph {
        GlyphKind::Superquadric => DVec3::from(r.map(f64::from)).length(),
        _ => bounding_radius(r),
    }
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
        if thickness > 0.0 && thickness.is_finite() && nearest.is_finite() {
            // Saturating: a NaN depth goes to the front layer, an overflow to the last.
            self.instances
                .par_sort_by_key(|g| ((depth(g) - nearest) / thickness) as u32);
        } else {
            self.instances
                .par_sort_by(|a, b| depth(a).total_cmp(&depth(b)));
        }
    }

    /// Whether Gumhold's ellipsoid shader moves every drawable glyph's proxy to its nearest
    /// plane for this camera (its centre is more than 1.5 radii beyond the near plane), so the
    /// depth it writes is never less than the rasterised depth and may be declared so.
    pub fn conservative_depth_holds(&self, camera: &crate::camera::Camera) -> bool {
        let eye = camera.eye - self.origin;
        let f = camera.forward();
        self.instances.iter().all(|g| {
            !crate::scene::rules::drawable_radii(g.radii) || {
                let geo = GlyphGeometry::of(g);
                (geo.centre - eye).dot(f) - 1.5 * geo.max_radius() > camera.near * (1.0 + 1e-6)
            }
        })
    }
}

/// The local frame of a superquadric glyph from its eigen frame: columns `e_i` in the order
/// `axes` of [`crate::glyph::superquadric::SuperquadricShape`] (local z the symmetry axis), the
/// middle one negated when that order is a reflection (the solid is mirror-symmetric), and the
/// radii in the same order.
pub fn superquadric_frame(
    rotation: [f32; 4],
    radii: [f32; 3],
    axes: [usize; 3],
) -> ([f32; 4], [f32; 3]) {
    permuted_frame(rotation, radii, axes, 1)
}

/// Reorder an eigen frame for a cylinder glyph (cylinder-capsule.md §6): the axis (first column)
/// is the direction of the largest radius, or of the smallest for planar shapes (cp > cl, a
/// disc), so the axis does not jump between neighbours whose two largest radii are close.
/// The frame stays right-handed.
pub fn cylinder_frame(rotation: [f32; 4], radii: [f32; 3]) -> ([f32; 4], [f32; 3]) {
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]));
    let [a, b, c] = order.map(|i| f64::from(radii[i]));
    let (cl, cp) = if a > 0.0 {
        ((a - b) / a, (b - c) / a)
    } else {
        (0.0, 0.0)
    };
    let cols = if cp > cl {
        [order[2], order[0], order[1]]
    } else {
        [order[0], order[1], order[2]]
    };
    permuted_frame(rotation, radii, cols, 2)
}

/// The frame whose columns are columns `cols` of `rotation`'s, column `flip` negated where that
/// order is a reflection (so it stays a rotation), and the radii in the same order.
fn permuted_frame(
    rotation: [f32; 4],
    radii: [f32; 3],
    cols: [usize; 3],
    flip: usize,
) -> ([f32; 4], [f32; 3]) {
    let q = DQuat::from_xyzw(
        f64::from(rotation[0]),
        f64::from(rotation[1]),
        f64::from(rotation[2]),
        f64::from(rotation[3]),
    )
    .normalize();
    let m = DMat3::from_quat(q);
    let mut f = DMat3::from_cols(m.col(cols[0]), m.col(cols[1]), m.col(cols[2]));
    if f.determinant() < 0.0 {
        *f.col_mut(flip) = -f.col(flip);
    }
    let q = DQuat::from_mat3(&f).normalize();
    (
        [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
        cols.map(|i| radii[i]),
    )
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

    /// The capsule reaches the cylinder's half-length along the axis, with the cross-section's
    /// mean as radius: isotropic radii give the sphere, planar ones (R > r1) the ball of R.
    #[test]
    fn capsule_of_gives_spheres_for_isotropic_radii() {
        assert_eq!(capsule_of(DVec3::splat(0.8)), (0.0, 0.8));
        let (h, r) = capsule_of(DVec3::new(1.0, 0.35, 0.25));
        assert!((r - 0.3).abs() < 1e-15 && (h + r - 1.0).abs() < 1e-15);
        assert_eq!(capsule_of(DVec3::new(0.1, 1.0, 0.6)), (0.0, 0.8));
        // The box holds every point of the capsule and is reached on each face.
        let geo = GlyphGeometry {
            centre: DVec3::new(1.0, 2.0, 3.0),
            frame: DMat3::from_quat(DQuat::from_axis_angle(
                DVec3::new(0.3, 0.5, 0.8).normalize(),
                0.9,
            )),
            radii: DVec3::new(1.0, 0.35, 0.25),
            exponents: DVec3::ZERO,
        };
        let half = geo.half_extents_as(GlyphKind::Capsule);
        let mut reach = DVec3::ZERO;
        for i in 0..=20 {
            let along = geo.frame.x_axis * (h * (f64::from(i) / 10.0 - 1.0));
            for j in 0..2000 {
                let (a, b) = (f64::from(j) * 2.399963, 1.0 - f64::from(j) / 999.5);
                let dir = DVec3::new(
                    b,
                    (1.0 - b * b).max(0.0).sqrt() * a.cos(),
                    (1.0 - b * b).max(0.0).sqrt() * a.sin(),
                );
                let p = along + dir * r;
                assert!(
                    (p.abs() - half).max_element() <= 1e-12,
                    "{p} outside {half}"
                );
                reach = reach.max(p.abs());
            }
        }
        assert!(
            (half - reach).max_element() <= 2e-3 * r,
            "{reach} vs {half}"
        );
    }

    /// Front to back in layers: every glyph's layer (its view depth past the nearest centre,
    /// in layer thicknesses computed here from the radii) is at most the next one's, file order
    /// within a layer, and the instances are the same ones.
    #[test]
    fn front_to_back_goes_by_layers_in_file_order() {
        let scene = grid_scene(9, GlyphKind::Superquadric);
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
                assert!(w[0].glyph < w[1].glyph, "file order within a layer");
            } else {
                layers_seen += 1;
            }
        }
        assert!(layers_seen >= 3, "{layers_seen} layer changes");
        let mut ids: Vec<u32> = sorted.instances.iter().map(|g| g.glyph).collect();
        ids.sort_unstable();
        assert_eq!(ids, (0..scene.instances.len() as u32).collect::<Vec<_>>());
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
        for glyph in [
            GlyphKind::Ellipsoid,
            GlyphKind::Cylinder,
            GlyphKind::Capsule,
            GlyphKind::Superquadric,
        ] {
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

    /// A superquadric instance is the glyph's own tensor seen in its local frame: the frame's
    /// third column is the eigenvector the mapping picked as the axis, the radii follow their
    /// eigenvectors, the exponents are the mapping's (to the 2⁻¹⁴ of their packing), and the
    /// box holds the solid.
    #[test]
    fn superquadric_instances_carry_the_mapping_in_their_local_frame() {
        use crate::glyph::superquadric::{Sharpness, superquadric_shape};
        let field = crate::field::synthetic::grid(6);
        let set = derive_glyphs(&field, &crate::progress::Silent);
        let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
        let scene = Scene::build(&set, &style, GlyphKind::Superquadric);
        let mut axes_seen = [0; 3];
        for inst in &scene.instances {
            let g = &set.glyphs[inst.glyph as usize];
            let shape = superquadric_shape(g.eigenvalues.map(f64::from), Sharpness::default());
            axes_seen[shape.axis()] += 1;
            let eigen = crate::tensor::eigen::quat_to_frame(g.rotation);
            let geo = GlyphGeometry::of(inst);
            let frame_radii = style.radii(g);
            for (local, &k) in shape.axes.iter().enumerate() {
                // The same direction up to sign (the solid is mirror-symmetric).
                let e = DVec3::from(eigen[k]);
                let cos = geo.frame.col(local).normalize().dot(e).abs();
                assert!(cos > 1.0 - 1e-5, "column {local} vs e{k}: cos {cos}");
                assert_eq!(inst.radii[local], frame_radii[k]);
            }
            assert!(geo.frame.determinant() > 0.0);
            let want = [shape.alpha, shape.beta, shape.c];
            for (got, want) in inst.exponents().iter().zip(want) {
                assert!((f64::from(*got) - want).abs() <= want * 2f64.powi(-14));
            }
            let box_half = geo.half_extents_as(GlyphKind::Superquadric);
            for corner in 0..8 {
                let s = |b: usize| if corner & b != 0 { 1.0 } else { -1.0 };
                let p = geo.frame * (geo.radii * DVec3::new(s(1), s(2), s(4)));
                assert!((p.abs() - box_half).max_element() <= 1e-9 * geo.max_radius());
            }
        }
        // The demo field has linear and planar glyphs: both axis choices are exercised.
        assert!(axes_seen[0] > 0 && axes_seen[2] > 0, "{axes_seen:?}");
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
}
