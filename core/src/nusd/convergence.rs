//! The stopping rule shared by the curve and surface solvers.
//!
//! The paper stops when the largest step of a moving point falls under `T`. When many points
//! are inserted between fixed points the iteration contracts slowly (its rate `ρ` approaches 1),
//! so a small step does not mean a small remaining error: a polyline with 16 inserted points per
//! segment stops 5 % of its size away from its fixed point at `T = 1e-3`. We therefore estimate
//! the remaining distance from the step and the observed contraction rate, as the tail of a
//! geometric series, `step · ρ / (1 − ρ)`, and stop when *that* is under `T`.
//!
//! `ρ` is the geometric mean of the step ratio over the last [`WINDOW`] iterations, which damps
//! the oscillation of the first iterations after a split or an edit; it is taken as the larger
//! of that and the rate over the window before, because right after a warm start the fast modes
//! die first and a single window overstates the contraction (a re-solve after undo stopped 7×
//! the threshold away with one window). While the steps are not shrinking, the estimate is
//! infinite and the solve goes on. The estimate is not a guaranteed
//! bound: for the iteration's Jordan-block modes it is low by a factor that tends to 1, and
//! while faster modes still carry the largest step the measured rate is that of the fast modes
//! and the slow ones hold the error: on the default scene with two rings unfixed, at tol 1e-3,
//! the plain iteration stopped 4–6 thresholds from its fixed point (up to 18 after a warm start).
//! Surface levels solved by multigrid use the per-cycle estimate of `surface::solver::cycle`
//! instead, whose contraction is the same for smooth and rough error and which stays true.

/// Iterations over which the contraction rate is measured.
pub const WINDOW: usize = 8;

/// Tracks the recent step sizes of one solve and estimates the remaining distance.
#[derive(Clone, Debug)]
pub struct ConvergenceMonitor {
    history: std::collections::VecDeque<f64>,
    growing: usize,
    /// Largest step before the last one.
    peak_before: f64,
    /// Largest step so far.
    peak: f64,
    /// Consecutive iterations whose largest step was mostly a reversing one.
    reversing: usize,
}

impl Default for ConvergenceMonitor {
    fn default() -> Self {
        ConvergenceMonitor { history: Default::default(), growing: 0, peak_before: 0.0, peak: 0.0, reversing: 0 }
    }
}

impl ConvergenceMonitor {
    /// Forget everything: called after a split, an edit or a rollback.
    pub fn reset(&mut self) {
        self.history.clear();
        self.growing = 0;
        self.peak_before = 0.0;
        self.peak = 0.0;
        self.reversing = 0;
    }

    /// Record the largest step of one iteration and the largest step of a vertex that reversed
    /// its direction (see [`oscillating`](Self::oscillating)).
    pub fn push_sweep(&mut self, step: f64, reversing: f64) {
        if reversing >= 0.5 * step && step > 0.0 {
            self.reversing += 1;
        } else {
            self.reversing = 0;
        }
        self.push(step);
    }

    /// Record the largest step of one iteration.
    pub fn push(&mut self, step: f64) {
        if let Some(&last) = self.history.back() {
            if step > last * (1.0 + 1e-12) {
                self.growing += 1;
            } else {
                self.growing = 0;
            }
        }
        self.peak_before = self.peak;
        self.peak = self.peak.max(step);

        self.history.push_back(step);
        if self.history.len() > 2 * WINDOW + 1 {
            self.history.pop_front();
        }
    }

    /// The last step, if any.
    pub fn last_step(&self) -> Option<f64> {
        self.history.back().copied()
    }

    /// Number of consecutive iterations in which the step grew.
    pub fn growing_iterations(&self) -> usize {
        self.growing
    }

    /// Divergence by growth: the step grew for `streak` iterations in a row *and* now exceeds
    /// every earlier step and `threshold`. A converging solve can see its step rise for hundreds
    /// of iterations (two decaying modes cancelling, then one taking over), but not past every
    /// earlier step, so the streak alone would reject sound solves.
    pub fn runaway(&self, streak: usize, threshold: f64) -> bool {
        let Some(last) = self.last_step() else { return false };
        self.growing >= streak && last > self.peak_before && last > threshold
    }

    /// Oscillation: for `streak` iterations in a row, vertices reversing their direction made at
    /// least half the largest step. Modes with a negative eigenvalue reverse every iteration and,
    /// in a stable iteration, die within a few; carrying the largest step for long they show the
    /// iteration unstable (or nearly) at this λ. Strong tension does this, and the nonlinear
    /// tension term then bounds the growth to a limit cycle whose steps neither grow past every
    /// earlier one nor shrink, which [`runaway`](Self::runaway) misses.
    pub fn oscillating(&self, streak: usize) -> bool {
        self.reversing >= streak
    }

    /// The observed contraction rate per iteration, once two full windows have been seen: the
    /// larger of the rates over the last window and the one before.
    pub fn rate(&self) -> Option<f64> {
        if self.history.len() < 2 * WINDOW + 1 {
            return None;
        }
        let n = self.history.len();
        let window_rate = |end: usize| {
            let (first, last) = (self.history[end - WINDOW], self.history[end]);
            if last == 0.0 {
                Some(0.0)
            } else if first <= 0.0 {
                None
            } else {
                Some((last / first).powf(1.0 / WINDOW as f64))
            }
        };
        let recent = window_rate(n - 1)?;
        let before = window_rate(n - 1 - WINDOW)?;
        Some(recent.max(before))
    }

    /// Estimated distance from the current iterate to the fixed point: `step · ρ / (1 − ρ)`.
    /// Infinite while the rate is unknown or not below 1; zero once a step is exactly zero.
    pub fn remaining(&self) -> f64 {
        let Some(step) = self.last_step() else { return f64::INFINITY };
        if step == 0.0 {
            return 0.0;
        }
        match self.rate() {
            Some(rho) if rho < 1.0 => step * rho / (1.0 - rho),
            _ => f64::INFINITY,
        }
    }

    /// True when both the last step and the estimated remaining distance are under `threshold`.
    pub fn converged(&self, threshold: f64) -> bool {
        self.last_step().is_some_and(|s| s < threshold) && self.remaining() < threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_series_tail_is_estimated_exactly() {
        // Steps of a pure geometric iteration x_k = x_0 ρ^k: the tail after the last step is
        // Σ_{m>k} step_k ρ^{m-k} = step_k ρ / (1 − ρ).
        let rho: f64 = 0.95;
        let mut monitor = ConvergenceMonitor::default();
        let mut step = 1.0;
        for _ in 0..40 {
            monitor.push(step);
            step *= rho;
        }
        let last = monitor.last_step().unwrap();
        let expected = last * rho / (1.0 - rho);
        assert!((monitor.remaining() - expected).abs() < 1e-12 * expected);
        assert!((monitor.rate().unwrap() - rho).abs() < 1e-12);
    }

    #[test]
    fn slow_contraction_is_not_converged_although_the_step_is_small() {
        let mut monitor = ConvergenceMonitor::default();
        let mut step = 5e-4;
        for _ in 0..20 {
            monitor.push(step);
            step *= 0.999;
        }
        assert!(monitor.last_step().unwrap() < 1e-3);
        assert!(!monitor.converged(1e-3), "remaining {}", monitor.remaining());
    }

    #[test]
    fn growth_is_counted() {
        let mut monitor = ConvergenceMonitor::default();
        for k in 0..5 {
            monitor.push(1.0 + k as f64);
        }
        assert_eq!(monitor.growing_iterations(), 4);
        assert_eq!(monitor.remaining(), f64::INFINITY);
        assert!(monitor.runaway(4, 1.0));
        assert!(!monitor.runaway(5, 1.0));
        assert!(!monitor.runaway(4, 10.0));
    }

    #[test]
    fn a_reversing_largest_step_is_an_oscillation() {
        let mut cycle = ConvergenceMonitor::default();
        let mut mixed = ConvergenceMonitor::default();
        for k in 0..200 {
            // A bounded period-2 cycle after a decaying transient: every step reverses.
            let step = if k < 100 { 10.0 * 0.95f64.powi(k) } else { 0.7 };
            cycle.push_sweep(step, if k < 100 { 0.0 } else { step });
            // A converging iteration whose reversing modes die fast (0.2 a sweep).
            mixed.push_sweep(0.99f64.powi(k), 0.2f64.powi(k));
        }
        assert!(cycle.oscillating(64));
        assert!(!cycle.runaway(64, 1e-3), "a bounded cycle is not growth");
        assert!(!mixed.oscillating(3));
    }

    #[test]
    fn a_rise_below_the_earlier_peak_is_not_runaway() {
        let mut monitor = ConvergenceMonitor::default();
        monitor.push(1.0);
        for k in 0..100 {
            monitor.push(1e-3 * (1.0 + 0.01 * k as f64));
        }
        assert_eq!(monitor.growing_iterations(), 99);
        assert!(!monitor.runaway(50, 1e-6));
    }
}
