//! What a surface solve reports: budgets for one call, per-level reports and timings, and the
//! status-bar snapshot.

use std::time::Duration;

/// How much work one [`SurfaceSolver::advance`](super::SurfaceSolver::advance) call may do.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Most iterations (summed over levels): sweeps of the level being solved.
    pub iterations: usize,
    /// Wall-clock limit, checked after every step (at most one sweep of one level).
    pub time: Option<Duration>,
}

impl Budget {
    /// No limit: run until converged or diverged.
    pub const UNLIMITED: Budget = Budget { iterations: usize::MAX, time: None };

    /// At most `iterations` iterations.
    pub fn iterations(iterations: usize) -> Self {
        Budget { iterations, time: None }
    }

    /// At most `time` of work (at least one step).
    pub fn time(time: Duration) -> Self {
        Budget { iterations: usize::MAX, time: Some(time) }
    }
}

/// Where a solve stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Levels remain to be iterated.
    Iterating,
    /// Every level is done (converged, or stopped at the iteration cap: see the reports).
    Done,
    /// Even the smallest λ diverged; the state is the last good one.
    Diverged,
}

/// What happened on one level during the latest solve of that level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelReport {
    pub level: u32,
    pub vertices: usize,
    /// Sweeps of this level: plain iterations, or under multigrid its smoothing sweeps and
    /// residual passes (the coarse levels' work inside the cycles is in [`LevelTiming`]).
    pub iterations: usize,
    /// Largest position change of a moving vertex in the last iteration (the last V-cycle under
    /// multigrid).
    pub last_step: f64,
    /// Estimated distance to the fixed point (see [`crate::nusd::convergence`]).
    pub remaining: f64,
    /// True when the estimate fell under the threshold (false: stopped at the cap).
    pub converged: bool,
    /// λ used.
    pub lambda: f64,
}

/// Where the time of one level's latest solve went.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LevelTiming {
    pub level: u32,
    /// Wall-clock time spent on this level's solve (its cycles' coarse work included).
    pub seconds: f64,
    /// Sweeps of this level (as in [`LevelReport::iterations`]).
    pub sweeps: usize,
    /// V-cycles (zero for a plain solve).
    pub cycles: usize,
    /// All work in sweeps of this level: coarse sweeps count by their share of its vertices.
    pub work: f64,
}

/// A snapshot for the status bar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Status {
    pub phase: Phase,
    /// Level being iterated (or the finest, when done).
    pub level: u32,
    pub levels: u32,
    /// Iterations on the current level so far.
    pub iterations: usize,
    /// Iterations since the last edit, all levels.
    pub total_iterations: usize,
    pub last_step: f64,
    pub remaining: f64,
    /// `tol · bbox_diagonal`.
    pub threshold: f64,
    pub lambda: f64,
}

impl Status {
    /// True when every level converged.
    pub fn converged(&self, reports: &[LevelReport]) -> bool {
        self.phase == Phase::Done && reports.iter().all(|r| r.converged)
    }
}
