//! The discrete log-aesthetic curve filters, planar and spatial (paper secs. 3.1–3.2 and 4.2,
//! eqs. 7, 8 and 11–13).
//!
//! Each pass moves every free point `P_i` so that, locally, the points follow a log-aesthetic
//! curve. The curvature of every point comes from the nonuniform derivatives of
//! [`crate::curve::derivatives`] on chord-length parameters; around each point a window of
//! 2m+1 curvature samples is fitted by the least-squares line `ρ^α = c s + d` in the window's
//! own arc length ([`super::law`]), and the line's value at the point is its target curvature κ*.
//! The point is then put on the line through `P_ic` along the discrete principal normal `N_i`,
//! `P_i' = P_ic + φ N_i`, with φ in closed form: the first derivative does not involve `P_i` and
//! the second is affine in it, so the curvature is linear in φ. The spatial filter also fits
//! `μ^β = g s + h` to the radius of torsion μ and moves the point along the binormal,
//! `P_i' = P_ic + φ N_i + ψ B_i`: φ first from the curvature target, then ψ from the torsion
//! target, which is quadratic in ψ because the third derivative uses the two points on either
//! side and not `P_i`; of the two roots we take the one of smaller |ψ| (sec. 4.2).
//!
//! Departures from the paper, and why (also in `docs/log-aesthetic.md`, "Where we depart"):
//! - Points move a fraction ω ([`FilterSettings::relaxation`], default ½) of the way to their
//!   target in a pass. The full step moves each point onto a target computed from neighbours that
//!   are themselves noisy and overshoots: on the paper's example (20 points with 0.5 % noise)
//!   full steps end with the points about 85 % as far from the true curve as the noisy input,
//!   half steps about 45 % (in twice as many passes); ω > 1 diverges.
//! - Passes are red–black (even points from the current state, then odd points from the
//!   updated one). Moving every point at once (Jacobi) leaves a zigzag of the points undamped:
//!   each point jumps to the mirror image of its offset. Red–black, unlike a sequential sweep,
//!   lets the points of a colour move on several threads with the same result for any count.
//! - Near an inflection the signed curvature changes sign inside the window and ρ^α has no
//!   meaning there; a window whose curvature varies by more than [`MAX_CURVATURE_RATIO`] counts
//!   as one (its smallest curvature is nearly zero, and with α > 0 its huge ρ^α would dominate
//!   the line fit: on noisy points that made a hook grow at the ends of the curve). The paper leaves such points where they are ([`InflectionRule::Hold`]);
//!   on noisy input the noise itself flips the sign in most windows, so nothing would move. By
//!   default ([`InflectionRule::Clothoid`]) we fit the signed curvature κ = c s + d instead, which
//!   is the law with α = −1: the clothoid, the log-aesthetic curve that passes through an
//!   inflection.
//! - A target never bends more sharply than the sharpest sample of its window: the law's value is
//!   kept to at most the window's largest curvature magnitude. The windows near the ends of an
//!   open curve are shifted inside it, so there the fitted line is read off beyond the window's
//!   middle, and for α > 0 the law reaches ρ = 0 at a finite arc length: on dense noisy curves the
//!   end's curvature then fed on itself until the end curled into a hook of about half a spacing
//!   radius (measured on spirals and involutes, α = 0.5, 1 and 2, of 300, 1,000 and 3,000 points
//!   with 0.05, 0.1 and 0.2 of the spacing as noise, six draws each: 57 of the 162 never
//!   converged). With the cap all 162 converge, and a sampled log-aesthetic curve, whose end
//!   sample is the window's extreme, stays a fixed point. The space filter's torsion target is
//!   kept within its window's sharpest torsion the same way.
//! - A move is capped so the point stays within the half chord of its neighbours (a target that
//!   asks for more would fold the curve); the number of capped moves is reported.
//! - With a [`DataTerm`] ([`FilterSettings::keeping_shape`], what `taut fair` runs) the points
//!   are first smoothed by [`super::prefit`], whose smoothing is chosen from the points by
//!   cross-validation, and every move is `ω ((1 − λ) (P* − P) + λ (S − P))`, with `P*` the paper's
//!   target and `S` the point's pre-fit place. The paper filters the measured points themselves
//!   and holds them to nothing. Why it drifted: the three-point curvature sees the noise divided
//!   by the spacing squared, so where the noise is not far below the spacing (0.5 % of the length
//!   on 200 points, any noise on 1,000) the curvature is mostly noise; the law `ρ^α` of noisy
//!   samples is biased (a noisy κ reads sharper on average), the targets bend too much, and the
//!   midpoint rule pulls the curve inward pass after pass, with nothing to stop it: the fixed
//!   points of the filter are every locally log-aesthetic curve, not the one the points sampled.
//!   Measured on half-turn segments of α in {−1, 0, 1, 2}: 1.3 to 5.9 times farther from the true
//!   curve than the input at 200 points, 3 to 1,000 times at 1,000, the pass cap reached. The
//!   pre-fit removes the noise at the scale the data allows (the filter then reads a curvature
//!   that means something), and the data term makes the fixed point unique and near the data,
//!   so the run converges geometrically (a share `ω λ` of any slow drift is taken back each pass).
//!
//! `P_ic` is the midpoint of the neighbours, as in the paper. There the second derivative is
//! parallel to the chord, so the curvature along the normal is exactly `−k φ / |U|²` with
//! `k = 2/(h0 h1)`. With unequal gaps the midpoint also slides the point along the curve by
//! `(h1 − h0)/2` a pass, so the points drift towards even spacing: this removes the tangential part
//! of noise, which would otherwise show as curvature noise through the first-order `U` (we tried the
//! parameter-weighted point of the chord instead: it keeps the spacing and converges far slower).
//!
//! Convergence: a pass's largest move, relative to the mean spacing of the points, below
//! [`FilterSettings::tolerance`]. The filter removes small-scale noise in a few hundred passes
//! whatever the number of points (the default 1e-4 stops there: about 250 passes on the paper's
//! 20 noisy points, as in the paper). Beyond that it keeps changing the curve slowly at the scale
//! of the whole curve: the local line fits do not reproduce a curvature that is not
//! log-aesthetic over a window, and the difference spreads like diffusion, in a number of passes
//! that grows with the square of the number of points. A tolerance of 1e-6 lets a short curve
//! (tens of points) get there, where its LCG becomes a straight line of slope α; on long curves
//! it would take far too long, and it moves the curve away from the input (the points follow one
//! log-aesthetic curve through the fixed ends, not the curve the input sampled).
//!
//! Where it is weak: the discrete curvature on chord parameters is biased by about `κ² h²/4`
//! relative, so an exactly sampled log-aesthetic curve is a fixed point only up to the change of
//! that bias across a window (the tests measure moves of 3e-5 of the length on 20 points, 2e-6 on
//! 40). The law fixes how the curvature changes along the curve, not its value at a free end:
//! the ends of an open curve are fixed points whose neighbours are fitted with shifted windows,
//! and on dense noisy curves (a thousand points with noise of a tenth of the spacing) the last
//! ten or so points can settle on a tighter spiral of the same law, curvature rising to up to
//! about ten times the curve's at the end point, far smaller than the noise in position; the
//! default tolerance also stops these curves with waves in their curvature a few tens of points
//! long (a larger window, or a smaller tolerance, smooths them further). A curve far from
//! log-aesthetic with the chosen α is reshaped, not just smoothed: the line fit across a
//! curvature extremum flattens it a little every pass (a sine wave faired with
//! α = 1 ends far from the sine), which is the filter's purpose but means a designer should stop
//! early or estimate α per piece. Torsion is a third derivative: near a helix it hardly depends on
//! the binormal offset (the third derivative has no normal part), so the quadratic for ψ is
//! ill-conditioned and its smaller root wanders; the spatial filter evens the torsion but brings
//! noisy points no nearer the true curve. Dense noisy curves (hundreds of points) keep a scattered
//! discrete LCG however long they are filtered, because the LCG differentiates the curvature again.

use super::filter_geometry::{Geometry, Local, PARALLEL_FROM, Shape, Spatial, Window, window_span};
use super::filter_planar::{PlanarCurve, Rules};
use super::law::{LineSums, law_value, radius_from_law};
use super::prefit::{Prefit, prefit_planar, prefit_space};
use crate::curve::{Plane, PointSequence};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

/// Default half-width m of the window: 2m + 1 = 7 points, the paper's example.
pub const DEFAULT_WINDOW: usize = 3;
/// Default convergence tolerance: the largest move of a pass, relative to the mean spacing.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// A window whose curvature magnitudes differ by more than this factor is fitted as one holding
/// an inflection (see [`InflectionRule`]): its smallest curvature is nearly zero.
pub const MAX_CURVATURE_RATIO: f64 = 10.0;
/// Default relaxation ω: points move half way to their target in a pass.
pub const DEFAULT_RELAXATION: f64 = 0.5;
/// Default cap on passes.
pub const DEFAULT_MAX_PASSES: usize = 10_000;
/// Default weight λ of the data term: the share of each move that pulls the point back towards
/// the pre-fit.
pub const DEFAULT_DATA_WEIGHT: f64 = 0.1;

/// The data term of the shape-keeping fairing (a departure from the paper; see the module docs):
/// the points are first smoothed by [`super::prefit`], at the scale the noise allows, and every
/// move of the filter then also pulls the point a share `weight` back towards its pre-fit place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DataTerm {
    /// λ in [0, 1): each move is `ω ((1 − λ) (target − P) + λ (pre-fit − P))`.
    pub weight: f64,
    /// The pre-fit's smoothing μ; `None`: chosen from the data by generalised cross-validation.
    pub smoothing: Option<f64>,
}

impl Default for DataTerm {
    fn default() -> Self {
        DataTerm { weight: DEFAULT_DATA_WEIGHT, smoothing: None }
    }
}

/// The slope α of the curvature graph the filter aims at: one for the whole curve or one per point.
#[derive(Clone, Debug, PartialEq)]
pub enum Alpha {
    /// One α everywhere.
    Uniform(f64),
    /// One α per point (as estimated per piece), same length as the curve.
    PerPoint(Vec<f64>),
}

/// What to do where the curvature changes sign within a window.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InflectionRule {
    /// Leave the point where it is (the paper).
    Hold,
    /// Fit the signed curvature linearly in arc length (α = −1, a clothoid) in such windows.
    #[default]
    Clothoid,
}

/// Settings of the curve filter.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterSettings {
    /// Half-width m of the window of 2m + 1 points (at least 1).
    pub window: usize,
    /// The slope α of the curvature graph to aim at.
    pub alpha: Alpha,
    /// `Some(β)`: the spatial filter, which also makes the radius of torsion follow
    /// `μ^β = g s + h`; `None`: the planar filter.
    pub torsion_beta: Option<f64>,
    /// What to do where the curvature changes sign within a window.
    pub inflection: InflectionRule,
    /// Stop when a pass's largest move is below `tolerance` × the mean spacing.
    pub tolerance: f64,
    /// Cap on passes of [`CurveFilter::run_to_convergence`].
    pub max_passes: usize,
    /// Fraction ω of the way to its target a point moves in a pass, in (0, 1].
    pub relaxation: f64,
    /// `Some`: smooth the points first and hold them to that pre-fit (keeps the shape of noisy
    /// input); `None`: the paper's filter on the points as given.
    pub data_term: Option<DataTerm>,
}

impl FilterSettings {
    /// The default settings with the default [`DataTerm`]: the fairing for measured or sketched
    /// points, which removes their noise and keeps the curve where they were.
    pub fn keeping_shape() -> Self {
        FilterSettings { data_term: Some(DataTerm::default()), ..FilterSettings::default() }
    }
}

impl Default for FilterSettings {
    fn default() -> Self {
        FilterSettings {
            window: DEFAULT_WINDOW,
            alpha: Alpha::Uniform(1.0),
            torsion_beta: None,
            inflection: InflectionRule::default(),
            tolerance: DEFAULT_TOLERANCE,
            max_passes: DEFAULT_MAX_PASSES,
            relaxation: DEFAULT_RELAXATION,
            data_term: None,
        }
    }
}

/// How the filter stands after the passes run so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilterStatus {
    /// Passes run since the filter was made.
    pub passes: usize,
    /// Largest move of the last pass relative to the mean spacing (∞ before the first pass).
    pub last_move: f64,
    /// Relative RMS distance of the curvature from its targets before the last pass,
    /// `sqrt(Σ(κ − κ*)² / Σκ²)` over the points that were moved.
    pub residual: f64,
    /// Points left in place in the last pass (near an inflection under [`InflectionRule::Hold`],
    /// or where the fit gave no positive radius).
    pub held: usize,
    /// Moves of the last pass cut back to the half chord of the neighbours.
    pub capped: usize,
    /// True once a pass moved no point by more than the tolerance.
    pub converged: bool,
}

/// The filter on one curve, run pass by pass (an editor runs a few passes a frame).
#[derive(Clone, Debug)]
pub struct CurveFilter {
    points: Vec<DVec3>,
    closed: bool,
    /// The planar filter's points in its plane (whose normal orients the signed curvature);
    /// `None` for the spatial filter. `points` follows it after every run.
    planar: Option<PlanarCurve>,
    alpha: Vec<f64>,
    settings: FilterSettings,
    status: FilterStatus,
    /// Largest distance of an input point from the plane it was projected onto.
    off_plane: f64,
    /// The free points of each colour of a red–black pass, in order.
    colours: Vec<Vec<usize>>,
    /// The pre-fit of the data term, whose points the moves are pulled towards.
    prefit: Option<Prefit>,
    scratch: Scratch,
}

/// Buffers a spatial pass works in, kept from pass to pass so that a pass allocates nothing.
#[derive(Clone, Debug, Default)]
struct Scratch {
    geometry: Geometry,
    before: Vec<DVec3>,
    moves: Vec<spatial::Move>,
    /// Every point's torsion target (NaN: none), for the data term's torsion step.
    torsion_targets: Vec<f64>,
}

impl CurveFilter {
    /// A filter on `curve`. The planar filter (no `torsion_beta`) projects the points onto their
    /// least-squares plane first ([`CurveFilter::off_plane_distance`] says how far they were).
    /// Needs at least 2m + 1 distinct, finite points (2m + 3 for the spatial filter, whose
    /// torsion uses two neighbours on each side).
    pub fn new(curve: &PointSequence, settings: FilterSettings) -> Result<CurveFilter> {
        let m = settings.window;
        if m == 0 || m > 1000 {
            return Err(Error::Input(format!("the window half-width m must be between 1 and 1000, not {m}")));
        }
        let least = if settings.torsion_beta.is_some() { 2 * m + 3 } else { 2 * m + 1 };
        curve.validate(least).map_err(|e| match e {
            Error::Input(msg) if msg.contains("needs at least") => Error::Input(format!(
                "{msg}: the filter's window has 2m + 1 = {} points{}; give more points or a smaller --window",
                2 * m + 1,
                if settings.torsion_beta.is_some() { " and torsion needs two more" } else { "" }
            )),
            other => other,
        })?;
        let n = curve.len();
        let alpha = match &settings.alpha {
            Alpha::Uniform(a) => vec![*a; n],
            Alpha::PerPoint(v) if v.len() == n => v.clone(),
            Alpha::PerPoint(v) => {
                return Err(Error::Input(format!("{} values of α given for a curve of {n} points", v.len())));
            }
        };
        if let Some(a) = alpha.iter().find(|a| !(a.is_finite() && a.abs() <= 100.0)) {
            return Err(Error::Input(format!("α must be a finite number between −100 and 100, not {a}")));
        }
        if let Some(beta) = settings.torsion_beta
            && !(beta.is_finite() && beta.abs() <= 100.0)
        {
            return Err(Error::Input(format!("β must be a finite number between −100 and 100, not {beta}")));
        }
        if !(settings.relaxation > 0.0 && settings.relaxation <= 1.0) {
            return Err(Error::Input(format!("the relaxation must lie in (0, 1], not {}", settings.relaxation)));
        }
        if !(settings.tolerance.is_finite() && settings.tolerance > 0.0) {
            return Err(Error::Input(format!("the tolerance must be a positive number, not {}", settings.tolerance)));
        }
        let (points, plane, off_plane) = if settings.torsion_beta.is_some() {
            (curve.points.clone(), None, 0.0)
        } else {
            let plane = Plane::fit(&curve.points).ok_or_else(|| {
                Error::Input("the points lie on a straight line: there is no curvature to fair".into())
            })?;
            let off = curve.points.iter().map(|p| plane.distance(*p).abs()).fold(0.0, f64::max);
            (curve.points.iter().map(|p| plane.project(*p)).collect(), Some(plane), off)
        };
        if let Some(term) = settings.data_term
            && !(term.weight >= 0.0 && term.weight < 1.0 && term.smoothing.is_none_or(|mu| mu.is_finite() && mu >= 0.0))
        {
            return Err(Error::Input(format!(
                "the data term's weight must lie in [0, 1) and its smoothing be a number ≥ 0, not {} and {:?}",
                term.weight, term.smoothing
            )));
        }
        let prefit = settings.data_term.map(|term| match &plane {
            Some(plane) => {
                let uniform = match &settings.alpha {
                    Alpha::Uniform(a) => Some(*a),
                    Alpha::PerPoint(_) => None,
                };
                prefit_planar(&points, curve.closed, plane.normal, uniform, term.smoothing)
            }
            None => {
                let uniform = match &settings.alpha {
                    Alpha::Uniform(a) => Some(*a),
                    Alpha::PerPoint(_) => None,
                };
                prefit_space(&points, curve.closed, uniform, term.smoothing)
            }
        });
        let points = prefit.as_ref().map_or(points, |p| p.points.clone());
        let sequence = PointSequence::new(points, curve.closed);
        sequence.validate(least)?;
        // Where the neighbours of a point coincide the curve turns back on itself: it has no
        // tangent there and its curvature is 0 / 0.
        let size = sequence.diagonal();
        let n = sequence.len();
        if let Some((i, (a, b))) = (0..n)
            .filter_map(|i| sequence.neighbours(i).map(|ab| (i, ab)))
            .find(|&(_, (a, b))| sequence.points[a].distance(sequence.points[b]) <= 1e-12 * size)
        {
            return Err(Error::Input(format!(
                "the curve turns back on itself at point {i} (points {a} and {b} are at the same place); remove point {i}"
            )));
        }
        let status = FilterStatus { last_move: f64::INFINITY, ..FilterStatus::default() };
        // A closed curve with an odd count has two even neighbours at the seam: a third colour.
        let closed = curve.closed;
        let count: usize = if closed && n % 2 == 1 { 3 } else { 2 };
        let colour = |i: usize| if count == 3 && i == n - 1 { 2 } else { i % 2 };
        let free = |i: usize| closed || (i > 0 && i + 1 < n);
        let colours = (0..count).map(|c| (0..n).filter(|&i| colour(i) == c && free(i)).collect()).collect();
        let mut planar = plane.map(|plane| PlanarCurve::new(&sequence.points, plane));
        if let (Some(planar), Some(term), Some(fit)) = (&mut planar, settings.data_term, &prefit) {
            planar.hold_to(&fit.points, term.weight);
        }
        Ok(CurveFilter {
            planar,
            points: sequence.points,
            closed,
            alpha,
            settings,
            status,
            off_plane,
            colours,
            prefit,
            scratch: Scratch::default(),
        })
    }

    /// The current points.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The current points as a sequence.
    pub fn sequence(&self) -> PointSequence {
        PointSequence::new(self.points.clone(), self.closed)
    }

    /// The plane of the planar filter, `None` for the spatial one.
    pub fn plane(&self) -> Option<Plane> {
        self.planar.as_ref().map(PlanarCurve::plane)
    }

    /// How far the farthest input point was from the plane the planar filter projected it onto.
    pub fn off_plane_distance(&self) -> f64 {
        self.off_plane
    }

    /// The pre-fit of the data term (its points, smoothing, degrees of freedom and the noise
    /// level it read), `None` without one.
    pub fn prefit(&self) -> Option<&Prefit> {
        self.prefit.as_ref()
    }

    /// α per point.
    pub fn alpha(&self) -> &[f64] {
        &self.alpha
    }

    /// The settings.
    pub fn settings(&self) -> &FilterSettings {
        &self.settings
    }

    /// Where the filter stands.
    pub fn status(&self) -> FilterStatus {
        self.status
    }

    /// Runs up to `passes` passes, stopping early once converged; `Err` when the points become
    /// degenerate (a non-finite coordinate or two points merging), in which case the points of
    /// the last good pass are kept.
    pub fn run(&mut self, passes: usize) -> Result<FilterStatus> {
        let mut result = Ok(self.status);
        for _ in 0..passes {
            if self.status.converged {
                break;
            }
            if let Err(e) = self.pass() {
                result = Err(e);
                break;
            }
            result = Ok(self.status);
        }
        if let Some(planar) = &mut self.planar {
            planar.write_back(&mut self.points);
        }
        result
    }

    /// Runs passes until converged or [`FilterSettings::max_passes`] in all.
    pub fn run_to_convergence(&mut self) -> Result<FilterStatus> {
        let left = self.settings.max_passes.saturating_sub(self.status.passes);
        self.run(left)
    }

    /// One red–black pass.
    fn pass(&mut self) -> Result<()> {
        let totals = match &mut self.planar {
            Some(planar) => {
                let rules = Rules {
                    closed: self.closed,
                    window: self.settings.window,
                    alpha: &self.alpha,
                    uniform_alpha: matches!(self.settings.alpha, Alpha::Uniform(_)),
                    clothoid: self.settings.inflection == InflectionRule::Clothoid,
                    relaxation: self.settings.relaxation,
                    continuous: self.settings.data_term.is_some(),
                };
                planar.pass(&self.colours, &rules)
            }
            None => {
                let mut scratch = std::mem::take(&mut self.scratch);
                let totals = self.spatial_pass(&mut scratch);
                self.scratch = scratch;
                totals
            }
        };
        let largest = totals.largest2.sqrt();
        let (shortest, mean_gap) = (totals.shortest2.sqrt(), totals.mean_gap);
        let failure = if !largest.is_finite() {
            Some("a point became non-finite")
        } else if shortest.is_nan() || shortest <= 1e-9 * mean_gap {
            Some("two points merged (the curve folded)")
        } else {
            None
        };
        if let Some(what) = failure {
            match &mut self.planar {
                Some(planar) => planar.restore(),
                None => std::mem::swap(&mut self.points, &mut self.scratch.before),
            }
            return Err(Error::Solver(format!(
                "the filter diverged at pass {}: {what}; use a larger window, a smaller relaxation or an α closer \
                 to the curve's",
                self.status.passes + 1
            )));
        }
        let last_move = largest / mean_gap;
        self.status = FilterStatus {
            passes: self.status.passes + 1,
            last_move,
            residual: if totals.k2 > 0.0 { (totals.err2 / totals.k2).sqrt() } else { 0.0 },
            held: totals.held,
            capped: totals.capped,
            converged: last_move < self.settings.tolerance,
        };
        Ok(())
    }

    fn shape(&self) -> Shape {
        let uniform_alpha = match self.settings.alpha {
            Alpha::Uniform(alpha) => Some(alpha),
            Alpha::PerPoint(_) => None,
        };
        Shape { closed: self.closed, uniform_alpha }
    }
}

/// The target magnitude where the law's line value `value` at a point gives no positive finite
/// radius: the law's limit, within the cap (the window's `sharpest` sample). A value at or below
/// zero is ρ → 0 for α > 0 (so the cap) and ρ → ∞ for α < 0 (straight). `None` for a NaN value. The paper's
/// filter holds such a point; with the data term the target stays continuous in the window's
/// samples instead, because a point that is held in one pass and moved in the next can cycle
/// for ever (measured: a 20-point clothoid with 1 % noise and an estimated α of −2.7 alternated
/// with a period of three passes until the pass cap).
pub(super) fn law_limit(value: f64, alpha: f64, sharpest: f64) -> Option<f64> {
    // The curvature 1/ρ straight from the law, where it under- or overflows the radius.
    let kappa = match alpha {
        _ if value.is_nan() => return None,
        0.0 => (-value).exp(),
        _ if value <= 0.0 => {
            if alpha > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        }
        _ => value.powf(-1.0 / alpha),
    };
    Some(kappa.min(sharpest))
}

/// With the data term, the share in [0, 1] of the clothoid's line (the signed value's own least-
/// squares line) in a window's target, the rest the law's: none while the window's magnitudes
/// differ by less than half [`MAX_CURVATURE_RATIO`], all from the full ratio on or where the
/// samples change sign, log-linear between, so the target never jumps as one sample crosses a
/// threshold (`largest`, `smallest`: the window's extreme samples, signed along the point's).
pub(super) fn clothoid_share(one_signed: bool, largest: f64, smallest: f64) -> f64 {
    let share = if one_signed && smallest > 0.0 {
        ((largest / smallest).ln() - (0.5 * MAX_CURVATURE_RATIO).ln()) / 2f64.ln()
    } else {
        1.0
    };
    share.clamp(0.0, 1.0)
}

/// The root of `a x² + b x + c = 0` of smaller magnitude, stably; `None` without a real root.
pub(crate) fn smaller_root(a: f64, b: f64, c: f64) -> Option<f64> {
    nearest_root(a, b, c, 0.0)
}

/// The real root of `a x² + b x + c = 0` nearest `near`, computed stably; `None` without one.
pub(crate) fn nearest_root(a: f64, b: f64, c: f64, near: f64) -> Option<f64> {
    if a == 0.0 {
        return (b != 0.0).then(|| -c / b);
    }
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let q = -0.5 * (b + if b < 0.0 { -disc.sqrt() } else { disc.sqrt() });
    if q == 0.0 {
        return Some(0.0);
    }
    let (r1, r2) = (c / q, q / a);
    Some(if (r1 - near).abs() <= (r2 - near).abs() { r1 } else { r2 })
}

/// What a pass did, in the units of the points it moved.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PassTotals {
    /// Largest squared move (NaN when a move was).
    pub largest2: f64,
    /// Sums over the moved points of `(κ − κ*)²` and of `κ²`.
    pub err2: f64,
    pub k2: f64,
    /// Points held, and moves cut back to the half chord.
    pub held: usize,
    pub capped: usize,
    /// Mean segment length before the pass.
    pub mean_gap: f64,
    /// Smallest squared segment length after the pass.
    pub shortest2: f64,
}

/// Fairs a curve to convergence (or [`FilterSettings::max_passes`]) and returns the filter.
pub fn fair(curve: &PointSequence, settings: FilterSettings) -> Result<CurveFilter> {
    let mut filter = CurveFilter::new(curve, settings)?;
    filter.run_to_convergence()?;
    Ok(filter)
}

#[path = "filter_spatial.rs"]
mod spatial;

#[cfg(test)]
#[path = "filter_tests.rs"]
mod tests;
