//! The log-aesthetic law and the least-squares lines fitted to it (paper eqs. 4–6 and 10–12).
//!
//! A log-aesthetic curve has `ρ^α = c s + d` for α ≠ 0 and `log ρ = c s + d` for α = 0, with ρ
//! the radius of curvature and s the arc length: in the variable [`law_value`]`(ρ, α)` the curve
//! is a straight line in s. The filters fit that line to a window of points by least squares and
//! read the target radius back with [`radius_from_law`]; the same line fit gives the slope of a
//! logarithmic curvature graph. The space-curve filter uses the same law for the radius of
//! torsion μ with its own exponent β.
//!
//! Where it is weak: the fit is an ordinary least-squares line in the transformed variable, so
//! for α > 0 a point of nearly zero curvature (ρ → ∞) dominates it; the filters therefore leave
//! windows with such points alone (see `filter`).

/// `ρ^α` (α ≠ 0) or `log ρ` (α = 0): the quantity that is linear in arc length.
#[inline]
pub fn law_value(radius: f64, alpha: f64) -> f64 {
    // The common slopes without `powf`, which dominates a filter pass otherwise.
    match alpha {
        0.0 => radius.ln(),
        1.0 => radius,
        -1.0 => 1.0 / radius,
        2.0 => radius * radius,
        _ => radius.powf(alpha),
    }
}

/// The radius whose [`law_value`] is `y`; `None` when no positive finite radius has it (`y ≤ 0`
/// for α ≠ 0).
#[inline]
pub fn radius_from_law(y: f64, alpha: f64) -> Option<f64> {
    let r = match alpha {
        0.0 => y.exp(),
        _ if y <= 0.0 || y.is_nan() => return None,
        1.0 => y,
        -1.0 => 1.0 / y,
        2.0 => y.sqrt(),
        _ => y.powf(1.0 / alpha),
    };
    (r.is_finite() && r > 0.0).then_some(r)
}

/// A least-squares line `y = slope · x + intercept`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    /// Slope; for a logarithmic curvature graph, α.
    pub slope: f64,
    /// Value at `x = 0`.
    pub intercept: f64,
    /// Root-mean-square distance, in y, of the points from the line.
    pub residual: f64,
    /// Number of points fitted.
    pub count: usize,
}

impl LineFit {
    /// The line's value at `x`.
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        self.slope * x + self.intercept
    }
}

/// Accumulates the sums of a least-squares line fit, centred on the first x for accuracy.
#[derive(Clone, Copy, Debug, Default)]
pub struct LineSums {
    x0: f64,
    n: f64,
    sx: f64,
    sy: f64,
    sxx: f64,
    sxy: f64,
}

impl LineSums {
    /// Adds the point `(x, y)`.
    #[inline]
    pub fn add(&mut self, x: f64, y: f64) {
        if self.n == 0.0 {
            self.x0 = x;
        }
        let x = x - self.x0;
        self.n += 1.0;
        self.sx += x;
        self.sy += y;
        self.sxx += x * x;
        self.sxy += x * y;
    }

    /// Adds the point `(x, y)` where the first x added was 0 (or is to be taken as the origin of
    /// the x): [`LineSums::add`] without its centring.
    #[inline]
    pub fn add_from_zero(&mut self, x: f64, y: f64) {
        self.n += 1.0;
        self.sx += x;
        self.sy += y;
        self.sxx += x * x;
        self.sxy += x * y;
    }

    /// Slope and intercept, `None` with fewer than two distinct x.
    #[inline]
    pub fn line(&self) -> Option<(f64, f64)> {
        let det = self.n * self.sxx - self.sx * self.sx;
        if det.is_nan() || det <= 1e-14 * self.n * self.sxx {
            return None;
        }
        let slope = (self.n * self.sxy - self.sx * self.sy) / det;
        let intercept = (self.sy - slope * self.sx) / self.n;
        Some((slope, intercept - slope * self.x0))
    }
}

/// The least-squares line through `(x, y)` pairs, `None` with fewer than two distinct x or
/// non-finite values.
pub fn fit_line(x: &[f64], y: &[f64]) -> Option<LineFit> {
    let mut sums = LineSums::default();
    for (a, b) in x.iter().zip(y) {
        if !(a.is_finite() && b.is_finite()) {
            return None;
        }
        sums.add(*a, *b);
    }
    let (slope, intercept) = sums.line()?;
    let count = x.len().min(y.len());
    let residual =
        (x.iter().zip(y).map(|(a, b)| (b - slope * a - intercept).powi(2)).sum::<f64>() / count as f64).sqrt();
    Some(LineFit { slope, intercept, residual, count })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_law_inverts() {
        for alpha in [-2.0, -1.0, 0.0, 0.5, 1.0, 2.0] {
            let y = law_value(3.7, alpha);
            assert!((radius_from_law(y, alpha).unwrap() - 3.7).abs() < 1e-12, "{alpha}");
        }
        assert_eq!(radius_from_law(-1.0, 2.0), None);
        assert_eq!(radius_from_law(0.0, -1.0), None);
    }

    #[test]
    fn a_line_is_fitted_exactly_far_from_zero() {
        let x: Vec<f64> = (0..7).map(|i| 1e6 + 0.1 * i as f64).collect();
        let y: Vec<f64> = x.iter().map(|x| -2.5 * (x - 1e6) + 4.0).collect();
        let fit = fit_line(&x, &y).unwrap();
        assert!((fit.slope + 2.5).abs() < 1e-8 && (fit.at(1e6) - 4.0).abs() < 1e-8 && fit.residual < 1e-8, "{fit:?}");
        assert_eq!(fit_line(&[1.0, 1.0], &[0.0, 1.0]), None);
        assert_eq!(fit_line(&[1.0, f64::NAN], &[0.0, 1.0]), None);
    }
}
