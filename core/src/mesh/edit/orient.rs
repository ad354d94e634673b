//! Flipping normals: reversing the order of faces' corners.
//!
//! The halfedge mesh needs neighbouring faces to run opposite ways along their shared edge, so a
//! flip can only take whole connected pieces of the surface: a selection that includes a face
//! and not its neighbour across an edge is refused, naming both. Every element keeps its
//! identity ([`Same`](super::FaceOrigin::Same)); each face keeps its first corner.

use super::Edited;
use super::draft::{Draft, face_mask};
use super::provenance::FaceOrigin;
use crate::mesh::{FaceId, PolyMesh};
use crate::{Error, Result};

/// Reverses the selected faces, or every face when `faces` is `None`.
pub fn flip_normals(mesh: &PolyMesh, faces: Option<&[FaceId]>) -> Result<Edited> {
    const OP: &str = "flip normals";
    let mask = match faces {
        Some(faces) => face_mask(OP, mesh, faces)?,
        None => vec![true; mesh.face_count()],
    };
    for e in mesh.edges() {
        let (f, g) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
        if f.is_valid() && g.is_valid() && mask[f.index()] != mask[g.index()] {
            let (flipped, kept) = if mask[f.index()] { (f, g) } else { (g, f) };
            return Err(Error::Topology(format!(
                "{OP}: face {} would be flipped but its neighbour face {} not, and neighbours must face the same \
                 way; flip whole connected pieces (select linked first)",
                flipped.0, kept.0
            )));
        }
    }
    let mut draft = Draft::new(mesh, OP);
    let mut ring: Vec<u32> = Vec::new();
    for f in mesh.faces() {
        if !mask[f.index()] {
            draft.keep_face(f);
            continue;
        }
        ring.clear();
        ring.extend(mesh.face_vertices(f).map(|v| v.0));
        ring[1..].reverse();
        draft.push_face(ring.iter().copied(), FaceOrigin::Same(f));
    }
    draft.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::fixtures::{check, counts, cube};
    use crate::{DVec3, VertexId};

    fn volume(m: &PolyMesh) -> f64 {
        m.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| m.position(VertexId(v)));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn flipping_all_turns_the_cage_inside_out_and_back() {
        let cube = cube();
        let flipped = flip_normals(&cube, None).unwrap();
        check(&cube, &flipped);
        assert_eq!(counts(&flipped.mesh), counts(&cube));
        assert!((volume(&flipped.mesh) + 1.0).abs() < 1e-12);
        for f in cube.faces() {
            assert_eq!(flipped.mesh.face_area_vector(f), -cube.face_area_vector(f));
        }
        let back = flip_normals(&flipped.mesh, None).unwrap();
        assert_eq!(back.mesh.polygons(), cube.polygons());
    }

    #[test]
    fn only_whole_pieces_flip() {
        // Two cubes apart: one of them flips alone.
        let one = cube();
        let mut p = one.positions().to_vec();
        p.extend(one.positions().iter().map(|&q| q + DVec3::new(3.0, 0.0, 0.0)));
        let mut faces = one.polygons();
        faces.extend(one.polygons().into_iter().map(|f| f.into_iter().map(|v| v + 8).collect::<Vec<_>>()));
        let two = PolyMesh::from_polygons(p, &faces).unwrap();
        let second: Vec<FaceId> = (6..12).map(FaceId).collect();
        let edited = flip_normals(&two, Some(&second)).unwrap();
        check(&two, &edited);
        assert!(volume(&edited.mesh).abs() < 1e-12);
        let err = flip_normals(&two, Some(&[FaceId(0)])).unwrap_err().to_string();
        assert!(err.contains("face 0 would be flipped but its neighbour face"), "{err}");
        let err = flip_normals(&two, Some(&[])).unwrap_err().to_string();
        assert!(err.contains("nothing selected"), "{err}");
    }
}
