//! The Curves workspace's panels: the switch between the workspaces at the top of the window,
//! the curve list and tools at the left (import, draw, segments, Coons patches), the filter,
//! comb controls and plots at the right, drawn with `egui_plot`: the curvature against arc
//! length, and the logarithmic curvature graph with its fitted line and α per piece, both of the
//! curve as shown (they follow a running filter).

use crate::editor::curves::{CurveTool, DrawPlane};
use crate::editor::state::EditorState;
use crate::editor::ui::{PathPurpose, UiState};
use egui_plot::{Legend, Line, Plot, Points};
use taut_core::curve::Workspace;

/// Height of each plot, in points, where the panel has room.
const PLOT_HEIGHT: f32 = 170.0;
/// The least height of a plot: below it the panel scrolls instead.
const MIN_PLOT_HEIGHT: f32 = 80.0;

impl EditorState {
    /// The Surface / Curves switch in the menu bar.
    pub(crate) fn workspace_switch(&mut self, ui: &mut egui::Ui) {
        ui.separator();
        let mut ws = self.curves.workspace;
        ui.selectable_value(&mut ws, Workspace::Surface, "Surface workspace")
            .on_hover_text("The cage and its smooth surface");
        ui.selectable_value(&mut ws, Workspace::Curves, "Curves workspace")
            .on_hover_text("Curves faired toward log-aesthetic curves, segments and Coons patches");
        if ws != self.curves.workspace {
            self.set_workspace(ws);
        }
    }

    /// The whole frame of the Curves workspace below the menu bar.
    pub(crate) fn curves_workspace_ui(&mut self, ui_root: &mut egui::Ui, ui_state: &mut UiState) {
        self.step_curves(self.curves.filter_budget);
        egui::Panel::bottom("status").show(ui_root, |ui| self.curves_status_bar(ui, ui_state));
        egui::Panel::left("curves").resizable(false).exact_size(270.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.curve_list_panel(ui, ui_state));
        });
        egui::Panel::right("curve tools").resizable(false).exact_size(360.0).show(ui_root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                self.filter_panel(ui);
                ui.separator();
                self.plots_panel(ui);
            });
        });
        let viewport =
            egui::CentralPanel::no_frame().show(ui_root, |ui| self.curves_viewport(ui, ui_state)).response.rect;
        self.notice_overlay(&ui_root.ctx().clone(), viewport, ui_state);
        if self.curves_busy() {
            ui_root.ctx().request_repaint();
        }
    }

    fn curves_status_bar(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.horizontal(|ui| {
            ui.label(self.document.title());
            ui.separator();
            let set = self.curve_set();
            ui.label(format!("{} curves, {} Coons patches", set.curves.len(), set.patches.len()));
            ui.separator();
            let ms = self.frame_time.as_secs_f64() * 1e3;
            ui.label(format!("frame {ms:.1} ms"));
            ui.separator();
            if ui.small_button(format!("messages ({})", self.messages.len())).clicked() {
                ui_state.show_messages = true;
            }
        });
    }

    fn curve_list_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.heading("Curves");
        ui.horizontal(|ui| {
            if ui.button("Import…").on_hover_text("Read a point sequence from a .json or .csv file").clicked() {
                self.ask_path(PathPurpose::ImportCurve, ui_state);
            }
            let can_delete = self.curves.selected.is_some();
            if ui
                .add_enabled(can_delete, egui::Button::new("Delete"))
                .on_hover_text("Delete the selected curve (Delete)")
                .clicked()
            {
                self.delete_selected_curve();
            }
        });
        ui.horizontal(|ui| {
            ui.label("Mouse:");
            ui.selectable_value(&mut self.curves.tool, CurveTool::Select, "Select")
                .on_hover_text("Click a curve to select it; drag a segment's control point to move it");
            ui.selectable_value(&mut self.curves.tool, CurveTool::Draw, "Draw")
                .on_hover_text("Drag with the mouse or a pen to draw a curve on the plane");
        });
        egui::ComboBox::from_label("drawing plane").selected_text(self.curves.plane.label()).show_ui(ui, |ui| {
            for plane in DrawPlane::ALL {
                ui.selectable_value(&mut self.curves.plane, plane, plane.label());
            }
        });
        ui.separator();
        let names: Vec<(String, usize, bool)> =
            self.curve_set().curves.iter().map(|c| (c.name.clone(), c.points.len(), c.segment.is_some())).collect();
        if names.is_empty() {
            ui.add(
                egui::Label::new("No curves yet: import a point file, or choose Draw and drag in the viewport.").wrap(),
            );
        }
        for (i, (name, count, is_segment)) in names.into_iter().enumerate() {
            ui.horizontal(|ui| {
                let mut picked = self.curves.picked.contains(&i);
                if ui
                    .checkbox(&mut picked, "")
                    .on_hover_text("Pick for a Coons patch (four curves; or Shift+click the curve in the viewport)")
                    .changed()
                {
                    self.toggle_pick(i);
                }
                let kind = if is_segment { "segment" } else { "points" };
                let text = format!("{name}  ({count} {kind})");
                if ui.selectable_label(self.curves.selected == Some(i), text).clicked() {
                    self.select_curve(Some(i));
                }
            });
        }
        ui.separator();
        self.segment_controls(ui, ui_state);
        ui.separator();
        ui.label("Coons patch");
        ui.horizontal(|ui| {
            ui.label("samples a side");
            ui.add(egui::DragValue::new(&mut self.curves.patch_samples).range(2..=128));
        });
        let label = format!("Build Coons patch ({} of 4 picked)", self.curves.picked.len());
        if ui
            .button(label)
            .on_hover_text("A bilinearly blended Coons patch bounded by the four picked curves")
            .clicked()
        {
            self.build_coons();
        }
        let patches: Vec<bool> = self.curve_set().patches.iter().map(|p| p.sources.is_some()).collect();
        for (k, follows) in patches.into_iter().enumerate() {
            let text =
                format!("Coons patch {}  ({})", k + 1, if follows { "follows its curves" } else { "fixed shape" });
            if ui
                .selectable_label(self.curves.selected_patch == Some(k), text)
                .on_hover_text("Click to select; Delete deletes it")
                .clicked()
            {
                self.select_patch(Some(k));
            }
        }
        if self.curves.selected_patch.is_some()
            && ui.button("Delete patch").on_hover_text("Delete the selected Coons patch (Delete)").clicked()
        {
            self.delete_selected_patch();
        }
    }

    /// The selected segment's α slider, or the button making a new segment.
    fn segment_controls(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        ui.label("Log-aesthetic segment");
        let selected = self.curves.selected.and_then(|i| self.curve_set().curves[i].segment.map(|s| (i, s)));
        match selected {
            Some((i, mut controls)) => {
                let response = ui
                    .add(egui::Slider::new(&mut controls.alpha, -3.0..=3.0).text("segment α"))
                    .on_hover_text("Slope of the segment's curvature graph (−1 clothoid, 1 log spiral, 2 involute)");
                self.gesture_start(&response, ui_state);
                if response.changed() {
                    self.set_segment(i, controls);
                }
                self.gesture_end(&response, ui_state);
                if self.curve_set().curves[i].points.is_empty() {
                    ui.colored_label(
                        egui::Color32::LIGHT_RED,
                        "no such segment: no log-aesthetic curve with this α has these control points; \
                         change α or move the control points",
                    );
                } else {
                    ui.label("Drag its three control points in the viewport (Select).");
                }
            }
            None => {
                ui.add(egui::Slider::new(&mut self.curves.segment_alpha, -3.0..=3.0).text("new segment α"));
                if ui
                    .button("New segment")
                    .on_hover_text("A segment on the drawing plane, to shape by its controls")
                    .clicked()
                {
                    self.add_segment();
                }
            }
        }
    }

    fn filter_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Log-aesthetic filter");
        let f = &mut self.curves.filter;
        ui.checkbox(&mut f.estimate, "estimate α per piece").on_hover_text(
            "Fit a B-spline, split it at inflections and curvature extrema, take each piece's LCG slope",
        );
        ui.add_enabled(!f.estimate, egui::Slider::new(&mut f.alpha, -3.0..=3.0).text("α"));
        ui.add(egui::Slider::new(&mut f.window, 1..=10).text("window m"))
            .on_hover_text("Each point is moved by the curve through 2m + 1 points around it");
        ui.add_enabled(!f.space, egui::Checkbox::new(&mut f.keep_shape, "keep the shape")).on_hover_text(
            "Take the noise out and keep the curve where its points were (off: the paper's filter alone, \
             which moves a noisy curve)",
        );
        ui.checkbox(&mut f.space, "space curve (with torsion)")
            .on_hover_text("Keep the curve in 3D and make the radius of torsion follow μ^β = g s + h");
        ui.add_enabled(f.space, egui::Slider::new(&mut f.torsion_beta, -3.0..=3.0).text("torsion β"));
        ui.horizontal(|ui| {
            let running = self.curves_busy();
            if ui.add_enabled(!running, egui::Button::new("Run")).on_hover_text("Fair the selected curve").clicked() {
                self.run_filter();
            }
            if ui.add_enabled(running, egui::Button::new("Stop")).clicked() {
                self.stop_filter();
            }
            let stopped = self.curves.run.as_ref().is_some_and(|r| !r.running && !r.status().converged);
            if ui.add_enabled(stopped, egui::Button::new("Continue")).clicked() {
                self.continue_filter();
            }
        });
        if let Some(run) = &self.curves.run {
            let s = run.status();
            let state = if run.running {
                "running"
            } else if s.converged {
                "converged"
            } else {
                "stopped"
            };
            ui.label(format!(
                "{state}: {} passes, last move {:.2e} of the spacing, curvature residual {:.3}",
                s.passes, s.last_move, s.residual
            ));
            if let Some(before) = run.residual_before {
                ui.label(format!("LCG residual when the run began: {before:.3}"));
            }
        }
        ui.separator();
        ui.checkbox(&mut self.curves.show_combs, "curvature combs");
        ui.add(egui::Slider::new(&mut self.curves.comb_length, 0.01..=0.5).text("comb scale"))
            .on_hover_text("The longest tooth as a fraction of the curves' size");
        ui.add(egui::Slider::new(&mut self.curves.comb_density, 1..=20).text("comb: every n-th point"));
    }

    fn plots_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Curvature graphs");
        let Some(plots) = self.selected_plots().cloned() else {
            ui.label("Select a curve of three points or more to see its graphs.");
            return;
        };
        let graph = &plots.graph;
        let kappa: Vec<[f64; 2]> =
            graph.arc_length.iter().zip(&graph.curvature).filter_map(|(s, k)| k.map(|k| [*s, k])).collect();
        ui.label("curvature κ against arc length s");
        // Both plots share what is left of the panel below this line, with the labels between
        // them, so the LCG plot is not cut off at the panel's bottom.
        let row = ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y;
        let rows = 1 + plots.pieces.len() + usize::from(plots.estimate_error.is_some());
        let room = ui.clip_rect().bottom() - ui.cursor().top() - rows as f32 * row - 3.0 * ui.spacing().item_spacing.y;
        let plot_height = (0.5 * room).clamp(MIN_PLOT_HEIGHT, PLOT_HEIGHT);
        Plot::new("curvature plot").height(plot_height).x_axis_label("s").y_axis_label("κ").show(ui, |p| {
            p.line(Line::new("κ(s)", kappa));
        });
        let alpha_text = match graph.fit {
            Some(fit) => format!("LCG: slope α = {:.3}, residual {:.3}", fit.slope, fit.residual),
            None => "LCG: too few points for a line".into(),
        };
        ui.label(alpha_text);
        for (first, last, fit) in &plots.pieces {
            ui.label(format!("piece of points {first}–{last}: α = {:.3} (residual {:.3})", fit.slope, fit.residual));
        }
        if let Some(e) = &plots.estimate_error {
            ui.label(format!("α per piece: {e}"));
        }
        let lcg: Vec<[f64; 2]> = graph.lcg.iter().map(|p| [p.x, p.y]).collect();
        let x_range =
            lcg.iter().map(|p| p[0]).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
        Plot::new("lcg plot")
            .height(plot_height)
            .x_axis_label("log ρ")
            .y_axis_label("log |ρ ds/dρ|")
            .legend(Legend::default())
            .show(ui, |p| {
                p.points(Points::new("LCG", lcg).radius(1.5));
                if let Some(fit) = graph.fit
                    && x_range.0 < x_range.1
                {
                    let line = vec![[x_range.0, fit.at(x_range.0)], [x_range.1, fit.at(x_range.1)]];
                    p.line(Line::new(format!("fit α = {:.2}", fit.slope), line).width(2.0));
                }
                for (k, (first, last, fit)) in plots.pieces.iter().enumerate() {
                    let xs: Vec<f64> =
                        graph.lcg.iter().filter(|q| q.index >= *first && q.index <= *last).map(|q| q.x).collect();
                    let (lo, hi) =
                        xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(*x), hi.max(*x)));
                    if lo < hi {
                        let line = vec![[lo, fit.at(lo)], [hi, fit.at(hi)]];
                        p.line(Line::new(format!("piece {} α = {:.2}", k + 1, fit.slope), line).width(1.5));
                    }
                }
            });
    }
}
