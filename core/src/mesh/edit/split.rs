//! Splitting edges at a fraction, and splitting a face by connecting two of its vertices.
//!
//! A split edge gets a new vertex at `p + t (q − p)` (`p`, `q` its ends in
//! [`PolyMesh::edge_vertices`] order); the faces on both sides gain a corner (a quad becomes a
//! pentagon) and keep their identity, and both halves carry the old edge's values. Connecting two
//! vertices that share a face and are not yet joined cuts that face in two along a new edge (a
//! new edge inside a face, [`EdgeOrigin::InFace`](super::EdgeOrigin::InFace)); a pair sharing
//! several faces is refused as ambiguous, since the faces would have to be named.

use super::Edited;
use super::draft::{Draft, check_fraction, edge_mask};
use super::provenance::{FaceOrigin, VertexOrigin};
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::{Error, Result};

/// Splits each selected edge at `fraction` (strictly between 0 and 1) from its first vertex.
pub fn split_edges(mesh: &PolyMesh, edges: &[EdgeId], fraction: f64) -> Result<Edited> {
    const OP: &str = "split edges";
    check_fraction(OP, fraction)?;
    let mask = edge_mask(OP, mesh, edges)?;
    let mut draft = Draft::new(mesh, OP);
    let mut middle = vec![u32::MAX; mesh.edge_count()];
    for e in mesh.edges().filter(|e| mask[e.index()]) {
        let (p, q) = mesh.edge_vertices(e);
        let at = mesh.position(p).lerp(mesh.position(q), fraction);
        middle[e.index()] = draft.add_vertex(at, VertexOrigin::OnEdge { edge: e, t: fraction });
    }
    let mut ring = Vec::new();
    for f in mesh.faces() {
        ring.clear();
        for h in mesh.face_halfedges(f) {
            ring.push(mesh.from_vertex(h).0);
            if mask[h.edge().index()] {
                ring.push(middle[h.edge().index()]);
            }
        }
        draft.push_face(ring.iter().copied(), FaceOrigin::Same(f));
    }
    draft.finish()
}

/// Cuts the face that `a` and `b` share in two along a new edge from `a` to `b`.
pub fn connect_vertices(mesh: &PolyMesh, a: VertexId, b: VertexId) -> Result<Edited> {
    const OP: &str = "connect vertices";
    let n = mesh.vertex_count();
    for v in [a, b] {
        if v.index() >= n {
            return Err(Error::Input(format!("{OP}: vertex {} does not exist (the cage has {n} vertices)", v.0)));
        }
    }
    if a == b {
        return Err(Error::Input(format!("{OP}: pick two different vertices (both are vertex {})", a.0)));
    }
    if mesh.find_halfedge(a, b).is_some() {
        return Err(Error::Topology(format!("{OP}: vertices {} and {} are already joined by an edge", a.0, b.0)));
    }
    let shared: Vec<FaceId> = mesh
        .outgoing(a)
        .map(|h| mesh.face(h))
        .filter(|f| f.is_valid() && mesh.face_vertices(*f).any(|v| v == b))
        .collect();
    let f = match shared.as_slice() {
        [] => {
            return Err(Error::Topology(format!(
                "{OP}: vertices {} and {} share no face, so no face can be split between them",
                a.0, b.0
            )));
        }
        [f] => *f,
        [f, g, ..] => {
            return Err(Error::Topology(format!(
                "{OP}: vertices {} and {} share faces {} and {}, so the face to split is ambiguous",
                a.0, b.0, f.0, g.0
            )));
        }
    };
    let ring: Vec<u32> = mesh.face_vertices(f).map(|v| v.0).collect();
    let i = ring.iter().position(|&v| v == a.0).expect("a is a corner of its face");
    let rotated: Vec<u32> = ring[i..].iter().chain(&ring[..i]).copied().collect();
    let j = rotated.iter().position(|&v| v == b.0).expect("b is a corner of the shared face");
    let mut draft = Draft::new(mesh, OP);
    for g in mesh.faces() {
        if g == f {
            draft.push_face(rotated[..=j].iter().copied(), FaceOrigin::SplitFrom(f));
            draft.push_face(rotated[j..].iter().copied().chain([a.0]), FaceOrigin::SplitFrom(f));
        } else {
            draft.keep_face(g);
        }
    }
    draft.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::fixtures::{check, counts, cube, house, prism};
    use crate::mesh::edit::{EdgeOrigin, VertexOrigin};

    #[test]
    fn split_edges_make_pentagons_and_keep_the_halves() {
        let cube = cube();
        let e = cube.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
        let edited = split_edges(&cube, &[e], 0.3).unwrap();
        check(&cube, &edited);
        let m = &edited.mesh;
        assert_eq!(counts(m), (9, 13, 6));
        assert!(m.is_closed());
        assert_eq!(m.position(VertexId(8)), crate::DVec3::new(0.3, 0.0, 0.0));
        assert_eq!(edited.provenance.vertices[8], VertexOrigin::OnEdge { edge: e, t: 0.3 });
        let halves = edited.provenance.edges.iter().filter(|&&o| o == EdgeOrigin::SplitFrom(e)).count();
        assert_eq!(halves, 2);
        assert_eq!(m.faces().filter(|&f| m.face_valence(f) == 5).count(), 2);
        // Splitting every edge of a prism.
        let p = prism(5);
        let all: Vec<EdgeId> = p.edges().collect();
        let edited = split_edges(&p, &all, 0.5).unwrap();
        check(&p, &edited);
        assert_eq!(counts(&edited.mesh), (25, 30, 7));
    }

    #[test]
    fn connecting_two_corners_splits_their_face() {
        let cube = cube();
        let edited = connect_vertices(&cube, VertexId(0), VertexId(3)).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (8, 13, 7));
        let (a, b) = edited.mesh.edge_vertices(
            edited.mesh.edges().find(|&e| matches!(edited.provenance.edges[e.index()], EdgeOrigin::InFace(_))).unwrap(),
        );
        assert_eq!((a.0.min(b.0), a.0.max(b.0)), (0, 3));
        // A pentagon cap split into a triangle and a quad.
        let p = prism(5);
        let edited = connect_vertices(&p, VertexId(5), VertexId(7)).unwrap();
        check(&p, &edited);
        let sizes: Vec<usize> = edited.mesh.faces().map(|f| edited.mesh.face_valence(f)).collect();
        assert_eq!(sizes.iter().filter(|&&s| s == 3).count(), 1);
    }

    #[test]
    fn bad_connections_are_refused() {
        let (cube, h) = (cube(), house());
        let cases = [
            (connect_vertices(&cube, VertexId(0), VertexId(1)).err(), "already joined"),
            (connect_vertices(&cube, VertexId(0), VertexId(7)).err(), "share no face"),
            (connect_vertices(&cube, VertexId(0), VertexId(0)).err(), "two different vertices"),
            (connect_vertices(&cube, VertexId(0), VertexId(8)).err(), "vertex 8 does not exist"),
            (connect_vertices(&h, VertexId(4), VertexId(7)).err(), "share no face"),
            (split_edges(&cube, &[EdgeId(0)], 1.0).err(), "between 0 and 1"),
            (split_edges(&cube, &[], 0.5).err(), "nothing selected"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected), "expected '{expected}' in: {err}");
        }
    }
}
