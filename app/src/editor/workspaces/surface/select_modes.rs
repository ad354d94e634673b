//! Cage selection as Blender's edit mode has it: a vertex, edge or face select mode (Tab cycles),
//! face picking by the mouse ray, edge loops and rings (Alt+click, Ctrl+Alt+click), select more
//! and less (Ctrl+Plus, Ctrl+Minus) and select linked (Ctrl+L).
//!
//! Switching mode converts the selection through its vertices: the vertices of whatever is
//! selected, then (edge mode) the edges with both ends among them or (face mode) the faces with
//! every corner among them, as Blender does. More and less grow and shrink by one ring of
//! neighbours sharing a vertex. A loop walks straight on through vertices of valence four (it
//! stops at a boundary, at another valence, or back where it began); a ring steps across quads to
//! the opposite edge (it stops at a boundary or a face that is not a quad). These are standard
//! mesh-editing walks, not methods of Taut's papers; they are weak on triangle-dominant cages,
//! where loops and rings stop at once.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::{EditorState, Selection};
use glam::Vec2;
use std::collections::VecDeque;
use taut_core::{DVec3, EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use taut_render::Camera;

/// What a click in the viewport picks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SelectMode {
    /// Vertices (and edges, when no vertex is near the mouse).
    #[default]
    Vertex,
    Edge,
    Face,
}

impl SelectMode {
    /// The next mode, as Tab cycles them.
    pub fn next(self) -> SelectMode {
        match self {
            SelectMode::Vertex => SelectMode::Edge,
            SelectMode::Edge => SelectMode::Face,
            SelectMode::Face => SelectMode::Vertex,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SelectMode::Vertex => "vertex",
            SelectMode::Edge => "edge",
            SelectMode::Face => "face",
        }
    }
}

/// Every vertex of the selection: selected vertices, the ends of selected edges and the corners of
/// selected faces, each once, in that order.
pub fn selected_vertex_set(cage: &PolyMesh, selection: &Selection) -> Vec<VertexId> {
    let mut seen = vec![false; cage.vertex_count()];
    let mut out = Vec::new();
    let mut add = |v: VertexId| {
        if v.index() < seen.len() && !seen[v.index()] {
            seen[v.index()] = true;
            out.push(v);
        }
    };
    selection.vertices.iter().copied().for_each(&mut add);
    for &e in selection.edges.iter().filter(|e| e.index() < cage.edge_count()) {
        let (a, b) = cage.edge_vertices(e);
        add(a);
        add(b);
    }
    for &f in selection.faces.iter().filter(|f| f.index() < cage.face_count()) {
        cage.face_vertices(f).for_each(&mut add);
    }
    out
}

/// Replaces the selection by the elements of `mode` that the vertex flags cover.
fn select_covered(cage: &PolyMesh, selection: &mut Selection, mode: SelectMode, covered: &[bool]) {
    selection.clear();
    match mode {
        SelectMode::Vertex => selection.vertices = cage.vertices().filter(|v| covered[v.index()]).collect(),
        SelectMode::Edge => {
            selection.edges = cage
                .edges()
                .filter(|&e| {
                    let (a, b) = cage.edge_vertices(e);
                    covered[a.index()] && covered[b.index()]
                })
                .collect()
        }
        SelectMode::Face => {
            selection.faces = cage.faces().filter(|&f| cage.face_vertices(f).all(|v| covered[v.index()])).collect()
        }
    }
}

fn flags(cage: &PolyMesh, vertices: &[VertexId]) -> Vec<bool> {
    let mut covered = vec![false; cage.vertex_count()];
    let n = covered.len();
    for v in vertices.iter().filter(|v| v.index() < n) {
        covered[v.index()] = true;
    }
    covered
}

/// Switches the select mode, converting the selection through its vertices.
pub fn set_mode(cage: &PolyMesh, selection: &mut Selection, mode: SelectMode) {
    let covered = flags(cage, &selected_vertex_set(cage, selection));
    selection.mode = mode;
    select_covered(cage, selection, mode, &covered);
}

/// Select linked: everything connected to the selection by edges.
pub fn select_linked(cage: &PolyMesh, selection: &mut Selection) {
    let mut covered = flags(cage, &selected_vertex_set(cage, selection));
    let mut queue: VecDeque<VertexId> = cage.vertices().filter(|v| covered[v.index()]).collect();
    while let Some(v) = queue.pop_front() {
        for w in cage.vertex_neighbors(v) {
            if !covered[w.index()] {
                covered[w.index()] = true;
                queue.push_back(w);
            }
        }
    }
    select_covered(cage, selection, selection.mode, &covered);
}

/// Select more: adds every element sharing a vertex with the selection.
pub fn select_more(cage: &PolyMesh, selection: &mut Selection) {
    let selected = selected_vertex_set(cage, selection);
    let mut covered = flags(cage, &selected);
    match selection.mode {
        SelectMode::Vertex => {
            for &v in &selected {
                for w in cage.vertex_neighbors(v) {
                    covered[w.index()] = true;
                }
            }
            select_covered(cage, selection, SelectMode::Vertex, &covered);
        }
        SelectMode::Edge => {
            let touched = covered;
            let mut edges = selection.edges.clone();
            for e in cage.edges() {
                let (a, b) = cage.edge_vertices(e);
                if (touched[a.index()] || touched[b.index()]) && !edges.contains(&e) {
                    edges.push(e);
                }
            }
            selection.edges = edges;
        }
        SelectMode::Face => {
            let touched = covered;
            let mut faces = selection.faces.clone();
            for f in cage.faces() {
                if cage.face_vertices(f).any(|v| touched[v.index()]) && !faces.contains(&f) {
                    faces.push(f);
                }
            }
            selection.faces = faces;
        }
    }
}

/// Select less: drops the selected elements on the border of the selection (touching a vertex
/// that an unselected element of the mode also touches; in vertex mode, a vertex with an
/// unselected neighbour or on an open boundary).
pub fn select_less(cage: &PolyMesh, selection: &mut Selection) {
    let covered = flags(cage, &selected_vertex_set(cage, selection));
    match selection.mode {
        SelectMode::Vertex => {
            selection
                .vertices
                .retain(|&v| !cage.is_boundary_vertex(v) && cage.vertex_neighbors(v).all(|w| covered[w.index()]));
        }
        SelectMode::Edge => {
            let mut on = vec![false; cage.edge_count()];
            let n = on.len();
            selection.edges.iter().filter(|e| e.index() < n).for_each(|e| on[e.index()] = true);
            let mut border = vec![false; cage.vertex_count()];
            for e in cage.edges().filter(|e| !on[e.index()]) {
                let (a, b) = cage.edge_vertices(e);
                border[a.index()] = true;
                border[b.index()] = true;
            }
            selection.edges.retain(|&e| {
                let (a, b) = cage.edge_vertices(e);
                !border[a.index()] && !border[b.index()]
            });
        }
        SelectMode::Face => {
            let mut on = vec![false; cage.face_count()];
            let n = on.len();
            selection.faces.iter().filter(|f| f.index() < n).for_each(|f| on[f.index()] = true);
            let mut border = vec![false; cage.vertex_count()];
            for f in cage.faces().filter(|f| !on[f.index()]) {
                cage.face_vertices(f).for_each(|v| border[v.index()] = true);
            }
            for v in cage.vertices().filter(|&v| cage.is_boundary_vertex(v)) {
                border[v.index()] = true;
            }
            selection.faces.retain(|&f| cage.face_vertices(f).all(|v| !border[v.index()]));
        }
    }
}

/// The edge loop through `edge`: straight on through interior vertices of valence four, both
/// ways, in walking order (the clicked edge first).
pub fn edge_loop(cage: &PolyMesh, edge: EdgeId) -> Vec<EdgeId> {
    let mut out = vec![edge];
    let mut seen = vec![false; cage.edge_count()];
    seen[edge.index()] = true;
    for start in [edge.halfedge(0), edge.halfedge(1)] {
        let mut h = start;
        loop {
            let v = cage.to_vertex(h);
            if cage.is_boundary_vertex(v) || cage.valence(v) != 4 {
                break;
            }
            // Two steps round v from the halfedge back along h: the edge opposite h at v.
            let next = cage.next(cage.next(h).twin());
            if seen[next.edge().index()] {
                break;
            }
            seen[next.edge().index()] = true;
            out.push(next.edge());
            h = next;
        }
    }
    out
}

/// The edge ring through `edge`: across each quad to the opposite edge, both ways, with the
/// quads crossed (the face loop).
pub fn edge_ring(cage: &PolyMesh, edge: EdgeId) -> (Vec<EdgeId>, Vec<FaceId>) {
    let (mut edges, mut faces) = (vec![edge], Vec::new());
    let mut seen_edge = vec![false; cage.edge_count()];
    let mut seen_face = vec![false; cage.face_count()];
    seen_edge[edge.index()] = true;
    for start in [edge.halfedge(0), edge.halfedge(1)] {
        let mut h: HalfedgeId = start;
        while !cage.is_boundary_halfedge(h) {
            let f = cage.face(h);
            if cage.face_valence(f) != 4 || seen_face[f.index()] {
                break;
            }
            seen_face[f.index()] = true;
            faces.push(f);
            let opposite = cage.next(cage.next(h));
            if seen_edge[opposite.edge().index()] {
                break;
            }
            seen_edge[opposite.edge().index()] = true;
            edges.push(opposite.edge());
            h = opposite.twin();
        }
    }
    (edges, faces)
}

/// Alt+click (loop) or Ctrl+Alt+click (ring) on `edge`: selects the loop or ring in the current
/// mode (its vertices, its edges, or in face mode the faces of the ring), adding with `add`.
pub fn select_loop_or_ring(cage: &PolyMesh, selection: &mut Selection, edge: EdgeId, ring: bool, add: bool) {
    if edge.index() >= cage.edge_count() {
        return;
    }
    if !add {
        selection.clear();
    }
    let (edges, faces) = if ring { edge_ring(cage, edge) } else { (edge_loop(cage, edge), Vec::new()) };
    match selection.mode {
        SelectMode::Vertex => {
            for e in edges {
                let (a, b) = cage.edge_vertices(e);
                for v in [a, b] {
                    if !selection.vertices.contains(&v) {
                        selection.vertices.push(v);
                    }
                }
            }
        }
        SelectMode::Edge => {
            for e in edges {
                if !selection.edges.contains(&e) {
                    selection.edges.push(e);
                }
            }
        }
        SelectMode::Face => {
            // A loop of faces is the ring of quads crossed by the ring through the edge.
            let faces = if ring { faces } else { edge_ring(cage, edge).1 };
            for f in faces {
                if !selection.faces.contains(&f) {
                    selection.faces.push(f);
                }
            }
        }
    }
}

/// The face under the mouse: the nearest one the mouse ray meets, each polygon taken as the fan
/// of triangles from its first corner (exact for planar convex faces; a warped face is hit
/// where its fan is).
pub fn pick_face(camera: &Camera, rect: &ViewportRect, cage: &PolyMesh, mouse: Vec2) -> Option<FaceId> {
    let (origin, direction) = interaction::unproject_ray(camera, rect, mouse);
    ray_mesh(origin, direction, cage).map(|(_, f)| f)
}

/// Where the ray first meets `mesh` (its polygons as fans, as [`pick_face`]): the ray parameter
/// and the face.
pub fn ray_mesh(origin: DVec3, direction: DVec3, mesh: &PolyMesh) -> Option<(f64, FaceId)> {
    let mut best: Option<(f64, FaceId)> = None;
    for f in mesh.faces() {
        let ring: Vec<DVec3> = mesh.face_vertices(f).map(|v| mesh.position(v)).collect();
        for k in 1..ring.len().saturating_sub(1) {
            if let Some(t) = ray_triangle(origin, direction, ring[0], ring[k], ring[k + 1])
                && best.is_none_or(|(b, _)| t < b)
            {
                best = Some((t, f));
            }
        }
    }
    best
}

/// Möller–Trumbore: the ray parameter where it meets the triangle (both sides), if ahead.
fn ray_triangle(origin: DVec3, direction: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-14 * e1.length() * e2.length() {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let w = direction.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && w >= 0.0 && u + w <= 1.0 && t > 0.0 && t.is_finite()).then_some(t)
}

impl EditorState {
    /// What the mouse points at in the current mode (vertex mode: a vertex, else an edge).
    pub(crate) fn hover_in_mode(&mut self, view: &ViewportRect, cage: &PolyMesh, mouse: Option<Vec2>) {
        let hovered = match (self.view.selection.mode, mouse) {
            (_, None) => (None, None, None),
            (SelectMode::Vertex, Some(m)) => match self.pick_cage_vertex(view, cage, m, 8.0) {
                Some(v) => (Some(v), None, None),
                None => (None, self.pick_cage_edge(view, cage, m, 5.0), None),
            },
            (SelectMode::Edge, Some(m)) => (None, self.pick_cage_edge(view, cage, m, 8.0), None),
            (SelectMode::Face, Some(m)) => (None, None, self.pick_cage_face(view, cage, m)),
        };
        let s = &mut self.view.selection;
        (s.hovered_vertex, s.hovered_edge, s.hovered_face) = hovered;
    }

    /// A click or a press at `at` picked nothing in the current mode: where a vertex, an edge or a
    /// face of another mode lies there, says so (a click on empty space stays silent).
    pub(crate) fn say_missed_pick(&mut self, view: &ViewportRect, cage: &PolyMesh, at: Vec2) {
        let mode = self.view.selection.mode;
        // An element of this mode lies there, behind the cage's front: X-ray picks it.
        let behind = !self.view.display.xray
            && match mode {
                SelectMode::Vertex => {
                    interaction::pick_vertex(&self.view.camera, view, cage.positions(), at, 8.0).is_some()
                }
                SelectMode::Edge => interaction::pick_edge(&self.view.camera, view, cage, at, 8.0).is_some(),
                SelectMode::Face => false,
            };
        if behind {
            let name = mode.name();
            self.notify(format!("the {name} there is behind the cage's front: X-ray (Alt+Z) picks it"), false);
            return;
        }
        let other = if mode != SelectMode::Vertex && self.pick_cage_vertex(view, cage, at, 8.0).is_some() {
            Some("a vertex")
        } else if mode == SelectMode::Face && self.pick_cage_edge(view, cage, at, 8.0).is_some() {
            Some("an edge")
        } else if mode != SelectMode::Face && self.pick_cage_face(view, cage, at).is_some() {
            Some("a face")
        } else {
            None
        };
        if let Some(other) = other {
            let name = mode.name();
            self.notify(
                format!("{name} mode: no {name} there to select ({other} is; Tab changes the select mode)"),
                false,
            );
        }
    }

    /// A drag begins at `origin`: picks what lies there in the current mode (selecting it unless
    /// it is selected already) and says whether anything did.
    pub(crate) fn drag_handle(
        &mut self,
        view: &ViewportRect,
        cage: &PolyMesh,
        origin: Vec2,
        shift: bool,
    ) -> Option<()> {
        match self.view.selection.mode {
            SelectMode::Vertex => {
                let v = self.pick_cage_vertex(view, cage, origin, 8.0)?;
                if !self.view.selection.vertices.contains(&v) {
                    self.view.selection.click_vertex(v, shift);
                }
            }
            SelectMode::Edge => {
                let e = self.pick_cage_edge(view, cage, origin, 8.0)?;
                if !self.view.selection.edges.contains(&e) {
                    self.view.selection.click_edge(e, shift);
                }
            }
            SelectMode::Face => {
                let f = self.pick_cage_face(view, cage, origin)?;
                if !self.view.selection.faces.contains(&f) {
                    self.view.selection.click_face(f, shift);
                }
            }
        }
        Some(())
    }

    /// A box selection caught `boxed` vertices: adds them, or in edge and face mode the edges and
    /// faces they cover.
    pub(crate) fn box_select_in_mode(&mut self, boxed: Vec<VertexId>) {
        let cage = &self.document.doc().cage;
        let s = &mut self.view.selection;
        let covered = flags(cage, &boxed);
        let mut caught = Selection { mode: s.mode, ..Default::default() };
        select_covered(cage, &mut caught, s.mode, &covered);
        for v in caught.vertices {
            if !s.vertices.contains(&v) {
                s.vertices.push(v);
            }
        }
        for e in caught.edges {
            if !s.edges.contains(&e) {
                s.edges.push(e);
            }
        }
        for f in caught.faces {
            if !s.faces.contains(&f) {
                s.faces.push(f);
            }
        }
    }

    /// A click: Alt picks a loop (Ctrl+Alt a ring) through the edge under the mouse; in edge
    /// and face mode a click picks what is hovered. Returns false when vertex mode's own click
    /// handling should run.
    pub(crate) fn click_in_mode(
        &mut self,
        modifiers: egui::Modifiers,
        view: &ViewportRect,
        mouse: Option<Vec2>,
    ) -> bool {
        let add = modifiers.shift;
        if modifiers.alt {
            let cage = self.display_cage();
            let edge = self
                .view
                .selection
                .hovered_edge
                .or_else(|| mouse.and_then(|m| self.pick_cage_edge(view, &cage, m, 8.0)));
            if let Some(e) = edge {
                select_loop_or_ring(&self.document.doc().cage, &mut self.view.selection, e, modifiers.command, add);
            }
            return true;
        }
        let s = &mut self.view.selection;
        match s.mode {
            SelectMode::Vertex => return false,
            SelectMode::Edge => match s.hovered_edge {
                Some(e) => s.click_edge(e, add),
                None if !add => s.clear(),
                None => {}
            },
            SelectMode::Face => match s.hovered_face {
                Some(f) => s.click_face(f, add),
                None if !add => s.clear(),
                None => {}
            },
        }
        true
    }
}

#[cfg(test)]
#[path = "select_modes_tests.rs"]
mod tests;
