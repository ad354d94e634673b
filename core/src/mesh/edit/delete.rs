//! Deleting vertices, edges or faces, leaving a hole.
//!
//! Deleting faces removes them; deleting an edge removes the faces on its sides; deleting a
//! vertex removes every face around it and the vertex itself. Vertices and edges that no
//! remaining face uses are removed with them (vertices that were isolated before stay, unless
//! they are the ones deleted). A vertex whose remaining faces fall apart into separate fans (two
//! diagonal quads of a grid deleted around it) would pinch the surface, which the halfedge mesh
//! cannot hold, so it is split into one vertex per fan, at the same place, each continuing the
//! old vertex ([`VertexOrigin::Same`](super::VertexOrigin::Same)) — the fans then smooth
//! independently. Deleting every face is refused. Linear in the size of the cage.

use super::Edited;
use super::draft::{Corners, Draft, edge_mask, face_mask, vertex_mask};
use super::provenance::{FaceOrigin, VertexOrigin};
use crate::Result;
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};

/// Deletes faces.
pub fn delete_faces(mesh: &PolyMesh, faces: &[FaceId]) -> Result<Edited> {
    let doomed = face_mask("delete faces", mesh, faces)?;
    rebuild_without(mesh, &doomed, &[], "delete faces")
}

/// Deletes edges and the faces on both their sides.
pub fn delete_edges(mesh: &PolyMesh, edges: &[EdgeId]) -> Result<Edited> {
    const OP: &str = "delete edges";
    let mask = edge_mask(OP, mesh, edges)?;
    let mut doomed = vec![false; mesh.face_count()];
    for e in mesh.edges().filter(|e| mask[e.index()]) {
        for h in [e.halfedge(0), e.halfedge(1)] {
            if mesh.face(h).is_valid() {
                doomed[mesh.face(h).index()] = true;
            }
        }
    }
    rebuild_without(mesh, &doomed, &[], OP)
}

/// Deletes vertices and every face around them.
pub fn delete_vertices(mesh: &PolyMesh, vertices: &[VertexId]) -> Result<Edited> {
    const OP: &str = "delete vertices";
    let mask = vertex_mask(OP, mesh, vertices)?;
    let mut doomed = vec![false; mesh.face_count()];
    for v in mesh.vertices().filter(|v| mask[v.index()]) {
        for h in mesh.outgoing(v) {
            if mesh.face(h).is_valid() {
                doomed[mesh.face(h).index()] = true;
            }
        }
    }
    let listed: Vec<VertexId> = mesh.vertices().filter(|v| mask[v.index()]).collect();
    rebuild_without(mesh, &doomed, &listed, OP)
}

/// Rebuilds without the doomed faces and the listed vertices, splitting pinched vertices.
fn rebuild_without(mesh: &PolyMesh, doomed: &[bool], vertices: &[VertexId], op: &'static str) -> Result<Edited> {
    let remaining: Vec<bool> = doomed.iter().map(|&d| !d).collect();
    let corners = Corners::new(mesh);
    let (fan, fan_count) = corners.fans(mesh, &remaining, |_| true);
    let mut draft = Draft::new(mesh, op);
    let mut first_fan = vec![u32::MAX; mesh.vertex_count()];
    let mut fan_vertex = vec![u32::MAX; fan_count];
    for f in mesh.faces().filter(|f| remaining[f.index()]) {
        for c in corners.of_face(f) {
            let v = mesh.from_vertex(corners.halfedge[c]);
            let k = fan[c];
            if first_fan[v.index()] == u32::MAX {
                first_fan[v.index()] = k;
            }
            fan_vertex[k as usize] = if k == first_fan[v.index()] {
                v.0
            } else if fan_vertex[k as usize] == u32::MAX {
                draft.add_vertex(mesh.position(v), VertexOrigin::Same(v))
            } else {
                fan_vertex[k as usize]
            };
        }
        draft.push_face(corners.of_face(f).map(|c| fan_vertex[fan[c] as usize]), FaceOrigin::Same(f));
    }
    for &v in vertices {
        draft.remove_vertex(v);
    }
    draft.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, torus};

    #[test]
    fn deleting_leaves_a_hole_and_drops_what_is_unused() {
        let cube = cube();
        let edited = delete_faces(&cube, &[FaceId(1)]).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (8, 12, 5));
        assert_eq!(edited.mesh.euler_characteristic(), 1);
        assert!(!edited.mesh.is_closed());
        let edited = delete_edges(&cube, &[EdgeId(0)]).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (8, 11, 4));
        let edited = delete_vertices(&cube, &[VertexId(7)]).unwrap();
        check(&cube, &edited);
        assert_eq!(counts(&edited.mesh), (7, 9, 3));
        assert!(edited.mesh.positions().iter().all(|&p| p != crate::DVec3::ONE));
        // A torus loses a face and stays one piece with a hole: χ = −1.
        let t = torus();
        let edited = delete_faces(&t, &[FaceId(10)]).unwrap();
        check(&t, &edited);
        assert_eq!(edited.mesh.euler_characteristic(), -1);
    }

    #[test]
    fn a_pinched_vertex_is_split_per_fan() {
        let g = grid(3);
        // Faces (1,0) and (0,1) leave faces (0,0) and (1,1) meeting only at vertex 5.
        let edited = delete_faces(&g, &[FaceId(1), FaceId(3)]).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (17, 22, 7));
        assert_eq!(edited.mesh.euler_characteristic(), 2);
        let at_5: Vec<VertexId> =
            edited.mesh.vertices().filter(|&v| edited.mesh.position(v) == g.position(VertexId(5))).collect();
        assert_eq!(at_5.len(), 2);
        for v in at_5 {
            assert_eq!(edited.provenance.vertices[v.index()], super::super::VertexOrigin::Same(VertexId(5)));
        }
    }

    #[test]
    fn deleting_everything_or_nothing_is_refused() {
        let cube = cube();
        let all: Vec<FaceId> = cube.faces().collect();
        let verts: Vec<VertexId> = cube.vertices().collect();
        for err in [
            delete_faces(&cube, &all).unwrap_err(),
            delete_vertices(&cube, &verts).unwrap_err(),
            delete_edges(&cube, &cube.edges().collect::<Vec<_>>()).unwrap_err(),
        ] {
            assert!(err.to_string().contains("no faces left"), "{err}");
        }
        assert!(delete_faces(&cube, &[]).unwrap_err().to_string().contains("nothing selected"));
        assert!(delete_vertices(&cube, &[VertexId(8)]).unwrap_err().to_string().contains("vertex 8 does not exist"));
    }
}
