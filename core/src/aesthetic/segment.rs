//! Log-aesthetic curve segments from three control points and α (Yoshida and Saito,
//! "Interactive aesthetic curve segments", The Visual Computer 22, 2006; the filter paper's
//! ref. 8 and fig. 1(b)).
//!
//! The control points are the start P0, the intersection P1 of the two end tangents and the end
//! P2. A log-aesthetic curve has `dρ/dθ = Λ ρ^{2−α}` in its tangent angle θ; with the radius 1
//! at the start, `ρ(θ)^{α−1} = 1 + (α−1) Λ θ` (`ρ = e^{Λθ}` for α = 1), which covers α = 0 and,
//! with Λ = 0, the circle. The segment must turn by the exterior angle θ_e of the triangle at P1
//! and its chord must leave the start tangent at the triangle's angle a0 at P0; the one free
//! shape parameter is solved for by a safeguarded secant search, and a similarity then places
//! the chord exactly on P0 → P2.
//!
//! We search not over Λ but over `r_e = log(ρ_end/ρ_start)`, which covers every α with the
//! whole real line (Λ's range depends on α and ends where the radius reaches 0 or ∞) and makes
//! the formulas regular at the circle. In the normalised parameter `x ∈ [0, 1]`, with
//! `a = α − 1` and `g(y) = (e^y − 1)/y`: `ρ = e^{r_e x}`, `θ = θ_e x g(a r_e x)/g(a r_e)`,
//! `ds/dx = θ_e e^{α r_e x}/g(a r_e)` and `s = θ_e x g(α r_e x)/g(a r_e)`, all in closed form; the
//! position `∫ e^{iθ} ds` is integrated by composite Gauss–Legendre quadrature with panels
//! sized to the phase and growth rates (relative error near 1e-14).
//!
//! Where it is weak: not every triangle has a segment. For 0 ≤ α ≤ 1 every a0 in (0, θ_e) is
//! reached as `r_e` runs over the real line; for α < 0 or α > 1 only a band around θ_e/2 is
//! ([`AestheticSegment::feasible_start_angles`]), and outside it there is no segment (`None`).
//! The search is bounded by a curvature ratio of e^±[`MAX_LOG_RADIUS_RATIO`] between the ends,
//! so triangles that would need a more extreme ratio are reported as having no segment too.

use crate::{DVec3, Error, Result};

/// Largest `|log(ρ_end / ρ_start)|` searched: a curvature ratio of about 1e26 between the ends.
pub const MAX_LOG_RADIUS_RATIO: f64 = 60.0;

/// `(e^y − 1)/y`, 1 at 0.
fn g(y: f64) -> f64 {
    if y.abs() < 1e-8 { 1.0 + 0.5 * y } else { y.exp_m1() / y }
}

/// `log(1 + y)/y`, 1 at 0.
fn h(y: f64) -> f64 {
    if y.abs() < 1e-8 { 1.0 - 0.5 * y } else { y.ln_1p() / y }
}

/// Gauss–Legendre nodes and weights on [−1, 1], by Newton's method on the Legendre polynomial.
fn gauss_legendre<const N: usize>() -> ([f64; N], [f64; N]) {
    let (mut nodes, mut weights) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (N as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            // P_N(x) and P_N'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=N {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            derivative = N as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / derivative;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        nodes[i] = x;
        weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
    }
    (nodes, weights)
}

/// The curve in its standard position: start at the origin, start tangent +x, turning towards
/// +y by `turning`, start radius 1, end radius `e^{log_ratio}`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct StandardForm {
    alpha: f64,
    turning: f64,
    log_ratio: f64,
}

impl StandardForm {
    fn angle(&self, x: f64) -> f64 {
        let a = (self.alpha - 1.0) * self.log_ratio;
        self.turning * x * g(a * x) / g(a)
    }

    fn speed(&self, x: f64) -> f64 {
        self.turning * (self.alpha * self.log_ratio * x).exp() / g((self.alpha - 1.0) * self.log_ratio)
    }

    fn arc_length(&self, x: f64) -> f64 {
        self.turning * x * g(self.alpha * self.log_ratio * x) / g((self.alpha - 1.0) * self.log_ratio)
    }

    fn parameter_at(&self, s: f64) -> f64 {
        let sigma = s * g((self.alpha - 1.0) * self.log_ratio) / self.turning;
        (sigma * h(self.alpha * self.log_ratio * sigma)).clamp(0.0, 1.0)
    }

    /// Gauss–Legendre panels per unit of x: enough that each panel sees a phase change and a
    /// growth of the speed of about half a unit.
    fn panels_per_unit(&self) -> f64 {
        let a = ((self.alpha - 1.0) * self.log_ratio).abs();
        (2.0 * self.turning * (1.0 + a)).max(2.0 * (self.alpha * self.log_ratio).abs()).max(4.0)
    }

    /// `∫ e^{iθ} ds` from x0 to x1, as (real, imaginary).
    fn integrate(&self, x0: f64, x1: f64) -> (f64, f64) {
        let (nodes, weights) = gauss_legendre::<8>();
        let panels = ((x1 - x0).abs() * self.panels_per_unit()).ceil().max(1.0) as usize;
        let width = (x1 - x0) / panels as f64;
        let (mut re, mut im) = (0.0, 0.0);
        for p in 0..panels {
            let mid = x0 + (p as f64 + 0.5) * width;
            for (t, w) in nodes.iter().zip(&weights) {
                let x = mid + 0.5 * width * t;
                let (sin, cos) = self.angle(x).sin_cos();
                let f = w * 0.5 * width * self.speed(x);
                re += f * cos;
                im += f * sin;
            }
        }
        (re, im)
    }

    /// Angle between the start tangent and the chord.
    fn chord_angle(&self) -> f64 {
        let (re, im) = self.integrate(0.0, 1.0);
        im.atan2(re)
    }
}

/// A planar log-aesthetic segment placed in space.
#[derive(Clone, Debug, PartialEq)]
pub struct AestheticSegment {
    form: StandardForm,
    origin: DVec3,
    /// World image of the standard +x and +y directions, each of length `scale`.
    axis_x: DVec3,
    axis_y: DVec3,
    scale: f64,
}

impl AestheticSegment {
    /// The segment from `p0` to `p2` whose end tangents meet at `p1`, with slope `alpha` of its
    /// logarithmic curvature graph. `Err` for unusable control points (not finite, coincident,
    /// collinear) or α; `Ok(None)` when no log-aesthetic segment with this α has these control
    /// points (see [`AestheticSegment::feasible_start_angles`]).
    pub fn from_control_points(p0: DVec3, p1: DVec3, p2: DVec3, alpha: f64) -> Result<Option<AestheticSegment>> {
        let (form, frame) = Self::standard_problem(p0, p1, p2, alpha)?;
        let target = (p2 - p0).angle_between(p1 - p0);
        let Some(log_ratio) = solve_log_ratio(form, target) else { return Ok(None) };
        let form = StandardForm { log_ratio, ..form };
        // The similarity that puts the standard chord exactly on p0 → p2.
        let (re, im) = form.integrate(0.0, 1.0);
        let chord = (re * re + im * im).sqrt();
        let scale = (p2 - p0).length() / chord;
        let turn = target - im.atan2(re);
        let (e1, e2) = frame;
        let (sin, cos) = turn.sin_cos();
        let axis_x = scale * (cos * e1 + sin * e2);
        let axis_y = scale * (-sin * e1 + cos * e2);
        let segment = AestheticSegment { form, origin: p0, axis_x, axis_y, scale };
        // A turn of a few 1e-12 radians passes the collinearity check but leaves the standard
        // integral at rounding level: its numbers are not finite (or not meaningful). Refuse it.
        let finite = scale.is_finite()
            && axis_x.is_finite()
            && axis_y.is_finite()
            && segment.length().is_finite()
            && segment.lambda().is_finite();
        if !(chord > 0.0 && finite) {
            return Err(Error::Input(format!(
                "the three control points are almost collinear (the end tangents turn by {:.3e}°): the segment \
                 cannot be computed in floating point; move the middle point further off the line",
                form.turning.to_degrees()
            )));
        }
        Ok(Some(segment))
    }

    /// The log-aesthetic curve that starts at the origin along +x with radius of curvature
    /// `start_radius`, turns towards +y by `turning` radians (any amount, several turns too) and
    /// ends with radius `start_radius · e^{log_radius_ratio}`. `None` for non-finite or
    /// non-positive values, |α| > 100 or `|log_radius_ratio|` beyond [`MAX_LOG_RADIUS_RATIO`].
    pub fn in_standard_position(alpha: f64, turning: f64, log_radius_ratio: f64, start_radius: f64) -> Option<Self> {
        let ok = alpha.is_finite()
            && alpha.abs() <= 100.0
            && turning.is_finite()
            && turning > 0.0
            && log_radius_ratio.abs() <= MAX_LOG_RADIUS_RATIO
            && start_radius.is_finite()
            && start_radius > 0.0;
        ok.then(|| AestheticSegment {
            form: StandardForm { alpha, turning, log_ratio: log_radius_ratio },
            origin: DVec3::ZERO,
            axis_x: start_radius * DVec3::X,
            axis_y: start_radius * DVec3::Y,
            scale: start_radius,
        })
    }

    /// The range of start angles a0 (between the start tangent and the chord, radians) for which
    /// a segment with this α and total turning exists (within [`MAX_LOG_RADIUS_RATIO`]). It is
    /// all of `(0, turning)` in the limit for 0 ≤ α ≤ 1, a narrower band otherwise.
    pub fn feasible_start_angles(alpha: f64, turning: f64) -> (f64, f64) {
        let at = |log_ratio| StandardForm { alpha, turning, log_ratio }.chord_angle();
        (at(-MAX_LOG_RADIUS_RATIO), at(MAX_LOG_RADIUS_RATIO))
    }

    /// Checks the control points and α; the standard problem (with `log_ratio` 0) and the frame
    /// (start tangent, unit normal to it on the side of the turn).
    fn standard_problem(p0: DVec3, p1: DVec3, p2: DVec3, alpha: f64) -> Result<(StandardForm, (DVec3, DVec3))> {
        let bad = |m: String| Err(Error::Input(m));
        if !(p0.is_finite() && p1.is_finite() && p2.is_finite()) {
            return bad("the control points of an aesthetic segment must be finite".into());
        }
        if !(alpha.is_finite() && alpha.abs() <= 100.0) {
            return bad(format!("α must be a finite number between −100 and 100, not {alpha}"));
        }
        let size = (p1 - p0).length().max((p2 - p1).length()).max((p2 - p0).length());
        if !(size > 0.0 && size < 1e100) {
            return bad("the three control points coincide (or are absurdly far apart)".into());
        }
        let (t0, t2) = (p1 - p0, p2 - p1);
        if t0.length() <= 1e-12 * size || t2.length() <= 1e-12 * size {
            return bad("the middle control point must differ from both ends: it is where the end tangents meet".into());
        }
        let normal = t0.cross(t2);
        if normal.length() <= 1e-12 * t0.length() * t2.length() {
            return bad(
                "the three control points are collinear: the segment would be a straight line (or fold back); \
                 move the middle point off the line"
                    .into(),
            );
        }
        let e1 = t0.normalize();
        let e2 = normal.cross(e1).normalize();
        let turning = t0.angle_between(t2);
        Ok((StandardForm { alpha, turning, log_ratio: 0.0 }, (e1, e2)))
    }

    /// Slope α of the logarithmic curvature graph.
    pub fn alpha(&self) -> f64 {
        self.form.alpha
    }

    /// Total turning of the tangent, radians.
    pub fn turning(&self) -> f64 {
        self.form.turning
    }

    /// `log(ρ_end / ρ_start)`: 0 for a circular arc, positive when the curvature falls towards
    /// the end.
    pub fn log_radius_ratio(&self) -> f64 {
        self.form.log_ratio
    }

    /// Yoshida and Saito's Λ of the segment scaled to a start radius of 1.
    pub fn lambda(&self) -> f64 {
        let f = &self.form;
        f.log_ratio * g((f.alpha - 1.0) * f.log_ratio) / f.turning
    }

    /// Length of the segment.
    pub fn length(&self) -> f64 {
        self.scale * self.form.arc_length(1.0)
    }

    /// Radius of curvature at arc length `s` from the start (clamped to the segment).
    pub fn radius_at(&self, s: f64) -> f64 {
        let x = self.form.parameter_at(s / self.scale);
        self.scale * (self.form.log_ratio * x).exp()
    }

    /// Curvature `1/ρ` at arc length `s` (the segment turns one way throughout).
    pub fn curvature_at(&self, s: f64) -> f64 {
        1.0 / self.radius_at(s)
    }

    /// Unit tangent at arc length `s`.
    pub fn tangent_at(&self, s: f64) -> DVec3 {
        let (sin, cos) = self.form.angle(self.form.parameter_at(s / self.scale)).sin_cos();
        (cos * self.axis_x + sin * self.axis_y) / self.scale
    }

    /// The point at arc length `s` from the start (clamped to the segment).
    pub fn point_at(&self, s: f64) -> DVec3 {
        let (re, im) = self.form.integrate(0.0, self.form.parameter_at(s / self.scale));
        self.origin + re * self.axis_x + im * self.axis_y
    }

    /// The points at the given fractions of the length (each clamped to [0, 1]), integrating
    /// once along the segment however many there are.
    pub fn points_at_fractions(&self, fractions: &[f64]) -> Vec<DVec3> {
        let total = self.form.arc_length(1.0);
        let mut order: Vec<usize> = (0..fractions.len()).collect();
        order.sort_by(|&a, &b| fractions[a].total_cmp(&fractions[b]));
        let mut out = vec![self.origin; fractions.len()];
        let (mut x, mut re, mut im) = (0.0, 0.0, 0.0);
        for i in order {
            let f = if fractions[i].is_nan() { 0.0 } else { fractions[i].clamp(0.0, 1.0) };
            let next = if f == 1.0 { 1.0 } else { self.form.parameter_at(f * total) };
            let (dr, di) = self.form.integrate(x, next);
            (x, re, im) = (next, re + dr, im + di);
            out[i] = self.origin + re * self.axis_x + im * self.axis_y;
        }
        out
    }

    /// `count ≥ 2` points evenly spaced in arc length, both ends included.
    pub fn sample(&self, count: usize) -> Vec<DVec3> {
        let count = count.max(2);
        let fractions: Vec<f64> = (0..count).map(|i| i as f64 / (count - 1) as f64).collect();
        self.points_at_fractions(&fractions)
    }
}

/// The `log_ratio` whose chord leaves the start tangent at `target`, by the Illinois variant of
/// false position on `[−MAX, MAX]` (the chord angle increases with `log_ratio`); `None` when
/// `target` is outside the reachable range.
fn solve_log_ratio(form: StandardForm, target: f64) -> Option<f64> {
    let f = |r: f64| StandardForm { log_ratio: r, ..form }.chord_angle() - target;
    let (mut lo, mut hi) = (-MAX_LOG_RADIUS_RATIO, MAX_LOG_RADIUS_RATIO);
    let (mut f_lo, mut f_hi) = (f(lo), f(hi));
    if !(f_lo <= 0.0 && f_hi >= 0.0) {
        return None;
    }
    // Start from the circle, which is the answer for an isosceles triangle.
    let f0 = f(0.0);
    if f0 == 0.0 {
        return Some(0.0);
    }
    if f0 < 0.0 {
        (lo, f_lo) = (0.0, f0);
    } else {
        (hi, f_hi) = (0.0, f0);
    }
    let mut side = 0i8;
    for _ in 0..200 {
        let secant = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        // Fall back to bisection where the secant leaves the bracket or stalls at one end.
        let r = if secant.is_finite() && secant > lo && secant < hi { secant } else { 0.5 * (lo + hi) };
        let fr = f(r);
        if fr == 0.0 || (hi - lo) < 1e-15 * (1.0 + r.abs()) || fr.abs() < 1e-15 {
            return Some(r);
        }
        if fr < 0.0 {
            (lo, f_lo) = (r, fr);
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            (hi, f_hi) = (r, fr);
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_fifteen() {
        let (x, w) = gauss_legendre::<8>();
        for degree in 0..16 {
            let sum: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(degree)).sum();
            let exact = if degree % 2 == 1 { 0.0 } else { 2.0 / (degree + 1) as f64 };
            assert!((sum - exact).abs() < 1e-14, "x^{degree}: {sum}");
        }
    }

    #[test]
    fn the_logarithmic_spiral_matches_its_closed_form() {
        // α = 1: ρ = e^{Λθ}, C(θ) = (e^{(Λ+i)θ} − 1)/(Λ + i).
        let form = StandardForm { alpha: 1.0, turning: 2.5, log_ratio: 1.7 };
        let lambda = 1.7 / 2.5;
        let (re, im) = form.integrate(0.0, 1.0);
        let (mag, arg) = ((lambda * 2.5f64).exp(), 2.5f64);
        let (nr, ni) = (mag * arg.cos() - 1.0, mag * arg.sin());
        let d = lambda * lambda + 1.0;
        let (er, ei) = ((nr * lambda + ni) / d, (ni * lambda - nr) / d);
        assert!((re - er).abs() < 1e-13 && (im - ei).abs() < 1e-13, "({re}, {im}) vs ({er}, {ei})");
        // s(θ) = (e^{Λθ} − 1)/Λ and its inverse.
        assert!((form.arc_length(1.0) - (lambda * 2.5).exp_m1() / lambda).abs() < 1e-13);
        assert!((form.parameter_at(form.arc_length(0.3)) - 0.3).abs() < 1e-14);
    }

    #[test]
    fn the_chord_angle_increases_with_the_radius_ratio() {
        for alpha in [-2.0, -1.0, 0.0, 0.5, 1.0, 2.0, 3.0] {
            let mut previous = 0.0;
            for k in -30..=30 {
                let form = StandardForm { alpha, turning: 2.0, log_ratio: 2.0 * k as f64 };
                let chi = form.chord_angle();
                assert!(
                    chi > previous - 1e-12 && chi < 2.0,
                    "α = {alpha}, r = {}: {chi} after {previous}",
                    2.0 * k as f64
                );
                previous = chi;
            }
        }
    }

    #[test]
    fn an_isosceles_triangle_gives_a_circular_arc() {
        let (p0, p1, p2) = (DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 0.0, 0.0));
        for alpha in [-1.0, 0.0, 1.0, 2.0] {
            let seg = AestheticSegment::from_control_points(p0, p1, p2, alpha).unwrap().unwrap();
            assert!(seg.log_radius_ratio().abs() < 1e-12, "{alpha}");
            // A quarter circle of radius √2 about (1, −1).
            assert!((seg.length() - FRAC_PI_2 * 2f64.sqrt()).abs() < 1e-12);
            for p in seg.sample(9) {
                assert!((p.distance(DVec3::new(1.0, -1.0, 0.0)) - 2f64.sqrt()).abs() < 1e-12, "{p}");
            }
        }
    }

    #[test]
    fn outside_the_feasible_band_there_is_no_segment() {
        // α = 2 and a right-angle turn: a0 must lie in a band around 45°.
        let (lo, hi) = AestheticSegment::feasible_start_angles(2.0, FRAC_PI_2);
        assert!(lo > 0.05 && hi < FRAC_PI_2 - 0.05 && lo < PI / 4.0 && hi > PI / 4.0, "{lo} {hi}");
        let a0 = 0.5 * lo;
        let p1 = DVec3::X;
        let p2 = p1 + DVec3::Y * a0.tan();
        assert!((p2.angle_between(p1) - a0).abs() < 1e-12);
        assert_eq!(AestheticSegment::from_control_points(DVec3::ZERO, p1, p2, 2.0).unwrap(), None);
        assert!(AestheticSegment::from_control_points(DVec3::ZERO, p1, p2, 0.5).unwrap().is_some());
        assert!(AestheticSegment::from_control_points(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X, 0.5).is_err());
        assert!(AestheticSegment::from_control_points(DVec3::ZERO, DVec3::ZERO, DVec3::Y, 0.5).is_err());
        assert!(AestheticSegment::from_control_points(DVec3::ZERO, DVec3::X, DVec3::Y, f64::NAN).is_err());
    }
}
