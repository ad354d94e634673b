//! The editor's panels and its viewport input, in egui. Everything the designer does becomes an
//! [`Edit`] of the document or a change of the camera, selection or display; nothing here touches
//! the GPU, so the panels are tested with egui_kittest.
//!
//! Mouse, as Blender and Rhino users expect: left click selects (Shift adds), left drag on a
//! selected cage vertex moves the selection in the view plane (X, Y or Z while dragging locks an
//! axis, Esc cancels), left drag elsewhere box-selects; right or middle drag orbits, with Shift
//! pans; the wheel zooms. Keys: Ctrl+Z undo, Ctrl+Shift+Z or Ctrl+Y redo, Ctrl+S save,
//! Ctrl+Shift+S save as, Ctrl+O open, Ctrl+A select all, F frame selection, Home or A frame all,
//! 1 / 3 / 7 (or the numpad) front, right and top views, 5 perspective, Ctrl+Q quit.

use super::document::{Edit, EditorDocument};
use super::files::Recovery;
use super::interaction::{self, Axis, ViewportRect};
use super::state::{DisplayMode, EditorState};
use egui::{Key, Modifiers, PointerButton, Sense};
use std::path::PathBuf;
use taut_core::curvature::CurvatureQuantity;
use taut_core::nusd::Spacing;
use taut_core::nusd::surface::Phase;
use taut_core::{DVec3, VertexId};
use taut_render::StandardView;

/// What a file path is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPurpose {
    Open,
    SaveAs,
    ExportObj,
    ExportGlb,
    Screenshot,
}

impl PathPurpose {
    pub fn title(self) -> &'static str {
        match self {
            PathPurpose::Open => "Open a cage (.taut, .obj, .gltf, .glb)",
            PathPurpose::SaveAs => "Save the cage as (.taut)",
            PathPurpose::ExportObj => "Export the surface as OBJ",
            PathPurpose::ExportGlb => "Export the surface as GLB",
            PathPurpose::Screenshot => "Save a screenshot of the viewport (.png)",
        }
    }

    fn extension(self) -> &'static str {
        match self {
            PathPurpose::Open => "taut",
            PathPurpose::SaveAs => "taut",
            PathPurpose::ExportObj => "obj",
            PathPurpose::ExportGlb => "glb",
            PathPurpose::Screenshot => "png",
        }
    }
}

/// Makes a new document (the File ▸ New entries).
pub type MakeDocument = fn() -> taut_core::Document;

/// Something that would drop unsaved work, waiting for the designer's answer.
#[derive(Clone, Debug)]
pub enum Pending {
    New(MakeDocument),
    Open(Option<PathBuf>),
    Recover,
    Quit,
}

/// A drag of cage vertices in progress.
#[derive(Clone, Debug)]
struct VertexDrag {
    start: Vec<(VertexId, DVec3)>,
    mouse_start: glam::Vec2,
    axis: Option<Axis>,
}

/// Dialog and gesture state of the UI.
#[derive(Debug, Default)]
pub struct UiState {
    /// The in-app path field (used when there is no system file dialog).
    pub path_dialog: Option<(PathPurpose, String)>,
    /// An action waiting for "save changes?".
    pub pending: Option<Pending>,
    /// A crash recovery offered at start.
    pub recovery: Option<Recovery>,
    /// Set when the editor should close.
    pub quit: bool,
    /// A screenshot the window should write.
    pub screenshot: Option<PathBuf>,
    /// The viewport's rectangle in physical pixels, for the renderer.
    pub viewport_px: Option<[u32; 4]>,
    drag: Option<VertexDrag>,
    box_select: Option<(glam::Vec2, glam::Vec2)>,
    /// Tension slider values while a slider is held (one undo step a movement).
    slider_active: bool,
    /// Use the in-app path field even when a system dialog might exist (tests, Xvfb).
    pub no_native_dialogs: bool,
}

impl EditorState {
    /// Draws the whole UI for one frame and handles its input.
    pub fn ui(&mut self, ui_root: &mut egui::Ui, ui_state: &mut UiState) {
        let ctx = ui_root.ctx().clone();
        self.shortcuts(&ctx, ui_state);
        egui::Panel::top("menu").show(ui_root, |ui| {
            egui::MenuBar::new().ui(ui, |ui| self.menu(ui, ui_state));
        });
        egui::Panel::bottom("status").show(ui_root, |ui| self.status_bar(ui));
        egui::Panel::left("cage").resizable(false).exact_size(260.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.cage_panel(ui, ui_state));
        });
        egui::Panel::right("settings").resizable(false).exact_size(270.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                self.solver_panel(ui, ui_state);
                ui.separator();
                self.display_panel(ui);
            });
        });
        egui::CentralPanel::no_frame().show(ui_root, |ui| self.viewport(ui, ui_state));
        self.dialogs(&ctx, ui_state);
    }

    fn shortcuts(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        // Typing into a text field owns the keyboard; a focused slider or button does not.
        if ctx.text_edit_focused() {
            return;
        }
        let command = Modifiers::COMMAND;
        let command_shift = Modifiers::COMMAND | Modifiers::SHIFT;
        let (undo, redo, redo_y, save, save_as, open, select_all, quit) = ctx.input_mut(|i| {
            (
                i.consume_key(command, Key::Z),
                i.consume_key(command_shift, Key::Z),
                i.consume_key(command, Key::Y),
                i.consume_key(command, Key::S),
                i.consume_key(command_shift, Key::S),
                i.consume_key(command, Key::O),
                i.consume_key(command, Key::A),
                i.consume_key(command, Key::Q),
            )
        });
        if undo {
            self.undo();
        }
        if redo || redo_y {
            self.redo();
        }
        // Save without a path asks for one, as Save As does.
        if save_as || (save && !self.save()) {
            self.ask_path(PathPurpose::SaveAs, ui_state);
        }
        if open {
            self.request(Pending::Open(None), ui_state);
        }
        if select_all {
            self.selection.clear();
            self.selection.vertices = self.document.doc().cage.vertices().collect();
        }
        if quit {
            self.request(Pending::Quit, ui_state);
        }
        let keys = ctx.input(|i| {
            let pressed = |k: Key| i.key_pressed(k) && !i.modifiers.command;
            [
                pressed(Key::F),
                pressed(Key::Home) || pressed(Key::A),
                pressed(Key::Num1),
                pressed(Key::Num3),
                pressed(Key::Num7),
                pressed(Key::Num5),
                pressed(Key::X),
                pressed(Key::Y),
                pressed(Key::Z),
                pressed(Key::Escape),
            ]
        });
        let [frame_selection, frame_all, front, right, top, perspective, x, y, z, escape] = keys;
        if let Some(drag) = &mut ui_state.drag {
            for (pressed, axis) in [(x, Axis::X), (y, Axis::Y), (z, Axis::Z)] {
                if pressed {
                    drag.axis = if drag.axis == Some(axis) { None } else { Some(axis) };
                }
            }
            if escape {
                let start = drag.start.clone();
                self.edit(Edit::MoveVertices(start));
                self.document.end_gesture();
                ui_state.drag = None;
            }
        } else {
            if frame_selection {
                self.frame_selection();
            }
            if frame_all {
                self.frame_all();
            }
            for (pressed, view) in [
                (front, StandardView::Front),
                (right, StandardView::Right),
                (top, StandardView::Top),
                (perspective, StandardView::Perspective),
            ] {
                if pressed {
                    self.camera.set_view(view);
                }
            }
            if escape {
                self.selection.clear();
                ui_state.box_select = None;
            }
        }
    }

    pub fn undo(&mut self) {
        if self.document.undo() {
            self.prune_selection();
        }
    }

    pub fn redo(&mut self) {
        if self.document.redo() {
            self.prune_selection();
        }
    }

    /// Runs an action now, or asks first when it would drop unsaved changes.
    pub fn request(&mut self, action: Pending, ui_state: &mut UiState) {
        if self.document.is_dirty() {
            ui_state.pending = Some(action);
        } else {
            self.run_pending(action, ui_state);
        }
    }

    pub(super) fn run_pending(&mut self, action: Pending, ui_state: &mut UiState) {
        match action {
            Pending::New(make) => self.replace_document(EditorDocument::new(make(), None)),
            Pending::Open(Some(path)) => self.open(&path),
            Pending::Open(None) => self.ask_path(PathPurpose::Open, ui_state),
            Pending::Recover => {
                match self.autosave.as_ref().ok_or_else(|| "autosave is off".to_string()).and_then(|a| a.recover()) {
                    Ok(document) => {
                        self.replace_document(document);
                        self.notify("recovered the autosaved work; save it to keep it", false);
                    }
                    Err(e) => self.notify(format!("could not recover: {e}"), true),
                }
            }
            Pending::Quit => ui_state.quit = true,
        }
    }

    /// Asks for a path: the system dialog when there is one, else the in-app path field.
    pub fn ask_path(&mut self, purpose: PathPurpose, ui_state: &mut UiState) {
        if !ui_state.no_native_dialogs && native_dialogs_available() {
            let dialog = rfd::FileDialog::new().set_title(purpose.title());
            let dialog = match purpose {
                PathPurpose::Open => dialog.add_filter("Cages and meshes", &["taut", "obj", "gltf", "glb"]),
                other => dialog.add_filter(other.extension(), &[other.extension()]),
            };
            let picked = if purpose == PathPurpose::Open { dialog.pick_file() } else { dialog.save_file() };
            if let Some(path) = picked {
                self.path_chosen(purpose, path, ui_state);
            }
            return;
        }
        let suggestion = match (purpose, self.document.path()) {
            (PathPurpose::Open, _) => String::new(),
            (p, Some(path)) => path.with_extension(p.extension()).display().to_string(),
            (p, None) => format!("untitled.{}", p.extension()),
        };
        ui_state.path_dialog = Some((purpose, suggestion));
    }

    pub(super) fn path_chosen(&mut self, purpose: PathPurpose, path: PathBuf, ui_state: &mut UiState) {
        match purpose {
            PathPurpose::Open => self.open(&path),
            PathPurpose::SaveAs => self.save_as(&path),
            PathPurpose::ExportObj => self.export(&super::state::with_extension_if_missing(&path, "obj")),
            PathPurpose::ExportGlb => self.export(&super::state::with_extension_if_missing(&path, "glb")),
            PathPurpose::Screenshot => {
                ui_state.screenshot = Some(super::state::with_extension_if_missing(&path, "png"))
            }
        }
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label(self.document.title());
            ui.separator();
            match (&self.status, &self.solver_error) {
                (_, Some(error)) => {
                    ui.colored_label(egui::Color32::LIGHT_RED, format!("cannot smooth: {error}"));
                }
                (Some(s), None) => {
                    let state = match s.phase {
                        Phase::Iterating => "settling",
                        Phase::Done
                            if self.solver.as_ref().is_some_and(|x| x.reports().iter().all(|r| r.converged)) =>
                        {
                            "converged"
                        }
                        Phase::Done => "stopped at the iteration cap",
                        Phase::Diverged => "diverged (rolled back)",
                    };
                    ui.label(format!(
                        "level {}/{}  iterations {}  step {:.2e}  {}",
                        s.level, s.levels, s.total_iterations, s.last_step, state
                    ));
                    if s.lambda != self.document.doc().settings.lambda {
                        ui.label(format!("λ reduced to {}", s.lambda));
                    }
                }
                (None, None) => {
                    ui.label("starting");
                }
            }
            ui.separator();
            let ms = self.frame_time.as_secs_f64() * 1e3;
            ui.label(format!("frame {ms:.1} ms ({:.0} fps)", if ms > 0.0 { 1e3 / ms } else { 0.0 }));
            ui.separator();
            ui.label(format!(
                "{} vertices, {} edges selected",
                self.selection.vertices.len(),
                self.selection.edges.len()
            ));
            if let Some(notice) = self.notice.clone() {
                ui.separator();
                let color = if notice.is_error { egui::Color32::LIGHT_RED } else { ui.visuals().text_color() };
                ui.colored_label(color, &notice.text);
                if ui.small_button("✕").clicked() {
                    self.notice = None;
                }
            }
        });
    }

    fn cage_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Cage");
        let doc = self.document.doc().clone();
        let vertices = self.selected_vertices_with_edge_ends();
        if self.selection.is_empty() {
            ui.label("Click a cage vertex or edge to select it; Shift adds, a drag on empty space box-selects.");
            return;
        }
        if let [v] = self.selection.vertices.as_slice()
            && self.selection.edges.is_empty()
        {
            let v = *v;
            ui.label(format!("vertex {}", v.0));
            let mut p = doc.cage.position(v);
            let mut changed = false;
            let mut responses = Vec::new();
            ui.horizontal(|ui| {
                for (label, value) in [("X", &mut p.x), ("Y", &mut p.y), ("Z", &mut p.z)] {
                    let name = ui.label(label);
                    let response = ui
                        .add(egui::DragValue::new(value).speed(0.01 * doc.cage.bounding_diagonal()).max_decimals(4))
                        .labelled_by(name.id);
                    changed |= response.changed();
                    responses.push(response);
                }
            });
            for r in &responses {
                self.gesture_start(r, ui_state);
            }
            if changed {
                self.edit(Edit::MoveVertices(vec![(v, p)]));
            }
            for r in &responses {
                self.gesture_end(r, ui_state);
            }
        } else {
            ui.label(format!("{} vertices, {} edges", self.selection.vertices.len(), self.selection.edges.len()));
        }
        ui.separator();
        let all_fixed = vertices.iter().all(|v| doc.fixed[v.index()]);
        let mut fixed = all_fixed;
        if ui.checkbox(&mut fixed, "fixed (the surface passes through)").changed() {
            self.edit(Edit::SetFixed(vertices.clone(), fixed));
        }
        ui.separator();
        if !self.selection.vertices.is_empty() {
            let mut tau = self.selection.vertices.iter().map(|v| doc.vertex_tension[v.index()]).fold(0.0, f64::max);
            let name = ui.label("vertex tension τ");
            let response = ui
                .add(egui::Slider::new(&mut tau, 0.0..=8.0).clamping(egui::SliderClamping::Never))
                .labelled_by(name.id);
            self.gesture_start(&response, ui_state);
            if response.changed() {
                self.edit(Edit::SetVertexTension(self.selection.vertices.clone(), tau.max(0.0)));
            }
            self.gesture_end(&response, ui_state);
        }
        if !self.selection.edges.is_empty() {
            let mut tau = self.selection.edges.iter().map(|e| doc.edge_tension[e.index()]).fold(0.0, f64::max);
            let name = ui.label("edge tension τ");
            let response = ui
                .add(egui::Slider::new(&mut tau, 0.0..=8.0).clamping(egui::SliderClamping::Never))
                .labelled_by(name.id);
            self.gesture_start(&response, ui_state);
            if response.changed() {
                self.edit(Edit::SetEdgeTension(self.selection.edges.clone(), tau.max(0.0)));
            }
            self.gesture_end(&response, ui_state);
        }
        if ui.button("Reset tension").clicked() {
            self.edit(Edit::ResetTension {
                vertices: self.selection.vertices.clone(),
                edges: self.selection.edges.clone(),
            });
        }
        ui.small("Tension above about 4 over-flattens: the curve bends back.");
    }

    /// A slider or field drag is one undo step: the gesture opens when the drag starts and
    /// closes after the edit of the frame the drag stops in.
    fn gesture_start(&mut self, response: &egui::Response, ui_state: &mut UiState) {
        if response.drag_started() && !ui_state.slider_active && !self.document.in_gesture() {
            ui_state.slider_active = true;
            self.document.begin_gesture();
        }
    }

    fn gesture_end(&mut self, response: &egui::Response, ui_state: &mut UiState) {
        if response.drag_stopped() && ui_state.slider_active {
            ui_state.slider_active = false;
            self.document.end_gesture();
        }
    }

    fn solver_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Smoothing");
        let mut settings = self.document.doc().settings;
        let before = settings;
        let mut responses = Vec::new();
        ui.horizontal(|ui| {
            let name = ui.label("levels");
            responses.push(ui.add(egui::Slider::new(&mut settings.levels, 0..=5)).labelled_by(name.id));
        });
        ui.horizontal(|ui| {
            let name = ui.label("λ");
            responses.push(ui.add(egui::Slider::new(&mut settings.lambda, 0.05..=0.95)).labelled_by(name.id));
        });
        ui.horizontal(|ui| {
            let name = ui.label("tolerance");
            responses
                .push(ui.add(egui::Slider::new(&mut settings.tol, 1e-6..=1e-2).logarithmic(true)).labelled_by(name.id));
        });
        for r in &responses {
            self.gesture_start(r, ui_state);
        }
        egui::ComboBox::from_label("spacing").selected_text(format!("{:?}", settings.spacing).to_lowercase()).show_ui(
            ui,
            |ui| {
                for s in [Spacing::Chord, Spacing::Uniform, Spacing::Centripetal] {
                    ui.selectable_value(&mut settings.spacing, s, format!("{s:?}").to_lowercase());
                }
            },
        );
        if settings != before {
            self.edit(Edit::SetSettings(settings));
        }
        for r in &responses {
            self.gesture_end(r, ui_state);
        }
    }

    fn display_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Display");
        let before = self.display.clone();
        let d = &mut self.display;
        ui.horizontal(|ui| {
            ui.radio_value(&mut d.mode, DisplayMode::Shaded, "shaded");
            ui.radio_value(&mut d.mode, DisplayMode::Zebra, "zebra");
            ui.radio_value(&mut d.mode, DisplayMode::Curvature, "curvature");
        });
        match d.mode {
            DisplayMode::Shaded => {}
            DisplayMode::Zebra => {
                ui.add(egui::Slider::new(&mut d.stripes, 2.0..=40.0).text("stripes"));
                ui.add(egui::Slider::new(&mut d.stripe_angle, -90.0..=90.0).text("angle °"));
                ui.add(egui::Slider::new(&mut d.stripe_width, 0.1..=0.9).text("black share"));
            }
            DisplayMode::Curvature => {
                egui::ComboBox::from_label("quantity").selected_text(d.quantity.display_name()).show_ui(ui, |ui| {
                    for q in CurvatureQuantity::ALL {
                        ui.selectable_value(&mut d.quantity, q, q.display_name());
                    }
                });
                let mut automatic = d.fixed_range.is_none();
                if ui.checkbox(&mut automatic, "automatic range (2–98 %)").changed() {
                    d.fixed_range = if automatic { None } else { Some(self_range(&self.surface)) };
                }
                if let Some((min, max)) = &mut d.fixed_range {
                    ui.horizontal(|ui| {
                        let name = ui.label("min");
                        ui.add(egui::DragValue::new(min).speed(0.001)).labelled_by(name.id);
                        let name = ui.label("max");
                        ui.add(egui::DragValue::new(max).speed(0.001)).labelled_by(name.id);
                    });
                    if *max <= *min {
                        *max = *min + 1e-9_f64.max(min.abs() * 1e-6);
                    }
                }
            }
        }
        ui.separator();
        ui.checkbox(&mut d.show_cage, "cage");
        ui.checkbox(&mut d.show_wire, "refined wireframe");
        ui.checkbox(&mut d.show_curves, "curves with curvature combs");
        if self.display != before {
            self.invalidate_values();
        }
    }

    fn viewport(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        ui_state.viewport_px = Some([
            (rect.min.x * ppp).round().max(0.0) as u32,
            (rect.min.y * ppp).round().max(0.0) as u32,
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ]);
        // Interaction works in points; the viewport rectangle in the same units.
        let view = ViewportRect {
            min: glam::Vec2::new(rect.min.x, rect.min.y),
            size: glam::Vec2::new(rect.width(), rect.height()),
        };
        let (shift, scroll, pointer) =
            ui.ctx().input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y, i.pointer.hover_pos()));
        let mouse = pointer.map(|p| glam::Vec2::new(p.x, p.y));
        let cage = self.document.doc().cage.clone();

        // Hover.
        if ui_state.drag.is_none() {
            let hovered = response.hovered().then_some(mouse).flatten();
            self.selection.hovered_vertex =
                hovered.and_then(|m| interaction::pick_vertex(&self.camera, &view, cage.positions(), m, 8.0));
            self.selection.hovered_edge = match (hovered, self.selection.hovered_vertex) {
                (Some(m), None) => interaction::pick_edge(&self.camera, &view, &cage, m, 5.0),
                _ => None,
            };
        }

        // Navigation.
        if response.hovered() && scroll != 0.0 {
            self.camera.zoom(interaction::zoom_factor(scroll / 50.0));
        }
        for button in [PointerButton::Secondary, PointerButton::Middle] {
            if response.dragged_by(button) {
                let delta = response.drag_delta();
                if shift {
                    self.camera.pan(delta.x, delta.y, rect.height());
                } else {
                    let (da, de) = interaction::orbit_from_drag(glam::Vec2::new(delta.x, delta.y));
                    self.camera.orbit(da, de);
                }
            }
        }

        // Selection and dragging with the primary button.
        if response.drag_started_by(PointerButton::Primary) {
            let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
            if let Some(origin) = origin {
                match interaction::pick_vertex(&self.camera, &view, cage.positions(), origin, 8.0) {
                    Some(v) => {
                        if !self.selection.vertices.contains(&v) {
                            self.selection.click_vertex(v, shift);
                        }
                        let start: Vec<(VertexId, DVec3)> = self
                            .selected_vertices_with_edge_ends()
                            .into_iter()
                            .map(|v| (v, cage.position(v)))
                            .collect();
                        self.document.begin_gesture();
                        ui_state.drag = Some(VertexDrag { start, mouse_start: origin, axis: None });
                    }
                    None => ui_state.box_select = Some((origin, origin)),
                }
            }
        }
        if response.dragged_by(PointerButton::Primary)
            && let Some(m) = mouse
        {
            if let Some(drag) = &ui_state.drag {
                let moved =
                    interaction::drag_positions(&self.camera, &view, &drag.start, drag.mouse_start, m, drag.axis);
                self.edit(Edit::MoveVertices(moved));
            } else if let Some((_, end)) = &mut ui_state.box_select {
                *end = m;
            }
        }
        if response.drag_stopped_by(PointerButton::Primary) {
            if ui_state.drag.take().is_some() {
                self.document.end_gesture();
            }
            if let Some((a, b)) = ui_state.box_select.take() {
                if !shift {
                    self.selection.clear();
                }
                for v in interaction::box_select(&self.camera, &view, cage.positions(), a, b) {
                    if !self.selection.vertices.contains(&v) {
                        self.selection.vertices.push(v);
                    }
                }
            }
        }
        if response.clicked_by(PointerButton::Primary) {
            match (self.selection.hovered_vertex, self.selection.hovered_edge) {
                (Some(v), _) => self.selection.click_vertex(v, shift),
                (None, Some(e)) => self.selection.click_edge(e, shift),
                (None, None) if !shift => self.selection.clear(),
                _ => {}
            }
        }

        // What is drawn in the viewport by egui itself: the box and the drag axis.
        let painter = ui.painter_at(rect);
        if let Some((a, b)) = ui_state.box_select {
            let r = egui::Rect::from_two_pos(egui::pos2(a.x, a.y), egui::pos2(b.x, b.y));
            painter.rect_stroke(
                r,
                0.0,
                egui::Stroke::new(1.0, egui::Color32::from_rgb(255, 170, 60)),
                egui::StrokeKind::Inside,
            );
        }
        if let Some(drag) = &ui_state.drag {
            let text = match drag.axis {
                Some(axis) => format!("moving along {axis:?} (X, Y, Z to change, Esc to cancel)"),
                None => "moving in the view plane (X, Y or Z locks an axis, Esc cancels)".to_string(),
            };
            painter.text(
                rect.left_top() + egui::vec2(8.0, 8.0),
                egui::Align2::LEFT_TOP,
                text,
                egui::FontId::proportional(14.0),
                egui::Color32::WHITE,
            );
        }
        if self.busy() {
            ui.ctx().request_repaint();
        }
    }
}

fn self_range(surface: &Option<super::state::SurfaceView>) -> (f64, f64) {
    surface.as_ref().and_then(|s| s.values.as_ref()).map_or((-1.0, 1.0), |(_, a, b)| (*a, *b))
}

/// True when a system file dialog can be shown (an XDG desktop portal on the session bus).
pub fn native_dialogs_available() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some() && std::env::var_os("TAUT_NO_NATIVE_DIALOGS").is_none()
}
