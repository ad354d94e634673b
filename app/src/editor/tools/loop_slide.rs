//! Loop cut with a preview and a slide, as Blender's Ctrl+R: the loop the cut would insert
//! across the ring of quads through the edge under the mouse is drawn (or why it cannot be cut
//! is said), a click cuts it at the middle of the ring's edges, and then the mouse slides it
//! along the ring (the fraction of the core's [`loop_cut`] measured along the picked edge from
//! its first vertex: where the cursor's projection falls on the edge on screen) until a click
//! or Enter; Esc or a right click cancels the whole cut. Cut and slide are one undo step.
//!
//! The slide moves only the new vertices, to where [`loop_cut`] at the new fraction puts them,
//! through `Edit::MoveVertices` (so symmetric editing sees it), so a slide lands exactly where
//! a cut at that fraction would. With the mouse away from the viewport (the Mesh menu, a test)
//! and one edge selected, Ctrl+R cuts at once and slides. Weak where Blender does more: no
//! count of several loops (wheel), no even/flipped slide.

use crate::editor::document::Edit;
use crate::editor::interaction::{self, ViewportRect};
use crate::editor::shortcuts;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{CageStamp, End, Flow, Pointer, Tool};
use egui::Key;
use glam::Vec2;
use taut_core::document::modelling::MeshEdit;
use taut_core::mesh::edit::{EdgeOrigin, VertexOrigin, loop_cut};
use taut_core::{DVec3, Document, EdgeId, VertexId};

/// The loop-cut tool's stage.
#[derive(Clone, Debug)]
pub enum LoopCutTool {
    /// Showing the loop through the edge under the mouse.
    Preview {
        edge: Option<EdgeId>,
        /// The new loop's edges, in model coordinates.
        lines: Vec<[DVec3; 2]>,
        /// Why the ring through `edge` cannot be cut.
        refusal: Option<String>,
    },
    /// Cut; the mouse slides the new loop.
    Slide {
        /// The document before the cut (Esc puts it back).
        original: Box<Document>,
        /// The picked edge, in the original cage.
        edge: EdgeId,
        /// The loop's vertices in the cut cage.
        new_vertices: Vec<VertexId>,
        fraction: f64,
        /// The cut cage's topology: another one (a file opened meanwhile) ends the slide.
        topology: CageStamp,
    },
}

/// The fraction a slide never passes (the core needs it strictly inside the edge).
const SLIDE_MARGIN: f64 = 1e-3;

/// Ctrl+R: the preview over the viewport, or with the mouse elsewhere and one edge selected,
/// the cut at once.
pub(crate) fn start(editor: &mut EditorState, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    let selected = match editor.view.selection.edges.as_slice() {
        [e] => Some(*e),
        _ => None,
    };
    let target = editor.view.selection.hovered_edge.or(selected);
    if mouse.is_none() {
        let Some(edge) = target else {
            editor.notify("point at an edge (or select one edge) to cut the ring across it", true);
            return None;
        };
        return cut_and_slide(editor, edge).map(|t| Box::new(t) as Box<dyn Tool>);
    }
    let mut tool = LoopCutTool::Preview { edge: None, lines: Vec::new(), refusal: None };
    if let Some(edge) = target {
        tool = preview(editor, edge);
    }
    Some(Box::new(tool))
}

/// The loop a cut across the ring through `edge` would insert, or why it cannot.
fn preview(editor: &EditorState, edge: EdgeId) -> LoopCutTool {
    let cage = &editor.document.doc().cage;
    let (lines, refusal) = match loop_cut(cage, edge, 0.5) {
        Ok(edited) => {
            let m = &edited.mesh;
            let lines = m
                .edges()
                .filter(|e| matches!(edited.provenance.edges[e.index()], EdgeOrigin::InFace(_)))
                .map(|e| {
                    let (a, b) = m.edge_vertices(e);
                    [m.position(a), m.position(b)]
                })
                .collect();
            (lines, None)
        }
        Err(e) => (Vec::new(), Some(e.to_string())),
    };
    LoopCutTool::Preview { edge: Some(edge), lines, refusal }
}

/// Cuts the ring through `edge` at its middle and starts sliding it (one gesture); `None`, with
/// the message shown, when the cut is refused.
fn cut_and_slide(editor: &mut EditorState, edge: EdgeId) -> Option<LoopCutTool> {
    let original = Box::new(editor.document.doc().clone());
    editor.document.begin_gesture();
    let cut = editor.document.apply_mesh(MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 });
    let new_vertices: Vec<VertexId> = match cut {
        Ok(Some((Some(provenance), _))) => (0..provenance.vertices.len() as u32)
            .map(VertexId)
            .filter(|v| matches!(provenance.vertices[v.index()], VertexOrigin::OnEdge { .. }))
            .collect(),
        Ok(_) => Vec::new(),
        Err(message) => {
            editor.document.end_gesture();
            editor.notify(message, true);
            return None;
        }
    };
    // The new loop is the selection, in the current mode's elements.
    let selection = &mut editor.view.selection;
    let mode = selection.mode;
    selection.clear();
    selection.vertices = new_vertices.clone();
    selection.hovered_vertex = None;
    selection.hovered_edge = None;
    selection.hovered_face = None;
    crate::editor::select_modes::set_mode(&editor.document.doc().cage, &mut editor.view.selection, mode);
    let topology = CageStamp::now(editor);
    Some(LoopCutTool::Slide { original, edge, new_vertices, fraction: 0.5, topology })
}

impl LoopCutTool {
    /// Moves the new loop to `fraction` along the ring (where a cut at `fraction` puts it).
    pub(crate) fn slide(&mut self, editor: &mut EditorState, fraction: f64) {
        let LoopCutTool::Slide { original, edge, new_vertices, fraction: now, .. } = self else { return };
        let fraction = fraction.clamp(SLIDE_MARGIN, 1.0 - SLIDE_MARGIN);
        if !fraction.is_finite() || fraction == *now {
            return;
        }
        let Ok(edited) = loop_cut(&original.cage, *edge, fraction) else { return };
        *now = fraction;
        let moves = new_vertices.iter().map(|&v| (v, edited.mesh.position(v))).collect();
        editor.emit(Edit::MoveVertices(moves));
    }

    /// Cuts across the previewed edge, or sets the slide: the tool's next stage, or its end.
    fn advance(&mut self, editor: &mut EditorState, edge: Option<EdgeId>) -> Flow {
        match (&*self, edge) {
            (LoopCutTool::Slide { .. }, _) => Flow::Keep,
            (LoopCutTool::Preview { refusal: None, .. }, Some(edge)) => match cut_and_slide(editor, edge) {
                Some(slide) => {
                    *self = slide;
                    Flow::Continue
                }
                None => Flow::Cancel,
            },
            (LoopCutTool::Preview { .. }, _) => Flow::Cancel,
        }
    }
}

impl Tool for LoopCutTool {
    /// Enter cuts (previewing) or sets (sliding), Esc cancels.
    fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        let (enter, escape) =
            ctx.input_mut(|i| (shortcuts::take_plain(i, Key::Enter), shortcuts::take_plain(i, Key::Escape)));
        if escape {
            Flow::Cancel
        } else if enter {
            match self {
                LoopCutTool::Preview { edge: Some(edge), refusal: None, .. } => {
                    let edge = *edge;
                    self.advance(editor, Some(edge))
                }
                LoopCutTool::Preview { .. } => Flow::Continue,
                LoopCutTool::Slide { .. } => Flow::Keep,
            }
        } else {
            Flow::Continue
        }
    }

    /// The preview follows the edge under the mouse and a click cuts; then the mouse slides and
    /// a click sets; a right click cancels.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        let frame = editor.view.display_frame;
        let view = &pointer.view;
        if let LoopCutTool::Preview { edge: Some(e), .. } = self
            && e.index() >= editor.document.doc().cage.edge_count()
        {
            // The cage was replaced under the preview (a file opened from the menu).
            *self = LoopCutTool::Preview { edge: None, lines: Vec::new(), refusal: None };
        }
        match self {
            LoopCutTool::Preview { edge, .. } => {
                let edge = *edge;
                let display = editor.display_cage();
                let hovered = pointer.mouse.and_then(|m| editor.pick_cage_edge(view, &display, m, 8.0));
                if let Some(h) = hovered
                    && Some(h) != edge
                {
                    *self = preview(editor, h);
                }
                if pointer.clicked() {
                    return if hovered.is_some() { self.advance(editor, hovered) } else { Flow::Cancel };
                }
            }
            LoopCutTool::Slide { original, edge, .. } => {
                let (a, b) = original.cage.edge_vertices(*edge);
                let project = |p: DVec3| interaction::project(&editor.view.camera, view, frame.to_display_f64(p));
                let ends = project(original.cage.position(a)).zip(project(original.cage.position(b)));
                if let (Some(((pa, _), (pb, _))), Some(m)) = (ends, pointer.mouse) {
                    let ab = pb - pa;
                    if ab.length_squared() > 1.0 {
                        let f = f64::from((m - pa).dot(ab) / ab.length_squared());
                        self.slide(editor, f);
                    }
                }
                if pointer.clicked() {
                    return Flow::Keep;
                }
            }
        }
        if pointer.right_clicked() { Flow::Cancel } else { Flow::Continue }
    }

    /// The loop the cut would insert.
    fn overlay(&self, editor: &EditorState, painter: &egui::Painter, view: &ViewportRect) {
        let LoopCutTool::Preview { lines, .. } = self else { return };
        let colour = egui::Color32::from_rgb(255, 220, 50);
        let project =
            |p: DVec3| interaction::project(&editor.view.camera, view, editor.view.display_frame.to_display_f64(p));
        for [p, q] in lines {
            if let (Some((p, _)), Some((q, _))) = (project(*p), project(*q)) {
                painter.line_segment([egui::pos2(p.x, p.y), egui::pos2(q.x, q.y)], egui::Stroke::new(2.0, colour));
            }
        }
    }

    fn readout(&self, _editor: &EditorState) -> Option<String> {
        match self {
            LoopCutTool::Slide { fraction, .. } => Some(format!("slide {fraction:.3} along the edge")),
            LoopCutTool::Preview { .. } => None,
        }
    }

    fn status(&self, _editor: &EditorState) -> String {
        match self {
            // The core's refusals name the operation already.
            LoopCutTool::Preview { refusal: Some(why), .. } if why.starts_with("loop cut") => why.clone(),
            LoopCutTool::Preview { refusal: Some(why), .. } => format!("loop cut: {why}"),
            LoopCutTool::Preview { .. } => {
                "loop cut: point at an edge, click to cut across its ring, Esc leaves".into()
            }
            LoopCutTool::Slide { fraction, .. } => {
                format!("slide the new loop: {fraction:.3} along the edge; click or Enter sets, Esc cancels the cut")
            }
        }
    }

    /// Keeps the cut (one undo step) or puts the document back as it was; a preview ends.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if let LoopCutTool::Slide { original, .. } = *self {
            if end == End::Cancel {
                editor.emit(Edit::Replace(original));
                editor.emit_run(EditorState::prune_selection);
            }
            editor.emit_end_gesture();
        }
    }

    /// A slide whose cage was replaced ends without touching the new one.
    fn is_stale(&self, editor: &EditorState) -> bool {
        matches!(self, LoopCutTool::Slide { topology, .. } if topology.is_stale(editor))
    }

    fn navigates(&self) -> bool {
        true
    }
}
