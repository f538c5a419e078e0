//! The side panel: file summary, rendering and style options with the colour legend, selection,
//! camera buttons, screenshot and stats. It edits [`Settings`] and the [`Navigation`] in place and
//! returns what the app must do beyond that as [`Action`]s.

use std::path::PathBuf;

use egui::{Color32, RichText, Ui};

use crate::camera::ViewPreset;
use crate::glyph::colormap::{diverging, viridis};
use crate::glyph::{ColorScheme, Normalize, Scale};
use crate::request::{GlyphKind, Method, Preset, ProxyShape};
use crate::select::{Selection, Slicing};
use crate::tensor::shape::{ShapeClass, barycentric_color};
use crate::viewer::loader::Loaded;
use crate::viewer::navigation::Navigation;
use crate::viewer::state::{Legend, Settings, legend};
use crate::viewer::view3d::FrameTime;

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
        rendering_section(ui, settings);
        ui.separator();
        style_section(ui, settings, state, info);
        ui.separator();
        selection_section(ui, settings, info);
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
    if let Some(d) = info.data {
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
                "{} (NaN {}, inf {}, zero {})",
                s.skipped_nan + s.skipped_inf + s.skipped_zero,
                s.skipped_nan,
                s.skipped_inf,
                s.skipped_zero
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
        ui.label("No data: drop a VTK file here or open one below.");
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

fn rendering_section(ui: &mut Ui, settings: &mut Settings) {
    ui.heading("Rendering");
    egui::ComboBox::from_label("method")
        .selected_text(settings.method.to_string())
        .show_ui(ui, |ui| {
            for m in Method::gpu_methods() {
                ui.selectable_value(&mut settings.method, m, m.to_string());
            }
        });
    ui.horizontal(|ui| {
        ui.label("glyph");
        ui.selectable_value(&mut settings.glyph, GlyphKind::Ellipsoid, "ellipsoid");
        ui.selectable_value(&mut settings.glyph, GlyphKind::Cylinder, "cylinder");
    });
    ui.checkbox(&mut settings.depth_correction, "depth correction");
    // The presets of `render --preset` and the bench's paths; the controls below fine-tune.
    egui::ComboBox::from_label("preset")
        .selected_text(
            Preset::VALUES
                .iter()
                .copied()
                .find(|p| !p.sorts() && p.options() == settings.draw)
                .map_or("custom", Preset::name),
        )
        .show_ui(ui, |ui| {
            for p in Preset::VALUES.iter().copied().filter(|p| !p.sorts()) {
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
        if settings.glyph == GlyphKind::Ellipsoid && settings.depth_correction {
            ui.checkbox(&mut draw.conservative, "conservative depth")
                .on_hover_text(
                    "proxy on the glyph's nearest plane (lets a GPU reject hidden fragments early)",
                );
        }
        if settings.glyph == GlyphKind::Ellipsoid {
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

const SCHEMES: [(ColorScheme, &str); 6] = [
    (ColorScheme::Shape, "shape"),
    (ColorScheme::Dec, "dec"),
    (ColorScheme::Fa, "fa"),
    (ColorScheme::Md, "md"),
    (ColorScheme::Sign, "sign"),
    (ColorScheme::Solid, "solid"),
];

fn scheme_name(s: ColorScheme) -> &'static str {
    SCHEMES
        .iter()
        .find(|(c, _)| *c == s)
        .map_or("?", |(_, n)| n)
}

fn style_section(
    ui: &mut Ui,
    settings: &mut Settings,
    state: &mut PanelState,
    info: &PanelInfo<'_>,
) {
    ui.heading("Glyphs");
    let style = &mut settings.style;
    egui::ComboBox::from_label("colour")
        .selected_text(scheme_name(style.color))
        .show_ui(ui, |ui| {
            for (c, name) in SCHEMES {
                ui.selectable_value(&mut style.color, c, name);
            }
        });
    let md = info
        .data
        .map_or((0.0, 0.0), |d| (d.set.stats.md_min, d.set.stats.md_max));
    draw_legend(ui, legend(style.color, md));
    ui.horizontal(|ui| {
        ui.label("scale");
        let r = ui.add(egui::TextEdit::singleline(&mut state.scale_text).desired_width(60.0));
        if r.changed()
            && let Ok(s) = state.scale_text.parse::<Scale>()
        {
            style.scale = s;
        }
        if ui.small_button("auto").clicked() {
            style.scale = Scale::Auto;
            state.scale_text = "auto".into();
        }
        if state.scale_text.parse::<Scale>().is_err() {
            ui.colored_label(Color32::from_rgb(200, 30, 30), "auto or a number > 0");
        }
    });
    egui::ComboBox::from_label("normalise")
        .selected_text(match style.normalize {
            Normalize::None => "none",
            Normalize::Max => "max",
            Normalize::PerGlyph => "per-glyph",
        })
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut style.normalize, Normalize::None, "none");
            ui.selectable_value(&mut style.normalize, Normalize::Max, "max");
            ui.selectable_value(&mut style.normalize, Normalize::PerGlyph, "per-glyph");
        });
    ui.add(egui::Slider::new(&mut style.min_radius, 0.0..=1.0).text("min radius"));
}

fn color32(c: [f64; 3]) -> Color32 {
    let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    Color32::from_rgb(q(c[0]), q(c[1]), q(c[2]))
}

fn draw_legend(ui: &mut Ui, l: Legend) {
    match l {
        Legend::Shape => {
            ui.horizontal_wrapped(|ui| {
                for (class, name) in [
                    (ShapeClass::Linear, "linear (cigar)"),
                    (ShapeClass::Planar, "planar (pancake)"),
                    (ShapeClass::Spherical, "spherical (ball)"),
                    (ShapeClass::Unclassified, "unclassified"),
                ] {
                    swatch(ui, color32(class.color()));
                    ui.label(name);
                }
            });
            westin_triangle(ui);
        }
        Legend::Bar { lo, hi, label } => {
            colour_bar(ui, viridis);
            ui.horizontal(|ui| {
                ui.label(format!("{label} {lo:.3}"));
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    ui.label(format!("{hi:.3}"));
                });
            });
        }
        Legend::Sign => {
            colour_bar(ui, |t| diverging(2.0 * t - 1.0));
            ui.horizontal(|ui| {
                ui.label("compression (λ < 0)");
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    ui.label("tension (λ > 0)");
                });
            });
        }
        Legend::Dec => {
            ui.label("RGB = |e₁| (x, y, z) × FA");
        }
        Legend::Solid => {}
    }
}

/// A small filled square of colour `c`.
fn swatch(ui: &mut Ui, c: Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, c);
}

/// A horizontal bar of `map(t)`, t from 0 to 1.
fn colour_bar(ui: &mut Ui, map: impl Fn(f64) -> [f64; 3]) {
    let width = ui.available_width();
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 14.0), egui::Sense::hover());
    let mut mesh = egui::Mesh::default();
    let n = 32;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let x = rect.left() + rect.width() * t as f32;
        let c = color32(map(t));
        mesh.colored_vertex(egui::pos2(x, rect.top()), c);
        mesh.colored_vertex(egui::pos2(x, rect.bottom()), c);
        if k > 0 {
            let i = 2 * k as u32;
            mesh.add_triangle(i - 2, i - 1, i);
            mesh.add_triangle(i - 1, i, i + 1);
        }
    }
    ui.painter().add(egui::Shape::mesh(mesh));
}

/// The barycentric (cl, cp, cs) triangle of the shape colours.
fn westin_triangle(ui: &mut Ui) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(150.0, 120.0), egui::Sense::hover());
    let a = egui::pos2(rect.left() + 10.0, rect.bottom() - 16.0); // linear
    let b = egui::pos2(rect.right() - 10.0, rect.bottom() - 16.0); // planar
    let c = egui::pos2(rect.center().x, rect.top() + 14.0); // spherical
    let mut mesh = egui::Mesh::default();
    let n = 12u32;
    // A triangular grid of vertices with barycentric colours (cl, cp, cs).
    let mut index = std::collections::HashMap::new();
    for i in 0..=n {
        for j in 0..=(n - i) {
            let k = n - i - j;
            let w = [i, j, k].map(|x| x as f32 / n as f32);
            let p = egui::pos2(
                w[0] * a.x + w[1] * b.x + w[2] * c.x,
                w[0] * a.y + w[1] * b.y + w[2] * c.y,
            );
            let col = barycentric_color_of(w.map(f64::from));
            index.insert((i, j), mesh.vertices.len() as u32);
            mesh.colored_vertex(p, col);
        }
    }
    for i in 0..n {
        for j in 0..(n - i) {
            let v = |i, j| index[&(i, j)];
            mesh.add_triangle(v(i, j), v(i + 1, j), v(i, j + 1));
            if j + 1 < n - i {
                mesh.add_triangle(v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            }
        }
    }
    let painter = ui.painter();
    painter.add(egui::Shape::mesh(mesh));
    let font = egui::FontId::proportional(11.0);
    let text = ui.visuals().text_color();
    painter.text(
        a + egui::vec2(0.0, 3.0),
        egui::Align2::CENTER_TOP,
        "cl",
        font.clone(),
        text,
    );
    painter.text(
        b + egui::vec2(0.0, 3.0),
        egui::Align2::CENTER_TOP,
        "cp",
        font.clone(),
        text,
    );
    painter.text(
        c - egui::vec2(0.0, 2.0),
        egui::Align2::CENTER_BOTTOM,
        "cs",
        font,
        text,
    );
}

/// The colour `barycentric_color` gives a tensor with Westin measures `w` (it is `w` itself,
/// scaled so its largest component is 1).
fn barycentric_color_of(w: [f64; 3]) -> Color32 {
    // λ = (1, 1 − cl, cs) up to scale has cl = λ1 − λ2, cp = λ2 − λ3, cs = λ3 (λ1 = 1).
    let ev = [1.0, 1.0 - w[0], w[2]];
    color32(barycentric_color(ev, true))
}

fn selection_section(ui: &mut Ui, settings: &mut Settings, info: &PanelInfo<'_>) {
    ui.heading("Selection");
    let sel = &mut settings.selection;
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

fn roi_checkbox_id() -> egui::Id {
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
    ui.heading("Screenshot");
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
    if ui.button("Save PNG (S)").clicked() {
        actions.push(Action::Screenshot);
    }
}

fn stats_section(ui: &mut Ui, info: &PanelInfo<'_>) {
    ui.heading("Stats");
    if let Some(status) = info.status {
        ui.label(status);
    }
    let total = info.data.map_or(0, |d| d.set.glyphs.len());
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::vtk::ReadOptions;
    use crate::select::Plane;
    use crate::staging::{Demo, Source};
    use crate::viewer::loader::load_now;

    /// Run the panel once in a headless egui context.
    fn run_panel(
        ctx: &egui::Context,
        settings: &mut Settings,
        nav: &mut Navigation,
        state: &mut PanelState,
        info: &PanelInfo<'_>,
        events: Vec<egui::Event>,
    ) -> (Vec<Action>, egui::FullOutput) {
        let mut actions = Vec::new();
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(360.0, 2400.0),
            )),
            events,
            ..Default::default()
        };
        let mut out = ctx.run_ui(input, |ui| {
            actions = show(ui, settings, Some(nav), state, info);
        });
        // No painter here to upload the font atlas to.
        out.textures_delta.clear();
        (actions, out)
    }

    fn info(data: Option<&Loaded>) -> PanelInfo<'_> {
        PanelInfo {
            data,
            loading: None,
            error: Some("bad.vtk: not a VTK file"),
            status: None,
            glyphs_selected: 8,
            glyphs_drawn: 8,
            frame: Some(FrameTime {
                ms: 12.0,
                gpu_timestamps: true,
            }),
            adapter: "llvmpipe",
        }
    }

    #[test]
    fn panel_draws_every_scheme_and_slicing_mode() {
        let data = load_now(
            &Source::Demo(Demo { n: 4 }),
            &ReadOptions::default(),
            &crate::progress::Silent,
        )
        .unwrap();
        let ctx = egui::Context::default();
        let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
        let mut state = PanelState::default();
        for (scheme, _) in SCHEMES {
            for (slicing, roi) in [
                (Slicing::Whole, None),
                (Slicing::Slice { axis: 1, index: 2 }, None),
                (Slicing::Orthogonal { at: [1, 2, 3] }, None),
                (
                    Slicing::Planes(vec![
                        crate::select::Plane { axis: 0, index: 1 },
                        crate::select::Plane { axis: 2, index: 3 },
                    ]),
                    Some([0.5, 0.0, 0.0, 2.0, 3.0, 3.0]),
                ),
            ] {
                let mut settings = Settings::default();
                settings.style.color = scheme;
                settings.selection.slicing = slicing;
                settings.selection.roi = roi;
                let before = settings.clone();
                let (actions, out) = run_panel(
                    &ctx,
                    &mut settings,
                    &mut nav,
                    &mut state,
                    &info(Some(&data)),
                    vec![],
                );
                assert!(actions.is_empty());
                assert_eq!(settings, before, "drawing alone changes nothing");
                assert!(!out.shapes.is_empty());
            }
        }
    }

    #[test]
    fn roi_starts_at_the_field_bounds_and_stays_a_box() {
        let bounds = [0.0, -1.0, 2.0, 3.0, 4.0, 5.0];
        let mut sel = Selection::default();
        set_roi_enabled(&mut sel, false, bounds);
        assert_eq!(sel.roi, None);
        set_roi_enabled(&mut sel, true, bounds);
        assert_eq!(sel.roi, Some(bounds));
        // An ROI that is on keeps its edits.
        sel.roi = Some([1.0, -1.0, 2.0, 3.0, 4.0, 5.0]);
        set_roi_enabled(&mut sel, true, bounds);
        assert_eq!(sel.roi, Some([1.0, -1.0, 2.0, 3.0, 4.0, 5.0]));
        set_roi_enabled(&mut sel, false, bounds);
        assert_eq!(sel.roi, None);
        // x0 dragged past x1 pushes x1; y1 dragged below y0 pulls y0.
        let mut roi = [4.0, 0.0, 0.0, 3.0, -2.0, 1.0];
        order_roi(&mut roi, [false, true, false]);
        assert_eq!(roi, [4.0, -2.0, 0.0, 4.0, -2.0, 1.0]);
        let sel = Selection {
            roi: Some(roi),
            ..Selection::default()
        };
        sel.check().unwrap();
    }

    #[test]
    fn the_roi_checkbox_turns_the_box_on_at_the_field_bounds() {
        let data = load_now(
            &Source::Demo(Demo { n: 4 }),
            &ReadOptions::default(),
            &crate::progress::Silent,
        )
        .unwrap();
        assert_eq!(data.bounds, [0.0, 0.0, 0.0, 3.0, 3.0, 3.0]);
        let ctx = egui::Context::default();
        let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
        let mut state = PanelState::default();
        let mut settings = Settings::default();
        let info = info(Some(&data));
        // Find the checkbox by drawing once, then click its centre.
        run_panel(&ctx, &mut settings, &mut nav, &mut state, &info, vec![]);
        let rect = ctx
            .data(|d| d.get_temp::<egui::Rect>(roi_checkbox_id()))
            .expect("the ROI checkbox was drawn");
        let click = |pressed| egui::Event::PointerButton {
            pos: rect.center(),
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        };
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info,
            vec![egui::Event::PointerMoved(rect.center()), click(true)],
        );
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info,
            vec![click(false)],
        );
        assert_eq!(settings.selection.roi, Some(data.bounds));
    }

    #[test]
    fn without_a_lattice_slicing_falls_back_to_the_whole_volume() {
        // Unstructured points have no lattice to slice.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/legacy42_ascii_ugrid_T9.vtk");
        let data = load_now(
            &Source::File(path),
            &ReadOptions::default(),
            &crate::progress::Silent,
        )
        .unwrap();
        assert!(data.field.lattice_dims().is_none());
        let ctx = egui::Context::default();
        let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
        let mut state = PanelState::default();
        let mut settings = Settings::default();
        settings.selection.slicing = Slicing::Slice { axis: 0, index: 1 };
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info(Some(&data)),
            vec![],
        );
        assert_eq!(settings.selection.slicing, Slicing::Whole);
    }

    #[test]
    fn before_the_data_is_loaded_the_starting_slices_stay() {
        // `view --slice x=0 --slice z=3`: the panel runs before the file is read.
        let ctx = egui::Context::default();
        let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
        let mut state = PanelState::default();
        let mut settings = Settings::default();
        let planes = Slicing::Planes(vec![
            Plane { axis: 0, index: 0 },
            Plane { axis: 2, index: 3 },
        ]);
        settings.selection.slicing = planes.clone();
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info(None),
            vec![],
        );
        assert_eq!(settings.selection.slicing, planes);
    }

    #[test]
    fn typing_a_path_and_enter_opens_it() {
        let ctx = egui::Context::default();
        let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
        let mut state = PanelState::default();
        let mut settings = Settings::default();
        let info = info(None);
        // Tab focuses the first focusable widget: the path field.
        let tab = |pressed| egui::Event::Key {
            key: egui::Key::Tab,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Default::default(),
        };
        run_panel(&ctx, &mut settings, &mut nav, &mut state, &info, vec![]);
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info,
            vec![tab(true), tab(false)],
        );
        run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info,
            vec![egui::Event::Text("/tmp/x.vtk".into())],
        );
        assert_eq!(state.path, "/tmp/x.vtk");
        let key = |pressed| egui::Event::Key {
            key: egui::Key::Enter,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Default::default(),
        };
        let (actions, _) = run_panel(
            &ctx,
            &mut settings,
            &mut nav,
            &mut state,
            &info,
            vec![key(true), key(false)],
        );
        assert_eq!(actions, vec![Action::Open(PathBuf::from("/tmp/x.vtk"))]);
    }
}
