//! Shift+E and Shift+V as in Blender: the crease sharpness of the selected edges, or the corner
//! sharpness of the selected vertices, follows the mouse (100 points of travel a level) until a
//! click or Enter sets it, one undo step; Esc or a right click puts every value back.

use crate::editor::document::Edit;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{CageStamp, End, Flow, Pointer, Tool, enter_or_escape};
use glam::Vec2;

/// Shift+E: points of mouse travel per unit of sharpness.
const CREASE_POINTS_PER_LEVEL: f64 = 100.0;
/// Shift+E: the largest sharpness the mouse sets (larger ones are typed or "infinitely sharp").
const CREASE_DRAG_MAX: f64 = 10.0;

/// A crease being set with the mouse (Shift+E, as in Blender), or a corner (Shift+V: the
/// sharpness of vertices, when `vertices` is not empty).
#[derive(Clone, Debug)]
pub struct CreaseDrag {
    pub edges: Vec<taut_core::EdgeId>,
    pub vertices: Vec<taut_core::VertexId>,
    /// The sharpness of each edge or vertex when it began (Esc puts them back).
    start: Vec<f64>,
    /// Where the mouse was when it began (x, in points); `None` until the pointer is seen.
    mouse_start: Option<f32>,
    /// The sharpness now.
    pub value: f64,
    /// The cage's topology when it began: another one (a file opened meanwhile) ends it.
    topology: CageStamp,
}

/// Shift+E: starts setting the crease of the selection with the mouse.
pub(crate) fn start_crease(editor: &mut EditorState, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    if !editor.document.doc().scheme.is_subdivision() {
        editor.notify("creases belong to the subdivision schemes: choose Catmull–Clark or Loop first", true);
        return None;
    }
    let edges = editor.crease_targets();
    if edges.is_empty() {
        editor.notify("select the cage edges to crease first (or two vertices of an edge)", true);
        return None;
    }
    let crease = &editor.document.doc().crease;
    let start: Vec<f64> = edges.iter().map(|e| crease[e.index()]).collect();
    Some(CreaseDrag::begin(editor, edges, Vec::new(), start, mouse))
}

/// Shift+V: starts setting the corner sharpness of the selected vertices with the mouse.
pub(crate) fn start_corner(editor: &mut EditorState, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    if !editor.document.doc().scheme.is_subdivision() {
        editor.notify("corners belong to the subdivision schemes: choose Catmull–Clark or Loop first", true);
        return None;
    }
    let vertices =
        crate::editor::select_modes::selected_vertex_set(&editor.document.doc().cage, &editor.view.selection);
    if vertices.is_empty() {
        editor.notify("select the cage vertices to sharpen first", true);
        return None;
    }
    let corner = &editor.document.doc().corner;
    let start: Vec<f64> = vertices.iter().map(|v| corner[v.index()]).collect();
    Some(CreaseDrag::begin(editor, Vec::new(), vertices, start, mouse))
}

impl CreaseDrag {
    fn begin(
        editor: &mut EditorState,
        edges: Vec<taut_core::EdgeId>,
        vertices: Vec<taut_core::VertexId>,
        start: Vec<f64>,
        mouse: Option<Vec2>,
    ) -> Box<dyn Tool> {
        let value = start.iter().copied().filter(|s| s.is_finite()).fold(0.0, f64::max);
        editor.document.begin_gesture();
        let topology = CageStamp::now(editor);
        Box::new(CreaseDrag { edges, vertices, start, mouse_start: mouse.map(|m| m.x), value, topology })
    }

    /// The edit setting the sharpness of what the drag holds.
    fn edit(&self, value: f64) -> Edit {
        if self.vertices.is_empty() {
            Edit::SetCrease(self.edges.clone(), value)
        } else {
            Edit::SetCorner(self.vertices.clone(), value)
        }
    }
}

impl Tool for CreaseDrag {
    /// Enter sets and Esc cancels; nothing else runs.
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        enter_or_escape(ctx)
    }

    /// The mouse at `x`: 100 points to the right add one to the sharpness it began with; a click
    /// sets it, a right click cancels.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if let Some(x) = pointer.mouse.map(|m| m.x) {
            let start = *self.mouse_start.get_or_insert(x);
            let base = self.start.iter().copied().filter(|s| s.is_finite()).fold(0.0, f64::max);
            let value = (base + f64::from(x - start) / CREASE_POINTS_PER_LEVEL).clamp(0.0, CREASE_DRAG_MAX);
            let value = (value * 20.0).round() / 20.0;
            if value != self.value {
                self.value = value;
                editor.emit(self.edit(value));
            }
        }
        pointer.clicks()
    }

    fn readout(&self, _editor: &EditorState) -> Option<String> {
        let what = if self.vertices.is_empty() { "crease" } else { "corner" };
        Some(if self.value == f64::INFINITY { format!("{what} sharp") } else { format!("{what} {:.2}", self.value) })
    }

    fn status(&self, _editor: &EditorState) -> String {
        let value = if self.value == f64::INFINITY { "sharp".to_string() } else { format!("{:.2}", self.value) };
        let what = if self.vertices.is_empty() { "crease" } else { "corner" };
        format!("{what} s = {value}: move the mouse, click or Enter to set, Esc cancels")
    }

    /// Keeps the sharpness, or puts every edge and vertex back as it was.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            for (e, s) in self.edges.iter().zip(&self.start) {
                editor.emit(Edit::SetCrease(vec![*e], *s));
            }
            for (v, s) in self.vertices.iter().zip(&self.start) {
                editor.emit(Edit::SetCorner(vec![*v], *s));
            }
        }
        editor.emit_end_gesture();
    }

    fn is_stale(&self, editor: &EditorState) -> bool {
        self.topology.is_stale(editor)
    }
}
