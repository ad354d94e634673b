//! Shift+E and Shift+V as in Blender: the crease sharpness of the selected edges, or the corner
//! sharpness of the selected vertices, follows the mouse (100 points of travel a level) until a
//! click or Enter sets it, one undo step; Esc or a right click puts every value back. The
//! viewport and the keys call in while it runs (`viewport.rs`, `ui.rs`).

use crate::editor::document::Edit;
use crate::editor::state::EditorState;
use crate::editor::ui::{CreaseDrag, UiState};

/// Shift+E: points of mouse travel per unit of sharpness.
const CREASE_POINTS_PER_LEVEL: f64 = 100.0;
/// Shift+E: the largest sharpness the mouse sets (larger ones are typed or "infinitely sharp").
const CREASE_DRAG_MAX: f64 = 10.0;

impl EditorState {
    /// Starts setting the crease of the selection with the mouse (Shift+E).
    pub(crate) fn start_crease_drag(&mut self, mouse_x: Option<f32>, ui_state: &mut UiState) {
        if !self.document.doc().scheme.is_subdivision() {
            self.notify("creases belong to the subdivision schemes: choose Catmull–Clark or Loop first", true);
            return;
        }
        let edges = self.crease_targets();
        if edges.is_empty() {
            self.notify("select the cage edges to crease first (or two vertices of an edge)", true);
            return;
        }
        let crease = &self.document.doc().crease;
        let start: Vec<f64> = edges.iter().map(|e| crease[e.index()]).collect();
        let value = start.iter().copied().filter(|s| s.is_finite()).fold(0.0, f64::max);
        self.document.begin_gesture();
        ui_state.crease_drag = Some(CreaseDrag { edges, vertices: Vec::new(), start, mouse_start: mouse_x, value });
    }

    /// Starts setting the corner sharpness of the selected vertices with the mouse (Shift+V).
    pub(crate) fn start_corner_drag(&mut self, mouse_x: Option<f32>, ui_state: &mut UiState) {
        if !self.document.doc().scheme.is_subdivision() {
            self.notify("corners belong to the subdivision schemes: choose Catmull–Clark or Loop first", true);
            return;
        }
        let vertices = crate::editor::select_modes::selected_vertex_set(&self.document.doc().cage, &self.selection);
        if vertices.is_empty() {
            self.notify("select the cage vertices to sharpen first", true);
            return;
        }
        let corner = &self.document.doc().corner;
        let start: Vec<f64> = vertices.iter().map(|v| corner[v.index()]).collect();
        let value = start.iter().copied().filter(|s| s.is_finite()).fold(0.0, f64::max);
        self.document.begin_gesture();
        ui_state.crease_drag = Some(CreaseDrag { edges: Vec::new(), vertices, start, mouse_start: mouse_x, value });
    }

    /// The edit setting the sharpness of what a crease drag holds.
    fn crease_drag_edit(cd: &CreaseDrag, value: f64) -> Edit {
        if cd.vertices.is_empty() {
            Edit::SetCrease(cd.edges.clone(), value)
        } else {
            Edit::SetCorner(cd.vertices.clone(), value)
        }
    }

    /// The mouse at `x`: 100 points to the right add one to the sharpness it began with.
    pub(crate) fn move_crease_drag(&mut self, x: f32, ui_state: &mut UiState) {
        let Some(cd) = &mut ui_state.crease_drag else { return };
        let start = *cd.mouse_start.get_or_insert(x);
        let base = cd.start.iter().copied().filter(|s| s.is_finite()).fold(0.0, f64::max);
        let value = (base + f64::from(x - start) / CREASE_POINTS_PER_LEVEL).clamp(0.0, CREASE_DRAG_MAX);
        let value = (value * 20.0).round() / 20.0;
        if value != cd.value {
            cd.value = value;
            let edit = Self::crease_drag_edit(cd, value);
            self.edit(edit);
        }
    }

    /// Ends Shift+E: keeps the crease (`keep`) or puts every edge back as it was.
    pub(crate) fn finish_crease_drag(&mut self, ui_state: &mut UiState, keep: bool) {
        let Some(cd) = ui_state.crease_drag.take() else { return };
        if !keep {
            for (e, s) in cd.edges.iter().zip(&cd.start) {
                self.edit(Edit::SetCrease(vec![*e], *s));
            }
            for (v, s) in cd.vertices.iter().zip(&cd.start) {
                self.edit(Edit::SetCorner(vec![*v], *s));
            }
        }
        self.document.end_gesture();
    }
}
