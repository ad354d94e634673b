//! Extrude then move, as Blender's E: the extrusion is made at once (at the Mesh menu's offset)
//! and a grab starts on what it lifted, locked along the region's mean normal (the area-weighted
//! sum of the lifted faces' normals; for extruded boundary edges, the mean displacement the
//! extrusion gave their ends). The mouse or a typed distance sets how much further it goes; a
//! click or Enter confirms; Esc or a right click leaves the extrusion where the extrusion put it.
//! Extrusion and move are one gesture, so one undo step. X, Y, Z or a plane lock replace the
//! normal lock as in any grab.

use crate::editor::mesh_ops::MeshOp;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::Tool;
use crate::editor::transform::{Transform, TransformKind};
use glam::Vec2;
use taut_core::DVec3;

/// E: extrude the selection, then move what it lifted along the mean normal until a click.
pub(crate) fn start(editor: &mut EditorState, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    editor.extrude_and_move(mouse).map(|t| Box::new(t) as Box<dyn Tool>)
}

impl EditorState {
    /// Extrudes the selection and starts the grab of what it lifted (one gesture).
    fn extrude_and_move(&mut self, mouse: Option<Vec2>) -> Option<Transform> {
        let before = self.selected_vertices_with_edge_ends();
        let cage = &self.document.doc().cage;
        let old_mean = mean(before.iter().map(|&v| cage.position(v)));
        self.document.begin_gesture();
        let revision = self.document.revision();
        self.mesh_op(MeshOp::Extrude);
        if self.document.revision() == revision {
            // Refused (the message is shown): nothing to move.
            self.document.end_gesture();
            return None;
        }
        let cage = &self.document.doc().cage;
        let area: DVec3 = self.view.selection.faces.iter().map(|&f| cage.face_area_vector(f)).sum();
        let lifted = mean(self.selected_vertices_with_edge_ends().into_iter().map(|v| cage.position(v)));
        let normal = [area, lifted - old_mean]
            .into_iter()
            .map(|d| d.normalize_or_zero())
            .find(|d| d.is_finite() && *d != DVec3::ZERO);
        match self.new_transform(TransformKind::Grab, mouse) {
            Some(mut t) => {
                t.direction = normal;
                Some(t)
            }
            None => {
                self.document.end_gesture();
                None
            }
        }
    }
}

fn mean(points: impl Iterator<Item = DVec3>) -> DVec3 {
    let (sum, n) = points.fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p, n + 1));
    sum / n.max(1) as f64
}
