//! The smoothing pre-fit of the shape-keeping surface fairing: Whittaker's smoother on a grid
//! (a departure from the paper, whose surface filter works on the measured points themselves;
//! `docs/log-aesthetic.md`, "Shape-keeping fairing of surfaces").
//!
//! The surface filter reads the Gaussian curvature from second differences of the grid, so noise
//! of a fraction of the spacing is most of what it reads, and every constant-K surface through
//! the boundary is a fixed point: with nothing holding it to the data, the grid walks. As for
//! curves ([`super::prefit`]), the points are first smoothed at the scale the noise allows, and
//! the filter then starts from the smoothed grid and is pulled back towards it every pass.
//!
//! The smoother: the interior points `S` minimising `Σ |S_ij − D_ij|² + μ (Σ |Δ³_j S|² +
//! Σ |Δ³_i S|²)`, third differences along every row and every column (the null space holds
//! every surface quadratic in each parameter, so a sphere cap of a few points per radian is barely
//! flattened), with the boundary rows and columns kept, as the filter keeps them. Its normal
//! equations are `X + μ (A_r X + X A_c) = F` for the interior points `X` (one matrix per
//! coordinate), `A_r` and `A_c` the one-dimensional operators `ΔᵀΔ` of a column and a row with
//! their ends fixed, and `F` the data less the boundary's pull. Both are symmetric: with their
//! eigenvectors `A = Q Λ Qᵀ` the system is diagonal in `Q_r ⊗ Q_c`, so every μ costs `O(r c)`
//! once the data are transformed, the trace of the hat matrix is exactly
//! `Σ_ab 1 / (1 + μ (λ_a + λ_b))`, and the residual is measured in the transformed space (the
//! transform is orthogonal). μ is chosen by generalised cross-validation, as for curves.
//!
//! Where it is weak: the differences run over the grid's indices, so it assumes the points are
//! roughly evenly spaced in each direction (the filter assumes it too).

use super::prefit::gcv_search;
use super::surface::Grid;
use crate::DVec3;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par, Spec};

/// The smoothed grid and what was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct GridPrefit {
    /// The smoothed points, row by row as in the grid; the boundary is the input's.
    pub points: Vec<DVec3>,
    /// The smoothing μ (chosen by GCV unless given).
    pub smoothing: f64,
    /// Degrees of freedom `tr H` of the smoother over the interior points.
    pub dof: f64,
    /// The noise level the fit implies: RMS distance of an interior point from where it belongs.
    pub noise: f64,
}

/// Smooths the interior of `grid` with the given μ or one chosen by GCV. A grid whose rows or
/// columns are too short for a third difference inside comes back unchanged.
pub fn prefit_grid(grid: &Grid, smoothing: Option<f64>) -> GridPrefit {
    let unchanged = || GridPrefit {
        points: grid.points.clone(),
        smoothing: 0.0,
        dof: ((grid.rows.saturating_sub(2)) * grid.cols.saturating_sub(2)) as f64,
        noise: 0.0,
    };
    let Some(problem) = Problem::new(grid) else { return unchanged() };
    let m = problem.interior() as f64;
    let top = 2.0 * 3.0 * (grid.rows.max(grid.cols) as f64).log10() + 1.0;
    let Some(mu) = smoothing.or_else(|| {
        gcv_search(top, |log_mu| {
            let mu = 10f64.powf(log_mu);
            let tr = problem.trace(mu);
            if m - tr > 1e-9 { m * problem.rss(mu) / (m - tr).powi(2) } else { f64::INFINITY }
        })
    }) else {
        return unchanged();
    };
    let dof = problem.trace(mu);
    let noise = (problem.rss(mu) / (m - dof).max(1e-12)).sqrt();
    GridPrefit { points: problem.points(grid, mu), smoothing: mu, dof, noise }
}

/// The eigenvectors (columns) and eigenvalues of the operator `ΔᵀΔ` of third differences along a
/// line of `len` points with both ends fixed, over its `len − 2` inner points, and its pull from
/// the two ends: `ends[k]` is `(K[k + 1][0], K[k + 1][len − 1])`.
struct LineOperator {
    vectors: Mat<f64>,
    values: Vec<f64>,
    ends: Vec<(f64, f64)>,
}

impl LineOperator {
    fn new(len: usize) -> Option<LineOperator> {
        const D3: [f64; 4] = [-1.0, 3.0, -3.0, 1.0];
        let mut k = Mat::<f64>::zeros(len, len);
        for r in 0..len.checked_sub(3)? {
            for a in 0..4 {
                for b in 0..4 {
                    k[(r + a, r + b)] += D3[a] * D3[b];
                }
            }
        }
        let inner = len - 2;
        let block = Mat::<f64>::from_fn(inner, inner, |i, j| k[(i + 1, j + 1)]);
        let ends = (0..inner).map(|i| (k[(i + 1, 0)], k[(i + 1, len - 1)])).collect();
        let mut vectors = Mat::<f64>::zeros(inner, inner);
        let mut values = Mat::<f64>::zeros(inner, 1);
        // Sequential, so the result does not depend on the thread count.
        let scratch = self_adjoint_evd_scratch::<f64>(inner, ComputeEigenvectors::Yes, Par::Seq, Spec::default());
        self_adjoint_evd(
            block.as_ref(),
            values.as_mut().col_mut(0).as_diagonal_mut(),
            Some(vectors.as_mut()),
            Par::Seq,
            MemStack::new(&mut MemBuffer::new(scratch)),
            Spec::default(),
        )
        .ok()?;
        // ΔᵀΔ is positive semi-definite; round-off may leave a null eigenvalue a hair below 0.
        let values = (0..inner).map(|i| values[(i, 0)].max(0.0)).collect();
        Some(LineOperator { vectors, values, ends })
    }
}

/// `a · b` and `aᵀ · b` computed sequentially.
fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), b.ncols());
    matmul(out.as_mut(), Accum::Replace, a, b, 1.0, Par::Seq);
    out
}

/// The smoothing problem of one grid, transformed into the operators' eigenvector basis.
struct Problem {
    rows: LineOperator,
    cols: LineOperator,
    /// Per coordinate: `Q_rᵀ D Q_c` and `Q_rᵀ B Q_c` for the interior data D and the boundary's
    /// pull B (the right-hand side is `D − μ B`).
    data: [Mat<f64>; 3],
    pull: [Mat<f64>; 3],
}

impl Problem {
    fn new(grid: &Grid) -> Option<Problem> {
        let (rows, cols) = (LineOperator::new(grid.rows)?, LineOperator::new(grid.cols)?);
        let (r, c) = (grid.rows - 2, grid.cols - 2);
        let transform = |m: Mat<f64>| {
            let left = product(rows.vectors.transpose(), m.as_ref());
            product(left.as_ref(), cols.vectors.as_ref())
        };
        let data = std::array::from_fn(|k| transform(Mat::from_fn(r, c, |a, b| grid.at(a + 1, b + 1)[k])));
        let pull = std::array::from_fn(|k| {
            transform(Mat::from_fn(r, c, |a, b| {
                let (i, j) = (a + 1, b + 1);
                let (west, east) = cols.ends[b];
                let (north, south) = rows.ends[a];
                west * grid.at(i, 0)[k]
                    + east * grid.at(i, grid.cols - 1)[k]
                    + north * grid.at(0, j)[k]
                    + south * grid.at(grid.rows - 1, j)[k]
            }))
        });
        Some(Problem { rows, cols, data, pull })
    }

    fn interior(&self) -> usize {
        self.rows.values.len() * self.cols.values.len()
    }

    /// The smoothed interior in the transformed basis, per coordinate, handed to `each` with the
    /// transformed data: `(z, d)` per entry.
    fn for_each(&self, mu: f64, mut each: impl FnMut(usize, usize, usize, f64, f64)) {
        for k in 0..3 {
            for (a, la) in self.rows.values.iter().enumerate() {
                for (b, lb) in self.cols.values.iter().enumerate() {
                    let d = self.data[k][(a, b)];
                    let z = (d - mu * self.pull[k][(a, b)]) / (1.0 + mu * (la + lb));
                    each(k, a, b, z, d);
                }
            }
        }
    }

    /// Residual sum of squares over the interior (the basis is orthonormal, so it is the same
    /// in either basis).
    fn rss(&self, mu: f64) -> f64 {
        let mut sum = 0.0;
        self.for_each(mu, |_, _, _, z, d| sum += (z - d).powi(2));
        sum
    }

    /// `tr H` over the interior points.
    fn trace(&self, mu: f64) -> f64 {
        let lb = &self.cols.values;
        self.rows.values.iter().map(|la| lb.iter().map(|lb| 1.0 / (1.0 + mu * (la + lb))).sum::<f64>()).sum()
    }

    /// The smoothed grid for μ, boundary kept.
    fn points(&self, grid: &Grid, mu: f64) -> Vec<DVec3> {
        let (r, c) = (self.rows.values.len(), self.cols.values.len());
        let mut z: [Mat<f64>; 3] = std::array::from_fn(|_| Mat::zeros(r, c));
        self.for_each(mu, |k, a, b, value, _| z[k][(a, b)] = value);
        let back: Vec<Mat<f64>> = z
            .iter()
            .map(|z| product(product(self.rows.vectors.as_ref(), z.as_ref()).as_ref(), self.cols.vectors.transpose()))
            .collect();
        let mut points = grid.points.clone();
        for a in 0..r {
            for b in 0..c {
                points[(a + 1) * grid.cols + b + 1] = DVec3::new(back[0][(a, b)], back[1][(a, b)], back[2][(a, b)]);
            }
        }
        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of `rows × cols` points of `f(u, v)` on unit spacing.
    fn grid_of(rows: usize, cols: usize, f: impl Fn(f64, f64) -> DVec3) -> Grid {
        let points = (0..rows * cols).map(|k| f((k / cols) as f64, (k % cols) as f64)).collect();
        Grid { rows, cols, points }
    }

    #[test]
    fn quadratics_in_each_parameter_are_kept() {
        // Third differences vanish on them, so any μ keeps them.
        let grid = grid_of(9, 12, |u, v| DVec3::new(u, v, 0.3 * u * u - 0.2 * v * v + 0.1 * u * v * v * u));
        for mu in [1.0, 1e4] {
            let fit = prefit_grid(&grid, Some(mu));
            let off = fit.points.iter().zip(&grid.points).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            // Relative to the largest coordinate (about 800): round-off of the eigenbasis.
            assert!(off < 1e-10 * 800.0, "μ = {mu}: {off:e}");
        }
    }

    #[test]
    fn the_eigenbasis_solve_matches_a_direct_one() {
        // Independent check: the normal equations assembled densely and solved by faer's LU.
        let (rows, cols) = (6, 7);
        let wobble = |u: f64, v: f64| (1.7 * u + 2.3 * v).sin() * 0.1;
        let grid = grid_of(rows, cols, |u, v| DVec3::new(u, v + wobble(v, u), (u * v).sqrt() + wobble(u, v)));
        let mu = 3.0;
        let fit = prefit_grid(&grid, Some(mu));
        let index = |i: usize, j: usize| (i - 1) * (cols - 2) + j - 1;
        let n = (rows - 2) * (cols - 2);
        let mut a = Mat::<f64>::identity(n, n);
        let mut rhs = Mat::<f64>::zeros(n, 3);
        for i in 1..rows - 1 {
            for j in 1..cols - 1 {
                for k in 0..3 {
                    rhs[(index(i, j), k)] = grid.at(i, j)[k];
                }
            }
        }
        // Every third difference along a row or a column, as a list of (point, weight).
        let mut lines: Vec<[(usize, usize, f64); 4]> = Vec::new();
        for i in 0..rows {
            for j in 0..cols - 3 {
                lines.push(std::array::from_fn(|t| (i, j + t, [-1.0, 3.0, -3.0, 1.0][t])));
            }
        }
        for j in 0..cols {
            for i in 0..rows - 3 {
                lines.push(std::array::from_fn(|t| (i + t, j, [-1.0, 3.0, -3.0, 1.0][t])));
            }
        }
        let inner = |i: usize, j: usize| i > 0 && j > 0 && i + 1 < rows && j + 1 < cols;
        for line in &lines {
            for &(i, j, w) in line {
                if !inner(i, j) {
                    continue;
                }
                for &(p, q, x) in line {
                    if inner(p, q) {
                        a[(index(i, j), index(p, q))] += mu * w * x;
                    } else {
                        for k in 0..3 {
                            rhs[(index(i, j), k)] -= mu * w * x * grid.at(p, q)[k];
                        }
                    }
                }
            }
        }
        use faer::linalg::solvers::Solve;
        let x = a.partial_piv_lu().solve(&rhs);
        for i in 1..rows - 1 {
            for j in 1..cols - 1 {
                let p = fit.points[i * cols + j];
                let q = DVec3::new(x[(index(i, j), 0)], x[(index(i, j), 1)], x[(index(i, j), 2)]);
                assert!(p.distance(q) < 1e-10, "({i}, {j}): {p} against {q}");
            }
        }
        for j in 0..cols {
            assert_eq!(fit.points[j], grid.points[j]);
        }
    }
}
