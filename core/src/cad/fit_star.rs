//! Tangent continuity next to an extraordinary vertex (issue 21: G1 within 0.1° everywhere).
//!
//! Near an extraordinary vertex a Catmull–Clark surface is not a polynomial in the innermost
//! cell of the rings of knots: its normal turns like `r^α` with `α < 1` for valence 5 and more
//! (the curvature is unbounded there), so no bicubic piece follows it, and the two faces on a
//! side, each fitted on its own, miss it differently. Measured before this correction (with the
//! side curves' legs as the data had them), the faces' normals differed by 0.51° at the vertex
//! of the cube (valence 3) and 0.61° at the knob's valence-8 vertex, falling only as `h^0.46`
//! there with the sample spacing `h`; with the legs turned into the tangent plane the vertex
//! agrees but the innermost cell still differs by 0.42° on the knob. What the faces must share
//! is a normal, not the surface's: here both faces at a side take the same target, the samples'
//! exact normals interpolated along the side (at the vertex its limit normal), made
//! perpendicular to the shared side curve's tangent, and the second-row control points next to
//! the corner (the twist and the next two of each side) take the least change that makes the
//! cross-boundary derivative perpendicular to that target along both sides. Each face does this
//! from shared data only, so the correction is per face and deterministic, and the two faces'
//! normals agree wherever both meet their targets. The vertex enclosure problem (a bicubic
//! B-spline has one twist where valence ≠ 4 asks for two) keeps this a least-squares fit, not an
//! identity; the weight on the change trades the remaining angle against the distance to the
//! surface (the moved rows bend the faces away from the non-polynomial cell).

use super::{Context, corner_span, least_squares, side_index};
use crate::DVec3;
use crate::cad::bspline::Knots;
use crate::mesh::FaceId;

/// Control points of each side's second row, counted from the corner, that the correction at
/// a corner moves (the twist, 1, is shared by both sides): their supports reach the fourth ring.
const MOVED: usize = 3;

/// The weight of a moved point's change against the cross-derivative's departure from the target
/// plane (both lengths). Measured on the bundled cages at the default tolerance: 1e-3 leaves
/// 0.005° (cube) and 0.012° (knob) but takes the prism 1.2 times past the tolerance; 5e-3 leaves
/// 0.014°, 0.031° and 0.009° within 0.53, 0.13 and 0.66 of it; 2e-2 leaves 0.12° on the knob.
const MOVE_WEIGHT: f64 = 5e-3;

/// The shared normal at parameter `t` along a side (in its halfedge's direction), interpolated
/// between the samples' `normals` (the innermost cell has no samples inside: there the target is
/// smoother than the surface, which is what lets two bicubic faces meet it).
fn shared_normal(normals: &[DVec3], t: f64) -> DVec3 {
    let m = normals.len() - 1;
    let x = (t * m as f64).clamp(0.0, m as f64);
    let i = (x.floor() as usize).min(m - 1);
    let w = x - i as f64;
    (normals[i] * (1.0 - w) + normals[i + 1] * w).normalize_or_zero()
}

/// Moves the second rows next to corner `c` of face `f`, where that corner is an extraordinary
/// vertex with a tangent plane, so that along both sides at the corner the cross-boundary
/// derivative lies, in the least-squares sense, in the plane of the side curve's tangent and the
/// shared normal (then the face's normal there is that normal). `p` holds the face's boundary
/// rows and fitted second rows; `along` the knots of each side in its halfedge's direction.
pub(super) fn tangent_corner(ctx: &Context<'_>, f: FaceId, c: usize, p: &mut [Vec<DVec3>], along: &[Knots; 4]) {
    let net = ctx.net;
    let layout = &net.layout;
    let m = net.m;
    let Some(v) = layout.face_vertices(f).nth(c) else { return };
    if corner_span(net, v) == 0.0 || ctx.vertex_normals[v.index()].is_none() {
        return;
    }
    let hs: Vec<_> = layout.face_halfedges(f).collect();
    let (last_u, last_v) = (p.len() - 1, p[0].len() - 1);
    // Side c starts at the corner, side c - 1 ends there.
    let sides = [c, (c + 3) % 4];
    let mut unknowns: Vec<(usize, usize)> = Vec::new();
    for (n, &k) in sides.iter().enumerate() {
        let last = along[k].count() - 1;
        if last < 2 * MOVED + 1 || ctx.shared[hs[k].index()].is_none() {
            return;
        }
        for q in 1..=MOVED {
            let a = if n == 0 { q } else { last - q };
            let ij = side_index(k, a, 1, last_u, last_v);
            if !unknowns.contains(&ij) {
                unknowns.push(ij);
            }
        }
    }
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut rhs: Vec<f64> = Vec::new();
    for (n, &k) in sides.iter().enumerate() {
        let knots = &along[k];
        let last = knots.count() - 1;
        let normals = ctx.shared[hs[k].index()].as_ref().expect("checked above");
        let at = |a: usize, depth: usize| {
            let (i, j) = side_index(k, a, depth, last_u, last_v);
            p[i][j]
        };
        // Distances from the corner: dense in the two innermost rings, then every half sample up
        // to the end of the moved points' support.
        let full = knots.full();
        let reach = if n == 0 { full[MOVED + 4] } else { 1.0 - full[last - MOVED] };
        let mut distances: Vec<f64> = (1..=16).map(|x| x as f64 / (8 * m) as f64).collect();
        let mut x = 2.5;
        while x / (m as f64) < reach {
            distances.push(x / m as f64);
            x += 0.5;
        }
        for s in distances {
            let t = if n == 0 { s } else { 1.0 - s };
            let (first, b) = knots.basis(t, false);
            let (_, db) = knots.basis(t, true);
            let tangent: DVec3 = (0..4).map(|r| db[r] * at(first + r, 0)).sum();
            let target = shared_normal(normals, t);
            let t_hat = tangent.normalize_or_zero();
            let normal = (target - target.dot(t_hat) * t_hat).normalize_or_zero();
            let mut row = vec![0.0; 3 * unknowns.len()];
            let mut residual = 0.0;
            for r in 0..4 {
                let a = first + r;
                residual += b[r] * normal.dot(at(a, 1) - at(a, 0));
                let ij = side_index(k, a, 1, last_u, last_v);
                if let Some(u) = unknowns.iter().position(|&x| x == ij) {
                    row[3 * u] += b[r] * normal.x;
                    row[3 * u + 1] += b[r] * normal.y;
                    row[3 * u + 2] += b[r] * normal.z;
                }
            }
            rows.push(row);
            rhs.push(-residual);
        }
    }
    // The least change: a small weight on every coordinate (the constraints leave the moves
    // along the tangent plane free).
    for u in 0..3 * unknowns.len() {
        let mut row = vec![0.0; 3 * unknowns.len()];
        row[u] = MOVE_WEIGHT;
        rows.push(row);
        rhs.push(0.0);
    }
    let keep = vec![true; rows.len()];
    let op = least_squares(&rows, &keep);
    for (u, &(i, j)) in unknowns.iter().enumerate() {
        let d = |c: usize| op[3 * u + c].iter().zip(&rhs).map(|(w, r)| w * r).sum::<f64>();
        p[i][j] += DVec3::new(d(0), d(1), d(2));
    }
}
