//! The Catmull–Clark limit surface at the middle of every curve, for the cross-boundary field
//! that both patches on a curve share (`docs/curve-mesh-gregory.md`, "Where we depart").
//!
//! The middle of a curve is the middle vertex `w` of its edge's level-2 chain: its limit normal
//! turns the field `b(t)` (see [`super::chiyokura_kimura::side_inner_points`]), and the limit
//! surface's cross derivative there sets the field's length `|b(½)|`. `w` is an edge point of
//! level 1, so it has valence 4 and the four level-2 faces around it are regular: the limit
//! surface there is the uniform bicubic B-spline of the level-2 points, and its derivative across
//! the curve at `w` is the B-spline's, `(4 (x − y) + Σ o_x − Σ o_y)/12` per level-2 step, where `x`
//! and `y` are `w`'s neighbours off the chain and `o_x`, `o_y` the far corners of the faces on
//! their sides. A patch spans four level-2 steps, so its parameter's derivative is four times that.
//!
//! A patch's cross derivative at the middle of its side is `k(½) |b(½)| b̂ + h(½) C'(½)`, with
//! `k(½)` fixed by its corner legs; the length shared by the curve's two patches is the least-
//! squares fit of their `k(½) |b(½)|` to the limit surface's `b̂` components, kept between ¼ and
//! 4. A curve on an open boundary, or one whose fit is not positive, keeps the linear field's
//! length.

use super::chiyokura_kimura::{CurveMiddle, middle_factor, split};
use super::curve_mesh::CurveMesh;
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::subdiv::{RefinedPositions, Refinement};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

/// The bounds on a fitted `|b(½)|` (the ends are unit; the bundled cages fit between 0.63 and
/// 1.62): a patch whose `k(½)` nearly vanishes cannot ask for a runaway bulge.
const MIN_LENGTH: f64 = 0.25;
const MAX_LENGTH: f64 = 4.0;

/// The limit surface at the middle of every curve of `mesh`, whose topology `refinement`
/// refined twice (`refined` holds its level-2 positions and limit normals).
pub(crate) fn limit_middles(
    mesh: &CurveMesh,
    refinement: &Refinement,
    refined: &RefinedPositions,
) -> Result<Vec<CurveMiddle>> {
    mesh.topology()
        .edges()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&e| {
            let chain = refinement.cage_edge_chain(e, 2)?;
            let w = chain[chain.len() / 2];
            let normal = refined.normals[w.index()];
            let length = field_length(mesh, refinement, refined.finest(), e, &chain, normal)?;
            Ok(CurveMiddle { normal, length })
        })
        .collect()
}

/// The fitted `|b(½)|` of curve `e` (chain `chain` at level 2), or `None` (see the module).
fn field_length(
    mesh: &CurveMesh,
    refinement: &Refinement,
    level2: &[DVec3],
    e: EdgeId,
    chain: &[VertexId],
    normal: DVec3,
) -> Result<Option<f64>> {
    let t = mesh.topology();
    if t.is_boundary_edge(e) {
        return Ok(None);
    }
    let (s1, m1, s2) = (refinement.split(1), refinement.mesh(1), refinement.split(2));
    let oddly = || Error::Topology(format!("curve {} split oddly", e.0));
    let (mut num, mut den) = (0.0, 0.0);
    for h in [e.halfedge(0), e.halfedge(1)] {
        let f = t.face(h);
        let k = t.face_halfedges(f).position(|g| g == h).ok_or_else(oddly)?;
        let b = mesh.patch_boundary(f);
        let (side, q) = (b.sides[k], b.sides[k].points);
        let a0 = 3.0 * (b.sides[(k + 3) % 4].points[2] - q[0]);
        let a1 = 3.0 * (b.sides[(k + 1) % 4].points[1] - q[3]);
        let Some((half, k_mid)) = middle_factor(&side, b.normals[k], b.normals[(k + 1) % 4], normal, a0, a1) else {
            return Ok(None);
        };
        // The level-2 vertex next to the middle, inside f.
        let centre = s1.face_point(f).ok_or_else(oddly)?;
        let inward = m1.find_halfedge(s1.edge_point(e), centre).ok_or_else(oddly)?;
        let x = s2.edge_point(inward.edge());
        let Some(target) = cross_derivative(refinement.mesh(2), level2, chain, x) else {
            return Ok(None);
        };
        let (alpha, _) = split(4.0 * target, half, side.derivative(0.5));
        num += k_mid * alpha;
        den += k_mid * k_mid;
    }
    let length = num / den;
    Ok((length.is_finite() && length > 0.0).then(|| length.clamp(MIN_LENGTH, MAX_LENGTH)))
}

/// The limit surface's derivative at the chain's middle `w` towards its neighbour `x`, per
/// level-2 step (the regular B-spline mask; `None` unless `w` has valence 4).
fn cross_derivative(m: &PolyMesh, p: &[DVec3], chain: &[VertexId], x: VertexId) -> Option<DVec3> {
    let w = chain[chain.len() / 2];
    let (along_a, along_b) = (chain[chain.len() / 2 - 1], chain[chain.len() / 2 + 1]);
    if m.is_boundary_vertex(w) || m.valence(w) != 4 {
        return None;
    }
    let y = m.vertex_neighbors(w).find(|&v| v != x && v != along_a && v != along_b)?;
    let mut d = 4.0 * (p[x.index()] - p[y.index()]);
    for h in m.outgoing(w) {
        let far = p[m.to_vertex(m.next(h)).index()];
        if m.to_vertex(h) == x || m.from_vertex(m.prev(h)) == x { d += far } else { d -= far }
    }
    Some(d / 12.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cross_derivative_is_the_bsplines_at_a_knot() {
        // A 7 × 7 grid of points over a smooth height field; at vertex (3, 3) the uniform bicubic
        // B-spline's derivative along v, per grid step, is Σ N_i(0) N'_j(0) P_ij.
        let height = |i: f64, j: f64| 0.3 * (0.7 * i).sin() * (0.4 * j + 0.2).cos() + 0.05 * i * j;
        let id = |i: usize, j: usize| (7 * i + j) as u32;
        let points: Vec<DVec3> = (0..49)
            .map(|k| {
                let (i, j) = ((k / 7) as f64, (k % 7) as f64);
                DVec3::new(i + 0.1 * j, j, height(i, j))
            })
            .collect();
        let faces: Vec<Vec<u32>> = (0..6)
            .flat_map(|i| (0..6).map(move |j| vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
            .collect();
        let mesh = PolyMesh::from_polygons(points.clone(), &faces).unwrap();
        let chain = [VertexId(id(2, 3)), VertexId(id(3, 3)), VertexId(id(4, 3))];
        let d = cross_derivative(&mesh, &points, &chain, VertexId(id(3, 4))).unwrap();
        let (n, dn) = ([1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0], [-0.5, 0.0, 0.5]);
        let mut expected = DVec3::ZERO;
        for a in 0..3 {
            for b in 0..3 {
                expected += n[a] * dn[b] * points[id(2 + a, 2 + b) as usize];
            }
        }
        assert!(d.distance(expected) < 1e-14, "{d} vs {expected}");
        // Towards the other side it is the opposite; a vertex of another valence has none.
        let back = cross_derivative(&mesh, &points, &chain, VertexId(id(3, 2))).unwrap();
        assert!(back.distance(-expected) < 1e-14);
        let edge = [VertexId(id(0, 2)), VertexId(id(0, 3)), VertexId(id(0, 4))];
        assert!(cross_derivative(&mesh, &points, &edge, VertexId(id(1, 3))).is_none());
    }
}
