//! Splitting every polygon of a cage into triangles, so Loop subdivision can take it.
//!
//! No vertex is added or moved, so vertex `i` stays vertex `i`; the triangles of face `f` come in
//! place of `f`, in face order. Two ways:
//! - [`Triangulation::Fan`]: the triangles `(c0, c_k, c_{k+1})` from each face's first corner.
//! - [`Triangulation::ShortestDiagonal`]: cut each polygon along its shortest diagonal and recurse
//!   on the two parts (a quad is split along its shorter diagonal). This avoids the long slivers a
//!   fan makes in elongated faces.
//!
//! Weak spots: neither checks that a diagonal lies inside a non-convex face, and a diagonal that
//! is already an edge of the cage (two faces sharing two non-adjacent corners) makes a
//! non-manifold result, which is refused with the mesh builder's message.

use crate::mesh::PolyMesh;
use crate::{DVec3, Result};

/// How polygons are split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Triangulation {
    /// A fan from each face's first corner.
    Fan,
    /// Shortest diagonals first.
    #[default]
    ShortestDiagonal,
}

/// `mesh` with every face split into triangles.
pub fn triangulate(mesh: &PolyMesh, how: Triangulation) -> Result<PolyMesh> {
    let p = mesh.positions();
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(2 * mesh.face_count());
    let mut ring = Vec::new();
    for f in mesh.faces() {
        ring.clear();
        ring.extend(mesh.face_vertices(f).map(|v| v.0));
        match how {
            Triangulation::Fan => {
                for k in 1..ring.len() - 1 {
                    triangles.push([ring[0], ring[k], ring[k + 1]]);
                }
            }
            Triangulation::ShortestDiagonal => split_shortest(p, &ring, &mut triangles),
        }
    }
    PolyMesh::from_polygons(p.to_vec(), &triangles)
}

/// Splits polygon `ring` (vertex indices in order) along its shortest diagonal, recursively.
fn split_shortest(p: &[DVec3], ring: &[u32], out: &mut Vec<[u32; 3]>) {
    let n = ring.len();
    if n == 3 {
        out.push([ring[0], ring[1], ring[2]]);
        return;
    }
    let length = |i: usize, j: usize| (p[ring[i] as usize] - p[ring[j] as usize]).length_squared();
    let mut best = (0, 2);
    for i in 0..n {
        for j in i + 2..n {
            if (i == 0 && j == n - 1) || length(i, j) >= length(best.0, best.1) {
                continue;
            }
            best = (i, j);
        }
    }
    let (i, j) = best;
    let first: Vec<u32> = ring[i..=j].to_vec();
    let second: Vec<u32> = ring[j..].iter().chain(&ring[..=i]).copied().collect();
    split_shortest(p, &first, out);
    split_shortest(p, &second, out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::VertexId;

    fn long_hexagon_prism() -> PolyMesh {
        // A prism over an elongated hexagon: two hexagon caps and six quads.
        let base = [(0.0, 0.0), (4.0, 0.0), (5.0, 1.0), (4.0, 2.0), (0.0, 2.0), (-1.0, 1.0)];
        let mut p = Vec::new();
        for z in [0.0, 1.0] {
            p.extend(base.iter().map(|&(x, y)| DVec3::new(x, y, z)));
        }
        let mut faces: Vec<Vec<u32>> = vec![(0..6).rev().collect(), (6..12).collect()];
        for k in 0..6 {
            faces.push(vec![k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k]);
        }
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn triangulations_keep_vertices_area_and_orientation() {
        let m = long_hexagon_prism();
        for how in [Triangulation::Fan, Triangulation::ShortestDiagonal] {
            let t = triangulate(&m, how).unwrap();
            t.validate().unwrap();
            assert_eq!(t.vertex_count(), m.vertex_count());
            assert_eq!(t.face_count(), 2 * 4 + 6 * 2);
            assert_eq!(t.euler_characteristic(), m.euler_characteristic());
            assert!(t.faces().all(|f| t.face_valence(f) == 3));
            // Planar faces: the area vectors add up to the original ones.
            let total = |mesh: &PolyMesh| mesh.faces().map(|f| mesh.face_area_vector(f).abs()).sum::<DVec3>();
            assert!((total(&t) - total(&m)).length() < 1e-12);
            assert_eq!(t.position(VertexId(3)), m.position(VertexId(3)));
        }
    }

    #[test]
    fn shortest_diagonal_avoids_slivers() {
        let m = long_hexagon_prism();
        let longest = |mesh: &PolyMesh| mesh.edges().map(|e| mesh.edge_length(e)).fold(0.0, f64::max);
        let fan = triangulate(&m, Triangulation::Fan).unwrap();
        let short = triangulate(&m, Triangulation::ShortestDiagonal).unwrap();
        // The fan from corner 0 of a cap reaches across to corner 3 (length √(16 + 4)); the
        // shortest-diagonal split never takes a diagonal longer than needed.
        assert!(longest(&fan) > longest(&short), "{} vs {}", longest(&fan), longest(&short));
        // A quad is split along its shorter diagonal: side quad 0 is the 4 × 1 rectangle, whose
        // diagonals are equal, so check a rhombus instead.
        let p = vec![DVec3::ZERO, DVec3::new(2.0, 1.0, 0.0), DVec3::new(0.0, 2.0, 0.0), DVec3::new(-2.0, 1.0, 0.0)];
        let rhombus = PolyMesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap();
        let t = triangulate(&rhombus, Triangulation::ShortestDiagonal).unwrap();
        assert!(t.find_halfedge(VertexId(0), VertexId(2)).is_some());
    }
}
