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
//! Divergence (a non-finite value, a step larger than the model, a step growing for
//! [`DIVERGENCE_GROWTH`] iterations in a row past every earlier step, or an oscillation: the
//! largest step reversing direction for [`OSCILLATION_ITERATIONS`] in a row) restores the state the level started from, halves λ
//! and tries again, down to [`MIN_LAMBDA`]; each retry is reported as an event.
//!
//! Before solving, [`check_anchoring`] refuses cages whose fixed vertices cannot hold the
//! surface (it would collapse or flatten), and cages of extreme size are solved in a frame
//! scaled by a power of two ([`frame`]), so any finite cage is handled.

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
/// Consecutive iterations whose largest step reverses direction taken as an oscillation (the
/// explicit iteration unstable at this λ, seen with strong tension at λ = 0.6; its growth is
/// bounded by the nonlinear tension term, so it never diverges): treated like divergence.
pub const OSCILLATION_ITERATIONS: usize = 64;
/// Smallest λ tried before a solve is declared diverged.
pub const MIN_LAMBDA: f64 = 0.01;
