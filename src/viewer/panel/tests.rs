//! The panel driven headless: every section, scheme and slicing mode, and the selection rules.

use super::*;
use crate::field::vtk::ReadOptions;
use crate::glyph::ColorScheme;
use crate::select::{Plane, Selection, Slicing};
use crate::staging::{Demo, Source};
use crate::viewer::loader::load_now;
use crate::viewer::panel::selection::roi_checkbox_id;

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
        glyphs_clamped: 3,
        min_radius: Some(0.01),
        underlay_file: None,
        underlay_window: Some([0.1, 0.9]),
        legend: None,
    }
}

#[test]
fn panel_draws_every_scheme_and_slicing_mode() {
    let data = load_now(
        &Source::Demo(Demo { n: 4 }),
        &ReadOptions::default(),
        &None,
        &crate::progress::Silent,
    )
    .unwrap();
    let ctx = egui::Context::default();
    let mut nav = Navigation::framed(ViewPreset::Iso, glam::DVec3::ZERO, 1.0, false);
    let mut state = PanelState::default();
    for &scheme in ColorScheme::VALUES {
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
            if scheme == ColorScheme::Dec {
                settings.underlay = Some(crate::scene::UnderlaySource::Measure(
                    crate::tensor::measure::Measure::Md,
                ));
                settings.underlay_view.window = Some([0.2, 0.4]);
            }
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
        &None,
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
        .join("tests/data/vtk/legacy42_ascii_ugrid_T9.vtk");
    let data = load_now(
        &Source::File(path),
        &ReadOptions::default(),
        &None,
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

#[test]
fn an_underlay_chosen_over_the_whole_field_shows_the_middle_axial_slice() {
    let mut s = Settings::default();
    choose_underlay(
        &mut s,
        Some(crate::scene::UnderlaySource::Measure(
            crate::tensor::measure::Measure::Fa,
        )),
        [4, 6, 9],
    );
    assert_eq!(s.selection.slicing, Slicing::Slice { axis: 2, index: 4 });
    assert_eq!(
        s.underlay,
        Some(crate::scene::UnderlaySource::Measure(
            crate::tensor::measure::Measure::Fa
        ))
    );
    // A slice already chosen stays; turning the underlay off keeps the slice.
    s.selection.slicing = Slicing::Slice { axis: 0, index: 1 };
    choose_underlay(
        &mut s,
        Some(crate::scene::UnderlaySource::Measure(
            crate::tensor::measure::Measure::Md,
        )),
        [4, 6, 9],
    );
    assert_eq!(s.selection.slicing, Slicing::Slice { axis: 0, index: 1 });
    choose_underlay(&mut s, None, [4, 6, 9]);
    assert_eq!(s.underlay, None);
    assert_eq!(s.selection.slicing, Slicing::Slice { axis: 0, index: 1 });
}
