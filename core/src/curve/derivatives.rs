//! Discrete derivatives of a point sequence on nonuniform parameters, and the curvature and
//! torsion made from them (Miura, Yoshida and Saito, "Discrete log-aesthetic filter", sec. 3.1
//! eqs. 1 and 3, sec. 4.2; our reading is `docs/log-aesthetic.md`).
//!
//! Point `i` has the parameter gaps `h0 = Δt_{i−1}` before it and `h1 = Δt_i` after it (chord
//! lengths by default). The first derivative is the paper's central difference
//! `U = (P_{i+1} − P_{i−1}) / (h0 + h1)`, which does not involve `P_i`; the second derivative is
//! the three-point formula of the parabola through the three points,
//! `V = 2 [(P_{i+1} − P_i)/h1 − (P_i − P_{i−1})/h0] / (h0 + h1)` (the uniform `(P_{i+1} − 2P_i +
//! P_{i−1})/h²` when the gaps are equal), affine in `P_i` with the weight `−2/(h0 h1)`; the third
//! derivative is that of the cubic through the two points on either side, `P_i` left out (sec.
//! 4.2), so it too does not involve `P_i`. Curvature is `|U × V| / |U|³` (eq. 1, signed about a
//! plane normal for planar curves), torsion `(U × V)·W / |U × V|²`.
//!
//! Where it is weak: `U` is only first-order accurate when the gaps differ (its second-order
//! cousin would involve `P_i` and lose the closed forms the filters rely on), so the curvature of
//! unevenly spaced points carries an O(|h1 − h0|) error; on evenly spaced points of a circle of
//! radius r with chord h it reads `1 / (r cos²(θ/2))`, θ the angle a chord subtends, a bias of
//! about `h²/(4r²)` that is the same at every point. The third derivative is first-order
//! accurate; torsion is noisy where the curvature is small.

use super::sequence::PointSequence;
use crate::DVec3;

/// Central first derivative at a point with neighbours `before` and `after` at parameter gaps
/// `h0` and `h1` (sec. 3.1).
#[inline]
pub fn first_derivative(before: DVec3, after: DVec3, h0: f64, h1: f64) -> DVec3 {
    (after - before) / (h0 + h1)
}

/// Three-point second derivative at `point` on nonuniform gaps `h0` (before) and `h1` (after).
#[inline]
pub fn second_derivative(before: DVec3, point: DVec3, after: DVec3, h0: f64, h1: f64) -> DVec3 {
    2.0 * ((after - point) / h1 - (point - before) / h0) / (h0 + h1)
}

/// The weight of the point itself in [`second_derivative`], `−2 / (h0 h1)`: moving the point by
/// `d` changes the second derivative by `second_derivative_weight · d`.
#[inline]
pub fn second_derivative_weight(h0: f64, h1: f64) -> f64 {
    -2.0 / (h0 * h1)
}

/// Third derivative of the cubic through four points at the parameters `t` (strictly
/// increasing): six times their third divided difference. For the filter these are the two
/// points on either side of the point considered, which is left out (sec. 4.2).
pub fn third_derivative(points: [DVec3; 4], t: [f64; 4]) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for j in 0..4 {
        let mut product = 1.0;
        for k in 0..4 {
            if k != j {
                product *= t[j] - t[k];
            }
        }
        sum += points[j] / product;
    }
    6.0 * sum
}

/// Unsigned curvature `|U × V| / |U|³` (eq. 1).
#[inline]
pub fn curvature(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length() / u.length().powi(3)
}

/// Curvature of a planar curve, positive where it turns counter-clockwise seen from the side
/// `normal` (unit) points to.
#[inline]
pub fn signed_curvature(u: DVec3, v: DVec3, normal: DVec3) -> f64 {
    u.cross(v).dot(normal) / u.length().powi(3)
}

/// Torsion `(U × V)·W / |U × V|²`; 0 where the curvature vanishes.
#[inline]
pub fn torsion(u: DVec3, v: DVec3, w: DVec3) -> f64 {
    let b = u.cross(v);
    let b2 = b.length_squared();
    if b2 > 0.0 { b.dot(w) / b2 } else { 0.0 }
}

/// The discrete differential geometry of a point sequence with chord-length parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurveGeometry {
    /// Cumulative chord length at every point.
    pub arc_length: Vec<f64>,
    /// Per point: the curvature where the point has a neighbour on each side (signed about the
    /// plane normal when one was given, else unsigned), `None` at the ends of an open curve.
    pub curvature: Vec<Option<f64>>,
    /// Per point: the torsion where the point has two neighbours on each side, `None` elsewhere.
    pub torsion: Vec<Option<f64>>,
    /// Per point: the unit tangent `U/|U|` (zero at the ends of an open curve).
    pub tangent: Vec<DVec3>,
}

/// Curvature and torsion of every point of `curve` with chord-length parameters; the curvature
/// is signed about `plane_normal` (unit) when one is given. The points should have passed
/// [`PointSequence::validate`]: a repeated point gives non-finite values around it.
pub fn curve_geometry(curve: &PointSequence, plane_normal: Option<DVec3>) -> CurveGeometry {
    let n = curve.len();
    let p = &curve.points;
    let gaps = curve.chord_lengths();
    let gap_before = |i: usize| if i == 0 { gaps[n - 1] } else { gaps[i - 1] };
    let mut out = CurveGeometry {
        arc_length: curve.arc_lengths(),
        curvature: vec![None; n],
        torsion: vec![None; n],
        tangent: vec![DVec3::ZERO; n],
    };
    for i in 0..n {
        let Some((a, b)) = curve.neighbours(i) else { continue };
        let (h0, h1) = (gap_before(i), gaps[i]);
        let u = first_derivative(p[a], p[b], h0, h1);
        let v = second_derivative(p[a], p[i], p[b], h0, h1);
        out.tangent[i] = u.normalize_or_zero();
        out.curvature[i] = Some(match plane_normal {
            Some(normal) => signed_curvature(u, v, normal),
            None => curvature(u, v),
        });
        let (Some((aa, _)), Some((_, bb))) = (curve.neighbours(a), curve.neighbours(b)) else { continue };
        if n < 5 && curve.closed {
            continue;
        }
        let h00 = gap_before(a);
        let t = [-(h0 + h00), -h0, h1, h1 + gaps[b]];
        let w = third_derivative([p[aa], p[a], p[b], p[bb]], t);
        out.torsion[i] = Some(torsion(u, v, w));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_polynomials_are_exact() {
        // A quadratic in t is reproduced by the three-point second derivative on any gaps, and a
        // cubic by the four-point third derivative.
        let quadratic = |t: f64| DVec3::new(1.0 + 2.0 * t - 3.0 * t * t, 0.5 * t * t, -t);
        let (h0, h1) = (0.3, 0.7);
        let v = second_derivative(quadratic(-h0), quadratic(0.0), quadratic(h1), h0, h1);
        assert!((v - DVec3::new(-6.0, 1.0, 0.0)).length() < 1e-12, "{v}");
        let cubic = |t: f64| DVec3::new(t * t * t, 2.0 * t * t - t, -0.5 * t * t * t + t);
        let t = [-1.1, -0.4, 0.3, 0.9];
        let w = third_derivative(t.map(cubic), t);
        assert!((w - DVec3::new(6.0, 0.0, -3.0)).length() < 1e-12, "{w}");
        // The weight of the point in the second derivative.
        let d = DVec3::new(0.1, -0.2, 0.3);
        let moved = second_derivative(quadratic(-h0), quadratic(0.0) + d, quadratic(h1), h0, h1);
        assert!((moved - v - second_derivative_weight(h0, h1) * d).length() < 1e-12);
    }

    #[test]
    fn a_helix_has_its_curvature_and_torsion() {
        // (a cos t, a sin t, b t): κ = a/(a² + b²), τ = b/(a² + b²); both converge as O(h²) on
        // even spacing.
        let (a, b) = (2.0, 0.7);
        let (kappa, tau) = (a / (a * a + b * b), b / (a * a + b * b));
        let helix: Vec<DVec3> =
            (0..200).map(|i| 0.02 * i as f64).map(|t| DVec3::new(a * t.cos(), a * t.sin(), b * t)).collect();
        let g = curve_geometry(&PointSequence::new(helix, false), None);
        assert!(g.curvature[0].is_none() && g.torsion[1].is_none() && g.torsion[2].is_some());
        for i in 2..198 {
            assert!((g.curvature[i].unwrap() - kappa).abs() < 1e-4 * kappa, "{i}: {:?}", g.curvature[i]);
            assert!((g.torsion[i].unwrap() - tau).abs() < 1e-4 * tau, "{i}: {:?}", g.torsion[i]);
        }
    }

    #[test]
    fn a_counter_clockwise_circle_curves_positively() {
        let circle: Vec<DVec3> = (0..24)
            .map(|i| i as f64 * std::f64::consts::TAU / 24.0)
            .map(|t| 3.0 * DVec3::new(t.cos(), t.sin(), 0.0))
            .collect();
        let g = curve_geometry(&PointSequence::new(circle, true), Some(DVec3::Z));
        // The bias of eq. 3 on a circle: 1 / (r cos²(θ/2)), θ = 2π/24.
        let expected = 1.0 / (3.0 * (std::f64::consts::PI / 24.0).cos().powi(2));
        assert!(g.curvature.iter().all(|k| (k.unwrap() - expected).abs() < 1e-12));
        assert!(g.torsion.iter().all(|t| t.unwrap().abs() < 1e-12));
    }
}
