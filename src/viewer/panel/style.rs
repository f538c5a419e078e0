//! The style section: colour scheme, scale, normalisation and minimum radius, with the scheme's
//! legend (class swatches and the barycentric cl/cp/cs triangle, colour bars).

use egui::{Color32, Ui};

use crate::glyph::style::DEFAULT_MIN_RADIUS;
use crate::glyph::{ColorScheme, Normalize, Scale, SizeBy};
use crate::legend::{Legend, legend, short_number};
use crate::scene::odf::OdfNormalize;
use crate::tensor::shape::{ShapeClass, barycentric_color};
use crate::viewer::panel::{PanelInfo, PanelState};
use crate::viewer::state::Settings;

pub(super) fn style_section(
    ui: &mut Ui,
    settings: &mut Settings,
    state: &mut PanelState,
    info: &PanelInfo<'_>,
) {
    if let Some(sh) = info.data.and_then(|d| d.odf.as_deref()) {
        odf_section(ui, settings, sh);
        return;
    }
    if info.data.is_some_and(|d| d.peaks.is_some()) {
        peaks_section(ui, settings);
        return;
    }
    ui.heading("Glyphs");
    let style = &mut settings.style;
    egui::ComboBox::from_label("colour")
        .selected_text(style.color.name())
        .show_ui(ui, |ui| {
            for &c in ColorScheme::VALUES
                .iter()
                .filter(|&&c| settings.glyph.colours(c))
            {
                ui.selectable_value(&mut style.color, c, c.name());
            }
        });
    // The built scene's legend (its range and units) once it is built with the scheme chosen.
    let shown = info
        .legend
        .as_ref()
        .filter(|(asked, _)| *asked == style.color)
        .map(|(_, l)| l.clone());
    draw_legend(
        ui,
        shown.unwrap_or_else(|| legend(style.color, [0.0, 1.0], None)),
    );
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
    if style.scale == Scale::Auto && info.glyphs_clamped > 0 {
        ui.label(format!(
            "{} glyphs above the {:.0}th percentile shown at its size",
            info.glyphs_clamped,
            crate::glyph::style::AUTO_PERCENTILE * 100.0
        ))
        .on_hover_text("--scale auto: outliers (a singularity, CSF) are scaled down, shape kept");
    }
    egui::ComboBox::from_label("size by")
        .selected_text(style.size_by.name())
        .show_ui(ui, |ui| {
            for &s in SizeBy::VALUES {
                ui.selectable_value(&mut style.size_by, s, s.name());
            }
        });
    egui::ComboBox::from_label("normalise")
        .selected_text(style.normalize.name())
        .show_ui(ui, |ui| {
            for &n in Normalize::VALUES {
                ui.selectable_value(&mut style.normalize, n, n.name());
            }
        });
    // The field's default until the slider is moved.
    let mut eps = style
        .min_radius
        .or(info.min_radius)
        .unwrap_or(DEFAULT_MIN_RADIUS);
    if ui
        .add(egui::Slider::new(&mut eps, 0.0..=1.0).text("min radius"))
        .changed()
    {
        style.min_radius = Some(eps);
    }
}

fn color32(c: [f64; 3]) -> Color32 {
    let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    Color32::from_rgb(q(c[0]), q(c[1]), q(c[2]))
}

fn draw_legend(ui: &mut Ui, l: Legend) {
    match &l {
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
        Legend::Bar { lo, hi, title, .. } => {
            ui.label(title.as_str());
            colour_bar(ui, |t| l.bar_color(t).unwrap_or([1.0; 3]));
            ui.horizontal(|ui| {
                ui.label(short_number(*lo));
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    ui.label(short_number(*hi));
                });
            });
        }
        Legend::Sign => {
            colour_bar(ui, |t| l.bar_color(t).unwrap_or([1.0; 3]));
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
        Legend::Direction => {
            ui.label("RGB = |u| (x, y, z), u the point's direction from the centre");
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

/// ODF glyphs of a file of SH series: how each voxel's ODF is scaled (`--odf-normalize`) and
/// coloured (`--color dec`, `amplitude` or `solid`), as `render` does.
fn odf_section(ui: &mut Ui, settings: &mut Settings, sh: &crate::field::ShField) {
    ui.heading("ODF glyphs");
    let l = &sh.layout;
    ui.label(format!("SH lmax {}, {} basis", l.lmax, l.basis))
        .on_hover_text(&l.reason);
    egui::ComboBox::from_label("normalise")
        .selected_text(settings.odf_normalize.name())
        .show_ui(ui, |ui| {
            for &n in OdfNormalize::VALUES {
                ui.selectable_value(&mut settings.odf_normalize, n, n.name());
            }
        })
        .response
        .on_hover_text(
            "max: each voxel's ODF to its own largest value (DIPY's odf_slicer); minmax: \
             each voxel's [min, max] to [0, 1] (mrview); none: amplitudes comparable \
             across voxels",
        );
    // A tensor colouring kept from an earlier file is drawn as dec (the app builds it so):
    // the panel shows what is drawn.
    if !ODF_COLORS.contains(&settings.style.color) {
        settings.style.color = ColorScheme::Dec;
    }
    egui::ComboBox::from_label("colour")
        .selected_text(settings.style.color.name())
        .show_ui(ui, |ui| {
            for c in ODF_COLORS {
                ui.selectable_value(&mut settings.style.color, c, c.name());
            }
        })
        .response
        .on_hover_text(
            "dec: the direction of each point from the glyph's centre (red x, green y, blue \
             z); amplitude: the ODF's value there (1: the full radius); solid: one colour",
        );
    if settings.style.color == ColorScheme::Amplitude {
        draw_legend(ui, legend(ColorScheme::Amplitude, [0.0, 1.0], None));
    }
}

/// The sticks of a file of peaks: coloured by direction or solid, as `render` colours them.
fn peaks_section(ui: &mut Ui, settings: &mut Settings) {
    ui.heading("Peaks");
    if settings.style.color != ColorScheme::Solid {
        settings.style.color = ColorScheme::Dec;
    }
    egui::ComboBox::from_label("colour")
        .selected_text(settings.style.color.name())
        .show_ui(ui, |ui| {
            for c in [ColorScheme::Dec, ColorScheme::Solid] {
                ui.selectable_value(&mut settings.style.color, c, c.name());
            }
        })
        .response
        .on_hover_text("dec: the peak's direction (red x, green y, blue z); solid: one colour");
}

/// The colourings of ODF glyphs of SH series (`render --color` for such a file).
const ODF_COLORS: [ColorScheme; 3] = [ColorScheme::Dec, ColorScheme::Amplitude, ColorScheme::Solid];
