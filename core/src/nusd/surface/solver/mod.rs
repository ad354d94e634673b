//! [`SurfaceSolver`]: levels, warm starts, budgets and divergence handling.

mod blocks;
mod cycle;
mod inherit;
mod local_solve;
mod update;

use super::NusdInput;
use super::anchoring::check_anchoring;
use super::frame::Frame;
use super::kernel;
use super::level::{Level, refresh_levels};
use super::operator::Controls;
use super::status::{Budget, LevelReport, LevelTiming, Phase, Status};
use super::{DIVERGENCE_GROWTH, MIN_LAMBDA, OSCILLATION_ITERATIONS};
use crate::mesh::PolyMesh;
use crate::nusd::SolverSettings;
use crate::nusd::convergence::ConvergenceMonitor;
use crate::{DVec3, Error, Result};
use local_solve::{LocalSolve, Snapshot};
use std::time::Instant;

/// The hierarchical solver; see the [module docs](super).
#[derive(Clone, Debug)]
pub struct SurfaceSolver {
    /// The cage in the internal frame (the designer's unless its size is extreme).
    cage: PolyMesh,
    /// The topology generation of the cage this solver was last given (a topology edit's
    /// lineage starting from it can warm-start the next cage's levels from these).
    source_topology: u64,
    /// Levels taken from the previous cage's solve by the latest warm start (see `inherit.rs`).
    inherited: usize,
    frame: Frame,
    /// The finest level's P and R in the designer's frame, kept only when the frame scales.
    external: Option<(Vec<DVec3>, Vec<DVec3>)>,
    fixed: Vec<bool>,
    vertex_tension: Vec<f64>,
    edge_tension: Vec<f64>,
    settings: SolverSettings,
    levels: Vec<Level>,
    active: usize,
    phase: Phase,
    lambda: f64,
    threshold: f64,
    diagonal: f64,
    /// Levels from 2 up are solved by multigrid cycles unless this is off.
    multigrid: bool,
    /// The distance to the fixed point measured after a direct solve of the active level.
    direct_estimate: Option<f64>,
    /// Drags are re-solved locally unless this is off.
    local_allowed: bool,
    monitor: ConvergenceMonitor,
    /// The block estimate of plain solves of levels with tension.
    blocks: blocks::BlockMonitor,
    /// The V-cycle in progress and the cycles of the level being solved.
    cycle: cycle::CycleRun,
    level_iterations: usize,
    total_iterations: usize,
    snapshot: Option<Snapshot>,
    /// The local re-solve under way (see [`super::local`]), if any.
    local: Option<LocalSolve>,
    /// Counts the sets of regions made (each level's scratch knows the epoch it was injected in).
    epoch: u64,
    /// The estimated change beyond the region of the level just accepted.
    truncation: f64,
    /// Scratch for sparse propagation: zero except while in use.
    delta_p: Vec<DVec3>,
    delta_r: Vec<DVec3>,
    reports: Vec<LevelReport>,
    timings: Vec<LevelTiming>,
    events: Vec<String>,
}

impl SurfaceSolver {
    /// A solver for a cage and its controls (a `&Document` converts); nothing is iterated until
    /// [`advance`](Self::advance).
    pub fn new<'a>(input: impl Into<NusdInput<'a>>) -> Result<Self> {
        let doc = input.into();
        doc.validate()?;
        if doc.cage.face_count() == 0 {
            return Err(Error::Input("the cage has no faces to smooth".into()));
        }
        let frame = frame_of(doc.cage);
        let mut cage = doc.cage.clone();
        if !frame.is_identity() {
            cage.positions_mut().iter_mut().for_each(|p| *p = frame.to_internal(*p));
        }
        let diagonal = extent(cage.positions())?;
        check_anchoring(doc.cage, doc.fixed)?;
        let controls = Controls {
            fixed: doc.fixed,
            vertex_tension: doc.vertex_tension,
            edge_tension: doc.edge_tension,
            spacing: doc.settings.spacing,
        };
        let level0 = Level::cage(&cage, &controls);
        let mut solver = SurfaceSolver {
            source_topology: doc.cage.topology_generation(),
            inherited: 0,
            frame,
            external: None,
            fixed: doc.fixed.to_vec(),
            vertex_tension: doc.vertex_tension.to_vec(),
            edge_tension: doc.edge_tension.to_vec(),
            settings: doc.settings,
            levels: vec![level0],
            active: 0,
            phase: Phase::Iterating,
            lambda: doc.settings.lambda,
            threshold: doc.settings.tol * diagonal,
            diagonal,
            multigrid: true,
            direct_estimate: None,
            local_allowed: true,
            monitor: ConvergenceMonitor::default(),
            blocks: blocks::BlockMonitor::default(),
            cycle: cycle::CycleRun::default(),
            level_iterations: 0,
            total_iterations: 0,
            snapshot: None,
            local: None,
            epoch: 0,
            truncation: 0.0,
            delta_p: Vec::new(),
            delta_r: Vec::new(),
            reports: Vec::new(),
            timings: Vec::new(),
            events: Vec::new(),
            cage,
        };
        solver.refresh_external();
        Ok(solver)
    }

    /// Solves from the current state to the end; an error if the solve diverged at every λ.
    pub fn solve(&mut self) -> Result<Vec<LevelReport>> {
        match self.advance(Budget::UNLIMITED).phase {
            Phase::Diverged => {
                let tensioned = self.vertex_tension.iter().chain(&self.edge_tension).any(|&t| t > 0.0);
                let advice = if tensioned {
                    "lower the tensions"
                } else {
                    "the cage has no tension, so its shape defeats the iteration: look for nearly coincident vertices or folded faces"
                };
                Err(Error::Solver(format!(
                    "the solve diverged even with λ = {MIN_LAMBDA}: {}; {advice}",
                    self.events.join("; ")
                )))
            }
            _ => Ok(self.reports.clone()),
        }
    }

    /// Multigrid on (the default) or off: off, every level is solved by the plain iteration
    /// alone, to the same fixed point (for comparisons). Takes effect from the next level.
    pub fn set_multigrid(&mut self, on: bool) {
        self.multigrid = on;
    }

    /// Local re-solves after drags on (the default) or off: off, every level is re-solved whole
    /// (for comparisons; see [`super::local`]). Takes effect from the next edit.
    pub fn set_local(&mut self, on: bool) {
        self.local_allowed = on;
    }

    /// True when levels from 2 up are solved by multigrid cycles.
    pub fn multigrid(&self) -> bool {
        self.multigrid
    }

    fn uses_multigrid(&self, level: usize) -> bool {
        self.multigrid && level > self.coarsest() && !self.levels.get(level).is_some_and(|l| l.multigrid_failed)
    }

    /// The coarsest multigrid grid: the cage when some cage vertex is moving, else level 1.
    fn coarsest(&self) -> usize {
        usize::from(!self.levels[0].has_moving())
    }

    /// The coarsest grid of a cycle whose top is `top`: in a whole solve, the finest level below
    /// it that is solved directly (an exact coarse solve on the finest grid that allows one),
    /// else [`coarsest`](Self::coarsest).
    fn cycle_coarsest(&mut self, top: usize) -> usize {
        let base = self.coarsest();
        if self.levels[top].region.is_none() {
            for k in (base..top).rev() {
                if self.levels[k].vertex_count() <= super::direct::MAX_VERTICES && self.solve_directly(k) {
                    return k;
                }
            }
        }
        base
    }

    /// Iterates within `budget`, moving on to finer levels as each converges.
    pub fn advance(&mut self, budget: Budget) -> Status {
        let start = Instant::now();
        let (mut done, mut steps) = (0usize, 0usize);
        while self.phase == Phase::Iterating && done < budget.iterations {
            if budget.time.is_some_and(|t| steps > 0 && start.elapsed() >= t) {
                break;
            }
            if let Err(e) = self.ensure_active_level() {
                self.events.push(e.to_string());
                self.phase = Phase::Diverged;
                break;
            }
            let level = &mut self.levels[self.active];
            if !level.has_moving() {
                let before: Vec<DVec3> = level.operator.fixed.iter().map(|&v| level.state.r[v as usize]).collect();
                kernel::update_fixed(&level.operator, &mut level.state);
                // Only fixed vertices' R can change: record those that did.
                let changed: Vec<u32> = level
                    .operator
                    .fixed
                    .iter()
                    .zip(&before)
                    .filter(|&(&v, r)| level.state.r[v as usize] != *r)
                    .map(|(&v, _)| v)
                    .collect();
                let n = level.vertex_count();
                level.touched.add(&changed, n);
                self.finish_level(true);
                continue;
            }
            if self.snapshot.is_none() {
                self.start_level();
                self.monitor.reset();
                self.blocks.reset();
                self.cycle.reset();
                self.level_iterations = 0;
            }
            let t0 = Instant::now();
            let active = self.active;
            let direct = self.levels[active].region.is_none()
                && self.level_iterations == 0
                && self.cycle.cycles() == 0
                && self.solve_directly(active);
            let counted = if direct {
                self.direct_step()
            } else if self.uses_multigrid(active) {
                self.cycle_step()
            } else {
                self.plain_step()
            };
            steps += 1;
            done += counted;
            let timing = self.timing(active);
            timing.seconds += t0.elapsed().as_secs_f64();
        }
        self.refresh_external();
        self.status()
    }

    /// True when level `k` is solved directly (see [`super::direct`]): with multigrid on, a
    /// small level without tension whose factorisation succeeded (made now if needed).
    fn solve_directly(&mut self, k: usize) -> bool {
        let level = &mut self.levels[k];
        self.multigrid && !level.multigrid_failed && level.direct.get(&level.operator).is_some()
    }

    /// Solves the active level directly: two Newton steps, the second measuring how far the
    /// first left the fixed point (its size is the estimate reported). Counts the two residual
    /// passes as sweeps. A solve that is not finite, or not within the threshold, is undone and
    /// the level is left to the plain iteration.
    fn direct_step(&mut self) -> usize {
        let level = &mut self.levels[self.active];
        let super::level::Level { direct, operator, topology, state, .. } = level;
        let super::direct::Direct::Made(solve) = direct else { unreachable!("checked by solve_directly") };
        let first = solve.step(operator, &topology.mesh, state, None);
        let second = solve.step(operator, &topology.mesh, state, None);
        let timing = self.timing(self.active);
        timing.sweeps += 2;
        timing.work += 2.0;
        self.total_iterations += 2;
        let level = &mut self.levels[self.active];
        if first.is_finite() && second.is_finite() && second < self.threshold {
            self.level_iterations = 2;
            self.direct_estimate = Some(second);
            self.finish_level(true);
        } else {
            let snapshot = self.snapshot.as_ref().expect("a level being iterated has a snapshot");
            snapshot.restore(&mut level.state);
            level.direct = super::direct::Direct::Unavailable;
            self.events.push(format!(
                "level {}: the direct solve was inaccurate (a second step of {second:.3e}); solving it by the plain iteration",
                self.active
            ));
        }
        2
    }

    /// One plain iteration of the active level, with the stopping and divergence rules.
    /// Returns the iterations counted.
    fn plain_step(&mut self) -> usize {
        let n = self.levels[self.active].vertex_count();
        let level = &mut self.levels[self.active];
        let (op, mesh) = (&level.operator, &level.topology.mesh);
        let sweep = match &level.region {
            Some(region) => kernel::iterate_on(op, mesh, &mut level.state, self.lambda, None, region),
            None => kernel::iterate(op, mesh, &mut level.state, self.lambda),
        };
        let step = sweep.step;
        self.level_iterations += 1;
        self.total_iterations += 1;
        let work = self.levels[self.active].region.as_ref().map_or(1.0, |r| r.len() as f64 / n as f64);
        let timing = self.timing(self.active);
        timing.sweeps += 1;
        timing.work += work;
        self.monitor.push_sweep(step, sweep.reversing);
        let tensioned = self.tensioned_level();
        if tensioned {
            let level = &self.levels[self.active];
            self.blocks.push(self.level_iterations, &level.operator, level.region.as_ref(), &level.state.p);
        }
        let oscillating = self.monitor.oscillating(OSCILLATION_ITERATIONS) && step > self.threshold;
        if !step.is_finite()
            || step > 10.0 * self.diagonal
            || self.monitor.runaway(DIVERGENCE_GROWTH, self.threshold)
            || oscillating
        {
            let why = if oscillating {
                "the step stopped shrinking: an oscillation"
            } else if step.is_finite() {
                "the step kept growing"
            } else {
                "a value became infinite"
            };
            self.roll_back(why);
        } else if self.monitor.converged(self.threshold)
            && (!tensioned || self.blocks.remaining(blocks::FLOOR * self.threshold) < blocks::MARGIN * self.threshold)
        {
            if self.local_accepts(self.plain_remaining()) {
                self.finish_level(true);
            }
        } else if self.level_iterations >= self.settings.max_iterations {
            self.finish_level(false);
        }
        1
    }

    /// True when the active level has tension (its plain solves also use the block estimate).
    fn tensioned_level(&self) -> bool {
        self.levels.get(self.active).is_some_and(|l| !l.operator.overrides.is_empty())
    }

    /// The plain iteration's estimate of the distance left on the active level.
    fn plain_remaining(&self) -> f64 {
        let steps = self.monitor.remaining();
        if self.tensioned_level() { steps.max(self.blocks.remaining(blocks::FLOOR * self.threshold)) } else { steps }
    }

    /// The timing record of `level` in this solve.
    fn timing(&mut self, level: usize) -> &mut LevelTiming {
        while self.timings.len() <= level {
            let l = self.timings.len() as u32;
            self.timings.push(LevelTiming { level: l, ..Default::default() });
        }
        &mut self.timings[level]
    }

    /// Takes the latest solve's messages (λ reductions, divergence).
    pub fn take_events(&mut self) -> Vec<String> {
        std::mem::take(&mut self.events)
    }

    /// Per-level reports of the levels solved since the last edit.
    pub fn reports(&self) -> &[LevelReport] {
        &self.reports
    }

    /// Where the time went, per level, since the last edit.
    pub fn timings(&self) -> &[LevelTiming] {
        &self.timings
    }

    /// The finest level converged since the last edit (every coarser one converged too): the
    /// level an editor can show as settled while finer ones are still being solved.
    pub fn converged_level(&self) -> Option<u32> {
        let mut best = None;
        for l in 0..=self.settings.levels {
            match self.reports.iter().find(|r| r.level == l) {
                Some(r) if r.converged => best = Some(l),
                _ => break,
            }
        }
        best
    }

    /// The surface of one level as it stands (its own solution; `None` for a level not built
    /// yet), in the designer's frame.
    pub fn level_surface(&self, level: u32) -> Option<PolyMesh> {
        let l = self.levels.get(level as usize)?;
        let mut mesh = l.topology.mesh.clone();
        for (out, &p) in mesh.positions_mut().iter_mut().zip(&l.state.p) {
            *out = self.frame.position_out(p);
        }
        Some(mesh)
    }

    /// The connectivity of one level and how it was made from the level above (`None` for a
    /// level not built yet).
    pub fn level_topology(&self, level: u32) -> Option<&super::hierarchy::LevelTopology> {
        self.levels.get(level as usize).map(|l| &l.topology)
    }

    /// Where the solve stands.
    pub fn status(&self) -> Status {
        // Once done, the step and estimate are those the finest level stopped with.
        if self.phase == Phase::Done
            && let Some(last) = self.reports.iter().max_by_key(|r| r.level)
        {
            return Status {
                phase: self.phase,
                level: self.active as u32,
                levels: self.settings.levels,
                iterations: last.iterations,
                total_iterations: self.total_iterations,
                last_step: last.last_step,
                remaining: last.remaining,
                threshold: self.frame.length_out(self.threshold),
                lambda: self.lambda,
            };
        }
        let out = |x: f64| self.frame.length_out(x);
        let (last_step, remaining) = if self.uses_multigrid(self.active) && self.cycle.cycles() > 0 {
            (self.cycle.last_change(), self.cycle.remaining(self.levels[self.active].cycle_rate))
        } else {
            (self.monitor.last_step().unwrap_or(0.0), self.plain_remaining())
        };
        Status {
            phase: self.phase,
            level: self.active as u32,
            levels: self.settings.levels,
            iterations: self.level_iterations,
            total_iterations: self.total_iterations,
            last_step: out(last_step),
            remaining: out(remaining),
            threshold: out(self.threshold),
            lambda: self.lambda,
        }
    }

    /// The settings in force.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// The finest level built so far: its connectivity. Its positions are the domain's (the
    /// refined cage without smoothing) in the solver's frame, which is the designer's except for
    /// cages of extreme size (see [`frame`](super::frame)).
    pub fn surface_topology(&self) -> &PolyMesh {
        &self.finest().topology.mesh
    }

    /// Current positions of the finest level built so far (cage vertices first).
    pub fn surface_positions(&self) -> &[DVec3] {
        match &self.external {
            Some((p, _)) => p,
            None => &self.finest().state.p,
        }
    }

    /// The finest surface as a mesh of its own.
    pub fn surface(&self) -> PolyMesh {
        let mut mesh = self.finest().topology.mesh.clone();
        mesh.positions_mut().copy_from_slice(self.surface_positions());
        mesh
    }

    /// Second derivatives `R` of the finest level built so far.
    pub fn surface_second_derivatives(&self) -> &[DVec3] {
        match &self.external {
            Some((_, r)) => r,
            None => &self.finest().state.r,
        }
    }

    /// Copies the finest level into the designer's frame when the internal one differs.
    fn refresh_external(&mut self) {
        if self.frame.is_identity() {
            self.external = None;
            return;
        }
        let (frame, spacing) = (self.frame, self.settings.spacing);
        let state = &self.finest().state;
        let p = state.p.iter().map(|&x| frame.position_out(x)).collect();
        let r = state.r.iter().map(|&x| frame.second_derivative_out(x, spacing)).collect();
        self.external = Some((p, r));
    }

    /// The finest level's vertices along each cage edge, in order from the edge's first end
    /// vertex to its second: the surface's curve network (patch boundaries).
    pub fn cage_edge_curves(&self) -> Vec<(crate::mesh::EdgeId, Vec<crate::mesh::VertexId>)> {
        let topology = &self.finest().topology;
        let mesh = &topology.mesh;
        self.cage
            .edges()
            .map(|e| {
                let (a, b) = self.cage.edge_vertices(e);
                let mut chain = vec![a];
                let mut current = a;
                let mut previous = crate::mesh::VertexId::INVALID;
                while current != b {
                    let next = mesh
                        .outgoing(current)
                        .map(|h| (h, mesh.to_vertex(h)))
                        .find(|&(h, v)| topology.edge_on_cage[h.edge().index()] == e.0 && v != previous);
                    let Some((_, v)) = next else { break };
                    previous = current;
                    current = v;
                    chain.push(v);
                }
                (e, chain)
            })
            .collect()
    }

    fn finest(&self) -> &Level {
        let top = (self.settings.levels as usize).min(self.levels.len() - 1);
        &self.levels[top]
    }

    fn restart(&mut self) {
        self.active = 0;
        self.phase = Phase::Iterating;
        self.snapshot = None;
        self.monitor.reset();
        self.blocks.reset();
        self.cycle.reset();
        self.level_iterations = 0;
        self.total_iterations = 0;
        self.reports.clear();
        self.timings.clear();
    }

    /// Makes sure the active level exists, refining the finest one if needed.
    fn ensure_active_level(&mut self) -> Result<()> {
        while self.levels.len() <= self.active {
            let controls = Controls {
                fixed: &self.fixed,
                vertex_tension: &self.vertex_tension,
                edge_tension: &self.edge_tension,
                spacing: self.settings.spacing,
            };
            let finer = self.levels.last().expect("level 0 always exists").refine(&self.cage, &controls, true)?;
            // The new level starts from all of the coarser one.
            let coarser = self.levels.last_mut().expect("level 0 always exists");
            coarser.touched.take();
            coarser.start = None;
            self.levels.push(finer);
        }
        Ok(())
    }

    fn finish_level(&mut self, converged: bool) {
        let (last_step, remaining) = if let Some(d) = self.direct_estimate.take() {
            (d, d)
        } else if self.uses_multigrid(self.active) && self.cycle.cycles() > 0 {
            let rate = self.cycle.measured_rate();
            let level = &mut self.levels[self.active];
            let estimate = (self.cycle.last_change(), self.cycle.remaining(level.cycle_rate));
            if let Some(rate) = rate {
                level.cycle_rate = rate.clamp(super::level::MIN_CYCLE_RATE, 0.95);
            }
            estimate
        } else {
            (self.monitor.last_step().unwrap_or(0.0), self.plain_remaining())
        };
        let remaining = if converged { remaining + std::mem::take(&mut self.truncation) } else { remaining };
        let level = &self.levels[self.active];
        let out = |x: f64| self.frame.length_out(x);
        let report = LevelReport {
            level: self.active as u32,
            vertices: level.topology.vertex_count(),
            iterations: if level.has_moving() { self.level_iterations } else { 0 },
            last_step: if level.has_moving() { out(last_step) } else { 0.0 },
            remaining: if level.has_moving() { out(remaining) } else { 0.0 },
            converged,
            lambda: self.lambda,
        };
        self.reports.retain(|r| r.level != report.level);
        self.reports.push(report);
        // A local solve passes the level's change on to the next level only: the finer ones get
        // it with that level's own change when it is done (a drag already moved them all).
        let upto = if self.local.is_some() { self.active + 1 } else { self.levels.len() - 1 };
        self.propagate_through(self.active, upto);
        self.snapshot = None;
        self.monitor.reset();
        self.blocks.reset();
        self.cycle.reset();
        self.level_iterations = 0;
        if self.active >= self.settings.levels as usize {
            // The finest level is refined only if the levels are raised later: its start is
            // not kept for that.
            self.levels[self.active].start = None;
            self.phase = Phase::Done;
        } else {
            self.active += 1;
        }
    }

    fn roll_back(&mut self, why: &str) {
        let snapshot = self.snapshot.as_ref().expect("a level being iterated has a snapshot");
        snapshot.restore(&mut self.levels[self.active].state);
        self.cycle.reset();
        let reduced = self.lambda * 0.5;
        self.monitor.reset();
        self.blocks.reset();
        self.level_iterations = 0;
        if reduced < MIN_LAMBDA {
            self.events.push(format!(
                "level {}: diverged at λ = {} ({why}); kept the last good state",
                self.active, self.lambda
            ));
            self.phase = Phase::Diverged;
        } else {
            self.events.push(format!(
                "level {}: diverged at λ = {} ({why}); restored the last good state and retried with λ = {reduced}",
                self.active, self.lambda
            ));
            self.lambda = reduced;
        }
    }
}

/// The internal frame of a cage (see [`frame`](super::frame)).
fn frame_of(cage: &PolyMesh) -> Frame {
    cage.bounding_box().map_or(Frame::default(), |(lo, hi)| Frame::for_box(lo, hi))
}

/// The bounding-box diagonal of cage positions in the internal frame, or why they have none.
fn extent(positions: &[DVec3]) -> Result<f64> {
    let diagonal = crate::mesh::bounding_box(positions).map_or(0.0, |(lo, hi)| crate::mesh::diagonal_length(lo, hi));
    if diagonal > 0.0 && diagonal.is_finite() {
        Ok(diagonal)
    } else {
        Err(Error::Input("the cage has no extent: all its vertices are at one point".into()))
    }
}
