//! Vertex normals for the curvature estimate.
//!
//! The tensor fit differentiates normals along edges, so a normal error of order `h` (the edge
//! length) becomes a curvature error of order 1 that no refinement removes. Averages of face
//! normals are that inaccurate wherever the mesh is irregular: area weights are off by `O(h)` at
//! every vertex whose neighbours are unevenly spread; Max's weights (Max, "Weights for computing
//! vertex normals from facet normals", JGT 1999; the ones Rusinkiewicz's own code uses) are exact
//! when the vertex and its neighbours lie on a sphere but `O(h)` elsewhere. The default therefore
//! fits a quadric height function `z = ½Ax² + Bxy + ½Cy² + Dx + Ey` through the vertex to the
//! corners of its faces (least squares, in the frame of Max's normal) and takes the fitted
//! surface's normal, which is second-order accurate on any sampling. Where fewer than five
//! corners surround the vertex, and on the boundary, the fit takes in the next ring as well;
//! where it is still
//! ill-posed (too few or collinear neighbours) or turns far from Max's normal (a crease, a very
//! coarse mesh) the vertex keeps Max's normal.

use super::MIN_PARALLEL_LEN;
use super::tensor::Frame;
use crate::DVec3;
use crate::mesh::{PolyMesh, VertexId};
use rayon::prelude::*;

/// How [`vertex_curvature_with`](super::vertex_curvature_with) estimates vertex normals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum VertexNormals {
    /// Normal of a quadric fitted to the vertex's neighbourhood (second-order accurate; see the
    /// module documentation). The default.
    #[default]
    Fitted,
    /// Face normals weighted by Max's weights: exact on spheres, first-order elsewhere.
    MaxWeights,
    /// The mesh's area-weighted normals ([`PolyMesh::vertex_normals`]), as used for shading:
    /// first-order accurate, so the curvature error stops shrinking on irregular meshes.
    AreaWeighted,
}

/// Fewest neighbours the quadric fit uses before it widens to the second ring (five unknowns).
const MIN_FIT_POINTS: usize = 5;
/// The fitted normal replaces Max's only within this cosine of it (about 25°).
const MIN_FIT_AGREEMENT: f64 = 0.9;
/// Relative pivot below which the fit's 5×5 system counts as singular.
const SINGULAR_PIVOT: f64 = 1e-10;

/// Unit vertex normals by `method` (zero for isolated vertices and where all faces around a
/// vertex are degenerate).
pub(super) fn vertex_normals(mesh: &PolyMesh, method: VertexNormals) -> Vec<DVec3> {
    match method {
        VertexNormals::AreaWeighted => mesh.vertex_normals(),
        VertexNormals::MaxWeights => max_weighted(mesh),
        VertexNormals::Fitted => {
            let initial = max_weighted(mesh);
            (0..mesh.vertex_count())
                .into_par_iter()
                .with_min_len(MIN_PARALLEL_LEN)
                .map_init(Vec::new, |ring, v| {
                    let v = VertexId(v as u32);
                    let n0 = initial[v.index()];
                    if n0 == DVec3::ZERO { n0 } else { fitted(mesh, v, n0, ring).unwrap_or(n0) }
                })
                .collect()
        }
    }
}

/// Max's weights: every corner adds `a × b / (|a|²·|b|²)` for its two edge vectors `a`, `b`.
fn max_weighted(mesh: &PolyMesh) -> Vec<DVec3> {
    let positions = mesh.positions();
    (0..mesh.vertex_count())
        .into_par_iter()
        .with_min_len(MIN_PARALLEL_LEN)
        .map(|v| {
            let v = VertexId(v as u32);
            let p = positions[v.index()];
            let mut sum = DVec3::ZERO;
            for h in mesh.outgoing(v).filter(|&h| mesh.face(h).is_valid()) {
                let a = positions[mesh.to_vertex(h).index()] - p;
                let b = positions[mesh.from_vertex(mesh.prev(h)).index()] - p;
                let weight = a.length_squared() * b.length_squared();
                if weight > 0.0 {
                    sum += a.cross(b) / weight;
                }
            }
            let n = sum.normalize_or_zero();
            if n.is_finite() { n } else { DVec3::ZERO }
        })
        .collect()
}

/// The normal of the quadric fitted around `v` in the frame of `n0`; `None` where the fit is
/// ill-posed or disagrees with `n0`. `ring` is scratch space.
fn fitted(mesh: &PolyMesh, v: VertexId, n0: DVec3, ring: &mut Vec<VertexId>) -> Option<DVec3> {
    ring.clear();
    add_face_corners(mesh, v, v, ring);
    // A boundary vertex's corners lie on a half-disc, where five of them can fail to fix a
    // quadric (on a square grid they all lie on two lines); the next ring makes the fit sound.
    if ring.len() < MIN_FIT_POINTS || mesh.is_boundary_vertex(v) {
        for i in 0..ring.len() {
            add_face_corners(mesh, ring[i], v, ring);
        }
    }
    if ring.len() < MIN_FIT_POINTS {
        return None;
    }
    let positions = mesh.positions();
    let p = positions[v.index()];
    let frame = Frame::new(n0, positions[ring[0].index()] - p);
    // Fit in units of the mean neighbour distance, for a well-scaled system.
    let scale = ring.iter().map(|w| (positions[w.index()] - p).length()).sum::<f64>() / ring.len() as f64;
    let mut system = [[0.0; 6]; 5]; // normal equations, right-hand side in column 5
    for w in ring.iter() {
        let d = (positions[w.index()] - p) / scale;
        let (x, y, z) = (d.dot(frame.u), d.dot(frame.v), d.dot(frame.n));
        let row = [0.5 * x * x, x * y, 0.5 * y * y, x, y];
        for i in 0..5 {
            for j in 0..5 {
                system[i][j] += row[i] * row[j];
            }
            system[i][5] += row[i] * z;
        }
    }
    let [.., slope_u, slope_v] = solve5(system)?;
    let n = (frame.n - slope_u * frame.u - slope_v * frame.v).normalize();
    (n.dot(n0) > MIN_FIT_AGREEMENT).then_some(n)
}

/// Appends to `ring` the corners of `center`'s faces that are neither `exclude` nor already in.
fn add_face_corners(mesh: &PolyMesh, center: VertexId, exclude: VertexId, ring: &mut Vec<VertexId>) {
    for h in mesh.outgoing(center) {
        let f = mesh.face(h);
        if f.is_valid() {
            for w in mesh.face_vertices(f) {
                if w != exclude && !ring.contains(&w) {
                    ring.push(w);
                }
            }
        }
    }
}

/// Gaussian elimination with partial pivoting on the augmented 5×6 system; `None` when a pivot
/// is negligible against the matrix's trace.
fn solve5(mut m: [[f64; 6]; 5]) -> Option<[f64; 5]> {
    let trace: f64 = (0..5).map(|i| m[i][i]).sum();
    for col in 0..5 {
        let pivot = (col..5).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        m.swap(col, pivot);
        let sound = m[col][col].abs() > SINGULAR_PIVOT * trace; // false for NaN
        if !sound {
            return None;
        }
        for row in col + 1..5 {
            let factor = m[row][col] / m[col][col];
            for k in col..6 {
                m[row][k] -= factor * m[col][k];
            }
        }
    }
    let mut x = [0.0; 5];
    for row in (0..5).rev() {
        let tail: f64 = (row + 1..5).map(|k| m[row][k] * x[k]).sum();
        x[row] = (m[row][5] - tail) / m[row][row];
    }
    x.iter().all(|x| x.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangulated patch of `z = f(x, y)` around the origin, irregularly spaced, `t` wide.
    fn patch(t: f64, f: impl Fn(f64, f64) -> f64) -> PolyMesh {
        let ring = [(1.1, 0.2), (0.5, 0.9), (-0.7, 1.2), (-1.0, -0.1), (-0.4, -1.0), (0.8, -0.7)];
        let mut p = vec![DVec3::new(0.0, 0.0, f(0.0, 0.0))];
        p.extend(ring.iter().map(|&(x, y)| DVec3::new(t * x, t * y, f(t * x, t * y))));
        let faces: Vec<[u32; 3]> = (0..6).map(|i| [0, 1 + i, 1 + (i + 1) % 6]).collect();
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn the_fitted_normal_is_second_order_accurate() {
        // Normal at 0 along (−0.3, −0.2, 1); the cubic term keeps the fit from being exact.
        let f = |x: f64, y: f64| 0.3 * x + 0.2 * y + x * x - 3.0 * x * y + 2.0 * y * y + x * x * y;
        let exact = DVec3::new(-0.3, -0.2, 1.0).normalize();
        let error = |t: f64, method| (vertex_normals(&patch(t, f), method)[0] - exact).length();
        for t in [0.1, 0.05, 0.025] {
            let (fitted, coarse) = (error(t, VertexNormals::Fitted), error(2.0 * t, VertexNormals::Fitted));
            let (area, area_coarse) =
                (error(t, VertexNormals::AreaWeighted), error(2.0 * t, VertexNormals::AreaWeighted));
            assert!(coarse / fitted > 3.5, "fitted normals: {coarse:e} → {fitted:e} when the patch halves");
            assert!(area_coarse / area < 2.5 && area > 10.0 * fitted, "area-weighted: {area_coarse:e} → {area:e}");
        }
    }

    #[test]
    fn max_weights_are_exact_on_a_sphere() {
        let mesh = patch(0.1, |x, y| (4.0 - x * x - y * y).sqrt() - 2.0);
        let n = vertex_normals(&mesh, VertexNormals::MaxWeights)[0];
        assert!((n - DVec3::Z).length() < 1e-14, "{n}");
    }

    #[test]
    fn small_rings_widen_or_fall_back() {
        // A single triangle: two neighbours only, so Max's normal stands.
        let mesh = PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[[0u32, 1, 2]]).unwrap();
        assert_eq!(vertex_normals(&mesh, VertexNormals::Fitted), vec![DVec3::Z; 3]);
    }
}
