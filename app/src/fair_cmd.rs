//! `taut fair`: fair a sketched or digitised curve towards a log-aesthetic curve (see
//! `taut_core::aesthetic::filter`).
//!
//! Input and output are point files (`taut_core::io::points`: JSON `{"points": [[x, y], ...]}` or
//! CSV rows `x,y` / `x,y,z`); the output format follows its extension, JSON also carrying α per
//! point and how the filter went. α is given (`--alpha`) or estimated per piece of monotone
//! curvature (`--estimate-alpha`, the default). Prints α, the passes and the LCG residual before
//! and after, whole and per piece.
//!
//! By default the points are first smoothed at the scale their noise allows and the filter holds
//! them to that pre-fit (`taut_core::aesthetic::DataTerm`), so noise is removed and the curve
//! stays where the points were; `--paper` runs the paper's filter on the points as given. Space
//! curves (`--space`) are faired the same way, their torsion held to its law by a damped step
//! over the points around each (`taut_core::aesthetic::filter`).

use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use taut_core::DVec3;
use taut_core::aesthetic::filter::{DEFAULT_DATA_WEIGHT, DEFAULT_MAX_PASSES, DEFAULT_TOLERANCE, DEFAULT_WINDOW};
use taut_core::aesthetic::{
    Alpha, CurveFilter, DataTerm, EstimateSettings, FilterSettings, curvature_graph, estimate_alpha,
    prefit::PrefitModel,
};
use taut_core::curve::{Plane, PointSequence};
use taut_core::io::{self, points};

#[derive(Debug, Args)]
pub struct FairArgs {
    /// Points to fair: .json ({"points": [[x, y], ...]}) or .csv (x,y or x,y,z rows).
    pub input: PathBuf,
    /// Where to write the faired points: .json or .csv.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Slope α of the curvature graph to aim at (−1 clothoid, 0, 1 logarithmic spiral, 2 involute).
    #[arg(long, conflicts_with = "estimate_alpha", allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Estimate α per piece of monotone curvature from a least-squares B-spline (the default).
    #[arg(long)]
    pub estimate_alpha: bool,
    /// Half-width m of the filter's window of 2m + 1 points.
    #[arg(long, default_value_t = DEFAULT_WINDOW)]
    pub window: usize,
    /// Cap on filter passes [default: until converged, at most 10000].
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Stop when a pass moves no point by more than this fraction of the mean spacing.
    #[arg(long, default_value_t = DEFAULT_TOLERANCE)]
    pub tolerance: f64,
    /// Fair a space curve: control torsion too (μ^β = g s + h for the radius of torsion μ).
    #[arg(long)]
    pub space: bool,
    /// β of the torsion law (with --space).
    #[arg(long, requires = "space", default_value_t = 1.0, allow_negative_numbers = true)]
    pub torsion_beta: f64,
    /// The paper's filter on the points as given: no smoothing pre-fit and no data term (on
    /// dense or very noisy points it moves the curve away from them).
    #[arg(long, conflicts_with_all = ["data_weight", "smoothing"])]
    pub paper: bool,
    /// Weight λ in [0, 1) of the data term: the share of each move that pulls a point back
    /// towards the smoothing pre-fit.
    #[arg(long, default_value_t = DEFAULT_DATA_WEIGHT)]
    pub data_weight: f64,
    /// Smoothing μ of the pre-fit [default: chosen from the points by cross-validation].
    #[arg(long)]
    pub smoothing: Option<f64>,
    /// Treat the points as a closed curve (a JSON file can also say "closed": true).
    #[arg(long)]
    pub closed: bool,
    /// Write the output even when it is the input file.
    #[arg(long)]
    pub force: bool,
}

/// One piece of the curve and its α, for the report and the output.
#[derive(Debug, Serialize)]
struct Piece {
    first_point: usize,
    last_point: usize,
    alpha: f64,
    estimate_residual: f64,
    lcg_residual_before: Option<f64>,
    lcg_residual_after: Option<f64>,
}

#[derive(Debug, Serialize)]
struct FairedFile {
    points: Vec<Vec<f64>>,
    closed: bool,
    alpha: Vec<f64>,
    pieces: Vec<Piece>,
    passes: usize,
    converged: bool,
    last_move: f64,
    lcg_residual_before: Option<f64>,
    lcg_residual_after: Option<f64>,
    lcg_slope_after: Option<f64>,
    /// The pre-fit's smoothing and the noise level it read (absent with `--paper`).
    prefit_smoothing: Option<f64>,
    prefit_noise: Option<f64>,
}

pub fn run(args: &FairArgs) -> Result<(), String> {
    crate::cli::check_output(args.force, &[&args.input], &args.output)?;
    if args.iterations == Some(0) {
        return Err("--iterations 0: a fairing needs at least one pass; give 1 or more (default 10000)".into());
    }
    let input = args.input.display().to_string();
    let file = points::read_points(&args.input).map_err(|e| e.to_string())?;
    let out_kind = crate::surface_cmd::extension(&args.output);
    if out_kind != "json" && out_kind != "csv" {
        return Err(format!("{}: unsupported output; use .json or .csv", args.output.display()));
    }
    let curve = PointSequence::new(file.points.clone(), file.closed || args.closed);
    let torsion_beta = args.space.then_some(args.torsion_beta);
    let window = args.window;
    // The plane the planar filter works in orients the signed curvature of α estimation too.
    let normal = if args.space { None } else { Plane::fit(&curve.points).map(|p| p.normal) };
    let (alpha, pieces) = match args.alpha {
        Some(a) => (Alpha::Uniform(a), Vec::new()),
        None => {
            curve.validate(2 * window + 1).map_err(|e| format!("{input}: {e}"))?;
            let estimate = estimate_alpha(&curve, normal, &EstimateSettings::default())
                .map_err(|e| format!("{input}: cannot estimate α ({e})"))?;
            let per_point = estimate.per_point();
            let pieces: Vec<Piece> = estimate
                .pieces
                .iter()
                .filter_map(|p| {
                    let inside: Vec<usize> =
                        (0..curve.len()).filter(|&i| (p.start..=p.end).contains(&estimate.parameters[i])).collect();
                    Some(Piece {
                        first_point: *inside.first()?,
                        last_point: *inside.last()?,
                        alpha: p.alpha,
                        estimate_residual: p.residual,
                        lcg_residual_before: None,
                        lcg_residual_after: None,
                    })
                })
                .collect();
            (Alpha::PerPoint(per_point), pieces)
        }
    };
    let settings = FilterSettings {
        window,
        alpha,
        torsion_beta,
        tolerance: args.tolerance,
        max_passes: args.iterations.unwrap_or(DEFAULT_MAX_PASSES),
        data_term: (!args.paper).then_some(DataTerm { weight: args.data_weight, smoothing: args.smoothing }),
        ..FilterSettings::default()
    };
    let mut filter = CurveFilter::new(&curve, settings).map_err(|e| format!("{input}: {e}"))?;
    if filter.off_plane_distance() > 1e-9 * curve.diagonal() {
        crate::cli::note(format!(
            "the points were projected onto their best-fit plane (farthest {:.3e} away); use --space to keep them \
             in 3D",
            filter.off_plane_distance()
        ));
    }
    if let Some(fit) = filter.prefit() {
        println!(
            "pre-fit: smoothing {:.3e} ({:.1} degrees of freedom for {} points), noise level {:.3e} (RMS)",
            fit.smoothing,
            fit.dof,
            curve.len(),
            fit.noise
        );
        match fit.model {
            PrefitModel::Smoothed => {}
            PrefitModel::Segment { alpha } => println!(
                "pre-fit: one log-aesthetic segment (α {alpha:.3}) through the end points explains the points to the \
                 noise level; they start on it"
            ),
            PrefitModel::Circle { radius } => println!(
                "pre-fit: one circle (radius {radius:.6e}) explains the points to the noise level; they start on it"
            ),
        }
    }
    let started = std::time::Instant::now();
    let status = filter.run_to_convergence().map_err(|e| format!("{input}: {e}"))?;
    let elapsed = started.elapsed();

    let plane_normal = filter.plane().map(|p| p.normal);
    let before = curvature_graph(&PointSequence::new(filter_input(&filter, &curve), curve.closed), plane_normal);
    let after = curvature_graph(&filter.sequence(), plane_normal);
    let mut pieces = pieces;
    for p in &mut pieces {
        p.lcg_residual_before = before.fit_range(p.first_point, p.last_point).map(|f| f.residual);
        p.lcg_residual_after = after.fit_range(p.first_point, p.last_point).map(|f| f.residual);
    }
    let show = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.3e}"));
    match args.alpha {
        Some(a) => println!("α = {a} (given)"),
        None => {
            println!("α estimated per piece of monotone curvature:");
            for (k, p) in pieces.iter().enumerate() {
                println!(
                    "  piece {}: points {}–{}: α = {:.3} (fit residual {:.2e}); LCG residual before {}, after {}",
                    k + 1,
                    p.first_point,
                    p.last_point,
                    p.alpha,
                    p.estimate_residual,
                    show(p.lcg_residual_before),
                    show(p.lcg_residual_after)
                );
            }
        }
    }
    println!(
        "{} passes in {:.1} ms, last move {:.2e} of the mean spacing{}",
        status.passes,
        elapsed.as_secs_f64() * 1e3,
        status.last_move,
        if status.converged { " (converged)" } else { " (pass cap reached, not converged)" }
    );
    println!(
        "LCG residual of the whole curve: before {}, after {} (slope after {})",
        show(before.fit.map(|f| f.residual)),
        show(after.fit.map(|f| f.residual)),
        after.fit.map_or("none".to_string(), |f| format!("{:.3}", f.slope))
    );

    let dimension = if args.space { 3 } else { file.dimension };
    let mut faired = filter.points().to_vec();
    if dimension == 2 {
        // Flat input is filtered in its own plane z = const; keep the file's two coordinates.
        faired.iter_mut().for_each(|p| p.z = 0.0);
    }
    let bytes = if out_kind == "csv" {
        points::to_csv(&faired, dimension).into_bytes()
    } else {
        let out = FairedFile {
            points: points::to_json_arrays(&faired, dimension),
            closed: curve.closed,
            alpha: filter.alpha().to_vec(),
            pieces,
            passes: status.passes,
            converged: status.converged,
            last_move: status.last_move,
            lcg_residual_before: before.fit.map(|f| f.residual),
            lcg_residual_after: after.fit.map(|f| f.residual),
            lcg_slope_after: after.fit.map(|f| f.slope),
            prefit_smoothing: filter.prefit().map(|p| p.smoothing),
            prefit_noise: filter.prefit().map(|p| p.noise),
        };
        let mut bytes = serde_json::to_vec(&out).map_err(|e| format!("cannot encode the faired curve: {e}"))?;
        bytes.push(b'\n');
        bytes
    };
    io::write_atomic(&args.output, &bytes).map_err(|e| e.to_string())?;
    println!("wrote {} ({} points)", args.output.display(), faired.len());
    Ok(())
}

/// The input as the filter saw it (projected onto its plane for the planar filter), so the LCG
/// before and after compare like with like.
fn filter_input(filter: &CurveFilter, curve: &PointSequence) -> Vec<DVec3> {
    match filter.plane() {
        Some(plane) => curve.points.iter().map(|p| plane.project(*p)).collect(),
        None => curve.points.clone(),
    }
}
