//! The figure section: anti-aliasing of the view, deferred shading, outlines, shadows with
//! the key light's direction, and ambient occlusion, as `render
//! --ssaa/--shading/--outlines/--shadows/--light/--ao/--ao-reach` take them; "Save figure" (the screenshot section) renders through `render`'s path with them.

use egui::Ui;

use crate::effects::ao::AmbientOcclusion;
use crate::effects::{Outlines, Shading, Shadows};
use crate::viewer::state::Settings;

/// The key light's direction in view space as (azimuth, elevation) in degrees: azimuth 0
/// towards the viewer, −90 from the left; elevation 90 from above.
pub fn light_angles(light: [f64; 3]) -> (f64, f64) {
    let l = crate::effects::light::view_direction(light).unwrap_or(glam::DVec3::Z);
    (
        l.x.atan2(l.z).to_degrees(),
        l.y.clamp(-1.0, 1.0).asin().to_degrees(),
    )
}

/// The inverse of [`light_angles`].
pub fn light_from_angles(azimuth: f64, elevation: f64) -> [f64; 3] {
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    [e.cos() * a.sin(), e.sin(), e.cos() * a.cos()]
}

pub(super) fn figure_section(ui: &mut Ui, settings: &mut Settings) {
    ui.heading("Figure");
    let mut aa = settings.ssaa > 1;
    if ui
        .checkbox(&mut aa, "anti-aliasing (2×2 samples)")
        .changed()
    {
        settings.ssaa = if aa { 2 } else { 1 };
    }
    ui.checkbox(&mut settings.draft, "coarser frames while moving")
        .on_hover_text(
            "a scene slower than 66 ms a frame is drawn at a lower resolution while the camera moves, whole once it stops",
        );
    let fx = &mut settings.effects;
    let mut outlines = fx.outlines.is_some();
    let mut shadows = fx.shadows.is_some();
    let mut ao = fx.ao.is_some();
    let mut deferred = fx.shading == Shading::Deferred || fx.any();
    ui.add_enabled_ui(!fx.any(), |ui| {
        ui.checkbox(&mut deferred, "deferred shading")
            .on_disabled_hover_text(
                "outlines, shadows and ambient occlusion are drawn with deferred shading",
            );
    });
    fx.shading = if deferred {
        Shading::Deferred
    } else {
        Shading::Direct
    };
    if ui.checkbox(&mut outlines, "outlines").changed() {
        fx.outlines = outlines.then(Outlines::default);
    }
    if let Some(o) = &mut fx.outlines {
        ui.add(egui::Slider::new(&mut o.strength, 0.0..=1.0).text("strength"));
        ui.add(egui::Slider::new(&mut o.width, 1..=4).text("width px"));
    }
    if ui.checkbox(&mut shadows, "shadows").changed() {
        fx.shadows = shadows.then(Shadows::default);
    }
    if let Some(s) = &mut fx.shadows {
        let (mut az, mut el) = light_angles(s.light);
        let a = ui
            .add(egui::Slider::new(&mut az, -180.0..=180.0).text("light azimuth °"))
            .changed();
        let e = ui
            .add(egui::Slider::new(&mut el, -89.0..=89.0).text("light elevation °"))
            .changed();
        if a || e {
            s.light = light_from_angles(az, el);
        }
        ui.checkbox(&mut s.adaptive, "adaptive PCF");
    }
    if ui.checkbox(&mut ao, "ambient occlusion").changed() {
        fx.ao = ao.then(AmbientOcclusion::default);
    }
    if let Some(a) = &mut fx.ao {
        ui.add(egui::Slider::new(&mut a.strength, 0.0..=1.0).text("strength"));
        ui.add(egui::Slider::new(&mut a.reach, 1.0..=12.0).text("reach (radii)"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_angles_round_trip() {
        for l in [Shadows::DEFAULT_LIGHT, [0.0, 0.0, 1.0], [-1.0, 0.2, -0.3]] {
            let (a, e) = light_angles(l);
            let back = glam::DVec3::from_array(light_from_angles(a, e));
            let want = glam::DVec3::from_array(l).normalize();
            assert!((back - want).length() < 1e-12, "{l:?} → {back}");
        }
        // Azimuth −90 is the viewer's left.
        let left = light_from_angles(-90.0, 0.0);
        assert!((left[0] + 1.0).abs() < 1e-12);
    }
}
