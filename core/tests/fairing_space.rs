//! Shape-keeping fairing of space curves (issue 20, first section, "the same for space curves
//! with torsion"): on exact log-aesthetic space curves with Gaussian noise in all three
//! coordinates, the spatial filter with its pre-fit and data term ends at most half as far from
//! the true curve as the noisy input, on average over the points and the draws, with α given and
//! with α estimated, and every run converges.
//!
//! The curves are drawn here from their definition, independently of the filter: the radius of
//! curvature follows the log-aesthetic law `ρ^α = c s + d` (`ln ρ = c s + d` for α = 0) from ρ₀
//! to e·ρ₀ over the length, scaled so the tangent turns by half a turn, and the radius of torsion
//! the law of β = 1, `μ = g s + h`, from one to two radii of curvature's worth of the mean
//! curvature; the Frenet–Serret equations are integrated by fourth-order Runge–Kutta. A helix
//! (constant curvature and torsion) is log-aesthetic for every α and β and is checked too.
//! Figures measured are in `docs/log-aesthetic.md`.

use std::f64::consts::PI;
use taut_core::DVec3;
use taut_core::aesthetic::{Alpha, CurveFilter, EstimateSettings, FilterSettings, estimate_alpha};
use taut_core::curve::PointSequence;

#[path = "common/noise.rs"]
mod noise;
use noise::Noise;

/// `points` with Gaussian noise of standard deviation `sigma` in x, y and z; the end points kept.
fn with_noise(points: &[DVec3], sigma: f64, seed: u64) -> Vec<DVec3> {
    let mut noise = Noise::seeded(seed);
    let n = points.len();
    (0..n)
        .map(|i| {
            if i == 0 || i + 1 == n {
                points[i]
            } else {
                points[i] + sigma * DVec3::new(noise.gauss(), noise.gauss(), noise.gauss())
            }
        })
        .collect()
}

/// A space curve of unit length given by its curvature and torsion along the arc length.
struct SpaceCurve {
    kappa: Box<dyn Fn(f64) -> f64>,
    tau: Box<dyn Fn(f64) -> f64>,
}

impl SpaceCurve {
    /// The log-aesthetic curve of slope α whose end radii of curvature are e apart, turning by half a
    /// turn, with the radius of torsion linear in arc length (β = 1) from 1/(0.5 κ̄) to 1/κ̄, κ̄
    /// the mean curvature π.
    fn log_aesthetic(alpha: f64) -> SpaceCurve {
        SpaceCurve::with([alpha, PI, 1.0, 0.5 * PI, PI])
    }

    /// The log-aesthetic space curve of parameters `[α, turning, ln(ρ₁/ρ₀), τ₀, τ₁]` (torsion
    /// with μ = 1/τ linear in arc length).
    fn with(theta: [f64; 5]) -> SpaceCurve {
        let [alpha, total, log_ratio, t0, t1] = theta;
        // ρ(s) for ρ₀ = 1, then scaled so that ∫κ ds = the turning.
        let rho = move |s: f64| {
            if alpha == 0.0 {
                (s * log_ratio).exp()
            } else {
                (1.0 + ((alpha * log_ratio).exp() - 1.0) * s).powf(1.0 / alpha)
            }
        };
        let turning: f64 = {
            let m = 20_000;
            (0..m).map(|k| (k as f64 + 0.5) / m as f64).map(|s| 1.0 / rho(s)).sum::<f64>() / m as f64
        };
        let scale = turning / total;
        let (mu0, mu1) = (1.0 / t0, 1.0 / t1);
        SpaceCurve {
            kappa: Box::new(move |s| 1.0 / (scale * rho(s))),
            tau: Box::new(move |s| 1.0 / (mu0 + (mu1 - mu0) * s)),
        }
    }

    /// The helix of curvature π and torsion π/2 (half a turn of its tangent's projection).
    fn helix() -> SpaceCurve {
        SpaceCurve { kappa: Box::new(|_| PI), tau: Box::new(|_| 0.5 * PI) }
    }

    /// `n` points evenly spaced in arc length, the first at the origin heading along x, each
    /// interval integrated in `steps` Runge–Kutta steps.
    fn sample(&self, n: usize, steps: usize) -> Vec<DVec3> {
        // State: position, tangent, normal, binormal.
        type State = [DVec3; 4];
        let derivative = |s: f64, y: &State| -> State {
            let (k, t) = ((self.kappa)(s), (self.tau)(s));
            [y[1], k * y[2], -k * y[1] + t * y[3], -t * y[2]]
        };
        let add = |y: &State, d: &State, h: f64| -> State { std::array::from_fn(|i| y[i] + h * d[i]) };
        let mut y: State = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let mut points = vec![y[0]];
        let h = 1.0 / ((n - 1) * steps) as f64;
        let mut s = 0.0;
        for _ in 1..n {
            for _ in 0..steps {
                let k1 = derivative(s, &y);
                let k2 = derivative(s + 0.5 * h, &add(&y, &k1, 0.5 * h));
                let k3 = derivative(s + 0.5 * h, &add(&y, &k2, 0.5 * h));
                let k4 = derivative(s + h, &add(&y, &k3, h));
                y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
                s += h;
            }
            points.push(y[0]);
        }
        points
    }
}

/// Distance from a fine polyline of the true curve.
fn distance(dense: &[DVec3], p: DVec3) -> f64 {
    let coarse = (0..dense.len())
        .step_by(16)
        .min_by(|&a, &b| p.distance_squared(dense[a]).total_cmp(&p.distance_squared(dense[b])))
        .unwrap_or(0);
    let (lo, hi) = (coarse.saturating_sub(64), (coarse + 65).min(dense.len()));
    dense[lo..hi]
        .windows(2)
        .map(|w| {
            let t = ((p - w[0]).dot(w[1] - w[0]) / w[0].distance_squared(w[1])).clamp(0.0, 1.0);
            p.distance(w[0].lerp(w[1], t))
        })
        .fold(f64::INFINITY, f64::min)
}

fn mean_distance(dense: &[DVec3], points: &[DVec3]) -> f64 {
    points.iter().map(|p| distance(dense, *p)).sum::<f64>() / points.len() as f64
}

struct Outcome {
    ratio: f64,
    prefit_ratio: f64,
    passes: usize,
    converged: bool,
}

fn fair(noisy: &[DVec3], alpha: Alpha, dense: &[DVec3]) -> Outcome {
    let settings = FilterSettings { alpha, torsion_beta: Some(1.0), ..FilterSettings::keeping_shape() };
    let mut filter = CurveFilter::new(&PointSequence::new(noisy.to_vec(), false), settings).unwrap();
    let status = filter.run_to_convergence().unwrap();
    let before = mean_distance(dense, noisy);
    Outcome {
        ratio: mean_distance(dense, filter.points()) / before,
        prefit_ratio: mean_distance(dense, &filter.prefit().unwrap().points) / before,
        passes: status.passes,
        converged: status.converged,
    }
}

/// The bound on the mean ratio: the half from 60 points on. Twenty points are the tight
/// case, as for plane curves: with the pre-fit by one space segment they end 0.33–0.59 as far as
/// the input (0.40–0.61 with the smoother alone), a few cases of the thirty above a half; there
/// the bound is 0.6.
fn bound(n: usize) -> f64 {
    if n <= 20 { 0.6 } else { 0.5 }
}

fn grid(counts: &[usize], estimated: bool) {
    let mut failures = Vec::new();
    let curves: Vec<(String, f64, SpaceCurve)> = [-1.0, 0.0, 1.0, 2.0]
        .into_iter()
        .map(|a| (format!("α = {a}"), a, SpaceCurve::log_aesthetic(a)))
        .chain([("helix".to_string(), 1.0, SpaceCurve::helix())])
        .collect();
    for (name, alpha, curve) in &curves {
        let dense = curve.sample(8001, 2);
        for &n in counts {
            let exact = curve.sample(n, 8000 / n + 1);
            for share in [0.002, 0.005, 0.01] {
                let mut outcomes = Vec::new();
                let mut estimates = Vec::new();
                for draw in 0..if n <= 20 { 6 } else { 2 } {
                    let seed = (alpha + 2.0) as u64 * 1_000_003 + n as u64 * 101 + (share * 1e4) as u64 * 7 + draw;
                    let noisy = with_noise(&exact, share, seed);
                    let given = if estimated {
                        let estimate = estimate_alpha(
                            &PointSequence::new(noisy.clone(), false),
                            None,
                            &EstimateSettings::default(),
                        )
                        .unwrap();
                        estimates.extend(estimate.pieces.iter().map(|p| p.alpha));
                        Alpha::PerPoint(estimate.per_point())
                    } else {
                        Alpha::Uniform(*alpha)
                    };
                    outcomes.push(fair(&noisy, given, &dense));
                }
                let label = format!(
                    "{name}, {n} points, noise {:.1} %, α {}",
                    share * 100.0,
                    if estimated { "estimated" } else { "given" }
                );
                let mean = outcomes.iter().map(|o| o.ratio).sum::<f64>() / outcomes.len() as f64;
                let prefit = outcomes.iter().map(|o| o.prefit_ratio).sum::<f64>() / outcomes.len() as f64;
                let passes = outcomes.iter().map(|o| o.passes).max().unwrap_or(0);
                println!(
                    "{label}: mean ratio {mean:.3} (pre-fit alone {prefit:.3}), at most {passes} passes, α {estimates:.2?}"
                );
                for (draw, o) in outcomes.iter().enumerate().filter(|(_, o)| !o.converged) {
                    failures.push(format!("{label}, draw {draw}: stopped at the pass cap ({} passes)", o.passes));
                }
                if mean > bound(n) {
                    failures.push(format!("{label}: mean ratio {mean:.3}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn space_curves_keep_their_shape_with_alpha_given() {
    grid(&[20, 60, 200], false);
}

#[test]
fn space_curves_keep_their_shape_with_alpha_estimated() {
    grid(&[20, 60], true);
}

/// The smallest standard deviation an unbiased estimate of α can have (the Cramér–Rao bound)
/// from `n` points of the curve of parameters `theta`, evenly spaced in arc length with the end
/// points exact and the others off by isotropic Gaussian noise of standard deviation `sigma`.
/// The curve through the two end points has six parameters: the five of [`SpaceCurve::with`]
/// and its roll about the chord. Written from this file's own integration, independently of the
/// estimator.
fn cramer_rao_alpha(theta: [f64; 5], n: usize, sigma: f64) -> f64 {
    let steps = 8000 / n + 1;
    let base = SpaceCurve::with(theta).sample(n, steps);
    let (p0, p1) = (base[0], base[n - 1]);
    // The curve of parameters (θ, roll), moved so its ends are p0 and p1.
    let placed = |q: [f64; 6]| -> Vec<DVec3> {
        let c = SpaceCurve::with([q[0], q[1], q[2], q[3], q[4]]).sample(n, steps);
        let (d, t) = (c[n - 1] - c[0], p1 - p0);
        let rotation = glam::DQuat::from_rotation_arc(d.normalize(), t.normalize());
        let roll = glam::DQuat::from_axis_angle(t.normalize(), q[5]);
        let scale = t.length() / d.length();
        c.iter().map(|p| p0 + roll * (rotation * (*p - c[0])) * scale).collect()
    };
    let q0 = [theta[0], theta[1], theta[2], theta[3], theta[4], 0.0];
    let h = 1e-5;
    let gradients: Vec<Vec<DVec3>> = (0..6)
        .map(|k| {
            let (mut up, mut down) = (q0, q0);
            up[k] += h;
            down[k] -= h;
            placed(up).iter().zip(placed(down)).map(|(a, b)| (*a - b) / (2.0 * h)).collect()
        })
        .collect();
    // Fisher information Σ Jᵀ J over the free points, inverted by Gauss–Jordan.
    let mut m = [[0.0f64; 12]; 6];
    for i in 1..n - 1 {
        for a in 0..6 {
            for b in 0..6 {
                m[a][b] += gradients[a][i].dot(gradients[b][i]);
            }
        }
    }
    for (a, row) in m.iter_mut().enumerate() {
        row[6 + a] = 1.0;
    }
    for c in 0..6 {
        let pivot = (c..6).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs())).unwrap();
        m.swap(c, pivot);
        let d = m[c][c];
        for x in m[c].iter_mut() {
            *x /= d;
        }
        for r in 0..6 {
            if r != c {
                let f = m[r][c];
                let row = m[c];
                for (x, y) in m[r].iter_mut().zip(row) {
                    *x -= f * y;
                }
            }
        }
    }
    sigma * m[0][6].sqrt()
}

/// α of a space curve at the noise (0.5 % of the length): one piece for a single
/// segment every time (the criterion to split: no single space segment fits the points to 1.3
/// times the noise level a spline leaves), and an RMS error over eight draws within 1.7 times
/// the Cramér–Rao bound of the data (measured 1.08–1.47 times on 60 points, 1.34–1.61 on 200:
/// less efficient than the plane fit, which is held to 1.25; the bound itself, 0.57–0.69 on 60
/// points and 0.31–0.37 on 200, says ±0.25 is out of reach there for any estimator).
#[test]
fn space_alpha_is_one_piece_and_near_the_bound() {
    let mut failures = Vec::new();
    for alpha in [-1.0, 0.0, 1.0, 2.0] {
        let curve = SpaceCurve::log_aesthetic(alpha);
        for n in [60, 200] {
            let exact = curve.sample(n, 8000 / n + 1);
            let mut errors = Vec::new();
            for draw in 0..8 {
                let noisy = with_noise(&exact, 0.005, 900 + draw + 7 * n as u64);
                let estimate =
                    estimate_alpha(&PointSequence::new(noisy, false), None, &EstimateSettings::default()).unwrap();
                if estimate.pieces.len() != 1 {
                    failures.push(format!("α = {alpha}, {n} points, draw {draw}: {} pieces", estimate.pieces.len()));
                }
                errors.push(estimate.pieces[0].alpha - alpha);
            }
            let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
            let bound = cramer_rao_alpha([alpha, PI, 1.0, 0.5 * PI, PI], n, 0.005);
            println!("α = {alpha}, {n} points: RMS error {rms:.3}, Cramér–Rao bound {bound:.3}, errors {errors:.2?}");
            if rms > 1.7 * bound {
                failures.push(format!("α = {alpha}, {n} points: RMS error {rms:.3} against the bound {bound:.3}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
