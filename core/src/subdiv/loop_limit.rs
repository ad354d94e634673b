//! The limit-position matrix of a Loop cage (`docs/control-cage.md`, step 2).
//!
//! Row `i` maps the cage to the Loop limit position of vertex `i`: for an interior vertex of
//! valence `k`,
//! ```text
//! β_k = (1/k) (5/8 − (3/8 + ¼ cos(2π/k))²)
//! χ   = 1 / (k + 3/(8 β_k))
//! p∞  = (1 − kχ) p + χ Σ_{j ∈ 1-ring} p_j
//! ```
//! and for a vertex on an open boundary the boundary limit mask `(p_prev + 4 p + p_next) / 6`
//! along its two boundary neighbours (the limit of the boundary rule `(e_prev + 6v + e_next)/8`,
//! which makes each boundary a cubic B-spline curve). A vertex used by no face keeps its
//! position. Creases are not part of this matrix: it describes the smooth surface the control
//! cage fitter builds.

use super::sparse::SparseRows;
use crate::mesh::PolyMesh;
use crate::{Error, Result};

/// `β_k` of Loop's vertex rule for valence `k` (Loop 1987, Warren's form is not used).
pub fn loop_beta(k: usize) -> f64 {
    let k = k as f64;
    let c = 3.0 / 8.0 + 0.25 * (std::f64::consts::TAU / k).cos();
    (5.0 / 8.0 - c * c) / k
}

/// `χ_k` of the interior limit mask for valence `k`.
pub fn loop_limit_chi(k: usize) -> f64 {
    1.0 / (k as f64 + 3.0 / (8.0 * loop_beta(k)))
}

/// The sparse `n × n` limit-position matrix of a triangle cage; an error naming the first face
/// that is not a triangle.
pub fn loop_limit_matrix(cage: &PolyMesh) -> Result<SparseRows> {
    if let Some(f) = cage.faces().find(|&f| cage.face_valence(f) != 3) {
        return Err(Error::Topology(format!(
            "Loop subdivision needs a triangle cage, but face {} has {} sides; triangulate the cage first",
            f.0,
            cage.face_valence(f)
        )));
    }
    let n = cage.vertex_count();
    let mut m = SparseRows::with_columns(n);
    for v in cage.vertices() {
        if cage.is_isolated(v) {
            m.push_row([(v.0, 1.0)]);
        } else if cage.is_boundary_vertex(v) {
            let out = cage.vertex_halfedge(v);
            let next = cage.to_vertex(out);
            let prev = cage.from_vertex(cage.prev(out));
            m.push_row([(prev.0, 1.0 / 6.0), (v.0, 4.0 / 6.0), (next.0, 1.0 / 6.0)]);
        } else {
            let k = cage.valence(v);
            let chi = loop_limit_chi(k);
            m.push_row(
                std::iter::once((v.0, 1.0 - k as f64 * chi)).chain(cage.vertex_neighbors(v).map(|u| (u.0, chi))),
            );
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;

    fn octahedron() -> PolyMesh {
        let p = vec![DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        let faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn regular_mask_is_one_half_and_one_twelfth() {
        // The known regular Loop limit mask: 1/2 at the centre, 1/12 on each of six neighbours.
        assert!((loop_beta(6) - 1.0 / 16.0).abs() < 1e-15);
        assert!((loop_limit_chi(6) - 1.0 / 12.0).abs() < 1e-15);
    }

    #[test]
    fn octahedron_limit_points_are_symmetric_and_affine() {
        let cage = octahedron();
        let m = loop_limit_matrix(&cage).unwrap();
        assert_eq!(m.row_count(), 6);
        for s in m.row_sums() {
            assert!((s - 1.0).abs() < 1e-15);
        }
        // Valence 4 by hand: β = (5/8 − (3/8)²)/4 = 31/256, χ = 1/(4 + 3·256/(8·31)) = 31/220.
        let chi = 31.0 / 220.0;
        let limit = m.apply(cage.positions());
        // Vertex X: (1 − 4χ)·1 along x; its neighbours ±Y, ±Z cancel.
        assert!((limit[0] - DVec3::new(1.0 - 4.0 * chi, 0.0, 0.0)).length() < 1e-15);
        // An affine map commutes with the matrix.
        let f = |p: DVec3| DVec3::new(2.0 * p.x - p.z + 1.0, 3.0 * p.y, p.x + 0.5);
        let moved: Vec<DVec3> = cage.positions().iter().map(|&p| f(p)).collect();
        for (a, b) in m.apply(&moved).iter().zip(&limit) {
            assert!((*a - f(*b)).length() < 1e-14);
        }
    }

    #[test]
    fn boundary_rows_use_the_boundary_mask_and_quads_are_refused() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
        let open = PolyMesh::from_polygons(p.clone(), &[[0, 1, 2], [1, 3, 2]]).unwrap();
        let m = loop_limit_matrix(&open).unwrap();
        let limit = m.apply(open.positions());
        // Vertex 0's boundary neighbours are 1 and 2.
        assert!((limit[0] - (DVec3::X + DVec3::Y) / 6.0).length() < 1e-15);
        let quad = PolyMesh::from_polygons(p, &[[0, 1, 3, 2]]).unwrap();
        let err = loop_limit_matrix(&quad).unwrap_err().to_string();
        assert!(err.contains("face 0 has 4 sides") && err.contains("triangulate"), "{err}");
    }
}
