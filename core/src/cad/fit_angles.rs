//! How well a fitted face keeps tangent continuity: the angles between its normals and the
//! normals it shares with its neighbours along its sides ([`super::fit`] checks them while it
//! refines a face and reports them per edge).

use super::{Context, FacePatch, corner_span};
use crate::DVec3;
use crate::cad::bspline;
use crate::mesh::{EdgeId, FaceId};
use rayon::prelude::*;

/// The (u, v) of position `t ∈ [0, 1]` along side `k` (in its halfedge's direction).
fn side_uv(k: usize, t: f64) -> (f64, f64) {
    match k {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (1.0 - t, 1.0),
        _ => (0.0, 1.0 - t),
    }
}

fn unit_normal(patch: &FacePatch, u: f64, v: f64) -> DVec3 {
    let (_, du, dv) = bspline::surface_point(&patch.knots_u, &patch.knots_v, &patch.points, u, v);
    du.cross(dv).normalize_or_zero()
}

/// Largest angle (degrees) between the fitted face's normal and the shared normal along its
/// smooth sides, away from the corners.
pub(super) fn side_angle(ctx: &Context<'_>, f: FaceId, patch: &FacePatch) -> f64 {
    let layout = &ctx.net.layout;
    let m = ctx.net.m;
    let mut worst: f64 = 0.0;
    for (k, h) in layout.face_halfedges(f).enumerate() {
        let Some(normals) = &ctx.shared[h.index()] else { continue };
        let gap = ctx.own_gap[h.index()].as_deref().unwrap_or(&[]);
        let star_start = 2.0 * corner_span(ctx.net, layout.from_vertex(h));
        let star_end = 2.0 * corner_span(ctx.net, layout.to_vertex(h));
        for (t, n) in normals.iter().enumerate().take(m).skip(1) {
            let x = t as f64 / m as f64;
            if x < star_start || x > 1.0 - star_end {
                continue;
            }
            let (u, v) = side_uv(k, x);
            let own = 0.5 * gap.get(t).copied().unwrap_or(0.0);
            worst = worst.max(angle_degrees(unit_normal(patch, u, v), *n) - own);
        }
    }
    worst
}

pub(super) fn angle_degrees(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Per smooth interior edge: the largest angle between its two faces' normals, the largest
/// amount by which it exceeds the surface's own there, both away from the two innermost rings
/// around extraordinary ends, and the largest angle within those rings (sampled at `4m` points
/// along it, and within those rings also at `16` points a sample spacing and a thousandth of a
/// spacing from the vertex: the fit's angle there is largest next to the vertex).
pub(super) fn edge_angles(ctx: &Context<'_>, patches: &[FacePatch]) -> Vec<(EdgeId, f64, f64, f64)> {
    let layout = &ctx.net.layout;
    let samples = 4 * ctx.net.m;
    layout
        .edges()
        .collect::<Vec<_>>()
        .par_iter()
        .filter(|&&e| ctx.shared[e.halfedge(0).index()].is_some())
        .map(|&e| {
            let (h, twin) = (e.halfedge(0), e.halfedge(1));
            let (fa, fb) = (layout.face(h), layout.face(twin));
            let ka = layout.face_halfedges(fa).position(|x| x == h).unwrap_or(0);
            let kb = layout.face_halfedges(fb).position(|x| x == twin).unwrap_or(0);
            let gap = ctx.own_gap[h.index()].as_deref().unwrap_or(&[]);
            let m = ctx.net.m;
            let (mut worst, mut excess, mut star): (f64, f64, f64) = (0.0, 0.0, 0.0);
            // The two innermost rings of knots around an extraordinary end.
            let (a, b) = (layout.from_vertex(h), layout.to_vertex(h));
            let (star_start, star_end) = (2.0 * corner_span(ctx.net, a), 2.0 * corner_span(ctx.net, b));
            let mut at: Vec<f64> = (1..samples).map(|s| s as f64 / samples as f64).collect();
            let near: Vec<f64> = std::iter::once(1e-3).chain((1..32).map(|x| x as f64 / 16.0)).collect();
            if star_start > 0.0 {
                at.extend(near.iter().map(|x| x / m as f64));
            }
            if star_end > 0.0 {
                at.extend(near.iter().map(|x| 1.0 - x / m as f64));
            }
            for t in at {
                let (ua, va) = side_uv(ka, t);
                let (ub, vb) = side_uv(kb, 1.0 - t);
                let na = unit_normal(&patches[fa.index()], ua, va);
                let nb = unit_normal(&patches[fb.index()], ub, vb);
                let angle = angle_degrees(na, nb);
                // The surface's own gap here, from the nearest samples on either side.
                let x = t * m as f64;
                let own = gap
                    .get(x.floor() as usize)
                    .copied()
                    .unwrap_or(0.0)
                    .max(gap.get(x.ceil() as usize).copied().unwrap_or(0.0));
                if t < star_start || t > 1.0 - star_end {
                    star = star.max(angle);
                } else {
                    worst = worst.max(angle);
                    excess = excess.max(angle - own);
                }
            }
            (e, worst, excess, star)
        })
        .collect()
}
