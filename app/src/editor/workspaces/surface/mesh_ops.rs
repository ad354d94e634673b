//! The Mesh menu, toolbar and keys of cage modelling: extrude (E), inset (I), loop cut (Ctrl+R),
//! delete and dissolve (X, Delete), merge (M), fill (F), subdivide and connect, flip normals,
//! triangulate and join triangles, each on the current selection and select mode.
//!
//! Each operation becomes one core modelling edit (`taut_core::document::modelling::MeshEdit`: the
//! elements and distances of the selection), which the core performs, carries fixed flags,
//! tensions and creases through, and checks completely before anything changes: one undo step
//! named after it ("Undo Extrude"), and one step of the session's edit script. A refused request (nothing suitable selected, or the core refusing the edit) shows
//! the one-line message and leaves the document and the selection as they were. The selection
//! follows the edit through the provenance: an element stays selected when it came from a
//! selected one (the lifted cap of an extrusion, the inner faces of an inset).
//!
//! Where Blender differs: E extrudes by a fixed distance (a fifth of the mean length of the
//! selected edges) along the normal and leaves the cap selected, so a drag or G then moves it;
//! Blender's extrude starts that move at once. Ctrl+R cuts the ring of the edge under the mouse
//! (or the one selected edge) at its middle, with no preview of the ring. The new document
//! carries the edit's provenance (`Document::lineage`), so the NUSD surface warm-starts: its
//! levels start from the old ones where the cage survived and are re-solved around the edit.

use crate::editor::select_modes::{SelectMode, selected_vertex_set};
use crate::editor::state::EditorState;
use taut_core::document::modelling::MeshEdit;
use taut_core::mesh::edit::Provenance;
use taut_core::{EdgeId, FaceId, PolyMesh, VertexId};

/// A cage-modelling operation on the selection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshOp {
    /// Faces as one region (face mode), or boundary edges (edge mode).
    Extrude,
    Inset,
    /// The ring through the hovered edge (or the one selected edge), at its middle.
    LoopCut,
    /// Whatever the select mode selects: vertices, edges or faces, and what leans on them.
    Delete,
    DeleteVertices,
    DeleteEdges,
    DeleteFaces,
    DissolveVertices,
    DissolveEdges,
    DissolveFaces,
    MergeAtCentre,
    MergeByDistance,
    /// A face on a closed run of boundary edges (or vertices).
    Fill,
    /// Split the selected edges at their middles.
    Subdivide,
    /// An edge across a face between the two selected vertices.
    Connect,
    FlipNormals,
    Triangulate,
    JoinTriangles,
}

impl MeshOp {
    /// Every operation, in the order the Mesh menu lists them.
    pub const ALL: [MeshOp; 18] = [
        MeshOp::Extrude,
        MeshOp::Inset,
        MeshOp::LoopCut,
        MeshOp::Delete,
        MeshOp::DeleteVertices,
        MeshOp::DeleteEdges,
        MeshOp::DeleteFaces,
        MeshOp::DissolveVertices,
        MeshOp::DissolveEdges,
        MeshOp::DissolveFaces,
        MeshOp::MergeAtCentre,
        MeshOp::MergeByDistance,
        MeshOp::Fill,
        MeshOp::Subdivide,
        MeshOp::Connect,
        MeshOp::FlipNormals,
        MeshOp::Triangulate,
        MeshOp::JoinTriangles,
    ];

    /// The menu label.
    pub fn label(self) -> &'static str {
        match self {
            MeshOp::Extrude => "Extrude",
            MeshOp::Inset => "Inset faces",
            MeshOp::LoopCut => "Loop cut (edge under the mouse)",
            MeshOp::Delete => "Delete",
            MeshOp::DeleteVertices => "Delete vertices",
            MeshOp::DeleteEdges => "Delete edges",
            MeshOp::DeleteFaces => "Delete faces",
            MeshOp::DissolveVertices => "Dissolve vertices",
            MeshOp::DissolveEdges => "Dissolve edges",
            MeshOp::DissolveFaces => "Dissolve faces",
            MeshOp::MergeAtCentre => "Merge at centre",
            MeshOp::MergeByDistance => "Merge by distance",
            MeshOp::Fill => "Fill",
            MeshOp::Subdivide => "Subdivide edges",
            MeshOp::Connect => "Connect two vertices",
            MeshOp::FlipNormals => "Flip normals",
            MeshOp::Triangulate => "Triangulate",
            MeshOp::JoinTriangles => "Join triangles",
        }
    }
}

/// Merge by distance: vertices closer than this fraction of the cage's diagonal become one.
pub const MERGE_DISTANCE_FRACTION: f64 = 1e-3;
/// Extrude and inset: the distance as a fraction of the mean length of the selected edges.
pub const OFFSET_FRACTION: f64 = 0.2;

/// What the selection holds for an operation, as element lists of the cage.
pub(crate) struct Picked {
    pub(crate) vertices: Vec<VertexId>,
    pub(crate) edges: Vec<EdgeId>,
    pub(crate) faces: Vec<FaceId>,
}

pub(crate) fn picked(cage: &PolyMesh, state: &EditorState) -> Picked {
    let s = &state.view.selection;
    let vertices = selected_vertex_set(cage, s);
    let mut covered = vec![false; cage.vertex_count()];
    vertices.iter().for_each(|v| covered[v.index()] = true);
    // Edges and faces: what is selected in their mode, else what the selected vertices span.
    let edges = if s.edges.is_empty() {
        cage.edges()
            .filter(|&e| {
                let (a, b) = cage.edge_vertices(e);
                covered[a.index()] && covered[b.index()]
            })
            .collect()
    } else {
        s.edges.clone()
    };
    let faces = if s.faces.is_empty() {
        cage.faces().filter(|&f| cage.face_vertices(f).all(|v| covered[v.index()])).collect()
    } else {
        s.faces.clone()
    };
    Picked { vertices, edges, faces }
}

pub(crate) fn mean_edge_length(cage: &PolyMesh, edges: &[EdgeId]) -> f64 {
    let n = edges.len().max(1) as f64;
    let mean = edges.iter().map(|&e| cage.edge_length(e)).sum::<f64>() / n;
    if mean.is_finite() && mean > 0.0 { mean } else { 0.1 * cage.bounding_diagonal().max(1e-9) }
}

pub(crate) fn face_edges(cage: &PolyMesh, faces: &[FaceId]) -> Vec<EdgeId> {
    faces.iter().flat_map(|&f| cage.face_halfedges(f).map(|h| h.edge())).collect()
}

fn need<T>(items: &[T], what: &str) -> Result<(), String> {
    if items.is_empty() { Err(format!("select {what} first")) } else { Ok(()) }
}

impl EditorState {
    /// Runs a modelling operation on the selection: one undo step, or a message and no change.
    pub fn mesh_op(&mut self, op: MeshOp) {
        match self.try_mesh_op(op) {
            Ok(()) => {}
            Err(message) => self.notify(message, true),
        }
    }

    fn try_mesh_op(&mut self, op: MeshOp) -> Result<(), String> {
        let edit = self.mesh_edit(op)?;
        let faces = picked(&self.document.doc().cage, self).faces;
        let mode = self.view.selection.mode;
        let Some((provenance, carried)) = self.document.apply_mesh(edit)? else { return Ok(()) };
        // Curve-mesh edits whose vertices did not survive the operation are said, not lost
        // silently (undo brings them back).
        if let Some(message) = carried.message() {
            self.notify(message, false);
        }
        let Some(provenance) = provenance else { return Ok(()) };
        if matches!(op, MeshOp::Extrude | MeshOp::Inset) && !faces.is_empty() && mode != SelectMode::Edge {
            // The lifted faces stay selected, in the current mode's elements.
            self.view.selection.clear();
            self.view.selection.faces = faces;
            self.map_selection(&provenance);
            let selection = &mut self.view.selection;
            crate::editor::select_modes::set_mode(&self.document.doc().cage, selection, mode);
        } else {
            self.map_selection(&provenance);
        }
        Ok(())
    }

    /// The core's operation for `op` on the current selection, its distances from the
    /// selection's size; a message when nothing suitable is selected.
    fn mesh_edit(&self, op: MeshOp) -> Result<MeshEdit, String> {
        let cage = &self.document.doc().cage;
        let p = picked(cage, self);
        let mode = self.view.selection.mode;
        let v = |ids: &[VertexId]| ids.iter().map(|v| v.0).collect::<Vec<_>>();
        let e = |ids: &[EdgeId]| ids.iter().map(|e| e.0).collect::<Vec<_>>();
        let f = |ids: &[FaceId]| ids.iter().map(|f| f.0).collect::<Vec<_>>();
        let boundary: Vec<EdgeId> = p.edges.iter().copied().filter(|&e| cage.is_boundary_edge(e)).collect();
        Ok(match op {
            MeshOp::Extrude => {
                if mode == SelectMode::Edge || p.faces.is_empty() {
                    need(&boundary, "faces (Tab to face mode) or open-boundary edges to extrude")?;
                    let distance = OFFSET_FRACTION * mean_edge_length(cage, &boundary);
                    MeshEdit::ExtrudeEdges { edges: e(&boundary), distance }
                } else {
                    let distance = OFFSET_FRACTION * mean_edge_length(cage, &face_edges(cage, &p.faces));
                    MeshEdit::ExtrudeFaces { faces: f(&p.faces), distance }
                }
            }
            MeshOp::Inset => {
                need(&p.faces, "the faces to inset")?;
                let distance = OFFSET_FRACTION * mean_edge_length(cage, &face_edges(cage, &p.faces));
                MeshEdit::Inset { faces: f(&p.faces), distance }
            }
            MeshOp::LoopCut => {
                let edge = self.view.selection.hovered_edge.or(match self.view.selection.edges.as_slice() {
                    [e] => Some(*e),
                    _ => None,
                });
                let edge =
                    edge.ok_or_else(|| "point at an edge (or select one edge) to cut the ring across it".to_string())?;
                MeshEdit::LoopCut { edge: edge.0, fraction: 0.5 }
            }
            MeshOp::Delete => match mode {
                SelectMode::Vertex => return self.mesh_edit(MeshOp::DeleteVertices),
                SelectMode::Edge => return self.mesh_edit(MeshOp::DeleteEdges),
                SelectMode::Face => return self.mesh_edit(MeshOp::DeleteFaces),
            },
            MeshOp::DeleteVertices => {
                need(&p.vertices, "the vertices to delete")?;
                MeshEdit::DeleteVertices { vertices: v(&p.vertices) }
            }
            MeshOp::DeleteEdges => {
                need(&p.edges, "the edges to delete")?;
                MeshEdit::DeleteEdges { edges: e(&p.edges) }
            }
            MeshOp::DeleteFaces => {
                need(&p.faces, "the faces to delete")?;
                MeshEdit::DeleteFaces { faces: f(&p.faces) }
            }
            MeshOp::DissolveVertices => {
                need(&p.vertices, "the vertices to dissolve")?;
                MeshEdit::DissolveVertices { vertices: v(&p.vertices) }
            }
            MeshOp::DissolveEdges => {
                need(&p.edges, "the edges to dissolve")?;
                MeshEdit::DissolveEdges { edges: e(&p.edges) }
            }
            MeshOp::DissolveFaces => {
                need(&p.faces, "the faces to dissolve")?;
                MeshEdit::DissolveFaces { faces: f(&p.faces) }
            }
            MeshOp::MergeAtCentre => {
                if p.vertices.len() < 2 {
                    return Err("select two or more vertices to merge".to_string());
                }
                MeshEdit::MergeAtCentre { vertices: v(&p.vertices) }
            }
            MeshOp::MergeByDistance => {
                let all: Vec<VertexId> =
                    if p.vertices.is_empty() { cage.vertices().collect() } else { p.vertices.clone() };
                let distance = MERGE_DISTANCE_FRACTION * cage.bounding_diagonal();
                MeshEdit::MergeByDistance { vertices: v(&all), distance }
            }
            MeshOp::Fill => {
                if mode == SelectMode::Vertex && !self.view.selection.vertices.is_empty() {
                    MeshEdit::FillVertices { vertices: v(&p.vertices) }
                } else {
                    need(&boundary, "a closed run of open-boundary edges to fill")?;
                    MeshEdit::FillEdges { edges: e(&boundary) }
                }
            }
            MeshOp::Subdivide => {
                need(&p.edges, "the edges to subdivide")?;
                MeshEdit::SplitEdges { edges: e(&p.edges), fraction: 0.5 }
            }
            MeshOp::Connect => match p.vertices.as_slice() {
                [a, b] => MeshEdit::Connect { a: a.0, b: b.0 },
                _ => return Err("select exactly two vertices of one face to connect".to_string()),
            },
            MeshOp::FlipNormals => MeshEdit::FlipNormals { faces: (!p.faces.is_empty()).then(|| f(&p.faces)) },
            MeshOp::Triangulate => MeshEdit::Triangulate { faces: (!p.faces.is_empty()).then(|| f(&p.faces)) },
            MeshOp::JoinTriangles => MeshEdit::JoinTriangles { edges: (!p.edges.is_empty()).then(|| e(&p.edges)) },
        })
    }

    /// The selection after an edit: the new elements whose source was selected.
    fn map_selection(&mut self, provenance: &Provenance) {
        let (nv, ne, nf) = provenance.old_counts;
        let mut was_vertex = vec![false; nv];
        let mut was_edge = vec![false; ne];
        let mut was_face = vec![false; nf];
        let s = &mut self.view.selection;
        s.vertices.iter().filter(|v| v.index() < nv).for_each(|v| was_vertex[v.index()] = true);
        s.edges.iter().filter(|e| e.index() < ne).for_each(|e| was_edge[e.index()] = true);
        s.faces.iter().filter(|f| f.index() < nf).for_each(|f| was_face[f.index()] = true);
        let hit = |flags: &[bool], i: Option<usize>| i.is_some_and(|i| flags.get(i).copied().unwrap_or(false));
        s.vertices = (0..provenance.vertices.len() as u32)
            .map(VertexId)
            .filter(|v| hit(&was_vertex, provenance.vertices[v.index()].source().map(|o| o.index())))
            .collect();
        s.edges = (0..provenance.edges.len() as u32)
            .map(EdgeId)
            .filter(|e| hit(&was_edge, provenance.edges[e.index()].source().map(|o| o.index())))
            .collect();
        s.faces = (0..provenance.faces.len() as u32)
            .map(FaceId)
            .filter(|f| hit(&was_face, provenance.faces[f.index()].source().map(|o| o.index())))
            .collect();
        s.hovered_vertex = None;
        s.hovered_edge = None;
        s.hovered_face = None;
        self.prune_selection();
    }
}

impl EditorState {
    /// The Mesh menu: the select modes, selection helpers and every operation, with their keys.
    pub(crate) fn mesh_menu(&mut self, ui: &mut egui::Ui) {
        use crate::editor::shortcuts::{self, Action};
        let item = |action: Action| {
            let key = shortcuts::label(action);
            if key.is_empty() {
                shortcuts::describe(action).to_string()
            } else {
                format!("{}  {key}", shortcuts::describe(action))
            }
        };
        ui.menu_button("Mesh", |ui| {
            ui.menu_button("Select mode", |ui| {
                for mode in [SelectMode::Vertex, SelectMode::Edge, SelectMode::Face] {
                    let label = format!("{} select", mode.name());
                    if ui.radio(self.view.selection.mode == mode, label).clicked() {
                        crate::editor::select_modes::set_mode(
                            &self.document.doc().cage,
                            &mut self.view.selection,
                            mode,
                        );
                    }
                }
            });
            for action in [Action::SelectLinked, Action::SelectMore, Action::SelectLess] {
                if ui.button(item(action)).clicked() {
                    self.emit_action(action);
                }
            }
            ui.separator();
            for op in MeshOp::ALL {
                if matches!(op, MeshOp::Delete | MeshOp::MergeAtCentre | MeshOp::Subdivide | MeshOp::FlipNormals) {
                    ui.separator();
                }
                if ui.button(item(Action::Mesh(op))).clicked() {
                    self.emit_action(Action::Mesh(op));
                }
            }
            ui.separator();
            self.mirror_menu(ui);
        });
    }
}
