//! The side panel: file summary, rendering and style options with the colour legend, selection,
//! camera buttons, screenshot and stats. It edits [`Settings`] and the [`Navigation`] in place and
//! returns what the app must do beyond that as [`Action`]s.

mod figure;
mod selection;
mod style;
#[cfg(test)]
mod tests;
mod underlay;

use std::path::PathBuf;

use egui::{Color32, RichText, Ui};

use crate::camera::ViewPreset;
use crate::field::FieldKind;
use crate::request::{Method, Preset, ProxyShape};
use crate::viewer::loader::Loaded;
use crate::viewer::navigation::Navigation;
use crate::viewer::state::Settings;
use crate::viewer::view3d::FrameTime;
use figure::figure_section;
use selection::selection_section;
pub use selection::{order_roi, set_roi_enabled};
use style::style_section;
pub use underlay::choose_underlay;
use underlay::underlay_section;

/// What the panel asks the app to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    Open(PathBuf),
    View(ViewPreset),
    Screenshot,
}

/// Panel-only state: text fields and the screenshot size.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelState {
    pub path: String,
    pub screenshot_path: String,
    /// Screenshot at the window's size, else at `screenshot_size`.
    pub screenshot_window_size: bool,
    pub screenshot_size: String,
    /// Samples per pixel across (N×N) of a saved figure.
    pub figure_ssaa: u32,
    /// Burn the legend into a saved figure (`render --legend`).
    pub figure_legend: bool,
    /// A transparent background in a saved figure (`render --transparent`).
    pub figure_transparent: bool,
    /// The text of the scale field (`auto` or a factor).
    pub scale_text: String,
}

impl Default for PanelState {
    fn default() -> Self {
        Self {
            path: String::new(),
            screenshot_path: "tensorglyph.png".into(),
            screenshot_window_size: true,
            screenshot_size: "1920x1080".into(),
            figure_ssaa: 2,
            figure_legend: false,
            figure_transparent: false,
            scale_text: "auto".into(),
        }
    }
}

/// Read-only things the panel shows.
pub struct PanelInfo<'a> {
    pub data: Option<&'a Loaded>,
    /// (stage, fraction) of a load under way.
    pub loading: Option<(String, String, Option<f32>)>,
    pub error: Option<&'a str>,
    pub status: Option<&'a str>,
    pub glyphs_selected: usize,
    pub glyphs_drawn: usize,
    pub frame: Option<FrameTime>,
    pub adapter: &'a str,
    /// Selected glyphs `--scale auto` scaled down to the robust largest size.
    pub glyphs_clamped: usize,
    /// The smallest relative radius the scene was built with.
    pub min_radius: Option<f64>,
    /// `--underlay FILE`, offered when its volume was read.
    pub underlay_file: Option<&'a crate::scene::UnderlaySource>,
    /// The scene's underlay window (its 2nd and 98th percentiles).
    pub underlay_window: Option<[f32; 2]>,
    /// The colour scheme the scene was built with (as asked for) and its legend, with the
    /// field's range and units.
    pub legend: Option<(crate::glyph::ColorScheme, crate::legend::Legend)>,
}

impl PanelInfo<'_> {
    /// What the open file holds (tensors before one is open); its offers decide the controls.
    fn kind(&self) -> FieldKind {
        self.data.map_or(FieldKind::Tensors, Loaded::kind)
    }
}

pub fn show(
    ui: &mut Ui,
    settings: &mut Settings,
    nav: Option<&mut Navigation>,
    state: &mut PanelState,
    info: &PanelInfo<'_>,
) -> Vec<Action> {
    let mut actions = Vec::new();
    egui::ScrollArea::vertical().show(ui, |ui| {
        file_section(ui, state, info, &mut actions);
        ui.separator();
        rendering_section(ui, settings, info.kind());
        ui.separator();
        style_section(ui, settings, state, info);
        ui.separator();
        selection_section(ui, settings, info);
        ui.separator();
        underlay_section(ui, settings, info);
        ui.separator();
        figure_section(ui, settings);
        ui.separator();
        camera_section(ui, nav, &mut actions);
        ui.separator();
        screenshot_section(ui, state, &mut actions);
        ui.separator();
        stats_section(ui, info);
    });
    actions
}

fn file_section(
    ui: &mut Ui,
    state: &mut PanelState,
    info: &PanelInfo<'_>,
    actions: &mut Vec<Action>,
) {
    ui.heading("File");
    if let Some(d) = info.data
        && let Some(sh) = &d.odf
    {
        let name = d.name();
        ui.add(egui::Label::new(RichText::new(&name).strong()).truncate())
            .on_hover_text(name);
        let [x, y, z] = sh.dims;
        egui::Grid::new("summary").num_columns(2).show(ui, |ui| {
            ui.label("dataset");
            ui.label(format!("SH series ({})", sh.format));
            ui.end_row();
            ui.label("dims");
            ui.label(format!("{x} × {y} × {z}"));
            ui.end_row();
            ui.label("series");
            ui.label(format!(
                "lmax {}, {} coefficients, {}",
                sh.layout.lmax,
                sh.layout.count,
                sh.coefficients.type_name()
            ));
            ui.end_row();
            ui.label("basis");
            ui.label(sh.layout.basis.to_string())
                .on_hover_text(&sh.layout.reason);
            ui.end_row();
        });
    } else if let Some(d) = info.data
        && let Some(p) = &d.peaks
    {
        let name = d.name();
        ui.add(egui::Label::new(RichText::new(&name).strong()).truncate())
            .on_hover_text(name);
        let [x, y, z] = p.dims;
        let counts = p.counts();
        egui::Grid::new("summary").num_columns(2).show(ui, |ui| {
            ui.label("dataset");
            ui.label(format!("fibre peaks ({})", p.format));
            ui.end_row();
            ui.label("dims");
            ui.label(format!("{x} × {y} × {z}"));
            ui.end_row();
            ui.label("peaks");
            ui.label(format!(
                "up to {} a voxel; voxels with 0, 1, …: {}",
                p.per_voxel,
                counts
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
            ui.end_row();
        });
    } else if let Some(d) = info.data {
        let f = &d.field;
        let s = &d.set.stats;
        let name = d.name();
        ui.add(egui::Label::new(RichText::new(&name).strong()).truncate())
            .on_hover_text(name);
        egui::Grid::new("summary").num_columns(2).show(ui, |ui| {
            ui.label("dataset");
            ui.label(format!("{} ({})", f.dataset.as_str(), f.format));
            ui.end_row();
            ui.label("dims");
            ui.label(match f.dims {
                Some([x, y, z]) => format!("{x} × {y} × {z}"),
                None => "unstructured".into(),
            });
            ui.end_row();
            ui.label("points / cells");
            ui.label(format!("{} / {}", f.points, f.cells));
            ui.end_row();
            ui.label("array");
            ui.label(format!(
                "{} ({} comp., {})",
                f.array.name,
                f.array.components,
                f.array.location.as_str()
            ));
            ui.end_row();
            ui.label("tensors");
            ui.label(format!("{} ({} valid)", s.tensors, s.valid));
            ui.end_row();
            ui.label("skipped");
            ui.label(format!(
                "{} (NaN {}, inf {}, zero {}, beyond f32 {})",
                s.skipped_nan + s.skipped_inf + s.skipped_zero + s.skipped_overflow,
                s.skipped_nan,
                s.skipped_inf,
                s.skipped_zero,
                s.skipped_overflow
            ));
            ui.end_row();
            ui.label("symmetrised");
            ui.label(s.symmetrised.to_string());
            ui.end_row();
            ui.label("FA");
            ui.label(format!(
                "{:.3} … {:.3} (mean {:.3})",
                s.fa_min, s.fa_max, s.fa_mean
            ));
            ui.end_row();
        });
    } else if info.loading.is_none() {
        ui.label("No data: drop a tensor file here or open one below.");
    }
    if let Some((name, stage, frac)) = &info.loading {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.add(egui::Label::new(format!("loading {name}: {stage}")).truncate());
        });
        if let Some(f) = frac {
            ui.add(egui::ProgressBar::new(*f).show_percentage());
        }
    }
    if let Some(e) = info.error {
        ui.colored_label(Color32::from_rgb(200, 30, 30), e);
    }
    // The page opens files with its own button and drops (a browser gives no paths).
    if cfg!(target_arch = "wasm32") {
        ui.small("Open a file with the button above the view, or drop it on the page.");
        return;
    }
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(&mut state.path)
                .hint_text("path to a .vtk/.vti/… file")
                .desired_width(180.0),
        );
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (ui.button("Open").clicked() || enter) && !state.path.trim().is_empty() {
            actions.push(Action::Open(PathBuf::from(state.path.trim())));
        }
    });
    ui.small("…or drag and drop a file onto the window.");
}

fn rendering_section(ui: &mut Ui, settings: &mut Settings, field: FieldKind) {
    ui.heading("Rendering");
    egui::ComboBox::from_label("method")
        .selected_text(settings.method.to_string())
        .show_ui(ui, |ui| {
            for m in Method::gpu_methods() {
                ui.selectable_value(&mut settings.method, m, m.to_string());
            }
        });
    // The glyph kinds the file's kind is drawn as (SH series: their ODF alone).
    let kind = match field.offers().glyphs {
        [only] => {
            ui.label(format!(
                "glyph: {} (a file of {})",
                only.name(),
                field.holds()
            ));
            *only
        }
        glyphs => {
            ui.horizontal(|ui| {
                ui.label("glyph");
                for &kind in glyphs {
                    ui.selectable_value(&mut settings.glyph, kind, kind.name());
                }
            });
            settings.glyph
        }
    };
    let caps = kind.caps();
    if caps.sharpness {
        // A new sharpness rebuilds the scene (it is part of the style).
        ui.add(
            egui::Slider::new(&mut settings.style.sharpness.gamma, 0.0..=10.0).text("sharpness γ"),
        )
        .on_hover_text(
            "Kindlmann's γ: 0 ellipsoids, 3 the default, larger boxier. Indefinite tensors take \
             Schultz–Kindlmann's shapes (β_max = 3).",
        );
    }
    if caps.arrows {
        // Heads are instances of their own: a toggle rebuilds the scene (part of the style).
        ui.checkbox(&mut settings.style.arrows, "arrows")
            .on_hover_text("cone heads: outward for tension, inward for compression");
    }
    ui.checkbox(&mut settings.depth_correction, "depth correction");
    // The presets of `render --preset` and the bench's paths; the controls below fine-tune.
    egui::ComboBox::from_label("preset")
        .selected_text(
            Preset::VALUES
                .iter()
                .copied()
                .find(|&p| p != Preset::Sorted && p.options() == settings.draw)
                .map_or("custom", Preset::name),
        )
        .show_ui(ui, |ui| {
            // Sorted differs from the baseline only in order, which the viewer keeps.
            for p in Preset::VALUES
                .iter()
                .copied()
                .filter(|&p| p != Preset::Sorted)
            {
                if ui.selectable_label(false, p.name()).clicked() {
                    settings.draw = p.options();
                }
            }
        });
    let draw = &mut settings.draw;
    if settings.method == Method::Gumhold {
        ui.horizontal(|ui| {
            ui.label("proxy");
            for (shape, name) in [
                (ProxyShape::Quad, "quad"),
                (ProxyShape::Octagon, "octagon"),
                (ProxyShape::Triangle, "triangle"),
            ] {
                ui.selectable_value(&mut draw.proxy, shape, name);
            }
        });
        if caps.conservative_depth && settings.depth_correction {
            ui.checkbox(&mut draw.conservative, "conservative depth")
                .on_hover_text(
                    "proxy on the glyph's nearest plane (lets a GPU reject hidden fragments early)",
                );
        }
        if caps.prepass {
            ui.checkbox(&mut draw.prepass, "compute prepass")
                .on_hover_text("build each glyph's proxy once in compute; always on with splats");
            ui.horizontal(|ui| {
                ui.label("splats up to");
                ui.add(egui::Slider::new(&mut draw.splat, 0..=128).suffix(" px"))
                    .on_hover_text(
                        "glyphs at most this many pixels across are ray cast per pixel in \
                         compute instead of drawn (0: off)",
                    );
            });
        }
    }
    ui.checkbox(&mut draw.cull, "frustum culling")
        .on_hover_text("skip glyphs outside the view");
    ui.horizontal(|ui| {
        ui.label("background");
        ui.color_edit_button_rgb(&mut settings.background);
        for (name, c) in [("white", 1.0), ("grey", 0.5), ("black", 0.0)] {
            if ui.small_button(name).clicked() {
                settings.background = [c; 3];
            }
        }
    });
}

fn camera_section(ui: &mut Ui, nav: Option<&mut Navigation>, actions: &mut Vec<Action>) {
    ui.heading("Camera");
    ui.horizontal_wrapped(|ui| {
        if ui.button("reset").on_hover_text("R").clicked() {
            actions.push(Action::View(ViewPreset::Iso));
        }
        for (k, (preset, name)) in [
            (ViewPreset::PosX, "+x"),
            (ViewPreset::NegX, "−x"),
            (ViewPreset::PosY, "+y"),
            (ViewPreset::NegY, "−y"),
            (ViewPreset::PosZ, "+z"),
            (ViewPreset::NegZ, "−z"),
        ]
        .into_iter()
        .enumerate()
        {
            if ui
                .button(name)
                .on_hover_text(format!("look along {name} (key {})", k + 1))
                .clicked()
            {
                actions.push(Action::View(preset));
            }
        }
    });
    ui.horizontal(|ui| {
        for preset in [ViewPreset::Axial, ViewPreset::Coronal, ViewPreset::Sagittal] {
            if ui
                .button(preset.name())
                .on_hover_text("anatomical (RAS) views, the subject's right on the right")
                .clicked()
            {
                actions.push(Action::View(preset));
            }
        }
    });
    if let Some(nav) = nav {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut nav.ortho, false, "perspective");
            ui.selectable_value(&mut nav.ortho, true, "orthographic")
                .on_hover_text("P toggles");
        });
        ui.add(egui::Slider::new(&mut nav.fov_deg, 5.0..=90.0).text("field of view °"));
    }
}

fn screenshot_section(ui: &mut Ui, state: &mut PanelState, actions: &mut Vec<Action>) {
    ui.heading("Save figure");
    ui.horizontal(|ui| {
        ui.label("file");
        ui.add(egui::TextEdit::singleline(&mut state.screenshot_path).desired_width(170.0));
    });
    ui.horizontal(|ui| {
        ui.radio_value(&mut state.screenshot_window_size, true, "view size");
        ui.radio_value(&mut state.screenshot_window_size, false, "size");
        ui.add_enabled(
            !state.screenshot_window_size,
            egui::TextEdit::singleline(&mut state.screenshot_size).desired_width(80.0),
        );
    });
    ui.add(egui::Slider::new(&mut state.figure_ssaa, 1..=4).text("anti-aliasing N×N"));
    ui.horizontal(|ui| {
        ui.checkbox(&mut state.figure_legend, "legend");
        ui.checkbox(&mut state.figure_transparent, "transparent");
    });
    if ui.button("Save figure (S)").clicked() {
        actions.push(Action::Screenshot);
    }
}

fn stats_section(ui: &mut Ui, info: &PanelInfo<'_>) {
    ui.heading("Stats");
    if let Some(status) = info.status {
        ui.label(status);
    }
    let total = info.data.map_or(0, |d| d.total);
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        ui.label("glyphs");
        ui.label(format!(
            "{total} total, {} selected, {} drawn",
            info.glyphs_selected, info.glyphs_drawn
        ));
        ui.end_row();
        ui.label("frame");
        ui.label(match info.frame {
            Some(f) if f.gpu_timestamps => format!("{:.1} ms (GPU timestamps)", f.ms),
            Some(f) => format!("{:.1} ms (wall clock)", f.ms),
            None => "–".into(),
        });
        ui.end_row();
        ui.label("adapter");
        ui.label(info.adapter);
        ui.end_row();
    });
}
