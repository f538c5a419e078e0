//! The eframe app, the same on the desktop and in the browser: owns the data, the scene, the
//! navigation and the 3D view, and ties panel, input, loading, picking and figures together.
//! What the platform does differently it does through a [`Host`], a [`Remote`], the loader and
//! [`Pending`](crate::viewer::pending::Pending) work.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui_wgpu::RenderState;
use glam::DVec3;

mod figures;
mod picks;
mod rebuild;
mod report;
mod underlay_file;

use crate::camera::{Framing, ViewPreset};
use crate::defaults::DataKind;
use crate::field::Inputs;
use crate::field::vtk::ReadOptions;
use crate::glyph::style::ResolvedStyle;
use crate::render::{GpuContext, GpuRenderer};
use crate::scene::Scene;
use crate::scene::UnderlaySource;
use crate::select::Slicing;
use crate::staging::Source;
use crate::viewer::draft::{self, Draft, Next};
use crate::viewer::loader::{Loaded, Loading, main_file};
use crate::viewer::navigation::{Navigation, axis_view};
use crate::viewer::panel::{self, Action, PanelInfo, PanelState};
use crate::viewer::picking::PickInfo;
use crate::viewer::screenshot::save_window;
use crate::viewer::state::{BuildKey, RenderKey, Settings};
use crate::viewer::triad;
use crate::viewer::view3d::View3d;
use crate::viewer::{Command, Host, Options, Outcome, Remote, Report, ViewerError};
use figures::FigureJob;
use picks::{PickFor, PickJob};

/// The scene built from the current data, settings and selection.
struct Built {
    key: BuildKey,
    scene: Arc<Scene>,
    /// Glyph k of the scene (its instances' `glyph`) is glyph `selected[k]` of the set.
    selected: Vec<usize>,
    /// Of those, glyphs `--scale auto` scaled down to the robust largest size.
    clamped: usize,
    /// The style with the field's numbers fixed (the legend, the smallest relative radius).
    style: ResolvedStyle,
    generation: u64,
    /// What `render` frames by default: the field's box (or the face-on slice), and the
    /// framing the view started with.
    render_framing: (Framing, DVec3, DVec3),
}

pub struct ViewerApp {
    gpu: Arc<GpuRenderer>,
    render_state: RenderState,
    read: ReadOptions,
    /// `--underlay FILE`: read with every field opened, offered in the panel.
    underlay_file: Option<UnderlaySource>,
    settings: Settings,
    panel: PanelState,
    data: Option<Loaded>,
    data_generation: u64,
    loading: Option<Loading>,
    error: Option<String>,
    status: Option<String>,
    built: Option<Built>,
    scene_generation: u64,
    nav: Option<Navigation>,
    /// The camera options the first scene is framed with.
    framing: Framing,
    /// The first scene, if it shows one slice, is seen face-on.
    face_slice: bool,
    /// The first data opens on its middle axial slice.
    middle_slice: bool,
    view: View3d,
    last_render: Option<RenderKey>,
    /// Coarser frames while the camera moves, and the draft on screen.
    draft: Draft,
    /// The view's size in window pixels, as last drawn.
    pub(super) pixels: (u32, u32),
    hover: Option<(u32, u32)>,
    picked: Option<PickInfo>,
    drawn: usize,
    /// The hover pick is stale (the pointer moved or the frame changed).
    pick_dirty: bool,
    pick_job: Option<PickJob>,
    figure_job: Option<FigureJob>,
    /// `?figure=`: asked for before a scene was there to draw.
    figure_asked: Option<(u32, u32, String)>,
    /// Each opened source brings its kind's defaults (the page; the desktop keeps its command
    /// line's).
    adopt_defaults: bool,
    /// The adapter's name where the back end gives none.
    adapter_label: Option<String>,
    /// A frame of the current scene was drawn (the status waits for it).
    drawn_generation: Option<u64>,
    host: Box<dyn Host>,
    remote: Remote,
    reported: Report,
    // Scripted mode.
    script: Option<Script>,
    outcome: Arc<Mutex<Outcome>>,
}

struct Script {
    output: PathBuf,
    frames_left: u32,
    requested: bool,
    saved: Arc<Mutex<Option<Result<(), String>>>>,
}

impl ViewerApp {
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        opts: Options,
        outcome: Arc<Mutex<Outcome>>,
        host: Box<dyn Host>,
    ) -> Result<Self, ViewerError> {
        let rs = cc
            .wgpu_render_state
            .clone()
            .ok_or_else(|| ViewerError::Window("the viewer needs eframe's wgpu renderer".into()))?;
        let ctx = GpuContext::from_device(&rs.adapter, rs.device.clone(), rs.queue.clone());
        let gpu = Arc::new(GpuRenderer::new(ctx)?);
        cc.egui_ctx.set_theme(egui::Theme::Dark);
        let mut app = Self {
            gpu,
            render_state: rs,
            read: opts.read.clone(),
            underlay_file: opts
                .settings
                .underlay
                .clone()
                .filter(|u| matches!(u, UnderlaySource::File(_))),
            settings: opts.settings.clone(),
            panel: PanelState {
                scale_text: opts.settings.style.scale.to_string(),
                ..PanelState::default()
            },
            data: None,
            data_generation: 0,
            loading: None,
            error: None,
            status: None,
            built: None,
            scene_generation: 0,
            nav: None,
            framing: opts.framing,
            face_slice: opts.face_slice,
            middle_slice: opts.middle_slice,
            view: View3d::default(),
            last_render: None,
            draft: Draft::default(),
            pixels: (1, 1),
            hover: None,
            picked: None,
            drawn: 0,
            pick_dirty: false,
            pick_job: None,
            figure_job: None,
            figure_asked: None,
            adopt_defaults: opts.adopt_defaults,
            adapter_label: opts.adapter_label.clone(),
            drawn_generation: None,
            host,
            remote: opts.remote.clone(),
            reported: Report::default(),
            script: opts.screenshot.map(|output| Script {
                output,
                frames_left: opts.frames.max(1),
                requested: false,
                saved: Arc::new(Mutex::new(None)),
            }),
            outcome,
        };
        app.remote.attach(&cc.egui_ctx);
        if let Some(src) = opts.source {
            app.open(&cc.egui_ctx, src);
        }
        Ok(app)
    }

    fn open(&mut self, ctx: &egui::Context, source: Source) {
        self.open_from(ctx, source, Inputs::file_system());
    }

    /// Files handed over as bytes, read through the one that names the others.
    fn open_files(&mut self, ctx: &egui::Context, files: Vec<(String, Vec<u8>)>) {
        let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
        let Some(main) = main_file(&names) else {
            return;
        };
        let source = Source::File(PathBuf::from(main));
        self.open_from(ctx, source, Inputs::named(files));
    }

    fn open_from(&mut self, ctx: &egui::Context, source: Source, inputs: Inputs) {
        if let Source::File(p) = &source {
            self.panel.path = p.display().to_string();
        }
        if self.adopt_defaults {
            let defaults = DataKind::of(&source).defaults();
            self.settings.adopt(&defaults);
            self.face_slice = defaults.face_on;
            self.middle_slice = defaults.middle_slice;
            self.settings.selection.slicing = crate::select::Slicing::Whole;
        }
        let repaint = ctx.clone();
        self.loading = Some(Loading::start(
            source,
            inputs,
            self.read.clone(),
            self.underlay_file.clone(),
            move || repaint.request_repaint(),
        ));
    }

    /// Take a finished load: new data replaces the old; an error keeps the old.
    fn poll_loading(&mut self, ctx: &egui::Context) {
        let Some(loading) = &mut self.loading else {
            return;
        };
        match loading.poll() {
            None => ctx.request_repaint_after(std::time::Duration::from_millis(100)),
            Some(Ok(data)) => {
                self.loading = None;
                // A selection that does not fit this data (slices beyond its lattice, or any
                // slice of unstructured data) is adjusted, and the panel says so.
                self.error = self
                    .settings
                    .selection
                    .check_field(&data.field)
                    .err()
                    .map(|e| format!("{e}; the selection was adjusted to fit"));
                self.settings.clamp_to_lattice(data.field.lattice_dims());
                if let (true, Some(d)) = (
                    std::mem::take(&mut self.middle_slice),
                    data.field.lattice_dims(),
                ) && self.settings.selection.slicing == Slicing::Whole
                {
                    self.settings.selection.slicing = Slicing::Slice {
                        axis: 2,
                        index: d[2] / 2,
                    };
                }
                self.data = Some(data);
                self.data_generation += 1;
                self.nav = None; // framed anew once the scene is built
                self.status = None;
            }
            Some(Err(e)) => {
                self.loading = None;
                self.error = Some(e);
                if let (Some(s), None) = (&mut self.script, &self.data) {
                    // A scripted run has nothing to show: stop with the error.
                    s.frames_left = 0;
                }
            }
        }
    }

    fn handle_keys(&mut self, ctx: &egui::Context) -> Vec<Action> {
        let mut actions = Vec::new();
        if ctx.egui_wants_keyboard_input() {
            return actions;
        }
        ctx.input(|i| {
            let keys = [
                egui::Key::Num1,
                egui::Key::Num2,
                egui::Key::Num3,
                egui::Key::Num4,
                egui::Key::Num5,
                egui::Key::Num6,
            ];
            for (k, key) in keys.into_iter().enumerate() {
                if i.key_pressed(key) {
                    actions.extend(axis_view(k + 1).map(Action::View));
                }
            }
            if i.key_pressed(egui::Key::R) {
                actions.push(Action::View(ViewPreset::Iso));
            }
            if i.key_pressed(egui::Key::S) {
                actions.push(Action::Screenshot);
            }
        });
        if ctx.input(|i| i.key_pressed(egui::Key::P))
            && let Some(nav) = &mut self.nav
        {
            nav.ortho = !nav.ortho;
        }
        actions
    }

    fn apply(&mut self, ctx: &egui::Context, action: Action) {
        match action {
            Action::Open(p) => self.open(ctx, Source::File(p)),
            Action::View(preset) => {
                if let Some(nav) = &mut self.nav {
                    nav.reset(preset);
                }
            }
            Action::Screenshot => self.screenshot(ctx),
        }
    }

    /// The adapter as people read it.
    fn adapter_name(&self) -> &str {
        match (self.gpu.adapter_name(), &self.adapter_label) {
            ("", Some(label)) => label,
            (name, _) => name,
        }
    }

    /// Whether the loaded field's world is anatomical (RAS): axes labelled R/A/S.
    fn anatomical(&self) -> bool {
        self.data.as_ref().is_some_and(|d| {
            d.field
                .meta
                .frame
                .as_ref()
                .is_some_and(|f| f.world == "RAS")
        })
    }

    /// Pointer navigation and picking on the 3D area.
    fn interact(&mut self, ui: &egui::Ui, response: &egui::Response, pixels: (u32, u32)) {
        let Some(nav) = &mut self.nav else { return };
        let height = f64::from(response.rect.height());
        let (shift, delta) = ui.input(|i| (i.modifiers.shift, i.pointer.delta()));
        let (dx, dy) = (f64::from(delta.x), f64::from(delta.y));
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            nav.orbit(dx, dy);
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            nav.pan(dx, dy, height);
        }
        if response.hovered() {
            let (scroll, pinch) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            let mut factor = f64::from(pinch);
            if scroll != 0.0 {
                factor *= (f64::from(scroll) * 0.002).exp();
            }
            if factor != 1.0 {
                nav.zoom(factor);
            }
        }
        // The pixel under the pointer.
        let ppp = ui.ctx().pixels_per_point();
        self.hover = response.hover_pos().map(|p| {
            let rel = (p - response.rect.min) * ppp;
            (
                (rel.x.max(0.0) as u32).min(pixels.0.saturating_sub(1)),
                (rel.y.max(0.0) as u32).min(pixels.1.saturating_sub(1)),
            )
        });
        if response.double_clicked() {
            self.start_pick(ui.ctx(), PickFor::Centre);
        }
    }

    /// Draw the frame if anything it depends on changed: whole, or while the camera moves over
    /// a slow scene a coarser draft of it (whole once the camera is still).
    fn render_if_needed(&mut self, ctx: &egui::Context, pixels: (u32, u32)) -> bool {
        let (Some(nav), Some(built)) = (&self.nav, &self.built) else {
            return false;
        };
        self.pixels = pixels;
        let n = self.settings.ssaa.max(1);
        let full = (pixels.0 * n, pixels.1 * n);
        let key = RenderKey {
            scene: built.generation,
            camera: nav.camera(full.0, full.1),
            request: self.settings.request(n),
        };
        if self.draft.shown.is_none()
            && self.last_render.is_some()
            && let Some(f) = self.view.frame_time()
        {
            self.draft.full_ms = Some(f.ms);
        }
        let next = self
            .draft
            .next(&key, self.last_render.as_ref(), self.settings.draft);
        let (samples, camera, req) = match next {
            Next::Nothing => {
                if let Some(due) = self.draft.due_in() {
                    ctx.request_repaint_after(due);
                }
                return false;
            }
            Next::Full => (full, key.camera, key.request),
            Next::Draft(d) => {
                let size = draft::coarse_size(full, d);
                let mut req = key.request;
                req.min_pixel_radius /= d as f32;
                (size, nav.camera(size.0, size.1), req)
            }
        };
        let smooth = n > 1 || matches!(next, Next::Draft(_));
        let mut renderer = self.render_state.renderer.write();
        if let Err(e) =
            self.view
                .resize(&self.gpu, &mut renderer, samples, req.aux_target(), smooth)
        {
            self.error = Some(e.to_string());
            return false;
        }
        drop(renderer);
        let vis = built
            .scene
            .visibility(&camera, req.cull, req.min_pixel_radius);
        self.drawn = built.scene.instances.len()
            - vis.eye_inside
            - vis.behind_camera
            - vis.degenerate
            - vis.culled;
        if let Err(e) = self.view.draw(&self.gpu, &camera, &req) {
            self.error = Some(format!("rendering failed: {e}"));
        }
        match next {
            Next::Draft(d) => {
                self.draft.shown = Some((key, d, web_time::Instant::now()));
                ctx.request_repaint_after(draft::SETTLE);
            }
            _ => {
                self.draft.shown = None;
                self.last_render = Some(key);
            }
        }
        true
    }

    fn scripted(&mut self, ctx: &egui::Context) {
        let Some(s) = &mut self.script else { return };
        if let Some(result) = s.saved.lock().unwrap_or_else(|e| e.into_inner()).take() {
            let mut out = self.outcome.lock().unwrap_or_else(|e| e.into_inner());
            out.error = result.err();
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        if self.loading.is_some() {
            return;
        }
        if self.data.is_none() && !s.requested {
            let mut out = self.outcome.lock().unwrap_or_else(|e| e.into_inner());
            out.error = Some(self.error.clone().unwrap_or_else(|| "no data".into()));
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        if s.frames_left > 0 {
            s.frames_left -= 1;
            ctx.request_repaint();
        } else if !s.requested {
            s.requested = true;
            let saved = s.saved.clone();
            let path = s.output.clone();
            let wake = ctx.clone();
            ctx.request_screenshot(move |image| {
                *saved.lock().unwrap_or_else(|e| e.into_inner()) =
                    Some(save_window(&image, &path).map_err(|e| e.to_string()));
                wake.request_repaint();
            });
        }
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        for command in self.remote.take() {
            match command {
                Command::Open(source) => self.open(&ctx, source),
                Command::OpenFiles(files) => self.open_files(&ctx, files),
                Command::Figure { size, name } => self.figure_asked = Some((size.0, size.1, name)),
                Command::Underlay(files) => self.open_underlay(files),
                Command::Effects(effects) => self.settings.effects = effects,
            }
        }
        // The first is the cause; later ones tend to follow from it.
        if let Some(e) = self.gpu.ctx.take_late_errors().into_iter().next() {
            self.error = Some(e);
        }
        self.poll_loading(&ctx);
        self.poll_figure();
        self.poll_pick();
        // Files dropped on the window.
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        if let Some(p) = dropped.into_iter().next() {
            self.open(&ctx, Source::File(p));
        }
        let mut actions = self.handle_keys(&ctx);
        self.rebuild_if_needed();

        let loading = self.loading.as_ref().map(|l| {
            let (stage, frac) = l.progress();
            (l.source.name(), stage, frac)
        });
        let adapter = self.adapter_name().to_string();
        egui::Panel::left("panel")
            .default_size(330.0)
            .resizable(true)
            .show(ui, |ui| {
                let info = PanelInfo {
                    data: self.data.as_ref(),
                    loading: loading.clone(),
                    error: self.error.as_deref(),
                    status: self.status.as_deref(),
                    glyphs_selected: self.built.as_ref().map_or(0, |b| b.selected.len()),
                    glyphs_drawn: self.drawn,
                    frame: self.view.frame_time(),
                    adapter: &adapter,
                    glyphs_clamped: self.built.as_ref().map_or(0, |b| b.clamped),
                    min_radius: self.built.as_ref().map(|b| b.style.min_radius),
                    underlay_file: self.underlay_file.as_ref(),
                    underlay_window: self
                        .built
                        .as_ref()
                        .and_then(|b| b.scene.underlay.as_ref())
                        .map(|u| u.window),
                    legend: self
                        .built
                        .as_ref()
                        .map(|b| (b.key.style.color, crate::legend::Legend::of(&b.style))),
                };
                actions.extend(panel::show(
                    ui,
                    &mut self.settings,
                    self.nav.as_mut(),
                    &mut self.panel,
                    &info,
                ));
            });
        for a in actions {
            self.apply(&ctx, a);
        }
        self.rebuild_if_needed();

        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let ppp = ctx.pixels_per_point();
            let pixels = (
                ((rect.width() * ppp).round() as u32).max(1),
                ((rect.height() * ppp).round() as u32).max(1),
            );
            let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
            self.interact(ui, &response, pixels);
            let rendered = self.render_if_needed(&ctx, pixels);
            match self.view.texture {
                Some(tex) if self.built.is_some() => {
                    ui.painter().image(
                        tex,
                        rect,
                        egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                        egui::Color32::WHITE,
                    );
                    if let Some(nav) = &self.nav {
                        triad::paint(ui.painter(), rect, nav, self.anatomical());
                    }
                }
                _ => {
                    ui.painter().text(
                        rect.center(),
                        egui::Align2::CENTER_CENTER,
                        if self.loading.is_some() {
                            "loading…"
                        } else {
                            "drop a VTK file here"
                        },
                        egui::FontId::proportional(20.0),
                        ui.visuals().text_color(),
                    );
                }
            }
            // Hover picking: read the id under the pointer when it moved or the frame changed
            // (one read at a time: the browser's come a frame or so later).
            let moved = ui.input(|i| i.pointer.delta() != egui::Vec2::ZERO);
            if rendered {
                self.drawn_generation = self.built.as_ref().map(|b| b.generation);
            }
            if self.hover.is_none() {
                self.picked = None;
                self.pick_dirty = false;
            } else if (moved || rendered) && !response.dragged() {
                self.pick_dirty = true;
            }
            if self.pick_dirty && self.pick_job.is_none() {
                self.pick_dirty = false;
                self.start_pick(&ctx, PickFor::Hover);
            }
            if let (Some(p), Some(pos)) = (&self.picked, response.hover_pos()) {
                let text = p.text();
                egui::Tooltip::always_open(
                    ctx.clone(),
                    ui.layer_id(),
                    response.id,
                    egui::PopupAnchor::Position(pos + egui::vec2(16.0, 16.0)),
                )
                .show(|ui| {
                    ui.label(egui::RichText::new(text).monospace());
                });
            }
        });
        self.scripted(&ctx);
        if let (Some((w, h, name)), true) = (&self.figure_asked, self.drawn_generation.is_some()) {
            let (size, name) = ((*w, *h), name.clone());
            self.figure_asked = None;
            self.render_figure(&ctx, size, name);
        }
        self.report(&ctx);
    }
}
