//! Filling a hole: a new face on a loop of open-boundary edges.
//!
//! The loop is given by its edges or by its vertices. A whole boundary loop becomes one face; a
//! run along a boundary that does not close (three of a square hole's four edges, or the
//! vertices of part of a loop) is closed by one new edge between its ends, as Blender's "fill"
//! does. The face follows the boundary halfedges, so it is oriented like its neighbours. The new
//! face ([`FaceOrigin::New`](super::FaceOrigin::New)) and a closing edge
//! ([`EdgeOrigin::New`](super::EdgeOrigin::New)) take the values for made elements. Refused: an
//! edge or vertex not on the open boundary, a selection spread over several runs or loops, fewer
//! than three corners, corners on a line, and a closing edge that would double an existing edge.

use super::Edited;
use super::draft::{Draft, edge_mask, vertex_mask};
use super::provenance::FaceOrigin;
use crate::mesh::{EdgeId, HalfedgeId, PolyMesh, VertexId};
use crate::{Error, Result};

const OP: &str = "fill";

/// Fills the hole bordered by the given boundary edges (all of a loop, or a run along one).
pub fn fill_edges(mesh: &PolyMesh, edges: &[EdgeId]) -> Result<Edited> {
    let mask = edge_mask(OP, mesh, edges)?;
    let mut in_run = vec![false; mesh.halfedge_count()];
    let mut selected = Vec::new();
    for e in mesh.edges().filter(|e| mask[e.index()]) {
        let Some(h) = [e.halfedge(0), e.halfedge(1)].into_iter().find(|&h| mesh.is_boundary_halfedge(h)) else {
            let (a, b) = mesh.edge_vertices(e);
            return Err(Error::Topology(format!(
                "{OP}: edge {} (vertices {}-{}) has faces on both sides; only edges of an open boundary can \
                 border a new face",
                e.0, a.0, b.0
            )));
        };
        in_run[h.index()] = true;
        selected.push(h);
    }
    let starts: Vec<HalfedgeId> = selected.iter().copied().filter(|&h| !in_run[mesh.prev(h).index()]).collect();
    let (first, closed) = match starts.as_slice() {
        [] => (selected[0], true),
        [s] => (*s, false),
        _ => {
            return Err(Error::Topology(format!(
                "{OP}: the selected edges form {} separate runs along the boundary; fill one run or loop at a time",
                starts.len()
            )));
        }
    };
    let mut chain = vec![first];
    let mut h = mesh.next(first);
    while in_run[h.index()] && h != first && chain.len() <= selected.len() {
        chain.push(h);
        h = mesh.next(h);
    }
    if chain.len() != selected.len() {
        return Err(Error::Topology(format!(
            "{OP}: the selected edges form more than one loop along the boundary; fill one loop at a time"
        )));
    }
    fill_chain(mesh, &chain, closed)
}

/// Fills the hole through the given boundary vertices (all of a loop, or a run along one).
pub fn fill_vertices(mesh: &PolyMesh, vertices: &[VertexId]) -> Result<Edited> {
    let mask = vertex_mask(OP, mesh, vertices)?;
    let count = mask.iter().filter(|&&m| m).count();
    if let Some(v) = mesh.vertices().find(|&v| mask[v.index()] && !mesh.is_boundary_vertex(v)) {
        return Err(Error::Topology(format!(
            "{OP}: vertex {} is not on an open boundary, so it cannot be a corner of a new face",
            v.0
        )));
    }
    if count < 3 {
        return Err(Error::Input(format!("{OP}: select at least 3 boundary vertices (or the edges of a hole)")));
    }
    let start = mesh.vertex_halfedge(vertices[0]);
    let mut ring = vec![start];
    let mut h = mesh.next(start);
    while h != start && ring.len() <= mesh.halfedge_count() {
        ring.push(h);
        h = mesh.next(h);
    }
    let on = |h: HalfedgeId| mask[mesh.from_vertex(h).index()];
    if ring.iter().filter(|&&h| on(h)).count() != count {
        return Err(Error::Topology(format!(
            "{OP}: the selected vertices are not all on the boundary loop through vertex {}; fill one loop at a time",
            vertices[0].0
        )));
    }
    if count == ring.len() {
        return fill_chain(mesh, &ring, true);
    }
    let n = ring.len();
    let run_starts: Vec<usize> = (0..n).filter(|&k| on(ring[k]) && !on(ring[(k + n - 1) % n])).collect();
    if run_starts.len() != 1 {
        return Err(Error::Topology(format!(
            "{OP}: the selected vertices form {} separate runs along the boundary; select one unbroken run",
            run_starts.len()
        )));
    }
    let chain: Vec<HalfedgeId> = (0..count - 1).map(|k| ring[(run_starts[0] + k) % n]).collect();
    fill_chain(mesh, &chain, false)
}

/// A face through the boundary halfedges of `chain`; an open chain is closed by a new edge.
fn fill_chain(mesh: &PolyMesh, chain: &[HalfedgeId], closed: bool) -> Result<Edited> {
    let mut ring: Vec<u32> = chain.iter().map(|&h| mesh.from_vertex(h).0).collect();
    if !closed {
        let (last, first) = (mesh.to_vertex(*chain.last().expect("a chain has an edge")), mesh.from_vertex(chain[0]));
        if let Some(h) = mesh.find_halfedge(last, first)
            && !mesh.is_boundary_halfedge(h)
        {
            return Err(Error::Topology(format!(
                "{OP}: the ends of the run, vertices {} and {}, are already joined by an edge with a face on that \
                 side; select the whole loop instead",
                last.0, first.0
            )));
        }
        ring.push(last.0);
    }
    if ring.len() < 3 {
        return Err(Error::Input(format!("{OP}: a face needs at least 3 corners; select a longer run")));
    }
    let points: Vec<crate::DVec3> = ring.iter().map(|&v| mesh.position(VertexId(v))).collect();
    let area: crate::DVec3 = (0..points.len()).map(|k| points[k].cross(points[(k + 1) % points.len()])).sum();
    let scale = (0..points.len()).map(|k| points[k].distance(points[(k + 1) % points.len()])).fold(0.0, f64::max);
    if area.length() <= 1e-12 * scale * scale {
        return Err(Error::Topology(format!(
            "{OP}: the corners of the new face would lie on a line (no area); select a run that turns a corner"
        )));
    }
    let mut draft = Draft::new(mesh, OP);
    for f in mesh.faces() {
        draft.keep_face(f);
    }
    draft.push_face(ring, FaceOrigin::New);
    draft.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::FaceId;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid};
    use crate::mesh::edit::{EdgeOrigin, FaceOrigin, delete_faces};

    fn edges_of_hole(m: &PolyMesh) -> Vec<EdgeId> {
        m.edges().filter(|&e| m.is_boundary_edge(e)).collect()
    }

    #[test]
    fn filling_a_hole_closes_the_cage_again() {
        let open = delete_faces(&cube(), &[FaceId(1)]).unwrap().mesh;
        let hole = edges_of_hole(&open);
        for edited in [
            fill_edges(&open, &hole).unwrap(),
            fill_edges(&open, &hole[..3]).unwrap(),
            fill_vertices(&open, &[VertexId(4), VertexId(5), VertexId(6), VertexId(7)]).unwrap(),
        ] {
            check(&open, &edited);
            assert_eq!(counts(&edited.mesh), (8, 12, 6));
            assert!(edited.mesh.is_closed());
            let f = FaceId(5);
            assert_eq!(edited.provenance.faces[f.index()], FaceOrigin::New);
            assert!(edited.mesh.face_area_vector(f).z > 0.99, "the fill looks out of the cube");
        }
    }

    #[test]
    fn an_open_run_is_closed_by_a_new_edge() {
        // A two-quad hole inside a 4 × 4 grid: corners 6, 7, 8, 13, 12, 11.
        let g = grid(4);
        let open = delete_faces(&g, &[FaceId(5), FaceId(6)]).unwrap().mesh;
        assert_eq!(counts(&open), (25, 39, 14));
        let edited = fill_vertices(&open, &[VertexId(7), VertexId(8), VertexId(13), VertexId(12)]).unwrap();
        check(&open, &edited);
        assert_eq!(counts(&edited.mesh), (25, 40, 15));
        let new_edges = edited.provenance.edges.iter().filter(|&&o| o == EdgeOrigin::New).count();
        assert_eq!(new_edges, 1);
        let rest = edited.mesh.edges().filter(|&e| {
            let (a, b) = edited.mesh.edge_vertices(e);
            edited.mesh.is_boundary_edge(e) && [a, b].iter().all(|v| [6, 7, 11, 12].contains(&v.0))
        });
        let rest: Vec<EdgeId> = rest.collect();
        let full = fill_edges(&edited.mesh, &rest).unwrap();
        check(&edited.mesh, &full);
        assert_eq!(counts(&full.mesh), counts(&g));
        assert!(full.mesh.faces().all(|f| full.mesh.face_area_vector(f).z > 0.99));
    }

    #[test]
    fn bad_fills_are_refused() {
        let (cube, g) = (cube(), grid(3));
        let open = delete_faces(&g, &[FaceId(0), FaceId(8)]).unwrap().mesh;
        let boundary = edges_of_hole(&open);
        let cases = [
            (fill_edges(&cube, &[EdgeId(0)]).err(), "faces on both sides"),
            (fill_vertices(&g, &[VertexId(5), VertexId(6), VertexId(9)]).err(), "not on an open boundary"),
            (fill_vertices(&g, &[VertexId(0), VertexId(1), VertexId(2)]).err(), "on a line"),
            (fill_vertices(&g, &[VertexId(0), VertexId(1)]).err(), "at least 3"),
            (fill_vertices(&g, &[VertexId(0), VertexId(2), VertexId(12)]).err(), "separate runs"),
            (fill_edges(&g, &[EdgeId(0), EdgeId(99)]).err(), "edge 99 does not exist"),
            (fill_edges(&open, &[boundary[0], boundary[boundary.len() / 2]]).err(), "separate runs"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
        }
    }
}
