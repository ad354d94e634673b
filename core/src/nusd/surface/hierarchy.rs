//! The refinement hierarchy of a surface solve (`docs/nusd.md`, "Hierarchical refinement").
//!
//! Each level splits every edge at its midpoint; a triangle becomes four triangles, a quad or
//! any n-gon becomes n quads around a new face-centre vertex. Vertex numbering is stable: the
//! vertices of level `l − 1` keep their indices, then come one vertex per edge (in edge order),
//! then one per non-triangular face (in face order). So cage vertex `i` is vertex `i` at every
//! level, which the exporters rely on.
//!
//! A level also remembers, for every vertex, the coarser vertices it was made from (its
//! parents: itself, the two ends of its edge, or the corners of its face). Averaging over the
//! parents is the prolongation used to place new vertices, to carry the domain `D` down the
//! levels, and to pass corrections from a coarse level to the finer ones after an edit.

use super::kernel::Coloring;
use crate::DVec3;
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use rayon::prelude::*;

/// Marks an edge that does not lie on a cage edge.
pub const NOT_ON_CAGE_EDGE: u32 = u32::MAX;

/// The connectivity of one level and how it was made from the level above.
#[derive(Clone, Debug)]
pub struct LevelTopology {
    /// The level's mesh; its positions are the domain positions `D` at construction.
    pub mesh: PolyMesh,
    /// Per edge: the cage edge it lies on, or [`NOT_ON_CAGE_EDGE`].
    pub edge_on_cage: Vec<u32>,
    /// Per vertex: the cage edge it lies strictly inside of, or [`NOT_ON_CAGE_EDGE`] (cage
    /// vertices and vertices inside cage faces).
    pub vertex_on_cage_edge: Vec<u32>,
    /// Number of cage vertices (they are the first vertices of every level).
    pub cage_vertices: usize,
    /// The level's number: 0 for the cage, each split one more.
    pub depth: u32,
    /// Parents in the coarser level as a CSR list (`parent_offsets[v]..parent_offsets[v + 1]`);
    /// empty at level 0.
    pub parent_offsets: Vec<u32>,
    /// See `parent_offsets`.
    pub parents: Vec<u32>,
    /// The vertices in colour classes for Gauss–Seidel sweeps, made on first use.
    coloring: std::sync::OnceLock<Coloring>,
}

impl LevelTopology {
    /// The level's vertices in colour classes ([`Coloring`]), made on first use.
    pub fn coloring(&self) -> &Coloring {
        self.coloring.get_or_init(|| Coloring::of(&self.mesh))
    }

    /// Level 0: the cage itself; every cage edge lies on itself.
    pub fn cage(cage: &PolyMesh) -> Self {
        LevelTopology {
            mesh: cage.clone(),
            edge_on_cage: (0..cage.edge_count() as u32).collect(),
            vertex_on_cage_edge: vec![NOT_ON_CAGE_EDGE; cage.vertex_count()],
            cage_vertices: cage.vertex_count(),
            depth: 0,
            parent_offsets: Vec::new(),
            coloring: Default::default(),
            parents: Vec::new(),
        }
    }

    /// Number of vertices of this level.
    pub fn vertex_count(&self) -> usize {
        self.mesh.vertex_count()
    }

    /// The next finer level. Its mesh positions are the prolongation of this level's.
    pub fn refine(&self) -> crate::Result<LevelTopology> {
        let coarse = &self.mesh;
        let nv = coarse.vertex_count();
        let ne = coarse.edge_count();
        let mut parent_offsets = Vec::with_capacity(nv + ne + coarse.face_count() + 1);
        let mut parents = Vec::with_capacity(nv + 2 * ne + 4 * coarse.face_count());
        parent_offsets.push(0u32);
        for v in 0..nv as u32 {
            parents.push(v);
            parent_offsets.push(parents.len() as u32);
        }
        for e in coarse.edges() {
            let (a, b) = coarse.edge_vertices(e);
            parents.extend([a.0, b.0]);
            parent_offsets.push(parents.len() as u32);
        }
        let edge_vertex = |e: EdgeId| (nv + e.index()) as u32;
        let mut offsets: Vec<u32> = Vec::with_capacity(coarse.face_count() * 4 + 1);
        let mut indices: Vec<u32> = Vec::with_capacity(coarse.halfedge_count() * 4);
        offsets.push(0);
        let mut next_face_vertex = (nv + ne) as u32;
        let mut hs = Vec::new();
        for f in coarse.faces() {
            hs.clear();
            hs.extend(coarse.face_halfedges(f));
            let n = hs.len();
            let corner = |k: usize| coarse.from_vertex(hs[k]).0;
            let mid = |k: usize| edge_vertex(hs[k].edge());
            let mut push = |face: &[u32]| {
                indices.extend_from_slice(face);
                offsets.push(indices.len() as u32);
            };
            if n == 3 {
                push(&[corner(0), mid(0), mid(2)]);
                push(&[mid(0), corner(1), mid(1)]);
                push(&[mid(2), mid(1), corner(2)]);
                push(&[mid(0), mid(1), mid(2)]);
            } else {
                let centre = next_face_vertex;
                next_face_vertex += 1;
                for k in 0..n {
                    push(&[corner(k), mid(k), centre, mid((k + n - 1) % n)]);
                }
                parents.extend((0..n).map(corner));
                parent_offsets.push(parents.len() as u32);
            }
        }
        let count = next_face_vertex as usize;
        let mut positions = vec![DVec3::ZERO; count];
        prolong_into(&parent_offsets, &parents, coarse.positions(), &mut positions);
        let mesh = PolyMesh::from_face_list(positions, &offsets, &indices)?;

        // Edges along a coarse edge inherit its cage edge; all others lie inside a cage face.
        let mut edge_on_cage = vec![NOT_ON_CAGE_EDGE; mesh.edge_count()];
        let mut vertex_on_cage_edge = self.vertex_on_cage_edge.clone();
        vertex_on_cage_edge.resize(count, NOT_ON_CAGE_EDGE);
        for e in coarse.edges() {
            let tag = self.edge_on_cage[e.index()];
            if tag == NOT_ON_CAGE_EDGE {
                continue;
            }
            let m = VertexId(edge_vertex(e));
            vertex_on_cage_edge[m.index()] = tag;
            let (a, b) = coarse.edge_vertices(e);
            for end in [a, b] {
                let h = mesh.find_halfedge(end, m).expect("a split edge joins its end to its midpoint");
                edge_on_cage[h.edge().index()] = tag;
            }
        }
        Ok(LevelTopology {
            mesh,
            edge_on_cage,
            vertex_on_cage_edge,
            cage_vertices: self.cage_vertices,
            depth: self.depth + 1,
            parent_offsets,
            parents,
            coloring: Default::default(),
        })
    }

    /// Averages coarse values over each vertex's parents (`fine.len()` = this level's vertices).
    pub fn prolong(&self, coarse: &[DVec3], fine: &mut [DVec3]) {
        prolong_into(&self.parent_offsets, &self.parents, coarse, fine);
    }

    /// Adds the parent average of `coarse_delta` to `fine`.
    pub fn prolong_add(&self, coarse_delta: &[DVec3], fine: &mut [DVec3]) {
        let (offsets, parents) = (&self.parent_offsets, &self.parents);
        fine.par_iter_mut().with_min_len(4096).enumerate().for_each(|(v, out)| {
            *out += parent_average(offsets, parents, coarse_delta, v);
        });
    }
}

fn parent_average(offsets: &[u32], parents: &[u32], coarse: &[DVec3], v: usize) -> DVec3 {
    let range = offsets[v] as usize..offsets[v + 1] as usize;
    let n = range.len() as f64;
    let sum: DVec3 = parents[range].iter().map(|&p| coarse[p as usize]).sum();
    sum / n
}

fn prolong_into(offsets: &[u32], parents: &[u32], coarse: &[DVec3], fine: &mut [DVec3]) {
    fine.par_iter_mut().with_min_len(4096).enumerate().for_each(|(v, out)| {
        *out = parent_average(offsets, parents, coarse, v);
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mixed_cage() -> PolyMesh {
        // A square pyramid: one quad and four triangles, closed.
        let p = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.5, 0.5, 1.0),
        ];
        PolyMesh::from_polygons(p, &[vec![0, 3, 2, 1], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]])
            .unwrap()
    }

    #[test]
    fn counts_euler_and_numbering() {
        let l0 = LevelTopology::cage(&mixed_cage());
        let l1 = l0.refine().unwrap();
        l1.mesh.validate().unwrap();
        // 5 + 8 edges + 1 quad centre; 4 quads + 4·4 triangles.
        assert_eq!(l1.vertex_count(), 14);
        assert_eq!(l1.mesh.face_count(), 20);
        assert_eq!(l1.mesh.euler_characteristic(), 2);
        for v in 0..5 {
            assert_eq!(l1.mesh.position(VertexId(v)), l0.mesh.position(VertexId(v)));
        }
        let l2 = l1.refine().unwrap();
        l2.mesh.validate().unwrap();
        assert_eq!(l2.mesh.euler_characteristic(), 2);
        assert_eq!(l2.mesh.face_count(), 80);
    }

    #[test]
    fn cage_edges_are_tracked_down_the_levels() {
        let l0 = LevelTopology::cage(&mixed_cage());
        let l2 = l0.refine().unwrap().refine().unwrap();
        // Each cage edge is split into 4 edges at level 2, with 3 inner vertices.
        for tag in 0..l0.mesh.edge_count() as u32 {
            assert_eq!(l2.edge_on_cage.iter().filter(|&&t| t == tag).count(), 4);
            assert_eq!(l2.vertex_on_cage_edge.iter().filter(|&&t| t == tag).count(), 3);
        }
        // Inner vertices of a cage edge lie on the straight cage edge.
        for v in l2.mesh.vertices() {
            let tag = l2.vertex_on_cage_edge[v.index()];
            if tag != NOT_ON_CAGE_EDGE {
                let (a, b) = l0.mesh.edge_vertices(EdgeId(tag));
                let (pa, pb, p) = (l0.mesh.position(a), l0.mesh.position(b), l2.mesh.position(v));
                assert!(((p - pa).cross(pb - pa)).length() < 1e-12);
            }
        }
    }

    #[test]
    fn prolongation_reproduces_affine_functions() {
        let l1 = LevelTopology::cage(&mixed_cage()).refine().unwrap();
        let affine = |p: DVec3| DVec3::new(2.0 * p.x - p.y + 3.0, p.z, 0.5 * p.x);
        let coarse: Vec<DVec3> = mixed_cage().positions().iter().map(|&p| affine(p)).collect();
        let mut fine = vec![DVec3::ZERO; l1.vertex_count()];
        l1.prolong(&coarse, &mut fine);
        for (v, &f) in fine.iter().enumerate() {
            assert!((f - affine(l1.mesh.positions()[v])).length() < 1e-12);
        }
    }
}
