//! The curvature graph and the logarithmic curvature graph (LCG) of any point sequence, with
//! the fitted line (paper sec. 3.2, fig. 1; Harada's LCG).
//!
//! The curvature of each point is the discrete one of [`crate::curve::derivatives`] on chord
//! parameters; ρ = 1/|κ|. The LCG plots `x = log ρ` against `y = log |ρ ds/dρ|`, with `dρ/ds`
//! the central difference of ρ over the two neighbours' arc lengths. A log-aesthetic curve
//! `ρ^α = c s + d` has `ρ ds/dρ = α ρ^α / c`, so its LCG is the line `y = α x + log(α/c)`: the
//! least-squares line through the graph gives α as its slope and its RMS distance in y as the
//! residual, the measure of how far the points are from one log-aesthetic curve.
//!
//! Where it is weak: `dρ/ds` is a difference of a second difference, so the LCG of raw noisy
//! points is a scatter (which is what the residual before filtering shows); points whose
//! neighbours have curvature of the other sign (inflections) or an equal radius (`dρ/ds = 0`,
//! a curvature extremum or a circle) have no LCG point and are left out. A curve made of several
//! pieces of different α gives one line per piece only when fitted per piece
//! ([`CurvatureGraph::fit_range`]).

use super::law::{LineFit, fit_line};
use crate::DVec3;
use crate::curve::{PointSequence, curve_geometry};

/// One point of a logarithmic curvature graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LcgPoint {
    /// Index of the curve point it belongs to.
    pub index: usize,
    /// `log ρ`.
    pub x: f64,
    /// `log |ρ ds/dρ|`.
    pub y: f64,
}

/// Curvature against arc length and the LCG of a point sequence.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvatureGraph {
    /// Cumulative chord length at every point.
    pub arc_length: Vec<f64>,
    /// Curvature per point (signed about the plane normal when one was given), `None` at the
    /// ends of an open curve.
    pub curvature: Vec<Option<f64>>,
    /// The LCG, in the order of the points.
    pub lcg: Vec<LcgPoint>,
    /// The least-squares line through the whole LCG (`None` with fewer than two points).
    pub fit: Option<LineFit>,
}

impl CurvatureGraph {
    /// The least-squares line through the LCG points of the curve points `first..=last`.
    pub fn fit_range(&self, first: usize, last: usize) -> Option<LineFit> {
        let (x, y): (Vec<f64>, Vec<f64>) =
            self.lcg.iter().filter(|p| p.index >= first && p.index <= last).map(|p| (p.x, p.y)).unzip();
        fit_line(&x, &y)
    }
}

/// The curvature graph and LCG of `curve`; the curvature is signed about `plane_normal` when one
/// is given (the LCG uses |κ| either way). Repeated points give no values around them.
pub fn curvature_graph(curve: &PointSequence, plane_normal: Option<DVec3>) -> CurvatureGraph {
    let geometry = curve_geometry(curve, plane_normal);
    let n = curve.len();
    let s = &geometry.arc_length;
    let total = curve.total_length();
    let mut lcg = Vec::new();
    for i in 0..n {
        let Some((a, b)) = curve.neighbours(i) else { continue };
        let (Some(ka), Some(ki), Some(kb)) = (geometry.curvature[a], geometry.curvature[i], geometry.curvature[b])
        else {
            continue;
        };
        if ki == 0.0 {
            continue;
        }
        let (ra, ri, rb) = (1.0 / ka.abs(), 1.0 / ki.abs(), 1.0 / kb.abs());
        // Arc length from a to b, across the seam of a closed curve too.
        let mut ds = s[b] - s[a];
        if ds <= 0.0 {
            ds += total;
        }
        let drho = (rb - ra) / ds;
        let (x, y) = (ri.ln(), (ri / drho).abs().ln());
        if x.is_finite() && y.is_finite() {
            lcg.push(LcgPoint { index: i, x, y });
        }
    }
    let (x, y): (Vec<f64>, Vec<f64>) = lcg.iter().map(|p| (p.x, p.y)).unzip();
    let fit = fit_line(&x, &y);
    CurvatureGraph { arc_length: geometry.arc_length, curvature: geometry.curvature, lcg, fit }
}
