//! One Loop 4-to-1 refinement step of a triangle cage, as a stencil matrix (Loop 1987).
//!
//! The fitter needs one step for the paper's volume measure (Table 1: the volume of the cage
//! after one subdivision) and a few steps to sample the limit surface. Every triangle is split
//! into four through new points on its edges; with `k` the valence and `β_k` Loop's weight
//! ([`loop_beta`](crate::subdiv::loop_limit::loop_beta)):
//! ```text
//! old interior vertex   (1 − kβ_k) v + β_k Σ ring
//! old boundary vertex   (v_prev + 6 v + v_next) / 8
//! interior edge a–b     3/8 (a + b) + 1/8 (c + d)     (c, d the opposite corners)
//! boundary edge a–b     (a + b) / 2
//! ```
//! The boundary rules make each open border a cubic B-spline curve, matching the boundary limit
//! mask of [`loop_limit_matrix`](crate::subdiv::loop_limit_matrix). The rules are the
//! subdivision module's ([`Refinement`] in the Loop scheme, no creases); this file only gives
//! the fitter the one step it needs with its stencil matrix, and the refined mesh of a few steps.
//! The refined mesh numbers the old vertices first (vertex `i` stays `i`), then the edge points.

use crate::Result;
use crate::mesh::PolyMesh;
use crate::subdiv::{RefinedPositions, Refinement, Scheme, SparseRows};

/// One refinement step: the refined mesh (positions included) and the stencil matrix `S` with
/// `refined = S · cage` (rows: refined vertices, columns: cage vertices).
#[derive(Clone, Debug)]
pub struct LoopStep {
    /// The refined triangle mesh.
    pub mesh: PolyMesh,
    /// The stencils of its vertices over the cage's vertices.
    pub stencil: SparseRows,
}

/// Refines a triangle cage once; an error naming the first face that is not a triangle.
pub fn loop_step(cage: &PolyMesh) -> Result<LoopStep> {
    let refinement = Refinement::new(cage, Scheme::Loop, &[], 1)?;
    let stencil = refinement.stencils(1).clone();
    let mesh = refinement.surface(&stencil.apply(cage.positions()));
    Ok(LoopStep { mesh, stencil })
}

/// Refines `levels` times and returns the finest mesh.
pub fn refine(cage: &PolyMesh, levels: u32) -> Result<PolyMesh> {
    let refinement = Refinement::new(cage, Scheme::Loop, &[], levels)?;
    let mut positions = RefinedPositions::default();
    refinement.evaluate_levels(cage.positions(), &mut positions)?;
    Ok(refinement.surface(positions.finest()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;
    use crate::subdiv::loop_limit_matrix;

    fn octahedron() -> PolyMesh {
        let p = vec![DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        let faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn octahedron_step_counts_rules_and_closedness() {
        let cage = octahedron();
        let step = loop_step(&cage).unwrap();
        step.mesh.validate().unwrap();
        assert_eq!((step.mesh.vertex_count(), step.mesh.face_count()), (6 + 12, 32));
        assert!(step.mesh.is_closed());
        assert_eq!(step.mesh.euler_characteristic(), 2);
        for s in step.stencil.row_sums() {
            assert!((s - 1.0).abs() < 1e-15);
        }
        // By hand: vertex X, valence 4, β = 31/256; the ring ±Y, ±Z cancels.
        assert!((step.mesh.position(crate::VertexId(0)) - DVec3::X * (1.0 - 4.0 * 31.0 / 256.0)).length() < 1e-15);
        // Edge X–Y: 3/8 (X + Y) + 1/8 (Z − Z).
        let e = cage.find_halfedge(crate::VertexId(0), crate::VertexId(2)).unwrap().edge();
        let p = step.mesh.position(crate::VertexId(6 + e.0));
        assert!((p - DVec3::new(0.375, 0.375, 0.0)).length() < 1e-15);
    }

    #[test]
    fn limit_positions_are_invariant_under_refinement() {
        // A cage and its refinement have the same limit surface, so the old vertices' limit
        // points agree (up to rounding): an independent check of both stencils and masks.
        let mut cage = octahedron();
        for (k, p) in cage.positions_mut().iter_mut().enumerate() {
            *p *= 1.0 + 0.1 * k as f64;
        }
        let coarse = loop_limit_matrix(&cage).unwrap().apply(cage.positions());
        let fine_mesh = loop_step(&cage).unwrap().mesh;
        let fine = loop_limit_matrix(&fine_mesh).unwrap().apply(fine_mesh.positions());
        for (a, b) in coarse.iter().zip(&fine) {
            assert!((*a - *b).length() < 1e-12, "{a} vs {b}");
        }
        // The same on an open strip, where the boundary rules apply.
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.3, 0.0), DVec3::Y, DVec3::new(1.0, 1.2, 0.4), DVec3::ONE];
        let open = PolyMesh::from_polygons(p, &[[0, 1, 3], [1, 4, 3], [1, 2, 4], [2, 5, 4]]).unwrap();
        let coarse = loop_limit_matrix(&open).unwrap().apply(open.positions());
        let fine_mesh = loop_step(&open).unwrap().mesh;
        let fine = loop_limit_matrix(&fine_mesh).unwrap().apply(fine_mesh.positions());
        for (a, b) in coarse.iter().zip(&fine) {
            assert!((*a - *b).length() < 1e-12, "{a} vs {b}");
        }
    }
}
