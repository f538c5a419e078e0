//! The key light: given in view space (it moves with the camera, as a photographer's key light
//! does), turned into a world direction, and the orthographic camera its shadow map is drawn
//! with: looking along the light at the scene's bounding box, framed tight on it.

use glam::{DMat4, DVec3};

use crate::camera::{Camera, Framing};
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

/// The shadow map's camera: orthographic, looking along the light onto the scene's box `centre ±
/// half` ([`crate::scene::Scene`]'s), `shadows.map_size` texels square.
pub fn shadow_camera(camera: &Camera, centre: DVec3, half: DVec3, shadows: &Shadows) -> Camera {
    let l = world_direction(camera, shadows);
    // Any up not along the light; the camera's own keeps the map's orientation stable.
    let up = [view_axes(camera)[1], DVec3::Z, DVec3::X]
        .into_iter()
        .find(|u| u.cross(l).length() > 1e-3)
        .unwrap_or(DVec3::Y);
    let framing = Framing {
        ortho: true,
        toward: Some((-l, up)),
        ..Framing::default()
    };
    let half = if half.is_finite() && half.length() > 0.0 {
        half
    } else {
        DVec3::ONE
    };
    Camera::frame_box(&framing, centre, half, shadows.map_size, shadows.map_size)
}

/// Light clip space from the eye's view space (both relative to `origin`), for looking up the
/// shadow map of a point the eye sees.
pub fn view_to_light_clip(camera: &Camera, light: &Camera, origin: DVec3) -> DMat4 {
    light.projection_matrix() * light.view(origin) * camera.view(origin).inverse()
}
