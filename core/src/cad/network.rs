//! A scheme's surface as a network of four-sided patches, each sampled on a regular grid: what
//! the CAD fitter ([`super::fit`]) reads, whatever the scheme.
//!
//! The patches are the faces of an all-quad layout: the cage itself when it is all quads, else
//! its first Catmull–Clark-style refinement (every n-gon split into n quads at its centre), as
//! NUSD and Catmull–Clark both refine. Patch `f`'s parameters follow its face: corner 0 is the
//! start of `layout.face_halfedge(f)`, `u` runs along that halfedge and `v` along the face's last
//! halfedge reversed (the convention of the curve mesh's Gregory patches), so `∂u × ∂v` points
//! where the face's normal does. A grid holds `(m + 1)²` samples, `grid[j·(m+1) + i]` at
//! `(i/m, j/m)`; neighbouring patches share the samples of their common side.
//!
//! - Catmull–Clark: the exact limit points of level `L` (`m = 2^L` per cage quad).
//! - NUSD: the solved finest level (its points are the surface; there is nothing finer).
//! - Curve mesh: the Gregory patches evaluated exactly, at any `m`.

use crate::gregory::curve_mesh::CurveMesh;
use crate::gregory::patch::SurfacePatch;
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};

/// Four-sided patches sampled on grids, with the sides and points where the surface may break.
#[derive(Clone, Debug)]
pub struct PatchNetwork {
    /// The all-quad layout (its positions are the patch corners).
    pub layout: PolyMesh,
    /// Samples per patch side (a power of two).
    pub m: usize,
    /// Per layout face, `(m + 1)²` surface points.
    pub grids: Vec<Vec<DVec3>>,
    /// Per layout face, the surface's exact unit normals at the samples, where the scheme has
    /// them (zero where it does not); `None` to estimate them from the samples.
    pub normals: Option<Vec<Vec<DVec3>>>,
    /// Per layout edge: true where the surface has a crease (no tangent continuity across it).
    pub sharp: Vec<bool>,
    /// Per layout vertex: true at a sharp corner (no tangent plane).
    pub corner: Vec<bool>,
    /// Per layout vertex: how many rings of knots (`2^-1 … 2^-k` of the side) its patches take
    /// towards it (0 for none): a Catmull–Clark patch is a polynomial on each ring around an
    /// extraordinary vertex.
    pub grade: Vec<u32>,
    /// True when the innermost cell of those rings is where the surface stops being a
    /// polynomial (an extraordinary vertex of a subdivision surface): the fit then imposes no
    /// tangent plane there and reports the normals of the two innermost rings apart. False when the rings only make
    /// the corner spans short (the curve mesh: a B-spline keeps one twist at a corner where a
    /// Gregory patch has two, and the shorter the first span the less that costs).
    pub singular_corners: bool,
}

impl PatchNetwork {
    /// Index of sample `(i, j)` in a grid.
    pub fn at(&self, i: usize, j: usize) -> usize {
        j * (self.m + 1) + i
    }

    /// Index of the sample `t` steps along side `k` of a patch (in the direction of the side's
    /// halfedge) and `depth` steps inside.
    pub fn at_side(&self, k: usize, t: usize, depth: usize) -> usize {
        let m = self.m;
        match k {
            0 => self.at(t, depth),
            1 => self.at(m - depth, t),
            2 => self.at(m - t, m - depth),
            _ => self.at(depth, m - t),
        }
    }

    /// A network read off a refined mesh: `fine` is `layout` refined `log2(m)` times by a
    /// quad split that keeps every coarse vertex's index (as Catmull–Clark and NUSD do).
    /// `fine_normals`, when given, are the exact unit normals of `fine`'s vertices.
    pub fn from_refined(
        layout: PolyMesh,
        fine: &PolyMesh,
        fine_normals: Option<&[DVec3]>,
        m: usize,
        sharp: Vec<bool>,
        corner: Vec<bool>,
    ) -> Result<Self> {
        check_layout(&layout)?;
        let ids = layout.faces().map(|f| grid_in_refined(&layout, fine, f, m)).collect::<Result<Vec<_>>>()?;
        let grids = ids.iter().map(|g| g.iter().map(|&v| fine.position(v)).collect()).collect();
        let normals = fine_normals.map(|n| ids.iter().map(|g| g.iter().map(|&v| n[v.index()]).collect()).collect());
        let grade = vec![0; layout.vertex_count()];
        Ok(PatchNetwork { layout, m, grids, normals, sharp, corner, grade, singular_corners: true })
    }

    /// A curve mesh's Gregory patches, sampled `m` times per side (smooth everywhere).
    pub fn from_curve_mesh(curves: &CurveMesh, m: usize) -> Result<Self> {
        let layout = curves.topology().clone();
        check_layout(&layout)?;
        let mut grids = Vec::with_capacity(layout.face_count());
        let mut normals = Vec::with_capacity(layout.face_count());
        for f in layout.faces() {
            let patch = curves.patch(f);
            let (mut g, mut n) = (Vec::with_capacity((m + 1) * (m + 1)), Vec::with_capacity((m + 1) * (m + 1)));
            for j in 0..=m {
                for i in 0..=m {
                    let (u, v) = (i as f64 / m as f64, j as f64 / m as f64);
                    g.push(patch.point(u, v));
                    n.push(patch.normal(u, v).unwrap_or(DVec3::ZERO));
                }
            }
            grids.push(g);
            normals.push(n);
        }
        let sharp = vec![false; layout.edge_count()];
        let corner = vec![false; layout.vertex_count()];
        // Rings at every corner down to two samples: a Gregory patch's twist is singular at its
        // corners (its inner points blend as u/(u+v)), so its spans there must be short.
        let grade = vec![m.trailing_zeros().saturating_sub(1); layout.vertex_count()];
        Ok(PatchNetwork { layout, m, grids, normals: Some(normals), sharp, corner, grade, singular_corners: false })
    }
}

pub(super) fn check_layout(layout: &PolyMesh) -> Result<()> {
    if layout.face_count() == 0 {
        return Err(Error::Input("the surface is empty: there are no faces to export".into()));
    }
    if let Some(f) = layout.faces().find(|&f| layout.face_valence(f) != 4) {
        return Err(Error::Input(format!("patch {} is not four-sided", f.0)));
    }
    Ok(())
}

/// The next halfedge along a grid line: across the far side of `h`'s face's neighbour.
fn straight_on(mesh: &PolyMesh, h: HalfedgeId) -> Option<HalfedgeId> {
    let across = mesh.next(h).twin();
    (!mesh.is_boundary_halfedge(across)).then(|| mesh.next(across))
}

/// The fine halfedge leaving coarse corner `a` along the coarse halfedge `a → b`, inside the
/// coarse face: the one whose straight line reaches `b` after `m` steps.
fn first_halfedge(fine: &PolyMesh, a: VertexId, b: VertexId, m: usize) -> Option<HalfedgeId> {
    fine.outgoing(a).find(|&h| {
        if fine.is_boundary_halfedge(h) {
            return false;
        }
        let mut h = h;
        for _ in 1..m {
            match straight_on(fine, h) {
                Some(next) => h = next,
                None => return false,
            }
        }
        fine.to_vertex(h) == b
    })
}

/// The fine vertices of coarse face `f`'s grid.
pub(super) fn grid_in_refined(layout: &PolyMesh, fine: &PolyMesh, f: FaceId, m: usize) -> Result<Vec<VertexId>> {
    let h0 = layout.face_halfedge(f);
    let (a, b) = (layout.from_vertex(h0), layout.to_vertex(h0));
    let lost = || Error::Input(format!("patch {} could not be found in the refined surface", f.0));
    let mut row = first_halfedge(fine, a, b, m).ok_or_else(lost)?;
    let mut ids = vec![VertexId::INVALID; (m + 1) * (m + 1)];
    for j in 0..m {
        let mut h = row;
        for i in 0..m {
            ids[j * (m + 1) + i] = fine.from_vertex(h);
            ids[j * (m + 1) + i + 1] = fine.to_vertex(h);
            if j + 1 == m {
                let top = fine.next(fine.next(h));
                ids[m * (m + 1) + i] = fine.to_vertex(top);
                ids[m * (m + 1) + i + 1] = fine.from_vertex(top);
            }
            if i + 1 < m {
                h = straight_on(fine, h).ok_or_else(lost)?;
            }
        }
        if j + 1 < m {
            row = fine.next(fine.next(row)).twin();
        }
    }
    let corners = [ids[0], ids[m], ids[m * (m + 1) + m], ids[m * (m + 1)]];
    let expected: Vec<VertexId> = layout.face_vertices(f).collect();
    if corners[..] != expected[..] {
        return Err(lost());
    }
    Ok(ids)
}

/// True for every edge of `layout` that lies on a boundary.
pub fn boundary_edges(layout: &PolyMesh) -> Vec<bool> {
    layout.edges().map(|e: EdgeId| layout.is_boundary_edge(e)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::subdiv::{RefinedPositions, Refinement, Scheme};

    #[test]
    fn grids_of_a_refined_cube_have_the_cage_corners_and_share_their_sides() {
        let cube = crate::mesh::edit::fixtures::cube();
        let refinement = Refinement::new(&cube, Scheme::CatmullClark, &vec![0.0; cube.edge_count()], 3).unwrap();
        let mut positions = RefinedPositions::default();
        refinement.evaluate(cube.positions(), &mut positions).unwrap();
        let fine = refinement.surface(positions.finest());
        let n = PatchNetwork::from_refined(cube.clone(), &fine, None, 8, vec![false; 12], vec![false; 8]).unwrap();
        assert_eq!(n.grids.len(), 6);
        for f in cube.faces() {
            let g = &n.grids[f.index()];
            let v: Vec<_> = cube.face_vertices(f).collect();
            assert_eq!(g[n.at(0, 0)], fine.position(v[0]));
            assert_eq!(g[n.at(8, 0)], fine.position(v[1]));
            assert_eq!(g[n.at(8, 8)], fine.position(v[2]));
            assert_eq!(g[n.at(0, 8)], fine.position(v[3]));
        }
        // Every side's samples appear, reversed, in the neighbour's grid.
        for h in (0..cube.halfedge_count() as u32).map(HalfedgeId) {
            let side = |h: HalfedgeId| -> Vec<DVec3> {
                let f = cube.face(h);
                let g = &n.grids[f.index()];
                let k = cube.face_halfedges(f).position(|x| x == h).unwrap();
                (0..=8)
                    .map(|t| match k {
                        0 => g[n.at(t, 0)],
                        1 => g[n.at(8, t)],
                        2 => g[n.at(8 - t, 8)],
                        _ => g[n.at(0, 8 - t)],
                    })
                    .collect()
            };
            let mut other = side(h.twin());
            other.reverse();
            assert_eq!(side(h), other);
        }
    }
}
