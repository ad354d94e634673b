//! The 3D viewport's mouse: hover, select, box select, drag cage points, orbit, pan and zoom, as
//! Blender and Rhino users expect. Left click selects (Shift adds), left drag on a cage vertex
//! moves the selection in the view plane (X, Y or Z while dragging locks an axis, Esc cancels),
//! left drag elsewhere box-selects (Shift, held when the box begins, adds); right or middle drag
//! orbits, with Shift pans; the wheel zooms.
//!
//! The camera lives in display coordinates ([`taut_render::DisplayFrame`]): the cage is taken
//! into them for picking, and a drag's result is taken back to model coordinates, so any finite
//! cage can be picked and dragged.

use super::document::Edit;
use super::interaction::{self, ViewportRect};
use super::select_modes::SelectMode;
use super::state::EditorState;
use super::ui::{BoxSelect, UiState, VertexDrag};

use super::legend::{draw_legend, legend_strip};
use egui::{PointerButton, Sense};
use taut_core::{DVec3, PolyMesh, VertexId};

impl EditorState {
    pub(super) fn viewport(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        let [px, py, pw, ph] = [
            (rect.min.x * ppp).round().max(0.0) as u32,
            (rect.min.y * ppp).round().max(0.0) as u32,
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ];
        ui_state.viewport_px = Some([px, py, pw, ph]);
        // A legend takes a strip at the right, drawn here with the UI's font; the model is
        // framed in the rest.
        let margin = match self.curve_mesh_legend().or_else(|| self.legend()) {
            Some(legend) => {
                let strip = legend_strip(rect);
                draw_legend(ui, strip, &legend);
                strip.width() / rect.width().max(1.0)
            }
            None => 0.0,
        };
        self.viewport_shape = (rect.width() / rect.height().max(1.0), margin);
        self.keep_new_document_framed();
        // Interaction works in points; the viewport rectangle in the same units.
        let view = ViewportRect {
            min: glam::Vec2::new(rect.min.x, rect.min.y),
            size: glam::Vec2::new(rect.width(), rect.height()),
        };
        let (shift, pointer) = ui.ctx().input(|i| (i.modifiers.shift, i.pointer.hover_pos()));
        let mouse = pointer.map(|p| glam::Vec2::new(p.x, p.y));
        if mouse.is_some() {
            ui_state.pointer = mouse;
        }
        if ui_state.transform.is_some() {
            self.transform_viewport(ui, &response, &view, mouse, ui_state);
            return;
        }
        let cage = self.display_cage();
        if ui_state.crease_drag.is_some() {
            // Shift+E: the mouse sets the crease; a click sets it, a right click cancels.
            if let Some(m) = mouse {
                self.move_crease_drag(m.x, ui_state);
            }
            if response.clicked_by(PointerButton::Primary) {
                self.finish_crease_drag(ui_state, true);
            } else if response.clicked_by(PointerButton::Secondary) {
                self.finish_crease_drag(ui_state, false);
            }
            if let Some(cd) = &ui_state.crease_drag {
                let value = if cd.value == f64::INFINITY { "sharp".to_string() } else { format!("{:.2}", cd.value) };
                ui.painter_at(rect).text(
                    rect.left_top() + egui::vec2(8.0, 8.0),
                    egui::Align2::LEFT_TOP,
                    format!(
                        "{} s = {value}: move the mouse, click or Enter to set, Esc cancels",
                        if cd.vertices.is_empty() { "crease" } else { "corner" }
                    ),
                    egui::FontId::proportional(14.0),
                    egui::Color32::WHITE,
                );
            }
            return;
        }

        // Hover.
        if ui_state.drag.is_none() {
            let hovered = response.hovered().then_some(mouse).flatten();
            self.hover_in_mode(&view, &cage, hovered);
        }

        // Navigation, as in every viewport.
        super::navigation::navigate(&mut self.camera, ui, &response, rect.height());

        if ui_state.loop_cut.is_some() {
            self.loop_cut_viewport(ui, &response, &view, mouse, ui_state);
            return;
        }
        if ui_state.inset_drag.is_some() {
            self.inset_viewport(ui, &response, &view, mouse, ui_state);
            return;
        }
        if self.curve_mesh_viewport(ui, &response, &view, mouse, ui_state) {
            if self.busy() {
                ui.ctx().request_repaint();
            }
            return;
        }

        if self.gizmo_viewport(ui, &response, &view, &cage, mouse, ui_state) {
            return;
        }

        // Selection and dragging with the primary button.
        if response.drag_started_by(PointerButton::Primary) {
            let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
            if let Some(origin) = origin {
                match self.drag_handle(&view, &cage, origin, shift) {
                    Some(()) => {
                        let model = &self.document.doc().cage;
                        let start: Vec<(VertexId, DVec3)> = self
                            .selected_vertices_with_edge_ends()
                            .into_iter()
                            .map(|v| (v, model.position(v)))
                            .collect();
                        self.document.begin_gesture();
                        ui_state.drag = Some(VertexDrag { start, mouse_start: origin, axis: None });
                    }
                    None => {
                        self.say_missed_pick(&view, &cage, origin);
                        ui_state.box_select = Some(BoxSelect { from: origin, to: origin, add: shift });
                    }
                }
            }
        }
        if response.dragged_by(PointerButton::Primary)
            && let Some(m) = mouse
        {
            if let Some(drag) = &ui_state.drag {
                let frame = self.display_frame;
                let start: Vec<(VertexId, DVec3)> =
                    drag.start.iter().map(|&(v, p)| (v, frame.to_display_f64(p))).collect();
                let moved = interaction::drag_positions(&self.camera, &view, &start, drag.mouse_start, m, drag.axis);
                self.edit(Edit::MoveVertices(moved.into_iter().map(|(v, p)| (v, frame.to_model(p))).collect()));
            } else if let Some(band) = &mut ui_state.box_select {
                band.to = m;
            }
        }
        if response.drag_stopped_by(PointerButton::Primary) {
            if ui_state.drag.take().is_some() {
                self.document.end_gesture();
            }
            if let Some(band) = ui_state.box_select.take() {
                if !band.add {
                    self.selection.clear();
                }
                let boxed = self.box_cage(&view, &cage, band.from, band.to);
                self.box_select_in_mode(boxed);
            }
        }
        if response.clicked_by(PointerButton::Primary)
            && let Some(m) = mouse
            && !ui.ctx().input(|i| i.modifiers.alt)
        {
            let s = &self.selection;
            let missed = match s.mode {
                SelectMode::Vertex => s.hovered_vertex.is_none() && s.hovered_edge.is_none(),
                SelectMode::Edge => s.hovered_edge.is_none(),
                SelectMode::Face => s.hovered_face.is_none(),
            };
            if missed {
                self.say_missed_pick(&view, &cage, m);
            }
        }
        if response.clicked_by(PointerButton::Primary)
            && !self.click_in_mode(ui.ctx().input(|i| i.modifiers), &view, mouse)
        {
            match (self.selection.hovered_vertex, self.selection.hovered_edge) {
                (Some(v), _) => self.selection.click_vertex(v, shift),
                (None, Some(e)) => self.selection.click_edge(e, shift),
                (None, None) if !shift => self.selection.clear(),
                _ => {}
            }
        }

        // What is drawn in the viewport by egui itself: the box and the drag axis.
        let painter = ui.painter_at(rect);
        if let Some(band) = ui_state.box_select {
            let r = egui::Rect::from_two_pos(egui::pos2(band.from.x, band.from.y), egui::pos2(band.to.x, band.to.y));
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
        self.draw_gizmo(&painter, &view, ui_state);
        if self.busy() {
            ui.ctx().request_repaint();
        }
    }

    /// The cage in display coordinates, for picking.
    pub(super) fn display_cage(&self) -> PolyMesh {
        let mut cage = self.document.doc().cage.clone();
        let frame = self.display_frame;
        for p in cage.positions_mut() {
            *p = frame.to_display_f64(*p);
        }
        cage
    }
}
