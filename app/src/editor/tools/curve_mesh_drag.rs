//! A drag in the curve-mesh scheme: a press on a curve-mesh vertex moves the selected vertices
//! in the view plane, one on a leg's inner point moves that point, one on the tip of the
//! selected vertex's normal turns its tangent plane (the normal follows the cursor). X, Y or Z
//! locks an axis (again: unlocks), Esc puts the edits back as they were. The whole drag is one
//! undo step. The curve-mesh viewport ([`crate::editor::curve_mesh_edit`]) starts it.

use crate::editor::curve_mesh_edit::Handle;
use crate::editor::document::Edit;
use crate::editor::interaction::{self, Axis};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool};
use taut_core::gregory::CurveMeshEdits;
use taut_core::surface::SchemeKind;
use taut_core::{DVec3, VertexId};

/// A drag in the curve-mesh scheme.
#[derive(Clone, Debug)]
pub struct CurveMeshDrag {
    handle: Handle,
    /// What moves, where the drag began (model coordinates): the selected vertices, or the one
    /// handle point (keyed by its vertex).
    start: Vec<(VertexId, DVec3)>,
    /// The edit state before the drag (Esc puts it back).
    before: CurveMeshEdits,
    mouse_start: glam::Vec2,
    pub axis: Option<Axis>,
}

/// Begins a drag of `handle` from `origin` (one undo step until it ends); `None` when it holds
/// nothing to move.
pub(crate) fn start(
    editor: &mut EditorState,
    handle: Handle,
    origin: glam::Vec2,
    shift: bool,
) -> Option<Box<dyn Tool>> {
    if let Handle::Vertex(v) = handle
        && !editor.curve_mesh.selected.contains(&v)
    {
        editor.click_curve_mesh_vertex(v, shift);
    }
    let length = editor.handle_length();
    let cm = editor.curve_mesh_surface()?.curve_mesh();
    let start: Vec<(VertexId, DVec3)> = match handle {
        Handle::Vertex(_) => editor
            .curve_mesh
            .selected
            .iter()
            .filter(|w| w.index() < cm.vertex_count())
            .map(|&w| (w, cm.vertex_position(w)))
            .collect(),
        Handle::Inner { curve, end } => cm.inner_point(curve, end).map(|q| (end, q)).into_iter().collect(),
        Handle::Normal(v) => vec![(v, cm.vertex_position(v) + cm.vertex_normal(v) * length)],
    };
    if start.is_empty() {
        return None;
    }
    let before = editor.document.doc().curve_mesh.clone();
    editor.document.begin_gesture();
    Some(Box::new(CurveMeshDrag { handle, start, before, mouse_start: origin, axis: None }))
}

impl CurveMeshDrag {
    /// The drag with the mouse at `mouse`: one edit from where the drag began.
    fn follow(&self, editor: &mut EditorState, view: &interaction::ViewportRect, mouse: glam::Vec2) {
        let frame = editor.view.display_frame;
        let start: Vec<(VertexId, DVec3)> = self.start.iter().map(|&(v, p)| (v, frame.to_display_f64(p))).collect();
        let moved: Vec<(VertexId, DVec3)> =
            interaction::drag_positions(&editor.view.camera, view, &start, self.mouse_start, mouse, self.axis)
                .into_iter()
                .map(|(v, p)| (v, frame.to_model(p)))
                .collect();
        match self.handle {
            Handle::Vertex(_) => editor.emit(Edit::MoveCurveMeshVertices(moved)),
            Handle::Inner { curve, end } => {
                editor.emit(Edit::MoveCurveMeshInnerPoint { curve, end, position: moved[0].1 })
            }
            Handle::Normal(v) => {
                let Some(s) = editor.curve_mesh_surface() else { return };
                let p = s.curve_mesh().vertex_position(v);
                let start_normal = (self.start[0].1 - p).normalize_or_zero();
                let n = (moved[0].1 - p).normalize_or_zero();
                // A normal turned (almost) upside down would fold the patches: wait for a better one.
                if n == DVec3::ZERO || n.dot(start_normal) < -0.99 {
                    return;
                }
                // From the plane the drag began with, so the drag does not depend on its path.
                editor.emit(Edit::SetCurveMeshEdits(self.before.clone()));
                editor.emit(Edit::SetCurveMeshNormal(v, n));
            }
        }
    }
}

impl Tool for CurveMeshDrag {
    /// X, Y and Z lock an axis and Esc cancels; nothing else runs.
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        if crate::editor::navigation::drag_keys(ctx, &mut self.axis) { Flow::Cancel } else { Flow::Continue }
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        editor.curve_mesh_upkeep();
        if pointer.dragged()
            && let Some(m) = pointer.mouse
        {
            self.follow(editor, &pointer.view, m);
        }
        pointer.release()
    }

    fn status(&self, _editor: &EditorState) -> String {
        match (self.handle, self.axis) {
            (Handle::Normal(_), _) => "turning the tangent plane: the normal follows the cursor (Esc cancels)".into(),
            (_, Some(axis)) => format!("moving along {axis:?} (X, Y, Z to change, Esc to cancel)"),
            (_, None) => "moving in the view plane (X, Y or Z locks an axis, Esc cancels)".into(),
        }
    }

    /// Keeps the drag, or puts the curve-mesh edits back as they were.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            editor.emit(Edit::SetCurveMeshEdits(self.before));
        }
        editor.emit_end_gesture();
    }

    /// The document left the curve-mesh scheme (undo, a file opened) under the drag.
    fn is_stale(&self, editor: &EditorState) -> bool {
        editor.document.doc().scheme != SchemeKind::CurveMesh
    }

    fn navigates(&self) -> bool {
        true
    }
}
