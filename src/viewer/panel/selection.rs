//! The selection section: FA range, stride, region of interest and slicing (whole, one slice,
//! three orthogonal slices, or the planes given with `--slice`).

use egui::Ui;

use crate::select::{Selection, Slicing};
use crate::viewer::panel::PanelInfo;
use crate::viewer::state::Settings;

pub(super) fn selection_section(ui: &mut Ui, settings: &mut Settings, info: &PanelInfo<'_>) {
    ui.heading("Selection");
    let sel = &mut settings.selection;
    // SH series are selected by their planes only (the FA, stride and ROI are the tensors').
    if info.kind().offers().tensor_selection {
        tensor_controls(ui, sel, info);
    }
    slicing_controls(ui, sel, info);
}

/// FA range, stride and ROI.
fn tensor_controls(ui: &mut Ui, sel: &mut Selection, info: &PanelInfo<'_>) {
    ui.horizontal(|ui| {
        ui.label("FA");
        ui.add(
            egui::DragValue::new(&mut sel.fa_min)
                .range(0.0..=1.0)
                .speed(0.005),
        );
        ui.label("to");
        ui.add(
            egui::DragValue::new(&mut sel.fa_max)
                .range(0.0..=1.0)
                .speed(0.005),
        );
        if ui.small_button("all").clicked() {
            sel.fa_min = 0.0;
            sel.fa_max = 1.0;
        }
    });
    if sel.fa_min > sel.fa_max {
        std::mem::swap(&mut sel.fa_min, &mut sel.fa_max);
    }
    ui.add(egui::Slider::new(&mut sel.stride, 1..=16).text("stride"));
    roi_controls(ui, sel, info.data.map(|d| d.bounds));
}

/// Whole, one slice, three slices or the planes given.
fn slicing_controls(ui: &mut Ui, sel: &mut Selection, info: &PanelInfo<'_>) {
    // Before the data is loaded there is nothing to slice yet: keep the starting selection
    // (`view --slice` is applied once the data is there).
    let Some(data) = info.data else {
        return;
    };
    let Some(dims) = data.field.lattice_dims() else {
        ui.label("slicing: needs structured data");
        sel.slicing = Slicing::Whole;
        return;
    };
    let mid = dims.map(|n| n / 2);
    ui.horizontal(|ui| {
        let whole = matches!(sel.slicing, Slicing::Whole);
        let one = matches!(sel.slicing, Slicing::Slice { .. });
        let three = matches!(sel.slicing, Slicing::Orthogonal { .. });
        if ui.selectable_label(whole, "whole").clicked() {
            sel.slicing = Slicing::Whole;
        }
        if ui.selectable_label(one, "one slice").clicked() && !one {
            sel.slicing = Slicing::Slice {
                axis: 2,
                index: mid[2],
            };
        }
        if ui.selectable_label(three, "three slices").clicked() && !three {
            sel.slicing = Slicing::Orthogonal { at: mid };
        }
    });
    const AXES: [&str; 3] = ["x", "y", "z"];
    match &mut sel.slicing {
        Slicing::Whole => {}
        Slicing::Slice { axis, index } => {
            ui.horizontal(|ui| {
                ui.label("axis");
                for (a, name) in AXES.iter().enumerate() {
                    if ui.selectable_label(*axis == a, *name).clicked() && *axis != a {
                        *axis = a;
                        *index = mid[a];
                    }
                }
            });
            let last = dims[*axis].max(1) - 1;
            ui.add(egui::Slider::new(index, 0..=last).text(AXES[*axis]));
        }
        Slicing::Orthogonal { at } => {
            for a in 0..3 {
                let last = dims[a].max(1) - 1;
                ui.add(egui::Slider::new(&mut at[a], 0..=last).text(AXES[a]));
            }
        }
        Slicing::Planes(planes) => {
            // Set from the command line (`--slice`, repeatable): shown, changed by the modes above.
            let names: Vec<String> = planes.iter().map(|p| p.to_string()).collect();
            ui.label(format!("planes {}", names.join(", ")));
        }
    }
}

/// Turn the region of interest on (starting at `bounds`, the box around the glyph centres) or
/// off; an ROI already on stays as it is.
pub fn set_roi_enabled(sel: &mut Selection, on: bool, bounds: [f64; 6]) {
    match (on, sel.roi.is_some()) {
        (true, false) => sel.roi = Some(bounds),
        (false, true) => sel.roi = None,
        _ => {}
    }
}

/// Keep an edited ROI a valid box: a lower bound dragged past its upper bound moves both.
pub fn order_roi(roi: &mut [f64; 6], edited_upper: [bool; 3]) {
    for a in 0..3 {
        if roi[a] > roi[a + 3] {
            if edited_upper[a] {
                roi[a] = roi[a + 3];
            } else {
                roi[a + 3] = roi[a];
            }
        }
    }
}

pub(super) fn roi_checkbox_id() -> egui::Id {
    egui::Id::unique("tensorglyph roi checkbox")
}

/// The ROI checkbox and its six bounds (world coordinates of the glyph centres, inclusive).
fn roi_controls(ui: &mut Ui, sel: &mut Selection, bounds: Option<[f64; 6]>) {
    let bounds = bounds.unwrap_or([0.0; 6]);
    let mut on = sel.roi.is_some();
    let r = ui
        .checkbox(&mut on, "region of interest (box)")
        .on_hover_text("keep glyphs whose centre lies in the box, bounds included");
    // Where it is, for the panel tests to click.
    ui.ctx()
        .data_mut(|d| d.insert_temp(roi_checkbox_id(), r.rect));
    set_roi_enabled(sel, on, bounds);
    let Some(roi) = &mut sel.roi else { return };
    let extent = (0..3)
        .map(|a| bounds[a + 3] - bounds[a])
        .fold(0.0_f64, f64::max);
    let speed = (extent / 200.0).max(1e-6);
    let mut upper = [false; 3];
    egui::Grid::new("roi").num_columns(3).show(ui, |ui| {
        for (a, name) in ["x", "y", "z"].into_iter().enumerate() {
            ui.label(name);
            ui.add(egui::DragValue::new(&mut roi[a]).speed(speed));
            upper[a] = ui
                .add(egui::DragValue::new(&mut roi[a + 3]).speed(speed))
                .changed();
            ui.end_row();
        }
    });
    order_roi(roi, upper);
    if ui.small_button("reset to the field's bounds").clicked() {
        *roi = bounds;
    }
}
