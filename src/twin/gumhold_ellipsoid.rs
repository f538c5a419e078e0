//! The CPU twin of shaders/gumhold_ellipsoid.wgsl, in f64, with the notes' names. It exists so
//! the shader's formulas can be checked against shared/math/test-vectors.json without a GPU
//! (the GPU path itself is checked against the reference in tests/gpu/ray_casters.rs).

use glam::{DMat3, DMat4, DVec2, DVec3};

/// Per-glyph quad set-up (the vertex stage before the corner is chosen).
#[derive(Debug, Clone, Copy)]
pub struct QuadSetup {
    /// Perspective: e~ = T⁻¹(e − c); orthographic: d~ = T⁻¹ d (T: any matrix with
    /// T Tᵀ = O diag(r²) Oᵀ; the shader's is O diag(r)).
    pub e_t: DVec3,
    /// E = |e~| (perspective) or |d~| (orthographic).
    pub e_norm: f64,
    /// u~ = 1/E (perspective) or 1/|d~| (orthographic), the flat varying `u`.
    pub u: f64,
    pub m_t: DVec3,
    pub r_t: f64,
    pub x_hat: DVec3,
    pub y_hat: DVec3,
    pub z_hat: DVec3,
}

/// `orthonormal_pair` in common.wgsl (Duff et al.; glam `any_orthonormal_pair`).
pub fn orthonormal_pair(z: DVec3) -> (DVec3, DVec3) {
    let s = if z.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + z.z);
    let b = z.x * z.y * a;
    (
        DVec3::new(1.0 + s * z.x * z.x * a, s * b, -s * z.x),
        DVec3::new(b, s + z.y * z.y * a, -z.y),
    )
}

/// `None` when the eye is inside or on the glyph (the shader culls it).
pub fn setup_perspective(t_inv: &DMat3, c: DVec3, eye: DVec3) -> Option<QuadSetup> {
    let e_t = *t_inv * (eye - c);
    let e2 = e_t.length_squared();
    if e2.is_nan() || e2 <= crate::shape::rules::EYE_INSIDE_E2 {
        return None;
    }
    let e = e2.sqrt();
    let z_hat = -e_t / e;
    let (x_hat, y_hat) = orthonormal_pair(z_hat);
    Some(QuadSetup {
        e_t,
        e_norm: e,
        u: 1.0 / e,
        m_t: e_t / e2,
        r_t: ((e2 - 1.0) / e2).sqrt(),
        x_hat,
        y_hat,
        z_hat,
    })
}

pub fn setup_orthographic(t_inv: &DMat3, forward: DVec3) -> QuadSetup {
    let d_t = *t_inv * forward;
    let len = d_t.length();
    let z_hat = d_t / len;
    let (x_hat, y_hat) = orthonormal_pair(z_hat);
    QuadSetup {
        e_t: d_t,
        e_norm: len,
        u: 1.0 / len,
        m_t: DVec3::ZERO,
        r_t: 1.0,
        x_hat,
        y_hat,
        z_hat,
    }
}

impl QuadSetup {
    /// V~ for the quad point with attribute q (a corner when q = (±1, ±1)).
    pub fn quad_point_t(&self, q: DVec2) -> DVec3 {
        self.m_t + self.r_t * (q.x * self.x_hat + q.y * self.y_hat)
    }

    /// The attribute q where a world ray (parameter-space origin `o_t`, direction `d_t`) meets
    /// the quad's plane: what `splat_q` finds for that pixel.
    pub fn q_of_ray(&self, o_t: DVec3, d_t: DVec3) -> DVec2 {
        // The plane p~ · z^ = m~ · z^ (−1/E in perspective, 0 orthographic).
        let s = (self.m_t.dot(self.z_hat) - o_t.dot(self.z_hat)) / d_t.dot(self.z_hat);
        let p = o_t + s * d_t - self.m_t;
        DVec2::new(p.dot(self.x_hat), p.dot(self.y_hat)) / self.r_t
    }
}

/// What the fragment stage computes.
#[derive(Debug, Clone, Copy)]
pub struct FragmentResult {
    pub kappa: f64,
    pub p_t: DVec3,
    /// World hit point (perspective: V − κ v; orthographic: V + τ d).
    pub point: DVec3,
    /// Unit world normal T⁻ᵀ p~ (T⁻¹ p~ when T is symmetric).
    pub normal: DVec3,
    /// Standard-Z depth of the hit point.
    pub depth: f64,
}

/// The per-frame constants the fragment stage reads from the camera uniform.
#[derive(Debug, Clone, Copy)]
pub struct FrameConstants {
    pub view_proj: DMat4,
    pub ortho: bool,
}

impl FrameConstants {
    pub fn new(view: &DMat4, proj: &DMat4, ortho: bool) -> Self {
        Self {
            view_proj: *proj * *view,
            ortho,
        }
    }
}

/// `cast_hit` in the shader for quad point q (the shader finds q from the pixel, `splat_q`;
/// here it is given); `None` where the shader discards (q~² > 1).
pub fn fragment(
    setup: &QuadSetup,
    t: &DMat3,
    t_inv: &DMat3,
    c: DVec3,
    k: &FrameConstants,
    q: DVec2,
) -> Option<FragmentResult> {
    let q2 = q.length_squared();
    if q2 > 1.0 {
        return None;
    }
    let alpha = (1.0 - q2).sqrt();
    // `cast_p`: u = 1/E in perspective (κ = uα/(1 + uα)), 0 orthographic (κ = α).
    let u = if k.ortho { 0.0 } else { setup.u };
    let beta = u * alpha;
    let p_t = (setup.r_t * (q.x * setup.x_hat + q.y * setup.y_hat) - (u + alpha) * setup.z_hat)
        / (1.0 + beta);
    let kappa = if k.ortho { alpha } else { beta / (1.0 + beta) };
    let point = c + *t * p_t;
    // `view_depth` of the hit's view z.
    let clip = k.view_proj * point.extend(1.0);
    Some(FragmentResult {
        kappa,
        p_t,
        point,
        normal: (t_inv.transpose() * p_t).normalize(),
        depth: clip.z / clip.w,
    })
}

/// The proxy Gumhold's vertex stage draws for an instance, in pixel coordinates.
#[derive(Debug, Clone, PartialEq)]
pub enum ProxyShape {
    /// Not drawn (eye inside the glyph, or wholly clipped).
    None,
    /// The near-plane proxy: the whole viewport.
    Viewport,
    /// The quad's corners in strip order (−,−), (+,−), (−,+), (+,+), all in front of the eye.
    Quad([DVec2; 4]),
    /// The quad clipped by the view volume (a convex polygon).
    Clipped(Vec<DVec2>),
}

impl ProxyShape {
    /// Continuous pixel area inside the viewport.
    pub fn area(&self, width: u32, height: u32) -> f64 {
        let shoelace = |p: &[DVec2]| {
            (0..p.len())
                .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
                .sum::<f64>()
                .abs()
                / 2.0
        };
        match self {
            ProxyShape::None => 0.0,
            ProxyShape::Viewport => f64::from(width) * f64::from(height),
            ProxyShape::Quad(q) => {
                shoelace(&clip_to_viewport(&[q[0], q[1], q[3], q[2]], width, height))
            }
            ProxyShape::Clipped(p) => shoelace(&clip_to_viewport(p, width, height)),
        }
    }

    /// The screen triangles the rasteriser gets: the strip's two, or a fan of a clipped polygon.
    pub fn triangles(&self, width: u32, height: u32) -> Vec<[DVec2; 3]> {
        let (w, h) = (f64::from(width), f64::from(height));
        match self {
            ProxyShape::None => vec![],
            ProxyShape::Viewport => {
                let c = [
                    DVec2::ZERO,
                    DVec2::new(w, 0.0),
                    DVec2::new(0.0, h),
                    DVec2::new(w, h),
                ];
                vec![[c[0], c[1], c[2]], [c[1], c[2], c[3]]]
            }
            ProxyShape::Quad(q) => vec![[q[0], q[1], q[2]], [q[1], q[2], q[3]]],
            ProxyShape::Clipped(p) => (1..p.len().saturating_sub(1))
                .map(|k| [p[0], p[k], p[k + 1]])
                .collect(),
        }
    }
}

/// A convex polygon clipped to the pixel rectangle [0, w] x [0, h].
fn clip_to_viewport(poly: &[DVec2], width: u32, height: u32) -> Vec<DVec2> {
    let (w, h) = (f64::from(width), f64::from(height));
    let planes: [&dyn Fn(DVec2) -> f64; 4] = [&|p| p.x, &|p| w - p.x, &|p| p.y, &|p| h - p.y];
    clip_polygon(poly.to_vec(), &planes)
}

/// Sutherland–Hodgman: keep the part of a convex polygon where every plane function is ≥ 0.
fn clip_polygon<P>(mut poly: Vec<P>, planes: &[&dyn Fn(P) -> f64]) -> Vec<P>
where
    P: Copy
        + std::ops::Add<Output = P>
        + std::ops::Sub<Output = P>
        + std::ops::Mul<f64, Output = P>,
{
    for plane in planes {
        let mut out = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (plane(a), plane(b));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                out.push(a + (b - a) * (da / (da - db)));
            }
        }
        poly = out;
    }
    poly
}

/// Fragment-shader invocations a rasteriser that shades whole `block` x `block` tiles reports
/// (llvmpipe/lavapipe: 4x4, every lane counted): `block²` per tile holding a covered pixel
/// centre, per triangle.
pub fn tile_invocations(tris: &[[DVec2; 3]], width: u32, height: u32, block: u32) -> u64 {
    let mut total = 0u64;
    let mut tiles: Vec<(u32, u32)> = Vec::new();
    for t in tris {
        let e = |a: DVec2, b: DVec2, p: DVec2| (b - a).perp_dot(p - a);
        let area = e(t[0], t[1], t[2]);
        if area == 0.0 || !area.is_finite() {
            continue;
        }
        let lo = t[0].min(t[1]).min(t[2]).max(DVec2::ZERO);
        let hi = t[0]
            .max(t[1])
            .max(t[2])
            .min(DVec2::new(f64::from(width), f64::from(height)));
        tiles.clear();
        let (i0, i1) = (
            (lo.x - 0.5).ceil().max(0.0) as u32,
            (hi.x - 0.5).floor() as i64,
        );
        let (j0, j1) = (
            (lo.y - 0.5).ceil().max(0.0) as u32,
            (hi.y - 0.5).floor() as i64,
        );
        for j in j0..=(j1.max(-1) as u32).min(height.saturating_sub(1)) {
            if i64::from(j) > j1 {
                break;
            }
            for i in i0..=(i1.max(-1) as u32).min(width.saturating_sub(1)) {
                if i64::from(i) > i1 {
                    break;
                }
                let p = DVec2::new(f64::from(i) + 0.5, f64::from(j) + 0.5);
                let (a, b, c) = (e(t[1], t[2], p), e(t[2], t[0], p), e(t[0], t[1], p));
                let inside = if area > 0.0 {
                    a >= 0.0 && b >= 0.0 && c >= 0.0
                } else {
                    a <= 0.0 && b <= 0.0 && c <= 0.0
                };
                if inside {
                    let tile = (i / block, j / block);
                    if !tiles.contains(&tile) {
                        tiles.push(tile);
                    }
                }
            }
        }
        total += tiles.len() as u64 * u64::from(block * block);
    }
    total
}

/// The proxy Gumhold's vertex stage draws for instance `i` of `scene` (the fragments it shades,
/// since writing depth disables early rejection). Ellipsoids use their own quad, the other kinds
/// the quad of their bounding ellipsoid ([`crate::twin::ShapeTwin::gumhold_bound`]: a cylinder's
/// √3 along the axis, √(3/2) across; a capsule's circumscribed cylinder's; the ball around a
/// superquadric's unit box), or the whole viewport when the eye is inside that ellipsoid.
pub fn proxy_shape(
    scene: &crate::scene::Scene,
    camera: &crate::camera::Camera,
    i: usize,
) -> ProxyShape {
    let geo = scene.geometry(i);
    let eye = camera.eye - scene.origin;
    let (w, h) = (f64::from(camera.width), f64::from(camera.height));
    let ellipsoid = scene.kind == crate::scene::GlyphKind::Ellipsoid;
    let radii = if ellipsoid {
        geo.radii
    } else {
        match crate::twin::of(scene.kind).gumhold_bound(&geo, eye, camera.is_ortho()) {
            Some(r) => r,
            None => return ProxyShape::None,
        }
    };
    // Both shaders work in the glyph's principal frame scaled per axis, T = O diag(r) (not the
    // symmetric O diag(r) Oᵀ, whose f32 rounding mixes a thin axis's ×k components into the
    // others): the quad is the square of that frame.
    let (t, t_inv) = (
        geo.frame * DMat3::from_diagonal(radii),
        DMat3::from_diagonal(radii.recip()) * geo.frame.transpose(),
    );
    let setup = if camera.is_ortho() {
        setup_orthographic(&t_inv, camera.forward())
    } else {
        match setup_perspective(&t_inv, geo.centre, eye) {
            Some(s) => s,
            // Ellipsoid: culled. Solids: the near-plane proxy covers the viewport.
            None if !ellipsoid => return ProxyShape::Viewport,
            None => return ProxyShape::None,
        }
    };
    let view = camera.view(scene.origin);
    let view_proj = camera.projection_matrix() * view;
    // The ellipsoid's quad reaches PROXY_MARGIN_PX beyond the silhouette (`proxy_growth` in
    // shaders/method/gumhold_ellipsoid.wgsl): its half widths in pixels on the view plane
    // through the centre, each grown by the margin.
    let grow = if ellipsoid {
        let w = if camera.is_ortho() {
            1.0
        } else {
            (geo.centre - eye).dot(camera.forward()).max(1e-30)
        };
        let half = |a: DVec3| {
            view.transform_vector3(t * (setup.r_t * a))
                .truncate()
                .length()
                * camera.pixels_per_unit()
                / w
        };
        DVec2::ONE
            + crate::shape::rules::PROXY_MARGIN_PX
                / DVec2::new(half(setup.x_hat), half(setup.y_hat)).max(DVec2::splat(1e-30))
    } else {
        DVec2::ONE
    };
    let to_px =
        |p: glam::DVec4| DVec2::new((p.x / p.w + 1.0) * w / 2.0, (1.0 - p.y / p.w) * h / 2.0);
    let strip: Vec<glam::DVec4> = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .iter()
        .map(|&(sx, sy)| {
            view_proj * (geo.centre + t * setup.quad_point_t(DVec2::new(sx, sy) * grow)).extend(1.0)
        })
        .collect();
    if strip.iter().all(|p| p.w > 0.0 && p.z >= 0.0 && p.z <= p.w) {
        return ProxyShape::Quad([
            to_px(strip[0]),
            to_px(strip[1]),
            to_px(strip[2]),
            to_px(strip[3]),
        ]);
    }
    // Polygon order (−,−), (+,−), (+,+), (−,+), clipped in clip space against the near and far
    // planes and the four side planes.
    let poly: Vec<glam::DVec4> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(sx, sy)| {
            view_proj * (geo.centre + t * setup.quad_point_t(DVec2::new(sx, sy) * grow)).extend(1.0)
        })
        .collect();
    let planes: [&dyn Fn(glam::DVec4) -> f64; 6] = [
        &|p| p.z,
        &|p| p.w - p.z,
        &|p| p.w + p.x,
        &|p| p.w - p.x,
        &|p| p.w + p.y,
        &|p| p.w - p.y,
    ];
    let poly = clip_polygon(poly, &planes);
    if poly.is_empty() {
        return ProxyShape::None;
    }
    ProxyShape::Clipped(poly.into_iter().map(to_px).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, m3, m4, v3};

    fn close(a: DVec3, b: DVec3, tol: f64, what: &str) {
        assert!((a - b).length() <= tol, "{what}: {a} vs {b}");
    }

    /// Every ellipsoid case of the shared vectors, through the same steps as the shader:
    /// set-up, corners (world and NDC), the pixel's q, κ, hit point, normal and depth.
    #[test]
    fn shader_math_matches_the_test_vectors() {
        let mut checked = 0;
        for case in &cases() {
            if case["kind"] != "ellipsoid" {
                continue;
            }
            let id = case["id"].as_str().unwrap();
            let e = &case["expected"];
            let gh = &e["gumhold"];
            let t = m3(&case["glyph"]["T"]);
            let c = v3(&case["glyph"]["c"]);
            let t_inv = t.inverse();
            let size = (0..3)
                .map(|i| case["glyph"]["radii"][i].as_f64().unwrap())
                .fold(0.0, f64::max);
            let cam = &case["camera"];
            let ortho = cam["projection"] == "orthographic";
            let eye = v3(&cam["eye"]);
            let forward = (v3(&cam["target"]) - eye).normalize();
            let k = FrameConstants::new(&m4(&e["view_cols"]), &m4(&e["proj_cols"]), ortho);
            let setup = if ortho {
                setup_orthographic(&t_inv, forward)
            } else {
                match setup_perspective(&t_inv, c, eye) {
                    Some(s) => s,
                    None => {
                        assert_eq!(gh["applicable"], false, "{id}: culled but applicable");
                        checked += 1;
                        continue;
                    }
                }
            };
            let tol = 1e-9;
            if ortho {
                close(setup.e_t, v3(&gh["d_tilde"]), tol, id);
            } else {
                close(setup.e_t, v3(&gh["e_tilde"]), tol * setup.e_norm, id);
                assert!(
                    (setup.u - gh["u_tilde"].as_f64().unwrap()).abs() <= tol,
                    "{id}: u"
                );
                close(setup.m_t, v3(&gh["m_tilde"]), tol, id);
                assert!(
                    (setup.r_t - gh["r_tilde"].as_f64().unwrap()).abs() <= tol,
                    "{id}: r"
                );
            }
            close(setup.x_hat, v3(&gh["x_hat"]), tol, id);
            close(setup.y_hat, v3(&gh["y_hat"]), tol, id);
            close(setup.z_hat, v3(&gh["z_hat"]), tol, id);
            for (name, sx, sy) in [
                ("mm", -1.0, -1.0),
                ("pm", 1.0, -1.0),
                ("mp", -1.0, 1.0),
                ("pp", 1.0, 1.0),
            ] {
                let v = c + t * setup.quad_point_t(DVec2::new(sx, sy));
                close(v - c, v3(&gh["corners"][name]) - c, tol * size, id);
                let clip = k.view_proj * v.extend(1.0);
                close(
                    clip.truncate() / clip.w,
                    v3(&gh["corners_ndc"][name]),
                    tol,
                    id,
                );
            }
            // The pixel's q: where its ray meets the quad plane.
            let o = v3(&e["ray"]["origin"]);
            let d = v3(&e["ray"]["dir"]);
            let q = setup.q_of_ray(t_inv * (o - c), t_inv * d);
            let want_q = DVec2::new(gh["q"][0].as_f64().unwrap(), gh["q"][1].as_f64().unwrap());
            assert!((q - want_q).length() <= 1e-8, "{id}: q {q} vs {want_q}");
            // Near the rim α = √(1 − q²) amplifies the rounding in q, so the fragment is fed the
            // vectors' q (the q check above covers `splat_q`).
            let f = fragment(&setup, &t, &t_inv, c, &k, want_q);
            assert_eq!(f.is_some(), e["hit"].as_bool().unwrap(), "{id}: hit");
            let Some(f) = f else {
                checked += 1;
                continue;
            };
            if !ortho {
                let kappa = gh["kappa"].as_f64().unwrap();
                assert!(
                    (f.kappa - kappa).abs() <= 1e-8 * kappa,
                    "{id}: kappa {} vs {kappa}",
                    f.kappa
                );
            }
            close(f.point - c, v3(&e["point"]) - c, 1e-8 * size, id);
            close(f.normal, v3(&e["normal"]), 1e-8, id);
            let depth = e["ndc_depth"].as_f64().unwrap();
            assert!(
                (f.depth - depth).abs() <= 1e-9,
                "{id}: depth {} vs {depth}",
                f.depth
            );
            // The shader's frame, T = O diag(r) (a different quad): the same hit, normal, depth.
            let g = &case["glyph"];
            let rot = DMat3::from_axis_angle(
                v3(&g["rotation_axis"]).normalize(),
                g["rotation_angle_rad"].as_f64().unwrap(),
            );
            let r = v3(&g["radii"]);
            let (tp, tp_inv) = (
                rot * DMat3::from_diagonal(r),
                DMat3::from_diagonal(r.recip()) * rot.transpose(),
            );
            let sp = if ortho {
                setup_orthographic(&tp_inv, forward)
            } else {
                setup_perspective(&tp_inv, c, eye).expect(id)
            };
            let qp = sp.q_of_ray(tp_inv * (o - c), tp_inv * d);
            let fp = fragment(&sp, &tp, &tp_inv, c, &k, qp).expect(id);
            close(fp.point - c, v3(&e["point"]) - c, 1e-7 * size, id);
            close(fp.normal, v3(&e["normal"]), 1e-7, id);
            assert!((fp.depth - depth).abs() <= 1e-8, "{id}: principal depth");
            checked += 1;
        }
        assert_eq!(checked, 10, "every ellipsoid case");
    }
}
