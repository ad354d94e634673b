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
//! triangle gives `(c0, m0, m2)`, `(m0, c1, m1)`, `(m2, m1, c2)`, `(m0, m1, m2)`. Child edges are
//! numbered by [`PolyMesh::from_face_list`] from those faces.
//!
//! Every child vertex knows its [`VertexOrigin`]; every child edge the parent edge it lies on (the
//! two halves of a split edge) or none (edges inside a parent face); every parent edge its two
//! halves; every child face its parent face. Creases and curves along cage edges are followed down
//! the levels with these. The child mesh's positions are the linear prolongation (vertices stay,
//! edge points at midpoints, face points at centroids); the schemes place vertices with their own
//! stencils.

use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};

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
    /// Per child edge: the parent edge it lies on, or invalid.
    edge_parent: Vec<EdgeId>,
    /// Per parent edge: its half at its first end vertex, then its half at the second.
    edge_children: Vec<[EdgeId; 2]>,
    /// Per child face: its parent face.
    face_parent: Vec<FaceId>,
}

impl SplitTopology {
    /// Splits `parent` by `rule`. Fails only for [`SplitRule::Triangles`] on a face that is not a
    /// triangle (or if the child mesh could not be indexed).
    pub fn split(parent: &PolyMesh, rule: SplitRule) -> Result<Self> {
        if rule == SplitRule::Triangles
            && let Some(f) = parent.faces().find(|&f| parent.face_valence(f) != 3)
        {
            return Err(Error::Topology(format!(
                "Loop subdivision needs a triangle cage, but face {} has {} sides; triangulate the cage first",
                f.0,
                parent.face_valence(f)
            )));
        }
        let nv = parent.vertex_count();
        let ne = parent.edge_count();
        let nf = parent.face_count();
        let quads = |n: usize| match rule {
            SplitRule::Quads => true,
            SplitRule::Triangles => false,
            SplitRule::Mixed => n != 3,
        };
        let mut positions = Vec::with_capacity(nv + ne + nf);
        positions.extend_from_slice(parent.positions());
        for e in parent.edges() {
            let (a, b) = parent.edge_vertices(e);
            positions.push(0.5 * (parent.position(a) + parent.position(b)));
        }
        let edge_point = |e: EdgeId| (nv + e.index()) as u32;
        let mut face_point = vec![VertexId::INVALID; nf];
        let mut face_point_face = Vec::new();
        let mut face_parent = Vec::with_capacity(4 * nf);
        let mut offsets: Vec<u32> = Vec::with_capacity(4 * nf + 1);
        let mut indices: Vec<u32> = Vec::with_capacity(4 * parent.halfedge_count());
        offsets.push(0);
        let mut hs = Vec::new();
        for f in parent.faces() {
            hs.clear();
            hs.extend(parent.face_halfedges(f));
            let n = hs.len();
            let corner = |k: usize| parent.from_vertex(hs[k]).0;
            let mid = |k: usize| edge_point(hs[k].edge());
            let mut push = |face: &[u32]| {
                indices.extend_from_slice(face);
                offsets.push(indices.len() as u32);
                face_parent.push(f);
            };
            if quads(n) {
                let centre = positions.len() as u32;
                let sum: DVec3 = (0..n).map(|k| parent.position(VertexId(corner(k)))).sum();
                positions.push(sum / n as f64);
                face_point[f.index()] = VertexId(centre);
                face_point_face.push(f);
                for k in 0..n {
                    push(&[corner(k), mid(k), centre, mid((k + n - 1) % n)]);
                }
            } else {
                push(&[corner(0), mid(0), mid(2)]);
                push(&[mid(0), corner(1), mid(1)]);
                push(&[mid(2), mid(1), corner(2)]);
                push(&[mid(0), mid(1), mid(2)]);
            }
        }
        let mesh = PolyMesh::from_face_list(positions, &offsets, &indices)?;

        // A child edge joining a parent vertex to an edge point is a half of that parent edge
        // (a parent vertex is joined only to the edge points of its own edges); every other child
        // edge lies inside a parent face.
        let mut edge_parent = vec![EdgeId::INVALID; mesh.edge_count()];
        let mut edge_children = vec![[EdgeId::INVALID; 2]; ne];
        for c in mesh.edges() {
            let (a, b) = mesh.edge_vertices(c);
            let (corner, point) = if a.index() < nv { (a, b) } else { (b, a) };
            if corner.index() < nv && (nv..nv + ne).contains(&point.index()) {
                let e = EdgeId((point.index() - nv) as u32);
                edge_parent[c.index()] = e;
                let side = usize::from(parent.edge_vertices(e).0 != corner);
                edge_children[e.index()][side] = c;
            }
        }
        Ok(SplitTopology {
            mesh,
            rule,
            parent_vertices: nv as u32,
            parent_edges: ne as u32,
            face_point_face,
            face_point,
            edge_parent,
            edge_children,
            face_parent,
        })
    }

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

    /// The edge point of parent edge `e`.
    pub fn edge_point(&self, e: EdgeId) -> VertexId {
        VertexId(self.parent_vertices + e.0)
    }

    /// The face point of parent face `f`; `None` for a triangle split into triangles.
    pub fn face_point(&self, f: FaceId) -> Option<VertexId> {
        let p = self.face_point[f.index()];
        p.is_valid().then_some(p)
    }

    /// The parent edge child edge `e` lies on; `None` for an edge inside a parent face.
    pub fn edge_parent(&self, e: EdgeId) -> Option<EdgeId> {
        let p = self.edge_parent[e.index()];
        p.is_valid().then_some(p)
    }

    /// The two halves of parent edge `e`: the one at its first end vertex
    /// (`parent.edge_vertices(e).0`), then the one at its second.
    pub fn edge_children(&self, e: EdgeId) -> [EdgeId; 2] {
        self.edge_children[e.index()]
    }

    /// The parent face child face `f` lies in.
    pub fn face_parent(&self, f: FaceId) -> FaceId {
        self.face_parent[f.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nusd::surface::hierarchy::LevelTopology;

    fn pyramid_with_pentagon() -> PolyMesh {
        // A pentagonal pyramid with a quad cut: one pentagon, five triangles; plus an open quad
        // strip so boundaries are exercised.
        let mut p: Vec<DVec3> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 5.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        p.push(DVec3::new(0.1, 0.0, 1.0));
        let mut faces: Vec<Vec<u32>> = vec![(0..5).rev().collect()];
        for k in 0..5 {
            faces.push(vec![k, (k + 1) % 5, 5]);
        }
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    fn open_mixed() -> PolyMesh {
        let p = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.3),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.2),
            DVec3::new(2.0, 1.2, 0.0),
            DVec3::new(3.0, 0.5, 0.0),
        ];
        PolyMesh::from_polygons(p, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![2, 6, 5]]).unwrap()
    }

    #[test]
    fn mixed_rule_gives_exactly_the_nusd_hierarchy() {
        for cage in [pyramid_with_pentagon(), open_mixed()] {
            let mut nusd = LevelTopology::cage(&cage);
            let mut ours = cage.clone();
            for _ in 0..3 {
                nusd = nusd.refine().unwrap();
                let split = SplitTopology::split(&ours, SplitRule::Mixed).unwrap();
                assert_eq!(split.mesh.polygons(), nusd.mesh.polygons());
                assert_eq!(split.mesh.positions(), nusd.mesh.positions());
                // Edge parents agree with NUSD's cage-edge tags on the first level.
                ours = split.mesh;
            }
        }
    }

    #[test]
    fn counts_euler_origins_and_halves() {
        let cage = pyramid_with_pentagon();
        for (rule, faces) in [(SplitRule::Quads, 5 + 5 * 3), (SplitRule::Mixed, 5 + 5 * 4)] {
            let s = SplitTopology::split(&cage, rule).unwrap();
            s.mesh.validate().unwrap();
            assert_eq!(s.mesh.face_count(), faces);
            assert_eq!(s.mesh.euler_characteristic(), cage.euler_characteristic());
            for v in s.mesh.vertices() {
                let expected = match s.origin(v) {
                    VertexOrigin::Vertex(p) => cage.position(p),
                    VertexOrigin::Edge(e) => {
                        let (a, b) = cage.edge_vertices(e);
                        0.5 * (cage.position(a) + cage.position(b))
                    }
                    VertexOrigin::Face(f) => {
                        assert_eq!(s.face_point(f), Some(v));
                        cage.face_vertices(f).map(|u| cage.position(u)).sum::<DVec3>() / cage.face_valence(f) as f64
                    }
                };
                assert!((s.mesh.position(v) - expected).length() < 1e-15);
            }
            for e in cage.edges() {
                let (a, b) = cage.edge_vertices(e);
                let m = s.edge_point(e);
                let [ca, cb] = s.edge_children(e);
                let ends = |c: EdgeId| {
                    let (x, y) = s.mesh.edge_vertices(c);
                    [x.min(y), x.max(y)]
                };
                assert_eq!(ends(ca), [a.min(m), a.max(m)]);
                assert_eq!(ends(cb), [b.min(m), b.max(m)]);
                assert_eq!((s.edge_parent(ca), s.edge_parent(cb)), (Some(e), Some(e)));
            }
            let halves = s.mesh.edges().filter(|&c| s.edge_parent(c).is_some()).count();
            assert_eq!(halves, 2 * cage.edge_count());
            for f in s.mesh.faces() {
                let parent = s.face_parent(f);
                // Every child face's parent-vertex corners are corners of its parent face.
                for v in s.mesh.face_vertices(f).filter(|v| v.index() < cage.vertex_count()) {
                    assert!(cage.face_vertices(parent).any(|u| u == v));
                }
            }
        }
    }

    #[test]
    fn triangles_rule_refuses_other_faces_and_splits_triangles_in_four() {
        let err = SplitTopology::split(&open_mixed(), SplitRule::Triangles).unwrap_err().to_string();
        assert!(err.contains("face 0 has 4 sides") && err.contains("triangulate"), "{err}");
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let tet = PolyMesh::from_polygons(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]).unwrap();
        let s = SplitTopology::split(&tet, SplitRule::Triangles).unwrap();
        assert_eq!((s.mesh.vertex_count(), s.mesh.face_count()), (10, 16));
        assert!(s.mesh.faces().all(|f| s.mesh.face_valence(f) == 3));
        assert_eq!(s.mesh.euler_characteristic(), 2);
        assert!(tet.faces().all(|f| s.face_point(f).is_none()));
    }

    #[test]
    fn isolated_vertices_are_kept_in_place() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(5.0, 5.0, 5.0)];
        let m = PolyMesh::from_polygons(p, &[[0, 1, 2]]).unwrap();
        let s = SplitTopology::split(&m, SplitRule::Quads).unwrap();
        assert!(s.mesh.is_isolated(VertexId(3)));
        assert_eq!(s.mesh.position(VertexId(3)), DVec3::splat(5.0));
    }
}
