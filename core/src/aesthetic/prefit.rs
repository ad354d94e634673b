//! The smoothing pre-fit of the shape-keeping fairing ([`super::filter::DataTerm`]): a departure
//! from the paper, which filters the measured points themselves.
//!
//! The log-aesthetic filter reads curvature from three neighbouring points, so it can only tell
//! noise from shape where the noise is well below the spacing's curvature signal: with 0.5 % noise
//! on 200 points, or any noise on 1,000, the three-point curvature is mostly noise, its targets
//! are biased sharper (the law is nonlinear in κ), and the curve walks inward pass after pass.
//! Nothing holds it to the data. The pre-fit first takes out the noise at the scale the data
//! allows, and the filter then works on a curve whose curvature means something, pulled back
//! towards the pre-fit in every pass.
//!
//! The pre-fit is the discrete penalised least-squares smoother of Whittaker (1923), as Eilers
//! ("A perfect smoother", Anal. Chem. 75, 2003) writes it: the points `S` minimising
//! `Σ |S_i − D_i|² + μ Σ |Δ^p S_j|²` over the input points `D`, with `Δ^p` the p-th difference
//! along the sequence ([`ORDER`] = 3, so the null space holds every quadratic and a circular arc
//! of a few points per radian is barely flattened). The end points of an open curve stay, as they
//! do in the filter. The system is banded (half-width p) and solved by banded Cholesky for each
//! coordinate, `O(n)`; a closed curve is unrolled three times and the middle copy kept.
//!
//! The smoothing μ is chosen from the data by generalised cross-validation (Craven and Wahba
//! 1979): the μ minimising `m · RSS / (m − tr H)²`, with `H` the smoother's hat matrix over the
//! `m` free points. `tr H` (the pre-fit's degrees of freedom) is exact, from one solve per point,
//! up to [`EXACT_TRACE_UP_TO`] free points, and above that the eigenvalues of the periodic
//! difference operator, `(2 sin(π k / 2m))^{2p}`, whose error is a boundary effect of order
//! `p / m`. The noise level it implies, `sqrt(RSS / (m − tr H))`, is reported.
//!
//! Where it is weak: the differences run over the point index, so the smoother assumes the points
//! are roughly evenly spaced along the curve (a digitiser's are; points bunched in one place get
//! smoothed over a shorter length there). GCV on a few tens of points picks μ roughly, within a
//! factor of a few; the log-aesthetic filter that follows does the rest of the work there.

use crate::DVec3;

/// Order p of the differences the smoother penalises.
pub const ORDER: usize = 3;
/// Free points up to which the hat matrix's trace is computed exactly.
pub const EXACT_TRACE_UP_TO: usize = 200;
/// Candidate μ per decade in the first scan of GCV.
const PER_DECADE: f64 = 4.0;

/// What the pre-fit's points lie on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PrefitModel {
    /// The Whittaker smoother's points.
    Smoothed,
    /// One log-aesthetic segment through the end points fitted the whole open curve to the noise
    /// level (its α): the points were moved onto it.
    Segment { alpha: f64 },
    /// A circle fitted the whole closed curve to the noise level (a closed log-aesthetic curve is
    /// a circle): the points were moved onto it.
    Circle { radius: f64 },
}

/// The pre-fit's points and what was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct Prefit {
    /// The smoothed points, one per input point.
    pub points: Vec<DVec3>,
    /// The smoothing μ (chosen by GCV unless given).
    pub smoothing: f64,
    /// Degrees of freedom `tr H` of the smoother over the free points.
    pub dof: f64,
    /// The noise level the fit implies: RMS distance of an input point from where it belongs.
    pub noise: f64,
    /// What the points lie on: the smoother's, or one curve of the model that explains them.
    pub model: PrefitModel,
}

/// Smooths `points` (open: end points kept; closed: all free) with the given μ or one chosen by
/// GCV. Fewer than `ORDER + 3` points come back unchanged.
pub fn prefit(points: &[DVec3], closed: bool, smoothing: Option<f64>) -> Prefit {
    let n = points.len();
    let unchanged =
        || Prefit { points: points.to_vec(), smoothing: 0.0, dof: n as f64, noise: 0.0, model: PrefitModel::Smoothed };
    if n < ORDER + 3 {
        return unchanged();
    }
    let problem = Problem::new(points, closed);
    let Some(mu) = smoothing.or_else(|| problem.gcv()) else { return unchanged() };
    let Some(fit) = problem.fit(mu) else { return unchanged() };
    let dof = problem.trace(mu).unwrap_or(problem.free as f64);
    let noise = (fit.rss / (problem.free as f64 - dof).max(1e-12)).sqrt();
    Prefit { points: fit.points, smoothing: mu, dof, noise, model: PrefitModel::Smoothed }
}

/// The pre-fit of a planar curve (in the plane with this `normal`): when one log-aesthetic
/// segment through the end points (open) or one circle (closed) is as close to the points as the
/// smoother's noise level, the points moved onto it, else the smoother's. With one `alpha` given
/// for the whole curve, the segment is one of that α (the filter aims at it anyway). A curve the model
/// explains is best estimated by the model (three parameters besides the fixed ends, where the
/// smoother spends a few per radian): on 20 noisy points of a half-turn spiral the points end a
/// third as far from the true curve as the input, against 0.43–0.57 smoothed. The test of "as
/// close": RMS distance within [`super::segment_fit::NOISE_FACTOR`] times the smoother's noise
/// level, as α estimation uses it.
pub fn prefit_planar(
    points: &[DVec3],
    closed: bool,
    normal: DVec3,
    alpha: Option<f64>,
    smoothing: Option<f64>,
) -> Prefit {
    let smoothed = prefit(points, closed, smoothing);
    if smoothing.is_some() || smoothed.model != PrefitModel::Smoothed || smoothed.noise <= 0.0 {
        return smoothed;
    }
    let within = |rms: f64| rms <= super::segment_fit::NOISE_FACTOR * smoothed.noise;
    // Where along the model each point goes: its share of the smoothed points' length. Feet of
    // perpendiculars would keep the noise along the curve, and where it exceeds the spacing two
    // neighbours swap and the curve doubles back; the smoother's spacing is in order.
    let shares = chord_shares(&smoothed.points, closed);
    let model = if closed {
        circle_fit(points, normal)
            .filter(|c| within(c.rms))
            .map(|c| (c.at_shares(points, &shares), PrefitModel::Circle { radius: c.radius }))
    } else {
        super::segment_fit::fit_smoothed(points, &smoothed.points, normal, alpha).filter(|f| within(f.rms)).and_then(
            |f| {
                super::segment_fit::points_on(points, normal, &f, &shares)
                    .map(|p| (p, PrefitModel::Segment { alpha: f.alpha }))
            },
        )
    };
    match model {
        Some((mut on, model)) if on.len() == points.len() && on.iter().all(|p| p.is_finite()) => {
            if !closed {
                // The ends stay exactly where they are, as they do in the filter.
                let n = points.len();
                (on[0], on[n - 1]) = (points[0], points[n - 1]);
            }
            Prefit { points: on, model, ..smoothed }
        }
        _ => smoothed,
    }
}

/// The pre-fit of a space curve: when one log-aesthetic space segment through the end points
/// ([`super::space_fit`], of the given α when one is given) is as close to the points as the
/// smoother's noise level, the points moved onto it at the smoothed points' shares of the length,
/// else the smoother's (always for a closed curve). The space counterpart of [`prefit_planar`]:
/// on twenty noisy points the smoother alone ended 0.40–0.61 as far from the true curve as the
/// input.
pub fn prefit_space(points: &[DVec3], closed: bool, alpha: Option<f64>, smoothing: Option<f64>) -> Prefit {
    let smoothed = prefit(points, closed, smoothing);
    if closed || smoothing.is_some() || smoothed.noise <= 0.0 {
        return smoothed;
    }
    let fit = super::space_fit::fit_space_smoothed(points, &smoothed.points, alpha);
    match fit.and_then(|f| super::space_fit::explaining(points, &smoothed.points, &f, smoothed.noise).map(|p| (p, f))) {
        Some((mut on, fit)) if on.len() == points.len() => {
            let n = points.len();
            (on[0], on[n - 1]) = (points[0], points[n - 1]);
            Prefit { points: on, model: PrefitModel::Segment { alpha: fit.alpha }, ..smoothed }
        }
        _ => smoothed,
    }
}

/// A circle in a plane: centre, radius, and the RMS distance of the points it was fitted to.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Circle {
    centre: DVec3,
    radius: f64,
    normal: DVec3,
    rms: f64,
}

impl Circle {
    /// Points on the circle at the given shares of a turn, turned as a whole to lie nearest
    /// `points` on average (the circular mean of each point's angle less its share).
    fn at_shares(&self, points: &[DVec3], shares: &[f64]) -> Vec<DVec3> {
        let u = self.normal.any_orthonormal_vector();
        let v = self.normal.cross(u);
        let sense = {
            // Which way the points run around the normal.
            let n = points.len();
            let area: f64 = (0..n)
                .map(|i| (points[i] - self.centre).cross(points[(i + 1) % n] - self.centre).dot(self.normal))
                .sum();
            if area >= 0.0 { 1.0 } else { -1.0 }
        };
        let angle = |p: DVec3| (p - self.centre).dot(v).atan2((p - self.centre).dot(u));
        let (sin, cos) = points.iter().zip(shares).fold((0.0, 0.0), |(s, c), (p, f)| {
            let phase = angle(*p) - sense * std::f64::consts::TAU * f;
            (s + phase.sin(), c + phase.cos())
        });
        let phase = sin.atan2(cos);
        shares
            .iter()
            .map(|f| {
                let a = phase + sense * std::f64::consts::TAU * f;
                self.centre + self.radius * (a.cos() * u + a.sin() * v)
            })
            .collect()
    }
}

/// Each point's share of the polyline's length from its first point (closed: of the loop's).
fn chord_shares(points: &[DVec3], closed: bool) -> Vec<f64> {
    let n = points.len();
    let mut at = vec![0.0; n];
    for i in 1..n {
        at[i] = at[i - 1] + points[i].distance(points[i - 1]);
    }
    let total = if closed { at[n - 1] + points[0].distance(points[n - 1]) } else { at[n - 1] };
    if !(total > 0.0 && total.is_finite()) {
        return (0..n).map(|i| i as f64 / n.max(2) as f64).collect();
    }
    at.iter().map(|s| s / total).collect()
}

/// The circle nearest the points in the plane with this `normal`: Kåsa's algebraic fit, then
/// Gauss–Newton on the geometric distances (a few steps from there converge).
fn circle_fit(points: &[DVec3], normal: DVec3) -> Option<Circle> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let normal = normal.normalize();
    let origin = points.iter().copied().sum::<DVec3>() / n as f64;
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let xy: Vec<(f64, f64)> = points.iter().map(|p| ((*p - origin).dot(u), (*p - origin).dot(v))).collect();
    // Kåsa: x² + y² + D x + E y + F = 0 in least squares.
    let mut m = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for &(x, y) in &xy {
        let row = [x, y, 1.0];
        let rhs = -(x * x + y * y);
        for a in 0..3 {
            for b in 0..3 {
                m[a][b] += row[a] * row[b];
            }
            r[a] += row[a] * rhs;
        }
    }
    let solve3 = |m: [[f64; 3]; 3], r: [f64; 3]| -> Option<[f64; 3]> {
        let det = |m: [[f64; 3]; 3]| {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let d = det(m);
        if !(d.abs() > 0.0 && d.is_finite()) {
            return None;
        }
        Some(std::array::from_fn(|k| {
            let mut mk = m;
            for row in 0..3 {
                mk[row][k] = r[row];
            }
            det(mk) / d
        }))
    };
    let [d, e, f] = solve3(m, r)?;
    let (mut cx, mut cy) = (-d / 2.0, -e / 2.0);
    let mut radius = (cx * cx + cy * cy - f).max(0.0).sqrt();
    // Gauss–Newton on r_i = |p_i − c| − R.
    for _ in 0..20 {
        let mut jtj = [[0.0f64; 3]; 3];
        let mut jtr = [0.0f64; 3];
        for &(x, y) in &xy {
            let (dx, dy) = (x - cx, y - cy);
            let dist = (dx * dx + dy * dy).sqrt().max(f64::MIN_POSITIVE);
            let res = dist - radius;
            let j = [-dx / dist, -dy / dist, -1.0];
            for a in 0..3 {
                for b in 0..3 {
                    jtj[a][b] += j[a] * j[b];
                }
                jtr[a] -= j[a] * res;
            }
        }
        let Some(step) = solve3(jtj, jtr) else { break };
        (cx, cy, radius) = (cx + step[0], cy + step[1], radius + step[2]);
        if step.iter().map(|s| s.abs()).fold(0.0, f64::max) <= 1e-15 * radius.abs().max(1.0) {
            break;
        }
    }
    let rms = (xy.iter().map(|&(x, y)| ((x - cx).hypot(y - cy) - radius).powi(2)).sum::<f64>() / n as f64).sqrt();
    (radius > 0.0 && radius.is_finite() && rms.is_finite()).then_some(Circle {
        centre: origin + u * cx + v * cy,
        radius,
        normal,
        rms,
    })
}

/// The smoothing problem of one curve.
struct Problem<'a> {
    points: &'a [DVec3],
    closed: bool,
    /// Points the smoother moves: all of a closed curve, all but the ends of an open one.
    free: usize,
    /// The p-th difference's coefficients, `(−1)^{p−k} C(p, k)`.
    stencil: [f64; ORDER + 1],
}

/// One smoothed curve and its residual sum of squares over the free points.
struct Fit {
    points: Vec<DVec3>,
    rss: f64,
}

impl<'a> Problem<'a> {
    fn new(points: &'a [DVec3], closed: bool) -> Self {
        let n = points.len();
        let mut stencil = [0.0; ORDER + 1];
        let mut binomial = 1.0;
        for (k, c) in stencil.iter_mut().enumerate() {
            *c = if (ORDER - k).is_multiple_of(2) { binomial } else { -binomial };
            binomial = binomial * (ORDER - k) as f64 / (k + 1) as f64;
        }
        Problem { points, closed, free: if closed { n } else { n - 2 }, stencil }
    }

    /// The band of `I + μ K` (K = ΔᵀΔ) over `size` points, row i holding `A[i][i − d]` at `d`.
    fn band(&self, size: usize, mu: f64) -> Vec<f64> {
        let w = ORDER + 1;
        let mut band = vec![0.0; size * w];
        for i in 0..size {
            band[i * w] = 1.0;
        }
        for r in 0..=size.saturating_sub(w) {
            for a in 0..w {
                for b in 0..=a {
                    band[(r + a) * w + (a - b)] += mu * self.stencil[a] * self.stencil[b];
                }
            }
        }
        band
    }

    /// The smoothed points for μ.
    fn solve(&self, mu: f64) -> Option<Vec<DVec3>> {
        let n = self.points.len();
        if self.closed {
            // Unrolled three times; the middle copy is the closed curve's smoothing.
            let size = 3 * n;
            let factor = Cholesky::new(self.band(size, mu), size)?;
            let rhs: Vec<DVec3> = (0..size).map(|i| self.points[i % n]).collect();
            let all = factor.solve(rhs);
            return Some(all[n..2 * n].to_vec());
        }
        // Open: the whole band, then the ends moved to the right-hand side.
        let w = ORDER + 1;
        let full = self.band(n, mu);
        let m = n - 2;
        let mut band = vec![0.0; m * w];
        for i in 0..m {
            for d in 0..w.min(i + 1) {
                band[i * w + d] = full[(i + 1) * w + d];
            }
        }
        let factor = Cholesky::new(band, m)?;
        let at = |i: usize, j: usize| {
            let (hi, lo) = if i >= j { (i, j) } else { (j, i) };
            if hi - lo < w { full[hi * w + hi - lo] } else { 0.0 }
        };
        let (first, last) = (self.points[0], self.points[n - 1]);
        let rhs = (1..n - 1).map(|i| self.points[i] - at(i, 0) * first - at(i, n - 1) * last).collect();
        let mut out = Vec::with_capacity(n);
        out.push(first);
        out.extend(factor.solve(rhs));
        out.push(last);
        Some(out)
    }

    fn fit(&self, mu: f64) -> Option<Fit> {
        let points = self.solve(mu)?;
        let rss = points.iter().zip(self.points).map(|(s, d)| s.distance_squared(*d)).sum();
        Some(Fit { points, rss })
    }

    /// `tr H` over the free points.
    fn trace(&self, mu: f64) -> Option<f64> {
        let m = self.free;
        if self.closed || m > EXACT_TRACE_UP_TO {
            // Periodic eigenvalues (exact for a closed curve's circulant system).
            let period = if self.closed { m as f64 } else { 2.0 * (m + 1) as f64 };
            let count = if self.closed { 0..m } else { 1..m + 1 };
            let p = 2 * ORDER as i32;
            return Some(
                count
                    .map(|k| 1.0 / (1.0 + mu * (2.0 * (std::f64::consts::PI * k as f64 / period).sin()).powi(p)))
                    .sum(),
            );
        }
        let w = ORDER + 1;
        let n = self.points.len();
        let full = self.band(n, mu);
        let mut band = vec![0.0; m * w];
        for i in 0..m {
            for d in 0..w.min(i + 1) {
                band[i * w + d] = full[(i + 1) * w + d];
            }
        }
        let factor = Cholesky::new(band, m)?;
        Some((0..m).map(|i| factor.inverse_diagonal(i)).sum())
    }

    /// GCV over μ ([`gcv_search`]).
    fn gcv(&self) -> Option<f64> {
        let m = self.free as f64;
        // From no smoothing to a length scale of the whole curve (μ^{1/2p} points).
        let top = 2.0 * ORDER as f64 * (self.points.len() as f64).log10() + 1.0;
        gcv_search(top, |log_mu| {
            let mu = 10f64.powf(log_mu);
            match (self.fit(mu), self.trace(mu)) {
                (Some(fit), Some(tr)) if m - tr > 1e-9 => m * fit.rss / (m - tr).powi(2),
                _ => f64::INFINITY,
            }
        })
    }
}

/// The μ minimising a GCV `score` of `log10 μ` between 10⁻² and 10^`top`: a scan of
/// [`PER_DECADE`] values a decade, then golden-section search on log μ around the best.
pub(super) fn gcv_search(top: f64, score: impl Fn(f64) -> f64) -> Option<f64> {
    let (lo, hi) = (-2.0, top);
    let steps = ((hi - lo) * PER_DECADE).ceil() as usize;
    let grid: Vec<(f64, f64)> =
        (0..=steps).map(|k| lo + (hi - lo) * k as f64 / steps as f64).map(|x| (x, score(x))).collect();
    let best = (0..grid.len()).min_by(|&a, &b| grid[a].1.total_cmp(&grid[b].1))?;
    if !grid[best].1.is_finite() {
        return None;
    }
    let (mut a, mut b) = (grid[best.saturating_sub(1)].0, grid[(best + 1).min(grid.len() - 1)].0);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut fc, mut fd) = (score(c), score(d));
    for _ in 0..20 {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = score(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = score(d);
        }
    }
    let x = if fc < fd { c } else { d };
    Some(10f64.powf(if score(x) <= grid[best].1 { x } else { grid[best].0 }))
}

/// The Cholesky factor `L` of a banded symmetric positive definite matrix of half-width
/// [`ORDER`], row i holding `L[i][i − d]` at `d`.
struct Cholesky {
    l: Vec<f64>,
    size: usize,
}

impl Cholesky {
    const W: usize = ORDER + 1;

    /// `None` when the matrix is not positive definite (or not finite).
    fn new(mut l: Vec<f64>, size: usize) -> Option<Self> {
        let w = Self::W;
        for i in 0..size {
            for d in (0..w.min(i + 1)).rev() {
                let j = i - d;
                let mut s = l[i * w + d];
                // Σ over k < j within both rows' bands: L[i][k] L[j][k].
                for k in i.saturating_sub(w - 1)..j {
                    s -= l[i * w + (i - k)] * l[j * w + (j - k)];
                }
                if d == 0 {
                    if s.is_nan() || s <= 0.0 {
                        return None;
                    }
                    l[i * w] = s.sqrt();
                } else {
                    l[i * w + d] = s / l[j * w];
                }
            }
        }
        Some(Cholesky { l, size })
    }

    fn solve(&self, mut x: Vec<DVec3>) -> Vec<DVec3> {
        let (w, l) = (Self::W, &self.l);
        for i in 0..self.size {
            let mut s = x[i];
            for k in i.saturating_sub(w - 1)..i {
                s -= l[i * w + (i - k)] * x[k];
            }
            x[i] = s / l[i * w];
        }
        for i in (0..self.size).rev() {
            let mut s = x[i];
            for k in i + 1..(i + w).min(self.size) {
                s -= l[k * w + (k - i)] * x[k];
            }
            x[i] = s / l[i * w];
        }
        x
    }

    /// `(A⁻¹)_ii`: `|L⁻¹ e_i|²` summed from row i down, the forward solve of `e_i`.
    fn inverse_diagonal(&self, i: usize) -> f64 {
        let (w, l) = (Self::W, &self.l);
        // (A⁻¹)_ii = e_iᵀ L⁻ᵀ L⁻¹ e_i = |y|² with y = L⁻¹ e_i, which is zero above row i.
        let mut y = vec![0.0; self.size - i];
        let mut total = 0.0;
        for r in i..self.size {
            let mut s = if r == i { 1.0 } else { 0.0 };
            for k in r.saturating_sub(w - 1).max(i)..r {
                s -= l[r * w + (r - k)] * y[k - i];
            }
            let v = s / l[r * w];
            y[r - i] = v;
            total += v * v;
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic white noise in (−1, 1): a splitmix64 hash of the point and the stream.
    fn wobble(i: usize, k: u32) -> f64 {
        let mut z = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ u64::from(k).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }

    #[test]
    fn a_noisy_circle_is_pre_fitted_by_its_circle_in_order() {
        let (n, r, c) = (40, 2.5, DVec3::new(1.0, -2.0, 0.0));
        let points: Vec<DVec3> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                c + DVec3::new(a.cos(), a.sin(), 0.0) * (r + 0.02 * wobble(i, 1))
                    + DVec3::new(0.01, 0.0, 0.0) * wobble(i, 2)
            })
            .collect();
        let fit = prefit_planar(&points, true, DVec3::Z, None, None);
        let PrefitModel::Circle { radius } = fit.model else { panic!("not a circle: {:?}", fit.model) };
        assert!((radius - r).abs() < 0.01, "{radius}");
        for (i, p) in fit.points.iter().enumerate() {
            assert!(((*p - c).length() - radius).abs() < 0.01, "point {i} on the circle");
            // In order around it, as the input ran: each next point a little further round.
            let q = fit.points[(i + 1) % n];
            assert!((*p - c).cross(q - c).z > 0.0, "point {i} then {}", (i + 1) % n);
        }
    }

    #[test]
    fn an_s_curve_is_not_forced_onto_one_segment() {
        // Two arcs turning opposite ways: no single log-aesthetic segment explains them, and the
        // smoother's points stay (the model pre-fit is only taken where the data allow it).
        let n = 60;
        let points: Vec<DVec3> = (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                DVec3::new(4.0 * t, (std::f64::consts::TAU * t).sin() + 0.002 * wobble(i, 3), 0.0)
            })
            .collect();
        let fit = prefit_planar(&points, false, DVec3::Z, None, None);
        assert_eq!(fit.model, PrefitModel::Smoothed);
        assert_eq!(fit, prefit(&points, false, None));
        // Given a smoothing, the smoother is what was asked for.
        assert_eq!(prefit_planar(&points, false, DVec3::Z, Some(1.0), Some(3.0)).model, PrefitModel::Smoothed);
    }

    #[test]
    fn banded_cholesky_matches_a_dense_solve() {
        // A = I + μ ΔᵀΔ on 9 points against Gaussian elimination on the dense matrix.
        let points: Vec<DVec3> = (0..9).map(|i| DVec3::new(i as f64, ((i * i) % 7) as f64, 0.0)).collect();
        let problem = Problem::new(&points, true);
        let size = 9;
        let band = problem.band(size, 2.5);
        let w = ORDER + 1;
        let mut dense = vec![vec![0.0; size]; size];
        for i in 0..size {
            for d in 0..w.min(i + 1) {
                dense[i][i - d] = band[i * w + d];
                dense[i - d][i] = band[i * w + d];
            }
        }
        let rhs: Vec<f64> = (0..size).map(|i| (i as f64).sin()).collect();
        let factor = Cholesky::new(band, size).unwrap();
        let x = factor.solve(rhs.iter().map(|v| DVec3::new(*v, 0.0, 0.0)).collect());
        for i in 0..size {
            let ax: f64 = (0..size).map(|j| dense[i][j] * x[j].x).sum();
            assert!((ax - rhs[i]).abs() < 1e-10, "row {i}: {ax} against {}", rhs[i]);
        }
        // The inverse's diagonal: solve for e_i.
        for i in 0..size {
            let e: Vec<DVec3> = (0..size).map(|j| DVec3::new(if j == i { 1.0 } else { 0.0 }, 0.0, 0.0)).collect();
            let col = factor.solve(e);
            assert!((col[i].x - factor.inverse_diagonal(i)).abs() < 1e-12);
        }
    }

    #[test]
    fn quadratics_are_kept_and_noise_is_estimated() {
        // The penalty's null space holds every quadratic: a parabola comes back as it was.
        let parabola: Vec<DVec3> = (0..30).map(|i| DVec3::new(i as f64, 0.01 * (i * i) as f64, 0.0)).collect();
        let fit = prefit(&parabola, false, Some(1e4));
        let moved = fit.points.iter().zip(&parabola).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(moved < 1e-9, "{moved}");
        // Alternating noise of 0.1 on a parabola: GCV smooths it out and reads about 0.1.
        let noisy: Vec<DVec3> = parabola
            .iter()
            .enumerate()
            .map(|(i, p)| if i == 0 || i == 29 { *p } else { *p + DVec3::Y * if i % 2 == 0 { 0.1 } else { -0.1 } })
            .collect();
        let fit = prefit(&noisy, false, None);
        let error = fit.points.iter().zip(&parabola).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(error < 0.03, "{error} (μ {})", fit.smoothing);
        assert!((fit.noise - 0.1).abs() < 0.03, "noise {}", fit.noise);
    }
}
