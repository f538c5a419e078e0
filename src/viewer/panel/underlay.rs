//! The underlay section: which scalar image lies under the slices (none, a measure of the
//! tensors or the `--underlay` file), whether it shows, and its window. Turning one on with the whole field
//! selected shows the middle axial slice, as `render --underlay` does.

use egui::Ui;

use crate::scene::UnderlaySource;
use crate::select::Slicing;
use crate::tensor::measure::Measure;
use crate::viewer::panel::PanelInfo;
use crate::viewer::state::Settings;

pub(super) fn underlay_section(ui: &mut Ui, settings: &mut Settings, info: &PanelInfo<'_>) {
    ui.heading("Underlay");
    let Some(data) = info.data else {
        return;
    };
    let kind = data.kind();
    if !kind.offers().tensor_selection {
        // As `render` draws them: SH series have no tensors to measure an underlay from.
        ui.label(format!(
            "for tensor fields (a file of {} is drawn without one)",
            kind.holds()
        ));
        return;
    }
    let Some(dims) = data.field.lattice_dims() else {
        ui.label("needs structured data");
        return;
    };
    let file = data.underlay.as_ref().and(info.underlay_file);
    let mut choices: Vec<Option<UnderlaySource>> = std::iter::once(None)
        .chain(
            Measure::VALUES
                .iter()
                .map(|m| Some(UnderlaySource::Measure(*m))),
        )
        .collect();
    if let Some(f) = file {
        choices.push(Some(f.clone()));
    }
    let name = |c: &Option<UnderlaySource>| match c {
        None => "none".to_string(),
        Some(UnderlaySource::File(p)) => p
            .file_name()
            .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into()),
        Some(s) => s.to_string(),
    };
    let mut choice = settings.underlay.clone();
    egui::ComboBox::from_label("image")
        .selected_text(name(&choice))
        .show_ui(ui, |ui| {
            for c in choices {
                let label = name(&c);
                ui.selectable_value(&mut choice, c, label);
            }
        });
    if choice != settings.underlay {
        choose_underlay(settings, choice, dims);
    }
    if settings.underlay.is_none() {
        return;
    }
    let view = &mut settings.underlay_view;
    ui.checkbox(&mut view.shown, "show");
    let Some(default) = info.underlay_window else {
        return;
    };
    let [mut lo, mut hi] = view.window.unwrap_or(default);
    let speed = ((default[1] - default[0]).abs() / 200.0).max(1e-9);
    ui.horizontal(|ui| {
        ui.label("window");
        let a = ui.add(egui::DragValue::new(&mut lo).speed(speed)).changed();
        let b = ui.add(egui::DragValue::new(&mut hi).speed(speed)).changed();
        if a || b {
            if lo > hi {
                std::mem::swap(&mut lo, &mut hi);
            }
            view.window = Some([lo, hi]);
        }
        if ui.small_button("2–98 %").clicked() {
            view.window = None;
        }
    });
}

/// Show `choice` under the slices; from the whole field, the middle axial slice is shown.
pub fn choose_underlay(settings: &mut Settings, choice: Option<UnderlaySource>, dims: [usize; 3]) {
    if choice.is_some() && settings.selection.slicing == Slicing::Whole {
        settings.selection.slicing = Slicing::Slice {
            axis: 2,
            index: dims[2] / 2,
        };
    }
    settings.underlay = choice;
}
