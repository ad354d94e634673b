//! `taut fair-surface`: the constant-Gaussian-curvature filter on a regular grid of points (see
//! `taut_core::aesthetic::surface`).
//!
//! `GRID.json` is `{"grid": [[[x, y, z], ...], ...]}`, rows of points, every row as long; the
//! boundary rows and columns stay fixed. By default the grid is first smoothed at the scale its
//! noise allows and the filter holds it to that pre-fit (`SurfaceSettings::keeping_shape`), so a
//! measured grid loses its noise and keeps its shape; `--paper` runs the paper's filter on the
//! points as given. The output has the same grid, how the filter went, and
//! the mean and standard deviation of the Gaussian curvature over the interior before and after.

use clap::Args;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use taut_core::aesthetic::{DataTerm, Grid, SurfaceFilter, SurfaceSettings, gaussian_curvature};
use taut_core::{DVec3, io};

#[derive(Debug, Args)]
pub struct FairSurfaceArgs {
    /// The grid (JSON: {"grid": [[[x, y, z], ...], ...]}).
    pub input: PathBuf,
    /// Where to write the filtered grid (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Cap on passes [default: until converged, at most 5000].
    #[arg(long)]
    pub iterations: Option<usize>,
    /// The paper's filter on the points as given: no smoothing pre-fit and no data term (on
    /// noisy points it moves the surface; the default keeps it where the points were).
    #[arg(long)]
    pub paper: bool,
    /// Weight λ of the data term, in [0, 1): the share of each move that pulls a point back
    /// towards the smoothed grid.
    #[arg(long, default_value_t = taut_core::aesthetic::filter::DEFAULT_DATA_WEIGHT, conflicts_with = "paper")]
    pub data_weight: f64,
    /// The pre-fit's smoothing μ [default: chosen from the points by cross-validation].
    #[arg(long, conflicts_with = "paper")]
    pub smoothing: Option<f64>,
    /// Write the output even when it is the input file.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GridFile {
    grid: Vec<Vec<[f64; 3]>>,
}

#[derive(Debug, Serialize, Clone, Copy)]
struct Stats {
    mean: f64,
    std_dev: f64,
}

#[derive(Debug, Serialize)]
struct FilteredGrid {
    grid: Vec<Vec<[f64; 3]>>,
    passes: usize,
    converged: bool,
    gaussian_curvature_before: Option<Stats>,
    gaussian_curvature_after: Option<Stats>,
}

fn stats(grid: &Grid) -> Option<Stats> {
    let k: Vec<f64> = gaussian_curvature(grid).into_iter().flatten().collect();
    if k.is_empty() {
        return None;
    }
    let mean = k.iter().sum::<f64>() / k.len() as f64;
    let std_dev = (k.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / k.len() as f64).sqrt();
    Some(Stats { mean, std_dev })
}

pub fn run(args: &FairSurfaceArgs) -> Result<(), String> {
    crate::cli::check_output(args.force, &[&args.input], &args.output)?;
    let input = args.input.display();
    if crate::surface_cmd::extension(&args.output) != "json" {
        return Err(format!("{}: the grid is written as JSON; use a .json file name", args.output.display()));
    }
    let text = taut_core::io::file::read_regular_text(&args.input).map_err(|e| e.to_string())?;
    let file: GridFile = serde_json::from_str(&text)
        .map_err(|e| format!("{input}: not a valid grid file ({{\"grid\": [[[x, y, z], ...], ...]}}): {e}"))?;
    let cols = file.grid.first().map_or(0, |r| r.len());
    if let Some(i) = file.grid.iter().position(|r| r.len() != cols) {
        return Err(format!(
            "{input}: row {i} has {} points but row 0 has {cols}; every row must be as long",
            file.grid[i].len()
        ));
    }
    let rows = file.grid.len();
    let grid = Grid { rows, cols, points: file.grid.iter().flatten().map(|p| DVec3::from_array(*p)).collect() };
    let mut settings = if args.paper {
        SurfaceSettings::default()
    } else {
        SurfaceSettings {
            data_term: Some(DataTerm { weight: args.data_weight, smoothing: args.smoothing }),
            ..SurfaceSettings::default()
        }
    };
    if let Some(n) = args.iterations {
        settings.max_passes = n;
    }
    let before = stats(&grid);
    let mut filter = SurfaceFilter::new(grid, settings).map_err(|e| format!("{input}: {e}"))?;
    if let Some(fit) = filter.prefit() {
        println!(
            "pre-fit: smoothing {:.3e} ({:.1} degrees of freedom for {} interior points), noise level {:.3e} (RMS)",
            fit.smoothing,
            fit.dof,
            (rows - 2) * (cols - 2),
            fit.noise
        );
    }
    let status = filter.run_to_convergence().map_err(|e| format!("{input}: {e}"))?;
    let after = stats(filter.grid());
    let show = |s: Option<Stats>| {
        s.map_or("none".into(), |s| format!("mean {:.4e}, standard deviation {:.3e}", s.mean, s.std_dev))
    };
    println!(
        "{} passes{}; Gaussian curvature before: {}; after: {}{}",
        status.passes,
        if status.converged { " (converged)" } else { " (pass cap reached, not converged)" },
        show(before),
        show(after),
        if status.held > 0 {
            format!("; {} points had no reachable target in the last pass", status.held)
        } else {
            String::new()
        }
    );
    let g = filter.grid();
    let out = FilteredGrid {
        grid: (0..g.rows).map(|i| (0..g.cols).map(|j| g.at(i, j).to_array()).collect()).collect(),
        passes: status.passes,
        converged: status.converged,
        gaussian_curvature_before: before,
        gaussian_curvature_after: after,
    };
    let mut bytes = serde_json::to_vec(&out).map_err(|e| format!("cannot encode the grid: {e}"))?;
    bytes.push(b'\n');
    io::write_atomic(&args.output, &bytes).map_err(|e| e.to_string())?;
    println!("wrote {} ({} × {} points)", args.output.display(), g.rows, g.cols);
    Ok(())
}
