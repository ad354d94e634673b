//! The constant-Gaussian-curvature surface filter on regular grids (paper sec. 5.3, eq. 15).
//!
//! The surface is a grid of points `P_ij` (rows i, columns j) on unit parameter spacing. At an
//! interior point the first derivatives are central differences, `S_uu` and `S_vv` three-point
//! second differences along the row and the column, `S_uv` the central difference of the four
//! diagonal neighbours; with the unit normal N the fundamental forms give
//! `K = (eg − f²)/(EG − F²)`. N is the area-weighted mean of the normals of the eight triangles
//! the point makes with its ring of eight neighbours; that sum of cross products does not depend
//! on the point itself, so N stays fixed while the point moves, as the paper assumes. The point
//! moves along N from the mean `P_ijc` of its eight neighbours, `P_ij' = P_ijc + φ N`: only `S_uu`
//! and `S_vv` involve it, each with weight −2, so `K(φ)` is quadratic in φ; φ makes K equal to the
//! mean C of K over the point's 3 × 3 neighbourhood. Of the two roots the paper takes "the one
//! of smaller |φ|, so the smaller move"; we take the root nearest the point's own offset
//! `(P_ij − P_ijc)·N`, which is the smaller move. (Smaller |φ| measured from `P_ijc`, as the
//! earlier spec read it, `docs/README.md` correction 5, picks the wrong root on a cylinder: the
//! neighbours' mean lies inside it, and the
//! other root turns the bending from around the axis to along it.) As in the curve filter the point moves a fraction ω
//! ([`SurfaceSettings::relaxation`]) of the way there, and the passes go over the four classes of
//! (row parity, column parity) in turn, each from the state the previous one left, so no point
//! moves together with a neighbour and the result does not depend on the thread count.
//!
//! The boundary rows and columns stay where they are: they set the shape the curvature spreads
//! into. Where the quadratic has no real root (the mean asks for a curvature the point cannot
//! reach by moving along N) the point is left in place and counted.
//!
//! Where it is weak: the parameter spacing is taken as uniform, so a grid whose rows are very
//! unevenly spaced has a biased K; a constant K is the only target (the paper's first step towards
//! log-aesthetic surfaces), so the filter also removes curvature variation a designer wanted; the
//! mean over 3 × 3 spreads a change by one cell a pass, so large grids need many passes.

use super::filter::DataTerm;
use super::surface_prefit::{GridPrefit, prefit_grid};
use crate::{DVec3, Error, Result};

/// A regular grid of points, row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Rows (i).
    pub rows: usize,
    /// Columns (j).
    pub cols: usize,
    /// `rows × cols` points; point (i, j) is `points[i * cols + j]`.
    pub points: Vec<DVec3>,
}

impl Grid {
    /// Checks the shape and the points: at least 3 × 3, finite, no two neighbours in a row or
    /// column at the same place.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Input(m));
        if self.rows < 3 || self.cols < 3 {
            return bad(format!(
                "a surface grid needs at least 3 × 3 points (one interior point), got {} × {}",
                self.rows, self.cols
            ));
        }
        if self.points.len() != self.rows * self.cols {
            return bad(format!(
                "a {} × {} grid needs {} points, got {}",
                self.rows,
                self.cols,
                self.rows * self.cols,
                self.points.len()
            ));
        }
        if let Some(k) = self.points.iter().position(|p| !p.is_finite()) {
            return bad(format!("grid point ({}, {}) has a non-finite coordinate", k / self.cols, k % self.cols));
        }
        let size = crate::mesh::bounding_box(&self.points).map_or(0.0, |(lo, hi)| (hi - lo).length());
        if !(size > 0.0 && size < 1e100) {
            return bad("the grid points all coincide (or are absurdly far apart)".into());
        }
        for i in 0..self.rows {
            for j in 0..self.cols {
                let p = self.at(i, j);
                let repeated = (j + 1 < self.cols && p.distance(self.at(i, j + 1)) <= 1e-12 * size)
                    || (i + 1 < self.rows && p.distance(self.at(i + 1, j)) <= 1e-12 * size);
                if repeated {
                    return bad(format!(
                        "grid point ({i}, {j}) coincides with a neighbour: the grid is degenerate there"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Point (i, j).
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.cols + j]
    }
}

/// Settings of the surface filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSettings {
    /// Fraction ω of the way to its target a point moves in a pass, in (0, 1].
    pub relaxation: f64,
    /// Stop when a pass's largest move is below `tolerance` × the mean spacing of the grid.
    pub tolerance: f64,
    /// Cap on passes of [`SurfaceFilter::run_to_convergence`].
    pub max_passes: usize,
    /// `Some`: smooth the grid first ([`super::surface_prefit`]) and hold every move to that
    /// pre-fit (keeps the shape of a noisy grid); `None`: the paper's filter on the points as given.
    pub data_term: Option<DataTerm>,
}

impl SurfaceSettings {
    /// The default settings with the default [`DataTerm`]: the fairing for measured points, which
    /// removes their noise and keeps the surface where they were.
    pub fn keeping_shape() -> Self {
        SurfaceSettings { data_term: Some(DataTerm::default()), ..SurfaceSettings::default() }
    }
}

impl Default for SurfaceSettings {
    fn default() -> Self {
        SurfaceSettings { relaxation: 0.5, tolerance: 1e-4, max_passes: 5000, data_term: None }
    }
}

/// How the surface filter stands.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceStatus {
    /// Passes run.
    pub passes: usize,
    /// Largest move of the last pass relative to the mean spacing (∞ before the first pass).
    pub last_move: f64,
    /// Interior points left in place in the last pass (no real root).
    pub held: usize,
    /// True once a pass moved no point by more than the tolerance.
    pub converged: bool,
}

/// Per interior point: K and what the move needs (the fixed normal, the fundamental forms at the
/// neighbours' mean).
#[derive(Clone, Copy, Debug)]
struct Local {
    gaussian: f64,
    normal: DVec3,
    centre: DVec3,
    e: f64,
    f: f64,
    g: f64,
    det: f64,
}

/// The eight neighbours of an interior point in counter-clockwise order in (i, j).
const RING: [(isize, isize); 8] = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)];

/// K and the move data at interior point (i, j); `None` where the normal or the first
/// fundamental form degenerates.
fn local(grid: &Grid, i: usize, j: usize) -> Option<Local> {
    let q = |di: isize, dj: isize| grid.at((i as isize + di) as usize, (j as isize + dj) as usize);
    let p = grid.at(i, j);
    let mut area = DVec3::ZERO;
    let mut centre = DVec3::ZERO;
    for k in 0..8 {
        let (a, b) = (RING[k], RING[(k + 1) % 8]);
        area += (q(a.0, a.1) - p).cross(q(b.0, b.1) - p);
        centre += q(a.0, a.1);
    }
    let centre = centre / 8.0;
    let normal = area.try_normalize()?;
    let su = 0.5 * (q(1, 0) - q(-1, 0));
    let sv = 0.5 * (q(0, 1) - q(0, -1));
    let suv = 0.25 * (q(1, 1) - q(1, -1) - q(-1, 1) + q(-1, -1));
    let det = su.length_squared() * sv.length_squared() - su.dot(sv).powi(2);
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    let (suu, svv) = (q(1, 0) + q(-1, 0) - 2.0 * p, q(0, 1) + q(0, -1) - 2.0 * p);
    let (e, f, g) = (suu.dot(normal), suv.dot(normal), svv.dot(normal));
    let gaussian = (e * g - f * f) / det;
    // At the neighbours' mean the second derivatives gain 2 (p − centre)·N.
    let shift = 2.0 * (p - centre).dot(normal);
    Some(Local { gaussian, normal, centre, e: e + shift, f, g: g + shift, det })
}

/// With the data term, how far point (i, j) moves along its `normal`: one damped Gauss–Newton
/// step on the spread of K over its 3 × 3 block, `Σ_b (K_b − C)²` with `C` the block's mean,
/// `δ = −Σ J_b r_b / (Σ J_b² + (t / h)²)`, the slopes `J_b = ∂K_b/∂δ` of every K the point
/// takes part in measured by moving it, `h` the local spacing and `t = 2 |C|`, so a move of a
/// spacing is what it takes to change K by its own size; at most a quarter spacing.
///
/// The paper solves `K(φ) = C` at the point alone and takes a root; but K is a parabola in φ
/// whose vertex is where `e + g = 0`, and a surface of negative curvature sampled along its lines
/// of curvature sits there (the pseudosphere on its meridians and parallels has `e = −g`
/// exactly): an exact pseudosphere had no root at a fifth of its points and the rest jumped
/// between roots, flattening it to K ≈ 0 (12 × 12 and 24 × 24 grids). A Newton step on the
/// point's own K alone was no better on noisy ones: a point's move changes its neighbours' K
/// with half the weight and the opposite sign, and the moves grew into a checkerboard. The block
/// step sees all of them. The point moves from where it is, not from the neighbours' mean, which
/// slides it along the surface towards even spacing and on the pseudosphere's grid (three to
/// one along its meridians) moved it off the pre-fit faster than the data term pulled it back.
fn block_step(grid: &mut Grid, i: usize, j: usize, normal: DVec3, target: f64) -> Option<f64> {
    let (rows, cols) = (grid.rows, grid.cols);
    let inside = |a: usize, b: usize| a > 0 && b > 0 && a + 1 < rows && b + 1 < cols;
    let block = |grid: &Grid| -> [Option<f64>; 9] {
        std::array::from_fn(|k| {
            let (a, b) = (i + k / 3 - 1, j + k % 3 - 1);
            inside(a, b).then(|| local(grid, a, b).map(|l| l.gaussian)).flatten()
        })
    };
    let k = i * cols + j;
    let spacing =
        0.25 * (grid.at(i + 1, j).distance(grid.at(i - 1, j)) + grid.at(i, j + 1).distance(grid.at(i, j - 1)));
    let h = 1e-4 * spacing;
    let before = block(grid);
    let p = grid.points[k];
    grid.points[k] = p + h * normal;
    let after = block(grid);
    grid.points[k] = p;
    let (mut jr, mut jj) = (0.0, 0.0);
    for (b, a) in before.iter().zip(&after) {
        if let (Some(b), Some(a)) = (b, a) {
            let slope = (a - b) / h;
            jr += slope * (b - target);
            jj += slope * slope;
        }
    }
    let damping = 2.0 * target.abs() / spacing;
    let step = (-jr / (jj + damping * damping)).clamp(-0.25 * spacing, 0.25 * spacing);
    step.is_finite().then_some(step)
}

/// Gaussian curvature at every point of a grid (`None` on the boundary and where the grid
/// degenerates), row by row.
pub fn gaussian_curvature(grid: &Grid) -> Vec<Option<f64>> {
    let mut out = vec![None; grid.points.len()];
    for i in 1..grid.rows.saturating_sub(1) {
        for j in 1..grid.cols.saturating_sub(1) {
            out[i * grid.cols + j] = local(grid, i, j).map(|l| l.gaussian);
        }
    }
    out
}

/// The filter on one grid, pass by pass.
#[derive(Clone, Debug)]
pub struct SurfaceFilter {
    grid: Grid,
    settings: SurfaceSettings,
    status: SurfaceStatus,
    mean_spacing: f64,
    /// The pre-fit of the data term, whose points the moves are pulled towards.
    prefit: Option<GridPrefit>,
}

impl SurfaceFilter {
    /// A filter on a valid grid. With a data term the filter starts from the pre-fit.
    pub fn new(grid: Grid, settings: SurfaceSettings) -> Result<SurfaceFilter> {
        grid.validate()?;
        if let Some(term) = settings.data_term
            && !(term.weight >= 0.0 && term.weight < 1.0 && term.smoothing.is_none_or(|mu| mu.is_finite() && mu >= 0.0))
        {
            return Err(Error::Input(format!(
                "the data term's weight must lie in [0, 1) and its smoothing be a number ≥ 0, not {} and {:?}",
                term.weight, term.smoothing
            )));
        }
        if !(settings.relaxation > 0.0 && settings.relaxation <= 1.0) {
            return Err(Error::Input(format!("the relaxation must lie in (0, 1], not {}", settings.relaxation)));
        }
        if !(settings.tolerance.is_finite() && settings.tolerance > 0.0) {
            return Err(Error::Input(format!("the tolerance must be a positive number, not {}", settings.tolerance)));
        }
        let (mut sum, mut count) = (0.0, 0);
        for i in 0..grid.rows {
            for j in 0..grid.cols {
                if j + 1 < grid.cols {
                    sum += grid.at(i, j).distance(grid.at(i, j + 1));
                    count += 1;
                }
                if i + 1 < grid.rows {
                    sum += grid.at(i, j).distance(grid.at(i + 1, j));
                    count += 1;
                }
            }
        }
        let status = SurfaceStatus { last_move: f64::INFINITY, ..SurfaceStatus::default() };
        let prefit = settings.data_term.map(|term| prefit_grid(&grid, term.smoothing));
        let grid = match &prefit {
            Some(fit) => Grid { points: fit.points.clone(), ..grid },
            None => grid,
        };
        Ok(SurfaceFilter { grid, settings, status, mean_spacing: sum / count as f64, prefit })
    }

    /// The pre-fit of the data term (its points, smoothing, degrees of freedom and the noise
    /// level it read), `None` without one.
    pub fn prefit(&self) -> Option<&GridPrefit> {
        self.prefit.as_ref()
    }

    /// The current grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Where the filter stands.
    pub fn status(&self) -> SurfaceStatus {
        self.status
    }

    /// Runs up to `passes` passes, stopping early once converged; `Err` (keeping the last good
    /// grid) when a point becomes non-finite.
    pub fn run(&mut self, passes: usize) -> Result<SurfaceStatus> {
        for _ in 0..passes {
            if self.status.converged {
                break;
            }
            self.pass()?;
        }
        Ok(self.status)
    }

    /// Runs passes until converged or [`SurfaceSettings::max_passes`] in all.
    pub fn run_to_convergence(&mut self) -> Result<SurfaceStatus> {
        let left = self.settings.max_passes.saturating_sub(self.status.passes);
        self.run(left)
    }

    fn pass(&mut self) -> Result<()> {
        let (rows, cols) = (self.grid.rows, self.grid.cols);
        let before = self.grid.points.clone();
        let mut held = 0;
        for class in 0..4 {
            let locals: Vec<Option<Local>> = (0..rows * cols)
                .map(|k| {
                    let (i, j) = (k / cols, k % cols);
                    (i > 0 && j > 0 && i + 1 < rows && j + 1 < cols).then(|| local(&self.grid, i, j)).flatten()
                })
                .collect();
            for i in (1 + class / 2..rows - 1).step_by(2) {
                for j in (1 + class % 2..cols - 1).step_by(2) {
                    let Some(l) = locals[i * cols + j] else {
                        held += 1;
                        continue;
                    };
                    // C: the mean K over the 3 × 3 neighbourhood.
                    let (mut sum, mut count) = (0.0, 0);
                    for di in -1..=1isize {
                        for dj in -1..=1isize {
                            let k = (i as isize + di) as usize * cols + (j as isize + dj) as usize;
                            if let Some(m) = locals[k] {
                                sum += m.gaussian;
                                count += 1;
                            }
                        }
                    }
                    let target = sum / count as f64;
                    // ((e − 2φ)(g − 2φ) − f²) = C (EG − F²).
                    let here = (self.grid.at(i, j) - l.centre).dot(l.normal);
                    let goal = match self.settings.data_term {
                        Some(_) => block_step(&mut self.grid, i, j, l.normal, target)
                            .map(|step| self.grid.at(i, j) + step * l.normal),
                        None => super::filter::nearest_root(
                            4.0,
                            -2.0 * (l.e + l.g),
                            l.e * l.g - l.f * l.f - target * l.det,
                            here,
                        )
                        .map(|phi| l.centre + phi * l.normal),
                    };
                    let k = i * cols + j;
                    let p = self.grid.points[k];
                    // The move towards the target, ω (P* − P), and with the data term
                    // ω ((1 − λ) (P* − P) + λ (pre-fit − P)); a point with no target is still
                    // pulled towards its pre-fit.
                    let towards = match goal {
                        Some(goal) => goal - p,
                        None => {
                            held += 1;
                            DVec3::ZERO
                        }
                    };
                    let step = match (self.settings.data_term, &self.prefit) {
                        (Some(term), Some(fit)) => (1.0 - term.weight) * towards + term.weight * (fit.points[k] - p),
                        _ => towards,
                    };
                    self.grid.points[k] = p + self.settings.relaxation * step;
                }
            }
        }
        let largest = before
            .iter()
            .zip(&self.grid.points)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, |m: f64, d| if d <= m { m } else { d });
        if !largest.is_finite() {
            self.grid.points = before;
            return Err(Error::Solver(format!(
                "the surface filter diverged at pass {}: a point became non-finite; use a smaller relaxation",
                self.status.passes + 1
            )));
        }
        let last_move = largest / self.mean_spacing;
        self.status = SurfaceStatus {
            passes: self.status.passes + 1,
            last_move,
            held,
            converged: last_move < self.settings.tolerance,
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_cap(n: usize, radius: f64) -> Grid {
        let mut points = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (-0.5 + i as f64 / (n - 1) as f64, -0.5 + j as f64 / (n - 1) as f64);
                points.push(DVec3::new(x, y, (radius * radius - x * x - y * y).sqrt()));
            }
        }
        Grid { rows: n, cols: n, points }
    }

    #[test]
    fn a_sphere_has_gaussian_curvature_one_over_r_squared() {
        let grid = sphere_cap(21, 2.0);
        for (k, value) in gaussian_curvature(&grid).iter().enumerate() {
            let (i, j) = (k / 21, k % 21);
            match value {
                Some(value) => assert!((value - 0.25).abs() < 3e-3, "({i}, {j}): {value}"),
                None => assert!(i == 0 || j == 0 || i == 20 || j == 20),
            }
        }
    }

    #[test]
    fn a_plane_and_a_cylinder_stay_put() {
        // Both have K = 0 everywhere, and the point itself is the root of smaller |φ|.
        let plane = Grid {
            rows: 5,
            cols: 6,
            points: (0..30).map(|k| DVec3::new((k / 6) as f64, (k % 6) as f64 * 0.7, 0.3 * (k / 6) as f64)).collect(),
        };
        let cylinder = Grid {
            rows: 7,
            cols: 7,
            points: (0..49)
                .map(|k| {
                    let t = (k / 7) as f64 * 0.2;
                    DVec3::new(t.cos(), t.sin(), (k % 7) as f64 * 0.3)
                })
                .collect(),
        };
        for grid in [plane, cylinder] {
            let mut filter = SurfaceFilter::new(grid.clone(), SurfaceSettings::default()).unwrap();
            filter.run(10).unwrap();
            let moved = filter.grid().points.iter().zip(&grid.points).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            assert!(moved < 1e-12, "{moved}");
        }
    }

    #[test]
    fn bad_grids_are_refused() {
        let grid = sphere_cap(4, 2.0);
        assert!(Grid { rows: 2, ..grid.clone() }.validate().is_err());
        let mut nan = grid.clone();
        nan.points[5].y = f64::NAN;
        assert!(nan.validate().unwrap_err().to_string().contains("(1, 1)"));
        let mut repeated = grid;
        repeated.points[1] = repeated.points[0];
        assert!(repeated.validate().unwrap_err().to_string().contains("coincides"));
    }
}
