//! Shape-keeping fairing of surfaces (issue 20, first section: "`fair-surface` on a noisy sampled
//! constant Gaussian curvature patch (a sphere cap, a pseudosphere piece): noise removed, shape
//! kept"): the constant-K filter with its pre-fit and data term ends at most half as far from the
//! true surface as the noisy grid, on average over the interior points and the draws, and every
//! run converges; the paper's filter alone is measured beside it.
//!
//! The surfaces are sampled here from their closed forms, and distances are measured to them in
//! closed form (a sphere) or against a fine sampling of the meridian (the pseudosphere, a surface
//! of revolution of the tractrix). Noise is Gaussian in x, y and z with a standard deviation of a
//! share of the grid's diagonal, from a fixed seed; the boundary rows and columns are kept exact,
//! as the end points of the curve tests are (the filter keeps them where they are, so noise there
//! would stay noise). Figures measured are in `docs/log-aesthetic.md`.

use std::f64::consts::FRAC_PI_2;
use taut_core::DVec3;
use taut_core::aesthetic::{Grid, SurfaceFilter, SurfaceSettings, gaussian_curvature};

#[path = "common/noise.rs"]
mod noise;
use noise::Noise;

/// A constant-K surface: its grid of `n × n` points and the distance of a point from it.
trait Surface {
    fn grid(&self, n: usize) -> Grid;
    fn distance(&self, p: DVec3) -> f64;
    fn gaussian(&self) -> f64;
}

/// The unit sphere over the square [−½, ½]² of the xy-plane (up to 45° from the pole).
struct SphereCap;

impl Surface for SphereCap {
    fn grid(&self, n: usize) -> Grid {
        let at = |k: usize| -0.5 + k as f64 / (n - 1) as f64;
        let points = (0..n * n)
            .map(|k| {
                let (x, y) = (at(k / n), at(k % n));
                DVec3::new(x, y, (1.0 - x * x - y * y).sqrt())
            })
            .collect();
        Grid { rows: n, cols: n, points }
    }

    fn distance(&self, p: DVec3) -> f64 {
        (p.length() - 1.0).abs()
    }

    fn gaussian(&self) -> f64 {
        1.0
    }
}

/// A quarter of the unit pseudosphere (K = −1): the tractrix `(sech t, t − tanh t)` for t in
/// [0.3, 1.5] turned through a right angle about the z-axis.
struct Pseudosphere {
    /// The meridian, finely sampled, for distances.
    meridian: Vec<(f64, f64)>,
}

impl Pseudosphere {
    const T: (f64, f64) = (0.3, 1.5);

    fn new() -> Self {
        let m = 20_000;
        let meridian =
            (0..=m).map(|k| 0.1 + 1.6 * k as f64 / m as f64).map(|t| (1.0 / t.cosh(), t - t.tanh())).collect();
        Pseudosphere { meridian }
    }
}

impl Surface for Pseudosphere {
    fn grid(&self, n: usize) -> Grid {
        let points = (0..n * n)
            .map(|k| {
                let t = Self::T.0 + (Self::T.1 - Self::T.0) * (k / n) as f64 / (n - 1) as f64;
                let v = FRAC_PI_2 * (k % n) as f64 / (n - 1) as f64;
                let r = 1.0 / t.cosh();
                DVec3::new(r * v.cos(), r * v.sin(), t - t.tanh())
            })
            .collect();
        Grid { rows: n, cols: n, points }
    }

    fn distance(&self, p: DVec3) -> f64 {
        let (r, z) = (p.x.hypot(p.y), p.z);
        // The nearest of every 64th sample, then the segments around it.
        let m = &self.meridian;
        let coarse = (0..m.len())
            .step_by(64)
            .min_by(|&a, &b| (m[a].0 - r).hypot(m[a].1 - z).total_cmp(&(m[b].0 - r).hypot(m[b].1 - z)))
            .unwrap_or(0);
        m[coarse.saturating_sub(256)..(coarse + 257).min(m.len())]
            .windows(2)
            .map(|w| {
                let (dx, dz) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
                let t = (((r - w[0].0) * dx + (z - w[0].1) * dz) / (dx * dx + dz * dz)).clamp(0.0, 1.0);
                (r - w[0].0 - t * dx).hypot(z - w[0].1 - t * dz)
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn gaussian(&self) -> f64 {
        -1.0
    }
}

/// The grid with noise of standard deviation `sigma` on its interior points.
fn with_noise(grid: &Grid, sigma: f64, seed: u64) -> Grid {
    let mut noise = Noise::seeded(seed);
    let (rows, cols) = (grid.rows, grid.cols);
    let points = (0..rows * cols)
        .map(|k| {
            let (i, j) = (k / cols, k % cols);
            let p = grid.points[k];
            if i == 0 || j == 0 || i + 1 == rows || j + 1 == cols {
                p
            } else {
                p + sigma * DVec3::new(noise.gauss(), noise.gauss(), noise.gauss())
            }
        })
        .collect();
    Grid { rows, cols, points }
}

/// Mean distance of the interior points from the surface.
fn mean_distance(surface: &dyn Surface, grid: &Grid) -> f64 {
    let (rows, cols) = (grid.rows, grid.cols);
    let inside: Vec<DVec3> = (0..rows * cols)
        .filter(|k| (1..rows - 1).contains(&(k / cols)) && (1..cols - 1).contains(&(k % cols)))
        .map(|k| grid.points[k])
        .collect();
    inside.iter().map(|p| surface.distance(*p)).sum::<f64>() / inside.len() as f64
}

fn diagonal(grid: &Grid) -> f64 {
    let (lo, hi) = grid
        .points
        .iter()
        .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    (hi - lo).length()
}

#[test]
fn noisy_constant_curvature_patches_keep_their_shape() {
    let surfaces: [(&str, Box<dyn Surface>); 2] =
        [("sphere cap", Box::new(SphereCap)), ("pseudosphere", Box::new(Pseudosphere::new()))];
    let mut failures = Vec::new();
    for (name, surface) in &surfaces {
        for n in [12, 24, 48] {
            let exact = surface.grid(n);
            let size = diagonal(&exact);
            for share in [0.002, 0.005, 0.01] {
                let (mut ratios, mut prefit_ratios, mut paper_ratios, mut passes) = (0.0, 0.0, 0.0, 0);
                let draws = 3;
                let mut k_after = Vec::new();
                for draw in 0..draws {
                    let noisy = with_noise(&exact, share * size, n as u64 * 977 + (share * 1e4) as u64 + draw);
                    let before = mean_distance(surface.as_ref(), &noisy);
                    let mut kept = SurfaceFilter::new(noisy.clone(), SurfaceSettings::keeping_shape()).unwrap();
                    let status = kept.run_to_convergence().unwrap();
                    if !status.converged {
                        failures.push(format!("{name}, {n} × {n}, noise {share}, draw {draw}: pass cap ({status:?})"));
                    }
                    passes = passes.max(status.passes);
                    ratios += mean_distance(surface.as_ref(), kept.grid()) / before;
                    let fit = kept.prefit().unwrap();
                    prefit_ratios +=
                        mean_distance(surface.as_ref(), &Grid { points: fit.points.clone(), ..noisy.clone() }) / before;
                    let k: Vec<f64> = gaussian_curvature(kept.grid()).into_iter().flatten().collect();
                    k_after.push(k.iter().sum::<f64>() / k.len() as f64);
                    // The paper's filter beside it, on the small grids (on 48 × 48 with 1 % noise
                    // it diverges; docs/log-aesthetic.md has the figures).
                    if n <= 12 {
                        let mut paper = SurfaceFilter::new(noisy, SurfaceSettings::default()).unwrap();
                        paper_ratios += match paper.run_to_convergence() {
                            Ok(_) => mean_distance(surface.as_ref(), paper.grid()) / before,
                            Err(_) => f64::INFINITY,
                        };
                    }
                }
                let (mean, prefit, paper) =
                    (ratios / draws as f64, prefit_ratios / draws as f64, paper_ratios / draws as f64);
                println!(
                    "{name}, {n} × {n}, noise {:.1} %: mean ratio {mean:.3} (pre-fit alone {prefit:.3}, the paper's filter \
                     {paper:.3}), at most {passes} passes, mean K after {k_after:.3?} (true {})",
                    share * 100.0,
                    surface.gaussian()
                );
                if mean > 0.5 {
                    failures.push(format!("{name}, {n} × {n}, noise {share}: mean ratio {mean:.3}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn exact_constant_curvature_patches_stay_where_they_are() {
    // Without noise the pre-fit keeps the grid and the filter's fixed point is the sampled
    // surface. The paper's filter flattens the exact pseudosphere (its points sit at the vertex
    // of K's parabola along the normal; see `aesthetic::surface`), which the damped block step
    // does not.
    let surfaces: [(&str, Box<dyn Surface>); 2] =
        [("sphere cap", Box::new(SphereCap)), ("pseudosphere", Box::new(Pseudosphere::new()))];
    for (name, surface) in &surfaces {
        for n in [12, 24] {
            let exact = surface.grid(n);
            let size = diagonal(&exact);
            let mut kept = SurfaceFilter::new(exact.clone(), SurfaceSettings::keeping_shape()).unwrap();
            let status = kept.run_to_convergence().unwrap();
            let off = mean_distance(surface.as_ref(), kept.grid()) / size;
            let mut paper = SurfaceFilter::new(exact, SurfaceSettings::default()).unwrap();
            let paper_off = match paper.run(400) {
                Ok(_) => mean_distance(surface.as_ref(), paper.grid()) / size,
                Err(_) => f64::INFINITY,
            };
            println!(
                "{name}, {n} × {n}: {} passes, mean distance {off:.1e} of the size (the paper's filter {paper_off:.1e})",
                status.passes
            );
            assert!(status.converged && off < 1e-4, "{name}, {n} × {n}: {off:e}, {status:?}");
        }
    }
}
