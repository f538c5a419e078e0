//! Superquadric glyphs (docs/book/src/developer/superquadric-derivation.md): Kindlmann's shapes of the tensor and
//! `--sharpness` (Schultz–Kindlmann's for indefinite tensors, [`crate::glyph::superquadric`]),
//! the solid in its local unit box (third column the symmetry axis), scaled by the radii. The
//! exact intersection ([`exact`]) judges the GPU's root finder (shaders/shape/superquadric.wgsl);
//! `mesh:N` maps a shared grid through each glyph's exponents ([`mesh`]).

pub mod exact;
pub mod mesh;

use glam::DVec3;

pub use exact::Superquadric;

use super::geometry::permuted_frame;
use super::{Capabilities, Exact, GlyphGeometry, GlyphInstance, GlyphKind, Mesh, Part, Shape};
use crate::glyph::superquadric::{Sharpness, is_convex, pack_exponents, superquadric_shape};
use crate::glyph::{Glyph, ResolvedStyle};

/// The shape interface.
pub const WGSL: &str = include_str!("../../../shaders/shape/superquadric.wgsl");
/// The root finder it calls.
pub const FINDER_WGSL: &str = include_str!("../../../shaders/shape/superquadric_finder.wgsl");
/// `mesh:N`'s mapping of the unit grid to the glyph.
pub const MESH_WGSL: &str = include_str!("../../../shaders/shape/superquadric_mesh.wgsl");
/// Splats of Gumhold's superquadrics (the prepass's per-pixel casts).
pub const SPLAT_WGSL: &str = include_str!("../../../shaders/shape/superquadric_splat.wgsl");

/// The superquadric kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Superquadric
    }

    fn caps(&self) -> Capabilities {
        Capabilities {
            prepass: true,
            splats: true,
            sharpness: true,
            ..Capabilities::NONE
        }
    }

    fn place(&self, g: &Glyph, _part: usize, style: &ResolvedStyle) -> Option<Part> {
        let sq = style.superquadric(g);
        let frame = superquadric_frame(g.rotation, style.radii(g), sq.axes);
        Some(Part::whole(
            g,
            style,
            frame,
            pack_exponents([sq.alpha, sq.beta, sq.c]),
        ))
    }

    /// Each glyph's radii taken as its eigenvalues (positive definite: Kindlmann's shapes at the
    /// default sharpness). Instances that already carry exponents are kept.
    fn adopt(&self, g: &GlyphInstance) -> GlyphInstance {
        if g.shape != [0; 2] {
            return *g;
        }
        superquadric_instance(g, g.radii.map(f64::from), Sharpness::default())
    }

    /// The local unit box scaled by the radii, which holds every superquadric.
    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        (geo.frame.x_axis * geo.radii.x).abs()
            + (geo.frame.y_axis * geo.radii.y).abs()
            + (geo.frame.z_axis * geo.radii.z).abs()
    }

    /// The corner of the local box.
    fn cull_radius(&self, radii: [f32; 3]) -> f64 {
        DVec3::from(radii.map(f64::from)).length()
    }

    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        Box::new(Superquadric::of(geo))
    }

    fn unit_mesh(&self, level: u8) -> Mesh {
        mesh::superquadric_grid(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let s = super::mesh::prism_sides(level) as usize;
        let m = mesh::superquadric_rings(level) as usize;
        (s * (m - 1) + 2, 2 * s * (m - 1))
    }

    fn wgsl(&self) -> &'static [&'static str] {
        &[FINDER_WGSL, WGSL, MESH_WGSL]
    }

    fn splat_wgsl(&self) -> Option<&'static str> {
        Some(SPLAT_WGSL)
    }

    fn general_override(&self) -> Option<&'static str> {
        Some("SQ_GENERAL")
    }

    /// Pinched, or c ≠ β (indefinite tensors): the convex finder cannot draw it.
    fn is_general(&self, g: &GlyphInstance) -> bool {
        g.shape != [0; 2] && !is_convex(g.exponents())
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

impl Exact for Superquadric {
    fn centre(&self) -> DVec3 {
        self.centre
    }

    fn half_extents(&self) -> DVec3 {
        Superquadric::half_extents(self)
    }

    fn contains(&self, p: DVec3) -> bool {
        Superquadric::contains(self, p)
    }

    fn intersect(&self, o: DVec3, d: DVec3) -> Option<super::RayHit> {
        Superquadric::intersect(self, o, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::{GlyphStyle, derive_glyphs};
    use crate::staging::field_spacing;

    /// A superquadric instance is the glyph's own tensor seen in its local frame: the frame's
    /// third column is the eigenvector the mapping picked as the axis, the radii follow their
    /// eigenvectors, the exponents are the mapping's (to the 2⁻¹⁴ of their packing), and the
    /// box holds the solid.
    #[test]
    fn superquadric_instances_carry_the_mapping_in_their_local_frame() {
        use crate::glyph::superquadric::{Sharpness, superquadric_shape};
        use crate::shape::geometry::{pack_radius, unpack_radius};
        let field = crate::field::synthetic::grid(6);
        let set = derive_glyphs(&field, &crate::progress::Silent);
        let style = GlyphStyle::default().resolve(&set, field_spacing(&field));
        let scene = crate::scene::Scene::build(&set, &style, GlyphKind::Superquadric);
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
                // As stored (24-bit radii).
                let stored = unpack_radius(pack_radius(frame_radii[k]));
                assert_eq!(inst.radii[local], stored);
            }
            assert!(geo.frame.determinant() > 0.0);
            let want = [shape.alpha, shape.beta, shape.c];
            for (got, want) in inst.exponents().iter().zip(want) {
                assert!((f64::from(*got) - want).abs() <= want * 2f64.powi(-14));
            }
            let box_half = Kind.bounds(&geo);
            for corner in 0..8 {
                let s = |b: usize| if corner & b != 0 { 1.0 } else { -1.0 };
                let p = geo.frame * (geo.radii * DVec3::new(s(1), s(2), s(4)));
                assert!((p.abs() - box_half).max_element() <= 1e-9 * geo.max_radius());
            }
        }
        // The demo field has linear and planar glyphs: both axis choices are exercised.
        assert!(axes_seen[0] > 0 && axes_seen[2] > 0, "{axes_seen:?}");
    }
}
