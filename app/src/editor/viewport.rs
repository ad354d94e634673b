//! The 3D viewport's mouse: hover, select, box select, drag cage points, orbit, pan and zoom, as
//! Blender and Rhino users expect. Left click selects (Shift adds), left drag on a cage vertex
//! moves the selection in the view plane (X, Y or Z while dragging locks an axis, Esc cancels),
//! left drag elsewhere box-selects (Shift, held when the box begins, adds); right or middle drag
//! orbits, with Shift pans; the wheel zooms.
//!
//! The camera lives in display coordinates ([`taut_render::DisplayFrame`]): the cage is taken
//! into them for picking, and a drag's result is taken back to model coordinates, so any finite
//! cage can be picked and dragged.

use super::interaction::ViewportRect;
use super::select_modes::SelectMode;
use super::state::EditorState;
use super::tools::tool::Pointer;
use super::tools::triad;
use super::tools::vertex_drag::VertexDrag;
use super::transform::Transform;
use super::ui::UiState;

use super::legend::{draw_legend, legend_strip};
use egui::{PointerButton, Sense};
use taut_core::PolyMesh;

/// Lays out a workspace's viewport over the space left: its response, its rectangle in points
/// (the units interaction works in; the renderer is told it in physical pixels), and the
/// pointer over it (kept in `ui_state` for the tools a key starts).
pub(crate) fn allocate(
    ui: &mut egui::Ui,
    ui_state: &mut UiState,
) -> (egui::Response, ViewportRect, Option<glam::Vec2>) {
    let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    let ppp = ui.ctx().pixels_per_point();
    ui_state.viewport_px = Some([
        (rect.min.x * ppp).round().max(0.0) as u32,
        (rect.min.y * ppp).round().max(0.0) as u32,
        (rect.width() * ppp).round().max(1.0) as u32,
        (rect.height() * ppp).round().max(1.0) as u32,
    ]);
    let view = ViewportRect {
        min: glam::Vec2::new(rect.min.x, rect.min.y),
        size: glam::Vec2::new(rect.width(), rect.height()),
    };
    let mouse = ui.ctx().input(|i| i.pointer.hover_pos()).map(|p| glam::Vec2::new(p.x, p.y));
    if mouse.is_some() {
        ui_state.pointer = mouse;
    }
    (response, view, mouse)
}

impl EditorState {
    pub(super) fn viewport(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let (response, view, mouse) = allocate(ui, ui_state);
        let rect = response.rect;
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
        let pointer = Pointer { ui, response: &response, view, mouse };
        let cage = self.display_cage();
        if !ui_state.tool.navigates() {
            // G, R, S and the crease drags follow the bare mouse: nothing else has it.
            ui_state.tool.pointer(self, &pointer);
            self.gizmo_overlay(ui, rect, &view, ui_state);
            return;
        }

        // Hover, unless vertices are being dragged.
        if ui_state.tool.get::<VertexDrag>().is_none() {
            let hovered = response.hovered().then_some(mouse).flatten();
            self.hover_in_mode(&view, &cage, hovered);
        }

        // Navigation, as in every viewport.
        super::navigation::navigate(&mut self.view.camera, ui, &response, rect.height());

        if ui_state.tool.pointer(self, &pointer) {
            self.gizmo_overlay(ui, rect, &view, ui_state);
        } else if self.curve_mesh_viewport(&pointer, &mut ui_state.tool)
            || self.clip_handle_viewport(&pointer, &mut ui_state.tool)
        {
            // The curve mesh's drags, or the clipping plane's handle, took the press.
        } else if self.gizmo_viewport(ui, &response, &view, &cage, mouse, &mut ui_state.tool) {
            if ui_state.tool.is_running() {
                ui_state.tool.pointer(self, &pointer);
            }
        } else {
            self.select_and_drag(&pointer, &cage, ui_state);
            self.gizmo_overlay(ui, rect, &view, ui_state);
        }
        if !ui_state.tool.is_running() {
            let hot = mouse.is_some_and(|m| self.over_clip_handle(&view, m));
            self.draw_clip_handle(&ui.painter_at(rect), &view, hot);
        }
        let over_triad = mouse.is_some_and(|m| triad::contains(&view, m));
        triad::draw(
            &ui.painter_at(rect),
            &self.view.camera,
            &view,
            over_triad || ui_state.tool.get::<triad::TriadOrbit>().is_some(),
            mouse,
        );
        if self.busy() {
            ui.ctx().request_repaint();
        }
    }

    /// The gizmo over the viewport, when the running tool (if any) shows it.
    fn gizmo_overlay(&mut self, ui: &egui::Ui, rect: egui::Rect, view: &ViewportRect, ui_state: &UiState) {
        if ui_state.tool.shows_gizmo() {
            self.draw_gizmo(&ui.painter_at(rect), view, ui_state.tool.get::<Transform>().is_some());
        }
    }

    /// The primary button with no tool running: a click selects (Shift adds), a press on a cage
    /// vertex starts dragging the selection, a press elsewhere a box.
    fn select_and_drag(&mut self, pointer: &Pointer, cage: &PolyMesh, ui_state: &mut UiState) {
        let (ui, response, view, mouse) = (pointer.ui, pointer.response, pointer.view, pointer.mouse);
        let shift = ui.ctx().input(|i| i.modifiers.shift);
        // The triad in the corner: a click looks along an axis, a drag orbits.
        let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y));
        if response.drag_started_by(PointerButton::Primary) && origin.is_some_and(|o| triad::contains(&view, o)) {
            ui_state.tool.start(self, triad::start_orbit(self));
            ui_state.tool.pointer(self, pointer);
            return;
        }

        if response.clicked_by(PointerButton::Primary)
            && let Some(m) = mouse
            && triad::over_projection_button(&view, m)
        {
            self.emit_action(crate::editor::shortcuts::Action::ToggleOrthographic);
            return;
        }
        if response.clicked_by(PointerButton::Primary)
            && let Some(m) = mouse
            && triad::contains(&view, m)
        {
            if let Some(standard) = triad::pick(&self.view.camera, &view, m) {
                self.view.camera.set_view(standard);
            }
            return;
        }
        // A press starts a drag of the selection from a cage vertex, or a box elsewhere.
        if response.drag_started_by(PointerButton::Primary) {
            let origin = ui.ctx().input(|i| i.pointer.press_origin()).map(|p| glam::Vec2::new(p.x, p.y)).or(mouse);
            if let Some(origin) = origin {
                let tool = match self.drag_handle(&view, cage, origin, shift) {
                    Some(()) => super::tools::vertex_drag::start(self, origin),
                    None => {
                        self.say_missed_pick(&view, cage, origin);
                        super::tools::box_select::start(origin, shift)
                    }
                };
                ui_state.tool.start(self, tool);
                ui_state.tool.pointer(self, pointer);
            }
        }
        if response.clicked_by(PointerButton::Primary)
            && let Some(m) = mouse
            && !ui.ctx().input(|i| i.modifiers.alt)
        {
            let s = &self.view.selection;
            let missed = match s.mode {
                SelectMode::Vertex => s.hovered_vertex.is_none() && s.hovered_edge.is_none(),
                SelectMode::Edge => s.hovered_edge.is_none(),
                SelectMode::Face => s.hovered_face.is_none(),
            };
            if missed {
                self.say_missed_pick(&view, cage, m);
            }
        }
        if response.clicked_by(PointerButton::Primary)
            && !self.click_in_mode(ui.ctx().input(|i| i.modifiers), &view, mouse)
        {
            match (self.view.selection.hovered_vertex, self.view.selection.hovered_edge) {
                (Some(v), _) => self.view.selection.click_vertex(v, shift),
                (None, Some(e)) => self.view.selection.click_edge(e, shift),
                (None, None) if !shift => self.view.selection.clear(),
                _ => {}
            }
        }
    }

    /// The cage in display coordinates, for picking.
    pub(super) fn display_cage(&self) -> PolyMesh {
        let mut cage = self.document.doc().cage.clone();
        let frame = self.view.display_frame;
        for p in cage.positions_mut() {
            *p = frame.to_display_f64(*p);
        }
        cage
    }
}
