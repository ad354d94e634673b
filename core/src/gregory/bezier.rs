//! Cubic Bézier curves: the curves of a curve mesh, and the two least-squares fits that make them
//! (`docs/curve-mesh-gregory.md` §3–4; the seed paper's §3.2–3.3, eq. (7)–(11)).
//!
//! - [`fit_with_fixed_ends`]: the cubic through two end points that is closest, in least squares,
//!   to interior points given at known parameters (the paper's fit of five limit points at
//!   parameters 0, ¼, ½, ¾, 1; Piegl & Tiller's constrained fit). The two inner control points
//!   are the unknowns, one 2 × 2 system shared by the three coordinates.
//! - [`refit_with_tangents`]: Hoschek's refit, eq. (8)–(11): the end tangent directions are held
//!   fixed and only the two leg lengths `α1`, `α2` are fitted (two scalar unknowns, closed form).
//!   The system is never singular for unit tangents (its determinant is at least the one of the
//!   free fit), but the lengths can come out ≤ 0 when the held tangents point away from the
//!   points; the caller chooses the fallback ([`TangentRefit`] says when).
//!
//! Weak spot: both fits minimise distances at *given* parameters, not true point-to-curve
//! distances; [`CubicBezier::distance_to`] measures the latter afterwards.

use crate::DVec3;

/// A cubic Bézier curve `C(t) = Σ B³ᵢ(t) Pᵢ`, `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicBezier {
    /// The control points `P0..P3`; the curve runs from `P0` to `P3`.
    pub points: [DVec3; 4],
}

/// The four cubic Bernstein polynomials at `t`.
#[inline]
pub fn bernstein3(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// First derivatives of the four cubic Bernstein polynomials at `t`.
#[inline]
pub fn bernstein3_d1(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [-3.0 * s * s, 3.0 * s * (s - 2.0 * t), 3.0 * t * (2.0 * s - t), 3.0 * t * t]
}

/// Second derivatives of the four cubic Bernstein polynomials at `t`.
#[inline]
pub fn bernstein3_d2(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [6.0 * s, 6.0 * (3.0 * t - 2.0), 6.0 * (1.0 - 3.0 * t), 6.0 * t]
}

impl CubicBezier {
    /// The curve with these control points.
    pub fn new(p0: DVec3, p1: DVec3, p2: DVec3, p3: DVec3) -> Self {
        CubicBezier { points: [p0, p1, p2, p3] }
    }

    /// The same curve run backwards (`t → 1 − t`); exact, the points are only reordered.
    pub fn reversed(&self) -> Self {
        let [a, b, c, d] = self.points;
        CubicBezier { points: [d, c, b, a] }
    }

    /// Position at `t`.
    pub fn point(&self, t: f64) -> DVec3 {
        combine(&self.points, bernstein3(t))
    }

    /// First derivative `C'(t)`.
    pub fn derivative(&self, t: f64) -> DVec3 {
        combine(&self.points, bernstein3_d1(t))
    }

    /// Second derivative `C''(t)`.
    pub fn second_derivative(&self, t: f64) -> DVec3 {
        combine(&self.points, bernstein3_d2(t))
    }

    /// The control points of the derivative, a quadratic: `cᵢ = 3 (Pᵢ₊₁ − Pᵢ)`.
    pub fn derivative_points(&self) -> [DVec3; 3] {
        let p = &self.points;
        [3.0 * (p[1] - p[0]), 3.0 * (p[2] - p[1]), 3.0 * (p[3] - p[2])]
    }

    /// The closest point of the curve to `p`: `(t, distance)`. A coarse scan over 32 spans
    /// brackets the nearest span, then Newton's method on `C'(t)·(C(t) − p) = 0` refines it
    /// (clamped to `[0, 1]`); the result is never farther than the best scanned sample.
    pub fn distance_to(&self, p: DVec3) -> (f64, f64) {
        const SPANS: usize = 32;
        let (mut best_t, mut best) = (0.0, f64::INFINITY);
        for k in 0..=SPANS {
            let t = k as f64 / SPANS as f64;
            let d = self.point(t).distance_squared(p);
            if d < best {
                (best_t, best) = (t, d);
            }
        }
        let mut t = best_t;
        for _ in 0..16 {
            let r = self.point(t) - p;
            let d1 = self.derivative(t);
            let f = d1.dot(r);
            let df = d1.length_squared() + self.second_derivative(t).dot(r);
            if df <= 0.0 || !df.is_finite() {
                break;
            }
            let next = (t - f / df).clamp(0.0, 1.0);
            let done = (next - t).abs() < 1e-15;
            t = next;
            if done {
                break;
            }
        }
        let d = self.point(t).distance_squared(p);
        if d < best { (t, d.sqrt()) } else { (best_t, best.sqrt()) }
    }
}

fn combine(p: &[DVec3; 4], w: [f64; 4]) -> DVec3 {
    w[0] * p[0] + w[1] * p[1] + w[2] * p[2] + w[3] * p[3]
}

/// The least-squares cubic from `start` to `end` through `points` given at parameters `params`
/// (strictly inside `(0, 1)`, at least two distinct ones): the inner control points minimise
/// `Σ |C(tₖ) − pₖ|²`. `None` when the parameters do not determine both inner points.
pub fn fit_with_fixed_ends(start: DVec3, end: DVec3, points: &[DVec3], params: &[f64]) -> Option<CubicBezier> {
    debug_assert_eq!(points.len(), params.len());
    let (mut a11, mut a12, mut a22) = (0.0, 0.0, 0.0);
    let (mut r1, mut r2) = (DVec3::ZERO, DVec3::ZERO);
    for (&p, &t) in points.iter().zip(params) {
        let b = bernstein3(t);
        let r = p - b[0] * start - b[3] * end;
        a11 += b[1] * b[1];
        a12 += b[1] * b[2];
        a22 += b[2] * b[2];
        r1 += b[1] * r;
        r2 += b[2] * r;
    }
    let det = a11 * a22 - a12 * a12;
    if det.abs() <= 1e-12 * (a11 * a22).max(f64::MIN_POSITIVE) {
        return None;
    }
    let p1 = (a22 * r1 - a12 * r2) / det;
    let p2 = (a11 * r2 - a12 * r1) / det;
    Some(CubicBezier::new(start, p1, p2, end))
}

/// The result of Hoschek's refit: the leg lengths before any guard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentRefit {
    /// `α1`: `P1 = P0 + α1 T1`.
    pub alpha_start: f64,
    /// `α2`: `P2 = P3 − α2 T2`.
    pub alpha_end: f64,
}

/// Hoschek's refit (paper eq. (8)–(11)): with unit end tangents `t_start` (leaving `start`) and
/// `t_end` (arriving at `end`) held fixed, the leg lengths `α1`, `α2` minimising
/// `Σ |C(tₖ) − pₖ|²` for `C = (start, start + α1 t_start, end − α2 t_end, end)`.
/// The lengths are returned as solved, possibly ≤ 0: the caller guards them.
pub fn refit_with_tangents(
    start: DVec3,
    end: DVec3,
    t_start: DVec3,
    t_end: DVec3,
    points: &[DVec3],
    params: &[f64],
) -> TangentRefit {
    debug_assert_eq!(points.len(), params.len());
    // Residual model: α1 B1 T1 − α2 B2 T2 = pₖ − (B0 + B1) P0 − (B2 + B3) P3.
    let cos = t_start.dot(t_end);
    let (mut a11, mut a12, mut a22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (&p, &t) in points.iter().zip(params) {
        let b = bernstein3(t);
        let r = p - (b[0] + b[1]) * start - (b[2] + b[3]) * end;
        a11 += b[1] * b[1];
        a12 -= b[1] * b[2] * cos;
        a22 += b[2] * b[2];
        r1 += b[1] * t_start.dot(r);
        r2 -= b[2] * t_end.dot(r);
    }
    // det ≥ a11 a22 − (Σ B1 B2)² > 0 for unit tangents and two distinct parameters.
    let det = a11 * a22 - a12 * a12;
    TangentRefit { alpha_start: (a22 * r1 - a12 * r2) / det, alpha_end: (a11 * r2 - a12 * r1) / det }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> CubicBezier {
        CubicBezier::new(
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(3.0, 2.5, -1.0),
            DVec3::new(4.0, 0.0, 0.2),
        )
    }

    /// De Casteljau, written out independently of the Bernstein form.
    fn de_casteljau(p: [DVec3; 4], t: f64) -> DVec3 {
        let l = |a: DVec3, b: DVec3| a + t * (b - a);
        let (a, b, c) = (l(p[0], p[1]), l(p[1], p[2]), l(p[2], p[3]));
        let (d, e) = (l(a, b), l(b, c));
        l(d, e)
    }

    #[test]
    fn evaluation_matches_de_casteljau_and_finite_differences() {
        let c = sample();
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            assert!(c.point(t).distance(de_casteljau(c.points, t)) < 1e-14);
            // Central differences inside, one-sided (first order, looser) at the ends.
            let h = 1e-5;
            let (lo, hi) = ((t - h).max(0.0), (t + h).min(1.0));
            let tol = if k == 0 || k == 20 { 1e-3 } else { 1e-6 };
            let fd = (c.point(hi) - c.point(lo)) / (hi - lo);
            assert!(fd.distance(c.derivative(t)) < tol * (1.0 + fd.length()), "t = {t}");
            let fd2 = (c.derivative(hi) - c.derivative(lo)) / (hi - lo);
            assert!(fd2.distance(c.second_derivative(t)) < tol * (1.0 + fd2.length()), "t = {t}");
        }
        let d = c.derivative_points();
        assert!(c.derivative(0.0).distance(d[0]) < 1e-14 && c.derivative(1.0).distance(d[2]) < 1e-14);
        assert!(c.reversed().point(0.3).distance(c.point(0.7)) < 1e-14);
    }

    #[test]
    fn fits_reproduce_a_cubic_sampled_at_its_own_parameters() {
        let c = sample();
        let params = [0.25, 0.5, 0.75];
        let points: Vec<DVec3> = params.iter().map(|&t| c.point(t)).collect();
        let fit = fit_with_fixed_ends(c.points[0], c.points[3], &points, &params).unwrap();
        for k in 1..3 {
            assert!(fit.points[k].distance(c.points[k]) < 1e-12, "{k}: {:?}", fit.points[k]);
        }
        let t1 = (c.points[1] - c.points[0]).normalize();
        let t2 = (c.points[3] - c.points[2]).normalize();
        let refit = refit_with_tangents(c.points[0], c.points[3], t1, t2, &points, &params);
        assert!((refit.alpha_start - c.points[1].distance(c.points[0])).abs() < 1e-12);
        assert!((refit.alpha_end - c.points[3].distance(c.points[2])).abs() < 1e-12);
    }

    #[test]
    fn hoschek_refit_is_the_least_squares_minimum() {
        // Points off any cubic with these tangents: the refit must beat every nearby (α1, α2).
        let (p0, p3) = (DVec3::ZERO, DVec3::new(4.0, 0.0, 0.0));
        let points = [DVec3::new(1.0, 1.2, 0.1), DVec3::new(2.0, 1.6, -0.2), DVec3::new(3.1, 1.1, 0.3)];
        let params = [0.25, 0.5, 0.75];
        let (t1, t2) = (DVec3::new(0.6, 0.8, 0.0), DVec3::new(0.6, -0.8, 0.0));
        let r = refit_with_tangents(p0, p3, t1, t2, &points, &params);
        let cost = |a1: f64, a2: f64| {
            let c = CubicBezier::new(p0, p0 + a1 * t1, p3 - a2 * t2, p3);
            points.iter().zip(params).map(|(p, t)| c.point(t).distance_squared(*p)).sum::<f64>()
        };
        let best = cost(r.alpha_start, r.alpha_end);
        for (d1, d2) in [(1e-3, 0.0), (-1e-3, 0.0), (0.0, 1e-3), (0.0, -1e-3), (1e-3, -1e-3)] {
            assert!(cost(r.alpha_start + d1, r.alpha_end + d2) > best);
        }
        assert!(r.alpha_start > 0.0 && r.alpha_end > 0.0);
        // Tangents pointing away from the points give a negative length, reported as such.
        let away = refit_with_tangents(p0, p3, -t1, t2, &points, &params);
        assert!(away.alpha_start < 0.0);
    }

    #[test]
    fn distance_to_finds_the_closest_point() {
        let c = sample();
        for k in 0..10 {
            let t = 0.05 + 0.09 * k as f64;
            // Step off the curve along a normal direction: the closest point is back at t.
            let tangent = c.derivative(t).normalize();
            let side = tangent.any_orthonormal_vector();
            let (found, d) = c.distance_to(c.point(t) + 0.01 * side);
            assert!((found - t).abs() < 1e-4, "t {t} found {found}");
            assert!((d - 0.01).abs() < 1e-6, "{d}");
        }
        // Beyond the end, the end point is the closest.
        let (t, d) = c.distance_to(c.points[3] + DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(t, 1.0);
        assert!((d - 1.0).abs() < 1e-12);
    }
}
