//! Helpers of the subdivision tests: a refinement evaluated, uniform cubic B-splines evaluated
//! here (the independent reference of the regular parts), and shared cages.

use crate::grid;
use taut_core::mesh::edit::Triangulation;
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme};
use taut_core::{DVec3, PolyMesh};

/// Every face cut into triangles (the cage-editing triangulation; vertices kept).
pub fn triangulate(mesh: &PolyMesh, how: Triangulation) -> taut_core::Result<PolyMesh> {
    Ok(taut_core::mesh::edit::triangulate(mesh, None, how)?.mesh)
}

pub fn refine(cage: &PolyMesh, scheme: Scheme, sharpness: &[f64], levels: u32) -> (Refinement, RefinedPositions) {
    let r = Refinement::new(cage, scheme, sharpness, levels).expect("valid cage");
    let mut out = RefinedPositions::default();
    r.evaluate(cage.positions(), &mut out).unwrap();
    (r, out)
}

/// Uniform cubic B-spline basis on one span and its derivative.
pub fn bspline(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [-s * s / 2.0, (3.0 * t * t - 4.0 * t) / 2.0, (-3.0 * t * t + 2.0 * t + 1.0) / 2.0, t * t / 2.0],
    )
}

/// The point at parameter `t ∈ [0, 1]` of span `i` of the closed uniform cubic B-spline of `p`.
pub fn closed_bspline(p: &[DVec3], i: usize, t: f64) -> DVec3 {
    let n = p.len();
    let (b, _) = bspline(t);
    (0..4).map(|k| b[k] * p[(i + n + k - 1) % n]).sum()
}

/// The tensor-product uniform bicubic B-spline of a `(nx + 1) × (ny + 1)` grid of control points
/// (row-major, `x` fastest) at `(u, v)`, with its partial derivatives.
pub fn bicubic(p: &[DVec3], nx: usize, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let (i, j) = (u.floor() as usize, v.floor() as usize);
    let ((bu, du), (bv, dv)) = (bspline(u - i as f64), bspline(v - j as f64));
    let (mut s, mut su, mut sv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for a in 0..4 {
        for b in 0..4 {
            let q = p[(j + b - 1) * (nx + 1) + i + a - 1];
            s += bu[a] * bv[b] * q;
            su += du[a] * bv[b] * q;
            sv += bu[a] * dv[b] * q;
        }
    }
    (s, su, sv)
}

/// A smooth, bumpy grid patch.
pub fn bumpy_grid(n: u32) -> PolyMesh {
    grid(n, n, 1.0, |x, y| (0.9 * x).sin() * (0.6 * y).cos() + 0.05 * x * y)
}
