//! The axis triad in the view's corner: where the world axes point on screen, labelled R/L,
//! A/P, S/I when the world is anatomical (RAS, as NIfTI and NRRD files give it), else +x … −z.

use glam::DVec3;

use crate::viewer::navigation::Navigation;

/// (positive end, negative end) labels of the x, y and z axes.
pub fn axis_labels(anatomical: bool) -> [[&'static str; 2]; 3] {
    if anatomical {
        [["R", "L"], ["A", "P"], ["S", "I"]]
    } else {
        [["+x", "−x"], ["+y", "−y"], ["+z", "−z"]]
    }
}

/// Each world axis on screen for a camera looking along `forward` with `up`: (right, down)
/// components of its unit vector and its depth towards the viewer (positive: towards).
pub fn screen_axes(forward: DVec3, up: DVec3) -> [([f32; 2], f32); 3] {
    let right = forward.cross(up).normalize();
    let up = right.cross(forward).normalize();
    [DVec3::X, DVec3::Y, DVec3::Z].map(|a| {
        (
            [a.dot(right) as f32, -a.dot(up) as f32],
            -a.dot(forward) as f32,
        )
    })
}

/// Paint the triad in the lower left of `rect`.
pub fn paint(painter: &egui::Painter, rect: egui::Rect, nav: &Navigation, anatomical: bool) {
    const COLORS: [egui::Color32; 3] = [
        egui::Color32::from_rgb(230, 70, 70),
        egui::Color32::from_rgb(80, 200, 80),
        egui::Color32::from_rgb(90, 130, 255),
    ];
    let len = 32.0;
    let centre = rect.left_bottom() + egui::vec2(56.0, -56.0);
    let labels = axis_labels(anatomical);
    let axes = screen_axes(nav.forward, nav.up);
    let mut order = [0, 1, 2];
    // Back to front, so the axis towards the viewer is drawn last.
    order.sort_by(|&a, &b| axes[a].1.total_cmp(&axes[b].1));
    let font = egui::FontId::proportional(13.0);
    for a in order {
        let ([x, y], _) = axes[a];
        let d = egui::vec2(x, y);
        painter.line_segment(
            [centre, centre + d * len],
            egui::Stroke::new(2.5, COLORS[a]),
        );
        painter.text(
            centre + d * (len + 10.0),
            egui::Align2::CENTER_CENTER,
            labels[a][0],
            font.clone(),
            COLORS[a],
        );
        painter.text(
            centre - d * (len * 0.55),
            egui::Align2::CENTER_CENTER,
            labels[a][1],
            egui::FontId::proportional(10.0),
            COLORS[a].gamma_multiply(0.7),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ViewPreset;

    #[test]
    fn axial_shows_the_subject_right_on_the_right_and_anterior_up() {
        let (f, u) = ViewPreset::Axial.direction_up();
        let axes = screen_axes(f, u);
        // x (R) to the right, y (A) up (screen y grows down), z (S) towards the viewer.
        assert!((axes[0].0[0] - 1.0).abs() < 1e-6);
        assert!((axes[1].0[1] + 1.0).abs() < 1e-6);
        assert!((axes[2].1 - 1.0).abs() < 1e-6);
        let (f, u) = ViewPreset::Coronal.direction_up();
        let axes = screen_axes(f, u);
        assert!((axes[0].0[0] - 1.0).abs() < 1e-6, "coronal: R on the right");
        assert!((axes[2].0[1] + 1.0).abs() < 1e-6, "coronal: S up");
        let (f, u) = ViewPreset::Sagittal.direction_up();
        let axes = screen_axes(f, u);
        assert!((axes[1].0[0] + 1.0).abs() < 1e-6, "sagittal: A on the left");
        assert!((axes[2].0[1] + 1.0).abs() < 1e-6, "sagittal: S up");
        assert_eq!(axis_labels(true)[0], ["R", "L"]);
    }
}
