//! Steps 4 and 5: solving for the cage whose limit points are the targets.
//!
//! Step 4 (the paper's eq. 3, `V_C = M V_A`): one sparse LU factorisation of the limit-position
//! matrix `M` (faer, with a fill-reducing ordering), solved for the three coordinates. The
//! paper solves densely, O(n³); `M` has about seven entries a row, and its factorisation grows
//! like that of a surface mesh's Laplacian under nested dissection, about n^1.5 in the large:
//! the `cage_fit` bench measured 9, 62 and 1,680 ms for cages of 1 k, 10 k and 100 k vertices
//! (2 cores), so near-linear up to about 10 k vertices and then dominated by fill-in. `M` is not symmetric but is well conditioned (its smallest eigenvalue on a regular
//! mesh is 1/4), and every solve is checked by its residual.
//!
//! The further rounds ([`two_sided`](super::two_sided)) solve weighted least squares over many
//! more points of the limit surface by conjugate gradients on the normal equations
//! ([`least_squares`], CGLS), started from the current cage, so no second factorisation is needed.

use crate::DVec3;
use crate::subdiv::SparseRows;
use crate::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};

/// A factorised square sparse matrix, reusable for any number of right-hand sides.
pub struct Factorised {
    lu: faer::sparse::linalg::solvers::Lu<usize, f64>,
    matrix: SparseRows,
}

impl std::fmt::Debug for Factorised {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Factorised({} rows)", self.matrix.row_count())
    }
}

impl Factorised {
    /// Factorises a square matrix.
    pub fn new(matrix: &SparseRows) -> Result<Self> {
        let n = matrix.row_count();
        if matrix.column_count != n {
            return Err(Error::Solver(format!("the limit matrix is {n} × {}, not square", matrix.column_count)));
        }
        let triplets: Vec<Triplet<usize, usize, f64>> =
            (0..n).flat_map(|i| matrix.row(i).map(move |(c, w)| Triplet::new(i, c as usize, w))).collect();
        let csc = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
            .map_err(|e| Error::Solver(format!("cannot assemble the limit matrix ({e:?})")))?;
        let lu = csc.sp_lu().map_err(|e| {
            Error::Solver(format!("the limit matrix cannot be factorised ({e:?}); the cage may be degenerate"))
        })?;
        Ok(Factorised { lu, matrix: matrix.clone() })
    }

    /// Solves `M x = rhs` for three coordinates at once; fails when the result is not finite or
    /// its residual exceeds `tolerance`.
    pub fn solve(&self, rhs: &[DVec3], tolerance: f64) -> Result<Vec<DVec3>> {
        let n = rhs.len();
        let mut b = faer::Mat::<f64>::from_fn(n, 3, |i, j| rhs[i][j]);
        self.lu.solve_in_place(b.as_mut());
        let x: Vec<DVec3> = (0..n).map(|i| DVec3::new(b[(i, 0)], b[(i, 1)], b[(i, 2)])).collect();
        if x.iter().any(|p| !p.is_finite()) {
            return Err(Error::Solver("the limit-position solve gave non-finite positions".into()));
        }
        let residual = self.matrix.apply(&x).iter().zip(rhs).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
        if residual > tolerance {
            return Err(Error::Solver(format!(
                "the limit-position solve is inaccurate (residual {residual:.3e} above {tolerance:.3e}); the cage is \
                 nearly degenerate"
            )));
        }
        Ok(x)
    }
}

/// The product `a · b` of two sparse row matrices (`a`'s columns are `b`'s rows), each row's
/// entries in increasing column order.
pub fn compose(a: &SparseRows, b: &SparseRows) -> SparseRows {
    let mut out = SparseRows::with_columns(b.column_count);
    let mut dense = vec![0.0; b.column_count];
    let mut touched: Vec<u32> = Vec::new();
    for i in 0..a.row_count() {
        for (k, wa) in a.row(i) {
            for (c, wb) in b.row(k as usize) {
                if dense[c as usize] == 0.0 {
                    touched.push(c);
                }
                dense[c as usize] += wa * wb;
            }
        }
        touched.sort_unstable();
        touched.dedup();
        out.push_row(touched.iter().map(|&c| (c, std::mem::take(&mut dense[c as usize]))));
        touched.clear();
    }
    out
}

/// `Aᵀ y` for a sparse row matrix.
/// A linear map from the cage's points to values at other points, with its transpose: what
/// [`least_squares`] needs of its matrix.
pub trait LinearMap: Sync {
    /// `A x`.
    fn apply(&self, x: &[DVec3]) -> Vec<DVec3>;
    /// `Aᵀ y`.
    fn apply_transposed(&self, y: &[DVec3]) -> Vec<DVec3>;
}

impl LinearMap for SparseRows {
    fn apply(&self, x: &[DVec3]) -> Vec<DVec3> {
        SparseRows::apply(self, x)
    }

    fn apply_transposed(&self, y: &[DVec3]) -> Vec<DVec3> {
        apply_transposed(self, y)
    }
}

fn apply_transposed(a: &SparseRows, y: &[DVec3]) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; a.column_count];
    for (i, &yi) in y.iter().enumerate() {
        for (c, w) in a.row(i) {
            out[c as usize] += w * yi;
        }
    }
    out
}

/// `L D` for a diagonal `D` (one positive factor per column): least squares on it, with
/// `x = D y`, solve the same problem as on `L`, in fewer steps when `D` evens out the columns'
/// norms (Jacobi preconditioning of the normal equations).
struct ColumnScaled<'a, L: LinearMap> {
    inner: &'a L,
    scales: &'a [f64],
}

impl<L: LinearMap> LinearMap for ColumnScaled<'_, L> {
    fn apply(&self, y: &[DVec3]) -> Vec<DVec3> {
        let x: Vec<DVec3> = y.iter().zip(self.scales).map(|(p, s)| *p * *s).collect();
        self.inner.apply(&x)
    }

    fn apply_transposed(&self, r: &[DVec3]) -> Vec<DVec3> {
        let mut out = self.inner.apply_transposed(r);
        out.iter_mut().zip(self.scales).for_each(|(p, s)| *p *= *s);
        out
    }
}

/// [`least_squares`] on `L` with its columns scaled by `scales` (see [`ColumnScaled`]): the
/// same problem and start, the gradient measured in the scaled unknowns.
pub fn least_squares_scaled(
    l: &impl LinearMap,
    scales: &[f64],
    c: &[DVec3],
    x: &mut [DVec3],
    relative: f64,
    max_iterations: usize,
) -> usize {
    let mut y: Vec<DVec3> = x.iter().zip(scales).map(|(p, s)| *p / *s).collect();
    let steps = least_squares(&ColumnScaled { inner: l, scales }, c, &mut y, relative, max_iterations);
    for ((xi, yi), s) in x.iter_mut().zip(&y).zip(scales) {
        *xi = *yi * *s;
    }
    steps
}

/// Least squares `min |L x − c|²` by CGLS from `x`, per coordinate at once; stops when the
/// gradient's norm falls below `relative` times its start, or after `max_iterations`.
pub fn least_squares(l: &impl LinearMap, c: &[DVec3], x: &mut [DVec3], relative: f64, max_iterations: usize) -> usize {
    let dot = |u: &[DVec3], v: &[DVec3]| u.iter().zip(v).fold(DVec3::ZERO, |s, (a, b)| s + *a * *b);
    let mut r: Vec<DVec3> = c.iter().zip(l.apply(x)).map(|(c, lx)| *c - lx).collect();
    let mut s = l.apply_transposed(&r);
    let mut p = s.clone();
    let mut gamma = dot(&s, &s);
    let start = gamma;
    let mut iterations = 0;
    while iterations < max_iterations && (gamma.cmpgt(relative * relative * start)).any() {
        let q = l.apply(&p);
        let qq = dot(&q, &q);
        // Coordinates already converged (or with a zero step) keep their values.
        let alpha = DVec3::select(qq.cmpgt(DVec3::ZERO), gamma / qq.max(DVec3::splat(f64::MIN_POSITIVE)), DVec3::ZERO);
        for (xi, pi) in x.iter_mut().zip(&p) {
            *xi += alpha * *pi;
        }
        for (ri, qi) in r.iter_mut().zip(&q) {
            *ri -= alpha * *qi;
        }
        s = l.apply_transposed(&r);
        let next = dot(&s, &s);
        let beta =
            DVec3::select(gamma.cmpgt(DVec3::ZERO), next / gamma.max(DVec3::splat(f64::MIN_POSITIVE)), DVec3::ZERO);
        for (pi, si) in p.iter_mut().zip(&s) {
            *pi = *si + beta * *pi;
        }
        gamma = next;
        iterations += 1;
    }
    iterations
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tridiagonal(n: usize) -> SparseRows {
        let mut m = SparseRows::with_columns(n);
        for i in 0..n {
            let mut row = vec![(i as u32, 4.0 / 6.0)];
            if i > 0 {
                row.push((i as u32 - 1, 1.0 / 6.0));
            }
            if i + 1 < n {
                row.push((i as u32 + 1, 1.5 / 6.0));
            }
            m.push_row(row);
        }
        m
    }

    #[test]
    fn the_solve_inverts_the_matrix() {
        let m = tridiagonal(50);
        let x: Vec<DVec3> = (0..50).map(|i| DVec3::new(i as f64, (i as f64).sin(), 1.0)).collect();
        let b = m.apply(&x);
        let back = Factorised::new(&m).unwrap().solve(&b, 1e-9).unwrap();
        for (a, e) in back.iter().zip(&x) {
            assert!((*a - *e).length() < 1e-10);
        }
    }

    #[test]
    fn scaled_columns_solve_the_same_least_squares_in_fewer_steps() {
        // A tall system whose columns' norms differ by up to 1000: rows of neighbouring columns,
        // column j scaled by 10^(3 j / n).
        let n = 40;
        let weight = |j: usize| 10f64.powf(3.0 * j as f64 / n as f64);
        let mut m = SparseRows::with_columns(n);
        for i in 0..3 * n {
            let j = i % n;
            let k = (i * 7 + 3) % n;
            if k == j {
                m.push_row([(j as u32, weight(j))]);
            } else {
                m.push_row([(j as u32, weight(j)), (k as u32, 0.5 * weight(k))]);
            }
        }
        let c: Vec<DVec3> = (0..3 * n).map(|i| DVec3::new((i as f64).sin(), 1.0, (0.3 * i as f64).cos())).collect();
        // The exact solution of the normal equations, by the direct solve of `MᵀM`.
        let normal = compose(&m.transpose(), &m);
        let exact = Factorised::new(&normal).unwrap().solve(&LinearMap::apply_transposed(&m, &c), 1e-12).unwrap();
        let scales: Vec<f64> =
            (0..n).map(|j| 1.0 / normal.row(j).find(|&(c, _)| c as usize == j).unwrap().1.sqrt()).collect();
        let (mut plain, mut scaled) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let plain_steps = least_squares(&m, &c, &mut plain, 1e-10, 10_000);
        let scaled_steps = least_squares_scaled(&m, &scales, &c, &mut scaled, 1e-10, 10_000);
        let size = exact.iter().map(|p| p.length()).fold(0.0, f64::max);
        for (x, e) in scaled.iter().zip(&exact) {
            assert!((*x - *e).length() < 1e-6 * size, "{x} vs {e}");
        }
        for (x, e) in plain.iter().zip(&exact) {
            assert!((*x - *e).length() < 1e-6 * size, "{x} vs {e}");
        }
        assert!(2 * scaled_steps < plain_steps, "{scaled_steps} scaled steps against {plain_steps}");
    }

    #[test]
    fn singular_matrices_are_a_solver_error() {
        let mut m = SparseRows::with_columns(2);
        m.push_row([(0, 1.0), (1, 1.0)]);
        m.push_row([(0, 2.0), (1, 2.0)]);
        let result = Factorised::new(&m).and_then(|f| f.solve(&[DVec3::X, DVec3::Y], 1e-9));
        assert!(matches!(result, Err(Error::Solver(_))), "{result:?}");
    }

    #[test]
    fn compose_and_least_squares_match_dense_references() {
        let a = tridiagonal(6);
        let mut b = SparseRows::with_columns(4);
        for i in 0..6u32 {
            b.push_row([(i % 4, 1.0), ((i + 1) % 4, 0.5)]);
        }
        let ab = compose(&a, &b);
        // Dense reference product.
        let dense = |m: &SparseRows, rows: usize, cols: usize| {
            let mut d = vec![vec![0.0; cols]; rows];
            for i in 0..rows {
                for (c, w) in m.row(i) {
                    d[i][c as usize] += w;
                }
            }
            d
        };
        let (da, db, dab) = (dense(&a, 6, 6), dense(&b, 6, 4), dense(&ab, 6, 4));
        for i in 0..6 {
            for j in 0..4 {
                let e: f64 = (0..6).map(|k| da[i][k] * db[k][j]).sum();
                assert!((dab[i][j] - e).abs() < 1e-15);
            }
        }
        // Least squares of an overdetermined system: the residual is orthogonal to the columns.
        let c: Vec<DVec3> = (0..6).map(|i| DVec3::new(i as f64, 1.0 / (1.0 + i as f64), -(i as f64).powi(2))).collect();
        let mut x = vec![DVec3::ZERO; 4];
        least_squares(&ab, &c, &mut x, 1e-13, 100);
        let r: Vec<DVec3> = c.iter().zip(ab.apply(&x)).map(|(c, y)| *c - y).collect();
        for g in apply_transposed(&ab, &r) {
            assert!(g.abs().max_element() < 1e-9, "{g}");
        }
    }
}
