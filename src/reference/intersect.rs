//! Exact ray–glyph intersections in f64. The ray origin is first moved next to the glyph
//! (sigg-quadric.md §4), so nothing cancels for distant glyphs.

use glam::{DMat3, DVec3};

/// A forward hit: distance along the unit ray and the unit outward normal (world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    pub t: f64,
    pub normal: DVec3,
}

/// Front intersection of `o + t d` (d unit) with the ellipsoid |T⁻¹(p − c)| = 1 (with
/// `t_inv` = T⁻¹): `(t, p~)`. An origin inside gives the exit point (the only forward hit).
pub fn ellipsoid(o: DVec3, d: DVec3, c: DVec3, t_inv: &DMat3) -> Option<(f64, DVec3)> {
    let t0 = (c - o).dot(d);
    let o_t = *t_inv * ((o - c) + d * t0);
    let v_t = *t_inv * d;
    let alpha = v_t.length_squared();
    let beta = o_t.dot(v_t);
    let gamma = o_t.length_squared() - 1.0;
    let disc = beta * beta - alpha * gamma;
    if disc.is_nan() || disc < 0.0 || alpha <= 0.0 {
        return None;
    }
    let (near, far) = stable_roots(alpha, beta, gamma, disc);
    let tp = if t0 + near > 0.0 {
        near
    } else if t0 + far > 0.0 {
        far
    } else {
        return None;
    };
    Some((t0 + tp, o_t + v_t * tp))
}

/// Both roots of `alpha t² + 2 beta t + gamma = 0`, ascending, without cancellation.
fn stable_roots(alpha: f64, beta: f64, gamma: f64, disc: f64) -> (f64, f64) {
    let q = -(beta + beta.signum() * disc.sqrt());
    let (r1, r2) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / alpha, gamma / q)
    };
    (r1.min(r2), r1.max(r2))
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
    /// To local parameter space, where the solid is |x| ≤ 1, y² + z² ≤ 1.
    fn param(&self, v: DVec3) -> DVec3 {
        (self.frame.transpose() * v) / self.radii
    }

    pub fn contains(&self, p: DVec3) -> bool {
        let q = self.param(p - self.c);
        q.x.abs() <= 1.0 && q.y * q.y + q.z * q.z <= 1.0
    }

    /// Half-extents of its axis-aligned bounding box.
    pub fn half_extents(&self) -> DVec3 {
        let a = self.frame.x_axis * self.radii.x;
        let u = self.frame.y_axis * self.radii.y;
        let v = self.frame.z_axis * self.radii.z;
        a.abs() + DVec3::new(u.x.hypot(v.x), u.y.hypot(v.y), u.z.hypot(v.z))
    }

    /// First forward crossing of the surface by `o + t d` (slab method, sigg-quadric.md §7).
    pub fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let t0 = (self.c - o).dot(d);
        let o_t = self.param((o - self.c) + d * t0);
        let v_t = self.param(d);
        let (mut side_in, mut side_out) = (f64::NEG_INFINITY, f64::INFINITY);
        let a = v_t.y * v_t.y + v_t.z * v_t.z;
        let b = o_t.y * v_t.y + o_t.z * v_t.z;
        let g = o_t.y * o_t.y + o_t.z * o_t.z - 1.0;
        if a > 0.0 {
            let disc = b * b - a * g;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            (side_in, side_out) = stable_roots(a, b, g, disc);
        } else if g > 0.0 {
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
    /// The point of the segment nearest to `p` (relative to the centre).
    fn foot(&self, p: DVec3) -> DVec3 {
        self.axis * p.dot(self.axis).clamp(-self.h, self.h)
    }

    pub fn contains(&self, p: DVec3) -> bool {
        let q = p - self.c;
        (q - self.foot(q)).length_squared() <= self.r * self.r
    }

    /// Half-extents of its axis-aligned bounding box.
    pub fn half_extents(&self) -> DVec3 {
        (self.axis * self.h).abs() + self.r
    }

    /// First forward crossing of the surface by `o + t d` (`d` unit): §4 of the note for the
    /// entry and, reversed, for the exit, from the ray point nearest the centre (§5's
    /// well-conditioned origin), so nothing cancels for distant glyphs.
    pub fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
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
            let hit = ellipsoid(o, d, c, &t_inv);
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
            let want = ellipsoid(o, d, c, &t_inv);
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
}
