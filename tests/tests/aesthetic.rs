//! Log-aesthetic curves, filters and patches: properties against independent references
//! (issue 11, "Tests"). Every bound is stated where it is checked, with what was measured.

use std::f64::consts::PI;
use taut_core::DVec3;
use taut_core::aesthetic::{
    AestheticSegment, Alpha, BoundaryCurve, CurveFilter, EstimateSettings, FilterSettings, Grid, InflectionRule,
    SurfaceFilter, SurfaceSettings, coons_patch, curvature_graph, estimate_alpha, gaussian_curvature,
};
use taut_core::curve::{PointSequence, curve_geometry};

/// Deterministic noise in [−1, 1].
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// The same control triangle for every α (not isosceles, so no segment is a circle).
fn segment(alpha: f64) -> AestheticSegment {
    AestheticSegment::from_control_points(DVec3::ZERO, DVec3::X, DVec3::new(1.5, 1.2, 0.0), alpha).unwrap().unwrap()
}

/// Distance from `p` to the polyline `dense` (a fine sampling of the true curve).
fn distance_to(dense: &[DVec3], p: DVec3) -> f64 {
    dense
        .windows(2)
        .map(|w| {
            let t = ((p - w[0]).dot(w[1] - w[0]) / w[0].distance_squared(w[1])).clamp(0.0, 1.0);
            p.distance(w[0].lerp(w[1], t))
        })
        .fold(f64::INFINITY, f64::min)
}

fn rms_distance(dense: &[DVec3], points: &[DVec3]) -> f64 {
    (points.iter().map(|p| distance_to(dense, *p).powi(2)).sum::<f64>() / points.len() as f64).sqrt()
}

/// `points` with uniform noise of `amplitude` in x and y, the ends kept.
fn with_noise(points: &[DVec3], amplitude: f64, seed: u64) -> Vec<DVec3> {
    let mut noise = Noise(seed);
    let n = points.len();
    points
        .iter()
        .enumerate()
        .map(
            |(i, p)| {
                if i == 0 || i + 1 == n { *p } else { *p + amplitude * DVec3::new(noise.next(), noise.next(), 0.0) }
            },
        )
        .collect()
}

fn filter(points: Vec<DVec3>, alpha: f64, tolerance: f64) -> CurveFilter {
    let settings = FilterSettings { alpha: Alpha::Uniform(alpha), tolerance, ..FilterSettings::default() };
    CurveFilter::new(&PointSequence::new(points, false), settings).unwrap()
}

fn largest_move(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

#[test]
fn exact_log_aesthetic_segments_are_near_fixed_points_of_the_filter() {
    // The discrete curvature's bias (about κ²h²/4) changes slowly along the segment, so the window
    // fits are not exact: the points move, by little, and less with more points. Measured over the
    // whole run to a tolerance of 1e-6: at most 3.3e-5 of the length with 20 points, 2.1e-6 with 40.
    for alpha in [-1.0, 0.0, 1.0, 2.0] {
        let seg = segment(alpha);
        for (n, bound) in [(20, 6e-5), (40, 1e-5)] {
            let exact = seg.sample(n);
            let mut f = filter(exact.clone(), alpha, 1e-6);
            let status = f.run_to_convergence().unwrap();
            assert!(status.converged, "α = {alpha}, {n} points: {status:?}");
            let moved = largest_move(f.points(), &exact) / seg.length();
            println!("α = {alpha}, {n} points: {} passes, largest move {moved:.2e} of the length", status.passes);
            assert!(moved < bound, "α = {alpha}, {n} points: moved {moved:e}");
        }
    }
}

#[test]
fn noise_of_half_a_percent_is_removed() {
    // The paper's example: 20 points, noise 0.5 % of the length. After fairing (tolerance 1e-6,
    // about 1 100 passes) the LCG is a line of slope α: its residual falls by more than 300 times
    // (measured 1 500 to 2 000) and its slope is within 0.05 of α (measured 0.03); the points end
    // nearer the true curve than the noisy ones (RMS distance measured 0.36 to 0.5 of before).
    for alpha in [-1.0, 0.0, 1.0, 2.0] {
        let seg = segment(alpha);
        let dense = seg.sample(4000);
        let noisy = with_noise(&seg.sample(20), 0.005 * seg.length(), 12345);
        let before = curvature_graph(&PointSequence::new(noisy.clone(), false), Some(DVec3::Z)).fit.unwrap();
        let mut f = filter(noisy.clone(), alpha, 1e-6);
        let status = f.run_to_convergence().unwrap();
        let after = curvature_graph(&f.sequence(), Some(DVec3::Z)).fit.unwrap();
        let (d0, d1) = (rms_distance(&dense, &noisy), rms_distance(&dense, f.points()));
        println!(
            "α = {alpha}: {} passes; LCG residual {:.2e} → {:.2e}, slope {:.3}; RMS distance {d0:.2e} → {d1:.2e}",
            status.passes, before.residual, after.residual, after.slope
        );
        assert!(status.converged);
        assert!(after.residual * 300.0 < before.residual, "α = {alpha}: {} → {}", before.residual, after.residual);
        assert!((after.slope - alpha).abs() < 0.05, "α = {alpha}: slope {}", after.slope);
        assert!(d1 < 0.6 * d0, "α = {alpha}: {d0} → {d1}");
    }
}

#[test]
fn the_default_tolerance_removes_noise_in_a_few_hundred_passes() {
    // Tolerance 1e-4 (the default) stops once the noise is gone, about 250 passes on the paper's
    // example, as the paper reports; the LCG is then straighter (measured: residual 25 times
    // smaller) but not yet at its slope.
    let seg = segment(0.5);
    let dense = seg.sample(4000);
    let noisy = with_noise(&seg.sample(20), 0.005 * seg.length(), 777);
    let mut f = filter(noisy.clone(), 0.5, taut_core::aesthetic::filter::DEFAULT_TOLERANCE);
    let status = f.run_to_convergence().unwrap();
    assert!(status.converged && (100..600).contains(&status.passes), "{status:?}");
    assert!(rms_distance(&dense, f.points()) < 0.7 * rms_distance(&dense, &noisy));
    let before = curvature_graph(&PointSequence::new(noisy, false), Some(DVec3::Z)).fit.unwrap();
    let after = curvature_graph(&f.sequence(), Some(DVec3::Z)).fit.unwrap();
    assert!(after.residual * 5.0 < before.residual, "{} → {}", before.residual, after.residual);
}

#[test]
fn dense_noisy_curves_settle_without_hooks_at_their_ends() {
    // A thousand points with noise of a tenth of the spacing: the curvature is noise at first
    // (about 400 times the curve's), and the windows at the ends, shifted inside the curve, read
    // their line off beyond the middle. Before targets were capped at the window's sharpest
    // sample, these draws never converged: the ends curled into hooks of curvature about 1000
    // (the curve's is about 1) and 6e-3 of the length off the curve. Measured now: 216 to 252
    // passes, points at most 0.61 of the spacing's tenth from the true curve, RMS distance 0.36
    // to 0.39 of the noisy input's, curvature at most 11 times the curve's largest.
    for (alpha, draw) in [(1.0, 3), (1.0, 4), (2.0, 6), (2.0, 7)] {
        let seg = segment(alpha);
        let n = 1000;
        let exact = seg.sample(n);
        let dense = seg.sample(8 * n);
        let spacing = seg.length() / (n - 1) as f64;
        let noisy = with_noise(&exact, 0.1 * spacing, 0x5eed + draw * 7919);
        let mut f = filter(noisy.clone(), alpha, taut_core::aesthetic::filter::DEFAULT_TOLERANCE);
        let status = f.run_to_convergence().unwrap();
        assert!(status.converged && status.passes < 1000, "α = {alpha}, draw {draw}: {status:?}");
        let farthest = f.points().iter().map(|p| distance_to(&dense, *p)).fold(0.0, f64::max);
        assert!(
            farthest < 0.1 * spacing,
            "α = {alpha}, draw {draw}: a point {:.2} tenths of the spacing off",
            farthest / (0.1 * spacing)
        );
        let (d0, d1) = (rms_distance(&dense, &noisy), rms_distance(&dense, f.points()));
        assert!(d1 < 0.5 * d0, "α = {alpha}, draw {draw}: RMS distance {d0:.2e} → {d1:.2e}");
        let sharpest = |points: &[DVec3]| {
            let g = curve_geometry(&PointSequence::new(points.to_vec(), false), Some(DVec3::Z));
            g.curvature.iter().flatten().fold(0.0f64, |m, k| m.max(k.abs()))
        };
        let (curve, faired) = (sharpest(&exact), sharpest(f.points()));
        assert!(
            faired < 20.0 * curve,
            "α = {alpha}, draw {draw}: curvature {faired:.1} against the curve's {curve:.2}"
        );
    }
}

/// The largest distance between corresponding points.
fn farthest_apart(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

#[test]
fn the_planar_filter_moves_as_the_space_filter_does_on_a_plane_curve() {
    // An independent reference for the planar pass: the space filter computes the curvature through
    // the derivatives, fits its windows and moves along the principal normal by its own code. On a
    // plane curve without inflections its torsion is zero, so it has no torsion target and makes
    // the planar filter's moves: the two agree to rounding. Open with α per point (two pieces, so
    // some windows mix them), closed with an odd count (three colours), and closed on threads.
    let run = |points: &[DVec3], closed: bool, alpha: Alpha, passes: usize, space: bool| {
        let settings = FilterSettings { alpha, torsion_beta: space.then_some(1.0), ..FilterSettings::default() };
        let mut f = CurveFilter::new(&PointSequence::new(points.to_vec(), closed), settings).unwrap();
        let status = f.run(passes).unwrap();
        assert!(status.passes > 0 && status.capped == 0, "{status:?}");
        f.points().to_vec()
    };
    let seg = segment(1.0);
    let spacing = seg.length() / 59.0;
    let open = with_noise(&seg.sample(60), 0.002 * spacing, 21);
    let pieces = Alpha::PerPoint((0..60).map(|i| if i < 30 { 1.0 } else { 2.0 }).collect());
    let (planar, space) = (run(&open, false, pieces.clone(), 150, false), run(&open, false, pieces, 150, true));
    assert!(farthest_apart(&open, &planar) > 1e-4 * spacing, "the points moved");
    let apart = farthest_apart(&planar, &space) / seg.length();
    assert!(apart < 1e-9, "open, α in two pieces: {apart:e} of the length apart");

    let ellipse = |n: usize| -> Vec<DVec3> {
        let mut noise = Noise(77);
        (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / n as f64;
                let wobble = 1.0 + 1e-3 / n as f64 * noise.next();
                DVec3::new(2.0 * t.cos() * wobble, t.sin() * wobble, 0.0)
            })
            .collect()
    };
    let closed = ellipse(41);
    let (planar, space) =
        (run(&closed, true, Alpha::Uniform(1.0), 150, false), run(&closed, true, Alpha::Uniform(1.0), 150, true));
    assert!(farthest_apart(&closed, &planar) > 1e-6, "the points moved");
    let apart = farthest_apart(&planar, &space);
    assert!(apart < 1e-9, "closed, 41 points: {apart:e} apart");

    let many = ellipse(5001);
    let threads = |count: usize, space: bool| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(count).build().unwrap();
        pool.install(|| run(&many, true, Alpha::Uniform(1.0), 3, space))
    };
    let (one, two) = (threads(1, false), threads(2, false));
    assert!(one.iter().zip(&two).all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits)));
    let apart = farthest_apart(&one, &threads(2, true));
    assert!(apart < 1e-9, "closed, 5001 points on threads: {apart:e} apart");
}

#[test]
fn alpha_is_recovered_from_exact_samples() {
    // 100 samples: within 0.03 (measured at most 0.021); one piece, as the curvature is monotone.
    for alpha in [-1.0, 0.0, 0.5, 1.0, 2.0] {
        let points = PointSequence::new(segment(alpha).sample(100), false);
        let estimate = estimate_alpha(&points, Some(DVec3::Z), &EstimateSettings::default()).unwrap();
        assert_eq!(estimate.pieces.len(), 1, "α = {alpha}: {:?}", estimate.pieces);
        let found = estimate.pieces[0].alpha;
        assert!((found - alpha).abs() < 0.03, "α = {alpha}: estimated {found}");
        assert!(estimate.per_point().iter().all(|a| *a == found));
    }
}

#[test]
fn a_spiral_turning_one_and_a_half_times_is_filtered_and_estimated() {
    // A logarithmic spiral (α = 1) turning 540°: the filter works locally, so the turn does not
    // matter. To the default tolerance exact samples barely move (measured 2e-7 of the length),
    // 0.2 % noise is reduced (RMS distance measured 0.35 of before) and α comes back within 0.03
    // (measured 0.019).
    let spiral = AestheticSegment::in_standard_position(1.0, 3.0 * PI, 1.5, 1.0).unwrap();
    let exact = spiral.sample(120);
    let geometry = curve_geometry(&PointSequence::new(exact.clone(), false), Some(DVec3::Z));
    assert!(geometry.curvature.iter().flatten().all(|k| *k > 0.0), "one way round");
    let mut f = filter(exact.clone(), 1.0, 1e-4);
    f.run_to_convergence().unwrap();
    let moved = largest_move(f.points(), &exact) / spiral.length();
    let dense = spiral.sample(8000);
    let noisy = with_noise(&exact, 0.002 * spiral.length(), 4242);
    let mut f = filter(noisy.clone(), 1.0, 1e-4);
    f.run_to_convergence().unwrap();
    let (d0, d1) = (rms_distance(&dense, &noisy), rms_distance(&dense, f.points()));
    println!("spiral: exact moved {moved:.2e}, noisy {d0:.2e} → {d1:.2e}");
    assert!(moved < 1e-4, "{moved}");
    assert!(d1 < 0.6 * d0, "{d0} → {d1}");
    let estimate =
        estimate_alpha(&PointSequence::new(exact, false), Some(DVec3::Z), &EstimateSettings::default()).unwrap();
    assert_eq!(estimate.pieces.len(), 1, "{:?}", estimate.pieces);
    assert!((estimate.pieces[0].alpha - 1.0).abs() < 0.03, "{:?}", estimate.pieces);
}

/// A clothoid through its inflection, κ(s) = 3 s for s in [−1, 1], sampled at `n` points evenly
/// in arc length, integrated independently here (Simpson's rule, 200 steps a sample).
fn s_curve(n: usize) -> Vec<DVec3> {
    let angle = |s: f64| 1.5 * s * s;
    let mut out = vec![DVec3::ZERO];
    let h = 2.0 / (n - 1) as f64;
    for k in 1..n {
        let (a, steps) = (-1.0 + (k - 1) as f64 * h, 200);
        let mut sum = DVec3::ZERO;
        for j in 0..=steps {
            let s = a + h * j as f64 / steps as f64;
            let w = if j == 0 || j == steps {
                1.0
            } else if j % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * DVec3::new(angle(s).cos(), angle(s).sin(), 0.0);
        }
        let last = out[k - 1];
        out.push(last + sum * h / (3.0 * steps as f64));
    }
    out
}

fn sign_changes(points: &[DVec3]) -> usize {
    let g = curve_geometry(&PointSequence::new(points.to_vec(), false), Some(DVec3::Z));
    let k: Vec<f64> = g.curvature.iter().flatten().copied().collect();
    k.windows(2).filter(|w| w[0] * w[1] < 0.0).count()
}

#[test]
fn a_curve_with_an_inflection_keeps_exactly_its_inflection() {
    // A clothoid is the log-aesthetic curve (α = −1) through an inflection, so its exact samples
    // barely move (measured 8e-7 of the length). With 0.3 % noise the discrete curvature changes
    // sign many times; after fairing once, at the true inflection (within two spacings), and the
    // points are nearer the curve (RMS distance measured 0.73 of before).
    let exact = s_curve(41);
    let dense = s_curve(4001);
    let length = 2.0;
    let mut f = filter(exact.clone(), -1.0, 1e-4);
    f.run_to_convergence().unwrap();
    let moved = largest_move(f.points(), &exact) / length;
    let noisy = with_noise(&exact, 0.003 * length, 99);
    assert!(sign_changes(&noisy) > 3, "the noise must flip the curvature");
    let mut f = filter(noisy.clone(), -1.0, 1e-4);
    f.run_to_convergence().unwrap();
    let (d0, d1) = (rms_distance(&dense, &noisy), rms_distance(&dense, f.points()));
    println!(
        "clothoid S: exact moved {moved:.2e}, noisy {d0:.2e} → {d1:.2e}, sign changes {}",
        sign_changes(f.points())
    );
    assert!(moved < 1e-4, "{moved}");
    assert_eq!(sign_changes(f.points()), 1);
    let g = curve_geometry(&f.sequence(), Some(DVec3::Z));
    let flip = (1..39).find(|&i| g.curvature[i].unwrap() * g.curvature[i + 1].unwrap() < 0.0).unwrap();
    assert!((flip as f64 - 19.5).abs() <= 2.0, "inflection between points {flip} and {}", flip + 1);
    assert!(d1 < 0.8 * d0, "{d0} → {d1}");
    // The paper's rule holds the points whose window holds the inflection: the exact clothoid
    // stays put there.
    let settings =
        FilterSettings { alpha: Alpha::Uniform(-1.0), inflection: InflectionRule::Hold, ..FilterSettings::default() };
    let mut held = CurveFilter::new(&PointSequence::new(exact.clone(), false), settings).unwrap();
    let status = held.run(1).unwrap();
    assert!(status.held >= 4, "{status:?}");
    for i in 18..=22 {
        assert_eq!(held.points()[i], exact[i], "point {i} next to the inflection");
    }
}

#[test]
fn the_segment_meets_its_control_points_and_has_a_straight_lcg_of_slope_alpha() {
    // End points to 1e-12, end tangents along P0→P1 and P1→P2 to 1e-9; the discrete LCG of 400
    // samples has slope α within 0.01 (measured 0.002) and residual under 1e-3.
    let (p0, p1, p2) = (DVec3::new(1.0, 2.0, 0.5), DVec3::new(3.0, 2.5, 0.5), DVec3::new(3.8, 4.5, 0.5));
    for alpha in [-1.0, 0.0, 0.5, 1.0, 2.0] {
        let seg = AestheticSegment::from_control_points(p0, p1, p2, alpha).unwrap().unwrap();
        let length = seg.length();
        assert!(seg.point_at(0.0).distance(p0) < 1e-12 && seg.point_at(length).distance(p2) < 1e-12);
        assert!(seg.tangent_at(0.0).cross((p1 - p0).normalize()).length() < 1e-9);
        assert!(seg.tangent_at(length).cross((p2 - p1).normalize()).length() < 1e-9);
        assert!(seg.tangent_at(0.0).dot(p1 - p0) > 0.0 && seg.tangent_at(length).dot(p2 - p1) > 0.0);
        let points = seg.sample(400);
        let spacing: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
        assert!(spacing.iter().all(|h| (h - length / 399.0).abs() < 1e-4 * length / 399.0), "even in arc length");
        let fit = curvature_graph(&PointSequence::new(points, false), Some(DVec3::Z)).fit.unwrap();
        println!("α = {alpha}: LCG slope {:.4}, residual {:.2e}", fit.slope, fit.residual);
        assert!((fit.slope - alpha).abs() < 0.01 && fit.residual < 1e-3, "α = {alpha}: {fit:?}");
    }
}

#[test]
fn the_segment_follows_a_similarity_of_its_control_points() {
    let (p0, p1, p2) = (DVec3::ZERO, DVec3::new(2.0, 0.3, 0.0), DVec3::new(2.6, 1.9, 0.4));
    let rotation = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
    let map = |p: DVec3| 3.5 * (rotation * p) + DVec3::new(-4.0, 7.0, 2.0);
    for alpha in [-1.0, 0.0, 1.0, 2.0] {
        let a = AestheticSegment::from_control_points(p0, p1, p2, alpha).unwrap().unwrap();
        let b = AestheticSegment::from_control_points(map(p0), map(p1), map(p2), alpha).unwrap().unwrap();
        assert!((b.length() - 3.5 * a.length()).abs() < 1e-11 * b.length());
        for (p, q) in a.sample(25).into_iter().zip(b.sample(25)) {
            assert!(map(p).distance(q) < 1e-11 * b.length(), "α = {alpha}");
        }
    }
}

#[test]
fn the_filter_follows_a_similarity_and_does_not_depend_on_the_thread_count() {
    // Rotating, scaling and moving the input moves the output the same way (the curvature is
    // signed about the plane normal, which a rotation in the plane keeps). 5 000 points run the
    // passes on threads; one thread and two give the same bits.
    let seg = segment(1.0);
    let noisy = with_noise(&seg.sample(30), 0.003 * seg.length(), 5);
    let (angle, scale, shift) = (0.7f64, 2.5, DVec3::new(10.0, -3.0, 0.0));
    let map = |p: DVec3| {
        scale * DVec3::new(angle.cos() * p.x - angle.sin() * p.y, angle.sin() * p.x + angle.cos() * p.y, 0.0) + shift
    };
    let mut a = filter(noisy.clone(), 1.0, 1e-4);
    let mut b = filter(noisy.iter().map(|p| map(*p)).collect(), 1.0, 1e-4);
    a.run(300).unwrap();
    b.run(300).unwrap();
    for (p, q) in a.points().iter().zip(b.points()) {
        assert!(map(*p).distance(*q) < 1e-9 * scale * seg.length(), "{p} {q}");
    }
    let many = with_noise(&seg.sample(5000), 0.1 * seg.length() / 5000.0, 6);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut f = filter(many.clone(), 1.0, 1e-4);
            f.run(5).unwrap();
            f.points().to_vec()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.iter().zip(&two).all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits)));
}

#[test]
fn the_space_filter_fairs_a_noisy_helix() {
    // A helix has constant curvature and torsion, so any β fits it. Exact samples barely move
    // (measured 1e-6 of the length). With 0.2 % noise in all three directions the torsion varies
    // far less afterwards (spread measured 4.3 times smaller), but the points do not end nearer
    // the helix (RMS distance measured 1.5 times larger): torsion is a third derivative, and near
    // a helix it hardly depends on the binormal offset (W has no normal part), so the quadratic
    // for ψ is ill-conditioned and its root wanders. That weakness is what this test records.
    let (a, b) = (1.0, 0.4);
    let helix = |t: f64| DVec3::new(a * t.cos(), a * t.sin(), b * t);
    let exact: Vec<DVec3> = (0..60).map(|i| helix(i as f64 * 0.15)).collect();
    let dense: Vec<DVec3> = (0..=9000).map(|i| helix(i as f64 * 59.0 * 0.15 / 9000.0)).collect();
    let length = 59.0 * 0.15 * (a * a + b * b).sqrt();
    let settings = FilterSettings { torsion_beta: Some(1.0), ..FilterSettings::default() };
    let mut f = CurveFilter::new(&PointSequence::new(exact.clone(), false), settings.clone()).unwrap();
    f.run_to_convergence().unwrap();
    let moved = largest_move(f.points(), &exact) / length;
    println!("helix exact moved {moved:.2e}");
    assert!(moved < 1e-4, "{moved}");
    let mut noise = Noise(31);
    let noisy: Vec<DVec3> = exact
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if i == 0 || i == 59 {
                *p
            } else {
                *p + 0.002 * length * DVec3::new(noise.next(), noise.next(), noise.next())
            }
        })
        .collect();
    let spread = |points: &[DVec3]| {
        let g = curve_geometry(&PointSequence::new(points.to_vec(), false), None);
        let t: Vec<f64> = g.torsion.iter().flatten().copied().collect();
        let mean = t.iter().sum::<f64>() / t.len() as f64;
        (t.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / t.len() as f64).sqrt()
    };
    let mut f = CurveFilter::new(&PointSequence::new(noisy.clone(), false), settings).unwrap();
    let status = f.run_to_convergence().unwrap();
    let (d0, d1) = (rms_distance(&dense, &noisy), rms_distance(&dense, f.points()));
    let (s0, s1) = (spread(&noisy), spread(f.points()));
    println!("helix: {} passes, RMS distance {d0:.2e} → {d1:.2e}, torsion spread {s0:.2e} → {s1:.2e}", status.passes);
    assert!(d1 < 1.6 * d0, "{d0} → {d1}");
    assert!(s1 * 3.0 < s0, "{s0} → {s1}");
}

#[test]
fn the_surface_filter_drives_a_noisy_sphere_cap_towards_constant_gaussian_curvature() {
    // A 21 × 21 grid on a sphere of radius 2 with noise of 1 % of the spacing along the normal:
    // the standard deviation of K over the interior falls by more than 20 times (measured 40)
    // and its mean ends within 3 % of 1/r² (measured 1 %). Larger noise biases K upwards: it is a
    // product of second differences.
    let (n, radius) = (21usize, 2.0);
    let mut noise = Noise(8);
    let mut points = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (-0.5 + i as f64 / (n - 1) as f64, -0.5 + j as f64 / (n - 1) as f64);
            let p = DVec3::new(x, y, (radius * radius - x * x - y * y).sqrt());
            let interior = i > 0 && j > 0 && i + 1 < n && j + 1 < n;
            points.push(if interior { p + 0.0005 * noise.next() * p / radius } else { p });
        }
    }
    let grid = Grid { rows: n, cols: n, points };
    let stats = |g: &Grid| {
        let k: Vec<f64> = gaussian_curvature(g).into_iter().flatten().collect();
        let mean = k.iter().sum::<f64>() / k.len() as f64;
        (mean, (k.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / k.len() as f64).sqrt())
    };
    let (_, sd0) = stats(&grid);
    let mut f = SurfaceFilter::new(grid, SurfaceSettings::default()).unwrap();
    let status = f.run_to_convergence().unwrap();
    let (mean1, sd1) = stats(f.grid());
    println!("sphere cap: {} passes, K spread {sd0:.2e} → {sd1:.2e}, mean {mean1:.4}", status.passes);
    assert!(status.converged && sd1 * 20.0 < sd0, "{sd0} → {sd1}");
    assert!((mean1 * radius * radius - 1.0).abs() < 0.03, "mean K {mean1}");
}

#[test]
fn coons_patches_of_straight_and_aesthetic_sides() {
    // Four straight sides: the bilinear patch of the corners, exactly.
    let (p00, p10, p11, p01) =
        (DVec3::ZERO, DVec3::new(3.0, 0.2, 0.5), DVec3::new(2.5, 2.0, 1.5), DVec3::new(-0.3, 1.8, 0.2));
    let line = |a: DVec3, b: DVec3| BoundaryCurve::Polyline(vec![a, b]);
    let grid = coons_patch(&[line(p00, p10), line(p10, p11), line(p11, p01), line(p01, p00)], 8).unwrap();
    for i in 0..=8 {
        for j in 0..=8 {
            let (u, v) = (i as f64 / 8.0, j as f64 / 8.0);
            let bilinear = (1.0 - u) * (1.0 - v) * p00 + u * (1.0 - v) * p10 + (1.0 - u) * v * p01 + u * v * p11;
            assert!(grid.at(i, j).distance(bilinear) < 1e-12);
        }
    }
    // Two aesthetic sides and two straight ones: ruled, every line of constant u straight. With
    // the second side a translate of the first (the paper's figure) the patch is a cylinder, K = 0.
    let seg = |offset: DVec3| {
        AestheticSegment::from_control_points(offset, offset + DVec3::X, offset + DVec3::new(1.4, 1.0, 0.0), 2.0)
            .unwrap()
            .unwrap()
    };
    for top_offset in [DVec3::new(0.2, -0.1, 1.0), DVec3::new(0.0, 0.0, 1.0)] {
        let (bottom, top) = (seg(DVec3::ZERO), seg(top_offset));
        let (b_end, t_end) = (bottom.point_at(bottom.length()), top.point_at(top.length()));
        let curves = [
            BoundaryCurve::Aesthetic(bottom),
            line(b_end, t_end),
            BoundaryCurve::Aesthetic(top),
            line(top_offset, DVec3::ZERO),
        ];
        let grid = coons_patch(&curves, 16).unwrap();
        for i in 0..=16 {
            let (a, b) = (grid.at(i, 0), grid.at(i, 16));
            for j in 1..16 {
                let p = grid.at(i, j);
                assert!(
                    (p - a).cross(b - a).length() < 1e-12 * a.distance(b).powi(2),
                    "row {i} is not straight at {j}"
                );
            }
        }
        if top_offset == DVec3::new(0.0, 0.0, 1.0) {
            let k = gaussian_curvature(&grid);
            assert!(k.iter().flatten().all(|k| k.abs() < 1e-9), "a cylinder is flat in K");
        }
    }
}

#[test]
fn bad_curves_are_refused_with_one_clear_line() {
    let expect = |points: Vec<DVec3>, settings: FilterSettings, fragment: &str| {
        let err = CurveFilter::new(&PointSequence::new(points, false), settings).unwrap_err().to_string();
        assert!(err.contains(fragment) && !err.contains('\n'), "{err:?} should mention {fragment:?}");
    };
    let good = segment(1.0).sample(20);
    expect(good[..6].to_vec(), FilterSettings::default(), "2m + 1 = 7");
    let mut repeated = good.clone();
    repeated[7] = repeated[8];
    expect(repeated, FilterSettings::default(), "points 7 and 8 are at the same place");
    let mut nan = good.clone();
    nan[3].y = f64::NAN;
    expect(nan, FilterSettings::default(), "point 3 has a non-finite coordinate");
    expect(
        good.clone(),
        FilterSettings { alpha: Alpha::Uniform(f64::INFINITY), ..FilterSettings::default() },
        "α must be",
    );
    let mut hairpin = good.clone();
    hairpin[9] = hairpin[7];
    expect(hairpin, FilterSettings::default(), "turns back on itself at point 8 (points 7 and 9");
    expect(good.clone(), FilterSettings { window: 0, ..FilterSettings::default() }, "window");
    expect(good.clone(), FilterSettings { relaxation: 1.5, ..FilterSettings::default() }, "relaxation");
    expect(
        good[..8].to_vec(),
        FilterSettings { torsion_beta: Some(1.0), ..FilterSettings::default() },
        "torsion needs",
    );
    let err = taut_core::io::points::parse_csv("x,y\n0,0\n1,zz\n", std::path::Path::new("bad.csv")).unwrap_err();
    assert!(err.to_string().contains("bad.csv: row 3: 'zz' is not a number"), "{err}");
}

/// Gaussian noise of standard deviation `sigma` (Box–Muller on [`Noise`]), ends kept.
fn with_gaussian_noise(points: &[DVec3], sigma: f64, seed: u64) -> Vec<DVec3> {
    let mut noise = Noise(seed);
    let mut gauss = || {
        let (u1, u2) = (0.5 * (noise.next() + 1.0), 0.5 * (noise.next() + 1.0));
        (-2.0 * u1.max(1e-300).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let n = points.len();
    (0..n)
        .map(|i| if i == 0 || i + 1 == n { points[i] } else { points[i] + sigma * DVec3::new(gauss(), gauss(), 0.0) })
        .collect()
}

/// α read from noisy samples of exact log-aesthetic segments (half a turn, end radii e apart,
/// Gaussian noise of 0.5 % of the length, ends kept, three draws each): one piece every time,
/// and α within 0.3 on 200 points and 0.6 on 60 (measured at most 0.28 and 0.53). The paper's
/// curvature graph split these into up to thirteen pieces of α between −8 and 3.
#[test]
fn alpha_is_found_as_one_piece_from_noisy_samples() {
    for alpha in [-1.0, 0.0, 1.0, 2.0] {
        let segment = AestheticSegment::in_standard_position(alpha, PI, 1.0, 1.0).unwrap();
        for (n, tolerance) in [(60, 0.6), (200, 0.3)] {
            let mut errors = Vec::new();
            for seed in [1u64, 2, 3] {
                let noisy = with_gaussian_noise(&segment.sample(n), 0.005 * segment.length(), 77 + seed);
                let estimate =
                    estimate_alpha(&PointSequence::new(noisy, false), Some(DVec3::Z), &EstimateSettings::default())
                        .unwrap();
                assert_eq!(estimate.pieces.len(), 1, "α = {alpha}, {n} points: {:?}", estimate.pieces);
                errors.push(estimate.pieces[0].alpha - alpha);
            }
            println!("α = {alpha}, {n} points: errors {errors:.2?}");
            assert!(errors.iter().all(|e| e.abs() < tolerance), "α = {alpha}, {n} points: {errors:?}");
        }
    }
    // Two segments meeting at an inflection are still two pieces.
    let s = s_curve(80);
    let estimate = estimate_alpha(&PointSequence::new(s, false), Some(DVec3::Z), &EstimateSettings::default()).unwrap();
    assert!(estimate.pieces.len() >= 2, "{:?}", estimate.pieces);
}
