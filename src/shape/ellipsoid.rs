//! Ellipsoids: the glyph T = O diag(r) Oᵀ itself, ray cast exactly as a quadric
//! (gumhold-ellipsoid.md, sigg-quadric.md §4). Gumhold's method draws them with their own exact
//! quad (shaders/method/gumhold_ellipsoid.wgsl, a specialisation); every other method through
//! shaders/shape/ellipsoid.wgsl.

use glam::{DMat3, DVec3};

use super::mesh::Mesh;
use super::rules::EYE_INSIDE_E2;
use super::{
    Capabilities, Exact, GlyphGeometry, GlyphKind, Part, RayHit, Shape, unit_sphere_roots,
};
use crate::glyph::{Glyph, ResolvedStyle};

pub const WGSL: &str = include_str!("../../shaders/shape/ellipsoid.wgsl");

/// The ellipsoid kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Ellipsoid
    }

    fn caps(&self) -> Capabilities {
        Capabilities {
            prepass: true,
            splats: true,
            conservative_depth: true,
            benched_by_default: true,
            ..Capabilities::NONE
        }
    }

    fn place(&self, g: &Glyph, _part: usize, style: &ResolvedStyle) -> Option<Part> {
        Some(Part::whole(g, style, (g.rotation, style.radii(g)), [0; 2]))
    }

    /// The box of the glyph's capped cylinder, which holds the ellipsoid: scenes are framed
    /// alike whichever of the two is drawn.
    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        geo.glyph_half_extents()
    }

    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        Box::new(Ellipsoid::of(geo))
    }

    fn unit_mesh(&self, level: u8) -> Mesh {
        icosphere(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let f = 1usize << (2 * u32::from(level));
        (10 * f + 2, 20 * f)
    }

    fn wgsl(&self) -> &'static [&'static str] {
        &[WGSL]
    }
}

/// An ellipsoid glyph |T⁻¹(p − c)| ≤ 1 as the reference casts it.
#[derive(Debug, Clone, Copy)]
pub struct Ellipsoid {
    pub centre: DVec3,
    pub t_inv: DMat3,
    half: DVec3,
}

impl Ellipsoid {
    pub fn of(geo: &GlyphGeometry) -> Self {
        Self {
            centre: geo.centre,
            t_inv: geo.t_inv(),
            half: geo.half_extents(),
        }
    }
}

impl Exact for Ellipsoid {
    fn centre(&self) -> DVec3 {
        self.centre
    }

    fn half_extents(&self) -> DVec3 {
        self.half
    }

    /// E² ≤ [`EYE_INSIDE_E2`].
    fn contains(&self, p: DVec3) -> bool {
        (self.t_inv * (p - self.centre)).length_squared() <= EYE_INSIDE_E2
    }

    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        intersect(o, d, self.centre, &self.t_inv).map(|(t, p_t)| RayHit {
            t,
            normal: (self.t_inv * p_t).normalize(),
        })
    }
}

/// Front intersection of `o + t d` (d unit) with the ellipsoid |T⁻¹(p − c)| = 1 (with
/// `t_inv` = T⁻¹): `(t, p~)`. The ray origin is first moved next to the glyph
/// (sigg-quadric.md §4), so nothing cancels for distant glyphs. An origin inside gives the exit
/// point (the only forward hit).
pub fn intersect(o: DVec3, d: DVec3, c: DVec3, t_inv: &DMat3) -> Option<(f64, DVec3)> {
    let t0 = (c - o).dot(d);
    let o_t = *t_inv * ((o - c) + d * t0);
    let v_t = *t_inv * d;
    let (near, far) = unit_sphere_roots(o_t, v_t)?;
    let tp = if t0 + near > 0.0 {
        near
    } else if t0 + far > 0.0 {
        far
    } else {
        return None;
    };
    Some((t0 + tp, o_t + v_t * tp))
}

/// The icosahedron (level 0, Gumhold's comparison) split `level` times into four triangles per
/// triangle, midpoints pushed onto the unit sphere: 10·4^N + 2 vertices, 20·4^N triangles.
/// Positions are the normals.
pub fn icosphere(level: u8) -> Mesh {
    let (points, faces) = crate::geodesic::icosphere(u32::from(level));
    let mut mesh = Mesh::default();
    for p in points {
        mesh.push(p, p);
    }
    mesh.indices = faces.into_iter().flatten().collect();
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, m3, v3};

    #[test]
    fn ellipsoid_hits_match_the_test_vectors() {
        let mut checked = 0;
        for case in cases().iter().filter(|c| c["kind"] == "ellipsoid") {
            let id = case["id"].as_str().unwrap();
            let e = &case["expected"];
            let t = m3(&case["glyph"]["T"]);
            let c = v3(&case["glyph"]["c"]);
            let t_inv = t.inverse();
            let o = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let hit = intersect(o, d, c, &t_inv);
            assert_eq!(hit.is_some(), e["hit"].as_bool().unwrap(), "{id}");
            let Some((tt, p_t)) = hit else { continue };
            let size = (0..3)
                .map(|i| case["glyph"]["radii"][i].as_f64().unwrap())
                .fold(0.0, f64::max);
            let point = o + d * tt;
            // 1e-9 glyph sizes relative to the centre, as test-vectors.md suggests.
            assert!(
                ((point - c) - (v3(&e["point"]) - c)).length() <= 1e-9 * size,
                "{id}: point"
            );
            let n = (t_inv * p_t).normalize();
            assert!((n - v3(&e["normal"])).length() <= 1e-9, "{id}: normal {n}");
            checked += 1;
        }
        assert!(checked >= 9, "only {checked} ellipsoid cases");
    }

    #[test]
    fn icosphere_vertices_lie_on_the_sphere() {
        for v in icosphere(3).vertices {
            let p = v.position.map(f64::from);
            assert!((p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0).abs() < 1e-6);
            assert_eq!(v.position, v.normal);
        }
        assert_eq!(Kind.mesh_stats(0), (12, 20));
        assert_eq!(Kind.mesh_stats(6), (40962, 81920));
    }
}
