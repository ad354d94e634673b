//! Extrude then move, as Blender's E: the extrusion is made at once (at the Mesh menu's offset)
//! and a grab starts on what it lifted, locked along the region's mean normal (the area-weighted
//! sum of the lifted faces' normals; for extruded boundary edges, the mean displacement the
//! extrusion gave their ends). The mouse or a typed distance sets how much further it goes; a
//! click or Enter confirms; Esc or a right click leaves the extrusion where the extrusion put it.
//! Extrusion and move are one gesture, so one undo step. X, Y, Z or a plane lock replace the
//! normal lock as in any grab.
//!
//! I (inset) is not followed by a mouse-driven thickness yet: it insets by the menu's fraction.

use crate::editor::mesh_ops::MeshOp;
use crate::editor::state::EditorState;
use crate::editor::transform::TransformKind;
use crate::editor::ui::UiState;
use taut_core::DVec3;

impl EditorState {
    /// E: extrude the selection, then move what it lifted along the mean normal until a click.
    pub(crate) fn extrude_and_move(&mut self, ui_state: &mut UiState) {
        let before = self.selected_vertices_with_edge_ends();
        let cage = &self.document.doc().cage;
        let old_mean = mean(before.iter().map(|&v| cage.position(v)));
        self.document.begin_gesture();
        let revision = self.document.revision();
        self.mesh_op(MeshOp::Extrude);
        if self.document.revision() == revision {
            // Refused (the message is shown): nothing to move.
            self.document.end_gesture();
            return;
        }
        let cage = &self.document.doc().cage;
        let area: DVec3 = self.selection.faces.iter().map(|&f| cage.face_area_vector(f)).sum();
        let lifted = mean(self.selected_vertices_with_edge_ends().into_iter().map(|v| cage.position(v)));
        let normal = [area, lifted - old_mean]
            .into_iter()
            .map(|d| d.normalize_or_zero())
            .find(|d| d.is_finite() && *d != DVec3::ZERO);
        match self.new_transform(TransformKind::Grab, ui_state.pointer) {
            Some(mut t) => {
                t.direction = normal;
                ui_state.transform = Some(t);
            }
            None => self.document.end_gesture(),
        }
    }
}

fn mean(points: impl Iterator<Item = DVec3>) -> DVec3 {
    let (sum, n) = points.fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p, n + 1));
    sum / n.max(1) as f64
}
