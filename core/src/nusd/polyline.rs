//! NUSD for polylines: smooth an open or closed control polyline through its fixed points
//! (Kuriyama, sec. 2–3, eqs. 1–5; our reading is `docs/nusd.md`).
//!
//! [`smooth`] inserts evenly spaced moving points on every segment of the control polyline, takes
//! the spacing of each edge from that initial placement (chord length by default), and iterates
//! the diffusion of positions `P` and second derivatives `R` until the estimated distance to the
//! fixed point is under `tol · bbox_diagonal`. Without tension the converged polyline is the
//! natural cubic spline through the fixed points (periodic for closed curves) with chord-length
//! knots, sampled at the inserted parameters; its error is O(h²) in the inserted spacing h,
//! because the three-point second difference at a fixed point only leaves a first-derivative jump
//! of order h² there. With uniform spacing it is the uniform-knot spline instead.
//!
//! Tension (eq. 5) is given per point as a dimensionless `τ ≥ 0`; we use `β_i = τ_i / ℓ_i` with
//! `ℓ_i` the mean *parameter length* of the control segments at point i (their mean length with
//! chord spacing, the choice in `docs/nusd.md`, "Scale-free tension"). Using the parameter length
//! rather than the geometric length keeps uniform and centripetal spacing exactly
//! similarity-invariant too: translating, rotating or scaling the control polyline transforms the
//! result the same way, with any spacing.
//!
//! Weak spots: the iteration is explicit, so the number of iterations grows with the square of
//! the number of points between fixed points; large tensions can make it diverge, in which case
//! the solve starts over with half the λ (down to [`MIN_LAMBDA`]) and reports the retries. Eq. 5
//! is discrete: Ṗ is a central difference, which also vanishes when the two neighbours of a fixed
//! point fold back onto the same side, so beyond roughly `τ ≈ 5 (insert + 1)` more tension stops
//! flattening and the neighbours overshoot the fixed point by a fraction of the inserted spacing
//! (the continuous tension spline tends to the polygon instead). The stopping rule estimates the
//! remaining distance from the observed contraction rate (see [`super::convergence`]): it is an
//! estimate, not a guaranteed bound.

use super::convergence::{ConvergenceMonitor, WINDOW};
use super::surface::frame::Frame;
use super::{DEFAULT_LAMBDA_CURVE, DEFAULT_TOL, Spacing};
use crate::{DVec3, Error, Result};

/// Default cap on the iterations of one curve solve.
pub const DEFAULT_MAX_ITERATIONS_CURVE: usize = 200_000;
/// Smallest λ tried after divergence before the solve gives up.
pub const MIN_LAMBDA: f64 = 0.02;
/// The step growing for this many consecutive iterations, past every earlier step and past `T`,
/// counts as divergence. Growth alone is not enough: while converging, the step of a curve with
/// 16 or more inserted points per segment can rise for hundreds of iterations (two decaying modes
/// cancel, then one takes over), and a bare 50-iteration rule then rejects sound solves.
pub const DIVERGENCE_GROWTH: usize = 50;
/// Most points a refined polyline may have (a guard against absurd insert counts).
pub const MAX_POINTS: usize = 10_000_000;
/// Bounding-box diagonals outside `[1/MAX_SIZE, MAX_SIZE]` are refused: `K ∝ s²` and `1/K` must
/// stay far from underflow and overflow.
pub const MAX_SIZE: f64 = 1e100;

/// An ordered list of points, open or closed, with a fixed flag and a tension per point.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Positions, in order along the curve.
    pub points: Vec<DVec3>,
    /// Per point: true when the curve must pass through it. Both ends of an open curve must be
    /// fixed. A moving point only contributes its spacing: its position does not change the
    /// converged result.
    pub fixed: Vec<bool>,
    /// True when the last point joins back to the first.
    pub closed: bool,
    /// Per point: dimensionless tension τ ≥ 0 (eq. 5). It acts only at fixed points that have a
    /// neighbour on both sides; at the ends of an open curve the natural end condition `R = 0`
    /// holds instead, and on moving points it is ignored.
    pub tension: Vec<f64>,
}

impl Polyline {
    /// A polyline with every point fixed and no tension.
    pub fn new(points: Vec<DVec3>, closed: bool) -> Self {
        let n = points.len();
        Polyline { points, fixed: vec![true; n], closed, tension: vec![0.0; n] }
    }

    /// Number of segments: one per consecutive pair, plus the closing one of a closed curve.
    pub fn segment_count(&self) -> usize {
        crate::curve::sequence::segment_count(self.points.len(), self.closed)
    }

    /// Index of control point `k` in the polyline made by [`Polyline::with_inserted`]`(insert)`.
    pub fn refined_index(k: usize, insert: usize) -> usize {
        k * (insert + 1)
    }

    /// Checks sizes, coordinates, tensions and the fixed ends, with messages a designer can act
    /// on.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Input(m));
        let n = self.points.len();
        let kind = if self.closed { "a closed" } else { "an open" };
        let least = if self.closed { 3 } else { 2 };
        if n < least {
            return bad(format!("{kind} curve needs at least {least} points, got {n}"));
        }
        if self.fixed.len() != n {
            return bad(format!("`fixed` has {} entries but the curve has {n} points", self.fixed.len()));
        }
        if self.tension.len() != n {
            return bad(format!("`tension` has {} entries but the curve has {n} points", self.tension.len()));
        }
        if let Some(i) = self.points.iter().position(|p| !p.is_finite()) {
            let p = self.points[i];
            return bad(format!("point {i} has a non-finite coordinate ({}, {}, {})", p.x, p.y, p.z));
        }
        if let Some(i) = self.tension.iter().position(|t| !(t.is_finite() && *t >= 0.0)) {
            return bad(format!("tension of point {i} must be a finite number ≥ 0, not {}", self.tension[i]));
        }
        if !self.closed {
            for i in [0, n - 1] {
                if !self.fixed[i] {
                    return bad(format!(
                        "point {i} is an end of the open curve and must be fixed (the natural end \
                         condition needs it); unfix only interior points, or close the curve"
                    ));
                }
            }
        }
        let fixed = self.fixed.iter().filter(|f| **f).count();
        if self.closed && fixed < 2 {
            return bad(format!(
                "a closed curve needs at least 2 fixed points, it has {fixed}: with fewer it shrinks to a point"
            ));
        }
        let (lo, hi) = bounding_box(&self.points);
        // Measured without squaring underflow: a curve 1e-200 across is tiny, not a point.
        let size = crate::mesh::diagonal_length(lo, hi);
        if size == 0.0 {
            return bad("all points of the curve coincide: there is no curve to smooth".into());
        }
        if !(1.0 / MAX_SIZE..=MAX_SIZE).contains(&size) {
            let size = if size.is_finite() { format!("{size:e}") } else { "beyond 1e308".to_string() };
            return bad(format!(
                "the curve's size {size} is outside the range its arithmetic handles, 1e-100 to 1e100 \
                 (K grows as the square of the spacing); rescale it"
            ));
        }
        Ok(())
    }

    /// This polyline with `insert` moving points placed evenly on every segment (the closing one
    /// too); control point `k` lands at [`Polyline::refined_index`]`(k, insert)`. Inserted points
    /// are moving and have no tension.
    pub fn with_inserted(&self, insert: usize) -> Result<Polyline> {
        let n = self.points.len();
        let segments = self.segment_count();
        let total = segments.checked_mul(insert).and_then(|m| m.checked_add(n)).filter(|t| *t <= MAX_POINTS);
        let Some(total) = total else {
            return Err(Error::Input(format!(
                "inserting {insert} points on each of {segments} segments makes more than {MAX_POINTS} points"
            )));
        };
        let mut out = Polyline {
            points: Vec::with_capacity(total),
            fixed: Vec::with_capacity(total),
            closed: self.closed,
            tension: Vec::with_capacity(total),
        };
        for k in 0..n {
            out.points.push(self.points[k]);
            out.fixed.push(self.fixed.get(k).copied().unwrap_or(true));
            out.tension.push(self.tension.get(k).copied().unwrap_or(0.0));
            if k < segments {
                let (a, b) = (self.points[k], self.points[(k + 1) % n]);
                for j in 1..=insert {
                    out.points.push(a.lerp(b, j as f64 / (insert + 1) as f64));
                    out.fixed.push(false);
                    out.tension.push(0.0);
                }
            }
        }
        Ok(out)
    }
}

/// Settings of a curve solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveSettings {
    /// Moving points inserted evenly on each segment (0: smooth the polyline as given).
    pub insert: usize,
    /// Diffusion constant λ ∈ (0, 1).
    pub lambda: f64,
    /// Relative tolerance; the threshold is `T = tol · bbox_diagonal`.
    pub tol: f64,
    /// Cap on iterations (per attempt).
    pub max_iterations: usize,
    /// Parametrisation of the edges, measured on the initial placement.
    pub spacing: Spacing,
}

impl Default for CurveSettings {
    fn default() -> Self {
        CurveSettings {
            insert: 0,
            lambda: DEFAULT_LAMBDA_CURVE,
            tol: DEFAULT_TOL,
            max_iterations: DEFAULT_MAX_ITERATIONS_CURVE,
            spacing: Spacing::Chord,
        }
    }
}

impl CurveSettings {
    /// Checks every field, with a message a designer can act on.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Input(m));
        if !(self.lambda > 0.0 && self.lambda < 1.0) {
            return bad(format!("lambda must lie strictly between 0 and 1, not {}", self.lambda));
        }
        if !(self.tol > 0.0 && self.tol.is_finite()) {
            return bad(format!("tolerance must be a positive number, not {}", self.tol));
        }
        if self.max_iterations == 0 {
            return bad("the iteration cap must be at least 1".into());
        }
        Ok(())
    }
}

/// The smoothed curve and how the solve went.
#[derive(Clone, Debug)]
pub struct CurveSolution {
    /// The refined polyline with its final positions; control point `k` is at
    /// [`Polyline::refined_index`]`(k, insert)` and keeps its exact input coordinates when fixed.
    pub curve: Polyline,
    /// Per point: the second derivative `R` with respect to the spacing parameter (at a fixed
    /// point with tension, the mean of `R±`; zero at the ends of an open curve).
    pub second_derivatives: Vec<DVec3>,
    /// Iterations of the attempt that produced the result.
    pub iterations: usize,
    /// Largest move of a moving point in the last iteration.
    pub last_step: f64,
    /// Estimated distance from the result to the fixed point of the iteration.
    pub remaining_estimate: f64,
    /// The stopping threshold `T = tol · bbox_diagonal`.
    pub threshold: f64,
    /// True when the stopping rule was met before the iteration cap.
    pub converged: bool,
    /// λ of the attempt that produced the result.
    pub lambda_used: f64,
    /// Attempts restarted with half the λ after divergence.
    pub retries: usize,
}

/// Smooths a control polyline: inserts `settings.insert` moving points per segment and iterates
/// NUSD (eqs. 1–5) until the estimated remaining distance and the last step are both under
/// `T = tol · bbox_diagonal`, or the iteration cap. On divergence the solve restarts from the
/// initial placement with half the λ; below [`MIN_LAMBDA`] it fails with [`Error::Solver`].
pub fn smooth(control: &Polyline, settings: &CurveSettings) -> Result<CurveSolution> {
    // A curve of extreme size is solved scaled by a power of two, exactly, as surfaces are
    // (see `surface::frame`): `K` grows as the square of the spacing and would underflow or
    // overflow, but every step of the method commutes with the scaling.
    let finite = control.points.iter().all(|p| p.is_finite());
    let (lo, hi) = bounding_box(&control.points);
    let frame = if finite && !control.points.is_empty() { Frame::for_box(lo, hi) } else { Frame::default() };
    if frame.is_identity() {
        return smooth_in_range(control, settings);
    }
    let scaled = Polyline { points: control.points.iter().map(|&p| frame.to_internal(p)).collect(), ..control.clone() };
    let mut solution = smooth_in_range(&scaled, settings)?;
    for (i, p) in solution.curve.points.iter_mut().enumerate() {
        *p = frame.position_out(*p);
        if solution.curve.fixed[i] && i % (settings.insert + 1) == 0 {
            *p = control.points[i / (settings.insert + 1)];
        }
    }
    for r in &mut solution.second_derivatives {
        *r = frame.second_derivative_out(*r, settings.spacing);
    }
    solution.last_step = frame.length_out(solution.last_step);
    solution.remaining_estimate = frame.length_out(solution.remaining_estimate);
    solution.threshold = frame.length_out(solution.threshold);
    Ok(solution)
}

fn smooth_in_range(control: &Polyline, settings: &CurveSettings) -> Result<CurveSolution> {
    control.validate()?;
    settings.validate()?;
    let curve = control.with_inserted(settings.insert)?;
    let (lo, hi) = bounding_box(&control.points);
    let diagonal = (hi - lo).length();
    let threshold = settings.tol * diagonal;
    let system = System::new(&curve, settings.insert, settings.spacing, diagonal);
    // Work relative to the box centre, so the roundoff floor of the steps scales with the size of
    // the curve and not with its distance from the origin.
    let centre = (lo + hi) * 0.5;
    let initial: Vec<DVec3> = curve.points.iter().map(|p| *p - centre).collect();

    let mut lambda = settings.lambda;
    let mut retries = 0;
    loop {
        match system.run(&initial, lambda, threshold, settings.max_iterations) {
            Ok(run) => {
                let mut out = curve.clone();
                for (i, p) in out.points.iter_mut().enumerate() {
                    if !curve.fixed[i] {
                        *p = run.points[i] + centre;
                    }
                }
                return Ok(CurveSolution {
                    curve: out,
                    second_derivatives: run.second_derivatives,
                    iterations: run.iterations,
                    last_step: run.last_step,
                    remaining_estimate: run.remaining,
                    threshold,
                    converged: run.converged,
                    lambda_used: lambda,
                    retries,
                });
            }
            Err(_) if lambda * 0.5 >= MIN_LAMBDA => {
                lambda *= 0.5;
                retries += 1;
            }
            Err(reason) => {
                return Err(Error::Solver(format!(
                    "the curve solve diverged ({reason}) even with lambda = {lambda} after {retries} \
                     retries; lower the tensions or insert more points"
                )));
            }
        }
    }
}

/// Corners of the axis-aligned bounding box (of a validated, non-empty polyline).
fn bounding_box(points: &[DVec3]) -> (DVec3, DVec3) {
    crate::mesh::bounding_box(points).unwrap_or((DVec3::INFINITY, DVec3::NEG_INFINITY))
}

/// A moving point's stencil: eqs. 1–3.
#[derive(Clone, Copy, Debug)]
struct MovingStencil {
    i: usize,
    prev: usize,
    next: usize,
    w_prev: f64,
    w_next: f64,
    k: f64,
}

/// A fixed point with a neighbour on each side: eqs. 4–5.
#[derive(Clone, Copy, Debug)]
struct FixedStencil {
    i: usize,
    prev: usize,
    next: usize,
    w_prev: f64,
    w_next: f64,
    inv_k: f64,
    /// `β_i / 2`.
    half_beta: f64,
    inv_s_prev: f64,
    inv_s_next: f64,
}

/// The constant part of the iteration: who is whose neighbour, weights, K and β.
#[derive(Debug)]
struct System {
    len: usize,
    moving: Vec<MovingStencil>,
    fixed: Vec<FixedStencil>,
}

/// The outcome of one attempt that did not diverge.
struct Run {
    points: Vec<DVec3>,
    second_derivatives: Vec<DVec3>,
    iterations: usize,
    last_step: f64,
    remaining: f64,
    converged: bool,
}

impl System {
    /// Stencils of a validated, refined polyline with `insert` points per control segment.
    fn new(curve: &Polyline, insert: usize, spacing: Spacing, diagonal: f64) -> System {
        let n = curve.points.len();
        let min_s = spacing.min_spacing(diagonal);
        // s[e] is the spacing of the edge from point e to point e + 1 (mod n).
        let chords = crate::curve::sequence::chord_lengths(&curve.points, curve.closed);
        let s: Vec<f64> = chords.iter().map(|c| spacing.of_chord(*c, min_s)).collect();
        // ℓ of a control segment: its parameter length, the sum of the spacings of its edges.
        let segment_length = |first_edge: usize| s[first_edge..first_edge + insert + 1].iter().sum::<f64>();
        let mut moving = Vec::new();
        let mut fixed = Vec::new();
        for i in 0..n {
            let (prev, s_prev) = match i {
                0 if curve.closed => (n - 1, s[n - 1]),
                0 => continue, // open end: R = 0 forever (natural end condition)
                _ => (i - 1, s[i - 1]),
            };
            let (next, s_next) = match i {
                _ if i + 1 < n => (i + 1, s[i]),
                _ if curve.closed => (0, s[n - 1]),
                _ => continue,
            };
            // w_ij = (1/s_ij) / Σ_k (1/s_ik); K_i = s_prev s_next / 2 (eq. 1).
            let w_prev = s_next / (s_prev + s_next);
            let w_next = s_prev / (s_prev + s_next);
            let k = s_prev * s_next * 0.5;
            if !curve.fixed[i] {
                moving.push(MovingStencil { i, prev, next, w_prev, w_next, k });
                continue;
            }
            let tau = curve.tension[i];
            let half_beta = if tau > 0.0 && i % (insert + 1) == 0 {
                let c = i / (insert + 1);
                let segments = curve.segment_count() / (insert + 1);
                let before = segment_length(((c + segments - 1) % segments) * (insert + 1));
                let after = segment_length(c * (insert + 1));
                0.5 * tau / (0.5 * (before + after)).max(min_s)
            } else {
                0.0
            };
            fixed.push(FixedStencil {
                i,
                prev,
                next,
                w_prev,
                w_next,
                inv_k: 1.0 / k,
                half_beta,
                inv_s_prev: 1.0 / s_prev,
                inv_s_next: 1.0 / s_next,
            });
        }
        System { len: n, moving, fixed }
    }

    /// Eqs. 4–5: the `R` a fixed point shows its neighbours on the `i−1` side (`r_minus`) and on
    /// the `i+1` side (`r_plus`). Reads positions only.
    fn update_fixed(&self, p: &[DVec3], r_minus: &mut [DVec3], r_plus: &mut [DVec3]) {
        for f in &self.fixed {
            let (a, pi, b) = (p[f.prev], p[f.i], p[f.next]);
            let r = (f.w_prev * (a - pi) + f.w_next * (b - pi)) * f.inv_k;
            if f.half_beta == 0.0 {
                r_minus[f.i] = r;
                r_plus[f.i] = r;
            } else {
                let tangent = 0.5 * ((b - pi) * f.inv_s_next + (pi - a) * f.inv_s_prev);
                r_minus[f.i] = r - f.half_beta * tangent;
                r_plus[f.i] = r + f.half_beta * tangent;
            }
        }
    }

    /// One attempt from `initial` (positions relative to the box centre); `Err` names the way it
    /// diverged.
    fn run(&self, initial: &[DVec3], lambda: f64, threshold: f64, max_iterations: usize) -> Result<Run, String> {
        let n = self.len;
        let mut p = initial.to_vec();
        let mut p_next = initial.to_vec();
        // R_i as seen from the i−1 side and from the i+1 side; equal except at fixed points with
        // tension. Moving points start at R = 0.
        let mut r_minus = vec![DVec3::ZERO; n];
        let mut r_plus = vec![DVec3::ZERO; n];
        let mut r_new = vec![DVec3::ZERO; self.moving.len()];
        let mut monitor = ConvergenceMonitor::default();
        let mut iterations = 0;
        let mut converged = self.moving.is_empty();
        while !converged && iterations < max_iterations {
            iterations += 1;
            self.update_fixed(&p, &mut r_minus, &mut r_plus);
            // Eq. 2, reading the R of stage 1.
            for (m, r) in self.moving.iter().zip(r_new.iter_mut()) {
                let ri = r_plus[m.i];
                let dr = m.w_prev * (r_plus[m.prev] - ri) + m.w_next * (r_minus[m.next] - ri);
                *r = ri + lambda * dr;
            }
            // Eq. 3 with the new R; reads the old positions, writes the new ones.
            let mut step: f64 = 0.0;
            for (m, r) in self.moving.iter().zip(r_new.iter()) {
                let pi = p[m.i];
                let dp = m.w_prev * (p[m.prev] - pi) + m.w_next * (p[m.next] - pi);
                let d = lambda * (dp - m.k * *r);
                p_next[m.i] = pi + d;
                let len = d.length();
                // Not f64::max: a NaN must win so that divergence is seen.
                if len > step || len.is_nan() {
                    step = len;
                }
                r_minus[m.i] = *r;
                r_plus[m.i] = *r;
            }
            std::mem::swap(&mut p, &mut p_next);
            if !step.is_finite() {
                return Err(format!("a non-finite value at iteration {iterations}"));
            }
            monitor.push(step);
            if monitor.runaway(DIVERGENCE_GROWTH, threshold) {
                return Err(format!(
                    "the step grew for {DIVERGENCE_GROWTH} consecutive iterations, up to {step:e} at iteration {iterations}"
                ));
            }
            // The estimate needs a full window of steps to measure the contraction rate.
            converged = iterations > WINDOW && monitor.converged(threshold);
        }
        self.update_fixed(&p, &mut r_minus, &mut r_plus);
        let second_derivatives: Vec<DVec3> = r_minus.iter().zip(&r_plus).map(|(a, b)| (*a + *b) * 0.5).collect();
        if !second_derivatives.iter().all(|r| r.is_finite()) {
            return Err(format!("a non-finite second derivative at iteration {iterations}"));
        }
        Ok(Run {
            points: p,
            second_derivatives,
            iterations,
            last_step: monitor.last_step().unwrap_or(0.0),
            remaining: if self.moving.is_empty() { 0.0 } else { monitor.remaining() },
            converged,
        })
    }
}

#[cfg(test)]
#[path = "polyline_tests.rs"]
mod tests;
