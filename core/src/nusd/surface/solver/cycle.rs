//! The solver's multigrid driver: V-cycles on the level being solved, one step at a time, with
//! the stopping and divergence rules measured per cycle.
//!
//! Stopping: the change `δ` of the level over a cycle shrinks by the cycle's contraction `ρ`
//! (about the same for smooth and rough error, which is the point of multigrid), so the
//! distance left is estimated as the tail `δ ρ / (1 − ρ)`, with `ρ` the largest ratio of
//! successive changes measured in this solve and never below the rate this level showed in its
//! previous solves ([`Level::cycle_rate`](super::super::level::Level)), so that a warm start
//! that needs a single cycle is judged by the rate seen before. Divergence: a non-finite or
//! huge change, changes growing for three cycles, or no real progress (ratios over 0.9) for
//! eight: the level is rolled back and solved by the plain iteration, with its own fallback
//! (halving λ), until the tensions or fixed flags change.

use super::SurfaceSolver;
use crate::DVec3;
use crate::nusd::surface::direct::Direct;
use crate::nusd::surface::irregular::IrregularBlocks;
use crate::nusd::surface::multigrid::{self, COARSE_REDUCTION, COARSE_SWEEPS, Op, RELAX_COARSE_REDUCTION};

/// Cycles over which the contraction is measured.
const RATE_WINDOW: usize = 3;

/// The cycle in progress on the active level, and the changes of the cycles done so far.
#[derive(Clone, Debug, Default)]
pub(super) struct CycleRun {
    ops: Vec<Op>,
    next: usize,
    /// The level's positions when the cycle began.
    start_p: Vec<DVec3>,
    /// The first step of the coarse-grid smoothing in progress, and its sweeps.
    coarse_first: Option<f64>,
    coarse_sweeps: usize,
    /// Largest change of a moving vertex over each cycle of this solve.
    changes: Vec<f64>,
    /// How far the coarsest grid's smoothing brings its step down in the cycle in progress.
    coarse_reduction: f64,
}

impl CycleRun {
    pub fn reset(&mut self) {
        self.ops.clear();
        self.next = 0;
        self.coarse_first = None;
        self.coarse_sweeps = 0;
        self.changes.clear();
    }

    pub fn cycles(&self) -> usize {
        self.changes.len()
    }

    pub fn last_change(&self) -> f64 {
        self.changes.last().copied().unwrap_or(f64::INFINITY)
    }

    /// The largest contraction measured between successive cycles among the last
    /// [`RATE_WINDOW`] cycles.
    pub fn measured_rate(&self) -> Option<f64> {
        let n = self.changes.len();
        let recent = &self.changes[n.saturating_sub(RATE_WINDOW + 1)..];
        recent.windows(2).map(|w| if w[0] > 0.0 { w[1] / w[0] } else { 0.0 }).reduce(f64::max)
    }

    /// Estimated distance to the fixed point after the last cycle.
    pub fn remaining(&self, prior_rate: f64) -> f64 {
        let Some(&change) = self.changes.last() else { return f64::INFINITY };
        if change == 0.0 {
            return 0.0;
        }
        let rate = self.measured_rate().map_or(prior_rate, |r| r.max(prior_rate));
        if rate < 1.0 { change * rate / (1.0 - rate) } else { f64::INFINITY }
    }

    /// Ratios of the last `count` successive changes all above `bound`.
    fn ratios_above(&self, count: usize, bound: f64) -> bool {
        let n = self.changes.len();
        n > count && self.changes[n - count - 1..].windows(2).all(|w| w[1] > bound * w[0])
    }
}

impl SurfaceSolver {
    /// One step of a V-cycle on the active level. Returns the iterations counted (sweeps and
    /// residual passes of the active level itself).
    pub(super) fn cycle_step(&mut self) -> usize {
        let top = self.active;
        if self.cycle.next >= self.cycle.ops.len() {
            // Gauss–Seidel at the top of a level without tension (tensioned levels keep the
            // schedule, with whose cycles their fallback to the plain iteration was measured).
            let relax_top = self.levels[top].operator.overrides.is_empty();
            let coarsest = self.cycle_coarsest(top);
            self.cycle.ops = multigrid::cycle(top, coarsest, multigrid::GAMMA, relax_top);
            self.cycle.coarse_reduction = if relax_top { RELAX_COARSE_REDUCTION } else { COARSE_REDUCTION };
            self.cycle.next = 0;
            let level = &self.levels[top];
            match &level.region {
                Some(region) => {
                    self.cycle.start_p.clear();
                    self.cycle.start_p.extend(region.vertices.iter().map(|&v| level.state.p[v as usize]));
                }
                None => self.cycle.start_p.clone_from(&level.state.p),
            }
        }
        let op = self.cycle.ops[self.cycle.next];
        // Work in sweeps of the top level: a region's sweep costs its share of the level.
        let size = |solver: &Self, k: usize| {
            let level = &solver.levels[k];
            level.region.as_ref().map_or(level.vertex_count(), |r| r.len()) as f64
        };
        let whole = self.levels[top].vertex_count() as f64;
        let share = |solver: &Self, k: usize| size(solver, k) / whole;
        let lambda = self.lambda;
        let mut counted = 0;
        let work;
        match op {
            Op::Smooth(k, schedule) => {
                // The divergence fallback scales the whole schedule with λ.
                let scale = lambda / self.settings.lambda;
                let sweep = multigrid::smooth(&mut self.levels[k].grid(k == top), schedule * scale);
                work = share(self, k);
                self.cycle.next += 1;
                if k == top {
                    counted = 1;
                    if !sweep.step.is_finite() {
                        self.count(top, counted, work);
                        self.abandon_multigrid("a value became infinite");
                        return counted;
                    }
                }
            }
            Op::Relax(k, schedule) => {
                let scale = lambda / self.settings.lambda;
                let sweep = multigrid::relax(&mut self.levels[k].grid(k == top), schedule * scale);
                work = share(self, k);
                self.cycle.next += 1;
                counted = 1;
                if !sweep.step.is_finite() {
                    self.count(top, counted, work);
                    self.abandon_multigrid("a value became infinite");
                    return counted;
                }
            }
            Op::Restrict(k) => {
                let (coarse, fine) = self.levels.split_at_mut(k);
                multigrid::restrict(&mut fine[0].grid(k == top), &mut coarse[k - 1].grid(false));
                work = share(self, k) + share(self, k - 1);
                counted = usize::from(k == top);
                self.cycle.next += 1;
            }
            Op::Coarse(c) if self.levels[top].region.is_none() && self.solve_directly(c) => {
                // The coarse problem solved exactly (see `direct.rs`): one residual pass and
                // the factors' triangular solves.
                let level = &mut self.levels[c];
                let work_state = level.work.as_mut().expect("a restricted coarse grid has scratch");
                if let Direct::Made(direct) = &mut level.direct {
                    direct.step(
                        &level.operator,
                        &level.topology.mesh,
                        &mut work_state.state,
                        Some(&work_state.forcing),
                    );
                }
                work = share(self, c);
                self.cycle.next += 1;
            }
            Op::Coarse(c) => {
                let step = multigrid::smooth(&mut self.levels[c].grid(false), lambda).step;
                work = share(self, c);
                self.cycle.coarse_sweeps += 1;
                let first = *self.cycle.coarse_first.get_or_insert(step);
                // NaN ends the coarse smoothing too; the cycle's change then shows it.
                let settled =
                    step.partial_cmp(&(self.cycle.coarse_reduction * first)) != Some(std::cmp::Ordering::Greater);
                if settled || self.cycle.coarse_sweeps >= COARSE_SWEEPS {
                    self.cycle.coarse_first = None;
                    self.cycle.coarse_sweeps = 0;
                    self.cycle.next += 1;
                }
            }
            Op::Blocks(k) => {
                let level = &mut self.levels[k];
                work = if level.region.is_none() {
                    let blocks = level
                        .irregular
                        .get_or_insert_with(|| IrregularBlocks::new(&level.operator, &level.topology.mesh));
                    blocks.solve(&level.operator, &level.topology.mesh, &mut level.state, None);
                    blocks.work(&level.operator)
                } else {
                    0.0
                };
                self.cycle.next += 1;
            }
            Op::Correct(k) => {
                let (coarse, fine) = self.levels.split_at_mut(k);
                multigrid::correct(&mut coarse[k - 1].grid(false), &mut fine[0].grid(k == top));
                work = 0.5 * share(self, k);
                self.cycle.next += 1;
            }
        }
        self.count(top, counted, work);
        if self.cycle.next == self.cycle.ops.len() {
            self.end_cycle();
        }
        counted
    }

    /// The cycles diverged: restore the level and solve it by the plain iteration (whose own
    /// fallback, halving λ, then applies). Strong tension does this: its `R_i^j` terms act on
    /// one ring of vertices, twice as wide on the coarser level, so the coarse problem's response
    /// near them is off by that much and the correction overshoots.
    fn abandon_multigrid(&mut self, why: &str) {
        let snapshot = self.snapshot.as_ref().expect("a level being iterated has a snapshot");
        let level = &mut self.levels[self.active];
        snapshot.restore(&mut level.state);
        level.multigrid_failed = true;
        self.cycle.reset();
        self.monitor.reset();
        self.blocks.reset();
        self.level_iterations = 0;
        self.events.push(format!(
            "level {}: the multigrid cycles diverged ({why}); restored the last good state and solving it by the plain iteration",
            self.active
        ));
    }

    fn count(&mut self, level: usize, iterations: usize, work: f64) {
        self.level_iterations += iterations;
        self.total_iterations += iterations;
        let timing = self.timing(level);
        timing.sweeps += iterations;
        timing.work += work;
    }

    /// Measures the cycle just finished and applies the stopping and divergence rules.
    fn end_cycle(&mut self) {
        let top = self.active;
        let level = &self.levels[top];
        let change = match &level.region {
            Some(region) => multigrid::largest_change_on(&level.operator, region, &self.cycle.start_p, &level.state.p),
            None => multigrid::largest_change(&level.operator, &self.cycle.start_p, &level.state.p),
        };
        self.cycle.changes.push(change);
        self.timing(top).cycles += 1;
        let why = if !change.is_finite() {
            Some("a value became infinite")
        } else if change > 10.0 * self.diagonal {
            Some("the step kept growing")
        } else if self.cycle.ratios_above(3, 1.0) && change > self.threshold {
            Some("the cycles kept growing")
        } else if self.cycle.ratios_above(8, 0.9) && change > self.threshold {
            Some("the cycles stopped converging: an oscillation")
        } else {
            None
        };
        if let Some(why) = why {
            self.abandon_multigrid(why);
            return;
        }
        let remaining = self.cycle.remaining(self.levels[top].cycle_rate);
        if change < self.threshold && remaining < self.threshold {
            if self.local_accepts(remaining) {
                self.finish_level(true);
            }
        } else if self.level_iterations >= self.settings.max_iterations {
            self.finish_level(false);
        }
    }
}
