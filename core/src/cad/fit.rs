//! Fits a [`PatchNetwork`] with bicubic B-spline faces that share their edges exactly and keep
//! the surface's tangent continuity: the B-rep the STEP writer writes.
//!
//! Each network edge becomes one cubic B-spline curve, fitted once to the edge's samples with its
//! end points on the vertices and, at a smooth vertex, its end tangents in the vertex's tangent
//! plane; both faces on the edge take that curve as their boundary row (refined to their own span
//! count by exact knot insertion), so neighbours meet exactly. A face's second row of control
//! points sets its cross-boundary derivative; it is fitted to the surface's own derivative into
//! the face, first turned into the tangent plane the two faces share along the edge (the mean of
//! their normals), so the two faces' normals agree up to the fit's error, which falls with the
//! span count. The four points next to the corners belong to two such rows and take the mean of
//! both (the corner twist: Gregory patches keep two, a B-spline one); at an extraordinary vertex,
//! where the surface is not a polynomial, the twist and its neighbours are then moved into the
//! shared tangent planes ([`star`]). The inner points are the
//! least-squares fit to the samples. A face starts with as many spans as its edges and doubles
//! them until it is within the tolerance of every sample and its normals along each smooth side
//! agree with its neighbour's within [`MAX_ANGLE_DEGREES`]; a regular Catmull–Clark face (a
//! bicubic polynomial) is reproduced exactly with one span.

use super::assemble;
use super::brep::{BSplineSurface, BrepModel};
use super::bspline::{self, Knots};
use super::network::PatchNetwork;
use crate::mesh::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

#[path = "fit_angles.rs"]
mod angles;
use angles::{angle_degrees, edge_angles, side_angle};

#[path = "fit_star.rs"]
mod star;

/// Normals of neighbouring faces along a smooth edge may differ by at most this much (the export
/// promises 0.1°; the fit aims lower).
pub const MAX_ANGLE_DEGREES: f64 = 0.05;

/// The share of the tolerance a face may be from its samples (the callers check the faces again
/// between the samples, with [`distance_to`]).
pub const SAMPLE_SHARE: f64 = 1.0;

/// What the fit reached.
#[derive(Clone, Debug, PartialEq)]
pub struct FitReport {
    /// Largest distance from a fitted face to the network's samples.
    pub max_distance: f64,
    /// Largest angle (degrees) between neighbouring faces' normals along smooth edges.
    pub max_angle_degrees: f64,
    /// Largest angle (degrees) between the two sides' normals of the sampled surface itself
    /// along smooth edges (0 for an exact G1 scheme; NUSD's finest level is G1 only in the
    /// limit, and not at every extraordinary vertex).
    pub max_surface_gap_degrees: f64,
    /// Largest amount (degrees) by which the faces' angle exceeds the surface's own there: the
    /// fit's own break of tangent continuity.
    pub max_excess_degrees: f64,
    /// Largest angle (degrees) between neighbouring faces' normals within the two innermost
    /// rings of knots around an extraordinary vertex (`2^-k` of a side), where the surface is
    /// not a polynomial and the fit only approximates it; not part of `max_angle_degrees` (it
    /// does not make faces refine: more spans do not reach the innermost cell), but held within
    /// the promised 0.1° by the corner correction of `fit_star.rs`.
    pub max_star_angle_degrees: f64,
    /// Spans per face (both directions).
    pub spans: Vec<usize>,
    /// True when every face is within [`SAMPLE_SHARE`] of the tolerance of its samples and the fit adds at most 0.1° to the
    /// surface's own angle anywhere along a smooth edge.
    pub within: bool,
}

/// A face's control points, `points[i][j]` (`i` along u), its knots and its distance to the
/// samples.
#[derive(Clone, Debug)]
struct FacePatch {
    spans: usize,
    knots_u: Knots,
    knots_v: Knots,
    points: Vec<Vec<DVec3>>,
    distance: f64,
}

/// Everything the face fits read: samples, derivatives, shared normals, edge curves.
struct Context<'a> {
    net: &'a PatchNetwork,
    /// Per halfedge: the surface's derivative into its face along its side.
    inward: Vec<Vec<DVec3>>,
    /// Per halfedge: the unit normal both faces share along it (`None` on sharp and open edges).
    shared: Vec<Option<Vec<DVec3>>>,
    /// Per halfedge: the angle (degrees) between the two faces' own normals along it, from the
    /// samples: how far the surface itself is from tangent continuity there (0 for the exact
    /// schemes, the discretisation for NUSD's finest level).
    own_gap: Vec<Option<Vec<f64>>>,
    /// Per edge: its curve's knots, equal spans and control points (first vertex to second).
    curves: Vec<(Knots, usize, Vec<DVec3>)>,
    /// Per layout vertex: the unit normal of its tangent plane where the surface is smooth there.
    vertex_normals: Vec<Option<DVec3>>,
    tolerance: f64,
}

/// Fits every patch of `net` within `tolerance` (a distance), or reports how close it came.
pub fn fit(net: &PatchNetwork, tolerance: f64) -> Result<(BrepModel, FitReport)> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::Input(format!("the tolerance must be a positive distance, not {tolerance}")));
    }
    if net.m < 4 || !net.m.is_power_of_two() {
        return Err(Error::Input(format!("a patch needs 4, 8, 16… samples per side, not {}", net.m)));
    }
    if net.grids.iter().flatten().any(|p| !p.is_finite()) {
        return Err(Error::Input("the surface has a point that is not a number (NaN or infinite)".into()));
    }
    let layout = &net.layout;
    let halfedges = layout.halfedge_count();
    let mut side = vec![Vec::new(); halfedges];
    let mut inward = vec![Vec::new(); halfedges];
    for f in layout.faces() {
        for (k, h) in layout.face_halfedges(f).enumerate() {
            side[h.index()] = side_samples(net, f, k);
            inward[h.index()] = inward_derivative(net, f, k);
        }
    }
    let own_normal = |h: HalfedgeId| -> Vec<DVec3> {
        let t = along_derivative(&side[h.index()], net.m);
        let exact = exact_side_normals(net, h);
        (0..=net.m)
            .map(|k| {
                let n = exact.as_ref().map_or(DVec3::ZERO, |n| n[k]);
                if n != DVec3::ZERO { n } else { t[k].cross(inward[h.index()][k]).normalize_or_zero() }
            })
            .collect()
    };
    let vertex_normals = vertex_normals(net, &side, &inward);
    let mut shared = vec![None; halfedges];
    let mut own_gap = vec![None; halfedges];
    for e in layout.edges() {
        let (h, twin) = (e.halfedge(0), e.halfedge(1));
        if net.sharp[e.index()] || layout.is_boundary_halfedge(h) || layout.is_boundary_halfedge(twin) {
            continue;
        }
        let (a, b) = (own_normal(h), own_normal(twin));
        let m = net.m;
        let gap: Vec<f64> = (0..=m).map(|t| angle_degrees(a[t], b[m - t])).collect();
        let mut gap_reversed = gap.clone();
        gap_reversed.reverse();
        own_gap[h.index()] = Some(gap);
        own_gap[twin.index()] = Some(gap_reversed);
        let mut n: Vec<DVec3> = (0..=m).map(|t| (a[t] + b[m - t]).normalize_or_zero()).collect();
        if let Some(nv) = vertex_normals[layout.from_vertex(h).index()] {
            n[0] = nv;
        }
        if let Some(nv) = vertex_normals[layout.to_vertex(h).index()] {
            n[m] = nv;
        }
        let mut reversed = n.clone();
        reversed.reverse();
        shared[h.index()] = Some(n);
        shared[twin.index()] = Some(reversed);
    }
    let max_spans = (net.m / 4).max(1);
    let curves: Vec<(Knots, usize, Vec<DVec3>)> = layout
        .edges()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&e| edge_curve(net, &side, &vertex_normals, e, tolerance, max_spans))
        .collect();
    let ctx = Context { net, inward, shared, own_gap, curves, vertex_normals, tolerance };

    let start: Vec<usize> = layout
        .faces()
        .map(|f| layout.face_halfedges(f).map(|h| ctx.curves[h.edge().index()].1).max().unwrap_or(1))
        .collect();
    let mut patches: Vec<FacePatch> = layout
        .faces()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&f| fit_face_adaptive(&ctx, f, start[f.index()], max_spans))
        .collect();
    // Neighbours' normals along smooth edges: where they differ too much, both refine.
    let (max_angle, max_excess, max_star) = loop {
        let angles = edge_angles(&ctx, &patches);
        let max_angle = angles.iter().fold(0.0, |a: f64, &(_, x, _, _)| a.max(x));
        let max_excess = angles.iter().fold(0.0, |a: f64, &(_, _, x, _)| a.max(x));
        let max_star = angles.iter().fold(0.0, |a: f64, &(_, _, _, x)| a.max(x));
        let mut refine = vec![false; patches.len()];
        for &(e, _, excess, _) in &angles {
            if excess > MAX_ANGLE_DEGREES {
                for side in [0, 1] {
                    let f = layout.face(e.halfedge(side));
                    if patches[f.index()].spans < max_spans {
                        refine[f.index()] = true;
                    }
                }
            }
        }
        if !refine.contains(&true) {
            break (max_angle, max_excess, max_star);
        }
        let refitted: Vec<(usize, FacePatch)> = (0..patches.len())
            .into_par_iter()
            .filter(|&i| refine[i])
            .map(|i| (i, fit_face_adaptive(&ctx, FaceId(i as u32), patches[i].spans * 2, max_spans)))
            .collect();
        for (i, p) in refitted {
            patches[i] = p;
        }
    };
    let max_distance = patches.iter().fold(0.0, |a: f64, p| a.max(p.distance));
    let report = FitReport {
        max_distance,
        max_angle_degrees: max_angle,
        max_surface_gap_degrees: ctx.own_gap.iter().flatten().flatten().fold(0.0, |a: f64, &x| a.max(x)),
        max_excess_degrees: max_excess,
        max_star_angle_degrees: max_star,
        spans: patches.iter().map(|p| p.spans).collect(),
        within: max_distance <= SAMPLE_SHARE * tolerance && max_excess <= 2.0 * MAX_ANGLE_DEGREES,
    };
    let surfaces = patches.into_iter().map(|p| BSplineSurface::bicubic(&p.knots_u, &p.knots_v, p.points)).collect();
    Ok((assemble::model(net, &ctx.curves, surfaces), report))
}

/// The exact normals along halfedge `h`'s side of its face, where the network has them.
fn exact_side_normals(net: &PatchNetwork, h: HalfedgeId) -> Option<Vec<DVec3>> {
    let normals = net.normals.as_ref()?;
    let f = net.layout.face(h);
    let k = net.layout.face_halfedges(f).position(|x| x == h)?;
    let g = &normals[f.index()];
    Some((0..=net.m).map(|t| g[net.at_side(k, t, 0)]).collect())
}

/// Samples along side `k` of face `f`, in the direction of its halfedge.
fn side_samples(net: &PatchNetwork, f: FaceId, k: usize) -> Vec<DVec3> {
    let g = &net.grids[f.index()];
    (0..=net.m).map(|t| g[net.at_side(k, t, 0)]).collect()
}

/// The derivative into face `f` across side `k` (per unit of the face's parameter), along the
/// side: fourth-order one-sided differences of the grid.
fn inward_derivative(net: &PatchNetwork, f: FaceId, k: usize) -> Vec<DVec3> {
    let g = &net.grids[f.index()];
    let m = net.m as f64;
    (0..=net.m)
        .map(|t| {
            let s = |d: usize| g[net.at_side(k, t, d)];
            (-25.0 * s(0) + 48.0 * s(1) - 36.0 * s(2) + 16.0 * s(3) - 3.0 * s(4)) * (m / 12.0)
        })
        .collect()
}

/// The derivative along a row of `m + 1` samples (per unit parameter), fourth order.
fn along_derivative(row: &[DVec3], m: usize) -> Vec<DVec3> {
    let h = m as f64;
    (0..=m)
        .map(|t| {
            let s = |i: usize| row[i];
            if t >= 2 && t + 2 <= m {
                (s(t - 2) - 8.0 * s(t - 1) + 8.0 * s(t + 1) - s(t + 2)) * (h / 12.0)
            } else if t < 2 {
                (-25.0 * s(t) + 48.0 * s(t + 1) - 36.0 * s(t + 2) + 16.0 * s(t + 3) - 3.0 * s(t + 4)) * (h / 12.0)
            } else {
                -(-25.0 * s(t) + 48.0 * s(t - 1) - 36.0 * s(t - 2) + 16.0 * s(t - 3) - 3.0 * s(t - 4)) * (h / 12.0)
            }
        })
        .collect()
}

/// Per vertex, the unit normal of its tangent plane where the surface is smooth there (no sharp
/// edge or corner, not on the boundary): the mean of its faces' corner normals.
fn vertex_normals(net: &PatchNetwork, side: &[Vec<DVec3>], inward: &[Vec<DVec3>]) -> Vec<Option<DVec3>> {
    let layout = &net.layout;
    layout
        .vertices()
        .map(|v| {
            if net.corner[v.index()] || layout.is_boundary_vertex(v) || layout.is_isolated(v) {
                return None;
            }
            let mut sum = DVec3::ZERO;
            for h in layout.outgoing(v) {
                if net.sharp[h.edge().index()] {
                    return None;
                }
                // The face of h has v at the start of h: its normal there is along × inward.
                let exact = exact_side_normals(net, h).map_or(DVec3::ZERO, |n| n[0]);
                sum += if exact != DVec3::ZERO {
                    exact
                } else {
                    along_derivative(&side[h.index()], net.m)[0].cross(inward[h.index()][0]).normalize_or_zero()
                };
            }
            Some(sum.normalize_or_zero()).filter(|n| *n != DVec3::ZERO)
        })
        .collect()
}

/// Solves the normal equations of `a` (rows × cols, row-major) over the rows `keep` marks:
/// returns `(aᵀa)⁻¹aᵀ` (cols × rows, zero in the columns of rows not kept), the least-squares
/// operator.
fn least_squares(a: &[Vec<f64>], keep: &[bool]) -> Vec<Vec<f64>> {
    let cols = a.first().map_or(0, Vec::len);
    let rows = a.len();
    let a: Vec<Vec<f64>> = a.iter().zip(keep).map(|(row, &k)| if k { row.clone() } else { vec![0.0; cols] }).collect();
    // Gauss–Jordan on [aᵀa | aᵀ]; aᵀa is symmetric positive definite for the fits here.
    let mut m: Vec<Vec<f64>> = (0..cols)
        .map(|r| {
            let mut row: Vec<f64> = (0..cols).map(|c| (0..rows).map(|k| a[k][r] * a[k][c]).sum()).collect();
            row.extend((0..rows).map(|k| a[k][r]));
            row
        })
        .collect();
    for c in 0..cols {
        let pivot = (c..cols).max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs())).unwrap_or(c);
        m.swap(c, pivot);
        let d = m[c][c];
        if d.abs() < 1e-300 {
            continue;
        }
        for x in m[c].iter_mut() {
            *x /= d;
        }
        for r in 0..cols {
            if r != c {
                let factor = m[r][c];
                if factor != 0.0 {
                    let pivot_row = m[c].clone();
                    for (x, p) in m[r].iter_mut().zip(pivot_row) {
                        *x -= factor * p;
                    }
                }
            }
        }
    }
    m.into_iter().map(|row| row[cols..].to_vec()).collect()
}

/// The basis matrix of `knots` at the `m + 1` sample parameters, restricted to `columns`.
fn basis_matrix(knots: &Knots, m: usize, columns: std::ops::RangeInclusive<usize>) -> Vec<Vec<f64>> {
    (0..=m)
        .map(|k| {
            let (first, n) = knots.basis(k as f64 / m as f64, false);
            columns.clone().map(|c| if c >= first && c < first + 4 { n[c - first] } else { 0.0 }).collect()
        })
        .collect()
}

/// Edge `e`'s curve, from its first vertex to its second: the fewest equal spans (a power of
/// two, graded towards vertices that ask for it) within the tolerance of its samples, ends
/// on the vertices, end tangents in the tangent planes of smooth vertices.
fn edge_curve(
    net: &PatchNetwork,
    side: &[Vec<DVec3>],
    vertex_normals: &[Option<DVec3>],
    e: EdgeId,
    tolerance: f64,
    max_spans: usize,
) -> (Knots, usize, Vec<DVec3>) {
    let layout = &net.layout;
    let h = e.halfedge(0);
    let samples: Vec<DVec3> = if layout.is_boundary_halfedge(h) {
        side[h.twin().index()].iter().rev().copied().collect()
    } else {
        side[h.index()].clone()
    };
    let (a, b) = layout.edge_vertices(e);
    let m = net.m;
    let mut spans = 1;
    loop {
        let knots = Knots::graded(spans, net.grade[a.index()], net.grade[b.index()]);
        let keep = vec![true; m + 1];
        // At an extraordinary end too: the faces' normals at the vertex are then all its limit
        // normal (left as the data had them, the legs were not coplanar and the faces met at
        // 0.5° there); the second rows next to it follow (`fit_star.rs`).
        let plane = |v: VertexId| vertex_normals[v.index()];
        let points = fit_curve(&samples, &keep, &knots, plane(a), plane(b));
        let error = samples
            .iter()
            .enumerate()
            .map(|(k, s)| (bspline::curve_point(&knots, &points, k as f64 / m as f64) - *s).length())
            .fold(0.0, f64::max);
        if error <= tolerance || spans * 2 > max_spans {
            return (knots, spans, points);
        }
        spans *= 2;
    }
}

/// The width of the corner cell at `v` that is not a polynomial piece (0 where all are): the
/// fit only approximates the surface there: the second rows next to it are moved into the
/// shared tangent planes (`fit_star.rs`), and the normals of the two innermost rings are
/// reported apart.
fn corner_span(net: &PatchNetwork, v: VertexId) -> f64 {
    match net.grade[v.index()] {
        k if k > 0 && net.singular_corners => 0.5f64.powi(k as i32),
        _ => 0.0,
    }
}

/// The least-squares cubic B-spline on `knots` through the kept `samples` (at `k / m`), its ends on the
/// first and last sample, its end legs turned into the planes of `start` and `end` normals.
fn fit_curve(samples: &[DVec3], keep: &[bool], knots: &Knots, start: Option<DVec3>, end: Option<DVec3>) -> Vec<DVec3> {
    let m = samples.len() - 1;
    let count = knots.count();
    let (p0, pn) = (samples[0], samples[m]);
    let a = basis_matrix(knots, m, 1..=count - 2);
    let full = basis_matrix(knots, m, 0..=count - 1);
    let rhs: Vec<DVec3> = (0..=m).map(|k| samples[k] - full[k][0] * p0 - full[k][count - 1] * pn).collect();
    let op = least_squares(&a, keep);
    let mut points = vec![p0];
    points.extend(op.iter().map(|row| row.iter().zip(&rhs).map(|(w, r)| *w * *r).sum::<DVec3>()));
    points.push(pn);
    if let Some(n) = start {
        let leg = points[1] - p0;
        points[1] = p0 + (leg - leg.dot(n) * n);
    }
    if let Some(n) = end {
        let leg = points[count - 2] - pn;
        points[count - 2] = pn + (leg - leg.dot(n) * n);
    }
    points
}

/// The curve of `h`'s edge in `h`'s direction on the knots `along` (which hold the edge's).
fn curve_along(ctx: &Context<'_>, h: HalfedgeId, along: &Knots) -> Vec<DVec3> {
    let layout = &ctx.net.layout;
    let e = h.edge();
    let (knots, _, points) = &ctx.curves[e.index()];
    if layout.from_vertex(h) == layout.edge_vertices(e).0 {
        bspline::refine(knots, points, along)
    } else {
        let back: Vec<DVec3> = points.iter().rev().copied().collect();
        bspline::refine(&knots.reversed(), &back, along)
    }
}

/// Control-point index of side `k`'s `a`-th point at `depth` rows inside, for a face whose last
/// indices are `last_u` and `last_v`.
fn side_index(k: usize, a: usize, depth: usize, last_u: usize, last_v: usize) -> (usize, usize) {
    match k {
        0 => (a, depth),
        1 => (last_u - depth, a),
        2 => (last_u - a, last_v - depth),
        _ => (depth, last_v - a),
    }
}

/// Fits face `f` with `spans` equal spans, doubling them until within the tolerance (or
/// `max_spans`).
fn fit_face_adaptive(ctx: &Context<'_>, f: FaceId, spans: usize, max_spans: usize) -> FacePatch {
    let mut spans = spans.clamp(1, max_spans.max(1));
    loop {
        let patch = fit_face(ctx, f, spans);
        let ok =
            patch.distance <= SAMPLE_SHARE * ctx.tolerance && side_angle(ctx, f, &patch) <= 0.5 * MAX_ANGLE_DEGREES;
        if ok || spans * 2 > max_spans {
            return patch;
        }
        spans *= 2;
    }
}

/// The knots of face `f` with `n` equal spans: graded towards the corners that ask for it.
fn face_knots(net: &PatchNetwork, f: FaceId, n: usize) -> (Knots, Knots) {
    let c: Vec<u32> = net.layout.face_vertices(f).map(|v| net.grade[v.index()]).collect();
    (Knots::graded(n, c[0].max(c[3]), c[1].max(c[2])), Knots::graded(n, c[0].max(c[1]), c[3].max(c[2])))
}

/// Face `f` fitted with `n` equal spans in both directions.
fn fit_face(ctx: &Context<'_>, f: FaceId, n: usize) -> FacePatch {
    let net = ctx.net;
    let layout = &net.layout;
    let m = net.m;
    let (knots_u, knots_v) = face_knots(net, f, n);
    let (count_u, count_v) = (knots_u.count(), knots_v.count());
    let (last_u, last_v) = (count_u - 1, count_v - 1);
    let mut p = vec![vec![DVec3::ZERO; count_v]; count_u];
    let hs: Vec<HalfedgeId> = layout.face_halfedges(f).collect();
    // Per side: the knots along it (in its halfedge's direction) and the width of the span
    // across it at the side.
    let along = [knots_u.clone(), knots_v.clone(), knots_u.reversed(), knots_v.reversed()];
    let across = [knots_v.first_width(), knots_u.last_width(), knots_v.last_width(), knots_u.first_width()];
    // Boundary rows: the edges' curves.
    for (k, &h) in hs.iter().enumerate() {
        for (a, q) in curve_along(ctx, h, &along[k]).into_iter().enumerate() {
            let (i, j) = side_index(k, a, 0, last_u, last_v);
            p[i][j] = q;
        }
    }
    // Second rows: the cross-boundary derivative, in the shared tangent plane.
    let mut ring_sum = vec![vec![DVec3::ZERO; count_v]; count_u];
    let mut ring_count = vec![vec![0u32; count_v]; count_u];
    for (k, &h) in hs.iter().enumerate() {
        let knots = &along[k];
        let last = knots.count() - 1;
        let full = basis_matrix(knots, m, 0..=last);
        let keep = vec![true; m + 1];
        let op = least_squares(&basis_matrix(knots, m, 1..=last - 1), &keep);
        let mut target = ctx.inward[h.index()].clone();
        if let Some(normals) = &ctx.shared[h.index()] {
            for (d, nrm) in target.iter_mut().zip(normals) {
                *d -= d.dot(*nrm) * *nrm;
            }
        }
        let at = |a: usize, depth: usize| {
            let (i, j) = side_index(k, a, depth, last_u, last_v);
            p[i][j]
        };
        let width = across[k];
        let d_first = (at(0, 1) - at(0, 0)) * (3.0 / width);
        let d_last = (at(last, 1) - at(last, 0)) * (3.0 / width);
        let rhs: Vec<DVec3> = (0..=m).map(|t| target[t] - full[t][0] * d_first - full[t][last] * d_last).collect();
        for (r, row) in op.iter().enumerate() {
            let d: DVec3 = row.iter().zip(&rhs).map(|(w, x)| *w * *x).sum();
            let a = r + 1;
            let (i, j) = side_index(k, a, 1, last_u, last_v);
            ring_sum[i][j] += at(a, 0) + d * (width / 3.0);
            ring_count[i][j] += 1;
        }
    }
    for i in 0..count_u {
        for j in 0..count_v {
            if ring_count[i][j] > 0 {
                p[i][j] = ring_sum[i][j] / f64::from(ring_count[i][j]);
            }
        }
    }
    // Next to an extraordinary vertex the second rows are moved into the shared tangent planes.
    for c in 0..4 {
        star::tangent_corner(ctx, f, c, &mut p, &along);
    }
    // Inner points: least squares to the samples, the two outer rows of each side fixed.
    let g = &net.grids[f.index()];
    let full_u = basis_matrix(&knots_u, m, 0..=last_u);
    let full_v = basis_matrix(&knots_v, m, 0..=last_v);
    let evaluate = |p: &[Vec<DVec3>], k: usize, l: usize, only_fixed: bool| -> DVec3 {
        let fixed = |i: usize, j: usize| i < 2 || i + 2 > last_u || j < 2 || j + 2 > last_v;
        let mut s = DVec3::ZERO;
        for (i, wu) in full_u[k].iter().enumerate().filter(|(_, w)| **w != 0.0) {
            for (j, wv) in full_v[l].iter().enumerate().filter(|(_, w)| **w != 0.0) {
                if !only_fixed || fixed(i, j) {
                    s += (wu * wv) * p[i][j];
                }
            }
        }
        s
    };
    if last_u >= 4 && last_v >= 4 {
        let all = vec![true; m + 1];
        let op_u = least_squares(&basis_matrix(&knots_u, m, 2..=last_u - 2), &all);
        let op_v = least_squares(&basis_matrix(&knots_v, m, 2..=last_v - 2), &all);
        // Residual of the fixed points at every sample, `residual[l][k]` at (u_k, v_l).
        let residual: Vec<Vec<DVec3>> =
            (0..=m).map(|l| (0..=m).map(|k| g[l * (m + 1) + k] - evaluate(&p, k, l, true)).collect()).collect();
        // X = op_u · R · op_vᵀ with R indexed [u][v].
        let half: Vec<Vec<DVec3>> =
            op_u.iter().map(|row| (0..=m).map(|l| (0..=m).map(|k| row[k] * residual[l][k]).sum()).collect()).collect();
        for (r, h) in half.iter().enumerate() {
            for (c, row) in op_v.iter().enumerate() {
                p[r + 2][c + 2] = (0..=m).map(|l| row[l] * h[l]).sum();
            }
        }
    }
    let mut distance: f64 = 0.0;
    for l in 0..=m {
        for k in 0..=m {
            let s = evaluate(&p, k, l, false);
            distance = distance.max((s - g[l * (m + 1) + k]).length());
        }
    }
    FacePatch { spans: n, knots_u, knots_v, points: p, distance }
}

/// The largest distance from the faces of `model` (fitted to a network of the same layout) to
/// the samples of `net`, at the samples' own parameters: how far the faces are from the surface
/// at points their fit never saw.
pub fn distance_to(model: &BrepModel, net: &PatchNetwork) -> f64 {
    let m = net.m;
    model
        .faces
        .par_iter()
        .zip(&net.grids)
        .map(|(face, g)| {
            let s = &face.surface;
            let (ku, kv) = (Knots::from_breaks(s.knots_u.clone()), Knots::from_breaks(s.knots_v.clone()));
            let mut worst: f64 = 0.0;
            for j in 0..=m {
                for i in 0..=m {
                    let (p, _, _) =
                        bspline::surface_point(&ku, &kv, &s.points, i as f64 / m as f64, j as f64 / m as f64);
                    worst = worst.max((p - g[j * (m + 1) + i]).length());
                }
            }
            worst
        })
        .reduce(|| 0.0, f64::max)
}

#[cfg(test)]
#[path = "fit_tests.rs"]
mod tests;
