//! The fitted faces and edge curves assembled into a B-rep: one edge per network edge, one shell
//! per connected part of the layout, closed parts turned to enclose positive volume.

use super::brep::{BSplineCurve, BSplineSurface, BrepEdge, BrepFace, BrepModel, BrepShell};
use super::bspline::{DEGREE, Knots};
use super::network::PatchNetwork;
use crate::DVec3;
use crate::mesh::{FaceId, HalfedgeId, PolyMesh};

/// The B-rep of the fitted faces: one edge per network edge, one shell per connected part,
/// every face turned so that closed parts enclose positive volume.
pub(super) fn model(
    net: &PatchNetwork,
    curves: &[(Knots, usize, Vec<DVec3>)],
    surfaces: Vec<BSplineSurface>,
) -> BrepModel {
    let layout = &net.layout;
    let vertices = layout.positions().to_vec();
    let edges = layout
        .edges()
        .map(|e| {
            let (a, b) = layout.edge_vertices(e);
            let (knots, _, points) = &curves[e.index()];
            let (knots, multiplicities) = knots.with_multiplicities();
            let curve = BSplineCurve { degree: DEGREE, knots, multiplicities, points: points.clone() };
            BrepEdge { start: a.index(), end: b.index(), curve }
        })
        .collect();
    let parts = components(layout);
    let mut faces = Vec::with_capacity(surfaces.len());
    for (f, surface) in layout.faces().zip(surfaces) {
        let outer: Vec<(usize, bool)> = layout
            .face_halfedges(f)
            .map(|h| (h.edge().index(), layout.from_vertex(h) == layout.edge_vertices(h.edge()).0))
            .collect();
        let outer_uv = layout.face_halfedges(f).map(|h| side_uv(layout, h)).collect();
        faces.push(BrepFace { surface, outer, outer_uv, same_sense: true });
    }
    let mut shells = Vec::new();
    for part in parts {
        let closed = part.iter().all(|&f| layout.face_halfedges(f).all(|h| !layout.is_boundary_halfedge(h.twin())));
        if closed && signed_volume(net, &part) < 0.0 {
            for &f in &part {
                let face = &mut faces[f.index()];
                face.same_sense = false;
                face.outer.reverse();
                face.outer_uv.reverse();
                for entry in &mut face.outer {
                    entry.1 = !entry.1;
                }
            }
        }
        shells.push(BrepShell { faces: part.iter().map(|f| f.index()).collect(), closed });
    }
    BrepModel { vertices, edges, faces, shells }
}

/// Where the edge of halfedge `h` lies on the patch of `h`'s face, in the patch's own
/// parameters: the `(u, v)` at the edge curve's start and at its end. Side `k` of a patch runs
/// from corner `k` to corner `k + 1` of the unit square, and an edge curve is its side's
/// boundary curve with the same parameter, reversed where the edge runs against the halfedge.
pub(super) fn side_uv(layout: &PolyMesh, h: HalfedgeId) -> [[f64; 2]; 2] {
    const CORNERS: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let k = layout.face_halfedges(layout.face(h)).position(|x| x == h).expect("a halfedge of its own face");
    let (from, to) = (CORNERS[k], CORNERS[(k + 1) % 4]);
    if layout.from_vertex(h) == layout.edge_vertices(h.edge()).0 { [from, to] } else { [to, from] }
}

/// The faces of each connected part, in face order.
fn components(layout: &PolyMesh) -> Vec<Vec<FaceId>> {
    let mut part = vec![usize::MAX; layout.face_count()];
    let mut parts = Vec::new();
    for seed in layout.faces() {
        if part[seed.index()] != usize::MAX {
            continue;
        }
        let id = parts.len();
        let mut faces = vec![seed];
        part[seed.index()] = id;
        let mut k = 0;
        while k < faces.len() {
            let f = faces[k];
            k += 1;
            for h in layout.face_halfedges(f) {
                let t = h.twin();
                if !layout.is_boundary_halfedge(t) {
                    let g = layout.face(t);
                    if part[g.index()] == usize::MAX {
                        part[g.index()] = id;
                        faces.push(g);
                    }
                }
            }
        }
        faces.sort();
        parts.push(faces);
    }
    parts
}

/// The volume the part's sample grids enclose (positive when their normals point out).
fn signed_volume(net: &PatchNetwork, part: &[FaceId]) -> f64 {
    let m = net.m;
    let mut v = 0.0;
    for f in part {
        let g = &net.grids[f.index()];
        for j in 0..m {
            for i in 0..m {
                let p = |i: usize, j: usize| g[j * (m + 1) + i];
                v += p(i, j).dot(p(i + 1, j).cross(p(i + 1, j + 1)));
                v += p(i, j).dot(p(i + 1, j + 1).cross(p(i, j + 1)));
            }
        }
    }
    v / 6.0
}
