//! Deferred shading, the f64 twin of `fs_composite` in shaders/composite.wgsl (its outline filter
//! is [`crate::effects::outline`], shared with the reference as it is). Without shadows it
//! is the headlight Blinn-Phong of the direct path ([`crate::twin::common::shade`]), so deferred
//! and direct frames agree; with shadows [`KEY_SHARE`] of the diffuse light comes from the key
//! light instead, scaled by how lit the point is, so that shadows show and the eye's side of
//! every glyph stays readable.

use glam::DVec3;

use crate::effects::{KEY_SHARE, Outlines};
use crate::frame::Lighting;
use crate::twin::common::shade as headlight;

/// The key light at one point: the unit direction towards it (view space) and how lit the point
/// is (0 in shadow, 1 lit, in between in a penumbra).
#[derive(Debug, Clone, Copy)]
pub struct Key {
    pub light: DVec3,
    pub lit: f64,
}

/// The colour of a pixel showing base colour `base` with unit view normal `n_view` at view
/// position `p_view`, lit by the headlight and `key`, and darkened towards the outline colour
/// when `outline` is given (the pixel is on an outline). `ao` scales the ambient and headlight
/// terms (1: no occlusion; [`crate::effects::ao::AmbientOcclusion::factor`]).
#[allow(clippy::too_many_arguments)]
pub fn composite(
    lighting: &Lighting,
    ortho: bool,
    base: DVec3,
    n_view: DVec3,
    p_view: DVec3,
    key: Option<Key>,
    ao: f64,
    outline: Option<&Outlines>,
) -> DVec3 {
    let c = match key {
        None if ao == 1.0 => headlight(lighting, ortho, base, n_view, p_view),
        _ => {
            let l = if ortho {
                DVec3::Z
            } else {
                (-p_view).normalize()
            };
            let nl = n_view.dot(l).max(0.0);
            let diffuse = match key {
                Some(k) => {
                    let nk = n_view.dot(k.light).max(0.0);
                    (1.0 - KEY_SHARE) * nl * ao + KEY_SHARE * k.lit * nk
                }
                None => nl * ao,
            };
            let spec = nl.powf(f64::from(lighting.shininess));
            (base * (f64::from(lighting.ambient) * ao + f64::from(lighting.diffuse) * diffuse)
                + DVec3::splat(f64::from(lighting.specular) * spec))
            .clamp(DVec3::ZERO, DVec3::ONE)
        }
    };
    match outline {
        Some(o) => {
            let s = f64::from(o.strength.clamp(0.0, 1.0));
            c.lerp(DVec3::from_array(o.color.map(f64::from)), s)
        }
        None => c,
    }
}
