//! Curves as point sequences: the shared ground of NUSD's polylines, the log-aesthetic filters
//! and the curvature combs.
//!
//! - [`sequence`]: [`PointSequence`], ordered points (open or closed) with chord lengths, arc
//!   length, bounding box and validation.
//! - [`derivatives`]: first, second and third derivatives on nonuniform parameters, curvature
//!   and torsion from them (the log-aesthetic paper's eqs. 1 and 3).
//! - [`menger`]: the curvature of the circle through each point and its neighbours, for combs.
//! - [`plane`]: the least-squares plane of a planar curve.
//! - [`bspline`]: clamped B-splines and their least-squares fit to points.
//! - [`set`]: the curves, segments and Coons patches a document holds.

pub mod bspline;
pub mod derivatives;
pub mod menger;
pub mod plane;
pub mod sequence;
pub mod set;

pub use bspline::BSpline;
pub use derivatives::{CurveGeometry, curve_geometry};
pub use menger::{PolylineCurvature, polyline_curvature};
pub use plane::Plane;
pub use sequence::PointSequence;
pub use set::{CoonsPatch, CurveSet, CurvesView, DocCurve, SegmentControls, Workspace};
