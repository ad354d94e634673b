//! The hierarchical NUSD surface solver the editor drives every frame (spec: "Surfaces").
//!
//! Level 0 is the cage. Each level is refined from the previous one
//! ([`hierarchy`]), its operator is built from the unsmoothed domain ([`operator`]), and it is
//! iterated to convergence ([`kernel`]) before the next level is made.
//!
//! [`SurfaceSolver`] keeps every level's state between calls. An edit (a moved fixed point, a
//! changed tension, flag or setting) rebuilds only the operators and *warm-starts*: the change of
//! the cage is prolonged down to every finer level at once, so the finest surface follows the
//! edit immediately, and the levels are then re-solved from coarse to fine, each starting from
//! its previous solution plus the prolonged correction of the level above. Work is done in
//! [`SurfaceSolver::advance`] calls bounded by an iteration count and a time budget.
//!
//! Divergence (a non-finite value, a step larger than the model, or a step growing for
//! [`DIVERGENCE_GROWTH`] iterations in a row past every earlier step) restores the state the level started from, halves
//! λ and tries again, down to [`MIN_LAMBDA`]; each retry is reported as an event.

pub mod anchoring;
pub mod frame;
pub mod hierarchy;
pub mod kernel;
pub mod operator;
mod solver;

pub use anchoring::check_anchoring;
pub use solver::{Budget, LevelReport, Phase, Status, SurfaceSolver};

/// Consecutive growing steps taken as divergence.
pub const DIVERGENCE_GROWTH: usize = 64;
/// Smallest λ tried before a solve is declared diverged.
pub const MIN_LAMBDA: f64 = 0.01;
