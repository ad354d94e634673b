//! Taut's geometry core: polygon cages, their files, NUSD smoothing, and log-aesthetic curves.
//!
//! Data flows one way: a file is read into a [`Document`](document::Document) (a cage with fixed
//! flags, tensions and solver settings), the [`nusd`] solver refines and smooths it level by
//! level, and the smoothed [`PolyMesh`](mesh::PolyMesh) is written out or drawn. Curves are point
//! sequences ([`curve`]); [`aesthetic`] fairs them towards log-aesthetic curves and builds
//! segments and Coons patches from them. Nothing here touches a GPU or a window.

pub mod aesthetic;
pub mod curvature;
pub mod curve;
pub mod document;
pub mod error;
pub mod io;
pub mod mesh;
pub mod nusd;
pub mod subdiv;

pub use document::Document;
pub use error::{Error, Result};
pub use mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};

/// Double-precision 3-vector used for all geometry.
pub use glam::DVec3;
