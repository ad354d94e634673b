//! One topological refinement step shared by every scheme: split each edge at a new vertex and
//! each face by a [`SplitRule`], with stable numbering and the origin of every new element.
//!
//! - [`SplitRule::Quads`] (Catmull–Clark): every face, triangles included, becomes `n` quads
//!   around a new face point.
//! - [`SplitRule::Triangles`] (Loop): every triangle becomes 4 triangles; any other face is
//!   refused with a message that says to triangulate.
//! - [`SplitRule::Mixed`] (NUSD's hierarchy, `nusd::surface::hierarchy`): triangles become 4
//!   triangles, every other face `n` quads around a face point.
//!
//! **Numbering** (so cage vertex `i` is vertex `i` at every level; exporters rely on it): the
//! child vertices are first the parent's vertices with their indices, then one *edge point* per
//! parent edge in edge order (`edge point of e = parent vertices + e`), then one *face point* per
//! split-into-quads face in face order. Child faces come in parent-face order: a face split into
//! quads gives, for its `k`-th corner `c_k` (from its first halfedge on), the quad
//! `(c_k, m_k, face point, m_{k−1})` with `m_k` the edge point of the edge `c_k → c_{k+1}`; a
//! triangle gives `(c0, m0, m2)`, `(m0, c1, m1)`, `(m2, m1, c2)`, `(m0, m1, m2)`. Child edges
//! follow the parent's halfedges: the halves of parent edge `e` are child edges `2e` (at its first
//! end vertex) and `2e + 1`, then one edge inside a face per parent halfedge with a face
//! (`Plan`).
//!
//! Every child vertex knows its [`VertexOrigin`]; every child edge the parent edge it lies on (the
//! two halves of a split edge) or none (edges inside a parent face); every parent edge its two
//! halves; every child face its parent face. Creases and curves along cage edges are followed down
//! the levels with these. The child mesh's positions are the linear prolongation (vertices stay,
//! edge points at midpoints, face points at centroids); the schemes place vertices with their own
//! stencils.

use crate::mesh::{EdgeId, FaceId, HalfedgeArrays, HalfedgeId, PolyMesh, VertexId};
use crate::{Error, Result};
use rayon::prelude::*;

/// How faces are split.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplitRule {
    /// Every face becomes `n` quads around a face point (Catmull–Clark).
    Quads,
    /// Every triangle becomes 4 triangles; other faces are refused (Loop).
    Triangles,
    /// Triangles become 4 triangles, other faces quads around a face point (NUSD).
    Mixed,
}

/// The parent element a child vertex was made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexOrigin {
    /// The child of a parent vertex (same index).
    Vertex(VertexId),
    /// The edge point of a parent edge.
    Edge(EdgeId),
    /// The face point of a parent face.
    Face(FaceId),
}

/// One refinement step: the child mesh and how each of its elements relates to the parent.
#[derive(Clone, Debug)]
pub struct SplitTopology {
    /// The child mesh (positions: the linear prolongation of the parent's).
    pub mesh: PolyMesh,
    /// The rule it was split by.
    pub rule: SplitRule,
    parent_vertices: u32,
    parent_edges: u32,
    /// Parent face of each face point, in face-point order.
    face_point_face: Vec<FaceId>,
    /// Face point of each parent face, or invalid for a triangle split into triangles.
    face_point: Vec<VertexId>,
    /// Per child face: its parent face.
    face_parent: Vec<FaceId>,
}

impl SplitTopology {
    /// Splits `parent` by `rule`. Fails only for [`SplitRule::Triangles`] on a face that is not a
    /// triangle.
    ///
    /// The child mesh's halfedges are derived from the parent's (as OpenSubdiv's refiner derives
    /// each level's relations from the level above) rather than matched up from a face list:
    /// every child halfedge is a pure function of its index ([`Plan`]), so they are filled in
    /// parallel without hashing or sorting, and the result does not depend on the thread count.
    /// The four halfedge arrays are filled in one pass, so each child halfedge's parent halfedge,
    /// face and face point are read once (level-3 torus topology 21.3 → 16.8 ms on one thread).
    pub fn split(parent: &PolyMesh, rule: SplitRule) -> Result<Self> {
        SplitTopology::split_with(parent, rule, None)
    }

    /// [`SplitTopology::split`] of `parent.mesh`, the child of an earlier split: when that split
    /// made quads, where each halfedge sits in its quad follows from its index, and no face is
    /// walked to find it (the same result).
    pub fn split_again(parent: &SplitTopology, rule: SplitRule) -> Result<Self> {
        let made_by_quads = (parent.rule == SplitRule::Quads).then_some(4 * parent.parent_edges);
        SplitTopology::split_with(&parent.mesh, rule, made_by_quads)
    }

    fn split_with(parent: &PolyMesh, rule: SplitRule, made_by_quads: Option<u32>) -> Result<Self> {
        if rule == SplitRule::Triangles
            && let Some(f) = parent.faces().find(|&f| parent.face_valence(f) != 3)
        {
            return Err(Error::Topology(format!(
                "Loop subdivision needs a triangle cage, but face {} has {} sides; triangulate the cage first",
                f.0,
                parent.face_valence(f)
            )));
        }
        let plan = Plan::new(parent, rule, made_by_quads);
        let nh = plan.halves as usize + 2 * plan.interior_count();
        // The halfedges and the per-vertex arrays read only the plan and the parent: made side
        // by side, one part's waits on memory overlap the other's work.
        let ((halfedges, (face_halfedge, face_parent)), (positions, vertex_halfedge)) = rayon::join(
            || {
                let halfedges = if rule == SplitRule::Quads { plan.quad_halfedges(nh) } else { plan.halfedges(nh) };
                (halfedges, plan.face_halfedges_and_parents())
            },
            || {
                let vertex_halfedge = (0..plan.vertex_count() as u32)
                    .into_par_iter()
                    .with_min_len(PARALLEL_CHUNK)
                    .map(|v| plan.vertex_halfedge(v))
                    .collect();
                (plan.positions(), vertex_halfedge)
            },
        );
        let ChildHalfedges { to: halfedge_to, next: halfedge_next, prev: halfedge_prev, face: halfedge_face } =
            halfedges;
        let mesh = PolyMesh::from_halfedges(HalfedgeArrays {
            positions,
            vertex_halfedge,
            halfedge_to,
            halfedge_next,
            halfedge_prev,
            halfedge_face,
            face_halfedge,
        });
        Ok(SplitTopology {
            mesh,
            rule,
            parent_vertices: parent.vertex_count() as u32,
            parent_edges: parent.edge_count() as u32,
            face_point_face: plan.face_point_face,
            face_point: plan.face_point,
            face_parent,
        })
    }
}

impl SplitTopology {
    /// Number of parent vertices (the first child vertices).
    pub fn parent_vertex_count(&self) -> usize {
        self.parent_vertices as usize
    }

    /// The parent element child vertex `v` was made from.
    pub fn origin(&self, v: VertexId) -> VertexOrigin {
        let (nv, ne) = (self.parent_vertices, self.parent_edges);
        if v.0 < nv {
            VertexOrigin::Vertex(v)
        } else if v.0 < nv + ne {
            VertexOrigin::Edge(EdgeId(v.0 - nv))
        } else {
            VertexOrigin::Face(self.face_point_face[(v.0 - nv - ne) as usize])
        }
    }

    /// The first face point (every vertex before it is a parent vertex or an edge point).
    pub fn first_face_point(&self) -> usize {
        (self.parent_vertices + self.parent_edges) as usize
    }

    /// The rank of parent face `f`'s face point among the face points (its index minus
    /// [`first_face_point`](Self::first_face_point)); `None` for a triangle split into triangles.
    /// A split into quads gives every face a face point in face order, so there the rank is the
    /// face's index, read from no table.
    #[inline]
    pub fn face_point_rank(&self, f: FaceId) -> Option<usize> {
        if self.rule == SplitRule::Quads {
            debug_assert_eq!(self.face_point[f.index()].index(), self.first_face_point() + f.index());
            return Some(f.index());
        }
        self.face_point(f).map(|p| p.index() - self.first_face_point())
    }

    /// The edge point of parent edge `e`.
    pub fn edge_point(&self, e: EdgeId) -> VertexId {
        VertexId(self.parent_vertices + e.0)
    }

    /// The face point of parent face `f`; `None` for a triangle split into triangles.
    pub fn face_point(&self, f: FaceId) -> Option<VertexId> {
        if self.rule == SplitRule::Quads {
            // Every face has one, in face order (see `face_point_rank`).
            return Some(VertexId((self.first_face_point() + f.index()) as u32));
        }
        let p = self.face_point[f.index()];
        p.is_valid().then_some(p)
    }

    /// The parent edge child edge `e` lies on; `None` for an edge inside a parent face.
    pub fn edge_parent(&self, e: EdgeId) -> Option<EdgeId> {
        (e.0 < 2 * self.parent_edges).then_some(EdgeId(e.0 >> 1))
    }

    /// The two halves of parent edge `e`: the one at its first end vertex
    /// (`parent.edge_vertices(e).0`), then the one at its second.
    pub fn edge_children(&self, e: EdgeId) -> [EdgeId; 2] {
        [EdgeId(2 * e.0), EdgeId(2 * e.0 + 1)]
    }

    /// The parent face child face `f` lies in.
    pub fn face_parent(&self, f: FaceId) -> FaceId {
        self.face_parent[f.index()]
    }

    /// The spokes of child vertex `v` of a split into quads, read from the parent mesh rather than
    /// walked round the child's: for every outgoing child halfedge in the order
    /// `self.mesh.outgoing(v)` gives them, its child edge when that is a half of a parent edge
    /// (`None` for an edge inside a parent face, which is never sharp), its end vertex and the
    /// vertex across the quad after it (`to(next(h))`). False, with nothing reported, for a vertex
    /// on the boundary or an isolated one.
    ///
    /// The limit masks of the finest level read these rings for every vertex; the parent's arrays
    /// are a quarter of the child's, and an edge point's ring needs no walk at all, so this misses
    /// the cache far less than walking the child's halfedges. Follows [`Plan`]'s numbering: a
    /// parent vertex's spokes are the halves `2h` of its parent spokes `h`; an edge point's run
    /// from the half back to the first end, through the face of the edge's second halfedge, the
    /// other half and the face of the first; a face point's follow the face's halfedges.
    /// `split::tests` checks every vertex against the walk.
    #[inline]
    pub(crate) fn quad_spokes(
        &self,
        parent: &PolyMesh,
        v: VertexId,
        mut spoke: impl FnMut(Option<EdgeId>, u32, u32),
    ) -> bool {
        debug_assert_eq!(self.rule, SplitRule::Quads, "quad spokes of a split into triangles");
        let (nv, ne) = (self.parent_vertices, self.parent_edges);
        let edge_point = |h: HalfedgeId| nv + (h.0 >> 1);
        let face_point = |h: HalfedgeId| self.face_point[parent.face(h).index()].0;
        if v.0 < nv {
            let start = parent.vertex_halfedge(v);
            if !start.is_valid() || parent.is_boundary_halfedge(start) {
                return false;
            }
            for h in parent.outgoing(v) {
                spoke(Some(EdgeId(h.0)), edge_point(h), face_point(h));
            }
        } else if v.0 < nv + ne {
            let e = EdgeId(v.0 - nv);
            let (a, b) = (e.halfedge(0), e.halfedge(1));
            if parent.is_boundary_halfedge(a) || parent.is_boundary_halfedge(b) {
                return false;
            }
            spoke(Some(EdgeId(a.0)), parent.to_vertex(b).0, edge_point(parent.next(b)));
            spoke(None, face_point(b), edge_point(parent.prev(b)));
            spoke(Some(EdgeId(b.0)), parent.to_vertex(a).0, edge_point(parent.next(a)));
            spoke(None, face_point(a), edge_point(parent.prev(a)));
        } else {
            let f = self.face_point_face[(v.0 - nv - ne) as usize];
            for h in parent.face_halfedges(f) {
                spoke(None, edge_point(h), parent.to_vertex(h).0);
            }
        }
        true
    }
}

#[path = "topology_plan.rs"]
mod plan;
use plan::{ChildHalfedges, PARALLEL_CHUNK, Plan};

#[cfg(test)]
#[path = "topology_tests.rs"]
mod tests;
