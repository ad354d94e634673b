//! The curve mesh as an editable object: a network of cubic Bézier curves with the topology of an
//! all-quad mesh, a tangent plane at every vertex, and one Gregory patch per face (the seed
//! paper's §4–5; `docs/curve-mesh-gregory.md` §6).
//!
//! What is stored is only what a designer can change: per vertex a position and a unit normal
//! (its tangent plane), per curve its two inner control points. Curve end points are the vertex
//! positions, so a curve can never come loose from its vertices, and every patch is a pure
//! function of its four curves and four corner normals ([`gregory_patch`]). Three edits change
//! the stored values:
//! - [`CurveMesh::move_vertex`]: the vertex, its tangent plane and the inner points next to it
//!   translate together;
//! - [`CurveMesh::rotate_tangent_plane`] (or [`CurveMesh::set_vertex_normal`]): the normal and the
//!   inner points next to the vertex rotate about it;
//! - [`CurveMesh::move_inner_point`]: one inner point moves, projected onto its vertex's plane.
//!
//! Each edit rebuilds only the patches whose inputs it changed (the faces around the vertex, or
//! the one or two faces on the curve), in time independent of the mesh size, and returns them in
//! a [`Changed`] so an editor re-uploads only those. Every inner point an edit writes is projected
//! onto its vertex's tangent plane, so the legs at a vertex stay coplanar (G1 at the corners)
//! without drift.
//!
//! The edit state ([`CurveMeshEdits`]) lists the edited vertices and curves with their current
//! values: stored beside the cage, it is re-applied on a fresh build with
//! [`CurveMesh::set_edits`], which also serves undo (set an earlier state). Since patches depend
//! only on the stored values, a reopened file gives bit-identical patches.

use super::bezier::CubicBezier;
use super::chiyokura_kimura::{CurveMiddle, PatchBoundary, gregory_patch};
use super::continuity::{ContinuityReport, PatchSide, SharedBoundary, continuity_report};
use super::patch::GregoryPatch;
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use glam::DQuat;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

/// A network of Bézier curves on an all-quad topology, filled with Gregory patches.
#[derive(Clone, Debug)]
pub struct CurveMesh {
    /// The connectivity; its positions are kept equal to the vertex positions.
    topology: PolyMesh,
    normals: Vec<DVec3>,
    /// Per curve (edge), the inner points `[P1, P2]` for the direction of `edge.halfedge(0)`.
    inner: Vec<[DVec3; 2]>,
    /// Per curve, the limit surface at its middle (normal, field length), used while the curve
    /// and its ends are as built (an edit drops it: the field falls back to linear there).
    mids: Vec<Option<CurveMiddle>>,
    patches: Vec<GregoryPatch>,
    /// The values as built, before any edit (for [`CurveMesh::set_edits`]).
    base: Values,
    edited_vertices: BTreeSet<u32>,
    edited_curves: BTreeSet<u32>,
    generation: u64,
}

#[derive(Clone, Debug)]
struct Values {
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    inner: Vec<[DVec3; 2]>,
}

/// What an edit changed: the editor re-uploads these patches and redraws these curves.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Changed {
    /// Vertices whose position or tangent plane changed.
    pub vertices: Vec<VertexId>,
    /// Curves whose control points changed.
    pub curves: Vec<EdgeId>,
    /// Patches that were rebuilt (every patch whose inputs changed), ascending.
    pub patches: Vec<FaceId>,
}

/// The edit state of a curve mesh: every edited vertex and curve with its current values.
/// Compact (only edited entities), serialisable, and exact: f64 values round-trip through JSON.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveMeshEdits {
    /// Vertex, curve and patch counts of the curve mesh the edits belong to.
    pub shape: [u32; 3],
    /// Edited vertices, ascending.
    pub vertices: Vec<VertexEdit>,
    /// Edited curves, ascending.
    pub curves: Vec<CurveEdit>,
}

/// An edited vertex: its position and unit normal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VertexEdit {
    /// Vertex index.
    pub vertex: u32,
    /// Position.
    pub position: [f64; 3],
    /// Unit normal of the tangent plane.
    pub normal: [f64; 3],
}

/// An edited curve: its two inner control points, for the direction of its edge's first
/// halfedge (from the edge's first vertex to its second).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveEdit {
    /// Curve (edge) index.
    pub curve: u32,
    /// `[P1, P2]`.
    pub inner: [[f64; 3]; 2],
}

impl CurveMeshEdits {
    /// True when nothing is edited (the curve mesh as built). [`CurveMeshEdits::default`] is the
    /// empty state of any curve mesh: [`CurveMesh::set_edits`] takes it whatever the shape.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.curves.is_empty()
    }

    /// [`CurveMeshEdits::default`] when nothing is edited, else `self`: one value for "no edits"
    /// whatever the curve mesh, so two empty states compare equal.
    pub fn normalized(self) -> Self {
        if self.is_empty() { CurveMeshEdits::default() } else { self }
    }
}

impl CurveMesh {
    /// A curve mesh from its connectivity (all quads; the positions are the vertex positions),
    /// unit normals per vertex and inner points per edge (for the direction of
    /// `edge.halfedge(0)`). Inner points are projected onto their vertex's tangent plane.
    pub fn from_parts(topology: PolyMesh, normals: Vec<DVec3>, inner: Vec<[DVec3; 2]>) -> Result<Self> {
        if normals.len() != topology.vertex_count() || inner.len() != topology.edge_count() {
            return Err(Error::Input(format!(
                "a curve mesh needs one normal per vertex and two inner points per curve ({} and {} given for {} vertices and {} curves)",
                normals.len(),
                inner.len(),
                topology.vertex_count(),
                topology.edge_count()
            )));
        }
        if let Some(f) = topology.faces().find(|&f| topology.face_valence(f) != 4) {
            return Err(Error::Topology(format!(
                "face {} has {} sides; a curve mesh is built on quads (subdivide the cage once first)",
                f.0,
                topology.face_valence(f)
            )));
        }
        let mut normals = normals;
        for (v, n) in normals.iter_mut().enumerate() {
            if topology.is_isolated(VertexId(v as u32)) {
                *n = if n.is_finite() && n.length() > 0.0 { n.normalize() } else { DVec3::Z };
                continue;
            }
            if !n.is_finite() || n.length() < 1e-300 {
                return Err(Error::Input(format!("vertex {v} has no usable tangent-plane normal ({n})")));
            }
            *n = n.normalize();
        }
        let mut mesh = CurveMesh {
            base: Values { positions: Vec::new(), normals: Vec::new(), inner: Vec::new() },
            topology,
            normals,
            inner,
            mids: Vec::new(),
            patches: Vec::new(),
            edited_vertices: BTreeSet::new(),
            edited_curves: BTreeSet::new(),
            generation: 0,
        };
        for e in 0..mesh.inner.len() {
            let e = EdgeId(e as u32);
            let (a, b) = mesh.topology.edge_vertices(e);
            let [p1, p2] = mesh.inner[e.index()];
            if !p1.is_finite() || !p2.is_finite() {
                return Err(Error::Input(format!("curve {} has a non-finite inner control point", e.0)));
            }
            mesh.inner[e.index()] = [mesh.project(a, p1), mesh.project(b, p2)];
        }
        mesh.patches = mesh.topology.faces().collect::<Vec<_>>().par_iter().map(|&f| mesh.build_patch(f)).collect();
        mesh.base = Values {
            positions: mesh.topology.positions().to_vec(),
            normals: mesh.normals.clone(),
            inner: mesh.inner.clone(),
        };
        Ok(mesh)
    }

    /// Sets the limit surface at the middle of every curve (one per curve: its normal and, when
    /// fitted, the field's length there) and rebuilds the patches: each curve's cross-boundary
    /// field then turns through it ([`super::chiyokura_kimura::side_inner_points`]).
    pub fn with_middles(mut self, mids: Vec<CurveMiddle>) -> Result<Self> {
        if mids.len() != self.topology.edge_count() {
            return Err(Error::Input(format!(
                "{} middle normals for {} curves; give one per curve",
                mids.len(),
                self.topology.edge_count()
            )));
        }
        self.mids = mids
            .into_iter()
            .map(|m| {
                let n = m.normal;
                (n.is_finite() && n.length() > 0.0).then(|| CurveMiddle { normal: n.normalize(), length: m.length })
            })
            .collect();
        self.patches = self.topology.faces().collect::<Vec<_>>().par_iter().map(|&f| self.build_patch(f)).collect();
        Ok(self)
    }

    /// The connectivity: vertices are curve-mesh vertices, edges are curves, faces are patches.
    pub fn topology(&self) -> &PolyMesh {
        &self.topology
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.topology.vertex_count()
    }
    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.topology.edge_count()
    }
    /// Number of patches.
    pub fn patch_count(&self) -> usize {
        self.patches.len()
    }
    /// Bumped by every edit that changed something.
    pub fn generation(&self) -> u64 {
        self.generation
    }
    /// True when the vertex's position or tangent plane was edited (it is in [`CurveMesh::edits`]).
    pub fn is_vertex_edited(&self, v: VertexId) -> bool {
        self.edited_vertices.contains(&v.0)
    }
    /// The position and unit normal of a vertex as built, before any edit.
    pub fn built_vertex(&self, v: VertexId) -> (DVec3, DVec3) {
        (self.base.positions[v.index()], self.base.normals[v.index()])
    }
    /// The inner points `[P1, P2]` of a curve as built (for the direction of `edge.halfedge(0)`).
    pub fn built_inner_points(&self, e: EdgeId) -> [DVec3; 2] {
        self.base.inner[e.index()]
    }
    /// Position of a vertex.
    pub fn vertex_position(&self, v: VertexId) -> DVec3 {
        self.topology.position(v)
    }
    /// Unit normal of a vertex's tangent plane.
    pub fn vertex_normal(&self, v: VertexId) -> DVec3 {
        self.normals[v.index()]
    }
    /// A curve from its edge's first vertex to its second.
    pub fn curve(&self, e: EdgeId) -> CubicBezier {
        self.curve_along(e.halfedge(0))
    }
    /// A curve in the direction of a halfedge (exactly the reverse of its twin's).
    pub fn curve_along(&self, h: HalfedgeId) -> CubicBezier {
        let [p1, p2] = self.inner[h.edge().index()];
        let (a, b) =
            (self.topology.position(self.topology.from_vertex(h)), self.topology.position(self.topology.to_vertex(h)));
        if h == h.edge().halfedge(0) { CubicBezier::new(a, p1, p2, b) } else { CubicBezier::new(a, p2, p1, b) }
    }
    /// The inner control point of curve `e` next to its end vertex `end` (`None` when `end` is
    /// not an end of `e`).
    pub fn inner_point(&self, e: EdgeId, end: VertexId) -> Option<DVec3> {
        self.end_index(e, end).map(|k| self.inner[e.index()][k])
    }
    /// The Gregory patch of a face.
    pub fn patch(&self, f: FaceId) -> &GregoryPatch {
        &self.patches[f.index()]
    }
    /// All patches, indexed by face.
    pub fn patches(&self) -> &[GregoryPatch] {
        &self.patches
    }
    /// The four sides and corner normals a face's patch is built from. Side `k` runs along the
    /// face's `k`-th halfedge from `topology().face_halfedge(f)`, corner 0 is that halfedge's
    /// start, so the patch's `u` runs along the first halfedge and `v` along the last one
    /// reversed.
    pub fn patch_boundary(&self, f: FaceId) -> PatchBoundary {
        let h0 = self.topology.face_halfedge(f);
        let hs = [h0, self.topology.next(h0), self.topology.next(self.topology.next(h0)), self.topology.prev(h0)];
        PatchBoundary {
            sides: hs.map(|h| self.curve_along(h)),
            normals: hs.map(|h| self.normals[self.topology.from_vertex(h).index()]),
            mids: hs.map(|h| self.middle(h.edge())),
        }
    }

    /// The limit surface at the middle of curve `e`, while the curve and both its ends are as
    /// built (an edited curve or end vertex no longer stands for the limit surface there).
    pub fn middle(&self, e: EdgeId) -> Option<CurveMiddle> {
        let (a, b) = self.topology.edge_vertices(e);
        let edited = self.edited_curves.contains(&e.0)
            || self.edited_vertices.contains(&a.0)
            || self.edited_vertices.contains(&b.0);
        if edited { None } else { self.mids.get(e.index()).copied().flatten() }
    }

    fn build_patch(&self, f: FaceId) -> GregoryPatch {
        gregory_patch(&self.patch_boundary(f))
    }

    /// `p` projected onto the tangent plane of `v`.
    fn project(&self, v: VertexId, p: DVec3) -> DVec3 {
        let n = self.normals[v.index()];
        p - (p - self.topology.position(v)).dot(n) * n
    }

    /// Index 0 or 1 of the inner point next to `v` on curve `e`.
    fn end_index(&self, e: EdgeId, v: VertexId) -> Option<usize> {
        let (a, b) = self.topology.edge_vertices(e);
        if v == a {
            Some(0)
        } else if v == b {
            Some(1)
        } else {
            None
        }
    }

    fn check_vertex(&self, v: VertexId) -> Result<()> {
        if v.index() >= self.vertex_count() {
            return Err(Error::Input(format!(
                "vertex {} does not exist (the curve mesh has {})",
                v.0,
                self.vertex_count()
            )));
        }
        if self.topology.is_isolated(v) {
            return Err(Error::Input(format!("vertex {} is on no curve; there is nothing to edit there", v.0)));
        }
        Ok(())
    }

    /// Moves a vertex to `position`; its tangent plane and the inner points next to it translate
    /// with it. Returns the rebuilt patches (the faces around the vertex).
    pub fn move_vertex(&mut self, v: VertexId, position: DVec3) -> Result<Changed> {
        self.check_vertex(v)?;
        if !position.is_finite() {
            return Err(Error::Input(format!("vertex {}: the new position {position} is not finite", v.0)));
        }
        let delta = position - self.topology.position(v);
        self.topology.set_position(v, position);
        let edges: Vec<EdgeId> = self.topology.outgoing(v).map(|h| h.edge()).collect();
        for &e in &edges {
            let k = self.end_index(e, v).expect("an outgoing edge ends at v");
            let p = self.inner[e.index()][k] + delta;
            self.inner[e.index()][k] = self.project(v, p);
        }
        self.edited_vertices.insert(v.0);
        self.edited_curves.extend(edges.iter().map(|e| e.0));
        Ok(self.rebuild_around(&[v], &edges))
    }

    /// Rotates a vertex's tangent plane by `rotation` (a unit quaternion, about the vertex): the
    /// normal and the inner points next to the vertex turn with it.
    pub fn rotate_tangent_plane(&mut self, v: VertexId, rotation: DQuat) -> Result<Changed> {
        self.check_vertex(v)?;
        if !rotation.is_finite() || (rotation.length() - 1.0).abs() > 1e-6 {
            return Err(Error::Input(format!("vertex {}: the rotation {rotation} is not a unit quaternion", v.0)));
        }
        let rotation = rotation.normalize();
        let centre = self.topology.position(v);
        self.normals[v.index()] = (rotation * self.normals[v.index()]).normalize();
        let edges: Vec<EdgeId> = self.topology.outgoing(v).map(|h| h.edge()).collect();
        for &e in &edges {
            let k = self.end_index(e, v).expect("an outgoing edge ends at v");
            let p = centre + rotation * (self.inner[e.index()][k] - centre);
            self.inner[e.index()][k] = self.project(v, p);
        }
        self.edited_vertices.insert(v.0);
        self.edited_curves.extend(edges.iter().map(|e| e.0));
        Ok(self.rebuild_around(&[v], &edges))
    }

    /// Turns a vertex's tangent plane to the unit normal `normal` by the smallest rotation.
    pub fn set_vertex_normal(&mut self, v: VertexId, normal: DVec3) -> Result<Changed> {
        self.check_vertex(v)?;
        if !normal.is_finite() || normal.length() < 1e-300 {
            return Err(Error::Input(format!("vertex {}: {normal} is not a usable normal", v.0)));
        }
        let from = self.normals[v.index()];
        let to = normal.normalize();
        if from.dot(to) < -1.0 + 1e-12 {
            return Err(Error::Input(format!(
                "vertex {}: turning the tangent plane upside down flips its patches; rotate it about an axis instead",
                v.0
            )));
        }
        self.rotate_tangent_plane(v, DQuat::from_rotation_arc(from, to))
    }

    /// Moves the inner control point of curve `curve` next to its end vertex `end` to `target`,
    /// projected onto that vertex's tangent plane. Rebuilds the one or two patches on the curve.
    pub fn move_inner_point(&mut self, curve: EdgeId, end: VertexId, target: DVec3) -> Result<Changed> {
        if curve.index() >= self.curve_count() {
            return Err(Error::Input(format!(
                "curve {} does not exist (the curve mesh has {})",
                curve.0,
                self.curve_count()
            )));
        }
        let k = self.end_index(curve, end).ok_or_else(|| {
            Error::Input(format!(
                "vertex {} is not an end of curve {}; pick one of its two end vertices",
                end.0, curve.0
            ))
        })?;
        if !target.is_finite() {
            return Err(Error::Input(format!("curve {}: the new control point {target} is not finite", curve.0)));
        }
        let p = self.project(end, target);
        let leg = p - self.topology.position(end);
        if leg.length() <= 1e-12 * (1.0 + self.topology.position(end).length()) {
            return Err(Error::Input(format!(
                "curve {}: the control point would sit on vertex {}, which leaves the curve without a tangent there",
                curve.0, end.0
            )));
        }
        self.inner[curve.index()][k] = p;
        self.edited_curves.insert(curve.0);
        Ok(self.rebuild_around(&[], &[curve]))
    }

    /// Rebuilds the patches of every face around `vertices` and on `curves`.
    fn rebuild_around(&mut self, vertices: &[VertexId], curves: &[EdgeId]) -> Changed {
        let mut faces = BTreeSet::new();
        for &v in vertices {
            faces.extend(self.topology.outgoing(v).map(|h| self.topology.face(h)).filter(|f| f.is_valid()));
        }
        for &e in curves {
            for side in 0..2 {
                let f = self.topology.face(e.halfedge(side));
                if f.is_valid() {
                    faces.insert(f);
                }
            }
        }
        for &f in &faces {
            self.patches[f.index()] = self.build_patch(f);
        }
        self.generation += 1;
        let mut vertices = vertices.to_vec();
        vertices.sort();
        let mut curves = curves.to_vec();
        curves.sort();
        curves.dedup();
        Changed { vertices, curves, patches: faces.into_iter().collect() }
    }
}

impl CurveMesh {
    /// Every curve with a patch on both sides, with its two patch sides (for
    /// [`continuity_report`](super::continuity::continuity_report)); curves ascending.
    pub fn shared_boundaries(&self) -> (Vec<EdgeId>, Vec<SharedBoundary>) {
        let t = &self.topology;
        let side_of = |h: HalfedgeId| {
            let f = t.face(h);
            let side = t.face_halfedges(f).position(|x| x == h).expect("h is a halfedge of its face");
            PatchSide { patch: f.index(), side: side as u8 }
        };
        t.edges()
            .filter(|&e| !t.is_boundary_edge(e))
            .map(|e| {
                (
                    e,
                    SharedBoundary {
                        first: side_of(e.halfedge(0)),
                        second: side_of(e.halfedge(1)),
                        same_direction: false,
                    },
                )
            })
            .unzip()
    }

    /// The continuity of every shared curve, sampled `samples` spans along each.
    pub fn continuity(&self, samples: usize) -> (Vec<EdgeId>, ContinuityReport) {
        let (curves, boundaries) = self.shared_boundaries();
        (curves, continuity_report(&self.patches, &boundaries, samples))
    }
}

#[path = "curve_mesh_state.rs"]
mod state;
