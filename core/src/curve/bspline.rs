//! Clamped B-spline curves on uniform knots and their least-squares fit to a point sequence
//! (the first step of α estimation, sec. 3.3.1 of the log-aesthetic filter paper).
//!
//! [`BSpline::fit`] places `controls` control points on a clamped knot vector with uniform
//! interior knots over the parameter range of the data (normalised chord length by default) and
//! minimises the sum of squared distances between each data point and the curve point at its
//! parameter. The normal equations are banded (half-bandwidth = degree) and are solved by a banded
//! Cholesky factorisation, so a fit costs O(points + controls). Derivatives are B-splines of one
//! degree lower whose control points are scaled differences (de Boor), evaluated exactly.
//!
//! Where it is weak: least squares on fixed parameters is not the closest-point fit, so a curve
//! whose data parameters are far from arc length is fitted less well than it could be; with too
//! many control points for the data (a knot span without data) the normal equations are
//! singular and the fit is refused; a polynomial spline's curvature wiggles between knots, which
//! is why α is read from a fit with few control points.

use crate::{DVec3, Error, Result};

/// A clamped B-spline curve of any degree.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    degree: usize,
    knots: Vec<f64>,
    control: Vec<DVec3>,
}

impl BSpline {
    /// A curve from its degree, knot vector (non-decreasing, `control.len() + degree + 1`
    /// values, clamped: the first and last `degree + 1` equal) and control points.
    pub fn new(degree: usize, knots: Vec<f64>, control: Vec<DVec3>) -> Result<BSpline> {
        let clamped = knots.len() == control.len() + degree + 1
            && control.len() > degree
            && knots.windows(2).all(|w| w[0] <= w[1])
            && knots[..=degree].iter().all(|k| *k == knots[0])
            && knots[knots.len() - degree - 1..].iter().all(|k| *k == knots[knots.len() - 1])
            && knots[0] < knots[knots.len() - 1];
        if !clamped {
            return Err(Error::Input(format!(
                "a clamped B-spline of degree {degree} with {} control points needs {} non-decreasing knots, \
                 the first and last {} equal",
                control.len(),
                control.len() + degree + 1,
                degree + 1
            )));
        }
        Ok(BSpline { degree, knots, control })
    }

    /// Clamped uniform knots on `[t0, t1]` for `controls` control points of `degree`.
    pub fn uniform_knots(degree: usize, controls: usize, t0: f64, t1: f64) -> Vec<f64> {
        let interior = controls.saturating_sub(degree + 1);
        let mut knots = vec![t0; degree + 1];
        knots.extend((1..=interior).map(|j| t0 + (t1 - t0) * j as f64 / (interior + 1) as f64));
        knots.extend(std::iter::repeat_n(t1, degree + 1));
        knots
    }

    /// Least-squares fit of `controls` control points of `degree` on uniform knots over the range
    /// of `params` (one per point, non-decreasing). Fails clearly when there are fewer points
    /// than control points, or a knot span holds too little data to pin its control points.
    pub fn fit(points: &[DVec3], params: &[f64], degree: usize, controls: usize) -> Result<BSpline> {
        if points.len() != params.len() {
            return Err(Error::Input(format!("{} points but {} parameters", points.len(), params.len())));
        }
        if controls <= degree || points.len() < controls {
            return Err(Error::Input(format!(
                "a least-squares B-spline of degree {degree} needs more than {degree} control points and at \
                 least as many points as control points ({} points, {controls} control points asked)",
                points.len()
            )));
        }
        let (t0, t1) = (params[0], params[params.len() - 1]);
        if t0.is_nan()
            || t1.is_nan()
            || t0 >= t1
            || params.windows(2).any(|w| w[0].is_nan() || w[1].is_nan() || w[0] > w[1])
        {
            return Err(Error::Input("the parameters of a B-spline fit must increase along the points".into()));
        }
        let knots = Self::uniform_knots(degree, controls, t0, t1);
        let width = degree + 1;
        // Lower band of NᵀN: band[r][d] = (NᵀN)[r][r − d], d ≤ degree.
        let mut band = vec![vec![0.0; width]; controls];
        let mut rhs = vec![DVec3::ZERO; controls];
        let mut basis = vec![0.0; width];
        for (p, &t) in points.iter().zip(params) {
            let span = find_span(&knots, degree, controls, t);
            basis_functions(&knots, degree, span, t, &mut basis);
            let first = span - degree;
            for a in 0..width {
                rhs[first + a] += basis[a] * *p;
                for b in 0..=a {
                    band[first + a][a - b] += basis[a] * basis[b];
                }
            }
        }
        // Banded Cholesky: NᵀN = L Lᵀ, L stored in the same band.
        let scale = band.iter().map(|r| r[0]).fold(0.0, f64::max);
        for r in 0..controls {
            for d in (0..width).rev() {
                if d > r {
                    continue;
                }
                let c = r - d;
                let mut sum = band[r][d];
                for k in 1..width {
                    if d + k < width && k <= c {
                        sum -= band[r][d + k] * band[c][k];
                    }
                }
                if d == 0 {
                    if sum.is_nan() || sum <= 1e-12 * scale {
                        return Err(Error::Solver(format!(
                            "the least-squares B-spline is underdetermined near control point {r}: too little data \
                             there for {controls} control points; use fewer"
                        )));
                    }
                    band[r][0] = sum.sqrt();
                } else {
                    band[r][d] = sum / band[c][0];
                }
            }
        }
        // Forward (L y = rhs) and back (Lᵀ x = y) substitution.
        let mut x = rhs;
        for r in 0..controls {
            let mut sum = x[r];
            for d in 1..width.min(r + 1) {
                sum -= band[r][d] * x[r - d];
            }
            x[r] = sum / band[r][0];
        }
        for r in (0..controls).rev() {
            let mut sum = x[r];
            for d in 1..width {
                if r + d < controls {
                    sum -= band[r + d][d] * x[r + d];
                }
            }
            x[r] = sum / band[r][0];
        }
        BSpline::new(degree, knots, x)
    }

    /// Degree of the polynomial pieces.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The control points.
    pub fn control_points(&self) -> &[DVec3] {
        &self.control
    }

    /// The parameter range `[t0, t1]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// The distinct knot values: the curve is one polynomial (one Bézier segment) between two
    /// consecutive ones.
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for &k in &self.knots {
            if out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }

    /// The derivative curve (degree one lower); `None` for degree 0.
    pub fn derivative(&self) -> Option<BSpline> {
        let p = self.degree;
        if p == 0 {
            return None;
        }
        let control = (0..self.control.len() - 1)
            .map(|i| {
                let span = self.knots[i + p + 1] - self.knots[i + 1];
                if span > 0.0 { (self.control[i + 1] - self.control[i]) * (p as f64 / span) } else { DVec3::ZERO }
            })
            .collect();
        Some(BSpline { degree: p - 1, knots: self.knots[1..self.knots.len() - 1].to_vec(), control })
    }

    /// The point at parameter `t` (clamped to the domain), by de Boor's algorithm.
    pub fn point(&self, t: f64) -> DVec3 {
        let (t0, t1) = self.domain();
        let t = t.clamp(t0, t1);
        let span = find_span(&self.knots, self.degree, self.control.len(), t);
        let mut basis = vec![0.0; self.degree + 1];
        basis_functions(&self.knots, self.degree, span, t, &mut basis);
        (0..=self.degree).map(|a| basis[a] * self.control[span - self.degree + a]).sum()
    }
}

/// The knot span `[k_s, k_{s+1})` holding `t` (the last non-empty one at the right end).
fn find_span(knots: &[f64], degree: usize, controls: usize, t: f64) -> usize {
    if t >= knots[controls] {
        return controls - 1;
    }
    // The last index s in [degree, controls) with knots[s] <= t.
    let upper = knots[degree + 1..=controls].partition_point(|k| *k <= t);
    (degree + upper).min(controls - 1)
}

/// The `degree + 1` basis functions that do not vanish on `span`, at `t` (Cox–de Boor).
fn basis_functions(knots: &[f64], degree: usize, span: usize, t: f64, out: &mut [f64]) {
    out.iter_mut().for_each(|b| *b = 0.0);
    out[0] = 1.0;
    for q in 1..=degree {
        // Raise the degree of the q nonzero functions of degree q − 1 to q + 1 of degree q.
        let mut saved = 0.0;
        for r in 0..q {
            let left = knots[span + 1 + r - q];
            let right = knots[span + 1 + r];
            let value = out[r];
            let w = if right > left { value / (right - left) } else { 0.0 };
            out[r] = saved + (right - t) * w;
            saved = (t - left) * w;
        }
        out[q] = saved;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_functions_sum_to_one_and_a_cubic_is_reproduced() {
        // A cubic polynomial curve is exactly a cubic B-spline: the fit must reproduce it.
        let curve = |t: f64| DVec3::new(t, 2.0 * t * t - t, t * t * t - 0.5 * t);
        let params: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
        let points: Vec<DVec3> = params.iter().map(|t| curve(*t)).collect();
        let spline = BSpline::fit(&points, &params, 3, 8).unwrap();
        for i in 0..=100 {
            let t = i as f64 / 100.0;
            assert!((spline.point(t) - curve(t)).length() < 1e-12, "{t}");
        }
        let d1 = spline.derivative().unwrap();
        let d3 = d1.derivative().unwrap().derivative().unwrap();
        assert!((d1.point(0.3) - DVec3::new(1.0, 4.0 * 0.3 - 1.0, 3.0 * 0.09 - 0.5)).length() < 1e-10);
        assert!((d3.point(0.7) - DVec3::new(0.0, 0.0, 6.0)).length() < 1e-9);
        assert_eq!(spline.breakpoints().len(), 6);
        let knots = BSpline::uniform_knots(3, 8, 0.0, 1.0);
        let mut basis = [0.0; 4];
        basis_functions(&knots, 3, find_span(&knots, 3, 8, 0.37), 0.37, &mut basis);
        assert!((basis.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn too_many_control_points_are_refused() {
        let params = [0.0, 0.1, 0.2, 0.9, 1.0];
        let points: Vec<DVec3> = params.iter().map(|t| DVec3::new(*t, t * t, 0.0)).collect();
        assert!(BSpline::fit(&points, &params, 3, 6).is_err());
        let clustered = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 1.0];
        let points: Vec<DVec3> = clustered.iter().map(|t| DVec3::new(*t, t * t, 0.0)).collect();
        assert!(matches!(BSpline::fit(&points, &clustered, 3, 6), Err(Error::Solver(_))));
    }
}
