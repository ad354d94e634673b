//! How close the patches lie to the Catmull–Clark limit surface they were built from
//! (`docs/curve-mesh-gregory.md` §7; the seed paper's §5, 0.16 for its dog model).
//!
//! Two levels below the curve mesh, each of its quads holds 3 × 3 interior vertices: the face
//! point (at patch parameters `(½, ½)`), the four edge points between it and the face's edge
//! midpoints (`(½, ¼)`, `(¾, ½)`, `(½, ¾)`, `(¼, ½)`) and the four face points of the quarter
//! quads (`(¼, ¼)`, `(¾, ¼)`, `(¾, ¾)`, `(¼, ¾)`). Their limit points are measured against the
//! patch by the closest point ([`closest_point`]: Gauss–Newton from that parameter point, clamped
//! to the unit square), so the figure is a true point-to-surface distance, not a parametric
//! one. Weak spot: Gauss–Newton finds the nearest *local* minimum; from a start this close it is
//! the global one unless the patch folds back within a quarter of its size.

use super::curve_mesh::CurveMesh;
use super::patch::GregoryPatch;
use crate::mesh::FaceId;
use crate::subdiv::Refinement;
use crate::{DVec3, Result};
use rayon::prelude::*;

/// The closeness figure of a curve mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LimitCloseness {
    /// Largest distance from an interior limit point to its patch.
    pub max_distance: f64,
    /// The patch where it occurs.
    pub worst_patch: Option<FaceId>,
    /// How many limit points were measured (9 per patch).
    pub points: usize,
}

/// The point of `patch` closest to `p`, starting from `(u, v)`: `(u, v, distance)`.
pub fn closest_point(patch: &GregoryPatch, p: DVec3, start: (f64, f64)) -> (f64, f64, f64) {
    let (mut u, mut v) = start;
    let mut best = patch.point(u, v).distance_squared(p);
    for _ in 0..32 {
        let (s, su, sv) = patch.first_derivatives(u, v);
        let r = s - p;
        let (a, b, c) = (su.dot(su), su.dot(sv), sv.dot(sv));
        let det = a * c - b * b;
        if det <= 1e-30 * a * c || det == 0.0 {
            break;
        }
        let (g1, g2) = (su.dot(r), sv.dot(r));
        let (du, dv) = ((c * g1 - b * g2) / det, (a * g2 - b * g1) / det);
        // Damped step: halve until the distance drops (or give up).
        let mut step = 1.0;
        let mut moved = false;
        while step > 1e-6 {
            let (nu, nv) = ((u - step * du).clamp(0.0, 1.0), (v - step * dv).clamp(0.0, 1.0));
            let d = patch.point(nu, nv).distance_squared(p);
            if d < best {
                moved = (nu - u).abs() + (nv - v).abs() > 1e-15;
                (u, v, best) = (nu, nv, d);
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    (u, v, best.sqrt())
}

/// The 3 × 3 interior vertices of each patch two levels down with their patch parameters,
/// measured against the patches. `refinement` refines the curve mesh's topology twice and
/// `limit` holds its level-2 limit points.
pub(crate) fn interior_closeness(mesh: &CurveMesh, refinement: &Refinement, limit: &[DVec3]) -> Result<LimitCloseness> {
    let per_patch: Vec<f64> = mesh
        .topology()
        .faces()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&f| {
            let points = interior_points(refinement, f)?;
            Ok(points.iter().map(|&(w, uv)| closest_point(mesh.patch(f), limit[w.index()], uv).2).fold(0.0, f64::max))
        })
        .collect::<Result<_>>()?;
    let mut out = LimitCloseness { points: 9 * per_patch.len(), ..Default::default() };
    for (f, &d) in per_patch.iter().enumerate() {
        if out.worst_patch.is_none() || d > out.max_distance {
            out.max_distance = d;
            out.worst_patch = Some(FaceId(f as u32));
        }
    }
    Ok(out)
}

/// Level-2 vertices inside quad `f` of level 0 with their parameters in `f`'s patch (corner 0 at
/// the start of `face_halfedge(f)`, `u` along it).
pub fn interior_points(refinement: &Refinement, f: FaceId) -> Result<[(crate::VertexId, (f64, f64)); 9]> {
    let (m0, s1, m1, s2) = (refinement.mesh(0), refinement.split(1), refinement.mesh(1), refinement.split(2));
    let h0 = m0.face_halfedge(f);
    let hs = [h0, m0.next(h0), m0.next(m0.next(h0)), m0.prev(h0)];
    let centre = s1.face_point(f).ok_or_else(|| crate::Error::Topology(format!("face {} has no face point", f.0)))?;
    let mids = hs.map(|h| s1.edge_point(h.edge()));
    let mid_uv = [(0.5, 0.25), (0.75, 0.5), (0.5, 0.75), (0.25, 0.5)];
    let quarter_uv = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)];
    let mut out = [(centre, (0.5, 0.5)); 9];
    for k in 0..4 {
        // The level-1 edge from the k-th edge midpoint to the face point, and the quarter quad
        // (c_k, m_k, centre, m_{k−1}) left of it.
        let h = m1
            .find_halfedge(mids[k], centre)
            .ok_or_else(|| crate::Error::Topology(format!("face {} split oddly", f.0)))?;
        out[1 + k] = (s2.edge_point(h.edge()), mid_uv[k]);
        let quarter = m1.face(h);
        let fp = s2.face_point(quarter).ok_or_else(|| crate::Error::Topology(format!("face {} split oddly", f.0)))?;
        out[5 + k] = (fp, quarter_uv[k]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_on_a_flat_patch_is_the_foot_of_the_perpendicular() {
        let net: [[DVec3; 4]; 4] = std::array::from_fn(|i| {
            std::array::from_fn(|j| DVec3::new(i as f64 + 0.1 * (j as f64).powi(2), j as f64, 0.0))
        });
        let patch = GregoryPatch::from_bezier(net);
        let target = patch.point(0.3, 0.6);
        let (u, v, d) = closest_point(&patch, target + DVec3::new(0.0, 0.0, 0.25), (0.5, 0.5));
        assert!((u - 0.3).abs() < 1e-9 && (v - 0.6).abs() < 1e-9, "{u} {v}");
        assert!((d - 0.25).abs() < 1e-12);
        // Outside the square the nearest point is on the rim.
        let (u, _, _) = closest_point(&patch, DVec3::new(-2.0, 1.5, 0.0), (0.5, 0.5));
        assert_eq!(u, 0.0);
    }
}
