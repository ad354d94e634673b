//! Log-aesthetic curves (Miura, Yoshida and Saito, "Discrete log-aesthetic filter", seed
//! `003_0c1161d9995b9b01`; our reading is `docs/log-aesthetic.md`).
//!
//! A log-aesthetic curve has a radius of curvature with `ρ^α = c s + d` in arc length (clothoid
//! α = −1, logarithmic spiral α = 1, circle involute α = 2), so its logarithmic curvature graph
//! is a straight line of slope α.
//!
//! - [`law`]: the law and the least-squares lines fitted to it.
//! - [`filter`]: the planar and spatial curve filters, run pass by pass ([`CurveFilter::run`]
//!   takes a number of passes and reports [`FilterStatus`]: passes, last move, residual,
//!   converged), so an editor can run a few passes a frame and stop or continue.
//! - [`prefit`]: the smoothing pre-fit, with μ chosen by GCV, that the shape-keeping fairing
//!   starts from and is held to ([`DataTerm`]).
//! - [`estimate`]: α per piece of monotone curvature from a least-squares B-spline.
//! - [`lcg`]: the curvature graph and LCG of any point sequence with the fitted line, for plots.
//! - [`segment`]: Yoshida–Saito segments from three control points and α.
//! - [`surface`]: the constant-Gaussian-curvature filter on regular grids, and
//!   [`surface_prefit`] the smoothing pre-fit its shape-keeping variant starts from.
//! - [`coons`]: bilinearly blended Coons patches from four boundary curves.

pub mod coons;
pub mod estimate;
pub mod filter;
mod filter_geometry;
mod filter_planar;
pub mod law;
pub mod lcg;
pub mod prefit;
pub mod segment;
pub mod segment_fit;
pub mod space_fit;
pub mod surface;
pub mod surface_prefit;

pub use coons::{BoundaryCurve, coons_patch, grid_mesh};
pub use estimate::{AlphaEstimate, AlphaPiece, EstimateSettings, estimate_alpha};
pub use filter::{Alpha, CurveFilter, DataTerm, FilterSettings, FilterStatus, InflectionRule, fair};
pub use law::{LineFit, fit_line};
pub use lcg::{CurvatureGraph, LcgPoint, curvature_graph};
pub use prefit::{Prefit, prefit};
pub use segment::AestheticSegment;
pub use surface::{Grid, SurfaceFilter, SurfaceSettings, SurfaceStatus, gaussian_curvature};
pub use surface_prefit::{GridPrefit, prefit_grid};
