//! Building a [`PolyMesh`] from indexed polygons, and checking its invariants.

use super::{FaceId, HalfedgeId, PolyMesh, VertexId, fresh_topology_generation};
use crate::{DVec3, Error, Result};

pub(super) fn build<F: AsRef<[u32]>>(positions: Vec<DVec3>, faces: &[F]) -> Result<PolyMesh> {
    let mut offsets = Vec::with_capacity(faces.len() + 1);
    let mut indices = Vec::with_capacity(faces.len() * 4);
    offsets.push(0u32);
    for face in faces {
        indices.extend_from_slice(face.as_ref());
        offsets.push(indices.len() as u32);
    }
    build_flat(positions, &offsets, &indices)
}

/// Builds from faces in compressed rows: face `f` is `indices[offsets[f]..offsets[f + 1]]`.
///
/// Twins are matched through per-vertex lists of outgoing corners rather than a hash map, so
/// construction is linear in the number of corners with a small constant (the refinement of a
/// level rebuilds its mesh this way).
pub(super) fn build_flat(positions: Vec<DVec3>, offsets: &[u32], indices: &[u32]) -> Result<PolyMesh> {
    let n = positions.len();
    if n >= u32::MAX as usize / 2 || indices.len() >= u32::MAX as usize / 2 {
        return Err(Error::Input(format!("{n} vertices is more than Taut can index")));
    }
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::Input(format!(
            "vertex {v} has a non-finite coordinate ({:?}); every coordinate must be a finite number",
            positions[v].to_array()
        )));
    }
    let face_count = offsets.len().saturating_sub(1);
    let face = |f: usize| &indices[offsets[f] as usize..offsets[f + 1] as usize];
    for f in 0..face_count {
        let face = face(f);
        if face.len() < 3 {
            return Err(Error::Topology(format!("face {f} has {} vertices; a face needs at least 3", face.len())));
        }
        for (k, &v) in face.iter().enumerate() {
            if v as usize >= n {
                return Err(Error::Input(format!("face {f} refers to vertex {v}, but there are only {n} vertices")));
            }
            if face[..k].contains(&v) {
                return Err(Error::Topology(format!("face {f} uses vertex {v} more than once")));
            }
        }
    }

    // Corner c of the flat list is the directed edge from indices[c] to the next vertex of its face.
    let corners = indices.len();
    let mut corner_face = vec![0u32; corners];
    let mut corner_to = vec![0u32; corners];
    for f in 0..face_count {
        let (a, b) = (offsets[f] as usize, offsets[f + 1] as usize);
        for c in a..b {
            corner_face[c] = f as u32;
            corner_to[c] = indices[if c + 1 == b { a } else { c + 1 }];
        }
    }
    let (out_offsets, out_corners) =
        super::edge_sort::bucket_sort(corners, n, |c| indices[c] as usize, |c| c as u32, 0);
    let outgoing = |v: u32| &out_corners[out_offsets[v as usize] as usize..out_offsets[v as usize + 1] as usize];

    let mut corner_halfedge = vec![HalfedgeId::INVALID; corners];
    let mut halfedge_to: Vec<VertexId> = Vec::with_capacity(corners + corners / 4 + 16);
    for c in 0..corners {
        if corner_halfedge[c].is_valid() {
            continue;
        }
        let (a, b) = (indices[c], corner_to[c]);
        let mut same = outgoing(a).iter().filter(|&&d| corner_to[d as usize] == b);
        let mut opposite = outgoing(b).iter().filter(|&&d| corner_to[d as usize] == a);
        let (first_same, second_same) = (same.next().copied(), same.next().copied());
        let (first_opposite, second_opposite) = (opposite.next().copied(), opposite.next().copied());
        if let Some(other) = second_same.or(second_opposite) {
            let first = if second_same.is_some() { first_same } else { first_opposite };
            let faces_of = |d: Option<u32>| d.map(|d| corner_face[d as usize]);
            return Err(match (first_same, first_opposite) {
                (Some(_), Some(_)) => Error::Topology(format!(
                    "non-manifold edge between vertices {a} and {b}: it is used by faces {}, {} and {}; \
                     every edge may border at most two faces",
                    faces_of(first_same).unwrap(),
                    faces_of(first_opposite).unwrap(),
                    corner_face[other as usize]
                )),
                _ => Error::Topology(format!(
                    "faces {} and {} both run from vertex {} to vertex {}: they are oriented \
                     inconsistently (or the edge is non-manifold); flip one so neighbours run opposite ways",
                    faces_of(first).unwrap(),
                    corner_face[other as usize],
                    indices[other as usize],
                    corner_to[other as usize]
                )),
            });
        }
        let e = (halfedge_to.len() / 2) as u32;
        // Halfedge 2e runs from the smaller index to the larger one.
        let (lo, hi) = (a.min(b), a.max(b));
        halfedge_to.extend([VertexId(hi), VertexId(lo)]);
        corner_halfedge[c] = HalfedgeId(2 * e + u32::from(a > b));
        if let Some(d) = first_opposite {
            corner_halfedge[d as usize] = HalfedgeId(2 * e + u32::from(b > a));
        }
    }
    let nh = halfedge_to.len();
    let mut halfedge_face = vec![FaceId::INVALID; nh];
    let mut halfedge_next = vec![HalfedgeId::INVALID; nh];
    let mut halfedge_prev = vec![HalfedgeId::INVALID; nh];
    let mut face_halfedge = Vec::with_capacity(face_count);
    let mut vertex_halfedge = vec![HalfedgeId::INVALID; n];
    for f in 0..face_count {
        let (a, b) = (offsets[f] as usize, offsets[f + 1] as usize);
        for c in a..b {
            let h = corner_halfedge[c];
            let next = corner_halfedge[if c + 1 == b { a } else { c + 1 }];
            halfedge_face[h.index()] = FaceId(f as u32);
            halfedge_next[h.index()] = next;
            halfedge_prev[next.index()] = h;
            vertex_halfedge[indices[c] as usize] = h;
        }
        face_halfedge.push(corner_halfedge[a]);
    }

    // Link boundary halfedges into loops: the boundary halfedge into vertex v continues with the
    // unique boundary halfedge out of v.
    let mut boundary_out = vec![HalfedgeId::INVALID; n];
    for h in 0..halfedge_to.len() {
        if !halfedge_face[h].is_valid() {
            let h = HalfedgeId::from_index(h);
            let from = halfedge_to[h.twin().index()];
            if boundary_out[from.index()].is_valid() {
                return Err(Error::Topology(format!(
                    "non-manifold vertex {}: two separate fans of faces meet there (the surface pinches \
                     to a point); split the vertex in two",
                    from.0
                )));
            }
            boundary_out[from.index()] = h;
        }
    }
    for h in 0..halfedge_to.len() {
        if !halfedge_face[h].is_valid() {
            let next = boundary_out[halfedge_to[h].index()];
            halfedge_next[h] = next;
            halfedge_prev[next.index()] = HalfedgeId::from_index(h);
        }
    }
    for v in 0..n {
        if boundary_out[v].is_valid() {
            vertex_halfedge[v] = boundary_out[v];
        }
    }

    let mesh = PolyMesh {
        positions,
        vertex_halfedge,
        halfedge_to,
        halfedge_next,
        halfedge_prev,
        halfedge_face,
        face_halfedge,
        generation: 0,
        topology_generation: fresh_topology_generation(),
    };

    // A vertex whose outgoing halfedges are not all reachable by rotation is a pinch of two
    // closed fans (the boundary case was caught above).
    let mut valence = vec![0usize; n];
    for h in 0..mesh.halfedge_count() {
        valence[mesh.from_vertex(HalfedgeId::from_index(h)).index()] += 1;
    }
    for v in mesh.vertices() {
        let reached = mesh.outgoing(v).take(valence[v.index()] + 1).count();
        if reached != valence[v.index()] {
            return Err(Error::Topology(format!(
                "non-manifold vertex {}: separate fans of faces meet there; split the vertex in two",
                v.0
            )));
        }
    }
    Ok(mesh)
}

pub(super) fn validate(mesh: &PolyMesh) -> Result<(), String> {
    let nh = mesh.halfedge_count();
    if !nh.is_multiple_of(2) {
        return Err("odd number of halfedges".into());
    }
    for h in (0..nh).map(HalfedgeId::from_index) {
        let next = mesh.next(h);
        if !next.is_valid() || next.index() >= nh {
            return Err(format!("{h:?} has no next"));
        }
        if mesh.prev(next) != h {
            return Err(format!("prev(next({h:?})) != {h:?}"));
        }
        if mesh.from_vertex(next) != mesh.to_vertex(h) {
            return Err(format!("{h:?} and its next do not share a vertex"));
        }
        if mesh.face(next) != mesh.face(h) {
            return Err(format!("{h:?} and its next lie on different faces"));
        }
        if mesh.to_vertex(h) == mesh.from_vertex(h) {
            return Err(format!("{h:?} is a loop"));
        }
        if mesh.is_boundary_halfedge(h) && mesh.is_boundary_halfedge(h.twin()) {
            return Err(format!("edge {:?} has no face on either side", h.edge()));
        }
    }
    for f in mesh.faces() {
        let h = mesh.face_halfedge(f);
        if mesh.face(h) != f {
            return Err(format!("{f:?}'s halfedge points to another face"));
        }
        if mesh.face_halfedges(f).take(nh + 1).count() > nh {
            return Err(format!("{f:?}'s loop does not close"));
        }
    }
    for v in mesh.vertices() {
        let h = mesh.vertex_halfedge(v);
        if !h.is_valid() {
            continue;
        }
        if mesh.from_vertex(h) != v {
            return Err(format!("{v:?}'s halfedge does not start there"));
        }
        let boundary = mesh.outgoing(v).filter(|&h| mesh.is_boundary_halfedge(h)).count();
        if boundary > 1 || (boundary == 1 && !mesh.is_boundary_halfedge(h)) {
            return Err(format!("{v:?} is a non-manifold boundary vertex"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_grid(n: u32) -> PolyMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(DVec3::new(i as f64, j as f64, 0.0));
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                faces.push(vec![v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        PolyMesh::from_polygons(positions, &faces).unwrap()
    }

    fn cube() -> PolyMesh {
        let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
        let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn cube_normals_are_the_same_at_any_scale_even_subnormal() {
        let unit = cube().vertex_normals();
        for scale in [1e-200, 1e-320, 1e300] {
            let mut small = cube();
            for p in small.positions_mut() {
                *p *= scale;
            }
            let normals = small.vertex_normals();
            for (a, b) in normals.iter().zip(&unit) {
                assert!((*a - *b).length() < 1e-12, "scale {scale:e}: {a} against {b}");
            }
        }
    }

    #[test]
    fn cube_is_a_closed_genus_zero_surface() {
        let m = cube();
        m.validate().unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (8, 12, 6));
        assert_eq!(m.euler_characteristic(), 2);
        assert!(m.is_closed());
        for v in m.vertices() {
            assert_eq!(m.valence(v), 3);
        }
        // Outward normals: the corner (1,1,1) points along (1,1,1).
        let n = m.vertex_normals()[7];
        assert!((n - DVec3::ONE.normalize()).length() < 1e-12);
    }

    #[test]
    fn grid_boundary_and_rings() {
        let m = square_grid(3);
        m.validate().unwrap();
        assert_eq!(m.euler_characteristic(), 1);
        let corner = VertexId(0);
        assert!(m.is_boundary_vertex(corner));
        assert_eq!(m.valence(corner), 2);
        let inner = VertexId(5);
        assert!(!m.is_boundary_vertex(inner));
        let mut ring: Vec<u32> = m.vertex_neighbors(inner).map(|v| v.0).collect();
        ring.sort();
        assert_eq!(ring, vec![1, 4, 6, 9]);
        let boundary_edges = m.edges().filter(|&e| m.is_boundary_edge(e)).count();
        assert_eq!(boundary_edges, 12);
        assert_eq!(m.polygons()[0], vec![0, 1, 5, 4]);
        assert_eq!(m.triangles().len(), 18);
    }

    #[test]
    fn bad_connectivity_is_refused_with_a_message() {
        let p = || vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE];
        let cases: Vec<(Vec<Vec<u32>>, &str)> = vec![
            (vec![vec![0, 1, 7]], "only 5 vertices"),
            (vec![vec![0, 1]], "at least 3"),
            (vec![vec![0, 1, 1, 2]], "more than once"),
            (vec![vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]], "non-manifold edge"),
            (vec![vec![0, 1, 2], vec![0, 1, 3]], "inconsistently"),
            (vec![vec![0, 1, 2], vec![0, 3, 4]], "non-manifold vertex"),
        ];
        for (faces, expected) in cases {
            let err = PolyMesh::from_polygons(p(), &faces).unwrap_err().to_string();
            assert!(err.contains(expected), "{faces:?}: {err}");
        }
        let err = PolyMesh::from_polygons(vec![DVec3::new(f64::NAN, 0.0, 0.0)], &[] as &[Vec<u32>]).unwrap_err();
        assert!(err.to_string().contains("non-finite"));
    }

    #[test]
    fn pinched_closed_fans_are_refused() {
        // Two tetrahedra sharing only vertex 0.
        let mut p = vec![DVec3::ZERO];
        p.extend([DVec3::X, DVec3::Y, DVec3::Z, -DVec3::X, -DVec3::Y, -DVec3::Z]);
        let tet = |a: u32, b: u32, c: u32| vec![vec![0, b, a], vec![0, c, b], vec![0, a, c], vec![a, b, c]];
        let mut faces = tet(1, 2, 3);
        faces.extend(tet(4, 5, 6));
        let err = PolyMesh::from_polygons(p, &faces).unwrap_err().to_string();
        assert!(err.contains("non-manifold vertex 0"), "{err}");
    }

    #[test]
    fn isolated_vertices_are_kept() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
        let m = PolyMesh::from_polygons(p, &[[0, 1, 2]]).unwrap();
        m.validate().unwrap();
        assert!(m.is_isolated(VertexId(3)));
        assert_eq!(m.outgoing(VertexId(3)).count(), 0);
    }
}
