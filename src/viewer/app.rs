//! The eframe app: owns the data, the scene, the navigation and the 3D view, and ties panel,
//! input, loading, picking and screenshots together.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui_wgpu::RenderState;
use glam::DVec3;

use crate::camera::{Framing, ViewPreset};
use crate::field::vtk::ReadOptions;
use crate::progress::Silent;
use crate::render::{GpuContext, GpuRenderer};
use crate::scene::Scene;
use crate::scene::UnderlaySource;
use crate::select::Slicing;
use crate::staging::{self, Recipe, Source};
use crate::viewer::loader::{Loaded, Loading};
use crate::viewer::navigation::{Navigation, axis_view};
use crate::viewer::panel::{self, Action, PanelInfo, PanelState};
use crate::viewer::picking::{PickInfo, read_id};
use crate::viewer::screenshot::{Figure, parse_size, save_view, save_window};
use crate::viewer::state::{BuildKey, RenderKey, Settings};
use crate::viewer::triad;
use crate::viewer::view3d::View3d;
use crate::viewer::{Options, Outcome, ViewerError};

/// The scene built from the current data, settings and selection.
struct Built {
    key: BuildKey,
    scene: Scene,
    /// Glyph k of the scene (its instances' `glyph`) is glyph `selected[k]` of the set.
    selected: Vec<usize>,
    /// Of those, glyphs `--scale auto` scaled down to the robust largest size.
    clamped: usize,
    /// The style with the field's numbers fixed (the legend, the smallest relative radius).
    style: crate::glyph::style::ResolvedStyle,
    generation: u64,
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
    hover: Option<(u32, u32)>,
    picked: Option<PickInfo>,
    drawn: usize,
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
            hover: None,
            picked: None,
            drawn: 0,
            script: opts.screenshot.map(|output| Script {
                output,
                frames_left: opts.frames.max(1),
                requested: false,
                saved: Arc::new(Mutex::new(None)),
            }),
            outcome,
        };
        if let Some(src) = opts.source {
            app.open(&cc.egui_ctx, src);
        }
        Ok(app)
    }

    fn open(&mut self, ctx: &egui::Context, source: Source) {
        if let Source::File(p) = &source {
            self.panel.path = p.display().to_string();
        }
        let repaint = ctx.clone();
        self.loading = Some(Loading::start(
            source,
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

    /// Rebuild the scene when the data, style, glyph shape or selection changed.
    fn rebuild_if_needed(&mut self) {
        let Some(data) = &self.data else { return };
        let key = self.settings.build_key(self.data_generation);
        if self.built.as_ref().is_some_and(|b| b.key == key) {
            return;
        }
        let recipe = Recipe {
            read: self.read.clone(),
            style: key.style.clone(),
            selection: key.selection.clone(),
            glyph: key.glyph,
            underlay: key.underlay.clone(),
            // The panel shows the slicing it draws: the middle slice is set there on load.
            middle_slice: false,
            underlay_side: None,
        };
        let volume = data.underlay.as_deref();
        let built = match staging::build(
            &data.field,
            &data.set,
            data.spacing.clone(),
            &recipe,
            volume,
            &Silent,
        ) {
            Ok(b) => b,
            Err(e) => {
                // Nothing to draw (an empty selection): say why, keep the data.
                self.status = Some(e.to_string());
                staging::Built {
                    scene: Scene::default(),
                    glyphs_clamped: 0,
                    selected: Vec::new(),
                    frame_centre: DVec3::ZERO,
                    frame_radius: 1.0,
                    frame_half: DVec3::splat(1.0 / 3f64.sqrt()),
                    glyphs_valid: data.set.glyphs.len(),
                    face: None,
                    style: recipe.style.resolve(&data.set, data.spacing.clone()),
                }
            }
        };
        let staging::Built {
            scene,
            selected,
            frame_centre,
            frame_radius,
            face,
            glyphs_clamped,
            style,
            ..
        } = built;
        if let Err(e) = self.view.set_scene(&self.gpu, &scene) {
            self.error = Some(format!(
                "cannot upload {} glyphs: {e}",
                scene.instances.len()
            ));
        }
        self.scene_generation += 1;
        match &mut self.nav {
            Some(nav) => nav.set_bounds(scene.centre, scene.radius),
            None => {
                // Frame the whole field (not the selection) so slicing does not jump the view;
                // one slice of DTI data is seen face-on and close instead.
                let (framing, centre, radius) = match face.filter(|_| self.face_slice) {
                    Some(f) => (
                        Framing {
                            toward: Some(f.toward),
                            ..self.framing
                        },
                        f.centre,
                        f.radius,
                    ),
                    None => (self.framing, frame_centre, frame_radius),
                };
                self.nav = Some(Navigation::from_framing(&framing, centre, radius));
            }
        }
        self.picked = None;
        self.built = Some(Built {
            key,
            scene,
            selected,
            clamped: glyphs_clamped,
            style,
            generation: self.scene_generation,
        });
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
            Action::Screenshot => self.screenshot(),
        }
    }

    /// The 3D view as a PNG, through `render`'s own path.
    fn screenshot(&mut self) {
        let (Some(built), Some(nav)) = (&self.built, &self.nav) else {
            self.status = Some("nothing to save yet".into());
            return;
        };
        let size = if self.panel.screenshot_window_size {
            self.view.size()
        } else {
            parse_size(&self.panel.screenshot_size)
        };
        let Some(size) = size else {
            self.status = Some(format!(
                "screenshot size '{}' is not WxH",
                self.panel.screenshot_size
            ));
            return;
        };
        let path = PathBuf::from(self.panel.screenshot_path.trim());
        let ssaa = self.panel.figure_ssaa.clamp(1, 4);
        let camera = nav.camera(size.0, size.1);
        let mut req = self.settings.request(ssaa);
        if self.panel.figure_transparent {
            req.background[3] = 0.0;
        }
        let figure = Figure {
            size,
            ssaa,
            legend: self
                .panel
                .figure_legend
                .then(|| (&built.style, built.clamped, self.anatomical())),
        };
        self.status = Some(
            match save_view(&self.gpu, &built.scene, &camera, &req, &figure, &path) {
                Ok(()) => format!("saved {} ({}x{})", path.display(), size.0, size.1),
                Err(e) => format!("screenshot failed: {e:#}"),
            },
        );
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
        if response.double_clicked()
            && let Some(p) = self.pick()
            && let Some(nav) = &mut self.nav
        {
            nav.centre_on(DVec3::from(p.position));
        }
    }

    fn pick(&self) -> Option<PickInfo> {
        let (x, y) = self.hover?;
        let (targets, built, data) = (
            self.view.targets.as_ref()?,
            self.built.as_ref()?,
            self.data.as_ref()?,
        );
        // The targets hold n×n samples per window pixel: read the pixel's centre sample.
        let n = self.settings.ssaa.max(1);
        let id = read_id(&self.gpu.ctx, targets, x * n + n / 2, y * n + n / 2).ok()?;
        PickInfo::of(
            id,
            &built.scene,
            &built.selected,
            data,
            self.settings.style.class_threshold,
        )
    }

    /// Draw the frame if anything it depends on changed.
    fn render_if_needed(&mut self, pixels: (u32, u32)) -> bool {
        let (Some(nav), Some(built)) = (&self.nav, &self.built) else {
            return false;
        };
        let n = self.settings.ssaa.max(1);
        let samples = (pixels.0 * n, pixels.1 * n);
        let request = self.settings.request(n);
        let mut renderer = self.render_state.renderer.write();
        if let Err(e) = self.view.resize(
            &self.gpu,
            &mut renderer,
            samples,
            request.writes_aux(),
            n > 1,
        ) {
            self.error = Some(e.to_string());
            return false;
        }
        drop(renderer);
        let camera = nav.camera(samples.0, samples.1);
        let key = RenderKey {
            scene: built.generation,
            camera,
            request,
        };
        if self.last_render.as_ref() == Some(&key) {
            return false;
        }
        let req = &key.request;
        let vis = built
            .scene
            .visibility(&camera, req.cull, req.min_pixel_radius);
        self.drawn = built.scene.instances.len()
            - vis.eye_inside
            - vis.behind_camera
            - vis.degenerate
            - vis.culled;
        match self.view.draw(&self.gpu, &camera, &key.request) {
            Ok(()) => self.last_render = Some(key),
            Err(e) => {
                self.error = Some(format!("rendering failed: {e}"));
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
        self.poll_loading(&ctx);
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
        let adapter = self.gpu.adapter_name().to_string();
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
                    frame: self.view.last_frame,
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
            let rendered = self.render_if_needed(pixels);
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
            // Hover picking: read the id under the pointer when it moved or the frame changed.
            let moved = ui.input(|i| i.pointer.delta() != egui::Vec2::ZERO);
            if self.hover.is_none() {
                self.picked = None;
            } else if (moved || rendered) && !response.dragged() {
                self.picked = self.pick();
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
    }
}
