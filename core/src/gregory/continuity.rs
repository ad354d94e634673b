//! Continuity report of a patch network: along every shared boundary, the largest angle between
//! the two patches' normals (G1) and the largest jump in normal curvature across it (G2), both
//! sampled along the boundary (`docs/curve-mesh-gregory.md` §7; what Alias's continuity
//! check shows). Gregory patches promise G1 only, so the G2 jump is information, not a bound.
//!
//! A boundary is side `a` of one patch against side `b` of another; side `k` of a patch over
//! `[0, 1]²` runs from corner `k` to corner `k + 1` counter-clockwise: side 0 is `(t, 0)`, side 1
//! `(1, t)`, side 2 `(1 − t, 1)`, side 3 `(0, 1 − t)`. Two counter-clockwise patches run a shared
//! side in opposite directions (`same_direction: false`).
//!
//! G1 is sampled at `t = s/S` for `s = 0..=S`, corners included (first derivatives, hence the
//! normal, are exact there). A sample where either normal is undefined (parallel first
//! derivatives: a degenerate corner) is skipped and counted. G2 is sampled at the inner points
//! `0 < s < S` only: at a corner the second derivatives of a Gregory patch depend on the
//! direction of approach. The normal curvature is taken in the direction across the boundary in
//! the first patch's tangent plane (`n × T`, `T` the boundary tangent), with the first patch's
//! normal for both, so a fold shows as a jump and not as a sign flip.

use super::patch::{PatchDerivatives, SurfacePatch};
use crate::DVec3;
use rayon::prelude::*;

/// Default samples along each boundary.
pub const DEFAULT_BOUNDARY_SAMPLES: usize = 16;

/// One patch side: the patch's index and the side `0..4`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchSide {
    /// Index of the patch in the network.
    pub patch: usize,
    /// Side 0..4 (see the module documentation).
    pub side: u8,
}

/// Two patch sides that are the same curve in space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SharedBoundary {
    /// The first patch's side.
    pub first: PatchSide,
    /// The second patch's side.
    pub second: PatchSide,
    /// True when both sides run the curve the same way (false for two counter-clockwise patches).
    pub same_direction: bool,
}

/// The measured continuity of one shared boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryContinuity {
    /// Largest angle between the two normals, in radians.
    pub normal_angle: f64,
    /// Largest `|κ₁ − κ₂|` of the normal curvatures across the boundary, in 1/length.
    pub curvature_jump: f64,
    /// Largest `|κ|` of either side at the G2 samples (for judging the jump), in 1/length.
    pub curvature_scale: f64,
    /// G1 samples skipped where a normal is undefined.
    pub degenerate_samples: usize,
}

/// The continuity of a whole network.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContinuityReport {
    /// Per shared boundary, in the order given.
    pub boundaries: Vec<BoundaryContinuity>,
    /// Largest normal angle over all boundaries (radians).
    pub max_normal_angle: f64,
    /// Index of the boundary with the largest normal angle.
    pub worst_angle_boundary: Option<usize>,
    /// Largest normal-curvature jump over all boundaries (1/length).
    pub max_curvature_jump: f64,
    /// Index of the boundary with the largest curvature jump.
    pub worst_jump_boundary: Option<usize>,
    /// G1 samples skipped where a normal is undefined, over all boundaries.
    pub degenerate_samples: usize,
}

/// The parameter point of side `side` at `t`.
pub fn side_point(side: u8, t: f64) -> (f64, f64) {
    match side {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (1.0 - t, 1.0),
        _ => (0.0, 1.0 - t),
    }
}

/// Measures every shared boundary of a patch network at `samples` spans (≥ 1) each.
/// Runs in parallel; each boundary is measured on its own, so the result does not depend on the
/// thread count.
pub fn continuity_report<P: SurfacePatch + Sync>(
    patches: &[P],
    boundaries: &[SharedBoundary],
    samples: usize,
) -> ContinuityReport {
    let samples = samples.max(1);
    let measured: Vec<BoundaryContinuity> = boundaries.par_iter().map(|b| measure(patches, b, samples)).collect();
    let mut report = ContinuityReport { boundaries: measured, ..Default::default() };
    for (i, b) in report.boundaries.iter().enumerate() {
        if report.worst_angle_boundary.is_none() || b.normal_angle > report.max_normal_angle {
            report.max_normal_angle = b.normal_angle;
            report.worst_angle_boundary = Some(i);
        }
        if report.worst_jump_boundary.is_none() || b.curvature_jump > report.max_curvature_jump {
            report.max_curvature_jump = b.curvature_jump;
            report.worst_jump_boundary = Some(i);
        }
        report.degenerate_samples += b.degenerate_samples;
    }
    report
}

fn measure<P: SurfacePatch>(patches: &[P], b: &SharedBoundary, samples: usize) -> BoundaryContinuity {
    let (pa, pb) = (&patches[b.first.patch], &patches[b.second.patch]);
    let mut out =
        BoundaryContinuity { normal_angle: 0.0, curvature_jump: 0.0, curvature_scale: 0.0, degenerate_samples: 0 };
    for s in 0..=samples {
        let t = s as f64 / samples as f64;
        let tb = if b.same_direction { t } else { (samples - s) as f64 / samples as f64 };
        let (ua, va) = side_point(b.first.side, t);
        let (ub, vb) = side_point(b.second.side, tb);
        let (ea, eb) = (pa.evaluate(ua, va), pb.evaluate(ub, vb));
        let (Some(na), Some(nb)) = (ea.unit_normal(), eb.unit_normal()) else {
            out.degenerate_samples += 1;
            continue;
        };
        out.normal_angle = out.normal_angle.max(angle(na, nb));
        if s == 0 || s == samples {
            continue;
        }
        // The boundary tangent, from the first patch's side direction.
        let tangent = match b.first.side {
            0 => ea.du,
            1 => ea.dv,
            2 => -ea.du,
            _ => -ea.dv,
        };
        let across = na.cross(tangent);
        if across.length() == 0.0 {
            continue;
        }
        let across = across.normalize();
        if let (Some(ka), Some(kb)) = (normal_curvature(&ea, na, across), normal_curvature(&eb, na, across)) {
            out.curvature_jump = out.curvature_jump.max((ka - kb).abs());
            out.curvature_scale = out.curvature_scale.max(ka.abs()).max(kb.abs());
        }
    }
    out
}

/// The angle between two unit vectors, accurate near 0 and π.
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Normal curvature `II(w, w) / I(w, w)` in direction `w` (a tangent vector, expressed in the
/// patch's parameters by least squares) with the curvature sign taken against `normal`.
pub fn normal_curvature(e: &PatchDerivatives, normal: DVec3, w: DVec3) -> Option<f64> {
    let (g11, g12, g22) = (e.du.dot(e.du), e.du.dot(e.dv), e.dv.dot(e.dv));
    let det = g11 * g22 - g12 * g12;
    if det <= 1e-24 * g11 * g22 || det == 0.0 {
        return None;
    }
    let (r1, r2) = (e.du.dot(w), e.dv.dot(w));
    let a = (g22 * r1 - g12 * r2) / det;
    let b = (g11 * r2 - g12 * r1) / det;
    let tangent = a * e.du + b * e.dv;
    let second = a * a * e.duu + 2.0 * a * b * e.duv + b * b * e.dvv;
    Some(second.dot(normal) / tangent.length_squared())
}

#[cfg(test)]
mod tests {
    use super::super::patch::BezierPatch;
    use super::*;

    /// The blossom of `t²` (a quadratic seen as a cubic) at three arguments.
    fn blossom_square(t: [f64; 3]) -> f64 {
        (t[0] * t[1] + t[1] * t[2] + t[0] * t[2]) / 3.0
    }

    /// The exact bicubic Bézier net of the graph `z = a x² + b y²` over `[x0, x0 + 1] × [0, 1]`
    /// (control point `(i, j)` from the blossom with `i` arguments at the right end in x and `j`
    /// at the top in y).
    fn quadric(x0: f64, a: f64, b: f64) -> BezierPatch {
        let mut points = [[DVec3::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let xs: [f64; 3] = std::array::from_fn(|k| if k < i { x0 + 1.0 } else { x0 });
                let ys: [f64; 3] = std::array::from_fn(|k| if k < j { 1.0 } else { 0.0 });
                let z = a * blossom_square(xs) + b * blossom_square(ys);
                points[i][j] = DVec3::new(x0 + i as f64 / 3.0, j as f64 / 3.0, z);
            }
        }
        BezierPatch { points }
    }

    /// The left patch's side 1 (`u = 1`, x = 0, upwards) against the right patch's side 3
    /// (`u = 0`, downwards).
    const SHARED: SharedBoundary = SharedBoundary {
        first: PatchSide { patch: 0, side: 1 },
        second: PatchSide { patch: 1, side: 3 },
        same_direction: false,
    };

    #[test]
    fn one_polynomial_surface_split_in_two_is_g1_and_g2() {
        let r = continuity_report(&[quadric(-1.0, 0.5, -0.25), quadric(0.0, 0.5, -0.25)], &[SHARED], 16);
        assert!(r.max_normal_angle < 1e-14, "{}", r.max_normal_angle);
        assert!(r.max_curvature_jump < 1e-12, "{}", r.max_curvature_jump);
        // Across x = 0 the normal curvature of z = x²/2 − y²/4 is f_xx / √(1 + f_y²) = 1/√(1 + y²/4).
        let scale = r.boundaries[0].curvature_scale;
        assert!(scale > 1.0 / (1.0f64 + 0.25).sqrt() && scale <= 1.0 + 1e-12, "{scale}");
        assert_eq!(r.degenerate_samples, 0);
    }

    #[test]
    fn a_kink_and_a_curvature_jump_are_measured() {
        let left = quadric(-1.0, 0.5, -0.25);
        // A G1 join without G2: on the right z = −y²/4 only, so κ across drops from 1/√(1 + y²/4) to 0.
        let r = continuity_report(&[left, quadric(0.0, 0.0, -0.25)], &[SHARED], 8);
        assert!(r.max_normal_angle < 1e-14, "{}", r.max_normal_angle);
        let expected = 1.0 / (1.0f64 + (1.0f64 / 8.0).powi(2) / 4.0).sqrt(); // the sample at y = 1/8
        assert!((r.max_curvature_jump - expected).abs() < 1e-12, "{}", r.max_curvature_jump);
        // A kink: the right patch's slope across the boundary is 0.1 (z = 0.1 x + …).
        let mut kinked = quadric(0.0, 0.5, -0.25);
        for (i, row) in kinked.points.iter_mut().enumerate() {
            for p in row.iter_mut() {
                p.z += 0.1 * i as f64 / 3.0;
            }
        }
        let r = continuity_report(&[left, kinked], &[SHARED], 8);
        // At y = 0 both normals are in the xz-plane, 0.1 rad of slope apart: atan(0.1).
        assert!((r.max_normal_angle - 0.1f64.atan()).abs() < 1e-12, "{}", r.max_normal_angle);
        assert_eq!(r.worst_angle_boundary, Some(0));
    }
}
