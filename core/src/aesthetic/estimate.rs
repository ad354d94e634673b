//! Estimating α from the points (paper sec. 3.3–3.5, fig. 1).
//!
//! First, departing from the paper: a planar open curve is fitted as a whole by one
//! log-aesthetic segment through its end points ([`super::segment_fit`], a least-squares fit
//! in position). When that segment is as close to the points as the noise lets a smooth spline
//! be (RMS distance at most [`super::segment_fit::NOISE_FACTOR`] times the spline's), the curve
//! is one piece and its α is the segment's: the criterion for splitting is that one segment
//! cannot explain the points. The paper's graph reads α from curvature and its derivative, a
//! third derivative of the points, which half a percent of noise swamps (a noisy spiral came
//! out as seven pieces of α between −4 and −1; now one piece, with an error at the Cramér–Rao
//! bound of the data: about 0.6 on 60 points at that noise, 0.3 on 200, 0.15 on 1,000; see
//! `docs/log-aesthetic.md`). Otherwise, the paper's way:
//!
//! 1. Fit a cubic B-spline to the points by least squares ([`crate::curve::BSpline::fit`]) on
//!    normalised chord-length parameters, with few control points so its curvature does not
//!    wiggle.
//! 2. Split it where the curvature changes sign (inflections) and where its arc-length derivative
//!    does (curvature extrema): each piece has monotone curvature of one sign, as a log-aesthetic
//!    segment does. (The paper converts each piece to Bézier segments to evaluate it; we evaluate
//!    the B-spline and its exact derivatives directly, which is the same curve.)
//! 3. Sample each piece's logarithmic curvature graph from the spline's exact derivatives,
//!    `x = −log|κ|`, `y = log(|κ| / |dκ/ds|)`, and fit a line: its slope is α for the piece, its
//!    RMS distance the residual. κ comes from the spline's exact derivatives; dκ/ds is the
//!    difference of κ over one knot span on either side, because the exact one jumps at every
//!    knot (it involves the piecewise constant third derivative) and on a curve that turns much
//!    per span the jumps flip its sign, splitting the curve at every knot.
//!
//! Where it is weak: the spline is a polynomial, and its curvature derivative (a third
//! derivative) carries the fit's error amplified, so α is only as good as the fit: on exact
//! samples of a log-aesthetic curve α comes back within a few hundredths (see the tests), on
//! noisy points it is rough. Near the ends of a piece `dκ/ds → 0` or `κ → 0` and the graph runs
//! off to infinity, so the first and last [`EstimateSettings::trim`] of every piece are left out
//! of the fit; pieces shorter than [`EstimateSettings::min_piece`] of the length (spline wiggles)
//! and pieces whose curvature changes by less than [`MIN_CURVATURE_RATIO`] (nearly circular arcs,
//! on which every α fits) are not fitted, and their points take the α of the nearest fitted piece.

use super::law::fit_line;
use crate::curve::{BSpline, PointSequence};
use crate::{DVec3, Error, Result};

/// Pieces whose curvature changes by less than this factor are not fitted: they are nearly
/// circular arcs, on which any α fits.
pub const MIN_CURVATURE_RATIO: f64 = 1.1;

/// Settings of α estimation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimateSettings {
    /// Control points of the least-squares cubic B-spline; `None`: a fifth of the points, between
    /// 4 and 24.
    pub controls: Option<usize>,
    /// Samples of the spline per control point, for splitting and for the graphs.
    pub samples_per_control: usize,
    /// Fraction of each piece's samples left out of its line fit at either end.
    pub trim: f64,
    /// Pieces shorter than this fraction of the curve's length are not fitted.
    pub min_piece: f64,
}

impl Default for EstimateSettings {
    fn default() -> Self {
        EstimateSettings { controls: None, samples_per_control: 64, trim: 0.1, min_piece: 0.05 }
    }
}

/// One piece of monotone curvature and its α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaPiece {
    /// Spline parameter range (normalised chord length of the points, 0 to 1).
    pub start: f64,
    /// End of the parameter range.
    pub end: f64,
    /// Slope of the piece's logarithmic curvature graph.
    pub alpha: f64,
    /// RMS distance of the graph from its line.
    pub residual: f64,
    /// Graph samples fitted.
    pub samples: usize,
    /// True where the curvature grows along the piece.
    pub increasing: bool,
}

/// The estimate: the fitted spline and its pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct AlphaEstimate {
    /// The least-squares spline the curvature was read from.
    pub spline: BSpline,
    /// Parameter of every input point on the spline.
    pub parameters: Vec<f64>,
    /// The fitted pieces in order along the curve.
    pub pieces: Vec<AlphaPiece>,
}

impl AlphaEstimate {
    /// α for every input point: that of the piece its parameter falls in, or of the nearest
    /// piece.
    pub fn per_point(&self) -> Vec<f64> {
        self.parameters
            .iter()
            .map(|&t| {
                let distance = |p: &AlphaPiece| if t < p.start { p.start - t } else { (t - p.end).max(0.0) };
                self.pieces.iter().min_by(|a, b| distance(a).total_cmp(&distance(b))).map_or(0.0, |p| p.alpha)
            })
            .collect()
    }
}

/// Curvature (signed about `normal` when given, else unsigned) and its arc-length derivative on
/// the spline at `t`.
fn curvature_and_derivative(d: &[BSpline; 3], t: f64, normal: Option<DVec3>) -> (f64, f64) {
    let (c1, c2, c3) = (d[0].point(t), d[1].point(t), d[2].point(t));
    let speed = c1.length();
    let (b, db) = (c1.cross(c2), c1.cross(c3));
    let (k, dk_num) = match normal {
        Some(n) => (b.dot(n), db.dot(n)),
        None => {
            let len = b.length();
            (len, if len > 0.0 { b.dot(db) / len } else { 0.0 })
        }
    };
    let kappa = k / speed.powi(3);
    let dkappa_dt = dk_num / speed.powi(3) - 3.0 * kappa * c1.dot(c2) / (speed * speed);
    (kappa, dkappa_dt / speed)
}

/// The whole curve as one log-aesthetic segment, when one fits the points as closely as the
/// noise lets a smooth spline: `None` otherwise (or when the curve does not turn). A plane curve
/// (with its plane's `normal`) is fitted by a plane segment ([`super::segment_fit`]), a space
/// curve by a space segment, curvature and torsion laws with β = 1 ([`super::space_fit`]); the
/// search starts from the GCV pre-fit's points. Only the distance to the model counts here (α is
/// what is read, not where points go on it).
fn single_segment(points: &[DVec3], parameters: &[f64], spline: &BSpline, normal: Option<DVec3>) -> Option<AlphaPiece> {
    let smooth = super::prefit::prefit(points, false, None).points;
    let noise = (points.iter().zip(parameters).map(|(p, &t)| p.distance_squared(spline.point(t))).sum::<f64>()
        / points.len() as f64)
        .sqrt();
    let (alpha, log_ratio, rms) = match normal {
        Some(normal) => {
            let fit = super::segment_fit::fit_smoothed(points, &smooth, normal, None)?;
            (fit.alpha, fit.log_ratio, fit.rms)
        }
        None => {
            let fit = super::space_fit::fit_space_smoothed(points, &smooth, None)?;
            (fit.alpha, fit.log_ratio, fit.rms)
        }
    };
    // A segment whose curvature hardly changes is a circular arc (or a helix), which every α fits
    // equally: there is no α to read (the paper's graph below says so, as it does for such pieces).
    if log_ratio.abs() < MIN_CURVATURE_RATIO.ln() {
        return None;
    }
    let chord = points[0].distance(points[points.len() - 1]);
    (rms <= super::segment_fit::NOISE_FACTOR * noise + 1e-9 * chord).then_some(AlphaPiece {
        start: 0.0,
        end: 1.0,
        alpha,
        residual: rms,
        samples: points.len(),
        increasing: log_ratio < 0.0,
    })
}

/// Estimates α per piece of monotone curvature (see the module documentation). With the normal
/// of a planar curve's plane the curvature is signed, so inflections split pieces; without it
/// (space curves) it is unsigned.
pub fn estimate_alpha(
    curve: &PointSequence,
    plane_normal: Option<DVec3>,
    settings: &EstimateSettings,
) -> Result<AlphaEstimate> {
    let normal = plane_normal;
    curve.validate(5)?;
    let mut points = curve.points.clone();
    if curve.closed {
        points.push(points[0]);
    }
    let n = points.len();
    let controls = settings.controls.unwrap_or((n / 5).clamp(4, 24));
    if controls < 4 || controls > n {
        return Err(Error::Input(format!(
            "α estimation fits a cubic B-spline with 4 to {n} control points for {n} points, not {controls}"
        )));
    }
    if !(settings.trim >= 0.0 && settings.trim < 0.5 && settings.min_piece >= 0.0 && settings.min_piece < 1.0) {
        return Err(Error::Input("α estimation: trim must lie in [0, 0.5) and min_piece in [0, 1)".into()));
    }
    let arc = crate::curve::sequence::arc_lengths(&points);
    let total = arc[n - 1];
    let parameters: Vec<f64> = arc.iter().map(|s| s / total).collect();
    let spline = BSpline::fit(&points, &parameters, 3, controls)?;
    let d1 = spline.derivative().expect("cubic");
    let d2 = d1.derivative().expect("quadratic");
    let d3 = d2.derivative().expect("linear");
    let derivatives = [d1, d2, d3];

    // An open curve that one segment (plane or space) fits to the noise level is one piece, its
    // α the segment's (see [`super::segment_fit`] and [`super::space_fit`]).
    if !curve.closed
        && let Some(piece) = single_segment(&points, &parameters, &spline, normal)
    {
        return Ok(AlphaEstimate { spline, parameters, pieces: vec![piece] });
    }

    // Dense samples of curvature, its derivative and arc length.
    let count = (controls * settings.samples_per_control.max(4)).max(64);
    let ts: Vec<f64> = (0..=count).map(|k| k as f64 / count as f64).collect();
    let exact: Vec<(f64, f64)> = ts.iter().map(|&t| curvature_and_derivative(&derivatives, t, normal)).collect();
    let mut length = vec![0.0; ts.len()];
    for k in 1..ts.len() {
        length[k] = length[k - 1] + spline.point(ts[k]).distance(spline.point(ts[k - 1]));
    }
    let spline_length = length[count];
    // dκ/ds of a cubic spline jumps at every knot (it involves the third derivative, piecewise
    // constant), and on a curve that turns a lot per knot span the jumps flip its sign at the
    // knots. Differencing κ over one knot span either side averages the jumps out.
    let span = settings.samples_per_control.max(4);
    let values: Vec<(f64, f64)> = (0..ts.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(span), (k + span).min(count));
            let ds = length[b] - length[a];
            let derivative = if ds > 0.0 { (exact[b].0 - exact[a].0) / ds } else { exact[k].1 };
            (exact[k].0, derivative)
        })
        .collect();

    // Runs of constant sign of κ and of dκ/ds.
    let sign = |v: f64| {
        if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    };
    let mut pieces = Vec::new();
    let mut first = 0;
    for k in 1..=ts.len() {
        let ends =
            k == ts.len() || sign(values[k].0) != sign(values[first].0) || sign(values[k].1) != sign(values[first].1);
        if !ends {
            continue;
        }
        let last = k - 1;
        if length[last] - length[first] >= settings.min_piece * spline_length && last > first {
            let span = last - first;
            let cut = ((span as f64) * settings.trim).round() as usize;
            let (x, y): (Vec<f64>, Vec<f64>) = (first + cut..=last - cut)
                .filter_map(|j| {
                    let (k, dk) = values[j];
                    let (x, y) = (-k.abs().ln(), (k.abs() / dk.abs()).ln());
                    (x.is_finite() && y.is_finite()).then_some((x, y))
                })
                .unzip();
            // x = −log|κ|: a piece whose curvature varies by less than MIN_CURVATURE_RATIO is
            // nearly a circular arc, whose LCG is a vertical smear with no meaningful slope.
            let (x_lo, x_hi) = x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
            let varies = x_hi - x_lo >= MIN_CURVATURE_RATIO.ln();
            if let Some(fit) = fit_line(&x, &y).filter(|_| varies) {
                pieces.push(AlphaPiece {
                    start: ts[first],
                    end: ts[last],
                    alpha: fit.slope,
                    residual: fit.residual,
                    samples: fit.count,
                    increasing: values[first].0.abs() < values[last].0.abs(),
                });
            }
        }
        first = k;
    }
    if pieces.is_empty() {
        return Err(Error::Input(
            "no piece of the curve has a curvature that changes enough, monotonically and over long enough, to \
             read α from (a circle or a straight line has no α); give α instead"
                .into(),
        ));
    }
    if curve.closed {
        // The duplicated first point is not an input point.
        let mut parameters = parameters;
        parameters.pop();
        return Ok(AlphaEstimate { spline, parameters, pieces });
    }
    Ok(AlphaEstimate { spline, parameters, pieces })
}
