//! Capsules: the cylinder's axis with rounded ends, a segment swept by a ball
//! (cylinder-capsule.md §4–§6). In capsule space, the local frame scaled by the ball's radius R,
//! the solid is every point within 1 of the segment |x| ≤ h.

use glam::{DMat3, DVec3};

use super::cylinder::cylinder_frame;
use super::mesh::{Mesh, prism_sides};
use super::{Capabilities, Exact, GlyphGeometry, GlyphKind, Part, RayHit, Shape, stable_roots};
use crate::glyph::{Glyph, ResolvedStyle};

pub const WGSL: &str = include_str!("../../shaders/shape/capsule.wgsl");

/// The capsule kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Capsule
    }

    fn caps(&self) -> Capabilities {
        Capabilities::NONE
    }

    /// The cylinder's frame: the capsule's axis is the cylinder's.
    fn place(&self, g: &Glyph, _part: usize, style: &ResolvedStyle) -> Option<Part> {
        let frame = cylinder_frame(g.rotation, style.radii(g));
        Some(Part::whole(g, style, frame, [0; 2]))
    }

    /// The box of the segment swept by the ball (which may reach beyond the cylinder's box:
    /// its radius is the cross-section's mean).
    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        let (h, r) = capsule_of(geo.radii);
        (geo.frame.x_axis * h).abs() + r
    }

    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        Box::new(StoredCapsule::of(geo))
    }

    fn unit_mesh(&self, level: u8) -> Mesh {
        unit_capsule(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let (s, m) = (prism_sides(level) as usize, capsule_rings(level) as usize);
        (2 * m * s + 2, 4 * m * s)
    }

    fn wgsl(&self) -> &'static [&'static str] {
        &[WGSL]
    }
}

/// The capsule drawn for an instance's radii `r` (axis along the frame's first column, as the
/// cylinder's; cylinder-capsule.md §4, §6): `(h, R)` with the ball's radius R = (r2 + r3)/2, the
/// circular cross-section between the cylinder's semi-axes, and the straight segment's half-length
/// h = max(r1 − R, 0). The capsule reaches r1 along its axis when r1 ≥ R, so an isotropic tensor
/// (r1 = r2 = r3) is a sphere of that radius; when R > r1 (planar tensors, whose cylinder axis is
/// e3) it is the sphere of radius R. Mirrored by `capsule_of` in shaders/shape/capsule.wgsl.
pub fn capsule_of(r: DVec3) -> (f64, f64) {
    let radius = 0.5 * (r.y + r.z);
    ((r.x - radius).max(0.0), radius)
}

/// A capsule: the segment from `c − h n` to `c + h n` (`n` unit) swept by a ball of radius `r`
/// (cylinder-capsule.md §4).
#[derive(Debug, Clone, Copy)]
pub struct Capsule {
    pub c: DVec3,
    pub axis: DVec3,
    pub h: f64,
    pub r: f64,
}

impl Capsule {
    /// The capsule an instance's geometry is drawn as ([`capsule_of`]).
    pub fn of(geo: &GlyphGeometry) -> Self {
        let (h, r) = capsule_of(geo.radii);
        Self {
            c: geo.centre,
            axis: geo.frame.x_axis.normalize(),
            h,
            r,
        }
    }

    /// The point of the segment nearest to `p` (relative to the centre).
    fn foot(&self, p: DVec3) -> DVec3 {
        self.axis * p.dot(self.axis).clamp(-self.h, self.h)
    }
}

/// The capsule an instance is drawn as, in its parameter space as the shaders have it:
/// p~ = Oᵀ (p − c) / R with the frame O as stored (its quaternion's matrix, unnormalised, as
/// every kind's reference has it), where it is the unit capsule of half-length h/R along x. A
/// quaternion stored to f32 is 1 + ~2⁻²⁴ long, which turns O's columns by as much; a capsule
/// k thin is h/R = k radii long, so casting it about the normalised axis instead put its ends
/// ~2⁻²⁴·k radii from where the shaders draw them (normal p99 0.2–4° at k ≥ 1e5).
#[derive(Debug, Clone, Copy)]
pub struct StoredCapsule {
    pub c: DVec3,
    pub frame: DMat3,
    pub r: f64,
    /// The unit capsule of parameter space.
    unit: Capsule,
}

impl StoredCapsule {
    pub fn of(geo: &GlyphGeometry) -> Self {
        let (h, r) = capsule_of(geo.radii);
        Self {
            c: geo.centre,
            frame: geo.frame,
            r,
            unit: Capsule {
                c: DVec3::ZERO,
                axis: DVec3::X,
                // A degenerate glyph (r = 0, culled before it is cast) keeps a finite segment.
                h: Some(h / r).filter(|h| h.is_finite()).unwrap_or(0.0),
                r: 1.0,
            },
        }
    }

    fn local(&self, p: DVec3) -> DVec3 {
        self.frame.transpose() * p / self.r
    }
}

impl Exact for StoredCapsule {
    fn centre(&self) -> DVec3 {
        self.c
    }

    fn half_extents(&self) -> DVec3 {
        (self.frame.x_axis * (self.unit.h * self.r)).abs()
            + self.r * self.frame.x_axis.length().max(1.0)
    }

    fn contains(&self, p: DVec3) -> bool {
        self.unit.contains(self.local(p - self.c))
    }

    /// The unit capsule's crossing of the ray mapped into parameter space (its direction
    /// made unit there, t scaled back), the normal by the inverse transpose (O n~).
    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let v = self.local(d);
        let len = v.length();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let hit = self.unit.intersect(self.local(o - self.c), v / len)?;
        Some(RayHit {
            t: hit.t / len,
            normal: (self.frame * hit.normal).normalize(),
        })
    }
}

impl Exact for Capsule {
    fn centre(&self) -> DVec3 {
        self.c
    }

    /// Half-extents of its axis-aligned bounding box.
    fn half_extents(&self) -> DVec3 {
        (self.axis * self.h).abs() + self.r
    }

    fn contains(&self, p: DVec3) -> bool {
        let q = p - self.c;
        (q - self.foot(q)).length_squared() <= self.r * self.r
    }

    /// First forward crossing of the surface by `o + t d` (`d` unit): §4 of the note for the
    /// entry and, reversed, for the exit, from the ray point nearest the centre (§5's
    /// well-conditioned origin), so nothing cancels for distant glyphs.
    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let n = self.axis;
        let mut t0 = (self.c - o).dot(d);
        // The origin relative to the centre; a, b relative to the origin.
        let mut o_c = (o - self.c) + d * t0;
        // Then the ray point nearest the axis (within the balls' reach along it): nearest the
        // centre can be far from the glyph's surface for a long, thin capsule.
        let across = d - n * d.dot(n);
        if across.length_squared() > 0.0 {
            let mut s = -(o_c - n * o_c.dot(n)).dot(across) / across.length_squared();
            let x = (o_c + d * s).dot(n);
            let reach = self.h + self.r;
            if x.abs() > reach && d.dot(n) != 0.0 {
                s += (x.clamp(-reach, reach) - x) / d.dot(n);
            }
            t0 += s;
            o_c += d * s;
        }
        let a = -n * self.h - o_c;
        let length = 2.0 * self.h;
        let alpha = a.dot(n);
        let beta = d.dot(n);
        // §2's A, B, C from the parts across the axis (1 − β² cancels for rays along it).
        let a_perp = a - n * alpha;
        let d_perp = d - n * beta;
        let qa = d_perp.length_squared();
        let qb = -a_perp.dot(d_perp);
        let qc = a_perp.length_squared() - self.r * self.r;
        let (side_in, side_out) = if qa > 0.0 {
            let disc = qb * qb - qa * qc;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            stable_roots(qa, qb, qc, disc)
        } else if qc > 0.0 {
            return None;
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        };
        // The crossing at side root `t` (entry or exit): on the side if its axial coordinate s
        // is within [0, L], else on the ball at the end it lies beyond.
        let crossing = |t: f64, entry: bool| -> Option<(f64, DVec3)> {
            let s = t * beta - alpha;
            if (0.0..=length).contains(&s) {
                return Some((t, (d * t - a - n * s) / self.r));
            }
            let k = if s < 0.0 { a } else { a + n * length };
            let delta = k.dot(d);
            let ck = k.length_squared() - self.r * self.r;
            let disc = delta * delta - ck;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            let (near, far) = stable_roots(1.0, -delta, ck, disc);
            let tk = if entry { near } else { far };
            Some((tk, (d * tk - k) / self.r))
        };
        let (t_in, n_in) = crossing(side_in, true)?;
        let (t, normal) = if t0 + t_in > 0.0 {
            (t_in, n_in)
        } else {
            // From inside, the exit is the only forward crossing.
            let (t_out, n_out) = crossing(side_out, false)?;
            if t0 + t_out <= 0.0 {
                return None;
            }
            (t_out, n_out)
        };
        Some(RayHit {
            t: t0 + t,
            normal: normal.normalize(),
        })
    }
}

/// Latitude steps per hemisphere of the `mesh:N` capsule: as close to the longitude step (a
/// quarter of the sides) as whole steps allow.
pub fn capsule_rings(level: u8) -> u32 {
    prism_sides(level).div_ceil(4)
}

/// The unit capsule (segment x ∈ [−1, 1], radius 1) with 6·2^N sides around and M =
/// [`capsule_rings`] latitude steps per hemisphere, smooth normals throughout (the equators are
/// shared by the hemisphere and the tube): 2MS + 2 vertices and 4MS triangles for S sides.
pub fn unit_capsule(level: u8) -> Mesh {
    let s = prism_sides(level);
    let m = capsule_rings(level);
    let mut mesh = Mesh::default();
    // Ring j of end `x` at polar angle θ = j π / (2M) from that end's pole.
    let ring_point = |x: f64, j: u32, k: u32| {
        let theta = std::f64::consts::FRAC_PI_2 * f64::from(j) / f64::from(m);
        let a = std::f64::consts::TAU * f64::from(k % s) / f64::from(s);
        let n = [
            x * theta.cos(),
            theta.sin() * a.cos(),
            theta.sin() * a.sin(),
        ];
        ([x + n[0], n[1], n[2]], n)
    };
    let pole_a = mesh.push([-2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]);
    // Rings from the −x pole to its equator, then from the +x equator to its pole: 2M rings.
    let mut rings: Vec<u32> = Vec::new();
    for (x, js) in [
        (-1.0, (1..=m).collect::<Vec<_>>()),
        (1.0, (1..=m).rev().collect()),
    ] {
        for j in js {
            rings.push(mesh.vertices.len() as u32);
            for k in 0..s {
                let (p, n) = ring_point(x, j, k);
                mesh.push(p, n);
            }
        }
    }
    let pole_b = mesh.push([2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    // Looking down −x at the −x pole the ring angle a runs clockwise.
    let first = rings[0];
    for k in 0..s {
        mesh.indices
            .extend([pole_a, first + (k + 1) % s, first + k]);
    }
    for pair in rings.windows(2) {
        let (r0, r1) = (pair[0], pair[1]);
        for k in 0..s {
            let k1 = (k + 1) % s;
            mesh.indices
                .extend([r0 + k, r0 + k1, r1 + k1, r0 + k, r1 + k1, r1 + k]);
        }
    }
    let last = *rings.last().unwrap();
    for k in 0..s {
        mesh.indices.extend([pole_b, last + k, last + (k + 1) % s]);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, v3};
    use glam::{DMat3, DQuat};

    /// In parameter space with an orthonormal frame, the stored capsule is the capsule about
    /// its axis: the same crossings and normals; with the frame of a quaternion 1 + 1e-7 long
    /// (as f32 stores one), a needle k = 1e5 thin has its ends where the shaders put them,
    /// ~1e-7·k radii from the normalised axis's.
    #[test]
    fn stored_capsule_is_the_capsule_in_parameter_space() {
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let geo = |q: DQuat, radii: DVec3| GlyphGeometry {
            centre: DVec3::new(1.0, 2.0, -0.5),
            frame: crate::shape::geometry::quat_to_mat3_unnormalised(q),
            radii,
            exponents: DVec3::ZERO,
            params: [0; 2],
        };
        let g = geo(q, DVec3::new(2.0, 0.5, 0.4));
        let (stored, plain) = (StoredCapsule::of(&g), Capsule::of(&g));
        let mut hits = 0;
        for k in 0..300 {
            let a = f64::from(k) * 0.37;
            let o = g.centre + DVec3::new(a.cos(), (1.3 * a).sin(), 0.5 * a.sin()) * 6.0;
            let aim =
                g.centre + DVec3::new((2.1 * a).sin(), 0.4 * a.cos(), 0.4 * (0.9 * a).cos()) * 1.5;
            let d = (aim - o).normalize();
            let (s, p) = (stored.intersect(o, d), plain.intersect(o, d));
            assert_eq!(s.is_some(), p.is_some(), "ray {k}");
            if let (Some(s), Some(p)) = (s, p) {
                assert!(
                    (s.t - p.t).abs() <= 1e-12 * p.t,
                    "ray {k}: {} vs {}",
                    s.t,
                    p.t
                );
                assert!((s.normal - p.normal).length() <= 1e-9, "ray {k}");
                hits += 1;
            }
            let inside = g.centre + (aim - g.centre) * 0.3;
            assert_eq!(stored.contains(inside), plain.contains(inside), "point {k}");
        }
        assert!(hits > 100, "{hits} hits");
        // A needle whose quaternion is 1 + 1e-7 long: its end moves along (and off) the axis.
        let long = DQuat::from_xyzw(q.x, q.y, q.z, q.w) * (1.0 + 1e-7f64).sqrt();
        let n = geo(long, DVec3::new(1.0, 1e-5, 1e-5));
        let tip = StoredCapsule::of(&n);
        let end = n.frame * DVec3::X;
        // The shaders' end ball: centre at (h/R, 0, 0) in p~ = Oᵀ(p − c)/R.
        let (h, r) = capsule_of(n.radii);
        let centre = n.centre + tip.frame.transpose().inverse() * DVec3::new(h, 0.0, 0.0);
        assert!(tip.contains(centre + end.normalize() * (0.99 * r)));
        let normalised = Capsule::of(&n);
        assert!(
            (normalised.c + normalised.axis * h - centre).length() > 1e-3 * r,
            "the normalised axis's end is apart from the stored frame's"
        );
    }

    /// With no segment the capsule is the ball: every ray meets it where it meets the sphere.
    #[test]
    fn capsule_without_segment_is_the_sphere() {
        let (c, r) = (DVec3::new(3.0, -1.0, 2.0), 0.7);
        let ball = Capsule {
            c,
            axis: DVec3::new(0.6, 0.0, 0.8),
            h: 0.0,
            r,
        };
        let t_inv = DMat3::from_diagonal(DVec3::splat(1.0 / r));
        let mut hits = 0;
        for k in 0..200 {
            let a = f64::from(k) * 0.7;
            let o = c + DVec3::new(a.cos(), (1.3 * a).sin(), 0.5 * a.sin()) * 5.0;
            let aim = c + DVec3::new((2.1 * a).sin(), a.cos(), (0.9 * a).cos()) * 0.8;
            let d = (aim - o).normalize();
            let want = crate::shape::ellipsoid::intersect(o, d, c, &t_inv);
            let got = ball.intersect(o, d);
            assert_eq!(got.is_some(), want.is_some(), "ray {k}");
            if let (Some(g), Some((t, p_t))) = (got, want) {
                assert!((g.t - t).abs() <= 1e-12 * t, "ray {k}: {} vs {t}", g.t);
                assert!((g.normal - p_t.normalize()).length() <= 1e-12, "ray {k}");
                hits += 1;
            }
        }
        assert!(hits > 50 && hits < 200, "{hits} hits");
    }

    /// The capsule vectors: end points a, b and radius R; one side and one ball hit.
    #[test]
    fn capsule_hits_match_the_test_vectors() {
        let mut checked = 0;
        for case in cases().iter().filter(|c| c["kind"] == "capsule") {
            let id = case["id"].as_str().unwrap();
            let g = &case["glyph"];
            let e = &case["expected"];
            let (a, b) = (v3(&g["a"]), v3(&g["b"]));
            let cap = Capsule {
                c: (a + b) / 2.0,
                axis: (b - a).normalize(),
                h: (b - a).length() / 2.0,
                r: g["R"].as_f64().unwrap(),
            };
            let o = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let hit = cap.intersect(o, d).expect(id);
            let size = cap.h + cap.r;
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
            // From inside (the centre), the only forward crossing is the exit: on the surface,
            // its normal along the ray.
            let exit = cap.intersect(cap.c, d).expect(id);
            let q = d * exit.t;
            assert!(cap.contains(cap.c));
            assert!(
                ((q - cap.foot(q)).length() - cap.r).abs() <= 1e-12 * size,
                "{id}: exit"
            );
            assert!(exit.normal.dot(d) > 0.0, "{id}: exit normal");
            checked += 1;
        }
        assert_eq!(checked, 2);
    }

    #[test]
    fn unit_capsule_vertices_are_their_end_plus_the_normal() {
        for level in 0..=2 {
            for v in unit_capsule(level).vertices {
                // The end plus the unit normal, on the outer side of its end.
                let p = v.position.map(f64::from);
                let n = v.normal.map(f64::from);
                let end = p[0].signum();
                assert!(
                    (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0).abs() < 1e-6,
                    "{v:?}"
                );
                assert!(
                    (p[0] - end - n[0]).abs() < 1e-6 && p[1] == n[1] && p[2] == n[2],
                    "{v:?}"
                );
                assert!(n[0] * end >= -1e-7, "{v:?}");
            }
        }
        assert_eq!(Kind.mesh_stats(0), (26, 48));
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
            params: [0; 2],
        };
        let half = Kind.bounds(&geo);
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
}
