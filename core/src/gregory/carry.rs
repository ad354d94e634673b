//! Curve-mesh edits following a change of the cage they were made on: the rule a document uses
//! when the designer moves cage points or changes the cage's topology while the curve mesh
//! carries edits (Taut's rule; the seed paper edits the curve mesh only after the cage is done).
//!
//! The curve mesh is rebuilt from the new cage, and the edits are carried onto it:
//! - **Which vertex continues which.** Every curve-mesh vertex stands for one cage element
//!   ([`Role`]): the cage vertex itself when the cage is all quads (its curve mesh has the cage's
//!   topology), or, when the cage was subdivided once first (`docs/curve-mesh-gregory.md` §5), a
//!   cage vertex, the edge point of a cage edge or the face point of a cage face. A curve-mesh
//!   vertex continues the old one of the same role when that cage element continues unchanged in
//!   identity, by the cage edit's provenance ([`crate::mesh::edit::provenance`]) — `Same` only: a
//!   copy, a mirror image or a merged vertex is somewhere else, so an absolute position cannot
//!   follow it. A move of cage points keeps every role.
//! - **Vertices.** An edited vertex that continues keeps its edited position and tangent plane
//!   exactly (the designer put it there; it does not follow the cage). Every other vertex takes
//!   the new build's.
//! - **Curves.** A curve continues when both its end vertices continue and were joined by a curve.
//!   Each end of each curve keeps its *leg* (inner point − vertex) in the frame of its vertex: a
//!   leg the designer changed (it differs from the old build's) is carried from its old vertex
//!   frame, any other leg is the new build's; then the leg is carried into the vertex's frame now
//!   (translated with the vertex, turned by the smallest rotation from the frame's normal to the
//!   vertex's) and projected onto its tangent plane. A leg whose frame did not change keeps its
//!   inner point bit for bit, so edits far from the cage change stay exactly as they were.
//!
//! What cannot follow (an edited vertex whose cage element was deleted, copied or merged; an
//! edited curve whose ends are no longer joined) is dropped and counted in the [`CarryReport`].
//! Weak spot: a cage edit that changes a face's corners keeps its face point's role, so an edited
//! face point stays where it was even though its face moved away from it.

use super::curve_mesh::{CurveEdit, CurveMesh, CurveMeshEdits, VertexEdit};
use crate::mesh::edit::{EdgeOrigin, FaceOrigin, Provenance, VertexOrigin};
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::subdiv::{SplitRule, SplitTopology};
use crate::{DVec3, Error, Result};
use glam::DQuat;
use std::collections::HashMap;

/// The cage element a curve-mesh vertex stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// A cage vertex (every vertex of an all-quad cage's curve mesh, the first ones otherwise).
    Vertex(VertexId),
    /// The edge point of a cage edge (a cage subdivided once first).
    EdgePoint(EdgeId),
    /// The face point of a cage face (a cage subdivided once first).
    FacePoint(FaceId),
}

/// What carrying the edits kept and dropped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CarryReport {
    /// Edited vertices that kept their edits.
    pub kept_vertices: usize,
    /// Edited vertices dropped (their cage element is gone, copied or merged).
    pub dropped_vertices: usize,
    /// Edited curves that continue.
    pub kept_curves: usize,
    /// Edited curves dropped (their ends are no longer joined).
    pub dropped_curves: usize,
}

impl CarryReport {
    /// True when every edit followed.
    pub fn nothing_dropped(&self) -> bool {
        self.dropped_vertices == 0 && self.dropped_curves == 0
    }

    /// One line for the designer, or `None` when nothing was dropped.
    pub fn message(&self) -> Option<String> {
        (!self.nothing_dropped()).then(|| {
            format!(
                "{} edited curve-mesh vertices and {} edited curves could not follow the cage edit and were dropped (undo brings them back)",
                self.dropped_vertices, self.dropped_curves
            )
        })
    }
}

/// The role of every vertex of the curve mesh [`CurveMesh::from_cage`] builds on `cage`, in
/// curve-mesh vertex order.
pub fn roles(cage: &PolyMesh) -> Result<Vec<Role>> {
    if cage.faces().all(|f| cage.face_valence(f) == 4) {
        return Ok(cage.vertices().map(Role::Vertex).collect());
    }
    let split = SplitTopology::split(cage, SplitRule::Quads)?;
    Ok(split
        .mesh
        .vertices()
        .map(|v| match split.origin(v) {
            crate::subdiv::VertexOrigin::Vertex(v) => Role::Vertex(v),
            crate::subdiv::VertexOrigin::Edge(e) => Role::EdgePoint(e),
            crate::subdiv::VertexOrigin::Face(f) => Role::FacePoint(f),
        })
        .collect())
}

/// Per vertex of the new curve mesh, the vertex of the old one it continues (see the module
/// docs), from both cages' roles and the cage edit's provenance.
pub fn continuing_vertices(old_roles: &[Role], new_roles: &[Role], provenance: &Provenance) -> Vec<Option<VertexId>> {
    let old_index: HashMap<Role, VertexId> =
        old_roles.iter().enumerate().map(|(i, &r)| (r, VertexId(i as u32))).collect();
    new_roles
        .iter()
        .map(|role| {
            let old = match *role {
                Role::Vertex(v) => match provenance.vertices.get(v.index()) {
                    Some(VertexOrigin::Same(o)) => Role::Vertex(*o),
                    _ => return None,
                },
                Role::EdgePoint(e) => match provenance.edges.get(e.index()) {
                    Some(EdgeOrigin::Same(o)) => Role::EdgePoint(*o),
                    _ => return None,
                },
                Role::FacePoint(f) => match provenance.faces.get(f.index()) {
                    Some(FaceOrigin::Same(o)) => Role::FacePoint(*o),
                    _ => return None,
                },
            };
            old_index.get(&old).copied()
        })
        .collect()
}

/// The edits of `old` (a curve mesh with its edits, on the old cage) carried onto `new_base` (the
/// new cage's curve mesh as built, without edits); `source[w]` is the old vertex new vertex `w`
/// continues. The result is an edit state of `new_base` (apply it with
/// [`CurveMesh::set_edits`]).
pub fn carry_edits(
    old: &CurveMesh,
    new_base: &CurveMesh,
    source: &[Option<VertexId>],
) -> Result<(CurveMeshEdits, CarryReport)> {
    if source.len() != new_base.vertex_count() {
        return Err(Error::Input(format!(
            "carrying curve-mesh edits: {} vertex sources for a curve mesh of {} vertices",
            source.len(),
            new_base.vertex_count()
        )));
    }
    let old_edits = old.edits();
    let (old_t, new_t) = (old.topology(), new_base.topology());
    let mut report = CarryReport::default();

    // Vertices: edited ones that continue keep their values.
    let mut continued = vec![false; old.vertex_count()];
    let mut frames: Vec<(DVec3, DVec3)> = new_t.vertices().map(|w| new_base.built_vertex(w)).collect();
    let mut vertices = Vec::new();
    for (w, s) in source.iter().enumerate() {
        let Some(v) = *s else { continue };
        if v.index() >= old.vertex_count() {
            return Err(Error::Input(format!("carrying curve-mesh edits: old vertex {} does not exist", v.0)));
        }
        continued[v.index()] = true;
        if old.is_vertex_edited(v) && !new_t.is_isolated(VertexId(w as u32)) {
            let (p, n) = (old.vertex_position(v), old.vertex_normal(v));
            frames[w] = (p, n);
            vertices.push(VertexEdit { vertex: w as u32, position: p.to_array(), normal: n.to_array() });
        }
    }
    report.kept_vertices = vertices.len();
    report.dropped_vertices =
        old_edits.vertices.iter().filter(|e| !continued.get(e.vertex as usize).copied().unwrap_or(false)).count();

    // Curves: every end's leg carried into its vertex's frame now.
    let mut carried_old_curves = std::collections::BTreeSet::new();
    let mut curves = Vec::new();
    for c in new_t.edges() {
        let (a, b) = new_t.edge_vertices(c);
        let built = new_base.built_inner_points(c);
        // The old curve between the same two vertices, oriented from a to b.
        let old_curve = match (source[a.index()], source[b.index()]) {
            (Some(oa), Some(ob)) => old_t.find_halfedge(oa, ob).map(|h| (h, oa, ob)),
            _ => None,
        };
        let mut inner = built;
        for (k, end) in [(0, a), (1, b)] {
            let frame_now = frames[end.index()];
            let from = old_curve.and_then(|(h, oa, ob)| {
                let e = h.edge();
                let old_end = if k == 0 { oa } else { ob };
                let q = old.inner_point(e, old_end)?;
                let q_built = old.built_inner_points(e)[if old_t.edge_vertices(e).0 == old_end { 0 } else { 1 }];
                let changed = q.to_array().map(f64::to_bits) != q_built.to_array().map(f64::to_bits);
                changed.then(|| (q, (old.vertex_position(old_end), old.vertex_normal(old_end))))
            });
            let (q, frame) = from.unwrap_or((built[k], new_base.built_vertex(end)));
            inner[k] = reframe(q, frame, frame_now);
        }
        if let Some((h, ..)) = old_curve
            && old_edits.curves.binary_search_by_key(&h.edge().0, |e| e.curve).is_ok()
        {
            carried_old_curves.insert(h.edge().0);
        }
        if inner.map(|p| p.to_array().map(f64::to_bits)) != built.map(|p| p.to_array().map(f64::to_bits)) {
            curves.push(CurveEdit { curve: c.0, inner: inner.map(|p| p.to_array()) });
        }
    }
    report.kept_curves = carried_old_curves.len();
    report.dropped_curves = old_edits.curves.len() - carried_old_curves.len();
    let edits = CurveMeshEdits { shape: new_base.shape(), vertices, curves }.normalized();
    Ok((edits, report))
}

/// `q` (an inner point next to a vertex with frame `(p, n)`) carried into the frame
/// `(p_now, n_now)`: translated with the vertex, turned by the smallest rotation between the
/// normals, projected onto the plane. Unchanged, bit for bit, when the frames are the same.
fn reframe(q: DVec3, (p, n): (DVec3, DVec3), (p_now, n_now): (DVec3, DVec3)) -> DVec3 {
    if p == p_now && n == n_now {
        return q;
    }
    let leg = if n == n_now { q - p } else { DQuat::from_rotation_arc(n, n_now) * (q - p) };
    let q = p_now + leg;
    q - (q - p_now).dot(n_now) * n_now
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reframing_keeps_the_leg_in_the_new_plane() {
        let (p, n) = (DVec3::new(1.0, 2.0, 3.0), DVec3::Z);
        let q = p + DVec3::new(0.3, -0.2, 0.0);
        assert_eq!(reframe(q, (p, n), (p, n)), q, "an unchanged frame keeps the point exactly");
        let n_now = DVec3::new(0.0, 0.6, 0.8);
        let p_now = DVec3::new(-1.0, 0.5, 2.0);
        let moved = reframe(q, (p, n), (p_now, n_now));
        let leg = moved - p_now;
        assert!(leg.dot(n_now).abs() < 1e-15, "in the new tangent plane");
        assert!((leg.length() - (q - p).length()).abs() < 1e-15, "the leg keeps its length");
        // The rotation turns Z to n_now about the x axis: x components stay.
        assert!((leg.x - 0.3).abs() < 1e-15);
    }

    #[test]
    fn roles_of_a_mixed_cage_are_vertices_edge_points_and_face_points() {
        let cage = PolyMesh::from_polygons(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y, DVec3::new(2.0, 0.5, 0.0)],
            &[vec![0, 1, 2, 3], vec![1, 4, 2]],
        )
        .unwrap();
        let r = roles(&cage).unwrap();
        let (v, e, f) = (cage.vertex_count(), cage.edge_count(), cage.face_count());
        assert_eq!(r.len(), v + e + f);
        assert_eq!(r[..v], (0..v as u32).map(|i| Role::Vertex(VertexId(i))).collect::<Vec<_>>()[..]);
        assert_eq!(r[v], Role::EdgePoint(EdgeId(0)));
        assert_eq!(r[v + e], Role::FacePoint(FaceId(0)));
        let quads =
            PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y], &[[0, 1, 2, 3]]).unwrap();
        assert_eq!(roles(&quads).unwrap().len(), 4);
    }
}
