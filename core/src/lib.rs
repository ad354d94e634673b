//! Taut's geometry core: polygon cages, their files, and NUSD smoothing.
//!
//! Data flows one way: a file is read into a [`Document`](document::Document) (a cage with fixed
//! flags, tensions and solver settings), the [`nusd`] solver refines and smooths it level by
//! level, and the smoothed [`PolyMesh`](mesh::PolyMesh) is written out or drawn. Nothing here
//! touches a GPU or a window.

pub mod curvature;
pub mod document;
pub mod error;
pub mod gregory;
pub mod io;
pub mod mesh;
pub mod nusd;
pub mod subdiv;

pub use document::Document;
pub use error::{Error, Result};
pub use mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};

/// Double-precision 3-vector used for all geometry.
pub use glam::DVec3;
