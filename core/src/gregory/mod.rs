//! Curve meshes filled with G1 Gregory patches (seed 004: Yoshii, Tokuyama, Konno & Sone, "Curve
//! mesh generation of subdivision surfaces and Gregory patch interpolation"; read in
//! `docs/curve-mesh-gregory.md`).
//!
//! A polygon cage becomes a network of cubic Bézier curves with the cage's topology that lies on
//! its Catmull–Clark limit surface; every face is filled with a bicubic Gregory patch, and
//! neighbouring patches meet with G1 continuity by construction, however the designer then moves
//! the curve-mesh vertices, turns their tangent planes or drags the curves' inner control points.
//! Unlike a subdivision surface, a move changes only the patches around the moved vertex.
//!
//! - [`bezier`]: cubic Bézier curves and the two least-squares fits (limit points, Hoschek).
//! - [`patch`]: the bicubic Gregory patch, its exact evaluation and normal.
//! - [`chiyokura_kimura`]: the inner points from boundary curves and corner normals.
//! - [`build`]: from a cage to a curve mesh on its Catmull–Clark limit surface, with the fit's
//!   figures.
//! - [`closeness`]: distances from the limit surface to the patches.
//! - `middle`: the limit surface at the middle of every curve (normal, cross-derivative length).
//! - [`curve_mesh`]: the editable curve mesh, its edits and their serialisable state.
//! - [`tessellate`]: crack-free `K × K` sampling into one polygon mesh with analytic normals.
//! - [`export`]: OBJ and GLB of the tessellated patches, JSON of the curves and control points.
//! - [`continuity`]: G1 angles and G2 jumps along shared boundaries of any patch network.
//! - [`crate::document::curve_mesh_edits`]: the curve mesh of a document: its saved edit state, the core edits of it, a
//!   cache of the built curve mesh.
//! - [`carry`]: how curve-mesh edits follow a change of the cage they were made on.

pub mod bezier;
pub mod build;
pub mod carry;
pub mod chiyokura_kimura;
pub mod closeness;
pub mod continuity;
pub mod curve_mesh;
pub mod export;
mod middle;
pub mod patch;
pub mod tessellate;

pub use bezier::CubicBezier;
pub use build::{BuildReport, FitReport, fit_edge_curves};
pub use chiyokura_kimura::{CurveMiddle, PatchBoundary, gregory_patch};
pub use continuity::{ContinuityReport, SharedBoundary, continuity_report};
pub use curve_mesh::{Changed, CurveMesh, CurveMeshEdits};
pub use patch::{GregoryPatch, SurfacePatch};
pub use tessellate::Tessellation;
