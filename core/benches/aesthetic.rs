//! Log-aesthetic speed, reported against references measured in the same run.
//!
//! - Filter passes per second on 20, 1 000 and 100 000 points (a log-aesthetic segment with 10 %
//!   of the spacing as noise), and as a ratio to one evaluation of the discrete curvature of the
//!   same points (`curve_geometry`), the least any curvature filter must do. The paper: about 250
//!   passes over 20 points in 0.2 s on a 2008 PC.
//! - A full fairing of 1 000 noisy points to the default tolerance (target: under 16 ms, one
//!   frame), for the noise of the first measurement and for eight other draws of it.
//! - α estimation of 10 000 points, against the least-squares B-spline fit it starts with.
//! - Segment construction from three control points, against sampling 101 points of it.
//!
//! Run with `cargo bench -p taut-core --bench aesthetic`. `TAUT_BENCH_QUICK=1` runs fewer repeats.

use std::hint::black_box;
use std::time::{Duration, Instant};
use taut_core::DVec3;
use taut_core::aesthetic::{AestheticSegment, Alpha, CurveFilter, EstimateSettings, FilterSettings, estimate_alpha};
use taut_core::curve::{BSpline, PointSequence, curve_geometry};

/// Median wall time of `f` over `repeats` runs.
fn median(repeats: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..repeats)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

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

fn segment() -> AestheticSegment {
    AestheticSegment::from_control_points(DVec3::ZERO, DVec3::X, DVec3::new(1.5, 1.2, 0.0), 1.0).unwrap().unwrap()
}

/// `n` points of the segment with `relative` × the spacing of noise (the ends kept).
fn noisy(n: usize, relative: f64) -> PointSequence {
    noisy_draw(n, relative, 0)
}

/// [`noisy`] with noise of draw `draw`.
fn noisy_draw(n: usize, relative: f64, draw: u64) -> PointSequence {
    let seg = segment();
    let amplitude = relative * seg.length() / (n - 1) as f64;
    let mut noise = Noise(0x5eed + draw * 7919);
    let points = seg
        .sample(n)
        .into_iter()
        .enumerate()
        .map(
            |(i, p)| if i == 0 || i == n - 1 { p } else { p + amplitude * DVec3::new(noise.next(), noise.next(), 0.0) },
        )
        .collect();
    PointSequence::new(points, false)
}

fn settings() -> FilterSettings {
    FilterSettings { alpha: Alpha::Uniform(1.0), ..FilterSettings::default() }
}

fn pass_bench(n: usize, repeats: usize) {
    let curve = noisy(n, 0.1);
    let passes = (200_000 / n).clamp(1, 200);
    let mut filter = CurveFilter::new(&curve, settings()).unwrap();
    filter.run(1).unwrap();
    let pass = median(repeats, || {
        let mut f = CurveFilter::new(&curve, settings()).unwrap();
        black_box(f.run(passes).unwrap());
    }) / passes as u32;
    let reference = median(repeats, || {
        black_box(curve_geometry(&curve, Some(DVec3::Z)));
    });
    println!(
        "filter pass, {n} points: {:.1} µs = {:.0} passes/s; one curvature evaluation {:.1} µs; ratio {:.1}x",
        pass.as_secs_f64() * 1e6,
        1.0 / pass.as_secs_f64(),
        reference.as_secs_f64() * 1e6,
        pass.as_secs_f64() / reference.as_secs_f64()
    );
}

fn main() {
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 11 };
    println!("threads: {}", rayon::current_num_threads());
    for n in [20, 1_000, 100_000] {
        pass_bench(n, if n > 10_000 { repeats.min(3) } else { repeats });
    }

    let curve = noisy(1_000, 0.1);
    let mut passes = 0;
    let full = median(repeats, || {
        let mut f = CurveFilter::new(&curve, settings()).unwrap();
        passes = f.run_to_convergence().unwrap().passes;
    });
    println!(
        "full fairing, 1000 points with 10 % of the spacing as noise: {passes} passes in {:.1} ms ({:.0}% of a 16 ms frame)",
        full.as_secs_f64() * 1e3,
        100.0 * full.as_secs_f64() / 0.016
    );
    // Eight other draws of the noise: the passes a fairing takes depend on it.
    let mut draws: Vec<(Duration, usize)> = (1..=8)
        .map(|draw| {
            let curve = noisy_draw(1_000, 0.1, draw);
            let mut passes = 0;
            let time = median(repeats.min(5), || {
                let mut f = CurveFilter::new(&curve, settings()).unwrap();
                let status = f.run_to_convergence().unwrap();
                assert!(status.converged, "draw {draw}: {status:?}");
                passes = status.passes;
            });
            (time, passes)
        })
        .collect();
    draws.sort();
    let (fewest, most) = (draws.iter().map(|d| d.1).min().unwrap(), draws.iter().map(|d| d.1).max().unwrap());
    println!(
        "full fairing, eight more noise draws: {fewest} to {most} passes; median {:.1} ms, slowest {:.1} ms ({:.0}% of a frame)",
        draws[4].0.as_secs_f64() * 1e3,
        draws[7].0.as_secs_f64() * 1e3,
        100.0 * draws[7].0.as_secs_f64() / 0.016
    );

    let exact = PointSequence::new(segment().sample(10_000), false);
    let estimate = median(repeats, || {
        black_box(estimate_alpha(&exact, Some(DVec3::Z), &EstimateSettings::default()).unwrap());
    });
    let arc = exact.arc_lengths();
    let params: Vec<f64> = arc.iter().map(|s| s / arc[arc.len() - 1]).collect();
    let fit = median(repeats, || {
        black_box(BSpline::fit(&exact.points, &params, 3, 24).unwrap());
    });
    println!(
        "α estimation, 10000 points: {:.2} ms; the least-squares B-spline fit alone {:.2} ms; ratio {:.1}x",
        estimate.as_secs_f64() * 1e3,
        fit.as_secs_f64() * 1e3,
        estimate.as_secs_f64() / fit.as_secs_f64()
    );

    let construct = median(repeats * 10, || {
        black_box(segment());
    });
    let seg = segment();
    let sample = median(repeats * 10, || {
        black_box(seg.sample(101));
    });
    println!(
        "segment from three control points: {:.1} µs; sampling 101 points of it {:.1} µs; ratio {:.1}x",
        construct.as_secs_f64() * 1e6,
        sample.as_secs_f64() * 1e6,
        construct.as_secs_f64() / sample.as_secs_f64()
    );
}
