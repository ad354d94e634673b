//! Joining pairs of triangles into quads across their shared edge.
//!
//! Triangles `a, b, c` and `b, a, d` across edge `a–b` make the quad `a, d, b, c`. Each candidate
//! pair is scored (lower is better) by
//!
//! ```text
//! score = (1 − cos fold) / 2 + Σ_corners |cos θ_k| / 4
//! ```
//!
//! where `fold` is the angle between the two triangles' normals (the first term is 0 when the
//! quad is planar, 1/2 at a right-angled fold) and `θ_k` are the quad's four corner angles (the
//! sum is 0 for a rectangle, 1/2 for a 60° rhombus): planarity and squareness weigh about
//! equally, each from 0 to 1, and no trigonometry is needed. Pairs folded more than
//! [`JoinParams::max_fold`], and pairs whose quad would not be convex (a corner turning the
//! wrong way), are never joined. The rest are taken greedily, best score first (ties by edge
//! number, scores within 1e-9 counting as equal), each triangle at most once — the way Blender's
//! "triangles to quads" works, and like it not an optimal matching. The quad keeps the values of
//! the lower-numbered triangle.

use super::Edited;
use super::draft::{Draft, edge_mask};
use super::provenance::FaceOrigin;
use crate::mesh::{EdgeId, FaceId, PolyMesh};
use crate::{DVec3, Error, Result};
use std::f64::consts::PI;

/// Limits on which triangle pairs are joined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JoinParams {
    /// Largest angle between the two triangles' normals, in radians (default 40°).
    pub max_fold: f64,
}

impl Default for JoinParams {
    fn default() -> Self {
        JoinParams { max_fold: 40f64.to_radians() }
    }
}

/// The score of joining the two triangles across `e` (see the module docs), or `None` when they
/// are not two triangles, are folded too far or would make a non-convex quad.
pub fn join_score(mesh: &PolyMesh, e: EdgeId, params: &JoinParams) -> Option<f64> {
    pair_score(mesh, e, least_cos_fold(params))
}

fn least_cos_fold(params: &JoinParams) -> f64 {
    params.max_fold.min(PI).cos() - 1e-12
}

fn pair_score(mesh: &PolyMesh, e: EdgeId, least_cos_fold: f64) -> Option<f64> {
    quad_across(mesh, e).and_then(|(quad, _)| score(mesh, &quad, least_cos_fold))
}

/// Joins triangles in pairs across the selected edges (every edge when `edges` is `None`).
pub fn join_triangles(mesh: &PolyMesh, edges: Option<&[EdgeId]>, params: &JoinParams) -> Result<Edited> {
    const OP: &str = "join triangles";
    if !(params.max_fold.is_finite() && params.max_fold >= 0.0) {
        return Err(Error::Input(format!(
            "{OP}: the largest fold angle must be a finite angle ≥ 0, not {:?}",
            params.max_fold
        )));
    }
    let mask = match edges {
        Some(edges) => edge_mask(OP, mesh, edges)?,
        None => vec![true; mesh.edge_count()],
    };
    let least_cos = least_cos_fold(params);
    // Scores (0 to 2) within 1e-9 of each other tie, by edge number, so rounding never reorders
    // the pairs of a symmetric cage; score and edge pack into one sort key.
    let mut candidates: Vec<u64> = mesh
        .edges()
        .filter(|e| mask[e.index()])
        .filter_map(|e| pair_score(mesh, e, least_cos).map(|s| ((s * 1e9).round() as u64) << 32 | u64::from(e.0)))
        .collect();
    candidates.sort_unstable();
    let mut partner: Vec<Option<(EdgeId, bool)>> = vec![None; mesh.face_count()];
    for e in candidates.iter().map(|&key| EdgeId(key as u32)) {
        let (f, g) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
        if partner[f.index()].is_none() && partner[g.index()].is_none() {
            partner[f.index()] = Some((e, f < g));
            partner[g.index()] = Some((e, g < f));
        }
    }
    if partner.iter().all(Option::is_none) {
        return Ok(super::draft::unchanged(mesh));
    }
    let mut draft = Draft::new(mesh, OP);
    for f in mesh.faces() {
        match partner[f.index()] {
            None => draft.keep_face(f),
            Some((e, true)) => {
                let (quad, _) = quad_across(mesh, e).expect("a candidate edge has a quad across it");
                draft.push_face(quad, FaceOrigin::Merged(f));
            }
            Some((_, false)) => {}
        }
    }
    draft.finish()
}

/// The quad `a, d, b, c` across `e` and its two triangles, when both sides are triangles.
fn quad_across(mesh: &PolyMesh, e: EdgeId) -> Option<([u32; 4], [FaceId; 2])> {
    let h = e.halfedge(0);
    let (f, g) = (mesh.face(h), mesh.face(h.twin()));
    let triangle = |h: crate::HalfedgeId| mesh.next(mesh.next(mesh.next(h))) == h;
    if !f.is_valid() || !g.is_valid() || !triangle(h) || !triangle(h.twin()) {
        return None;
    }
    let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
    let c = mesh.to_vertex(mesh.next(h));
    let d = mesh.to_vertex(mesh.next(h.twin()));
    (c != d).then_some(([a.0, d.0, b.0, c.0], [f, g]))
}

fn score(mesh: &PolyMesh, quad: &[u32; 4], least_cos_fold: f64) -> Option<f64> {
    let p = quad.map(|v| mesh.position(crate::VertexId(v)));
    // Triangles a, b, c and b, a, d, as corners of the quad a, d, b, c.
    let n1 = (p[2] - p[0]).cross(p[3] - p[0]);
    let n2 = (p[0] - p[2]).cross(p[1] - p[2]);
    if n1.length() == 0.0 || n2.length() == 0.0 {
        return None;
    }
    let cos_fold = n1.dot(n2) / (n1.length() * n2.length());
    if cos_fold < least_cos_fold {
        return None;
    }
    let normal: DVec3 = n1.normalize() + n2.normalize();
    let mut squareness = 0.0;
    for k in 0..4 {
        let (prev, v, next) = (p[(k + 3) % 4], p[k], p[(k + 1) % 4]);
        if (v - prev).cross(next - v).dot(normal) <= 0.0 {
            return None;
        }
        let (u, w) = (prev - v, next - v);
        squareness += (u.dot(w) / (u.length() * w.length())).abs();
    }
    Some((1.0 - cos_fold) / 2.0 + squareness / 4.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VertexId;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, house};
    use crate::mesh::edit::{Triangulation, triangulate};

    fn sorted_faces(m: &PolyMesh) -> Vec<Vec<u32>> {
        let mut faces: Vec<Vec<u32>> = m
            .polygons()
            .into_iter()
            .map(|mut f| {
                f.sort();
                f
            })
            .collect();
        faces.sort();
        faces
    }

    #[test]
    fn joining_undoes_a_triangulation() {
        for (mesh, method) in [(cube(), Triangulation::Fan), (grid(3), Triangulation::ShortestDiagonal)] {
            let tris = triangulate(&mesh, None, method).unwrap().mesh;
            let edited = join_triangles(&tris, None, &JoinParams::default()).unwrap();
            check(&tris, &edited);
            assert_eq!(counts(&edited.mesh), counts(&mesh));
            assert_eq!(sorted_faces(&edited.mesh), sorted_faces(&mesh));
        }
    }

    #[test]
    fn the_score_has_its_closed_form() {
        // A unit square cut along a diagonal scores 0; a 60° rhombus scores 4 · cos 60° / 4 = 1/2.
        for (points, expected) in [
            (vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], 0.0),
            (
                vec![
                    DVec3::ZERO,
                    DVec3::X,
                    DVec3::new(1.5, 3f64.sqrt() / 2.0, 0.0),
                    DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0),
                ],
                0.5,
            ),
        ] {
            let m = PolyMesh::from_polygons(points, &[[0, 1, 2], [0, 2, 3]]).unwrap();
            let e = m.find_halfedge(VertexId(0), VertexId(2)).unwrap().edge();
            let s = join_score(&m, e, &JoinParams::default()).unwrap();
            assert!((s - expected).abs() < 1e-12, "{s} vs {expected}");
        }
        // Folded by 90° along the diagonal: (1 − cos 90°) / 2 = 1/2 plus the corners' term.
        let m = PolyMesh::from_polygons(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Z],
            &[[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let e = m.find_halfedge(VertexId(0), VertexId(2)).unwrap().edge();
        assert_eq!(join_score(&m, e, &JoinParams::default()), None);
        let wide = JoinParams { max_fold: std::f64::consts::PI };
        assert!(join_score(&m, e, &wide).unwrap() > 0.5);
    }

    #[test]
    fn folded_or_concave_pairs_stay_triangles() {
        let h = house();
        let edited = join_triangles(&h, None, &JoinParams::default()).unwrap();
        assert_eq!(counts(&edited.mesh), counts(&h));
        // A dart: the quad across the diagonal would have a reflex corner.
        let dart = PolyMesh::from_polygons(
            vec![DVec3::ZERO, DVec3::new(2.0, 1.0, 0.0), DVec3::new(0.5, 0.5, 0.0), DVec3::new(1.0, 2.0, 0.0)],
            &[[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let e = dart.find_halfedge(VertexId(0), VertexId(2)).unwrap().edge();
        assert_eq!(join_score(&dart, e, &JoinParams::default()), None);
        let err = join_triangles(&h, None, &JoinParams { max_fold: f64::NAN }).unwrap_err().to_string();
        assert!(err.contains("fold angle"), "{err}");
        assert!(join_triangles(&h, Some(&[]), &JoinParams::default()).is_err());
    }
}
