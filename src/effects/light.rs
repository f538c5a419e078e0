//! The key light: given in view space (it moves with the camera, as a photographer's key light
//! does), turned into a world direction, and the orthographic camera its shadow map is drawn
//! with: looking along the light at the part of the scene's box the eye sees.

use glam::{DMat4, DVec3, DVec4};

use crate::camera::{Camera, Projection};
use crate::effects::Shadows;

/// The camera's right, up and backward unit vectors (view x, y, z in world space).
fn view_axes(camera: &Camera) -> [DVec3; 3] {
    let f = camera.forward();
    let right = f.cross(camera.up).normalize();
    let up = right.cross(f);
    [right, up, -f]
}

/// Unit direction towards the key light in view space; `None` for a zero or non-finite vector.
pub fn view_direction(light: [f64; 3]) -> Option<DVec3> {
    let l = DVec3::from_array(light);
    let n = l.length();
    (n.is_finite() && n > 0.0).then(|| l / n)
}

/// Unit direction towards the key light in world space.
pub fn world_direction(camera: &Camera, shadows: &Shadows) -> DVec3 {
    let l = view_direction(shadows.light).unwrap_or(DVec3::Z);
    let [x, y, z] = view_axes(camera);
    (x * l.x + y * l.y + z * l.z).normalize()
}

/// Where the shadow map looks: orthographic, along the light, onto the part of the scene's box
/// `centre ± half` ([`crate::scene::Scene`]'s) that `camera`'s whole image sees, `shadows.map_size` texels
/// square.
///
/// Only points the eye sees receive shadows, and a directional light's rays are parallel, so
/// the map needs to cover only the light-space footprint of the box cut by the eye's frustum
/// (its corners are the vertices of that convex cut); in depth it spans the whole box, so every
/// caster between the light and a seen point is in it. A close view gets texels as fine as its
/// pixels instead of a whole-field map. The texel is square, kept from 2^(k/32) sizes, and the
/// map's centre snapped to whole texels, so a view that pans or zooms a little keeps the same
/// texel grid (no swimming shadow edges). A margin of `pcf_radius + 2` texels keeps the filter's
/// reach inside the map. With [`Shadows::glyph_fit`] the side grows (in steps of 128 texels, so
/// that a zoom does not make new textures every frame) until a glyph of `glyph_radius` (the
/// scene's mean largest radius; 0: none) spans [`Shadows::TEXELS_PER_GLYPH`] texels, up to twice
/// `shadows.map_size`.
pub fn shadow_camera(
    camera: &Camera,
    centre: DVec3,
    half: DVec3,
    shadows: &Shadows,
    glyph_radius: f64,
) -> Camera {
    let l = world_direction(camera, shadows);
    // Any up not along the light; the camera's own keeps the map's orientation stable.
    let up = [view_axes(camera)[1], DVec3::Z, DVec3::X]
        .into_iter()
        .find(|u| u.cross(l).length() > 1e-3)
        .unwrap_or(DVec3::Y);
    let forward = -l;
    let right = forward.cross(up).normalize();
    let up = right.cross(forward);
    let half = if half.is_finite() && half.length() > 0.0 {
        half
    } else {
        DVec3::ONE
    };
    let radius = half.length();
    let corners = box_corners(half);
    // Light-space (right, up) bounds of what the eye sees, relative to `centre`; the whole box
    // when the eye sees none of it (nothing then receives a shadow).
    // The whole image's frustum: every tile of a tiled image draws the same map.
    let seen = visible_corners(&camera.full(), centre, half);
    let points = if seen.is_empty() { &corners[..] } else { &seen };
    let (mut lo, mut hi) = (glam::DVec2::splat(f64::MAX), glam::DVec2::splat(f64::MIN));
    for p in points {
        let q = glam::DVec2::new(p.dot(right), p.dot(up));
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let margin = f64::from(shadows.pcf_radius + 2);
    let extent = (hi - lo).max_element().max(radius * 1e-6);
    let mut n = shadows.map_size.max(16);
    if shadows.glyph_fit && glyph_radius > 0.0 {
        let need = Shadows::TEXELS_PER_GLYPH * extent / (2.0 * glyph_radius) + 2.0 * margin;
        let most = n.saturating_mul(2).min(Shadows::MAX_MAP).max(n);
        if need.is_finite() && need > f64::from(n) {
            n = ((need.ceil() as u32).next_multiple_of(128)).clamp(n, most);
        }
    }
    let texel = quantised(extent / (f64::from(n) - 2.0 * margin).max(1.0));
    let mid = ((lo + hi) * 0.5 / texel).round() * texel;
    let (d_lo, d_hi) = corners.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.dot(forward)), b.max(p.dot(forward)))
    });
    let pad = 0.01 * (d_hi - d_lo) + radius * 1e-6;
    let eye = centre + right * mid.x + up * mid.y + forward * (d_lo - pad);
    Camera {
        eye,
        target: eye + forward,
        up,
        projection: Projection::Orthographic {
            height: texel * f64::from(n),
        },
        near: 0.0,
        far: d_hi - d_lo + 2.0 * pad,
        width: n,
        height: n,
        crop: None,
    }
}

/// The next size at or above `s` among 2^(k/32).
fn quantised(s: f64) -> f64 {
    ((s.log2() * 32.0).ceil() / 32.0).exp2()
}

fn box_corners(half: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|k| {
        let s = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
        DVec3::new(s(0) * half.x, s(1) * half.y, s(2) * half.z)
    })
}

/// The vertices of the box `centre ± half` cut by `camera`'s frustum, relative to `centre`:
/// every point where three of the twelve planes meet and that lies inside all of them (a
/// degenerate cut, such as a flat box, still gives its corners).
pub fn visible_corners(camera: &Camera, centre: DVec3, half: DVec3) -> Vec<DVec3> {
    let mut planes: Vec<DVec4> = camera.frustum_planes(centre).to_vec();
    for (axis, h) in [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .zip(half.to_array())
    {
        planes.push(axis.extend(h));
        planes.push((-axis).extend(h));
    }
    let scale = half.length().max(1e-300);
    let tolerance = 1e-9 * scale;
    let mut out = Vec::new();
    for a in 0..planes.len() {
        for b in a + 1..planes.len() {
            for c in b + 1..planes.len() {
                let m = glam::DMat3::from_cols(
                    planes[a].truncate(),
                    planes[b].truncate(),
                    planes[c].truncate(),
                )
                .transpose();
                if m.determinant().abs() < 1e-12 {
                    continue;
                }
                let p = m.inverse() * -DVec3::new(planes[a].w, planes[b].w, planes[c].w);
                if p.is_finite()
                    && planes
                        .iter()
                        .all(|q| q.truncate().dot(p) + q.w >= -tolerance)
                {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// Light clip space from the eye's view space (both relative to `origin`), for looking up the
/// shadow map of a point the eye sees.
pub fn view_to_light_clip(camera: &Camera, light: &Camera, origin: DVec3) -> DMat4 {
    light.projection_matrix() * light.view(origin) * camera.view(origin).inverse()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Framing;

    fn eye(zoom: f64, ortho: bool) -> Camera {
        let framing = Framing {
            zoom,
            ortho,
            ..Framing::default()
        };
        Camera::frame_box(&framing, CENTRE, HALF, 320, 240)
    }

    const CENTRE: DVec3 = DVec3::new(3.0, -2.0, 7.0);
    const HALF: DVec3 = DVec3::new(4.0, 2.0, 1.0);

    /// Where `p` (world) lands in the map: light NDC x, y.
    fn in_map(light: &Camera, p: DVec3) -> glam::DVec2 {
        let c = light.projection_matrix() * light.view(DVec3::ZERO) * p.extend(1.0);
        glam::DVec2::new(c.x / c.w, c.y / c.w)
    }

    /// Points of the box the eye sees, by rejection: inside the box and every frustum plane.
    fn seen_points(camera: &Camera) -> Vec<DVec3> {
        let planes = camera.frustum_planes(DVec3::ZERO);
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        (0..20_000)
            .map(|_| CENTRE + HALF * DVec3::new(next(), next(), next()))
            .filter(|p| planes.iter().all(|q| q.truncate().dot(*p) + q.w >= 0.0))
            .collect()
    }

    #[test]
    fn the_map_holds_every_point_the_eye_sees_and_shrinks_with_the_view() {
        let shadows = Shadows::default();
        let mut texels = Vec::new();
        for (zoom, ortho) in [(1.0, false), (3.0, false), (1.0, true), (4.0, true)] {
            let camera = eye(zoom, ortho);
            let light = shadow_camera(&camera, CENTRE, HALF, &shadows, 0.0);
            assert_eq!((light.width, light.height), (1024, 1024));
            let seen = seen_points(&camera);
            assert!(seen.len() > 100, "zoom {zoom}: {} points seen", seen.len());
            // The filter reaches pcf_radius + 1 texels: that much margin stays inside.
            let reach = 2.0 * f64::from(shadows.pcf_radius + 1) / f64::from(light.width);
            for p in &seen {
                let q = in_map(&light, *p);
                assert!(
                    q.abs().max_element() <= 1.0 - reach,
                    "zoom {zoom}: {p} at {q}"
                );
                let d = (*p - light.eye).dot(light.forward());
                assert!(d >= light.near && d <= light.far, "zoom {zoom}: depth {d}");
            }
            // Every caster lies in the map's depth range.
            for c in box_corners(HALF) {
                let d = (CENTRE + c - light.eye).dot(light.forward());
                assert!(d > light.near && d < light.far);
            }
            texels.push(light.projection_height() / f64::from(light.height));
        }
        // Zoomed in, the texels are finer than for the whole field; not by the zoom, as the
        // part seen runs through the box's whole depth along the view, which the light sees
        // from aside (0.82 and 0.74 here).
        assert!(texels[1] < 0.9 * texels[0], "{texels:?}");
        assert!(texels[3] < 0.9 * texels[2], "{texels:?}");
    }

    #[test]
    fn small_glyphs_raise_the_map_to_their_texels_up_to_twice_its_side() {
        let camera = eye(1.0, false);
        let asked = Shadows {
            map_size: 512,
            ..Shadows::default()
        };
        let fixed = Shadows {
            glyph_fit: false,
            ..asked
        };
        let side = |s: &Shadows, r: f64| shadow_camera(&camera, CENTRE, HALF, s, r).width;
        // Glyphs large enough for the asked map, none at all, or a side asked for: as asked.
        assert_eq!(side(&asked, 1.0), 512);
        assert_eq!(side(&asked, 0.0), 512);
        assert_eq!(side(&fixed, 0.01), 512);
        // Smaller glyphs: 9 texels per diameter, in steps of 128, at most twice the side. The
        // footprint's extent, from the map as asked (its texel is rounded up: a little more).
        let base = shadow_camera(&camera, CENTRE, HALF, &fixed, 0.0);
        let margin = 2.0 * f64::from(fixed.pcf_radius + 2);
        let extent = base.projection_height() / 512.0 * (512.0 - margin);
        for want in [600.0, 800.0, 1000.0] {
            let r = 9.0 * extent / (2.0 * (want - margin));
            let light = shadow_camera(&camera, CENTRE, HALF, &asked, r);
            let texel = light.projection_height() / f64::from(light.width);
            assert_eq!(light.width % 128, 0);
            assert!(light.width > 512 && light.width <= 1024, "{}", light.width);
            // One step of 128 less would not have held 9 texels a glyph.
            let coarser = texel * f64::from(light.width) / f64::from(light.width - 128);
            assert!(
                2.0 * r / texel >= 9.0 * 0.97,
                "r {r}: {} texels",
                2.0 * r / texel
            );
            assert!(2.0 * r / coarser < 9.0 * 1.04, "r {r}");
        }
        assert_eq!(side(&asked, 0.001), 1024);
    }

    #[test]
    fn a_small_move_keeps_the_texel_grid() {
        let shadows = Shadows::default();
        let mut camera = eye(3.0, true);
        let a = shadow_camera(&camera, CENTRE, HALF, &shadows, 0.0);
        camera.eye += camera.forward() * 1e-3 * HALF.length();
        camera.target += camera.forward() * 1e-3 * HALF.length();
        let b = shadow_camera(&camera, CENTRE, HALF, &shadows, 0.0);
        let texel = a.projection_height() / f64::from(a.height);
        assert_eq!(a.projection, b.projection);
        // The maps' centres differ by whole texels across the light.
        let d = b.eye - a.eye;
        let right = a.forward().cross(a.up).normalize();
        for axis in [right, right.cross(a.forward())] {
            let k = d.dot(axis) / texel;
            assert!((k - k.round()).abs() < 1e-6, "{k}");
        }
    }

    #[test]
    fn a_box_out_of_view_falls_back_to_the_whole_box() {
        let mut camera = eye(1.0, false);
        let away = camera.forward() * 1e3;
        camera.eye -= away;
        camera.target -= 2.0 * away;
        assert!(visible_corners(&camera, CENTRE, HALF).is_empty());
        let light = shadow_camera(&camera, CENTRE, HALF, &Shadows::default(), 0.0);
        for c in box_corners(HALF) {
            assert!(in_map(&light, CENTRE + c).abs().max_element() <= 1.0);
        }
    }
}
