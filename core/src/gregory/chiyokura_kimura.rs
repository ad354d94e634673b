//! Inner control points of a Gregory patch from its four boundary curves and corner normals, by
//! Chiyokura & Kimura's cross-boundary derivatives (Chiyokura & Kimura 1983, "Design of solids
//! with free-form surfaces"; `docs/curve-mesh-gregory.md` §6; the seed paper's §4).
//!
//! Along a boundary curve `C` (control points `Q0..Q3`, `C' = Σ B²ᵢ cᵢ`, `cᵢ = 3(Qᵢ₊₁ − Qᵢ)`)
//! between corners with unit normals `N0`, `N1`, the cross-boundary derivative into the patch is
//! `D(t) = k(t) b(t) + h(t) C'(t)` with `b(t) = (1 − t) b0 + t b1`, `b0 = N0 × c0`,
//! `b1 = N1 × c2` (normalised) and `k`, `h` linear. `b(t)` depends on the curve and the two corner
//! normals only, so the patch across the curve uses the same field (with the opposite sign, as it
//! runs the curve backwards): both cross derivatives lie in the plane of `b(t)` and `C'(t)`, and
//! the two patches meet with G1 continuity whatever their other sides are. `k0, h0` (and `k1,
//! h1`) come from the patch's own leg along the neighbouring side at each corner, so `D(0)` and
//! `D(1)` agree with those sides. The Bernstein coefficients of the cubic `D` give the side's two
//! inner points, `P = Qᵢ + dᵢ/3` (`docs/curve-mesh-gregory.md` §6 for `e`, `f`, `m`).
//!
//! Weak spots: the construction needs every corner's legs in its tangent plane (the curve mesh
//! keeps them there); a leg that is off the plane is split into its in-plane part by least
//! squares, which keeps G1 along the curves but not at that corner. Where `N × c0` vanishes (a
//! zero leg, or a leg along the normal) `b0` falls back to the next non-degenerate direction of
//! travel (`Q2 − Q0`, then the chord), chosen from the curve alone so both sides agree.

use super::bezier::CubicBezier;
use super::patch::GregoryPatch;
use crate::DVec3;

/// The data a patch is built from: its four sides counter-clockwise and its corner normals.
/// Side `k` runs from corner `k` to corner `k + 1`; corners 0, 1, 2, 3 are the parameter points
/// `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`, so side 0 is `v = 0`, side 1 is `u = 1`, side 2 is
/// `v = 1` (run from `u = 1` to `u = 0`) and side 3 is `u = 0` (from `v = 1` to `v = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchBoundary {
    /// The four boundary curves; `sides[k].points[3]` must equal `sides[k + 1].points[0]`.
    pub sides: [CubicBezier; 4],
    /// Unit tangent-plane normals at the four corners.
    pub normals: [DVec3; 4],
    /// Per side, what the surface the curve mesh stands for says at the side's middle, when
    /// known: the cross-boundary field `b(t)` then turns through its normal (quadratic instead
    /// of linear; see [`side_inner_points`]).
    pub mids: [Option<CurveMiddle>; 4],
}

/// The surface a curve stands for at the curve's middle, shared by both patches on the curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveMiddle {
    /// Its unit normal there.
    pub normal: DVec3,
    /// The length of the cross-boundary field `b(½)` (the end values `b0`, `b1` are unit),
    /// when fitted to the surface's cross derivatives there; without it `b(½)` is as long as
    /// the linear field's `(b0 + b1)/2`.
    pub length: Option<f64>,
}

/// The Gregory patch spanning a boundary, with Chiyokura–Kimura inner points on every side.
pub fn gregory_patch(boundary: &PatchBoundary) -> GregoryPatch {
    let sides = &boundary.sides;
    let mut patch = GregoryPatch { rim: [[DVec3::ZERO; 4]; 4], inner: [[[DVec3::ZERO; 2]; 2]; 2] };
    for k in 0..4 {
        let q = sides[k].points;
        match k {
            0 => (0..4).for_each(|i| patch.rim[i][0] = q[i]),
            1 => (0..4).for_each(|j| patch.rim[3][j] = q[j]),
            2 => (0..4).for_each(|i| patch.rim[3 - i][3] = q[i]),
            _ => (0..4).for_each(|j| patch.rim[0][3 - j] = q[j]),
        }
    }
    for k in 0..4 {
        let curve = &sides[k];
        let q = curve.points;
        // The patch's legs into its interior at the two ends: along the neighbouring sides.
        let a0 = 3.0 * (sides[(k + 3) % 4].points[2] - q[0]);
        let a1 = 3.0 * (sides[(k + 1) % 4].points[1] - q[3]);
        let (n0, n1) = (boundary.normals[k], boundary.normals[(k + 1) % 4]);
        let [p1, p2] = side_inner_points(curve, n0, n1, boundary.mids[k], a0, a1);
        let inner = &mut patch.inner;
        match k {
            0 => (inner[0][0][0], inner[1][0][0]) = (p1, p2),
            1 => (inner[1][0][1], inner[1][1][1]) = (p1, p2),
            2 => (inner[1][1][0], inner[0][1][0]) = (p1, p2),
            _ => (inner[0][1][1], inner[0][0][1]) = (p1, p2),
        }
    }
    patch.fill_middle();
    patch
}

/// The two inner points next to `Q1` and `Q2` of one side: `Q1 + d1/3`, `Q2 + d2/3`.
/// `a0`, `a1` are the cross derivatives into the patch at the two ends (three times the legs).
///
/// With `mid`, `b(t)` is the quadratic with `b(0) = b0`, `b(1) = b1` and `b(½)` along
/// `N × C'(½)` for the middle's normal `N`, of the middle's length (else of the linear field's
/// length there), Bernstein middle coefficient `Bm = 2 b(½) − (b0 + b1)/2`; `k b` is then cubic,
/// with coefficients `k0 b0`, `(2 k0 Bm + k1 b0)/3`, `(k0 b1 + 2 k1 Bm)/3`, `k1 b1`. `b(t)`
/// still depends on the curve and what is shared about it only, so the two patches on a curve
/// stay G1.
pub fn side_inner_points(
    curve: &CubicBezier,
    n0: DVec3,
    n1: DVec3,
    mid: Option<CurveMiddle>,
    a0: DVec3,
    a1: DVec3,
) -> [DVec3; 2] {
    let q = curve.points;
    let c = curve.derivative_points();
    let (b0, b1) = end_directions(curve, n0, n1);
    let (k0, h0) = split(a0, b0, c[0]);
    let (k1, h1) = split(a1, b1, c[2]);
    let e1 = (2.0 * h0 * c[1] + h1 * c[0]) / 3.0;
    let e2 = (h0 * c[2] + 2.0 * h1 * c[1]) / 3.0;
    let linear = 0.5 * (b0 + b1);
    let bm = match mid.and_then(|m| middle_direction(curve, b0, b1, m.normal).map(|half| (half, m.length))) {
        Some((half, length)) => {
            let length = length.filter(|l| l.is_finite() && *l > 0.0).unwrap_or(linear.length());
            2.0 * length * half - linear
        }
        None => linear,
    };
    let f1 = (2.0 * k0 * bm + k1 * b0) / 3.0;
    let f2 = (k0 * b1 + 2.0 * k1 * bm) / 3.0;
    [q[1] + (e1 + f1) / 3.0, q[2] + (e2 + f2) / 3.0]
}

/// The unit end values `b0`, `b1` of the cross-boundary field along `curve` between corners
/// with unit normals `n0`, `n1`.
fn end_directions(curve: &CubicBezier, n0: DVec3, n1: DVec3) -> (DVec3, DVec3) {
    let q = curve.points;
    let c = curve.derivative_points();
    (cross_direction(n0, [c[0], q[2] - q[0], q[3] - q[0]]), cross_direction(n1, [c[2], q[3] - q[1], q[3] - q[0]]))
}

/// The unit direction of `b(½)`: `normal × C'(½)`, on the side of the linear field (a normal
/// given the other way round flips it). `None` for an unusable normal.
fn middle_direction(curve: &CubicBezier, b0: DVec3, b1: DVec3, normal: DVec3) -> Option<DVec3> {
    if !normal.is_finite() || normal.length() == 0.0 {
        return None;
    }
    let q = curve.points;
    let half = cross_direction(normal.normalize(), [curve.derivative(0.5), q[3] - q[0], q[2] - q[1]]);
    Some(if half.dot(b0 + b1) < 0.0 { -half } else { half })
}

/// For one patch on `curve`, the unit direction of `b(½)` through the middle's `normal` and the
/// patch's `k(½)`: its cross derivative at the middle is `k(½) |b(½)| b̂ + h(½) C'(½)`. `a0`,
/// `a1` as in [`side_inner_points`].
pub fn middle_factor(
    curve: &CubicBezier,
    n0: DVec3,
    n1: DVec3,
    normal: DVec3,
    a0: DVec3,
    a1: DVec3,
) -> Option<(DVec3, f64)> {
    let c = curve.derivative_points();
    let (b0, b1) = end_directions(curve, n0, n1);
    let half = middle_direction(curve, b0, b1, normal)?;
    let (k0, _) = split(a0, b0, c[0]);
    let (k1, _) = split(a1, b1, c[2]);
    Some((half, 0.5 * (k0 + k1)))
}

/// `normalize(n × t)` for the first direction of travel `t` not along `n`; the last resort is a
/// fixed direction perpendicular to `n` (a curve collapsed to a point).
fn cross_direction(n: DVec3, travel: [DVec3; 3]) -> DVec3 {
    for t in travel {
        let b = n.cross(t);
        if b.length() > 1e-12 * t.length() && b.length() > 0.0 {
            return b.normalize();
        }
    }
    n.any_orthonormal_vector()
}

/// `a = k b + h c` in least squares (exact when `a` lies in the plane of `b` and `c`).
pub(crate) fn split(a: DVec3, b: DVec3, c: DVec3) -> (f64, f64) {
    let (bb, bc, cc) = (b.dot(b), b.dot(c), c.dot(c));
    let det = bb * cc - bc * bc;
    if det <= 1e-24 * bb * cc || cc == 0.0 {
        return (a.dot(b) / bb, 0.0);
    }
    let (ab, ac) = (a.dot(b), a.dot(c));
    ((cc * ab - bc * ac) / det, (bb * ac - bc * ab) / det)
}

#[cfg(test)]
mod tests {
    use super::super::patch::{BezierPatch, SurfacePatch};
    use super::*;

    /// The boundary of a bicubic Bézier patch with its corner normals.
    fn boundary_of(b: &[[DVec3; 4]; 4]) -> PatchBoundary {
        let bez = BezierPatch { points: *b };
        let normals = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(u, v)| bez.normal(u, v).unwrap());
        let g = GregoryPatch::from_bezier(*b);
        let [s0, s1, s2, s3] = g.boundary_curves();
        PatchBoundary { sides: [s0, s1, s2.reversed(), s3.reversed()], normals, mids: [None; 4] }
    }

    /// A cylinder patch: a planar cubic extruded along `w` (perpendicular to its plane). Its
    /// cross-boundary derivatives have the form `k b + h C'` with constant `k` and `h = 0`, so
    /// the construction must give back exactly its inner points.
    fn cylinder(w: DVec3, profile: [DVec3; 4]) -> [[DVec3; 4]; 4] {
        std::array::from_fn(|i| std::array::from_fn(|j| profile[i] + (j as f64 / 3.0) * w))
    }

    #[test]
    fn reproduces_a_bezier_whose_cross_derivatives_are_of_its_form() {
        let profile = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.5, 0.0),
            DVec3::new(2.5, 1.2, 0.0),
            DVec3::new(3.0, -0.5, 0.0),
        ];
        let b = cylinder(DVec3::new(0.0, 0.0, 2.0), profile);
        // Under a similarity transform too (rotation, scale, translation).
        let q = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let moved: [[DVec3; 4]; 4] = b.map(|row| row.map(|p| q * (2.5 * p) + DVec3::new(10.0, -3.0, 4.0)));
        for net in [b, moved] {
            let g = gregory_patch(&boundary_of(&net));
            for i in 0..2 {
                for j in 0..2 {
                    for k in 0..2 {
                        let d = g.inner[i][j][k].distance(net[i + 1][j + 1]);
                        assert!(d < 1e-12 * 10.0, "P{}{}{k} off by {d}", i + 1, j + 1);
                    }
                }
            }
            let bez = BezierPatch { points: net };
            for s in 0..=8 {
                for t in 0..=8 {
                    let (u, v) = (s as f64 / 8.0, t as f64 / 8.0);
                    assert!(g.point(u, v).distance(bez.evaluate(u, v).position) < 1e-11);
                }
            }
        }
    }

    #[test]
    fn cross_derivatives_lie_in_the_plane_of_b_and_the_curve_tangent() {
        // A warped patch: the cross derivative along side 0 must be k b + h C' with linear k, h.
        let mut net = cylinder(
            DVec3::new(0.0, 0.3, 2.0),
            [DVec3::ZERO, DVec3::new(1.0, 0.0, 0.5), DVec3::new(2.0, 0.2, 0.1), DVec3::new(3.0, 0.0, -0.2)],
        );
        net[1][1] += DVec3::new(0.2, -0.3, 0.1);
        net[2][1] += DVec3::new(-0.1, 0.2, 0.3);
        let boundary = boundary_of(&net);
        let g = gregory_patch(&boundary);
        let curve = boundary.sides[0];
        let c = curve.derivative_points();
        let b0 = boundary.normals[0].cross(c[0]).normalize();
        let b1 = boundary.normals[1].cross(c[2]).normalize();
        for s in 0..=10 {
            let t = s as f64 / 10.0;
            let d = g.evaluate(t, 0.0).dv;
            let b = (1.0 - t) * b0 + t * b1;
            let plane = b.cross(curve.derivative(t)).normalize();
            assert!(d.dot(plane).abs() < 1e-12 * d.length(), "t = {t}");
        }
        // And the corners' cross derivatives are the neighbouring sides' legs.
        assert!(g.evaluate(0.0, 0.0).dv.distance(3.0 * (net[0][1] - net[0][0])) < 1e-12);
        assert!(g.evaluate(1.0, 0.0).dv.distance(3.0 * (net[3][1] - net[3][0])) < 1e-12);
    }

    #[test]
    fn two_patches_on_one_curve_meet_with_g1() {
        // Two patches share the curve from (0,0) to (3,0); their other sides differ freely, but
        // the legs at the shared corners lie in the corner tangent planes.
        let n0 = DVec3::new(-0.2, 0.1, 1.0).normalize();
        let n1 = DVec3::new(0.25, -0.1, 1.0).normalize();
        let in_plane = |n: DVec3, d: DVec3| d - d.dot(n) * n;
        let (a, b) = (DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0));
        let curve = CubicBezier::new(
            a,
            a + in_plane(n0, DVec3::new(1.0, 0.1, 0.3)),
            b + in_plane(n1, DVec3::new(-1.0, -0.2, 0.4)),
            b,
        );
        // Patch A on +y: corners a, b, b + (0.3, 3), a + (-0.2, 3).
        let a_left = a + in_plane(n0, DVec3::new(-0.1, 1.0, 0.2));
        let b_left = b + in_plane(n1, DVec3::new(0.2, 1.1, -0.3));
        let top = CubicBezier::new(
            DVec3::new(3.3, 3.0, 0.5),
            DVec3::new(2.0, 3.2, 0.9),
            DVec3::new(1.0, 2.9, 0.2),
            DVec3::new(-0.2, 3.0, 0.1),
        );
        let side_a1 = CubicBezier::new(b, b_left, DVec3::new(3.2, 2.0, 0.6), top.points[0]);
        let side_a3 = CubicBezier::new(top.points[3], DVec3::new(-0.1, 2.0, 0.0), a_left, a);
        let na = [n0, n1, DVec3::Z, DVec3::Z];
        let nb = [n1, n0, DVec3::Z, DVec3::Z];
        // Patch B on −y runs the curve backwards.
        let a_right = a + in_plane(n0, DVec3::new(0.1, -1.0, -0.1));
        let b_right = b + in_plane(n1, DVec3::new(-0.2, -0.9, 0.4));
        let bottom = CubicBezier::new(
            DVec3::new(-0.3, -3.0, -0.4),
            DVec3::new(1.0, -3.1, 0.3),
            DVec3::new(2.0, -2.8, -0.2),
            DVec3::new(3.1, -3.0, 0.2),
        );
        let side_b1 = CubicBezier::new(a, a_right, DVec3::new(-0.2, -2.0, 0.1), bottom.points[0]);
        let side_b3 = CubicBezier::new(bottom.points[3], DVec3::new(3.0, -2.0, 0.0), b_right, b);
        // The linear field, one through a tilted middle normal, and one with a fitted length too:
        // whatever the two patches share about the curve, they meet with G1.
        let normal = DVec3::new(0.05, -0.2, 1.0).normalize();
        let middles =
            [None, Some(CurveMiddle { normal, length: None }), Some(CurveMiddle { normal, length: Some(1.6) })];
        let (mut pa, mut pb) =
            (GregoryPatch::from_bezier([[DVec3::ZERO; 4]; 4]), GregoryPatch::from_bezier([[DVec3::ZERO; 4]; 4]));
        for mid in middles {
            let mut mids = [None; 4];
            mids[0] = mid;
            pa = gregory_patch(&PatchBoundary { sides: [curve, side_a1, top, side_a3], normals: na, mids });
            pb = gregory_patch(&PatchBoundary {
                sides: [curve.reversed(), side_b1, bottom, side_b3],
                normals: nb,
                mids,
            });
            let mut worst: f64 = 0.0;
            for s in 0..=32 {
                let t = s as f64 / 32.0;
                let na = pa.normal(t, 0.0).unwrap();
                let nb = pb.normal(1.0 - t, 0.0).unwrap();
                worst = worst.max(na.cross(nb).length().atan2(na.dot(nb)));
            }
            assert!(worst < 1e-12, "largest normal angle {worst} with {mid:?}");
            if let Some(CurveMiddle { length: Some(length), .. }) = mid {
                // The cross derivative at the middle is k(½) |b(½)| b̂ + h(½) C'(½).
                let a0 = 3.0 * (side_a3.points[2] - curve.points[0]);
                let a1 = 3.0 * (side_a1.points[1] - curve.points[3]);
                let (half, k_mid) = middle_factor(&curve, n0, n1, normal, a0, a1).unwrap();
                let (along_b, _) = split(pa.evaluate(0.5, 0.0).dv, half, curve.derivative(0.5));
                assert!((along_b - k_mid * length).abs() < 1e-12 * along_b.abs(), "{along_b} vs {}", k_mid * length);
                assert!(half.dot(normal).abs() < 1e-12);
            }
        }
        // Without the common b(t) (inner points of B moved off it) the angle is visible.
        let mut broken = pb;
        broken.inner[0][0][0] += DVec3::new(0.0, 0.0, 0.3);
        let na = pa.normal(0.6, 0.0).unwrap();
        let nb = broken.normal(0.4, 0.0).unwrap();
        assert!(na.cross(nb).length() > 1e-3);
    }
}
