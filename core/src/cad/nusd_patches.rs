//! NUSD's solved surface as four-sided patches for the CAD fit.
//!
//! NUSD refines a quad or any n-gon into quads around a centre and a triangle into four
//! triangles (`nusd::surface::hierarchy`). On a cage of quads the patches are the cage faces; on
//! any other cage they are the faces of the first split of every face into quads around its
//! centre (corner, edge midpoint, centre, edge midpoint), the layout Catmull–Clark uses too.
//! Inside an n-gon (n ≥ 4) those quads are NUSD's own level-1 faces, and each patch reads its
//! grid straight off the finest level. Inside a triangle NUSD's finest level is a triangular
//! grid of `2^L` steps a side: the three patches meeting at the triangle's centroid read it at
//! their sample points by quadratic interpolation over the next coarser level's triangles (each
//! a triangle of two steps a side, its corners and edge midpoints the six nodes). On the
//! triangle's sides the samples fall on the finest level's points, so a triangle's patches meet
//! their neighbours in exactly the points the neighbours have; inside it the interpolant departs
//! from the limit surface by the cube of the finest spacing, and is what the export stands for
//! there. Sample positions are computed in integers, so two patches that share a side find the
//! same points bit for bit.

use super::network::{PatchNetwork, check_layout, grid_in_refined};
use crate::document::Document;
use crate::mesh::{FaceId, PolyMesh, VertexId};
use crate::nusd::surface::SurfaceSolver;
use crate::{DVec3, Error, Result};

/// The relative tolerance the NUSD surface is solved to for export (the document's, if tighter).
pub const EXPORT_TOL: f64 = 1e-4;

/// NUSD solved to `levels` (at most [`crate::nusd::MAX_LEVELS`]), its finest level on the
/// patches of level `base` (0 on a cage of quads, else 1); and the level it was solved to.
pub(super) fn nusd_network(doc: &Document, base: u32, levels: u32) -> Result<(PatchNetwork, u32)> {
    let levels = levels.min(crate::nusd::MAX_LEVELS);
    let mut solved = doc.clone();
    solved.settings.levels = levels;
    // Exported to CAD, the surface is the fixed point to a tenth of the default tolerance: a
    // solve stopped at 1e-3 T leaves its unfinished part in the normals (the knob's differed by
    // 0.18° across cage edges at 1e-3, 0.10° at 1e-4), which the fit must then follow.
    solved.settings.tol = solved.settings.tol.min(EXPORT_TOL);
    let mut solver = SurfaceSolver::new(&solved)?;
    solver.solve()?;
    let surface =
        |l: u32| solver.level_surface(l).ok_or_else(|| Error::Solver(format!("NUSD level {l} was not solved")));
    let fine = surface(levels)?;
    let m = 1usize << (levels - base);
    let cage = &doc.cage;
    let net = if cage.faces().all(|f| cage.face_valence(f) != 3) {
        let mut layout = surface(base)?;
        // The patch corners where the finest level has them (a vertex keeps its index down the
        // levels, and a coarser level's points are not on the finest surface).
        let count = layout.vertex_count();
        layout.positions_mut().copy_from_slice(&fine.positions()[..count]);
        let (e, v) = (layout.edge_count(), layout.vertex_count());
        PatchNetwork::from_refined(layout, &fine, None, m, vec![false; e], vec![false; v])?
    } else {
        with_triangles(cage, &solver, &fine, levels)?
    };
    Ok((net, levels))
}

/// The patches of a cage with triangles: every face split into quads around its centre.
fn with_triangles(cage: &PolyMesh, solver: &SurfaceSolver, fine: &PolyMesh, levels: u32) -> Result<PatchNetwork> {
    let lost = |what: &str| Error::Input(format!("the NUSD surface could not be read as patches: {what}"));
    let level_one = solver.level_topology(1).ok_or_else(|| lost("level 1 is missing"))?;
    let grids = TriangleGrids::new(cage, solver, fine, levels)?;
    let n = 1i64 << levels;
    // Vertices: NUSD's level 1 (cage vertices, edge midpoints, centres of the other faces, in
    // its numbering), then one centroid per triangle.
    let nusd_count = level_one.vertex_count();
    let mut positions = fine.positions()[..nusd_count].to_vec();
    let (mut polygons, mut origin) = (Vec::new(), Vec::new());
    let edge_vertex = |h: crate::mesh::HalfedgeId| (cage.vertex_count() + h.edge().index()) as u32;
    let (mut next_centre, mut triangle) = (cage.vertex_count() + cage.edge_count(), 0);
    for f in cage.faces() {
        let hs: Vec<_> = cage.face_halfedges(f).collect();
        let k = hs.len();
        let centre = if k == 3 {
            positions.push(grids.point(triangle, [n, n, 3]));
            triangle += 1;
            positions.len() - 1
        } else {
            next_centre += 1;
            next_centre - 1
        };
        for i in 0..k {
            let corner = cage.from_vertex(hs[i]).0;
            polygons.push([corner, edge_vertex(hs[i]), centre as u32, edge_vertex(hs[(i + k - 1) % k])]);
            origin.push((k == 3).then(|| (triangle - 1, i)));
        }
    }
    let layout = PolyMesh::from_polygons(positions, &polygons)?;
    check_layout(&layout)?;
    let m = 1usize << (levels - 1);
    let grids = layout
        .faces()
        .zip(&origin)
        .map(|(f, origin)| match *origin {
            None => Ok(grid_in_refined(&layout, fine, f, m)?.iter().map(|&v| fine.position(v)).collect()),
            Some((t, corner)) => Ok(grids.patch(t, corner, m)),
        })
        .collect::<Result<Vec<_>>>()?;
    let (e, v) = (layout.edge_count(), layout.vertex_count());
    let grade = vec![0; v];
    Ok(PatchNetwork {
        layout,
        m,
        grids,
        normals: None,
        sharp: vec![false; e],
        corner: vec![false; v],
        grade,
        singular_corners: true,
    })
}

/// The finest level's points of every cage triangle, on its triangular grid.
struct TriangleGrids<'a> {
    fine: &'a PolyMesh,
    /// Steps a side.
    n: usize,
    /// Per triangle (in face order), the fine vertex at grid point `(i, j)`, `i` steps towards
    /// its second corner and `j` towards its third, at `i·(n + 1) + j`.
    vertices: Vec<Vec<VertexId>>,
}

impl<'a> TriangleGrids<'a> {
    /// Follows every vertex down the levels from the triangle's corners: an edge's midpoint
    /// whose two ends lie in a triangle lies in it, halfway.
    fn new(cage: &PolyMesh, solver: &SurfaceSolver, fine: &'a PolyMesh, levels: u32) -> Result<Self> {
        let lost = |what: String| Error::Input(format!("the NUSD surface could not be read as patches: {what}"));
        let triangles: Vec<FaceId> = cage.faces().filter(|&f| cage.face_valence(f) == 3).collect();
        // Per vertex of the current level: (triangle, i, j) for each triangle it lies in.
        let mut at: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); cage.vertex_count()];
        for (t, &f) in triangles.iter().enumerate() {
            for (k, v) in cage.face_vertices(f).enumerate() {
                at[v.index()].push((t, usize::from(k == 1), usize::from(k == 2)));
            }
        }
        for l in 1..=levels {
            let topology = solver.level_topology(l).ok_or_else(|| lost(format!("level {l} is missing")))?;
            let parents = |v: usize| {
                &topology.parents[topology.parent_offsets[v] as usize..topology.parent_offsets[v + 1] as usize]
            };
            at = (0..topology.vertex_count())
                .map(|v| match *parents(v) {
                    [p] => at[p as usize].iter().map(|&(t, i, j)| (t, 2 * i, 2 * j)).collect(),
                    [p, q] => at[p as usize]
                        .iter()
                        .filter_map(|&(t, i, j)| {
                            at[q as usize].iter().find(|x| x.0 == t).map(|&(_, i2, j2)| (t, i + i2, j + j2))
                        })
                        .collect(),
                    _ => Vec::new(),
                })
                .collect();
        }
        let n = 1usize << levels;
        let mut vertices = vec![vec![VertexId::INVALID; (n + 1) * (n + 1)]; triangles.len()];
        for (v, places) in at.iter().enumerate() {
            for &(t, i, j) in places {
                let slot = &mut vertices[t][i * (n + 1) + j];
                if i + j > n || *slot != VertexId::INVALID {
                    return Err(lost(format!("triangle {} is not a grid at level {levels}", triangles[t].0)));
                }
                *slot = VertexId(v as u32);
            }
        }
        for (t, grid) in vertices.iter().enumerate() {
            let filled = grid.iter().filter(|&&v| v != VertexId::INVALID).count();
            if filled != (n + 1) * (n + 2) / 2 {
                return Err(lost(format!("triangle {} has {filled} of its grid's points", triangles[t].0)));
            }
        }
        Ok(TriangleGrids { fine, n, vertices })
    }

    /// The surface of triangle `t` at the point whose grid coordinates are `(x, y) / d`, given
    /// as `[x, y, d]`: the finest point there when it is one, else the quadratic through the six
    /// points of the two-step triangle holding it.
    fn point(&self, t: usize, [x, y, d]: [i64; 3]) -> DVec3 {
        let n = self.n as i64;
        let node = |i: i64, j: i64| self.fine.position(self.vertices[t][(i * (n + 1) + j) as usize]);
        if x % d == 0 && y % d == 0 {
            return node(x / d, y / d);
        }
        // In two-step cells: cell (i0, j0), position (s, t) inside it.
        let cell = 2 * d;
        let half = n / 2;
        let (mut i0, mut j0) = ((x / cell).min(half - 1), (y / cell).min(half - 1));
        let (mut s, mut r) = ((x - i0 * cell) as f64 / cell as f64, (y - j0 * cell) as f64 / cell as f64);
        if i0 + j0 > half - 1 {
            if j0 > 0 {
                j0 -= 1;
                r += 1.0;
            } else {
                i0 -= 1;
                s += 1.0;
            }
        }
        let (a, b) = (2 * i0, 2 * j0);
        // Corners, then the midpoints of sides 01, 02, 12, and the barycentric coordinates.
        let (nodes, l1, l2) = if s + r <= 1.0 {
            ([(a, b), (a + 2, b), (a, b + 2), (a + 1, b), (a, b + 1), (a + 1, b + 1)], s, r)
        } else {
            ([(a + 2, b + 2), (a, b + 2), (a + 2, b), (a + 1, b + 2), (a + 2, b + 1), (a + 1, b + 1)], 1.0 - s, 1.0 - r)
        };
        let l0 = 1.0 - l1 - l2;
        let weights = [
            l0 * (2.0 * l0 - 1.0),
            l1 * (2.0 * l1 - 1.0),
            l2 * (2.0 * l2 - 1.0),
            4.0 * l0 * l1,
            4.0 * l0 * l2,
            4.0 * l1 * l2,
        ];
        nodes.iter().zip(weights).map(|(&(i, j), w)| w * node(i, j)).sum()
    }

    /// The `(m + 1)²` samples of the patch at corner `corner` of triangle `t`: the quad (corner,
    /// midpoint of the side leaving it, centroid, midpoint of the side arriving), bilinear in
    /// the triangle's grid coordinates.
    fn patch(&self, t: usize, corner: usize, m: usize) -> Vec<DVec3> {
        let n = self.n as i64;
        // Grid coordinates times 6: corners, side midpoints and the centroid are integers.
        let corners = [[0, 0], [6 * n, 0], [0, 6 * n]];
        let mid = |k: usize| {
            let (p, q) = (corners[k % 3], corners[(k + 1) % 3]);
            [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2]
        };
        let quad = [corners[corner], mid(corner), [2 * n, 2 * n], mid(corner + 2)];
        let m = m as i64;
        let mut grid = Vec::with_capacity(((m + 1) * (m + 1)) as usize);
        for j in 0..=m {
            for i in 0..=m {
                let w = [(m - i) * (m - j), i * (m - j), i * j, (m - i) * j];
                let at = |c: usize| quad.iter().zip(w).map(|(q, w)| q[c] * w).sum::<i64>();
                grid.push(self.point(t, [at(0), at(1), 6 * m * m]));
            }
        }
        grid
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::SchemeKind;

    /// A quadratic in the triangle's grid coordinates.
    fn quadratic(x: f64, y: f64) -> DVec3 {
        DVec3::new(1.0 + 2.0 * x - y + 0.5 * x * x, 0.3 * x * y - y * y, 2.0 - x + 3.0 * y + x * x - 0.7 * x * y)
    }

    /// A triangular grid of `n` steps a side whose points lie on [`quadratic`].
    fn grid_mesh(n: usize) -> (PolyMesh, Vec<VertexId>) {
        let index = |i: usize, j: usize| (i * (n + 1) + j) as u32;
        let mut positions = vec![DVec3::ZERO; (n + 1) * (n + 1)];
        let mut triangles = Vec::new();
        for i in 0..=n {
            for j in 0..=n - i {
                positions[index(i, j) as usize] = quadratic(i as f64, j as f64);
                if i + j < n {
                    triangles.push([index(i, j), index(i + 1, j), index(i, j + 1)]);
                }
                if i + j + 2 <= n {
                    triangles.push([index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)]);
                }
            }
        }
        let used: Vec<VertexId> = (0..(n + 1) * (n + 1))
            .map(|k| if k / (n + 1) + k % (n + 1) <= n { VertexId(k as u32) } else { VertexId::INVALID })
            .collect();
        (PolyMesh::from_polygons(positions, &triangles).unwrap(), used)
    }

    #[test]
    fn a_quadratic_is_read_exactly_anywhere_in_the_triangle() {
        let n = 8;
        let (fine, vertices) = grid_mesh(n);
        let grids = TriangleGrids { fine: &fine, n, vertices: vec![vertices] };
        for (x, y, d) in [(1, 1, 3), (8, 8, 3), (5, 7, 13), (0, 21, 3), (23, 1, 3), (47, 1, 6), (7, 9, 2)] {
            let got = grids.point(0, [x, y, d]);
            let want = quadratic(x as f64 / d as f64, y as f64 / d as f64);
            assert!((got - want).length() < 1e-12, "({x}, {y}) / {d}: {got} against {want}");
        }
        // The three patches of the triangle: each corner, and the sides two of them share, bit
        // for bit.
        let m = n / 2;
        let patches: Vec<Vec<DVec3>> = (0..3).map(|k| grids.patch(0, k, m)).collect();
        let at = |i: usize, j: usize| j * (m + 1) + i;
        for k in 0..3 {
            let next = &patches[(k + 1) % 3];
            for t in 0..=m {
                // Patch k's side from its edge midpoint to the centroid (u = 1) is patch k + 1's
                // from its corner 3 to its corner 2 (v = 1).
                assert_eq!(patches[k][at(m, t)].to_array(), next[at(t, m)].to_array(), "patch {k}, t {t}");
            }
            assert_eq!(patches[k][at(m, m)].to_array(), grids.point(0, [n as i64, n as i64, 3]).to_array());
        }
    }

    #[test]
    fn a_pyramid_of_triangles_and_a_quad_gives_three_patches_a_triangle_sharing_their_sides() {
        let positions = vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.5),
        ];
        let faces: Vec<Vec<u32>> = vec![vec![3, 2, 1, 0], vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]];
        let cage = PolyMesh::from_polygons(positions, &faces).unwrap();
        let doc = Document::new(cage).with_scheme(SchemeKind::Nusd);
        let (net, levels) = nusd_network(&doc, 1, 4).unwrap();
        assert_eq!((levels, net.m, net.layout.face_count()), (4, 8, 4 + 4 * 3));
        let layout = &net.layout;
        let side = |h: crate::mesh::HalfedgeId| -> Vec<[f64; 3]> {
            let f = layout.face(h);
            let k = layout.face_halfedges(f).position(|x| x == h).unwrap();
            (0..=net.m).map(|t| net.grids[f.index()][net.at_side(k, t, 0)].to_array()).collect()
        };
        for e in layout.edges() {
            let (h, twin) = (e.halfedge(0), e.halfedge(1));
            let mut other = side(twin);
            other.reverse();
            assert_eq!(side(h), other, "edge {}", e.index());
        }
        // Corners are the grids' corners.
        for f in layout.faces() {
            let first = layout.from_vertex(layout.face_halfedge(f));
            assert_eq!(net.grids[f.index()][0], layout.position(first));
        }
    }
}
