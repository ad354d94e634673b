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
use crate::editor::ui::UiState;
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
        topology: u64,
    },
}

/// The fraction a slide never passes (the core needs it strictly inside the edge).
const SLIDE_MARGIN: f64 = 1e-3;

impl EditorState {
    /// Ctrl+R: the preview over the viewport, or with the mouse elsewhere and one edge selected,
    /// the cut at once.
    pub(crate) fn start_loop_cut(&mut self, ui_state: &mut UiState) {
        let selected = match self.selection.edges.as_slice() {
            [e] => Some(*e),
            _ => None,
        };
        if ui_state.pointer.is_none() {
            match self.selection.hovered_edge.or(selected) {
                Some(edge) => self.cut_and_slide(edge, ui_state),
                None => self.notify("point at an edge (or select one edge) to cut the ring across it", true),
            }
            return;
        }
        ui_state.loop_cut = Some(LoopCutTool::Preview { edge: None, lines: Vec::new(), refusal: None });
        if let Some(edge) = self.selection.hovered_edge.or(selected) {
            self.preview_loop(edge, ui_state);
        }
    }

    fn preview_loop(&mut self, edge: EdgeId, ui_state: &mut UiState) {
        let cage = &self.document.doc().cage;
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
        ui_state.loop_cut = Some(LoopCutTool::Preview { edge: Some(edge), lines, refusal });
    }

    /// Cuts the ring through `edge` at its middle and starts sliding it (one gesture).
    fn cut_and_slide(&mut self, edge: EdgeId, ui_state: &mut UiState) {
        let original = Box::new(self.document.doc().clone());
        self.document.begin_gesture();
        let cut = self.document.apply_mesh(MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 });
        let new_vertices: Vec<VertexId> = match cut {
            Ok(Some((Some(provenance), _))) => (0..provenance.vertices.len() as u32)
                .map(VertexId)
                .filter(|v| matches!(provenance.vertices[v.index()], VertexOrigin::OnEdge { .. }))
                .collect(),
            Ok(_) => Vec::new(),
            Err(message) => {
                self.document.end_gesture();
                ui_state.loop_cut = None;
                self.notify(message, true);
                return;
            }
        };
        // The new loop is the selection, in the current mode's elements.
        let mode = self.selection.mode;
        self.selection.clear();
        self.selection.vertices = new_vertices.clone();
        self.selection.hovered_vertex = None;
        self.selection.hovered_edge = None;
        self.selection.hovered_face = None;
        crate::editor::select_modes::set_mode(&self.document.doc().cage, &mut self.selection, mode);
        let topology = self.document.doc().cage.topology_generation();
        ui_state.loop_cut = Some(LoopCutTool::Slide { original, edge, new_vertices, fraction: 0.5, topology });
    }

    /// Moves the new loop to `fraction` along the ring (where a cut at `fraction` puts it).
    pub(crate) fn slide_loop(&mut self, fraction: f64, ui_state: &mut UiState) {
        let Some(LoopCutTool::Slide { original, edge, new_vertices, fraction: now, .. }) = &mut ui_state.loop_cut
        else {
            return;
        };
        let fraction = fraction.clamp(SLIDE_MARGIN, 1.0 - SLIDE_MARGIN);
        if !fraction.is_finite() || fraction == *now {
            return;
        }
        let Ok(edited) = loop_cut(&original.cage, *edge, fraction) else { return };
        *now = fraction;
        let moves = new_vertices.iter().map(|&v| (v, edited.mesh.position(v))).collect();
        self.edit(Edit::MoveVertices(moves));
    }

    /// Drops the tool when the cage it works on was replaced (a file opened from the menu):
    /// a preview is made again from the new cage, a slide ends without touching it.
    fn drop_stale_loop_cut(&mut self, ui_state: &mut UiState) {
        let topology = self.document.doc().cage.topology_generation();
        match &ui_state.loop_cut {
            Some(LoopCutTool::Slide { topology: t, .. }) if *t != topology => {
                ui_state.loop_cut = None;
                self.document.end_gesture();
            }
            Some(LoopCutTool::Preview { edge: Some(e), .. }) if e.index() >= self.document.doc().cage.edge_count() => {
                ui_state.loop_cut = Some(LoopCutTool::Preview { edge: None, lines: Vec::new(), refusal: None });
            }
            _ => {}
        }
    }

    /// Ends the tool: keeps the cut (one undo step) or puts the document back as it was.
    pub(crate) fn finish_loop_cut(&mut self, keep: bool, ui_state: &mut UiState) {
        match ui_state.loop_cut.take() {
            Some(LoopCutTool::Slide { original, .. }) => {
                if !keep {
                    self.edit(Edit::Replace(original));
                    self.prune_selection();
                }
                self.document.end_gesture();
            }
            Some(LoopCutTool::Preview { .. }) | None => {}
        }
    }

    /// The keys while the tool runs: Enter cuts (previewing) or sets (sliding), Esc cancels.
    pub(crate) fn loop_cut_keys(&mut self, ctx: &egui::Context, ui_state: &mut UiState) -> bool {
        self.drop_stale_loop_cut(ui_state);
        let Some(tool) = &ui_state.loop_cut else { return false };
        let (enter, escape) =
            ctx.input_mut(|i| (shortcuts::take_plain(i, Key::Enter), shortcuts::take_plain(i, Key::Escape)));
        if escape {
            self.finish_loop_cut(false, ui_state);
        } else if enter {
            match tool {
                LoopCutTool::Preview { edge: Some(edge), refusal: None, .. } => {
                    let edge = *edge;
                    self.cut_and_slide(edge, ui_state);
                }
                LoopCutTool::Preview { .. } => {}
                LoopCutTool::Slide { .. } => self.finish_loop_cut(true, ui_state),
            }
        }
        true
    }

    /// The viewport while the tool runs: the preview follows the edge under the mouse and a
    /// click cuts; then the mouse slides and a click sets; a right click cancels.
    pub(crate) fn loop_cut_viewport(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        view: &ViewportRect,
        mouse: Option<Vec2>,
        ui_state: &mut UiState,
    ) {
        self.drop_stale_loop_cut(ui_state);
        let frame = self.display_frame;
        match &ui_state.loop_cut {
            Some(LoopCutTool::Preview { edge, refusal, .. }) => {
                let (edge, refused) = (*edge, refusal.is_some());
                let display = self.display_cage();
                let hovered = mouse.and_then(|m| self.pick_cage_edge(view, &display, m, 8.0));
                if let Some(h) = hovered
                    && Some(h) != edge
                {
                    self.preview_loop(h, ui_state);
                }
                if response.clicked_by(egui::PointerButton::Primary) {
                    match (hovered.or(edge), refused) {
                        (Some(e), false) if hovered.is_some() => self.cut_and_slide(e, ui_state),
                        _ => ui_state.loop_cut = None,
                    }
                } else if response.clicked_by(egui::PointerButton::Secondary) {
                    ui_state.loop_cut = None;
                }
            }
            Some(LoopCutTool::Slide { original, edge, .. }) => {
                let (a, b) = original.cage.edge_vertices(*edge);
                let project = |p: DVec3| interaction::project(&self.camera, view, frame.to_display_f64(p));
                let ends = project(original.cage.position(a)).zip(project(original.cage.position(b)));
                if let (Some(((pa, _), (pb, _))), Some(m)) = (ends, mouse) {
                    let ab = pb - pa;
                    if ab.length_squared() > 1.0 {
                        let f = f64::from((m - pa).dot(ab) / ab.length_squared());
                        self.slide_loop(f, ui_state);
                    }
                }
                if response.clicked_by(egui::PointerButton::Primary) {
                    self.finish_loop_cut(true, ui_state);
                } else if response.clicked_by(egui::PointerButton::Secondary) {
                    self.finish_loop_cut(false, ui_state);
                }
            }
            None => return,
        }
        let painter = ui.painter_at(response.rect);
        let text = match &ui_state.loop_cut {
            Some(LoopCutTool::Preview { lines, refusal, .. }) => {
                let colour = egui::Color32::from_rgb(255, 220, 50);
                for [p, q] in lines {
                    let project = |p: DVec3| interaction::project(&self.camera, view, frame.to_display_f64(p));
                    if let (Some((p, _)), Some((q, _))) = (project(*p), project(*q)) {
                        painter
                            .line_segment([egui::pos2(p.x, p.y), egui::pos2(q.x, q.y)], egui::Stroke::new(2.0, colour));
                    }
                }
                match refusal {
                    Some(why) => format!("loop cut: {why}"),
                    None => "loop cut: point at an edge, click to cut across its ring, Esc leaves".to_string(),
                }
            }
            Some(LoopCutTool::Slide { fraction, .. }) => {
                format!("slide the new loop: {fraction:.3} along the edge; click or Enter sets, Esc cancels the cut")
            }
            None => return,
        };
        painter.text(
            response.rect.left_top() + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            text,
            egui::FontId::proportional(14.0),
            egui::Color32::WHITE,
        );
    }
}
