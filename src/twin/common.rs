//! The f64 twin of `shade()` in shaders/common.wgsl: Blinn-Phong with a headlight.

use glam::DVec3;

use crate::frame::Lighting;

/// `base` in [0, 1]; `n_view` unit; `p_view` the view-space hit point.
pub fn shade(lighting: &Lighting, ortho: bool, base: DVec3, n_view: DVec3, p_view: DVec3) -> DVec3 {
    let l = if ortho {
        DVec3::Z
    } else {
        (-p_view).normalize()
    };
    let nl = n_view.dot(l).max(0.0);
    let spec = nl.powf(f64::from(lighting.shininess));
    (base * (f64::from(lighting.ambient) + f64::from(lighting.diffuse) * nl)
        + DVec3::splat(f64::from(lighting.specular) * spec))
    .clamp(DVec3::ZERO, DVec3::ONE)
}

/// Unorm8 conversion as the GPU does it (round to nearest).
pub fn to_unorm8(x: f64) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}
