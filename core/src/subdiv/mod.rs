//! Subdivision surfaces: Catmull–Clark and Loop refinement with weighted stencils, creases, and
//! exact limit positions and normals (`docs/subdivision.md`; the Loop limit matrix also in
//! `docs/control-cage.md`).
//!
//! - [`topology`]: one topological split for every scheme (quads, triangles or NUSD's mix), with
//!   stable numbering and the origin of every child element.
//! - [`crease`]: per-edge sharpness, vertex rules and uniform semi-sharp creasing (OpenSubdiv's
//!   semantics), boundaries as infinitely sharp edges.
//! - [`rules`]: the Catmull–Clark and Loop rules as stencils from one level to the next.
//! - [`limit`]: limit positions and normals as stencils over a level; [`eigen_masks`]: the exact
//!   masks at darts and across creases and boundaries.
//! - [`refinement`]: [`Refinement`], built once per cage topology and re-evaluated per drag.
//! - [`sparse`]: the sparse row matrices the stencils and limit masks are stored in.
//! - [`loop_limit`]: the limit-position matrix of a smooth Loop cage, `p∞ = M p`, which the
//!   control cage fitter solves with.

pub mod crease;
pub mod eigen_masks;
pub mod limit;
pub mod loop_limit;
pub mod refinement;
pub mod rules;
pub mod sparse;
pub mod topology;

pub use crease::{Rule, corners_from_pairs, sharpness_from_pairs};
pub use limit::{LimitStencils, catmull_clark_limit};
pub use loop_limit::loop_limit_matrix;
pub use refinement::{MAX_LEVELS, MAX_REFINED_FACES, RefinedPositions, Refinement};
pub use rules::Scheme;
pub use sparse::SparseRows;
pub use topology::{SplitRule, SplitTopology, VertexOrigin};
