//! Capped elliptic cylinders along the principal axis (cylinder-capsule.md §6; sigg-quadric.md
//! §7): in parameter space, the local frame scaled by the radii, the solid |x| ≤ 1,
//! y² + z² ≤ 1, entered through the slab method.

use glam::{DMat3, DVec3};

use super::geometry::permuted_frame;
use super::mesh::{Mesh, prism_sides};
use super::{
    Capabilities, Exact, GlyphGeometry, GlyphKind, Part, RayHit, Shape, unit_sphere_roots,
};
use crate::glyph::{Glyph, ResolvedStyle};

pub const WGSL: &str = include_str!("../../shaders/shape/cylinder.wgsl");
/// The slab test it enters by (shared with the principal-stress bars).
pub const SLAB_WGSL: &str = include_str!("../../shaders/shape/slab.wgsl");

/// The cylinder kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Cylinder
    }

    fn caps(&self) -> Capabilities {
        Capabilities {
            benched_by_default: true,
            ..Capabilities::NONE
        }
    }

    fn place(&self, g: &Glyph, _part: usize, style: &ResolvedStyle) -> Option<Part> {
        let frame = cylinder_frame(g.rotation, style.radii(g));
        Some(Part::whole(g, style, frame, [0; 2]))
    }

    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        geo.glyph_half_extents()
    }

    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        Box::new(Cylinder::of(geo))
    }

    fn unit_mesh(&self, level: u8) -> Mesh {
        prism(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let s = prism_sides(level) as usize;
        (4 * s + 2, 4 * s)
    }

    fn wgsl(&self) -> &'static [&'static str] {
        &[SLAB_WGSL, WGSL]
    }
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

/// A capped elliptic cylinder: centre `c`, frame `o` (axis = first column), radii `r`
/// (half-length, then the cross-section semi-axes).
#[derive(Debug, Clone, Copy)]
pub struct Cylinder {
    pub c: DVec3,
    pub frame: DMat3,
    pub radii: DVec3,
}

impl Cylinder {
    pub fn of(geo: &GlyphGeometry) -> Self {
        Self {
            c: geo.centre,
            frame: geo.frame,
            radii: geo.radii,
        }
    }

    /// To local parameter space, where the solid is |x| ≤ 1, y² + z² ≤ 1.
    fn param(&self, v: DVec3) -> DVec3 {
        (self.frame.transpose() * v) / self.radii
    }
}

impl Exact for Cylinder {
    fn centre(&self) -> DVec3 {
        self.c
    }

    /// Half-extents of its axis-aligned bounding box.
    fn half_extents(&self) -> DVec3 {
        let a = self.frame.x_axis * self.radii.x;
        let u = self.frame.y_axis * self.radii.y;
        let v = self.frame.z_axis * self.radii.z;
        a.abs() + DVec3::new(u.x.hypot(v.x), u.y.hypot(v.y), u.z.hypot(v.z))
    }

    fn contains(&self, p: DVec3) -> bool {
        let q = self.param(p - self.c);
        q.x.abs() <= 1.0 && q.y * q.y + q.z * q.z <= 1.0
    }

    /// First forward crossing of the surface by `o + t d` (slab method, sigg-quadric.md §7).
    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let t0 = (self.c - o).dot(d);
        let o_t = self.param((o - self.c) + d * t0);
        let v_t = self.param(d);
        let (mut side_in, mut side_out) = (f64::NEG_INFINITY, f64::INFINITY);
        let side = |p: DVec3| DVec3::new(0.0, p.y, p.z);
        if v_t.y != 0.0 || v_t.z != 0.0 {
            (side_in, side_out) = unit_sphere_roots(side(o_t), side(v_t))?;
        } else if o_t.y * o_t.y + o_t.z * o_t.z > 1.0 {
            return None;
        }
        let (mut cap_in, mut cap_out) = (f64::NEG_INFINITY, f64::INFINITY);
        if v_t.x != 0.0 {
            let t1 = (-1.0 - o_t.x) / v_t.x;
            let t2 = (1.0 - o_t.x) / v_t.x;
            (cap_in, cap_out) = (t1.min(t2), t1.max(t2));
        } else if o_t.x.abs() > 1.0 {
            return None;
        }
        let t_in = side_in.max(cap_in);
        let t_out = side_out.min(cap_out);
        if t_in > t_out || t0 + t_out <= 0.0 {
            return None;
        }
        // From inside, the exit is the only forward crossing.
        let (t, entering) = if t0 + t_in > 0.0 {
            (t_in, true)
        } else {
            (t_out, false)
        };
        let p = o_t + v_t * t;
        let on_cap = if entering {
            cap_in > side_in
        } else {
            cap_out < side_out
        };
        let n_t = if on_cap {
            DVec3::new(p.x.signum(), 0.0, 0.0)
        } else {
            DVec3::new(0.0, p.y, p.z)
        };
        let normal = (self.frame * (n_t / self.radii)).normalize();
        Some(RayHit { t: t0 + t, normal })
    }
}

/// The unit cylinder as a prism with 6·2^N sides (smooth normals around, the rings shared by the
/// side quads) and flat caps (their own vertices, a fan around the centre): 4S + 2 vertices and
/// 4S triangles for S sides.
pub fn prism(level: u8) -> Mesh {
    let s = prism_sides(level);
    let mut mesh = Mesh::default();
    let ring = |k: u32| {
        let a = std::f64::consts::TAU * f64::from(k % s) / f64::from(s);
        (a.cos(), a.sin())
    };
    // Sides: vertex 2k at x = −1, 2k + 1 at x = +1.
    for k in 0..s {
        let (c, si) = ring(k);
        mesh.push([-1.0, c, si], [0.0, c, si]);
        mesh.push([1.0, c, si], [0.0, c, si]);
    }
    for k in 0..s {
        let (a0, a1) = (2 * k, 2 * k + 1);
        let (b0, b1) = (2 * ((k + 1) % s), 2 * ((k + 1) % s) + 1);
        mesh.indices.extend([a0, b0, b1, a0, b1, a1]);
    }
    // Caps: the centre, then the ring.
    for x in [-1.0, 1.0] {
        let centre = mesh.push([x, 0.0, 0.0], [x, 0.0, 0.0]);
        for k in 0..s {
            let (c, si) = ring(k);
            mesh.push([x, c, si], [x, 0.0, 0.0]);
        }
        for k in 0..s {
            let (i, j) = (centre + 1 + k, centre + 1 + (k + 1) % s);
            if x > 0.0 {
                mesh.indices.extend([centre, i, j]);
            } else {
                mesh.indices.extend([centre, j, i]);
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, v3};

    /// The elliptic-cylinder vectors give Sigg's columns u, v (cross-section) and w (axis).
    #[test]
    fn cylinder_hits_match_the_test_vectors() {
        let mut checked = 0;
        for case in cases()
            .iter()
            .filter(|c| c["kind"].as_str().unwrap().starts_with("cylinder"))
        {
            let id = case["id"].as_str().unwrap();
            let g = &case["glyph"];
            let e = &case["expected"];
            let cyl = if case["kind"] == "cylinder" {
                let (u, v, w) = (v3(&g["u"]), v3(&g["v"]), v3(&g["w"]));
                Cylinder {
                    c: v3(&g["c"]),
                    frame: DMat3::from_cols(w.normalize(), u.normalize(), v.normalize()),
                    radii: DVec3::new(w.length(), u.length(), v.length()),
                }
            } else {
                // Circular: end points a, b and radius R.
                let (a, b) = (v3(&g["a"]), v3(&g["b"]));
                let r = g["R"].as_f64().unwrap();
                let axis = (b - a).normalize();
                let (x, y) = axis.any_orthonormal_pair();
                Cylinder {
                    c: (a + b) / 2.0,
                    frame: DMat3::from_cols(axis, x, y),
                    radii: DVec3::new((b - a).length() / 2.0, r, r),
                }
            };
            // Right-handed frames only: the vectors' columns may not be; the solid is the same.
            let o = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let hit = cyl.intersect(o, d).expect(id);
            let size = cyl.radii.max_element();
            let p = o + d * hit.t;
            assert!(
                (p - v3(&e["point"])).length() <= 1e-9 * size,
                "{id}: point {p}"
            );
            assert!(
                (hit.normal - v3(&e["normal"])).length() <= 1e-9,
                "{id}: normal {}",
                hit.normal
            );
            checked += 1;
        }
        assert_eq!(checked, 3);
    }

    #[test]
    fn prism_vertices_lie_on_the_cylinder() {
        for v in prism(2).vertices {
            let [x, y, z] = v.position.map(f64::from);
            let on_side = (x.abs() - 1.0).abs() < 1e-6 && ((y * y + z * z) - 1.0).abs() < 1e-6;
            let on_cap = (x.abs() - 1.0).abs() < 1e-6 && y * y + z * z <= 1.0 + 1e-6;
            assert!(on_side || on_cap, "{v:?}");
        }
        assert_eq!(Kind.mesh_stats(0), (26, 24));
    }
}
