//! One log-aesthetic segment fitted to a whole planar curve through its end points: α, the
//! total turning and the log ratio of the end radii chosen so the segment passes as close to the
//! points as it can (least squares in position), the similarity that puts the segment's chord
//! on the points' fixed by the two end points.
//!
//! This is the robust way to read α from noisy points: it compares positions, where the
//! paper's logarithmic curvature graph compares curvature and its derivative (second and third
//! derivatives of the points, which noise of half a percent of the length swamps: a spiral read
//! that way splits into seven pieces of α between −4 and −1). A position fit averages the noise
//! over every point. [`super::estimate`] uses it first: when the segment's RMS distance is no
//! larger than [`NOISE_FACTOR`] times what a least-squares spline with many more degrees of
//! freedom leaves (the noise level), the curve is one segment and its α is the fit's.
//!
//! The minimisation is a profile over α (Nelder–Mead over turning and log ratio for each α of a
//! grid), then Nelder–Mead over all three from the grid's best, with turning and ratio started
//! from the caller's; it is deterministic (no randomness, no threads). Weak spots: a curve whose curvature hardly changes (a circular arc)
//! fits every α nearly equally well; the end points are taken as exact.

use super::segment::{AestheticSegment, MAX_LOG_RADIUS_RATIO};
use crate::DVec3;

/// A single segment is accepted when its RMS distance to the points is at most this many times
/// the noise level (the RMS distance of the dense least-squares spline).
pub const NOISE_FACTOR: f64 = 1.3;

/// Most points a fit measures (longer inputs are averaged in runs).
const MAX_FITTED: usize = 200;

/// The grid of α the profile search scans (ends and steps).
const PROFILE_ALPHAS: (f64, f64) = (-3.0, 5.0);
const PROFILE_STEPS: usize = 8;

/// Samples of the model segment the points are measured against.
const MODEL_SAMPLES: usize = 120;

/// The best single segment: its α, turning, log radius ratio and RMS distance to the points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentFit {
    pub alpha: f64,
    pub turning: f64,
    pub log_ratio: f64,
    pub rms: f64,
}

/// Points in the plane of the curve, the first at the origin and the last on +x, so the
/// model's chord maps onto them by a scale alone (and a mirror when the curve turns clockwise).
struct Frame {
    points: Vec<(f64, f64)>,
    chord: f64,
}

impl Frame {
    fn new(points: &[DVec3], normal: DVec3) -> Option<Self> {
        let (first, last) = (*points.first()?, *points.last()?);
        let chord = last - first;
        let length = chord.length();
        if length.is_nan() || length <= 0.0 || !normal.is_finite() {
            return None;
        }
        let e1 = chord / length;
        let e2 = normal.normalize().cross(e1);
        let points = points.iter().map(|p| ((*p - first).dot(e1), (*p - first).dot(e2))).collect();
        Some(Frame { points, chord: length })
    }
}

/// The model segment with these parameters in the frame's coordinates (its chord on the
/// points'), mirrored when `clockwise`, as `samples` points evenly spaced in arc length; `None`
/// where no such segment exists.
fn model(
    frame: &Frame,
    alpha: f64,
    turning: f64,
    log_ratio: f64,
    clockwise: bool,
    samples: usize,
) -> Option<Vec<(f64, f64)>> {
    let fractions: Vec<f64> = (0..samples.max(2)).map(|i| i as f64 / (samples.max(2) - 1) as f64).collect();
    model_at(frame, alpha, turning, log_ratio, clockwise, &fractions)
}

/// The model segment's points at these fractions of its length (the last fraction 1), in the
/// frame's coordinates as [`model`].
fn model_at(
    frame: &Frame,
    alpha: f64,
    turning: f64,
    log_ratio: f64,
    clockwise: bool,
    fractions: &[f64],
) -> Option<Vec<(f64, f64)>> {
    if !(turning > 0.0 && log_ratio.abs() < MAX_LOG_RADIUS_RATIO && (-6.0..=8.0).contains(&alpha)) {
        return None;
    }
    let segment = AestheticSegment::in_standard_position(alpha, turning, log_ratio, 1.0)?;
    let samples = segment.points_at_fractions(fractions);
    let end = segment.point_at(segment.length());
    let (ex, ey) = (end.x, end.y);
    let norm = ex * ex + ey * ey;
    if norm.is_nan() || norm <= 0.0 || !norm.is_finite() {
        return None;
    }
    // Complex multiplication by chord / end maps the model's end onto (chord, 0).
    let (a, b) = (frame.chord * ex / norm, -frame.chord * ey / norm);
    let sign = if clockwise { -1.0 } else { 1.0 };
    Some(samples.iter().map(|p| (a * p.x - b * p.y, sign * (a * p.y + b * p.x))).collect())
}

/// For each of the frame's points (in order along the curve), the nearest point of the model
/// polyline, searched near the point's share of the way, and its squared distance.
fn feet(frame: &Frame, model: &[(f64, f64)]) -> Vec<((f64, f64), f64)> {
    let n = frame.points.len();
    let m = model.len();
    let reach = (m / 4).max(8);
    frame
        .points
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| {
            let guess = i * (m - 1) / (n - 1).max(1);
            let (lo, hi) = (guess.saturating_sub(reach), (guess + reach).min(m - 1));
            let mut best = ((x, y), f64::INFINITY);
            for k in lo..hi {
                let ((ax, ay), (bx, by)) = (model[k], model[k + 1]);
                let (dx, dy) = (bx - ax, by - ay);
                let len2 = dx * dx + dy * dy;
                let t = if len2 > 0.0 { (((x - ax) * dx + (y - ay) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
                let foot = (ax + t * dx, ay + t * dy);
                let d2 = (foot.0 - x).powi(2) + (foot.1 - y).powi(2);
                if d2 < best.1 {
                    best = (foot, d2);
                }
            }
            best
        })
        .collect()
}

/// The RMS distance from the points (in order along the curve) to the model with these
/// parameters, mirrored when `clockwise`; `None` where no such segment exists.
fn distance(frame: &Frame, alpha: f64, turning: f64, log_ratio: f64, clockwise: bool) -> Option<f64> {
    let model = model(frame, alpha, turning, log_ratio, clockwise, MODEL_SAMPLES)?;
    let sum: f64 = feet(frame, &model).iter().map(|f| f.1).sum();
    let rms = (sum / frame.points.len() as f64).sqrt();
    rms.is_finite().then_some(rms)
}

/// The points of the fitted segment (`fit` from [`fit_segment`] on `points` and `normal`) at the
/// given fractions of its length, placed as the fit placed it on the points.
pub fn points_on(points: &[DVec3], normal: DVec3, fit: &SegmentFit, fractions: &[f64]) -> Option<Vec<DVec3>> {
    let frame = Frame::new(points, normal)?;
    let clockwise = fit.turning < 0.0;
    let model = model_at(&frame, fit.alpha, fit.turning.abs(), fit.log_ratio, clockwise, fractions)?;
    let (first, last) = (points[0], points[points.len() - 1]);
    let e1 = (last - first) / frame.chord;
    let e2 = normal.normalize().cross(e1);
    Some(model.into_iter().map(|(x, y)| first + x * e1 + y * e2).collect())
}

/// At most [`MAX_FITTED`] points: longer inputs averaged in runs of consecutive points (the ends
/// kept), so every point's information counts (picking every fifth point of 1,000 once left α as
/// uncertain as 200 points leave it) at the cost of 200.
pub(super) fn averaged_runs(points: &[DVec3]) -> Vec<DVec3> {
    if points.len() <= MAX_FITTED {
        return points.to_vec();
    }
    let inner = &points[1..points.len() - 1];
    let runs = MAX_FITTED - 2;
    let mut out = vec![points[0]];
    out.extend((0..runs).map(|k| {
        let run = &inner[k * inner.len() / runs..(k + 1) * inner.len() / runs];
        run.iter().copied().sum::<DVec3>() / run.len().max(1) as f64
    }));
    out.push(points[points.len() - 1]);
    out
}

/// Nelder–Mead on `f` from `start` with initial steps `step`; at most `iterations` steps.
pub(super) fn nelder_mead<const N: usize>(
    f: impl Fn([f64; N]) -> f64,
    start: [f64; N],
    step: [f64; N],
    iterations: usize,
) -> ([f64; N], f64) {
    let mut simplex: Vec<([f64; N], f64)> = (0..=N)
        .map(|k| {
            let mut p = start;
            if k > 0 {
                p[k - 1] += step[k - 1];
            }
            (p, f(p))
        })
        .collect();
    let combine = |a: [f64; N], b: [f64; N], t: f64| std::array::from_fn(|i| a[i] + t * (b[i] - a[i]));
    for _ in 0..iterations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let centroid: [f64; N] = std::array::from_fn(|i| simplex[..N].iter().map(|s| s.0[i]).sum::<f64>() / N as f64);
        let worst = simplex[N];
        let reflected = combine(centroid, worst.0, -1.0);
        let fr = f(reflected);
        if fr < simplex[0].1 {
            let expanded = combine(centroid, worst.0, -2.0);
            let fe = f(expanded);
            simplex[N] = if fe < fr { (expanded, fe) } else { (reflected, fr) };
        } else if fr < simplex[N - 1].1 {
            simplex[N] = (reflected, fr);
        } else {
            let contracted = combine(centroid, worst.0, 0.5);
            let fc = f(contracted);
            if fc < worst.1 {
                simplex[N] = (contracted, fc);
            } else {
                let best = simplex[0].0;
                for s in &mut simplex[1..] {
                    s.0 = combine(best, s.0, 0.5);
                    s.1 = f(s.0);
                }
            }
        }
        let spread = simplex.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max) - simplex[0].1;
        if spread.abs() < 1e-14 * (1.0 + simplex[0].1.abs()) {
            break;
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0]
}

/// The single log-aesthetic segment closest to `points` (planar, about `normal`) through their
/// end points, from a start `turning` (signed: negative turns clockwise) and `log_ratio`
/// (ln of end radius over start radius) read off a smooth fit; with `alpha` given, only the
/// segments of that α are searched. `None` when no segment fits.
pub fn fit_segment(
    points: &[DVec3],
    normal: DVec3,
    turning: f64,
    log_ratio: f64,
    alpha: Option<f64>,
) -> Option<SegmentFit> {
    let picked = averaged_runs(points);
    let frame = Frame::new(&picked, normal)?;
    let clockwise = turning < 0.0;
    let cost = |p: [f64; 3]| distance(&frame, p[0], p[1], p[2], clockwise).unwrap_or(f64::INFINITY);
    let turn = turning.abs().max(1e-3);
    let ratio = log_ratio.clamp(-20.0, 20.0);
    // The profile over α: for each α of a grid, the best turning and ratio (a 2-D search from the
    // spline's), so a search in all three cannot settle in a valley of the wrong α; then all
    // three are polished from the grid's best.
    let mut best: Option<([f64; 3], f64)> = None;
    let grid: Vec<f64> = match alpha {
        Some(a) => vec![a],
        None => (0..=PROFILE_STEPS)
            .map(|k| PROFILE_ALPHAS.0 + (PROFILE_ALPHAS.1 - PROFILE_ALPHAS.0) * k as f64 / PROFILE_STEPS as f64)
            .collect(),
    };
    for alpha in grid {
        let at = |q: [f64; 3]| cost([alpha, q[1], q[2]]);
        if !at([alpha, turn, ratio]).is_finite() {
            continue;
        }
        let found = nelder_mead(at, [alpha, turn, ratio], [0.0, 0.1 * turn, 0.2], 80);
        let found = ([alpha, found.0[1], found.0[2]], found.1);
        if best.is_none_or(|b| found.1 < b.1) {
            best = Some(found);
        }
    }
    let (start, _) = best.filter(|b| b.1.is_finite())?;
    let polished = match alpha {
        Some(a) => {
            let at = |q: [f64; 3]| cost([a, q[1], q[2]]);
            let (q, rms) = nelder_mead(at, start, [0.0, 0.05 * turn, 0.1], 300);
            ([a, q[1], q[2]], rms)
        }
        None => nelder_mead(cost, start, [0.25, 0.05 * turn, 0.1], 300),
    };
    let (p, rms) = Some(polished).filter(|b| b.1.is_finite())?;
    // The RMS distance of every point, not of the averages (which the averaging made smaller).
    let rms = if picked.len() == points.len() {
        rms
    } else {
        distance(&Frame::new(points, normal)?, p[0], p[1], p[2], clockwise).filter(|r| r.is_finite())?
    };
    Some(SegmentFit { alpha: p[0], turning: if clockwise { -p[1] } else { p[1] }, log_ratio: p[2], rms })
}

/// [`fit_segment`] started from the turning and the end curvatures of `smooth`, the points
/// smoothed (the GCV pre-fit), read from its polyline's angles: a least-squares spline with a
/// fifth as many controls as points follows the noise on a few hundred points, and its
/// curvature's wiggles once turned a spiral's half turn counter-clockwise into −2.6 radians, so
/// the search began mirrored and found nothing. `None` when the curve does not turn.
pub fn fit_smoothed(points: &[DVec3], smooth: &[DVec3], normal: DVec3, alpha: Option<f64>) -> Option<SegmentFit> {
    // Signed turning of each polyline corner about the normal, and the length around it.
    let mut angles = Vec::with_capacity(smooth.len());
    let mut lengths = Vec::with_capacity(smooth.len());
    for w in smooth.windows(3) {
        let (a, b) = (w[1] - w[0], w[2] - w[1]);
        angles.push(a.cross(b).dot(normal).atan2(a.dot(b)));
        lengths.push(0.5 * (a.length() + b.length()));
    }
    let turning: f64 = angles.iter().sum();
    if turning.is_nan() || turning.abs() <= 1e-6 || angles.len() < 5 {
        return None;
    }
    // Mean curvature over the first and last fifth: turning over length there.
    let fifth = (angles.len() / 5).max(1);
    let curvature = |range: std::ops::Range<usize>| {
        let (turn, length) = range.fold((0.0, 0.0), |(t, l), k| (t + angles[k], l + lengths[k]));
        (turn / length.max(f64::MIN_POSITIVE)).abs()
    };
    let (start, end) = (curvature(0..fifth), curvature(angles.len() - fifth..angles.len()));
    let log_ratio = if start > 0.0 && end > 0.0 { (start / end).ln() } else { 0.0 };
    fit_segment(points, normal, turning, log_ratio, alpha)
}
