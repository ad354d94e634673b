//! Log-aesthetic curves (Miura, Yoshida and Saito, "Discrete log-aesthetic filter", seed
//! `003_0c1161d9995b9b01`; our reading is `shared/spec/log-aesthetic.md`).

pub mod coons;
pub mod estimate;
pub mod filter;
pub mod law;
pub mod lcg;
pub mod segment;
pub mod surface;

pub use coons::{BoundaryCurve, coons_patch, grid_mesh};
pub use estimate::{AlphaEstimate, AlphaPiece, EstimateSettings, estimate_alpha};
pub use filter::{Alpha, CurveFilter, FilterSettings, FilterStatus, InflectionRule, fair};
pub use law::{LineFit, fit_line};
pub use lcg::{CurvatureGraph, LcgPoint, curvature_graph};
pub use segment::AestheticSegment;
pub use surface::{Grid, SurfaceFilter, SurfaceSettings, SurfaceStatus, gaussian_curvature};
