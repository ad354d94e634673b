//! A left drag from a cage vertex moves the selection in the view plane; X, Y or Z while
//! dragging locks an axis (again: unlocks), Esc puts every vertex back. The whole drag is one
//! undo step. The viewport starts it when a press lands on a vertex.

use crate::editor::document::Edit;
use crate::editor::interaction::{self, Axis};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{CageStamp, End, Flow, Pointer, Tool, end_vertex_move};
use glam::Vec2;
use taut_core::{DVec3, VertexId};

/// A drag of cage vertices in progress.
#[derive(Clone, Debug)]
pub struct VertexDrag {
    /// The dragged vertices where the drag began, in model coordinates.
    start: Vec<(VertexId, DVec3)>,
    mouse_start: Vec2,
    pub axis: Option<Axis>,
    /// The cage's topology when it began: another one (a file opened meanwhile) ends it.
    topology: CageStamp,
}

/// Starts dragging the selection (with the ends of selected edges) from `origin` (one gesture).
pub(crate) fn start(editor: &mut EditorState, origin: Vec2) -> Box<dyn Tool> {
    let model = &editor.document.doc().cage;
    let start = editor.selected_vertices_with_edge_ends().into_iter().map(|v| (v, model.position(v))).collect();
    let topology = CageStamp::now(editor);
    editor.document.begin_gesture();
    Box::new(VertexDrag { start, mouse_start: origin, axis: None, topology })
}

impl Tool for VertexDrag {
    /// X, Y and Z lock an axis and Esc cancels; nothing else runs.
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        if crate::editor::navigation::drag_keys(ctx, &mut self.axis) { Flow::Cancel } else { Flow::Continue }
    }

    /// The vertices follow the mouse until the button is let go.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged()
            && let Some(m) = pointer.mouse
        {
            let frame = editor.view.display_frame;
            let start: Vec<(VertexId, DVec3)> = self.start.iter().map(|&(v, p)| (v, frame.to_display_f64(p))).collect();
            let moved =
                interaction::drag_positions(&editor.view.camera, &pointer.view, &start, self.mouse_start, m, self.axis);
            editor.emit(Edit::MoveVertices(moved.into_iter().map(|(v, p)| (v, frame.to_model(p))).collect()));
        }
        pointer.release()
    }

    /// ΔX ΔY ΔZ and the distance the dragged vertices moved (their mean).
    fn readout(&self, editor: &EditorState) -> Option<String> {
        let cage = &editor.document.doc().cage;
        let n = self.start.len().max(1) as f64;
        let d: DVec3 = self.start.iter().map(|&(v, p)| cage.position(v) - p).sum::<DVec3>() / n;
        let f = |x: f64| format!("{:.4}", if x == 0.0 { 0.0 } else { x });
        Some(format!("ΔX {}  ΔY {}  ΔZ {}  distance {}", f(d.x), f(d.y), f(d.z), f(d.length())))
    }

    fn status(&self, _editor: &EditorState) -> String {
        match self.axis {
            Some(axis) => format!("moving along {axis:?} (X, Y, Z to change, Esc to cancel)"),
            None => "moving in the view plane (X, Y or Z locks an axis, Esc cancels)".to_string(),
        }
    }

    /// Keeps the move, or puts every vertex back.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        end_vertex_move(editor, self.start, end);
    }

    fn is_stale(&self, editor: &EditorState) -> bool {
        self.topology.is_stale(editor)
    }

    fn navigates(&self) -> bool {
        true
    }

    fn shows_gizmo(&self) -> bool {
        true
    }
}
