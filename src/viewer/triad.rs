//! The axis triad in the view's corner: where the world axes point on screen, labelled R/L,
//! A/P, S/I when the world is anatomical (RAS, as NIfTI and NRRD files give it), else +x … −z.

use crate::legend::{axis_labels, screen_axes};
use crate::viewer::navigation::Navigation;

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
