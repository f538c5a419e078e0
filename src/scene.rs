//! What the renderers draw: GPU-ready glyph instances around a scene origin, and the bounds the
//! camera frames. Built on the CPU, uploaded by the renderer, ray cast by the reference.

use glam::{DMat3, DQuat, DVec3};

use crate::render::gpu_data::GpuGlyph;

/// Glyph instances relative to `origin`, plus a bounding sphere in world space.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// World point that instance centres are relative to (keeps f32 precise far from 0).
    pub origin: DVec3,
    pub instances: Vec<GpuGlyph>,
    /// Bounding sphere of all glyphs (world).
    pub centre: DVec3,
    pub radius: f64,
}

/// A glyph instance's geometry in f64, as both the reference and the tests need it.
#[derive(Debug, Clone, Copy)]
pub struct GlyphGeometry {
    /// Centre relative to the scene origin.
    pub centre: DVec3,
    /// Eigenvector frame O (columns).
    pub frame: DMat3,
    pub radii: DVec3,
}

impl GlyphGeometry {
    pub fn of(g: &GpuGlyph) -> Self {
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

    pub fn max_radius(&self) -> f64 {
        self.radii.max_element()
    }
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
                GpuGlyph {
                    centre: [c.x as f32, c.y as f32, c.z as f32],
                    color: GpuGlyph::pack_color(s.color),
                    rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                    radii: [s.radii.x as f32, s.radii.y as f32, s.radii.z as f32],
                    glyph: s.glyph,
                }
            })
            .collect();
        Self::from_instances(origin, instances)
    }

    /// Wrap ready instances; computes the bounding sphere.
    pub fn from_instances(origin: DVec3, instances: Vec<GpuGlyph>) -> Self {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for g in &instances {
            let geo = GlyphGeometry::of(g);
            let h = geo.half_extents();
            lo = lo.min(geo.centre - h);
            hi = hi.max(geo.centre + h);
        }
        let (centre, radius) = if instances.is_empty() {
            (origin, 1.0)
        } else {
            ((lo + hi) / 2.0 + origin, ((hi - lo) / 2.0).length())
        };
        Self {
            origin,
            instances,
            centre,
            radius,
        }
    }

    pub fn geometry(&self, instance: usize) -> GlyphGeometry {
        GlyphGeometry::of(&self.instances[instance])
    }
}
