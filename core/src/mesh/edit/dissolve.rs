//! Dissolving edges, faces and vertices: the surface stays closed, with fewer, larger faces.
//!
//! Dissolving edges merges the faces on their sides: faces joined through dissolved edges form a
//! group, and the group's one border loop — traced through halfedges whose other side is outside
//! the group — becomes one face (the first face of the group, by number, gives its values).
//! Edges with the group on both sides go with it, so dissolving three of the four edges round a
//! grid vertex still gives one octagon, and vertices left inside are removed.
//!
//! Dissolving faces merges each connected group of them the same way.
//!
//! Dissolving a vertex merges the faces around it into one and removes it: where it had two
//! edges (the middle of a split edge) its two edges become one instead
//! ([`EdgeOrigin::Merged`](super::EdgeOrigin::Merged), keeping the lower-numbered one's values),
//! and on the open boundary the boundary skips it the same way.
//!
//! Refused, with the face or vertex named: a dissolve that would leave a face with a hole, one
//! that touches itself at a vertex, fewer than three corners, or an edge on the open boundary (it
//! has no second face to merge with). Linear in the size of the cage.

use super::Edited;
use super::draft::{Draft, edge_mask, vertex_mask};
use super::provenance::{EdgeOrigin, FaceOrigin};
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{Error, Result};

/// Merges the faces on both sides of each edge.
pub fn dissolve_edges(mesh: &PolyMesh, edges: &[EdgeId]) -> Result<Edited> {
    const OP: &str = "dissolve edges";
    let mask = edge_mask(OP, mesh, edges)?;
    let mut groups = FaceUnion::new(mesh.face_count());
    for e in mesh.edges().filter(|e| mask[e.index()]) {
        let (f, g) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
        if !f.is_valid() || !g.is_valid() {
            let (a, b) = mesh.edge_vertices(e);
            return Err(Error::Topology(format!(
                "{OP}: edge {} (vertices {}-{}) lies on the open boundary, so it has no second face to merge \
                 with; delete it instead",
                e.0, a.0, b.0
            )));
        }
        groups.union(f, g);
    }
    merge_groups(mesh, groups, &vec![false; mesh.vertex_count()], &[], OP)
}

/// Merges each group of selected faces joined through shared edges into one face.
pub fn dissolve_faces(mesh: &PolyMesh, faces: &[FaceId]) -> Result<Edited> {
    const OP: &str = "dissolve faces";
    let mask = super::draft::face_mask(OP, mesh, faces)?;
    let mut groups = FaceUnion::new(mesh.face_count());
    let mut joined = false;
    for e in mesh.edges() {
        let (f, g) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
        if f.is_valid() && g.is_valid() && mask[f.index()] && mask[g.index()] {
            groups.union(f, g);
            joined = true;
        }
    }
    if !joined {
        return Err(Error::Input(format!("{OP}: no two of the selected faces share an edge; select neighbours")));
    }
    merge_groups(mesh, groups, &vec![false; mesh.vertex_count()], &[], OP)
}

/// Merges the faces around each vertex into one and removes the vertex.
pub fn dissolve_vertices(mesh: &PolyMesh, vertices: &[VertexId]) -> Result<Edited> {
    const OP: &str = "dissolve vertices";
    let drop = vertex_mask(OP, mesh, vertices)?;
    let mut groups = FaceUnion::new(mesh.face_count());
    for v in mesh.vertices().filter(|v| drop[v.index()]) {
        if mesh.valence(v) < 3 {
            continue;
        }
        let mut faces = mesh.outgoing(v).map(|h| mesh.face(h)).filter(|f| f.is_valid());
        if let Some(first) = faces.next() {
            for f in faces {
                groups.union(first, f);
            }
        }
    }
    let listed: Vec<VertexId> = mesh.vertices().filter(|v| drop[v.index()]).collect();
    merge_groups(mesh, groups, &drop, &listed, OP)
}

/// Faces grouped by union-find.
struct FaceUnion {
    parent: Vec<u32>,
}

impl FaceUnion {
    fn new(n: usize) -> Self {
        FaceUnion { parent: (0..n as u32).collect() }
    }
    fn root(&mut self, f: FaceId) -> u32 {
        let mut c = f.0;
        while self.parent[c as usize] != c {
            self.parent[c as usize] = self.parent[self.parent[c as usize] as usize];
            c = self.parent[c as usize];
        }
        c
    }
    fn union(&mut self, a: FaceId, b: FaceId) {
        let (ra, rb) = (self.root(a), self.root(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.parent[hi as usize] = lo;
    }
}

/// Replaces each group of two or more faces by its border loop and drops the `drop` vertices
/// from every loop. A group's representative is its lowest-numbered face.
fn merge_groups(
    mesh: &PolyMesh,
    mut groups: FaceUnion,
    drop: &[bool],
    removed: &[VertexId],
    op: &'static str,
) -> Result<Edited> {
    let nf = mesh.face_count();
    let root: Vec<u32> = mesh.faces().map(|f| groups.root(f)).collect();
    let mut size = vec![0u32; nf];
    for &r in &root {
        size[r as usize] += 1;
    }
    let group = |f: FaceId| (f.is_valid() && size[root[f.index()] as usize] > 1).then(|| root[f.index()]);
    let inner = |h: HalfedgeId| group(mesh.face(h)).is_some() && group(mesh.face(h)) == group(mesh.face(h.twin()));

    // The loop of halfedges of each face, or of each group at its representative.
    let mut loops: Vec<Option<Vec<HalfedgeId>>> = vec![None; nf];
    let mut visited = vec![false; mesh.halfedge_count()];
    for f in mesh.faces() {
        let Some(g) = group(f) else { continue };
        for start in mesh.face_halfedges(f) {
            if inner(start) || visited[start.index()] {
                continue;
            }
            if loops[g as usize].is_some() {
                return Err(Error::Topology(format!(
                    "{op}: merging the faces around face {g} would make a face with a hole in it (its border \
                     has more than one loop); dissolve fewer edges"
                )));
            }
            let mut border = Vec::new();
            let mut h = start;
            loop {
                visited[h.index()] = true;
                border.push(h);
                let mut next = mesh.next(h);
                let mut guard = 0;
                while inner(next) && guard <= mesh.halfedge_count() {
                    next = mesh.next(next.twin());
                    guard += 1;
                }
                h = next;
                if h == start || border.len() > mesh.halfedge_count() {
                    break;
                }
            }
            loops[g as usize] = Some(border);
        }
    }
    if let Some(f) = mesh.faces().find(|&f| group(f) == Some(f.0) && loops[f.index()].is_none()) {
        return Err(Error::Topology(format!(
            "{op}: the faces around face {} would merge into a closed piece with no border; dissolve fewer",
            f.0
        )));
    }

    let mut draft = Draft::new(mesh, op);
    let mut ring: Vec<u32> = Vec::new();
    let mut scratch: Vec<u32> = Vec::new();
    let mut own: Vec<HalfedgeId> = Vec::new();
    for f in mesh.faces() {
        let (border, origin) = match group(f) {
            Some(g) if g == f.0 => (loops[f.index()].as_deref().unwrap_or_default(), FaceOrigin::Merged(f)),
            Some(_) => continue,
            None if mesh.face_vertices(f).any(|v| drop[v.index()]) => {
                own.clear();
                own.extend(mesh.face_halfedges(f));
                (own.as_slice(), FaceOrigin::Same(f))
            }
            None => {
                draft.keep_face(f);
                continue;
            }
        };
        ring.clear();
        // Start at a kept vertex so each kept vertex is followed by the edges up to the next one.
        let Some(first) = border.iter().position(|&h| !drop[mesh.from_vertex(h).index()]) else {
            return Err(too_small(op, f));
        };
        // Runs of dropped vertices between two kept ones become one edge, keeping the values of
        // the lowest-numbered edge of the run.
        let mut last = mesh.from_vertex(border[first]).0;
        ring.push(last);
        let (mut span, mut span_len) = (EdgeId::INVALID, 0);
        for k in 0..border.len() {
            let h = border[(first + k) % border.len()];
            span = if span_len == 0 { h.edge() } else { span.min(h.edge()) };
            span_len += 1;
            let to = mesh.to_vertex(h);
            if !drop[to.index()] {
                if span_len > 1 {
                    draft.hint_edge(last, to.0, EdgeOrigin::Merged(span));
                }
                if k + 1 < border.len() {
                    ring.push(to.0);
                }
                (last, span_len) = (to.0, 0);
            }
        }
        if ring.len() < 3 {
            return Err(too_small(op, f));
        }
        if let Some(v) = super::merge::repeated(&ring, &mut scratch) {
            return Err(Error::Topology(format!(
                "{op}: the merged face at face {} would touch itself at vertex {v}; dissolve fewer elements",
                f.0
            )));
        }
        draft.push_face(ring.iter().copied(), origin);
    }
    for &v in removed {
        draft.remove_vertex(v);
    }
    draft.finish()
}

fn too_small(op: &str, f: FaceId) -> Error {
    Error::Topology(format!("{op}: face {} would be left with fewer than 3 corners", f.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, torus};
    use crate::mesh::edit::split_edges;

    fn edge(m: &PolyMesh, a: u32, b: u32) -> EdgeId {
        m.find_halfedge(VertexId(a), VertexId(b)).unwrap().edge()
    }

    #[test]
    fn dissolving_an_edge_merges_its_faces() {
        let cube = cube();
        let edited = dissolve_edges(&cube, &[edge(&cube, 0, 1)]).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (8, 11, 5));
        assert!(edited.mesh.is_closed());
        assert_eq!(edited.mesh.faces().filter(|&f| edited.mesh.face_valence(f) == 6).count(), 1);
        assert!(edited.provenance.faces.contains(&FaceOrigin::Merged(FaceId(0))));
    }

    #[test]
    fn dissolving_faces_merges_each_connected_group() {
        let g = grid(3);
        // Faces 0, 1 (a row pair) and 8 (alone, nothing to merge with).
        let edited = dissolve_faces(&g, &[FaceId(0), FaceId(1), FaceId(8)]).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (16, 23, 8));
        assert_eq!(edited.mesh.face_valence(FaceId(0)), 6);
        let err = dissolve_faces(&g, &[FaceId(0), FaceId(8)]).unwrap_err().to_string();
        assert!(err.contains("share an edge"), "{err}");
        // A 2 × 2 block: the middle vertex goes.
        let block = dissolve_faces(&g, &[FaceId(0), FaceId(1), FaceId(3), FaceId(4)]).unwrap();
        assert_eq!(counts(&block.mesh), (15, 20, 6));
    }

    #[test]
    fn dissolving_round_a_vertex_removes_it() {
        let g = grid(3);
        // Three of the four edges at vertex 5: the fourth has the group on both sides and goes too.
        let three = [edge(&g, 5, 1), edge(&g, 5, 4), edge(&g, 5, 6)];
        let by_edges = dissolve_edges(&g, &three).unwrap();
        check(&g, &by_edges);
        assert_eq!(counts(&by_edges.mesh), (15, 20, 6));
        let by_vertex = dissolve_vertices(&g, &[VertexId(5)]).unwrap();
        check(&g, &by_vertex);
        assert_eq!(by_vertex.mesh.polygons(), by_edges.mesh.polygons());
        assert_eq!(by_vertex.mesh.positions(), by_edges.mesh.positions());
        // A cube corner: three quads become a hexagon.
        let cube = cube();
        let edited = dissolve_vertices(&cube, &[VertexId(7)]).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (7, 9, 4));
        assert!(edited.mesh.is_closed());
        // Interior vertex of a torus: four quads become an octagon.
        let t = torus();
        let edited = dissolve_vertices(&t, &[VertexId(9)]).unwrap();
        check(&t, &edited);
        assert_eq!(counts(&edited.mesh), (47, 92, 45));
    }

    #[test]
    fn dissolving_the_vertex_of_a_split_restores_the_edge() {
        let cube = cube();
        let e = edge(&cube, 3, 7);
        let split = split_edges(&cube, &[e], 0.4).unwrap();
        let edited = dissolve_vertices(&split.mesh, &[VertexId(8)]).unwrap();
        check(&split.mesh, &edited);
        assert_eq!(counts(&edited.mesh), (8, 12, 6));
        let sorted = |m: &PolyMesh| {
            let mut faces: Vec<Vec<u32>> = m
                .polygons()
                .into_iter()
                .map(|mut f| {
                    let k = (0..f.len()).min_by_key(|&k| f[k]).unwrap();
                    f.rotate_left(k);
                    f
                })
                .collect();
            faces.sort();
            faces
        };
        assert_eq!(sorted(&edited.mesh), sorted(&cube));
        // The rejoined edge is a merge of the two halves, keeping the lower-numbered one's values.
        let joined = edge(&edited.mesh, 3, 7);
        let halves: Vec<EdgeId> = split
            .mesh
            .edges()
            .filter(|&h| split.provenance.edges[h.index()] == super::super::EdgeOrigin::SplitFrom(e))
            .collect();
        assert_eq!(edited.provenance.edges[joined.index()], EdgeOrigin::Merged(halves[0].min(halves[1])));
    }

    #[test]
    fn a_boundary_vertex_is_skipped_by_its_boundary() {
        let g = grid(3);
        let edited = dissolve_vertices(&g, &[VertexId(1)]).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (15, 22, 8));
        let joined = edited.mesh.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge(); // old 0 and 2
        assert_eq!(edited.provenance.edges[joined.index()], EdgeOrigin::Merged(edge(&g, 0, 1).min(edge(&g, 1, 2))));
        // A corner (one face): the face loses it.
        let edited = dissolve_vertices(&g, &[VertexId(0)]).unwrap();
        check(&g, &edited);
        assert_eq!(edited.mesh.face_valence(FaceId(0)), 3);
    }

    #[test]
    fn bad_dissolves_are_refused() {
        let (cube, g) = (cube(), grid(3));
        let ring: Vec<EdgeId> = g
            .edges()
            .filter(|&e| {
                let (f, h) = (g.face(e.halfedge(0)), g.face(e.halfedge(1)));
                f.is_valid() && h.is_valid() && f != FaceId(4) && h != FaceId(4)
            })
            .collect();
        let all: Vec<EdgeId> = cube.edges().collect();
        let triangle =
            PolyMesh::from_polygons(vec![crate::DVec3::ZERO, crate::DVec3::X, crate::DVec3::Y], &[[0, 1, 2]]).unwrap();
        let cases = [
            (dissolve_edges(&g, &[edge(&g, 0, 1)]).err(), "open boundary"),
            (dissolve_edges(&g, &ring).err(), "hole"),
            (dissolve_edges(&cube, &all).err(), "no border"),
            (dissolve_edges(&cube, &[]).err(), "nothing selected"),
            (dissolve_vertices(&triangle, &[VertexId(0)]).err(), "fewer than 3"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
        }
    }
}
