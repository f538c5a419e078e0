//! The CPU twin of shaders/shape/capsule.wgsl (the capsule test of cylinder-capsule.md §4 in
//! capsule space: the glyph's frame scaled by the ball's radius R, the solid within 1 of the
//! segment |x| <= h; the bounding ellipsoid whose quad Gumhold's method draws, §5; the union of
//! the end balls' screen boxes Sigg's method draws), in f64 with the shaders' names, so they
//! can be checked against shared/math/test-vectors.json.

use glam::{DMat4, DVec3};

use super::ShapeTwin;
use super::screen_box::{Proxy, QuadricBox, quadric_box};
use crate::scene::GlyphGeometry;

/// `capsule_of` in capsule.wgsl: (h in units of R, R) from a glyph's radii.
pub fn capsule_of(r: DVec3) -> (f64, f64) {
    let (h, radius) = crate::shape::capsule::capsule_of(r);
    (h / radius, radius)
}

pub struct Twin;

/// The eye in capsule space inside the capsule (`shape_contains`).
fn eye_inside(geo: &GlyphGeometry, eye: DVec3) -> bool {
    let (h, r) = capsule_of(geo.radii);
    contains((geo.frame.transpose() * (eye - geo.centre)) / r, h)
}

impl ShapeTwin for Twin {
    /// The two end balls' boxes, in capsule space for the eye.
    fn sigg_proxy(&self, view_proj: &DMat4, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Proxy {
        let (h, r) = capsule_of(geo.radii);
        if !ortho && eye_inside(geo, eye) {
            return Proxy::Culled;
        }
        let (x, y, z) = (
            geo.frame.x_axis * r,
            geo.frame.y_axis * r,
            geo.frame.z_axis * r,
        );
        let balls = [
            quadric_box(view_proj, x, y, z, geo.centre - x * h),
            quadric_box(view_proj, x, y, z, geo.centre + x * h),
        ];
        if (0..6).any(|k| balls[0].reach[k].max(balls[1].reach[k]) < 0.0) {
            return Proxy::Culled;
        }
        let behind = |q: &QuadricBox| q.r4dr4 < 0.0 && q.w_centre <= 0.0;
        match (balls[0].bbox, balls[1].bbox) {
            (Some(a), Some(b)) => Proxy::Box(a.union(b)),
            _ if behind(&balls[0]) && behind(&balls[1]) => Proxy::Culled,
            _ => Proxy::Viewport,
        }
    }

    fn gumhold_bound(&self, geo: &GlyphGeometry, eye: DVec3, ortho: bool) -> Option<DVec3> {
        let (h, r) = capsule_of(geo.radii);
        (ortho || !eye_inside(geo, eye)).then(|| bound(h) * r)
    }
}

/// The bounding ellipsoid's semi-axes in units of R: the minimal ellipsoid of the cylinder of
/// half-length h + 1 and radius 1 (√3 along the axis, √(3/2) across).
pub fn bound(h: f64) -> DVec3 {
    DVec3::new(3f64.sqrt() * (h + 1.0), 1.5f64.sqrt(), 1.5f64.sqrt())
}

/// `capsule_normal`: p minus the nearest segment point (unit on the surface).
pub fn normal(p: DVec3, h: f64) -> DVec3 {
    p - DVec3::new(p.x.clamp(-h, h), 0.0, 0.0)
}

/// `capsule_contains`.
pub fn contains(p: DVec3, h: f64) -> bool {
    normal(p, h).length_squared() <= 1.0
}

/// `capsule_roots`.
fn roots(a: f64, b: f64, c: f64, disc: f64) -> (f64, f64) {
    let q = -(b + if b >= 0.0 { 1.0 } else { -1.0 } * disc.sqrt());
    let (r1, r2) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    (r1.min(r2), r1.max(r2))
}

/// `capsule_crossing`; `None` where the shader discards.
fn crossing(o: DVec3, v: DVec3, h: f64, t: f64, entry: bool) -> Option<f64> {
    let s = o.x + t * v.x;
    if s.abs() <= h {
        return Some(t);
    }
    let ok = o - DVec3::new(if s > 0.0 { h } else { -h }, 0.0, 0.0);
    let (a, b, c) = (v.dot(v), ok.dot(v), ok.dot(ok) - 1.0);
    let disc = b * b - a * c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let (near, far) = roots(a, b, c, disc);
    Some(if entry { near } else { far })
}

/// `capsule_span`: entry and exit along o + t v; `None` where the shader discards.
pub fn span(o: DVec3, v: DVec3, h: f64) -> Option<(f64, f64)> {
    let (a, b, c) = (
        v.y * v.y + v.z * v.z,
        o.y * v.y + o.z * v.z,
        o.y * o.y + o.z * o.z - 1.0,
    );
    let side = if a > 0.0 {
        let disc = b * b - a * c;
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        roots(a, b, c, disc)
    } else if c > 0.0 {
        return None;
    } else {
        (-1e30, 1e30)
    };
    Some((
        crossing(o, v, h, side.0, true)?,
        crossing(o, v, h, side.1, false)?,
    ))
}

/// `capsule_slide`: how far along v the ray point nearest the axis lies from o, or, where that
/// lies beyond an end ball's reach (|x| > h + 1), the point nearest that ball's centre; 0 for
/// rays along the axis.
pub fn slide(o: DVec3, v: DVec3, h: f64) -> f64 {
    let a = v.y * v.y + v.z * v.z;
    if a.is_nan() || a <= 0.0 {
        return 0.0;
    }
    let s = -(o.y * v.y + o.z * v.z) / a;
    let x = o.x + s * v.x;
    if x.abs() > h + 1.0 {
        let end = DVec3::new(if x > 0.0 { h } else { -h }, 0.0, 0.0);
        return -(o - end).dot(v) / v.length_squared();
    }
    s
}

/// `shape_entry`: the entry t along o + t v, solved from the slid origin, and the normal there
/// (capsule space); `None` where the shader discards.
pub fn entry(o: DVec3, v: DVec3, h: f64) -> Option<(f64, DVec3)> {
    let s = slide(o, v, h);
    let o2 = o + s * v;
    let (t, _) = span(o2, v, h)?;
    Some((s + t, normal(o2 + t * v, h)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, m3, m4, v3};
    use crate::twin::gumhold_ellipsoid::setup_perspective;
    use crate::twin::screen_box::quadric_box;
    use glam::DMat3;

    /// Both capsule cases through the steps of gumhold_capsule.wgsl: the bounding ellipsoid, the
    /// pixel's quad point V, the capsule-space ray from V, its entry t' (the vectors' `t_quad`),
    /// hit point, normal and the depth update of §5; and Sigg's box, the union of the balls'.
    #[test]
    fn shader_math_matches_the_capsule_vectors() {
        let mut checked = 0;
        for case in cases().iter().filter(|c| c["kind"] == "capsule") {
            let id = case["id"].as_str().unwrap();
            let g = &case["glyph"];
            let e = &case["expected"];
            let (a, b) = (v3(&g["a"]), v3(&g["b"]));
            let r = g["R"].as_f64().unwrap();
            let c = (a + b) / 2.0;
            let axis = (b - a).normalize();
            let (y, z) = axis.any_orthonormal_pair();
            let o = DMat3::from_cols(axis, y, z);
            // The glyph radii whose capsule_of is this capsule: r1 = h + R, r2 = r3 = R.
            let (h, radius) = capsule_of(DVec3::new((b - a).length() / 2.0 + r, r, r));
            assert!((radius - r).abs() <= 1e-15 && (h * r - (b - a).length() / 2.0).abs() <= 1e-12);
            let size = (h + 1.0) * r;
            let rb = bound(h) * r;
            let t_b = o * DMat3::from_diagonal(rb) * o.transpose();
            let want_t = m3(&e["bounding_ellipsoid"]["T"]);
            for k in 0..3 {
                assert!(
                    (t_b.col(k) - want_t.col(k)).length() <= 1e-9 * size,
                    "{id}: bounding ellipsoid"
                );
            }
            // The shader's quad, in the glyph's frame scaled by the bounding radii.
            let eye = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let t_inv = DMat3::from_diagonal(rb.recip()) * o.transpose();
            let setup = setup_perspective(&t_inv, c, eye).expect(id);
            let q = setup.q_of_ray(t_inv * (eye - c), t_inv * d);
            assert!(
                q.x.abs() <= 1.0 && q.y.abs() <= 1.0,
                "{id}: pixel outside the quad"
            );
            let v_point = c + o * (rb * setup.quad_point_t(q));
            let v = v_point - eye;
            let o_t = o.transpose() * (v_point - c) / r;
            let v_t = o.transpose() * v / r;
            let (t, n_t) = entry(o_t, v_t, h).expect(id);
            assert_eq!(
                span(o_t, v_t, h).map(|s| (s.0 - t).abs() <= 1e-9 * t.abs().max(1.0)),
                Some(true),
                "{id}: the slid origin's entry is the ray's"
            );
            let want = e["bounding_ellipsoid"]["t_quad"].as_f64().unwrap();
            assert!(
                (t - want).abs() <= 1e-9 * want.abs().max(1e-3),
                "{id}: t' {t} vs {want}"
            );
            let p = v_point + t * v;
            assert!(
                (p - v3(&e["point"])).length() <= 1e-9 * size,
                "{id}: point {p}"
            );
            let n = (o * n_t).normalize();
            assert!((n - v3(&e["normal"])).length() <= 1e-9, "{id}: normal {n}");
            // depth(p) = depth(V) − (t' / (1 + t')) P[2][3] / w_V.
            let vp = m4(&e["proj_cols"]) * m4(&e["view_cols"]);
            let clip = vp * v_point.extend(1.0);
            let b23 = m4(&e["proj_cols"]).w_axis.z;
            let depth = clip.z / clip.w - (t / (1.0 + t)) * b23 / clip.w;
            let want_depth = e["ndc_depth"].as_f64().unwrap();
            assert!((depth - want_depth).abs() <= 1e-9, "{id}: depth {depth}");
            // Sigg: the balls' boxes at c ∓ h R n, columns R O.
            let ball = |k: f64| {
                quadric_box(
                    &vp,
                    o.x_axis * r,
                    o.y_axis * r,
                    o.z_axis * r,
                    c + axis * (k * h * r),
                )
            };
            let union = ball(-1.0)
                .bbox
                .unwrap()
                .union(ball(1.0).bbox.unwrap())
                .to_array();
            for k in 0..4 {
                let want = e["bbox_ndc"][k].as_f64().unwrap();
                assert!((union[k] - want).abs() <= 1e-9, "{id}: box {union:?}");
            }
            checked += 1;
        }
        assert_eq!(checked, 2, "both capsule cases");
    }

    /// Span from inside (exit only forward), along the axis (no side root) and a miss.
    /// A ray almost across the axis, beyond an end: the slide stays within the end ball's
    /// distance (clamping x along it would slide it by ~1/v.x), and sliding changes no answer.
    #[test]
    fn slide_stays_near_the_glyph() {
        let (v, h) = (DVec3::new(1e-9, 0.0, 1.0), 2.0);
        let o = DVec3::new(5.0, 0.3, 0.0);
        assert!(slide(o, v, h).abs() <= (o - DVec3::new(h, 0.0, 0.0)).length());
        assert!(entry(o, v, h).is_none() && span(o, v, h).is_none());
        let o = DVec3::new(2.5, 0.3, -4.0);
        let (t, n) = entry(o, v, h).unwrap();
        assert!((t - span(o, v, h).unwrap().0).abs() < 1e-12);
        assert!((n.length() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn span_covers_rays_along_the_axis_and_misses() {
        // Along the axis from far away: enters the ball at −h, leaves the ball at +h.
        let (t_in, t_out) = span(DVec3::new(-10.0, 0.2, 0.0), DVec3::X, 2.0).unwrap();
        let x_in = -2.0 - (1.0f64 - 0.04).sqrt();
        assert!((t_in - (x_in + 10.0)).abs() <= 1e-12);
        assert!((t_out - (-x_in + 10.0)).abs() <= 1e-12);
        // Parallel to the axis outside the radius: a miss; across, beside a ball: a miss.
        assert!(span(DVec3::new(-10.0, 1.1, 0.0), DVec3::X, 2.0).is_none());
        assert!(span(DVec3::new(3.5, -5.0, 0.0), DVec3::Y, 2.0).is_none());
        // Across a ball's cap, off the segment: the ball's chord.
        let (t_in, t_out) = span(DVec3::new(2.5, -5.0, 0.0), DVec3::Y, 2.0).unwrap();
        let half = (1.0f64 - 0.25).sqrt();
        assert!((t_in - (5.0 - half)).abs() <= 1e-12 && (t_out - (5.0 + half)).abs() <= 1e-12);
        // From the centre: the side, one unit away either way.
        let (t_in, t_out) = span(DVec3::ZERO, DVec3::Z, 2.0).unwrap();
        assert_eq!((t_in, t_out), (-1.0, 1.0));
        assert!(
            contains(DVec3::new(2.9, 0.0, 0.0), 2.0) && !contains(DVec3::new(3.1, 0.0, 0.0), 2.0)
        );
    }
}
