//! The editor's panels: the cage panel (coordinates, fixed flags, tension), the smoothing
//! settings, the status bar and the message strip (the Display panel is `display_panel.rs`). Every control says what it does in a
//! tooltip; a control over a multi-selection shows mixed values as mixed and sets all of them.

use crate::editor::document::Edit;
use crate::editor::select_modes::SelectMode;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;
use taut_core::nusd::Spacing;
use taut_core::surface::SchemeKind;
use taut_render::overlay::TENSION_SATURATION;

/// The crease slider's end: beyond four levels a crease looks sharp at any level a designer
/// uses; larger values can be typed, and "infinitely sharp" is a checkbox.
const CREASE_SLIDER_MAX: f64 = 4.0;

fn sharpness_text(s: f64) -> String {
    if s == f64::INFINITY { "sharp".into() } else { format!("{s:.2}") }
}

/// Width of the coordinate and number fields of the cage panel, in points.
const FIELD_WIDTH: f32 = 150.0;

/// The values of one property over the selection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Mixed<T> {
    None,
    All(T),
    Range(T, T),
}

/// Collects `values` into one value or a mixed range.
pub(crate) fn mixed<T: PartialOrd + Copy>(values: impl IntoIterator<Item = T>) -> Mixed<T> {
    let mut out = Mixed::None;
    for v in values {
        out = match out {
            Mixed::None => Mixed::All(v),
            Mixed::All(a) if a == v => Mixed::All(a),
            Mixed::All(a) => Mixed::Range(if v < a { v } else { a }, if v < a { a } else { v }),
            Mixed::Range(lo, hi) => Mixed::Range(if v < lo { v } else { lo }, if v > hi { v } else { hi }),
        };
    }
    out
}

impl EditorState {
    /// "2 vertices, 1 edge", with the faces too when any are selected.
    fn selection_summary(&self) -> String {
        let count = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        let s = &self.view.selection;
        let mut text =
            format!("{}, {}", count(s.vertices.len(), "vertex", "vertices"), count(s.edges.len(), "edge", "edges"));
        if !s.faces.is_empty() {
            text += &format!(", {}", count(s.faces.len(), "face", "faces"));
        }
        text
    }

    pub(crate) fn status_bar(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.horizontal(|ui| {
            // The running tool's numbers first, where the eye goes (Blender shows them in its
            // header): a move's ΔX ΔY ΔZ, an angle, a factor, a measurement.
            if let Some(numbers) = ui_state.tool.readout(self) {
                ui.label(
                    egui::RichText::new(numbers).strong().monospace().color(egui::Color32::from_rgb(255, 220, 60)),
                );
                ui.separator();
            }
            ui.label(self.document.title());
            ui.separator();
            match (&self.progress, &self.surface_error) {
                (_, Some(_)) => {
                    ui.colored_label(egui::Color32::LIGHT_RED, "cannot make the surface: see the message");
                }
                (Some(p), None) => {
                    ui.label(&p.summary).on_hover_text(
                        "The scheme and its work: for NUSD the level being solved, the iterations since the last \
                         edit, the last step and whether the surface reached its fixed point; for subdivision the \
                         level and the faces of the limit surface",
                    );
                }
                (None, None) => {
                    ui.label("starting");
                }
            }
            ui.separator();
            let ms = self.frame_time.as_secs_f64() * 1e3;
            ui.label(format!("frame {ms:.1} ms ({:.0} fps)", if ms > 0.0 { 1e3 / ms } else { 0.0 }));
            ui.separator();
            ui.label(format!("{} mode", self.view.selection.mode.name()))
                .on_hover_text("What a click in the viewport selects: vertices, edges or faces (Tab changes it)");
            if self.view.display.xray {
                ui.label("X-ray").on_hover_text("The back of the cage is drawn and picked too (Alt+Z turns it off)");
            }
            ui.separator();
            ui.label(format!("{} selected", self.selection_summary()));
            ui.separator();
            if ui
                .small_button(format!("messages ({})", self.messages.len()))
                .on_hover_text("Every message of this session")
                .clicked()
            {
                ui_state.show_messages = true;
            }
        });
    }

    /// The newest message, wrapped to the window's width, with its dismiss and history buttons.
    /// The message over the bottom of the viewport, `viewport` in points: drawn on top rather
    /// than in a panel of its own, so the viewport keeps its size (and the model stays put)
    /// whether a message shows or not. It leaves the legend's strip at the right free.
    pub(crate) fn notice_overlay(&mut self, ctx: &egui::Context, viewport: egui::Rect, ui_state: &mut UiState) {
        if self.notice.is_none() {
            return;
        }
        let mut viewport = viewport;
        viewport.set_right(viewport.right() - self.viewport_shape.1 * viewport.width());
        egui::Area::new(egui::Id::unique("notice"))
            .order(egui::Order::Foreground)
            .pivot(egui::Align2::LEFT_BOTTOM)
            .fixed_pos(viewport.left_bottom())
            .show(ctx, |ui| {
                egui::Frame::side_top_panel(ui.style()).show(ui, |ui| {
                    let width = viewport.width() - 2.0 * ui.style().spacing.window_margin.leftf();
                    ui.set_width(width.max(1.0));
                    self.notice_strip(ui, ui_state);
                });
            });
    }

    pub(crate) fn notice_strip(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let Some(notice) = self.notice.clone() else { return };
        ui.horizontal(|ui| {
            if ui.small_button("×").on_hover_text("Dismiss the message").clicked() {
                self.notice = None;
            }
            if ui.small_button("history").on_hover_text("Every message of this session").clicked() {
                ui_state.show_messages = true;
            }
            let color = if notice.is_error { egui::Color32::LIGHT_RED } else { ui.visuals().text_color() };
            ui.add(egui::Label::new(egui::RichText::new(&notice.text).color(color)).wrap());
        });
    }

    pub(crate) fn cage_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Cage");
        if self.document.doc().scheme == SchemeKind::CurveMesh {
            self.view.selection.clear();
            ui.add(
                egui::Label::new(
                    "The curve mesh is edited in the viewport and the Surface panel; the cage is shown for \
                     reference. To change the cage, choose another scheme: the curve-mesh edits follow.",
                )
                .wrap(),
            );
            return;
        }
        self.mirror_panel(ui);
        let vertices = self.selected_vertices_with_edge_ends();
        if self.view.selection.is_empty() {
            let what = match self.view.selection.mode {
                SelectMode::Vertex => "Vertex mode: click a cage vertex (or an edge) to select it",
                SelectMode::Edge => "Edge mode: click a cage edge to select it",
                SelectMode::Face => "Face mode: click a cage face to select it",
            };
            ui.add(
                egui::Label::new(format!(
                    "{what}; Shift adds, a drag on empty space box-selects. Tab changes the mode."
                ))
                .wrap(),
            );
            return;
        }
        let doc = self.document.doc();
        let diagonal = doc.cage.bounding_diagonal();
        let moving = crate::editor::select_modes::selected_vertex_set(&doc.cage, &self.view.selection);
        if !moving.is_empty() {
            // One vertex: its coordinates. More (or an edge, a face): their median (mean), and a
            // typed or dragged value moves them all by the same offset, as Blender's N panel.
            let median = moving.iter().map(|&v| doc.cage.position(v)).sum::<taut_core::DVec3>() / moving.len() as f64;
            let unit = doc.units;
            match moving.as_slice() {
                [v] => ui.label(format!("vertex {} ({})", v.0, unit.symbol())),
                _ => ui.label(format!("median of {} vertices ({})", moving.len(), unit.symbol())),
            };
            let mut p = median;
            let mut changed = false;
            let mut responses = Vec::new();
            egui::Grid::new("coordinates").num_columns(2).show(ui, |ui| {
                for (label, value) in [("X", &mut p.x), ("Y", &mut p.y), ("Z", &mut p.z)] {
                    let name = ui.label(label);
                    let response = ui
                        .add_sized(
                            [FIELD_WIDTH, 20.0],
                            egui::DragValue::new(value).speed(0.002 * diagonal).max_decimals(6),
                        )
                        .labelled_by(name.id)
                        .on_hover_text(format!("The {label} coordinate ({}): drag or type a value", unit.name()));
                    changed |= response.changed();
                    responses.push(response);
                    ui.end_row();
                }
            });
            for r in &responses {
                self.gesture_start(r, ui_state);
            }
            if changed {
                let moves = match moving.as_slice() {
                    // A typed value lands exactly.
                    [v] => vec![(*v, p)],
                    _ => {
                        let cage = &self.document.doc().cage;
                        moving.iter().map(|&v| (v, cage.position(v) + (p - median))).collect()
                    }
                };
                self.emit(Edit::MoveVertices(moves));
            }
            for r in &responses {
                self.gesture_end(r, ui_state);
            }
            if moving.len() > 1 {
                ui.label(self.selection_summary());
            }
        } else {
            ui.label(self.selection_summary());
        }
        ui.separator();
        if self.document.doc().scheme.is_subdivision() {
            self.crease_controls(ui, ui_state);
            ui.separator();
            self.corner_controls(ui, ui_state);
        } else {
            self.nusd_controls(ui, ui_state, &vertices);
        }
    }

    /// Fixed flags and tension: what a NUSD designer sets on the selection.
    fn nusd_controls(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState, vertices: &[taut_core::VertexId]) {
        let fixed_state = mixed(vertices.iter().map(|v| self.document.doc().fixed[v.index()]));
        let mut fixed = fixed_state == Mixed::All(true);
        let indeterminate = matches!(fixed_state, Mixed::Range(..));
        let response = ui
            .add(egui::Checkbox::new(&mut fixed, "fixed (the surface passes through)").indeterminate(indeterminate))
            .on_hover_text(
                "Fixed vertices are interpolated: the surface passes through them. Moving ones are \
                 approximated. A mixed box means some selected vertices are fixed and some are not; \
                 a click sets them all.",
            );
        if response.changed() {
            self.emit(Edit::SetFixed(vertices.to_vec(), fixed));
        }
        ui.separator();
        if !self.view.selection.vertices.is_empty() {
            let doc = self.document.doc();
            let values = mixed(self.view.selection.vertices.iter().map(|v| doc.vertex_tension[v.index()]));
            let vertices = self.view.selection.vertices.clone();
            self.tension_control(ui, ui_state, "vertex tension τ", values, TENSION_HELP_VERTEX, |tau| {
                Edit::SetVertexTension(vertices, tau)
            });
        }
        let doc = self.document.doc();
        if !self.view.selection.edges.is_empty() {
            let values = mixed(self.view.selection.edges.iter().map(|e| doc.edge_tension[e.index()]));
            let edges = self.view.selection.edges.clone();
            self.tension_control(ui, ui_state, "edge tension τ", values, TENSION_HELP_EDGE, |tau| {
                Edit::SetEdgeTension(edges, tau)
            });
        }
        if ui.button("Reset tension").on_hover_text("Set the tension of the selection back to 0").clicked() {
            self.emit(Edit::ResetTension {
                vertices: self.view.selection.vertices.clone(),
                edges: self.view.selection.edges.clone(),
            });
        }
    }

    /// Crease sharpness of the selected edges: what a subdivision designer sets.
    fn crease_controls(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let edges = self.crease_targets();
        if edges.is_empty() {
            ui.add(egui::Label::new("Select cage edges (or two vertices of an edge) to crease them.").wrap());
            return;
        }
        let doc = self.document.doc();
        let values = mixed(edges.iter().map(|e| doc.crease[e.index()]));
        let texts = SharpnessTexts {
            label: "crease sharpness s",
            hover: "How sharp the selected edges are: 0 smooth; s creases them for s levels and blends the \
                    fraction (as in Blender and OpenSubdiv). Shift+E and a drag sets it in the viewport.",
            sharp: ("infinitely sharp", "A crease at every level: the surface keeps a sharp edge there"),
            clear: ("Clear creases", "Make the selected edges smooth again"),
        };
        self.sharpness_controls(ui, ui_state, values, &texts, |s| Edit::SetCrease(edges.clone(), s));
    }

    /// Corner sharpness of the selected vertices (OpenSubdiv's corners, Blender's vertex crease).
    fn corner_controls(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let doc = self.document.doc();
        let vertices = crate::editor::select_modes::selected_vertex_set(&doc.cage, &self.view.selection);
        if vertices.is_empty() {
            ui.add(egui::Label::new("Select cage vertices to sharpen them into corners.").wrap());
            return;
        }
        let values = mixed(vertices.iter().map(|v| doc.corner[v.index()]));
        let texts = SharpnessTexts {
            label: "corner sharpness",
            hover: "How sharp the selected vertices are: 0 smooth; s keeps each one a corner for s levels and \
                    blends the fraction (OpenSubdiv's corners, Blender's vertex crease). Shift+V and a drag sets \
                    it in the viewport.",
            sharp: (
                "sharp corner",
                "A corner at every level: the surface passes through the vertex with a point there",
            ),
            clear: ("Clear corners", "Make the selected vertices smooth again"),
        };
        self.sharpness_controls(ui, ui_state, values, &texts, |s| Edit::SetCorner(vertices.clone(), s));
    }

    /// A sharpness slider (a drag is one undo step), an "infinitely sharp" checkbox and a clear
    /// button for the selection's sharpness `values`; `edit` sets them all to one value.
    fn sharpness_controls(
        &mut self,
        ui: &mut egui::Ui,
        ui_state: &mut UiState,
        values: Mixed<f64>,
        texts: &SharpnessTexts,
        edit: impl Fn(f64) -> Edit,
    ) {
        let (mut s, sharp) = match values {
            Mixed::None => (0.0, false),
            Mixed::All(s) => (if s.is_finite() { s } else { CREASE_SLIDER_MAX }, s == f64::INFINITY),
            Mixed::Range(lo, hi) => (if hi.is_finite() { hi } else { CREASE_SLIDER_MAX }, lo == f64::INFINITY),
        };
        let name = ui.label(texts.label);
        let response = ui
            .push_id(texts.label, |ui| {
                ui.add(
                    egui::Slider::new(&mut s, 0.0..=CREASE_SLIDER_MAX)
                        .clamping(egui::SliderClamping::Never)
                        .max_decimals(2),
                )
            })
            .inner
            .labelled_by(name.id)
            .on_hover_text(texts.hover);
        if let Mixed::Range(lo, hi) = values {
            ui.label(format!("mixed: {} to {}; a change sets them all", sharpness_text(lo), sharpness_text(hi)));
        }
        self.gesture_start(&response, ui_state);
        if response.changed() {
            self.emit(edit(s.max(0.0)));
        }
        self.gesture_end(&response, ui_state);
        let mut infinite = sharp;
        if ui.checkbox(&mut infinite, texts.sharp.0).on_hover_text(texts.sharp.1).changed() {
            self.emit(edit(if infinite { f64::INFINITY } else { 0.0 }));
        }
        if ui.button(texts.clear.0).on_hover_text(texts.clear.1).clicked() {
            self.emit(edit(0.0));
        }
    }

    /// The edges a crease applies to: the selected edges, and the edges joining two selected
    /// vertices.
    pub(crate) fn crease_targets(&self) -> Vec<taut_core::EdgeId> {
        let cage = &self.document.doc().cage;
        let mut edges = self.view.selection.edges.clone();
        for &a in &self.view.selection.vertices {
            for &b in &self.view.selection.vertices {
                if a < b
                    && let Some(h) = cage.find_halfedge(a, b)
                    && !edges.contains(&h.edge())
                {
                    edges.push(h.edge());
                }
            }
        }
        edges
    }

    /// A tension slider over the useful range 0–4 (larger values can be typed and are marked);
    /// a change applies the edit `make` builds, inside the slider's gesture.
    fn tension_control(
        &mut self,
        ui: &mut egui::Ui,
        ui_state: &mut UiState,
        label: &str,
        values: Mixed<f64>,
        help: &str,
        make: impl FnOnce(f64) -> Edit,
    ) {
        let name = ui.label(label);
        let (mut tau, largest, range) = match values {
            Mixed::None => (0.0, 0.0, None),
            Mixed::All(t) => (t, t, None),
            Mixed::Range(lo, hi) => (hi, hi, Some((lo, hi))),
        };
        // A stable id, and the notes below the slider: a note that appears or goes while the
        // slider is dragged must not move it or change its identity, or the drag is lost.
        let response = ui
            .push_id(label, |ui| {
                ui.add(
                    egui::Slider::new(&mut tau, 0.0..=TENSION_SATURATION)
                        .clamping(egui::SliderClamping::Never)
                        .max_decimals(3),
                )
            })
            .inner
            .labelled_by(name.id)
            .on_hover_text(help);
        if let Some((lo, hi)) = range {
            ui.label(format!("mixed: {lo:.2} to {hi:.2}; a change sets them all"));
        }
        if largest > TENSION_SATURATION {
            ui.colored_label(
                egui::Color32::from_rgb(255, 170, 60),
                format!("above {TENSION_SATURATION}: over-flattens (a sharp crease)"),
            );
        }
        self.gesture_start(&response, ui_state);
        if response.changed() {
            self.emit(make(tau.max(0.0)));
        }
        self.gesture_end(&response, ui_state);
    }

    /// A slider or field drag is one undo step: the gesture opens when the drag starts and
    /// closes after the edit of the frame the drag stops in.
    pub(crate) fn gesture_start(&mut self, response: &egui::Response, ui_state: &mut UiState) {
        if response.drag_started() && !ui_state.slider_active && !self.document.in_gesture() {
            ui_state.slider_active = true;
            self.document.begin_gesture();
        }
    }

    pub(crate) fn gesture_end(&mut self, response: &egui::Response, ui_state: &mut UiState) {
        if response.drag_stopped() && ui_state.slider_active {
            ui_state.slider_active = false;
            self.emit_end_gesture();
        }
    }

    /// The surface scheme and its settings.
    pub(crate) fn solver_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Surface");
        let doc = self.document.doc();
        let mut scheme = doc.scheme;
        egui::ComboBox::from_label("scheme")
            .selected_text(scheme.display_name())
            .show_ui(ui, |ui| {
                for (k, help) in [
                    (
                        SchemeKind::Nusd,
                        "Nonuniform spline diffusion: passes through the fixed cage points, with tension",
                    ),
                    (SchemeKind::CatmullClark, "Catmull–Clark subdivision, as Blender's: any polygons, with creases"),
                    (SchemeKind::Loop, "Loop subdivision: triangle cages, with creases"),
                    (
                        SchemeKind::CurveMesh,
                        "Bézier curves on the Catmull–Clark limit surface filled with G1 Gregory patches: drag \
                         curve-mesh vertices, tangent planes and control points; a move changes only nearby patches",
                    ),
                ] {
                    ui.selectable_value(&mut scheme, k, k.display_name()).on_hover_text(help);
                }
            })
            .response
            .on_hover_text("How the surface is made from the cage (undoable, saved with the document)");
        if scheme != doc.scheme {
            self.emit(Edit::SetScheme(scheme));
        }
        if self.document.doc().scheme == SchemeKind::CurveMesh {
            self.curve_mesh_panel(ui, ui_state);
        } else if self.document.doc().scheme.is_subdivision() {
            self.subdivision_settings(ui, ui_state);
        } else {
            self.nusd_settings(ui, ui_state);
        }
    }

    fn subdivision_settings(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let mut settings = self.document.doc().subdiv;
        let before = settings;
        let response = ui
            .horizontal(|ui| {
                let name = ui.label("levels");
                ui.add(egui::Slider::new(&mut settings.levels, 1..=5)).labelled_by(name.id).on_hover_text(
                    "Subdivision levels of the surface drawn: each has about four times the faces; the \
                     drawn vertices sit on the exact limit surface",
                )
            })
            .inner;
        self.gesture_start(&response, ui_state);
        if settings != before {
            self.emit(Edit::SetSubdivSettings(settings));
        }
        self.gesture_end(&response, ui_state);
    }

    fn nusd_settings(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let mut settings = self.document.doc().settings;
        let before = settings;
        let mut responses = Vec::new();
        ui.horizontal(|ui| {
            let name = ui.label("levels");
            responses.push(
                ui.add(egui::Slider::new(&mut settings.levels, 0..=5))
                    .labelled_by(name.id)
                    .on_hover_text("How many times the cage is refined: each level has about four times the faces"),
            );
        });
        ui.horizontal(|ui| {
            let name = ui.label("λ");
            responses.push(
                ui.add(egui::Slider::new(&mut settings.lambda, 0.05..=0.95)).labelled_by(name.id).on_hover_text(
                    "The diffusion step of each iteration (0.6 by default): larger converges faster until it \
                     oscillates; the solver halves it by itself if a solve diverges",
                ),
            );
        });
        ui.horizontal(|ui| {
            let name = ui.label("tolerance");
            responses.push(
                ui.add(egui::Slider::new(&mut settings.tol, 1e-6..=1e-2).logarithmic(true))
                    .labelled_by(name.id)
                    .on_hover_text(
                        "The solve stops when its estimated distance to the fixed point is below this fraction \
                         of the model's size",
                    ),
            );
        });
        for r in &responses {
            self.gesture_start(r, ui_state);
        }
        egui::ComboBox::from_label("spacing")
            .selected_text(format!("{:?}", settings.spacing).to_lowercase())
            .show_ui(ui, |ui| {
                for (s, help) in [
                    (Spacing::Chord, "Parameter intervals from edge lengths: no bulges where edges differ in length"),
                    (Spacing::Uniform, "Every edge counts the same: bulges next to short edges"),
                    (Spacing::Centripetal, "The square root of the edge lengths: between the two"),
                ] {
                    ui.selectable_value(&mut settings.spacing, s, format!("{s:?}").to_lowercase()).on_hover_text(help);
                }
            })
            .response
            .on_hover_text("How the parameter interval of each edge is measured");
        if settings != before {
            self.emit(Edit::SetSettings(settings));
        }
        for r in &responses {
            self.gesture_end(r, ui_state);
        }
    }
}

const TENSION_HELP_VERTEX: &str = "Tension at the selected vertices: more tautens the surface around them. \
    Useful values are 0 to 4; larger ones can be typed, but over-flatten.";
const TENSION_HELP_EDGE: &str = "Tension across the selected edges: more tautens the surface across them \
    without changing the curve along them. Useful values are 0 to 4; larger ones can be typed, but over-flatten.";

/// What the sharpness controls of one kind (edge creases, vertex corners) say.
struct SharpnessTexts {
    label: &'static str,
    hover: &'static str,
    /// The "infinitely sharp" checkbox: its label and hover text.
    sharp: (&'static str, &'static str),
    /// The clear button: its label and hover text.
    clear: (&'static str, &'static str),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixed_values_are_told_apart() {
        assert_eq!(mixed(Vec::<f64>::new()), Mixed::None);
        assert_eq!(mixed([2.0, 2.0]), Mixed::All(2.0));
        assert_eq!(mixed([2.0, 8.0, 0.5]), Mixed::Range(0.5, 8.0));
        assert_eq!(mixed([true, false]), Mixed::Range(false, true));
    }
}
