//! Subdivision surfaces: Catmull–Clark and Loop refinement with weighted stencils, creases, and
//! exact limit positions and normals (`shared/spec/curve-mesh-gregory.md` §1–2 for
//! Catmull–Clark, `shared/spec/control-cage.md` for Loop).
//!
//! - [`sparse`]: the sparse row matrices the stencils and limit masks are stored in.
//! - [`loop_limit`]: the limit-position matrix of a Loop cage, `p∞ = M p`, which the control
//!   cage fitter solves with.

pub mod loop_limit;
pub mod sparse;

pub use loop_limit::loop_limit_matrix;
pub use sparse::SparseRows;
