//! The boundary representation Taut hands to CAD: B-spline faces that share their edges and
//! vertices, grouped into shells (closed parts become solids), in the units the designer chose.
//!
//! This is the seam between the surface fitters ([`super::fit`]) and the STEP writer
//! ([`super::step`]): nothing here knows where the patches came from. Indices are plain `usize`
//! into the model's lists; a face's outer loop lists its edges in order, each with the sense in
//! which the loop runs along it, counter-clockwise seen from the side the face's normal points to.

use crate::DVec3;

/// A clamped, non-rational B-spline curve.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve {
    pub degree: usize,
    /// Distinct knot values, increasing.
    pub knots: Vec<f64>,
    /// How often each knot occurs (the ends `degree + 1`); sums to `points.len() + degree + 1`.
    pub multiplicities: Vec<usize>,
    pub points: Vec<DVec3>,
}

/// A clamped, non-rational tensor-product B-spline surface.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurface {
    pub degree_u: usize,
    pub degree_v: usize,
    pub knots_u: Vec<f64>,
    pub multiplicities_u: Vec<usize>,
    pub knots_v: Vec<f64>,
    pub multiplicities_v: Vec<usize>,
    /// Control points, `points[i][j]` the `i`-th along u and the `j`-th along v.
    pub points: Vec<Vec<DVec3>>,
}

/// An edge: a curve from one vertex to another (the curve starts at `start` and ends at `end`).
#[derive(Clone, Debug, PartialEq)]
pub struct BrepEdge {
    pub start: usize,
    pub end: usize,
    pub curve: BSplineCurve,
}

/// A face: a surface bounded by one loop of edges.
#[derive(Clone, Debug, PartialEq)]
pub struct BrepFace {
    pub surface: BSplineSurface,
    /// The outer loop: `(edge, same_sense)`, true when the loop runs from the edge's start to its
    /// end.
    pub outer: Vec<(usize, bool)>,
    /// Per entry of `outer`, where its edge lies on this face's surface: the `(u, v)` at the
    /// edge curve's first and at its last parameter, the curve running straight between them
    /// with its own parameter (written as the edge's `PCURVE`s, so a reader need not project the
    /// edge onto the surface). Empty when not known.
    pub outer_uv: Vec<[[f64; 2]; 2]>,
    /// True when the face's normal is the surface's `∂u × ∂v`, false when it is the opposite.
    pub same_sense: bool,
}

/// A connected set of faces: closed (every edge shared by two of its faces, a solid's boundary)
/// or open.
#[derive(Clone, Debug, PartialEq)]
pub struct BrepShell {
    pub faces: Vec<usize>,
    pub closed: bool,
}

/// Length units written into the file: the document's own ([`crate::document::units`]).
pub use crate::document::units::LengthUnit;

/// Vertices, edges, faces and shells, with one length unit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BrepModel {
    pub vertices: Vec<DVec3>,
    pub edges: Vec<BrepEdge>,
    pub faces: Vec<BrepFace>,
    pub shells: Vec<BrepShell>,
}
