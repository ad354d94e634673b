//! NUSD: nonuniform spline diffusion (Kuriyama, seed `000_9238026bd154f5a3`; our reading is
//! `docs/nusd.md`).
//!
//! Every vertex carries a position `P` and a second-derivative vector `R`. Moving vertices
//! diffuse both (eqs. 2 and 3); fixed vertices keep `P` and recompute `R = ΔP/K` (eq. 4). With
//! chord-length spacing the converged polyline is the natural cubic spline with chord-length
//! knots; on surfaces the cage is refined level by level and each level is diffused to
//! convergence before the next split.
//!
//! - [`polyline`]: open and closed curves with fixed points and tension (eq. 5).
//! - [`surface`]: the hierarchical surface solver the editor drives every frame.
//!
//! Weak spots, as in the paper: large or many tensions can make the explicit iteration diverge or
//! oscillate (the solver then rolls back and retries with a smaller λ), and the iteration count of
//! a single level grows with the square of the number of points inserted between fixed points.

pub mod convergence;
pub mod polyline;
pub mod surface;

use serde::{Deserialize, Serialize};

/// How the parameter interval `s_ij` of an edge is measured (`docs/nusd.md`, "Spacing").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Spacing {
    /// `s_ij = |D_j − D_i|`, the chord length of the unsmoothed domain (the paper's choice).
    #[default]
    Chord,
    /// `s_ij = 1` (the paper's Fig. 4: bulges where edges have very different lengths).
    Uniform,
    /// `s_ij = sqrt(|D_j − D_i|)`.
    Centripetal,
}

impl Spacing {
    /// The spacing of an edge of domain length `chord`, clamped below by `min_spacing` so that
    /// no weight divides by zero.
    #[inline]
    pub fn of_chord(self, chord: f64, min_spacing: f64) -> f64 {
        let s = match self {
            Spacing::Chord => chord,
            Spacing::Uniform => 1.0,
            Spacing::Centripetal => chord.sqrt(),
        };
        if s.is_finite() { s.max(min_spacing) } else { min_spacing }
    }

    /// The spacing of an edge of a surface level `depth` splits below the cage, of domain
    /// length `chord` (unclamped; 0 when not finite). Each split halves an edge's parameter interval, so the
    /// parametrisation's own unit halves too: uniform spacing is `2^-depth` and centripetal
    /// `sqrt(chord · 2^-depth)`, a cage edge's parameter length shared evenly by its pieces
    /// (chord spacing, a length, halves with the chord by itself). Without tension a
    /// level's `P` is the same whatever constant its spacings are scaled by (`R` scales
    /// instead), but the levels' `R` must agree for one level to start and correct the
    /// next: with `1` at every level, level `k`'s `R` was `4^-k` of the cage's, and multigrid
    /// stalled on the default scene (`docs/nusd.md`, "Spacing").
    #[inline]
    pub fn of_level_chord(self, chord: f64, depth: u32) -> f64 {
        let unit = 0.5f64.powi(depth.min(1000) as i32);
        let s = match self {
            Spacing::Chord => chord,
            Spacing::Uniform => unit,
            Spacing::Centripetal => (chord * unit).sqrt(),
        };
        if s.is_finite() { s } else { 0.0 }
    }

    /// The smallest spacing allowed for a model whose bounding box has diagonal `diagonal`
    /// (`docs/nusd.md`, "Spacing": clamp to `1e-9 · bbox_diagonal`).
    pub fn min_spacing(self, diagonal: f64) -> f64 {
        match self {
            Spacing::Chord => 1e-9 * diagonal.max(f64::MIN_POSITIVE),
            Spacing::Uniform => 1e-9,
            Spacing::Centripetal => (1e-9 * diagonal.max(f64::MIN_POSITIVE)).sqrt(),
        }
    }
}

impl std::str::FromStr for Spacing {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "chord" => Ok(Spacing::Chord),
            "uniform" => Ok(Spacing::Uniform),
            "centripetal" => Ok(Spacing::Centripetal),
            other => Err(format!("unknown spacing '{other}' (use chord, uniform or centripetal)")),
        }
    }
}

/// Default diffusion constant λ for curves (`docs/nusd.md`, "One iteration").
pub const DEFAULT_LAMBDA_CURVE: f64 = 0.7;
/// Default diffusion constant λ for surfaces (`docs/nusd.md`, "One iteration"; the paper's 0.6).
pub const DEFAULT_LAMBDA_SURFACE: f64 = 0.6;
/// Default relative tolerance: the solve stops when the estimated distance to the fixed point is
/// below `tol · bbox_diagonal`.
pub const DEFAULT_TOL: f64 = 1e-3;

/// Default number of refinement levels of a surface.
pub const DEFAULT_LEVELS: u32 = 3;
/// Default cap on iterations per level of a surface solve.
pub const DEFAULT_MAX_ITERATIONS: usize = 5_000;
/// Most refinement levels accepted (each level multiplies the faces by about four).
pub const MAX_LEVELS: u32 = 7;

/// Settings of a surface solve, saved with the cage document.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// Number of refinement levels (0 = the cage itself).
    pub levels: u32,
    /// Diffusion constant λ ∈ (0, 1).
    pub lambda: f64,
    /// Relative tolerance; the threshold is `tol · bbox_diagonal`.
    pub tol: f64,
    /// Cap on iterations per level.
    pub max_iterations: usize,
    /// Parametrisation of the edges.
    pub spacing: Spacing,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            levels: DEFAULT_LEVELS,
            lambda: DEFAULT_LAMBDA_SURFACE,
            tol: DEFAULT_TOL,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            spacing: Spacing::Chord,
        }
    }
}

impl SolverSettings {
    /// Checks every field, with a message a designer can act on.
    pub fn validate(&self) -> crate::Result<()> {
        let bad = |m: String| Err(crate::Error::Input(m));
        if self.levels > MAX_LEVELS {
            return bad(format!("{} levels is too many (at most {MAX_LEVELS})", self.levels));
        }
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

/// Refuses a tension τ that is not a finite number ≥ 0, naming what it belongs to.
pub(crate) fn check_tension(tau: f64, what: impl Fn() -> String) -> crate::Result<()> {
    if tau.is_finite() && tau >= 0.0 {
        Ok(())
    } else {
        Err(crate::Error::Input(format!("tension of {} must be a finite number ≥ 0, not {tau}", what())))
    }
}
