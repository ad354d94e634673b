//! One log-aesthetic space segment fitted to a whole open space curve through its end points:
//! the space counterpart of [`super::segment_fit`], which α estimation and the shape-keeping
//! pre-fit use first for space curves (a departure from the paper, whose curvature graph reads α
//! from a third derivative of the points; see `docs/log-aesthetic.md`).
//!
//! The model has unit length and starts at the origin heading along x with its principal normal
//! along y. Its radius of curvature follows the law, `ρ^α = c s + d` (`ln ρ = c s + d` for
//! α = 0), from ρ₀ to `e^r ρ₀`, scaled so the tangent turns by `Θ` in all; its radius of torsion
//! follows the law of β = 1 (the filter's default), `μ = g s + h`, from `1/τ₀` to `1/τ₁` (both of
//! one sign). The Frenet–Serret equations are integrated by fourth-order Runge–Kutta to the
//! points' shares of the length. The model's chord is put on the points' by the rotation that
//! takes one onto the other and a scale, and the roll about the chord that brings it nearest the
//! points in the least-squares sense (closed form: the two-dimensional Procrustes angle); the
//! cost is the RMS distance of each point from the model point at its share of the length.
//!
//! The minimisation is a profile over α (Nelder–Mead over Θ, r, τ₀, τ₁ for each α of a grid),
//! then Nelder–Mead over all five from the grid's best; deterministic. Weak spots: the end
//! points are taken as exact; β is fixed at 1; a curve whose torsion changes sign is not a
//! segment of this model (none is found, and the caller falls back to the smoother).

use super::segment_fit::{averaged_runs, nelder_mead};
use crate::DVec3;

/// The grid of α the profile search scans (ends and steps), as for plane curves.
const PROFILE_ALPHAS: (f64, f64) = (-3.0, 5.0);
const PROFILE_STEPS: usize = 8;
/// Runge–Kutta steps between two consecutive samples of the model.
const SUBSTEPS: usize = 4;
/// Samples of the model polyline the points are measured against.
const MODEL_SAMPLES: usize = 120;

/// The best single space segment and its RMS distance to the points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceSegmentFit {
    pub alpha: f64,
    /// Total turning of the tangent, radians.
    pub turning: f64,
    /// ln of the end radius of curvature over the start radius.
    pub log_ratio: f64,
    /// Torsion at the start and at the end, times the length.
    pub torsion: [f64; 2],
    pub rms: f64,
}

/// The model's points at these increasing `fractions` of its length (the first 0), in its own
/// frame; `None` where no such segment exists.
fn model_at(alpha: f64, turning: f64, log_ratio: f64, torsion: [f64; 2], fractions: &[f64]) -> Option<Vec<DVec3>> {
    let [t0, t1] = torsion;
    let same_sign = t0 * t1 > 0.0 || (t0 == 0.0 && t1 == 0.0);
    if !(turning > 0.0 && log_ratio.abs() < 20.0 && (-6.0..=8.0).contains(&alpha) && same_sign) {
        return None;
    }
    if !(t0.abs() < 1e3 && t1.abs() < 1e3) {
        return None;
    }
    // ρ(s)/ρ₀ along the unit length.
    let shape = |s: f64| -> f64 {
        if alpha == 0.0 {
            (log_ratio * s).exp()
        } else {
            (1.0 + ((alpha * log_ratio).exp() - 1.0) * s).powf(1.0 / alpha)
        }
    };
    // κ = Θ (ρ₀/ρ(s)) / ∫ ρ₀/ρ, the integral by Simpson's rule.
    let m = 256;
    let integral: f64 = (0..=m)
        .map(|k| {
            let w = if k == 0 || k == m {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w / shape(k as f64 / m as f64)
        })
        .sum::<f64>()
        / (3.0 * m as f64);
    let scale = turning / integral;
    let kappa = |s: f64| scale / shape(s);
    let tau = |s: f64| if t0 == 0.0 { 0.0 } else { 1.0 / (1.0 / t0 + (1.0 / t1 - 1.0 / t0) * s) };
    type State = [DVec3; 4];
    let derivative = |s: f64, y: &State| -> State {
        let (k, t) = (kappa(s), tau(s));
        [y[1], k * y[2], -k * y[1] + t * y[3], -t * y[2]]
    };
    let add = |y: &State, d: &State, h: f64| -> State { std::array::from_fn(|i| y[i] + h * d[i]) };
    let mut y: State = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let mut s = 0.0;
    let mut out = Vec::with_capacity(fractions.len());
    for &f in fractions {
        let h = (f - s) / SUBSTEPS as f64;
        if h > 0.0 {
            for _ in 0..SUBSTEPS {
                let k1 = derivative(s, &y);
                let k2 = derivative(s + 0.5 * h, &add(&y, &k1, 0.5 * h));
                let k3 = derivative(s + 0.5 * h, &add(&y, &k2, 0.5 * h));
                let k4 = derivative(s + h, &add(&y, &k3, h));
                y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
                s += h;
            }
        }
        out.push(y[0]);
    }
    out.iter().all(|p| p.is_finite()).then_some(out)
}

/// Where the model goes on the points: `first + rotation · p · scale`.
#[derive(Clone, Copy, Debug)]
struct Placement {
    first: DVec3,
    rotation: glam::DQuat,
    scale: f64,
}

impl Placement {
    fn apply(&self, p: DVec3) -> DVec3 {
        self.first + self.rotation * p * self.scale
    }
}

/// The placement of the model's polyline `model` (first at the origin, evenly spaced in arc
/// length) on `points`: chord onto chord, then the roll about it that brings the model's points
/// at the points' `shares` of the length nearest them in the least-squares sense.
fn placement(model: &[DVec3], points: &[DVec3], shares: &[f64]) -> Option<Placement> {
    let (first, last) = (points[0], points[points.len() - 1]);
    let (chord, their) = (last - first, model[model.len() - 1]);
    let (length, their_length) = (chord.length(), their.length());
    if !(length > 0.0 && their_length > 0.0) {
        return None;
    }
    let axis = chord / length;
    let rotation = glam::DQuat::from_rotation_arc(their / their_length, axis);
    let scale = length / their_length;
    let on: Vec<DVec3> = model.iter().map(|p| rotation * *p * scale).collect();
    // The roll about the axis that best matches the points (2-D Procrustes in the plane across).
    let (mut sin, mut cos) = (0.0, 0.0);
    let last_sample = (on.len() - 1) as f64;
    for (&share, p) in shares.iter().zip(points) {
        let x = (share * last_sample).clamp(0.0, last_sample);
        let k = (x as usize).min(on.len() - 2);
        let a = on[k].lerp(on[k + 1], x - k as f64);
        let b = *p - first;
        let (a, b) = (a - a.dot(axis) * axis, b - b.dot(axis) * axis);
        sin += a.cross(b).dot(axis);
        cos += a.dot(b);
    }
    let roll = glam::DQuat::from_axis_angle(axis, sin.atan2(cos));
    Some(Placement { first, rotation: roll * rotation, scale })
}

/// The model's polyline of [`MODEL_SAMPLES`] points with parameters `p`, and its placement on
/// `points`.
fn uniform_model(points: &[DVec3], shares: &[f64], p: [f64; 5]) -> Option<(Vec<DVec3>, Placement)> {
    let fractions: Vec<f64> = (0..MODEL_SAMPLES).map(|k| k as f64 / (MODEL_SAMPLES - 1) as f64).collect();
    let model = model_at(p[0], p[1], p[2], [p[3], p[4]], &fractions)?;
    let placement = placement(&model, points, shares)?;
    Some((model, placement))
}

/// The shares of the length at each point of `smooth` (a polyline), first 0 and last 1.
fn shares(smooth: &[DVec3]) -> Vec<f64> {
    let mut arc = vec![0.0];
    for w in smooth.windows(2) {
        arc.push(arc[arc.len() - 1] + w[0].distance(w[1]));
    }
    let total = arc[arc.len() - 1].max(f64::MIN_POSITIVE);
    arc.into_iter().map(|s| s / total).collect()
}

/// RMS distance of `points` from the model placed on them: from each point to the nearest point
/// of the model's polyline near its share of the way (so noise along the curve does not count,
/// as in the plane fit).
fn rms(points: &[DVec3], shares: &[f64], p: [f64; 5]) -> Option<f64> {
    let (model, placement) = uniform_model(points, shares, p)?;
    let on: Vec<DVec3> = model.iter().map(|q| placement.apply(*q)).collect();
    let m = on.len();
    let reach = (m / 4).max(8);
    let sum: f64 = points
        .iter()
        .zip(shares)
        .map(|(x, &share)| {
            let guess = (share * (m - 1) as f64).round() as usize;
            let (lo, hi) = (guess.saturating_sub(reach), (guess + reach).min(m - 1));
            (lo..hi)
                .map(|k| {
                    let (a, b) = (on[k], on[k + 1]);
                    let d = b - a;
                    let t = if d.length_squared() > 0.0 {
                        ((*x - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    x.distance_squared(a + t * d)
                })
                .fold(f64::INFINITY, f64::min)
        })
        .sum();
    let rms = (sum / points.len() as f64).sqrt();
    rms.is_finite().then_some(rms)
}

/// The single log-aesthetic space segment closest to `points` through their end points, started
/// from what `smooth` (the points smoothed, the GCV pre-fit) turns and twists by; with `alpha`
/// given only segments of that α are searched. `None` when no segment fits (a curve that does
/// not turn, or whose torsion changes sign).
pub fn fit_space_smoothed(points: &[DVec3], smooth: &[DVec3], alpha: Option<f64>) -> Option<SpaceSegmentFit> {
    if points.len() < 5 || points.len() != smooth.len() {
        return None;
    }
    let (picked, picked_smooth) = (averaged_runs(points), averaged_runs(smooth));
    let fractions = shares(&picked_smooth);
    // Turning, end curvatures and torsion read off the smoothed polyline.
    let length: f64 = smooth.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut angles = Vec::new();
    let mut binormals = Vec::new();
    for w in smooth.windows(3) {
        let (a, b) = (w[1] - w[0], w[2] - w[1]);
        angles.push((a.cross(b).length()).atan2(a.dot(b)));
        binormals.push((a.cross(b).normalize_or_zero(), 0.5 * (a.length() + b.length())));
    }
    let turning: f64 = angles.iter().sum();
    if turning.is_nan() || turning <= 1e-6 || angles.len() < 5 {
        return None;
    }
    // In space the angles between consecutive chords have no sign, so noise left by the
    // smoother adds to every one of them: twenty points of a half turn with 1 % noise read
    // 5.6 radians, and the search, started there, settled on a curve of three turns that
    // explained nothing (the pre-fit fell back to the smoother, whose noisy torsion kept the
    // filter cycling to the pass cap). Over chords of an eighth of the points the noise
    // averages out (2.6 radians there), at the cost of the turn near the ends, which such chords
    // cut short; the search starts from both readings and keeps the better fit.
    let coarse = coarse_turning(smooth, 8);
    // Readings within a tenth of each other start the search in the same valley: one search.
    let turnings = if (coarse - turning).abs() > 0.1 * turning { vec![turning, coarse] } else { vec![turning] };
    let fifth = (angles.len() / 5).max(1);
    let curvature = |range: std::ops::Range<usize>| {
        let turn: f64 = angles[range.clone()].iter().sum();
        let len: f64 = binormals[range].iter().map(|b| b.1).sum();
        turn / len.max(f64::MIN_POSITIVE)
    };
    let (k0, k1) = (curvature(0..fifth), curvature(angles.len() - fifth..angles.len()));
    let log_ratio = if k0 > 0.0 && k1 > 0.0 { (k0 / k1).ln() } else { 0.0 };
    // Torsion: the signed turn of the binormal about the tangent, over the length, on each half.
    let twist = |range: std::ops::Range<usize>| {
        let mut turn = 0.0;
        let mut len = 0.0;
        for k in range {
            let (b0, b1) = (binormals[k].0, binormals[k + 1].0);
            let t = smooth[k + 2] - smooth[k + 1];
            turn += b0.cross(b1).dot(t.normalize_or_zero()).atan2(b0.dot(b1));
            len += binormals[k].1;
        }
        turn / len.max(f64::MIN_POSITIVE) * length
    };
    let half = binormals.len() / 2;
    let (tau0, tau1) = (twist(0..half.max(1)), twist(half.min(binormals.len() - 1)..binormals.len() - 1));
    let mean = 0.5 * (tau0 + tau1);
    let start_torsion = if tau0 * tau1 > 0.0 { [tau0, tau1] } else { [mean, mean] };
    let torsion_step = 0.2 * mean.abs().max(0.5);
    let cost = |p: [f64; 5]| rms(&picked, &fractions, p).unwrap_or(f64::INFINITY);
    let grid: Vec<f64> = match alpha {
        Some(a) => vec![a],
        None => (0..=PROFILE_STEPS)
            .map(|k| PROFILE_ALPHAS.0 + (PROFILE_ALPHAS.1 - PROFILE_ALPHAS.0) * k as f64 / PROFILE_STEPS as f64)
            .collect(),
    };
    let mut best: Option<([f64; 5], f64)> = None;
    for a in grid {
        let at = |q: [f64; 4]| cost([a, q[0], q[1], q[2], q[3]]);
        for &turning in &turnings {
            let start = [turning, log_ratio.clamp(-10.0, 10.0), start_torsion[0], start_torsion[1]];
            if !at(start).is_finite() {
                continue;
            }
            let (q, value) = nelder_mead(at, start, [0.1 * turning, 0.2, torsion_step, torsion_step], 200);
            if best.is_none_or(|b| value < b.1) {
                best = Some(([a, q[0], q[1], q[2], q[3]], value));
            }
        }
    }
    let (start, _) = best.filter(|b| b.1.is_finite())?;
    // Polished twice: a restart from the first polish's best takes Nelder–Mead out of a
    // collapsed simplex.
    let polish = |start: [f64; 5]| match alpha {
        Some(a) => {
            let at = |q: [f64; 4]| cost([a, q[0], q[1], q[2], q[3]]);
            let (q, value) = nelder_mead(
                at,
                [start[1], start[2], start[3], start[4]],
                [0.05 * turning, 0.1, torsion_step, torsion_step],
                400,
            );
            ([a, q[0], q[1], q[2], q[3]], value)
        }
        None => nelder_mead(cost, start, [0.25, 0.05 * turning, 0.1, torsion_step, torsion_step], 600),
    };
    let (p, _) = polish(polish(start).0);
    // The RMS distance of every point, not of the run averages.
    let rms = rms(points, &shares(smooth), p)?;
    Some(SpaceSegmentFit { alpha: p[0], turning: p[1], log_ratio: p[2], torsion: [p[3], p[4]], rms })
}

/// The turning of the polyline through every k-th point of `points` (and the last), k chosen so
/// there are about `chords` chords: the sum of the angles between consecutive chords.
fn coarse_turning(points: &[DVec3], chords: usize) -> f64 {
    let n = points.len();
    let stride = (n - 1).div_ceil(chords).max(1);
    let mut at: Vec<usize> = (0..n).step_by(stride).collect();
    if at.last() != Some(&(n - 1)) {
        at.push(n - 1);
    }
    at.windows(3)
        .map(|w| {
            let (a, b) = (points[w[1]] - points[w[0]], points[w[2]] - points[w[1]]);
            a.cross(b).length().atan2(a.dot(b))
        })
        .sum()
}

/// The points of `fit` at the shares of `smooth`'s length when the segment explains `points` to
/// `noise` (RMS): its distance to them ([`SpaceSegmentFit::rms`], measured to the nearest point of
/// the model) within [`super::segment_fit::NOISE_FACTOR`] times the noise, and the RMS distance
/// of each point from the model's point at its share within twice that (it counts the noise along
/// the curve too, which the smoother's level counts at its own points, not at the model's). The
/// second test keeps out a model that passes near every point but not in their order and spacing
/// (a loop or a doubled-back end, which twenty noisy points let the fit find: the points placed on
/// it landed 5 to 24 times as far from the true curve as the input).
pub fn explaining(points: &[DVec3], smooth: &[DVec3], fit: &SpaceSegmentFit, noise: f64) -> Option<Vec<DVec3>> {
    let limit = super::segment_fit::NOISE_FACTOR * noise;
    // Not `fit.rms > limit`: a NaN distance must fail too.
    if fit.rms.partial_cmp(&limit).is_none_or(|o| o == std::cmp::Ordering::Greater) {
        return None;
    }
    let on = space_points_on(points, smooth, fit)?;
    let rms = (on.iter().zip(points).map(|(a, b)| a.distance_squared(*b)).sum::<f64>() / points.len() as f64).sqrt();
    (rms <= 2.0 * limit && on.iter().all(|p| p.is_finite())).then_some(on)
}

/// The points of a fitted segment at the shares of `smooth`'s length, placed on `points` as the
/// fit placed it.
pub fn space_points_on(points: &[DVec3], smooth: &[DVec3], fit: &SpaceSegmentFit) -> Option<Vec<DVec3>> {
    let fractions = shares(smooth);
    let p = [fit.alpha, fit.turning, fit.log_ratio, fit.torsion[0], fit.torsion[1]];
    let (_, placement) = uniform_model(points, &fractions, p)?;
    let model = model_at(fit.alpha, fit.turning, fit.log_ratio, fit.torsion, &fractions)?;
    Some(model.into_iter().map(|q| placement.apply(q)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coarse_turning_of_an_arc_misses_half_a_chord_at_each_end() {
        // 21 points on an arc of 2.4 radians; chords through every third point (and the last)
        // subtend 3 × 0.12 radians, the last one 2 × 0.12. Between the first chord's direction and
        // the last's the tangent turns by the arc less half of each end chord's angle.
        let step = 2.4 / 20.0;
        let arc: Vec<DVec3> =
            (0..21).map(|i| DVec3::new((i as f64 * step).cos(), (i as f64 * step).sin(), 0.0)).collect();
        let expected = 2.4 - 0.5 * (3.0 * step) - 0.5 * (2.0 * step);
        assert!((coarse_turning(&arc, 7) - expected).abs() < 1e-12, "{}", coarse_turning(&arc, 7));
    }

    #[test]
    fn an_exact_space_segment_is_found_again() {
        // The model itself, sampled evenly, moved and scaled: the fit finds its α and shape.
        let fractions: Vec<f64> = (0..40).map(|i| i as f64 / 39.0).collect();
        let truth = model_at(1.0, 2.5, -0.8, [1.5, 3.0], &fractions).unwrap();
        let rotation = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let points: Vec<DVec3> = truth.iter().map(|p| DVec3::new(1.0, -2.0, 0.5) + rotation * *p * 3.0).collect();
        let fit = fit_space_smoothed(&points, &points, None).unwrap();
        assert!((fit.alpha - 1.0).abs() < 0.05, "{fit:?}");
        assert!(fit.rms < 1e-4, "{fit:?}");
        let on = space_points_on(&points, &points, &fit).unwrap();
        let off = on.iter().zip(&points).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(off < 1e-3, "{off}");
    }
}
