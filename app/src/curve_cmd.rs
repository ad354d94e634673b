//! `taut smooth-curve`: smooth a polyline given as JSON with NUSD (see
//! `taut_core::nusd::polyline`).
//!
//! Input: `{"points": [[x, y, z], ...], "fixed": [bool, ...], "closed": bool, "tension": [τ, ...]}`;
//! only `points` is required (`fixed` defaults to all true, `tension` to zeros, `closed` to
//! false) and unknown keys are refused, so a misspelt key never passes silently. Output: the same
//! keys for every point of the smoothed polyline in order (input point `k` is point
//! `k · (insert + 1)`; inserted points are moving with tension 0), plus how the solve went.

use clap::Args;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use taut_core::nusd::polyline::{CurveSettings, DEFAULT_MAX_ITERATIONS_CURVE, Polyline, smooth};
use taut_core::nusd::{DEFAULT_LAMBDA_CURVE, DEFAULT_TOL, Spacing};
use taut_core::{DVec3, io};

#[derive(Debug, Args)]
pub struct SmoothCurveArgs {
    /// Curve to smooth (JSON: points, and optionally fixed, closed, tension).
    pub input: PathBuf,
    /// Where to write the smoothed curve (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Moving points inserted evenly on each segment.
    #[arg(long, value_name = "N")]
    pub insert: usize,
    /// Diffusion constant λ in (0, 1).
    #[arg(long, default_value_t = DEFAULT_LAMBDA_CURVE)]
    pub lambda: f64,
    /// Relative tolerance: stop when the estimated distance to convergence is below
    /// tol × bounding-box diagonal.
    #[arg(long, default_value_t = DEFAULT_TOL)]
    pub tol: f64,
    /// Cap on iterations.
    #[arg(long = "max-iter", default_value_t = DEFAULT_MAX_ITERATIONS_CURVE)]
    pub max_iter: usize,
    /// Parametrisation of the edges: chord, uniform or centripetal.
    #[arg(long, default_value = "chord")]
    pub spacing: Spacing,
    /// Write the output even when it is the input file.
    #[arg(long)]
    pub force: bool,
}

/// The curve file as read.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveFile {
    points: Vec<[f64; 3]>,
    #[serde(default)]
    fixed: Option<Vec<bool>>,
    #[serde(default)]
    closed: bool,
    #[serde(default)]
    tension: Option<Vec<f64>>,
}

/// The curve file as written: the smoothed polyline and the solver's report.
#[derive(Debug, Serialize)]
struct SmoothedCurveFile<'a> {
    points: Vec<[f64; 3]>,
    fixed: &'a [bool],
    closed: bool,
    tension: &'a [f64],
    iterations: usize,
    last_step: f64,
    /// `null` when the solve stopped before the contraction rate could be measured.
    remaining_estimate: Option<f64>,
    threshold: f64,
    converged: bool,
    lambda: f64,
    retries: usize,
}

pub fn run(args: &SmoothCurveArgs) -> Result<(), String> {
    crate::cli::check_output(args.force, &[&args.input], &args.output)?;
    let input = args.input.display();
    let text = io::file::read_regular_text(&args.input).map_err(|e| e.to_string())?;
    let file: CurveFile = serde_json::from_str(&text).map_err(|e| format!("{input}: not a valid curve file: {e}"))?;
    let n = file.points.len();
    let control = Polyline {
        points: file.points.iter().map(|p| DVec3::from_array(*p)).collect(),
        fixed: file.fixed.unwrap_or_else(|| vec![true; n]),
        closed: file.closed,
        tension: file.tension.unwrap_or_else(|| vec![0.0; n]),
    };
    let settings = CurveSettings {
        insert: args.insert,
        lambda: args.lambda,
        tol: args.tol,
        max_iterations: args.max_iter,
        spacing: args.spacing,
    };
    let started = std::time::Instant::now();
    let solution = smooth(&control, &settings).map_err(|e| format!("{input}: {e}"))?;
    let elapsed = started.elapsed();

    let curve = &solution.curve;
    let remaining = solution.remaining_estimate;
    let out = SmoothedCurveFile {
        points: curve.points.iter().map(|p| p.to_array()).collect(),
        fixed: &curve.fixed,
        closed: curve.closed,
        tension: &curve.tension,
        iterations: solution.iterations,
        last_step: solution.last_step,
        remaining_estimate: remaining.is_finite().then_some(remaining),
        threshold: solution.threshold,
        converged: solution.converged,
        lambda: solution.lambda_used,
        retries: solution.retries,
    };
    let mut bytes = serde_json::to_vec(&out).map_err(|e| format!("cannot encode the smoothed curve: {e}"))?;
    bytes.push(b'\n');

    io::write_atomic(&args.output, &bytes).map_err(|e| e.to_string())?;
    println!(
        "{} iterations, final step {:.3e}, estimated distance to convergence {:.3e} (threshold {:.3e}){}{}",
        solution.iterations,
        solution.last_step,
        remaining,
        solution.threshold,
        if solution.converged { "" } else { " (iteration cap reached, not converged)" },
        if solution.retries > 0 {
            format!(" (diverged {} times, λ reduced to {})", solution.retries, solution.lambda_used)
        } else {
            String::new()
        },
    );
    println!(
        "wrote {} ({} points: {n} input, {} inserted); solved in {:.1} ms",
        args.output.display(),
        curve.points.len(),
        curve.points.len() - n,
        elapsed.as_secs_f64() * 1e3
    );
    Ok(())
}
