//! The hierarchical NUSD surface solver the editor drives every frame (`docs/nusd.md`, "Surfaces").
//!
//! Level 0 is the cage. Each level is refined from the previous one ([`hierarchy`]), its
//! operator is built from the unsmoothed domain ([`operator`]), and it is solved to convergence
//! before the next level is made: the cage (and level 1, unless some cage vertex moves) by the
//! plain NUSD iteration ([`kernel`]) or, when it is small and has no tension, by a sparse direct
//! solve ([`direct`]), every finer level by multigrid W-cycles that use the coarser levels as
//! coarse grids and the NUSD iteration as smoother ([`multigrid`]). Multigrid reaches
//! the same fixed point in a number of sweeps that stays flat with the level, where the plain
//! iteration's grows; [`SurfaceSolver::set_multigrid`] turns it off for comparisons.
//!
//! [`SurfaceSolver`] keeps every level's state between calls. An edit (a moved fixed point, a
//! changed tension, flag or setting) updates the level set-up only where the cage changed
//! (the domain and the operator rows that see a moved vertex, in `level.rs`) and *warm-starts*: the change
//! of the cage is prolonged down to every finer level at once, so the finest surface follows the
//! edit immediately, and the levels are then re-solved from coarse to fine, each starting from
//! its previous solution plus the prolonged correction of the level above. After an edit that
//! only moved cage vertices, each level is re-solved *locally* ([`local`]): only within a few cage
//! rings of the moved vertices, the rest held, with the change beyond the region measured and the
//! region grown until it is small (a drag of a million-vertex surface costs a few plain iterations
//! of it instead of a whole re-solve). Work is done in
//! [`SurfaceSolver::advance`] calls bounded by an iteration count and a time budget, checked
//! after every step of at most one sweep; [`SurfaceSolver::converged_level`],
//! [`SurfaceSolver::level_surface`] and [`SurfaceSolver::timings`] tell an editor which level has
//! settled, show any level, and say where the time went.
//!
//! Divergence of the plain iteration (a non-finite value, a step larger than the model, a step
//! growing for [`DIVERGENCE_GROWTH`] iterations in a row past every earlier step, or an
//! oscillation: the largest step reversing direction for [`OSCILLATION_ITERATIONS`] in a row)
//! restores the state the level started from, halves λ and tries again, down to
//! [`MIN_LAMBDA`]; divergence of the cycles (strong tension) restores the level and solves it by
//! the plain iteration. Each retry is reported as an event.
//!
//! Before solving, [`check_anchoring`] refuses cages whose fixed vertices cannot hold the
//! surface (it would collapse or flatten), and cages of extreme size are solved in a frame
//! scaled by a power of two ([`frame`]), so any finite cage is handled.

pub mod anchoring;
pub mod direct;
pub mod frame;
pub mod hierarchy;
mod input;
pub mod irregular;
pub mod kernel;
mod level;
pub mod local;
pub mod multigrid;
pub mod operator;
mod solver;
mod status;
pub mod survival;

pub use anchoring::check_anchoring;
pub use input::NusdInput;
pub use solver::SurfaceSolver;
pub use status::{Budget, LevelReport, LevelTiming, Phase, Status};

/// Consecutive growing steps taken as divergence.
pub const DIVERGENCE_GROWTH: usize = 64;
/// Consecutive iterations whose largest step reverses direction taken as an oscillation (the
/// explicit iteration unstable at this λ, seen with strong tension at λ = 0.6; its growth is
/// bounded by the nonlinear tension term, so it never diverges): treated like divergence.
pub const OSCILLATION_ITERATIONS: usize = 64;
/// Smallest λ tried before a solve is declared diverged.
pub const MIN_LAMBDA: f64 = 0.01;
