//! A small level's NUSD system solved directly: the coarsest multigrid grid, and level 1 when
//! every cage vertex is fixed (issue 22).
//!
//! Without tension the fixed point of the iteration is linear in the moving vertices' `P` and
//! `R` (`docs/nusd.md`, "Sweeps per level"): per moving vertex `i` the equations of
//! [`kernel::residual`], `(ΔR̃_i)/K_i = f_r` and `ΔP_i/K_i − R_i = f_p`, with a fixed neighbour's
//! `R_j = ΔP_j/K_j − f_r` substituted (a linear function of its neighbours' positions). Their
//! Jacobian `A` is assembled once per operator and factorised by sparse LU (faer, with its
//! fill-reducing column ordering, sequential so that the result does not depend on the thread
//! count). A solve is Newton's step on that affine map: the residual `f − N(x)` is measured by
//! the kernel itself, `A e = f − N(x)` is solved, and `x + e` is the fixed point up to rounding.
//! So the solution is the iteration's own fixed point, with whatever forcing the multigrid
//! coarse problem has, and a second step measures how far the first one left it.
//!
//! Only small levels are factorised ([`MAX_VERTICES`]): the factorisation's cost grows much
//! faster than the level (a level of the 2,048-face torus at 131 k vertices took 8.5 s where
//! multigrid takes 0.14 s, `nusd_scale` bench).

use super::kernel::{self, Forcing, State};
use super::operator::{Operator, Role};
use crate::DVec3;
use crate::mesh::PolyMesh;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par};

/// Levels with more vertices than this are not factorised. faer's factorisation of these
/// systems grows fast with their size: 0.6 ms for level 1 of the default scene (154 vertices),
/// 7 ms for its level 2 (610), 20 ms for level 3 (2,434) and 120 ms for level 4 (9,730), where
/// their multigrid solves take 0.7, 3.6 and 13 ms (2 cores). So only levels of a few hundred
/// vertices are solved directly, where the factorisation costs well under a millisecond.
pub const MAX_VERTICES: usize = 256;

/// The factorised Jacobian of a level's equations and the scratch of its solves.
#[derive(Clone, Debug)]
pub struct DirectSolve {
    /// The row pair of each vertex (`2u`: its `R` equation and unknown, `2u + 1`: its `P`), or
    /// `u32::MAX` for a vertex that does not move.
    unknown: Vec<u32>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    rhs: Mat<f64>,
    residual: Forcing,
}

impl DirectSolve {
    /// Factorises the Jacobian of `op`'s equations; `None` when the level has tension (its
    /// equations are not linear), is too large, has no moving vertex, or its matrix is singular.
    pub fn new(op: &Operator) -> Option<DirectSolve> {
        if op.role.len() > MAX_VERTICES {
            return None;
        }
        Self::new_unbounded(op)
    }

    /// [`new`](Self::new) whatever the level's size.
    pub fn new_unbounded(op: &Operator) -> Option<DirectSolve> {
        let n = op.role.len();
        if !op.overrides.is_empty() {
            return None;
        }
        let mut unknown = vec![u32::MAX; n];
        let mut m = 0u32;
        for (i, role) in op.role.iter().enumerate() {
            if *role == Role::Moving {
                unknown[i] = m;
                m += 1;
            }
        }
        if m == 0 {
            return None;
        }
        let rows = 2 * m as usize;
        let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(rows * 24);
        let index = |j: usize| (unknown[j] != u32::MAX).then_some(unknown[j] as usize);
        for i in 0..n {
            if let Some(u) = index(i) {
                jacobian_rows(op, i, u, index, |row, col, value| triplets.push(Triplet::new(row, col, value)));
            }
        }
        // Duplicates (a neighbour reached directly and through a fixed vertex) are summed.
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(rows, rows, &triplets).ok()?;
        let symbolic = factorize_symbolic_lu(a.symbolic(), Default::default()).ok()?;
        let mut numeric = NumericLu::new();
        let scratch = symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default());
        let mut buffer = MemBuffer::try_new(scratch).ok()?;
        symbolic
            .factorize_numeric_lu(&mut numeric, a.as_ref(), Par::Seq, MemStack::new(&mut buffer), Default::default())
            .ok()?;
        Some(DirectSolve { unknown, symbolic, numeric, rhs: Mat::zeros(rows, 3), residual: Forcing::zeros(n) })
    }

    /// One Newton step of `N(x) = f` (`forcing` `None`: `f = 0`) on `state`: afterwards the
    /// moving vertices hold the fixed point up to rounding and the fixed vertices' `R` is up to
    /// date. Returns the largest position step taken (NaN if a value became non-finite).
    pub fn step(&mut self, op: &Operator, mesh: &PolyMesh, state: &mut State, forcing: Option<&Forcing>) -> f64 {
        kernel::residual(op, mesh, state, forcing, &mut self.residual);
        for (i, &u) in self.unknown.iter().enumerate() {
            if u == u32::MAX {
                continue;
            }
            let (rr, pr) = (2 * u as usize, 2 * u as usize + 1);
            for c in 0..3 {
                self.rhs[(rr, c)] = self.residual.r[i][c];
                self.rhs[(pr, c)] = self.residual.p[i][c];
            }
        }
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let Ok(mut buffer) = MemBuffer::try_new(self.symbolic.solve_in_place_scratch::<f64>(3, Par::Seq)) else {
            return f64::NAN;
        };
        lu.solve_in_place_with_conj(Conj::No, self.rhs.as_mut(), Par::Seq, MemStack::new(&mut buffer));
        let mut largest = 0.0f64;
        for (i, &u) in self.unknown.iter().enumerate() {
            if u == u32::MAX {
                continue;
            }
            let (rr, pr) = (2 * u as usize, 2 * u as usize + 1);
            let dr = DVec3::new(self.rhs[(rr, 0)], self.rhs[(rr, 1)], self.rhs[(rr, 2)]);
            let dp = DVec3::new(self.rhs[(pr, 0)], self.rhs[(pr, 1)], self.rhs[(pr, 2)]);
            state.r[i] += dr;
            state.p[i] += dp;
            let d = dp.length();
            largest = if largest.is_nan() || d.is_nan() { f64::NAN } else { largest.max(d) };
        }
        kernel::update_fixed_forced(op, state, forcing);
        largest
    }
}

/// The Jacobian entries of the two equations of moving vertex `i` (see the module docs), for
/// unknowns laid out in pairs (`2u`: `R`, `2u + 1`: `P` of the vertex numbered `u`): `u` is
/// `i`'s number and `index` numbers the other unknown vertices (`None`: held, not an unknown).
/// Calls `emit(row, column, value)`; a column may come more than once (its values add).
pub(super) fn jacobian_rows(
    op: &Operator,
    i: usize,
    u: usize,
    index: impl Fn(usize) -> Option<usize>,
    mut emit: impl FnMut(usize, usize, f64),
) {
    let slots = |i: usize| op.offsets[i] as usize..op.offsets[i + 1] as usize;
    let (rr, pr) = (2 * u, 2 * u + 1);
    let inv_k = 1.0 / op.k[i];
    // (Σ w_r R_j − R_i) / K_i, a fixed neighbour's R_j = (Σ w_p P_l − P_j) / K_j.
    emit(rr, rr, -inv_k);
    for s in slots(i) {
        let (j, w) = (op.neighbors[s] as usize, op.weight_r[s]);
        if w == 0.0 {
            continue;
        }
        if op.role[j] == Role::Fixed {
            let scale = w * inv_k / op.k[j];
            for t in slots(j) {
                if let Some(l) = index(op.neighbors[t] as usize) {
                    emit(rr, 2 * l + 1, scale * op.weight_p[t]);
                }
            }
        } else if let Some(v) = index(j) {
            emit(rr, 2 * v, w * inv_k);
        }
    }
    // (Σ w_p P_j − P_i) / K_i − R_i.
    emit(pr, pr, -inv_k);
    emit(pr, rr, -1.0);
    for s in slots(i) {
        if let Some(v) = index(op.neighbors[s] as usize) {
            emit(pr, 2 * v + 1, op.weight_p[s] * inv_k);
        }
    }
}

/// A level's factorisation, made on first use and dropped whenever its operator changes.
#[derive(Clone, Debug, Default)]
pub enum Direct {
    /// Not tried since the operator last changed.
    #[default]
    Unmade,
    /// The level cannot be solved directly (tension, size, a singular matrix, or a solve that
    /// failed).
    Unavailable,
    Made(Box<DirectSolve>),
}

impl Direct {
    /// The factorisation of `op`, made now if it was not tried yet.
    pub fn get(&mut self, op: &Operator) -> Option<&mut DirectSolve> {
        if matches!(self, Direct::Unmade) {
            *self = DirectSolve::new(op).map_or(Direct::Unavailable, |d| Direct::Made(Box::new(d)));
        }
        match self {
            Direct::Made(d) => Some(d),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::level::Level;
    use super::super::operator::Controls;
    use super::*;
    use crate::mesh::VertexId;

    /// A curved, closed cage of quads and triangles, some vertices fixed, refined `levels`
    /// times, with tension on one vertex when `tension` is positive.
    fn level(levels: usize, tension: f64) -> Level {
        let mut cage = crate::mesh::PolyMesh::from_polygons(
            vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.1),
                DVec3::new(1.1, 1.0, 0.0),
                DVec3::new(0.0, 0.9, 0.2),
                DVec3::new(0.1, 0.0, 1.0),
                DVec3::new(1.0, 0.2, 1.1),
                DVec3::new(1.0, 1.0, 0.9),
                DVec3::new(0.5, 1.4, 1.3),
                DVec3::new(-0.1, 1.0, 1.0),
            ],
            &[
                vec![0, 3, 2, 1],
                vec![0, 1, 5, 4],
                vec![1, 2, 6, 5],
                vec![2, 3, 8, 7, 6],
                vec![3, 0, 4, 8],
                vec![4, 5, 6],
                vec![4, 6, 7, 8],
            ],
        )
        .unwrap();
        cage.set_position(VertexId(7), DVec3::new(0.5, 1.5, 1.4));
        let fixed: Vec<bool> = (0..9).map(|v| v % 2 == 0).collect();
        let mut vertex_tension = vec![0.0; 9];
        vertex_tension[4] = tension;
        let edge_tension = vec![0.0; cage.edge_count()];
        let controls = Controls {
            fixed: &fixed,
            vertex_tension: &vertex_tension,
            edge_tension: &edge_tension,
            spacing: Default::default(),
        };
        let mut level = Level::cage(&cage, &controls);
        for _ in 0..levels {
            level = level.refine(&cage, &controls, false).unwrap();
        }
        level
    }

    /// The plain iteration run until its steps are at rounding level.
    fn iterated(level: &Level, forcing: Option<&Forcing>) -> State {
        let mut state = level.state.clone();
        for _ in 0..2_000_000 {
            let sweep = kernel::iterate_forced(&level.operator, &level.topology.mesh, &mut state, 0.6, forcing);
            if sweep.step < 1e-15 {
                break;
            }
        }
        state
    }

    fn distance(a: &[DVec3], b: &[DVec3]) -> f64 {
        a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
    }

    #[test]
    fn a_direct_solve_lands_on_the_plain_iterations_fixed_point() {
        for levels in [0, 1, 2] {
            let level = level(levels, 0.0);
            let (op, mesh) = (&level.operator, &level.topology.mesh);
            let mut direct = DirectSolve::new_unbounded(op).expect("no tension");
            let mut state = level.state.clone();
            let first = direct.step(op, mesh, &mut state, None);
            let second = direct.step(op, mesh, &mut state, None);
            assert!(first > 1e-3 && second < 1e-12, "level {levels}: steps {first:e}, {second:e}");
            let reference = iterated(&level, None);
            let d = distance(&state.p, &reference.p);
            assert!(d < 1e-11, "level {levels}: {d:e} from the plain iteration's fixed point");
            assert!(distance(&state.r, &reference.r) < 1e-9);
            // With a right-hand side, as a multigrid coarse grid has.
            let n = level.vertex_count();
            let mut forcing = Forcing::zeros(n);
            for i in 0..n {
                if op.role[i] == Role::Moving {
                    let t = i as f64;
                    forcing.r[i] = 0.1 * DVec3::new(t.sin(), (2.0 * t).cos(), 0.3);
                    forcing.p[i] = 0.05 * DVec3::new((3.0 * t).cos(), 0.2, t.sin());
                }
            }
            let mut forced = level.state.clone();
            direct.step(op, mesh, &mut forced, Some(&forcing));
            let reference = iterated(&level, Some(&forcing));
            let d = distance(&forced.p, &reference.p);
            assert!(d < 1e-10, "level {levels}, forced: {d:e} from the plain iteration's fixed point");
        }
    }

    #[test]
    fn levels_with_tension_or_many_vertices_are_not_factorised() {
        assert!(DirectSolve::new(&level(1, 0.0).operator).is_some());
        assert!(DirectSolve::new(&level(1, 2.0).operator).is_none());
        let big = level(3, 0.0);
        assert!(big.vertex_count() > MAX_VERTICES);
        assert!(DirectSolve::new(&big.operator).is_none());
        assert!(DirectSolve::new_unbounded(&big.operator).is_some());
    }

    #[test]
    fn the_solution_does_not_depend_on_the_thread_count() {
        let level = level(2, 0.0);
        let solve = || {
            let mut direct = DirectSolve::new_unbounded(&level.operator).unwrap();
            let mut state = level.state.clone();
            direct.step(&level.operator, &level.topology.mesh, &mut state, None);
            state.p.iter().flat_map(|p| p.to_array()).map(f64::to_bits).collect::<Vec<u64>>()
        };
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(solve);
        let four = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap().install(solve);
        assert_eq!(one, four);
    }
}
