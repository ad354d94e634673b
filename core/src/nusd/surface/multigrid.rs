//! Multigrid for one level's NUSD system: the same fixed point, reached in a flat number of
//! sweeps (issue 13).
//!
//! The plain NUSD iteration is a damped Jacobi-type diffusion: it removes the rough part of the
//! error within a few sweeps but the smooth part only slowly (its rate tends to 1 as the level
//! gets finer), and smooth error is exactly what refinement and drags leave. The level hierarchy
//! Taut already builds is a natural multigrid hierarchy (Brandt's full approximation scheme,
//! FAS, because tension makes the system nonlinear; Trottenberg, Oosterlee & Schüller,
//! *Multigrid*, 2001, ch. 5.3): a V-cycle on level `L`
//! 1. smooths with the NUSD iteration itself (ν₁ sweeps), computes the residual `f − N(x)` of
//!    the level's equations, written per vertex divided by `K` so that they mean the same
//!    continuous equations on every level ([`kernel::Forcing`]),
//! 2. restricts the iterate (coarse vertex `i` is fine vertex `i`: injection) and the residual
//!    (full weighting: the transpose of the parent-average prolongation, normalised, gathering
//!    only from fine vertices whose equation is of the same kind — open boundary, patch-boundary
//!    curve, interior — because the patch-boundary rule and open boundaries make those different
//!    equations),
//! 3. sets the coarse right-hand side `f_c = N_c(x_c⁰) + restricted residual` and solves the
//!    coarse problem the same way (recursively, [`GAMMA`] cycles: a W-cycle); the coarsest
//!    grid (level 0 when some cage vertex is moving, else level 1) is solved exactly when it is
//!    small and has no tension ([`super::direct`]), else smoothed until its steps fall to a
//!    tenth,
//! 4. adds the prolonged coarse correction `x_c − x_c⁰` and smooths again (ν₂ sweeps).
//!
//! The top level's right-hand side is zero, so a converged cycle leaves an exact fixed point of
//! the plain iteration: the surface does not change, only the number of sweeps. Fixed vertices,
//! tension (the `R_i^j` substitution, evaluated on every level with that level's own operator),
//! open boundaries and patch-boundary diffusion all enter through the operators; the coarse
//! levels' own solutions are not touched (each level keeps a scratch iterate for its role as a
//! coarse grid).
//!
//! A cycle is a list of [`Op`]s, each at most one sweep of one level, so the solver can stop
//! between any two of them when a frame's time is up and carry on in the next frame.
//!
//! A cycle that relaxes its top by Gauss–Seidel ([`cycle`]'s `relax_top`) also solves the
//! neighbourhoods of the top level's crowded vertices exactly after its coarse correction
//! ([`Op::Blocks`], [`super::irregular`]).
//!
//! Weak spots: the smoother is the plain iteration, so a λ at which it is unstable (strong
//! tension) makes the cycle diverge like the plain iteration does, and the same fallback (halve
//! λ) applies; the coarsest grid is only smoothed, so with very few fixed vertices (a
//! slowly converging level 1) cycles cost more.

use super::hierarchy::{LevelTopology, NOT_ON_CAGE_EDGE};
use super::kernel::{self, Forcing, State};
use super::local::{self, Region};
use super::operator::{Operator, Role};
use crate::DVec3;
use rayon::prelude::*;

/// Smoothing sweeps before the coarse correction, and as many after it. Measured on the
/// default scene (levels 2–5), its partly unfixed variant and a torus: 3 sweeps with W-cycles
/// gave the fewest sweeps per level (flat, 21–42); 2 diverged at level 2, 4 and 6 cost more.
pub const SWEEPS: usize = 3;
/// The part of the spectrum of `I − W` (the diffusion's random-walk Laplacian, eigenvalues in
/// `[0, 2]`) that the smoother damps; the rest is left to the coarse level. On a quad grid the
/// modes the coarse grid cannot represent have eigenvalues from 0.5 up; the interval starts at
/// 0.7 because wider ones (larger λ steps) made the cycles erratic or divergent: the coupling of
/// `P` and `R` (and of a fixed vertex's `R` to its neighbours' `P`) makes the iteration
/// non-normal, and big steps amplify that.
pub const ROUGH_SPECTRUM: (f64, f64) = (0.7, 2.0);
/// Cycles each coarse problem gets below the top: 2, a W-cycle (V-cycles, 1, lost their
/// contraction with depth: 7 cycles at level 5 of the default scene against 3).
pub const GAMMA: usize = 2;

/// The smoothing λ of each of the [`SWEEPS`] sweeps: the Chebyshev schedule for
/// [`ROUGH_SPECTRUM`] (the reciprocals of the Chebyshev nodes), which damps every mode in it by
/// `1/T_ν(27/13)` (0.02 for 3 sweeps) where a fixed λ = 0.6 damps those at its lower end by
/// `0.7^ν`. The iteration's eigenvalues are real (the weights are those of a symmetric
/// conductance matrix, scaled per row), so the Chebyshev bound applies. Only the path changes:
/// any λ schedule has the same fixed point.
pub fn smoothing_schedule() -> [f64; SWEEPS] {
    let (a, b) = ROUGH_SPECTRUM;
    let (centre, half) = ((a + b) / 2.0, (b - a) / 2.0);
    std::array::from_fn(|k| {
        let node = (std::f64::consts::PI * (2 * k + 1) as f64 / (2 * SWEEPS) as f64).cos();
        1.0 / (centre + half * node)
    })
}
/// The coarsest grid is smoothed until its step falls to this fraction of its first step...
pub const COARSE_REDUCTION: f64 = 0.1;
/// ... or for at most this many sweeps.
pub const COARSE_SWEEPS: usize = 200;

/// The kind of equation a vertex's `R` (or `P`) obeys; residuals are restricted only between
/// vertices of one kind.
fn kind_r(level: &LevelTopology, v: usize) -> u8 {
    if level.mesh.is_boundary_vertex(crate::mesh::VertexId(v as u32)) {
        0
    } else if v < level.cage_vertices || level.vertex_on_cage_edge[v] != NOT_ON_CAGE_EDGE {
        1
    } else {
        2
    }
}

fn kind_p(level: &LevelTopology, v: usize) -> u8 {
    u8::from(level.mesh.is_boundary_vertex(crate::mesh::VertexId(v as u32)))
}

/// Full-weighting restriction from a level to the next coarser one, per coarse vertex a
/// normalised list of fine vertices and weights, for the `R` and the `P` equations.
#[derive(Clone, Debug, Default)]
pub struct Transfer {
    r_offsets: Vec<u32>,
    r_entries: Vec<(u32, f64)>,
    p_offsets: Vec<u32>,
    p_entries: Vec<(u32, f64)>,
}

impl Transfer {
    /// The restriction from `fine` (a refined level, with its parents) to its coarser level,
    /// whose vertices are the first `coarse_count` of `fine`.
    pub fn new(fine: &LevelTopology, coarse_count: usize) -> Transfer {
        let n = fine.vertex_count();
        let build = |kind: &dyn Fn(usize) -> u8| {
            let mut counts = vec![0u32; coarse_count + 1];
            let parents =
                |v: usize| &fine.parents[fine.parent_offsets[v] as usize..fine.parent_offsets[v + 1] as usize];
            for v in 0..n {
                for &c in parents(v) {
                    if kind(v) == kind(c as usize) {
                        counts[c as usize + 1] += 1;
                    }
                }
            }
            for c in 0..coarse_count {
                counts[c + 1] += counts[c];
            }
            let mut fill = counts.clone();
            let mut entries = vec![(0u32, 0.0f64); counts[coarse_count] as usize];
            for v in 0..n {
                let ps = parents(v);
                let w = 1.0 / ps.len() as f64;
                for &c in ps {
                    if kind(v) == kind(c as usize) {
                        entries[fill[c as usize] as usize] = (v as u32, w);
                        fill[c as usize] += 1;
                    }
                }
            }
            for c in 0..coarse_count {
                let row = &mut entries[counts[c] as usize..counts[c + 1] as usize];
                let sum: f64 = row.iter().map(|e| e.1).sum();
                row.iter_mut().for_each(|e| e.1 /= sum);
            }
            (counts, entries)
        };
        let (r_offsets, r_entries) = build(&|v| kind_r(fine, v));
        let (p_offsets, p_entries) = build(&|v| kind_p(fine, v));
        Transfer { r_offsets, r_entries, p_offsets, p_entries }
    }

    /// `coarse = restricted fine − coarse` on moving coarse vertices (the FAS right-hand side
    /// from the fine residual and `coarse`, which holds `−N_c(x_c⁰)`); zero elsewhere.
    fn right_hand_side(&self, fine: &Forcing, coarse_role: &[Role], coarse: &mut Forcing) {
        let gather = |offsets: &[u32], entries: &[(u32, f64)], values: &[DVec3], c: usize| {
            let mut sum = DVec3::ZERO;
            for &(v, w) in &entries[offsets[c] as usize..offsets[c + 1] as usize] {
                sum += w * values[v as usize];
            }
            sum
        };
        let Forcing { r, p } = coarse;
        r.par_iter_mut().zip(p.par_iter_mut()).with_min_len(4096).enumerate().for_each(|(c, (rc, pc))| {
            if coarse_role[c] == Role::Moving {
                *rc = gather(&self.r_offsets, &self.r_entries, &fine.r, c) - *rc;
                *pc = gather(&self.p_offsets, &self.p_entries, &fine.p, c) - *pc;
            } else {
                *rc = DVec3::ZERO;
                *pc = DVec3::ZERO;
            }
        });
    }
}

impl Transfer {
    /// [`right_hand_side`](Self::right_hand_side) at the vertices of a region only (the fine
    /// residual must be zero outside the fine region).
    fn right_hand_side_on(&self, fine: &Forcing, coarse_role: &[Role], coarse: &mut Forcing, region: &Region) {
        let gather = |offsets: &[u32], entries: &[(u32, f64)], values: &[DVec3], c: usize| {
            let mut sum = DVec3::ZERO;
            for &(v, w) in &entries[offsets[c] as usize..offsets[c + 1] as usize] {
                sum += w * values[v as usize];
            }
            sum
        };
        let values = local::map_vertices(&region.vertices, |c| {
            let c = c as usize;
            if coarse_role[c] == Role::Moving {
                (
                    gather(&self.r_offsets, &self.r_entries, &fine.r, c) - coarse.r[c],
                    gather(&self.p_offsets, &self.p_entries, &fine.p, c) - coarse.p[c],
                )
            } else {
                (DVec3::ZERO, DVec3::ZERO)
            }
        });
        for (&c, (r, p)) in region.vertices.iter().zip(values) {
            coarse.r[c as usize] = r;
            coarse.p[c as usize] = p;
        }
    }
}

/// A level's scratch for its role as a coarse grid: its iterate, the state it started from, and
/// its right-hand side.
#[derive(Clone, Debug, Default)]
pub struct Work {
    pub state: State,
    pub start_p: Vec<DVec3>,
    pub start_r: Vec<DVec3>,
    pub forcing: Forcing,
    /// The local-solve epoch in which the whole iterate was last injected (0: none): within
    /// it, vertices outside the region keep their injected values and only the region's are
    /// injected again.
    pub injected: u64,
}

impl Work {
    pub fn new(n: usize) -> Work {
        Work {
            state: State::new(vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]),
            start_p: vec![DVec3::ZERO; n],
            start_r: vec![DVec3::ZERO; n],
            forcing: Forcing::zeros(n),
            injected: 0,
        }
    }
}

/// Gauss–Seidel sweeps of the top level before its coarse correction, and after it, in a cycle
/// that relaxes its top ([`cycle`]'s `relax_top`), and their λ. Measured on the default scene's
/// levels 2–5, cage fixed and waist unfixed (`docs/nusd.md`, "Sweeps per level"): 2 + 1
/// at λ 0.9 needs three cycles at levels 4–5 and four at levels 2–3, where 3 + 3 Chebyshev
/// sweeps of the plain iteration needed four at levels 2–3 and three at levels 4–5 at nearly
/// twice the sweeps a cycle; 1 + 1 stalls at level 2, λ 1 at level 1–2 with the waist unfixed.
pub const RELAX_SWEEPS: (usize, usize) = (2, 1);
pub const RELAX_LAMBDA: f64 = 0.9;
/// The coarsest grid of such a cycle is smoothed until its step falls to this fraction of its
/// first (instead of [`COARSE_REDUCTION`]): with a tenth, level 2 of the default scene took 16
/// cycles over level 1; with a hundredth 4, like the levels above it.
pub const RELAX_COARSE_REDUCTION: f64 = 0.01;

/// One step of a cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// One smoothing sweep of a level with the given λ (before the divergence fallback's
    /// scaling).
    Smooth(usize, f64),
    /// One Gauss–Seidel sweep of the top level with the given λ (before the fallback's scaling).
    Relax(usize, f64),
    /// Residual of a level, restricted to the next coarser one, which starts from the injected
    /// iterate.
    Restrict(usize),
    /// One sweep of the coarsest grid; repeated until its step has fallen enough.
    Coarse(usize),
    /// The coarse correction added to a level.
    Correct(usize),
    /// The neighbourhoods of the level's extraordinary vertices solved exactly (see
    /// [`super::irregular`]).
    Blocks(usize),
}

/// The operations of one cycle whose top is level `top` and coarsest grid `coarsest` (below
/// `top`): the smoothing schedule before each restriction, and in reverse order after each
/// correction; below the top each coarse problem gets `gamma` cycles (1: a V-cycle, 2: a
/// W-cycle).
///
/// `relax_top`: the top level is smoothed by [`RELAX_SWEEPS`] Gauss–Seidel sweeps
/// ([`kernel::iterate_colored`]) instead of the schedule (the levels below keep it: with
/// Gauss–Seidel there too the cycles settled short of the fixed point at an irregular vertex).
pub fn cycle(top: usize, coarsest: usize, gamma: usize, relax_top: bool) -> Vec<Op> {
    fn visit(k: usize, top: Option<usize>, coarsest: usize, gamma: usize, schedule: &[f64], ops: &mut Vec<Op>) {
        if k == coarsest {
            ops.push(Op::Coarse(k));
            return;
        }
        let relax = top == Some(k);
        if relax {
            ops.extend((0..RELAX_SWEEPS.0).map(|_| Op::Relax(k, RELAX_LAMBDA)));
        } else {
            ops.extend(schedule.iter().map(|&l| Op::Smooth(k, l)));
        }
        ops.push(Op::Restrict(k));
        let repeats = if k - 1 == coarsest { 1 } else { gamma };
        for _ in 0..repeats {
            visit(k - 1, None, coarsest, gamma, schedule, ops);
        }
        ops.push(Op::Correct(k));
        if relax {
            ops.push(Op::Blocks(k));
        }
        if relax {
            ops.extend((0..RELAX_SWEEPS.1).map(|_| Op::Relax(k, RELAX_LAMBDA)));
        } else {
            ops.extend(schedule.iter().rev().map(|&l| Op::Smooth(k, l)));
        }
    }
    let mut ops = Vec::new();
    visit(top, relax_top.then_some(top), coarsest, gamma, &smoothing_schedule(), &mut ops);
    ops
}

/// What a level offers a cycle: its connectivity and operator, the iterate it works on (its own
/// solution at the top, its coarse-grid scratch below), and a residual buffer.
#[derive(Debug)]
pub struct Grid<'a> {
    pub topology: &'a LevelTopology,
    pub operator: &'a Operator,
    pub transfer: Option<&'a Transfer>,
    /// The level's own state: the iterate when the level is the cycle's top.
    pub state: &'a mut State,
    /// The coarse-grid scratch: present below the top.
    pub work: Option<&'a mut Work>,
    pub residual: &'a mut Forcing,
    /// The vertices iterated in a local solve (see [`local`]); `None`: all. The residual
    /// buffer is zero outside it.
    pub region: Option<&'a Region>,
    /// The local solve's epoch (see [`Work::injected`]).
    pub epoch: u64,
}

impl Grid<'_> {
    fn iterate_and_forcing(&mut self) -> (&mut State, Option<&Forcing>) {
        match &mut self.work {
            Some(work) => (&mut work.state, Some(&work.forcing)),
            None => (&mut *self.state, None),
        }
    }
}

/// One smoothing sweep of `grid` (the plain iteration at the top, forced below).
pub fn smooth(grid: &mut Grid<'_>, lambda: f64) -> kernel::Sweep {
    let (operator, mesh, region) = (grid.operator, &grid.topology.mesh, grid.region);
    let (state, forcing) = grid.iterate_and_forcing();
    match region {
        Some(region) => kernel::iterate_on(operator, mesh, state, lambda, forcing, region),
        None => kernel::iterate_forced(operator, mesh, state, lambda, forcing),
    }
}

/// One Gauss–Seidel sweep of `grid`, or of its region (see [`kernel::iterate_colored`]).
pub fn relax(grid: &mut Grid<'_>, lambda: f64) -> kernel::Sweep {
    let (operator, topology, region) = (grid.operator, grid.topology, grid.region);
    let (state, forcing) = grid.iterate_and_forcing();
    let (mesh, coloring) = (&topology.mesh, topology.coloring());
    match region {
        Some(region) => kernel::iterate_colored_on(operator, mesh, state, lambda, forcing, region, coloring),
        None => kernel::iterate_colored(operator, mesh, state, lambda, forcing, coloring),
    }
}

/// The fine residual restricted to `coarse`, which starts from the injected fine iterate.
pub fn restrict(fine: &mut Grid<'_>, coarse: &mut Grid<'_>) {
    let (operator, mesh, transfer, fine_region) = (fine.operator, &fine.topology.mesh, fine.transfer, fine.region);
    let Grid { state, work, residual, .. } = fine;
    let (source, forcing) = match work {
        Some(work) => (&mut work.state, Some(&work.forcing)),
        None => (&mut **state, None),
    };
    match fine_region {
        Some(region) => kernel::residual_on(operator, mesh, source, forcing, residual, region),
        None => kernel::residual(operator, mesh, source, forcing, residual),
    };
    let n = coarse.topology.vertex_count();
    let (epoch, coarse_region) = (coarse.epoch, coarse.region);
    let target = coarse.work.as_deref_mut().expect("a coarse grid has scratch");
    let transfer = transfer.expect("a level above the coarsest has a transfer");
    match coarse_region {
        Some(region) => {
            // Within an epoch only the region changes; the first injection of one copies all.
            let again = epoch != 0 && target.injected == epoch;
            if again {
                for &c in &region.vertices {
                    let c = c as usize;
                    target.state.p[c] = source.p[c];
                    target.state.r[c] = source.r[c];
                }
            } else {
                target.state.p.copy_from_slice(&source.p[..n]);
                target.state.r.copy_from_slice(&source.r[..n]);
                kernel::update_fixed(coarse.operator, &mut target.state);
            }
            let (operator, mesh) = (coarse.operator, &coarse.topology.mesh);
            kernel::residual_on(operator, mesh, &mut target.state, None, &mut target.forcing, region);
            if again {
                for &c in &region.vertices {
                    let c = c as usize;
                    target.start_p[c] = target.state.p[c];
                    target.start_r[c] = target.state.r[c];
                }
            } else {
                target.start_p.copy_from_slice(&target.state.p);
                target.start_r.copy_from_slice(&target.state.r);
            }
            transfer.right_hand_side_on(residual, &coarse.operator.role, &mut target.forcing, region);
            target.injected = epoch;
        }
        None => {
            target.state.p.copy_from_slice(&source.p[..n]);
            target.state.r.copy_from_slice(&source.r[..n]);
            kernel::residual(coarse.operator, &coarse.topology.mesh, &mut target.state, None, &mut target.forcing);
            target.start_p.copy_from_slice(&target.state.p);
            target.start_r.copy_from_slice(&target.state.r);
            transfer.right_hand_side(residual, &coarse.operator.role, &mut target.forcing);
            target.injected = 0;
        }
    }
}

/// Adds the prolonged coarse correction `x_c − x_c⁰` to the fine iterate.
pub fn correct(coarse: &mut Grid<'_>, fine: &mut Grid<'_>) {
    let work = coarse.work.as_deref_mut().expect("a coarse grid has scratch");
    // The coarse residual buffer is free now: it holds the correction.
    let Forcing { r: dr, p: dp } = &mut *coarse.residual;
    match coarse.region {
        // Zero outside the region already (the residual buffer's invariant).
        Some(region) => {
            for &c in &region.vertices {
                let c = c as usize;
                dp[c] = work.state.p[c] - work.start_p[c];
                dr[c] = work.state.r[c] - work.start_r[c];
            }
        }
        None => {
            dp.par_iter_mut().zip(&work.state.p).zip(&work.start_p).for_each(|((d, a), b)| *d = *a - *b);
            dr.par_iter_mut().zip(&work.state.r).zip(&work.start_r).for_each(|((d, a), b)| *d = *a - *b);
        }
    }
    let (topology, fine_region) = (fine.topology, fine.region);
    let (target, _) = fine.iterate_and_forcing();
    match fine_region {
        Some(region) => {
            local::prolong_add_on(topology, &region.vertices, dp, &mut target.p);
            local::prolong_add_on(topology, &region.vertices, dr, &mut target.r);
        }
        None => {
            topology.prolong_add(dp, &mut target.p);
            topology.prolong_add(dr, &mut target.r);
        }
    }
}

/// Largest change of a moving vertex of `region` between `before` (in region order) and
/// `after`.
pub fn largest_change_on(operator: &Operator, region: &Region, before: &[DVec3], after: &[DVec3]) -> f64 {
    region
        .vertices
        .iter()
        .zip(before)
        .map(|(&v, b)| if operator.role[v as usize] == Role::Moving { (after[v as usize] - *b).length() } else { 0.0 })
        .fold(0.0, |a, b| if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) })
}

/// Largest change of a moving vertex between `before` and `after`.
pub fn largest_change(operator: &Operator, before: &[DVec3], after: &[DVec3]) -> f64 {
    before
        .par_iter()
        .zip(after)
        .zip(&operator.role)
        .with_min_len(4096)
        .map(|((a, b), role)| if *role == Role::Moving { (*b - *a).length() } else { 0.0 })
        .reduce(|| 0.0, |a, b| if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) })
}

#[cfg(test)]
#[path = "multigrid_tests.rs"]
mod tests;
