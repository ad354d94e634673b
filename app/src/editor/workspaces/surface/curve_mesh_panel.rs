//! The Surface panel's curve-mesh controls: typed coordinates and tangent-plane angles of the
//! selected vertex, the overlays, and "Rebuild from cage" with its question.

use crate::editor::document::Edit;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;
use taut_core::{DVec3, VertexId};

impl EditorState {
    /// The Surface panel's curve-mesh controls: typed coordinates and tangent-plane angles of the
    /// selected vertex, the overlays, and "Rebuild from cage" with its question.
    pub(crate) fn curve_mesh_panel(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        let Some(s) = self.curve_mesh_surface() else {
            ui.label("The curve mesh is not built yet.");
            return;
        };
        let cm = s.curve_mesh();
        let patches = cm.patch_count();
        let selected: Option<(VertexId, DVec3, DVec3)> = match self.curve_mesh.selected[..] {
            [v] if v.index() < cm.vertex_count() => Some((v, cm.vertex_position(v), cm.vertex_normal(v))),
            _ => None,
        };
        let many = self.curve_mesh.selected.len();
        let edits = &self.document.doc().curve_mesh;
        let (edited_vertices, edited_curves) = (edits.vertices.len(), edits.curves.len());
        let diagonal = self.document.doc().cage.bounding_diagonal();
        ui.label(format!("{patches} Gregory patches; {edited_vertices} vertices and {edited_curves} curves edited"));
        match selected {
            Some((v, p, n)) => self.curve_mesh_vertex_fields(ui, ui_state, v, p, n, diagonal),
            None if many > 1 => {
                ui.label(format!("{many} curve-mesh vertices selected: drag one to move them all"));
            }
            None => {
                ui.add(egui::Label::new("Click a curve-mesh vertex to select it; Shift adds.").wrap());
            }
        }
        ui.checkbox(&mut self.curve_mesh.show_continuity, "Continuity").on_hover_text(
            "Colours every shared curve by the jump in normal curvature across it (G2) and draws it thick red \
             where the normals differ (not G1), with a legend; measured again while you drag",
        );
        self.refresh_curve_mesh_continuity();
        if let Some(m) = self.measured_continuity() {
            ui.label(format!(
                "largest G1 angle {:.1e} rad, largest G2 jump {:.3e} over {} curves",
                m.report.max_normal_angle,
                m.report.max_curvature_jump,
                m.curves.len()
            ));
        }
        ui.checkbox(&mut self.curve_mesh.highlight_last_edit, "Highlight the last edit's patches")
            .on_hover_text("Outlines the patches the last change rebuilt: a vertex move changes only those around it");
        let has_edits = edited_vertices + edited_curves > 0;
        if ui
            .add_enabled(has_edits, egui::Button::new("Rebuild from cage…"))
            .on_hover_text("Builds the curve mesh from the cage again, discarding every curve-mesh edit (asks first)")
            .clicked()
        {
            ui_state.curve_mesh.confirm_rebuild = true;
        }
        if ui_state.curve_mesh.confirm_rebuild {
            ui.add(
                egui::Label::new(format!(
                    "Discard the edits of {edited_vertices} vertices and {edited_curves} curves and rebuild from the \
                     cage? Undo brings them back."
                ))
                .wrap(),
            );
            let (mut discard, mut keep) = (false, false);
            ui.horizontal(|ui| {
                discard = ui.button("Discard edits").clicked();
                keep = ui.button("Keep edits").clicked();
            });
            if discard {
                self.emit(Edit::RebuildCurveMesh);
            }
            if discard || keep || !has_edits {
                ui_state.curve_mesh.confirm_rebuild = false;
            }
        }
    }

    /// Typed position and normal angles of the one selected curve-mesh vertex.
    fn curve_mesh_vertex_fields(
        &mut self,
        ui: &mut egui::Ui,
        ui_state: &mut UiState,
        v: VertexId,
        p: DVec3,
        n: DVec3,
        diagonal: f64,
    ) {
        ui.label(format!("curve-mesh vertex {}", v.0));
        let mut q = p;
        let mut tilt = n.z.clamp(-1.0, 1.0).acos().to_degrees();
        let mut azimuth = n.y.atan2(n.x).to_degrees();
        let (mut moved, mut turned) = (false, false);
        let mut responses = Vec::new();
        egui::Grid::new("curve mesh vertex").num_columns(2).show(ui, |ui| {
            for (label, value) in [("X", &mut q.x), ("Y", &mut q.y), ("Z", &mut q.z)] {
                let name = ui.label(label);
                let r = ui
                    .add(egui::DragValue::new(value).speed(0.002 * diagonal).max_decimals(6))
                    .labelled_by(name.id)
                    .on_hover_text(format!("The curve-mesh vertex's {label} coordinate: drag or type a value"));
                moved |= r.changed();
                responses.push(r);
                ui.end_row();
            }
            for (label, value, range, help) in [
                ("tilt (deg)", &mut tilt, 0.0..=180.0, "The normal's angle from +Z, in degrees"),
                ("azimuth (deg)", &mut azimuth, -180.0..=180.0, "The normal's direction about Z from +X, in degrees"),
            ] {
                let name = ui.label(label);
                let r = ui
                    .add(egui::DragValue::new(value).speed(0.5).range(range).max_decimals(4))
                    .labelled_by(name.id)
                    .on_hover_text(help);
                turned |= r.changed();
                responses.push(r);
                ui.end_row();
            }
        });
        for r in &responses {
            self.gesture_start(r, ui_state);
        }
        if moved {
            self.emit(Edit::MoveCurveMeshVertices(vec![(v, q)]));
        }
        if turned {
            let (t, a) = (tilt.to_radians(), azimuth.to_radians());
            self.emit(Edit::SetCurveMeshNormal(v, DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos())));
        }
        for r in &responses {
            self.gesture_end(r, ui_state);
        }
    }
}
