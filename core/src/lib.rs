//! Taut's geometry core: polygon cages, their files, and the schemes that make smooth surfaces
//! of them.
//!
//! Data flows one way: a file is read into a [`Document`](document::Document) (a cage, its
//! scheme, fixed flags, tensions, creases and settings), changed only through [`Edit`]s, handed
//! to the document's [`surface`] scheme ([`nusd`] smoothing, [`subdiv`]ision), and the surface's
//! [`PolyMesh`](mesh::PolyMesh) with its normals is written out or drawn. Nothing here touches a
//! GPU or a window. Curves are point sequences ([`curve`]); [`aesthetic`] fairs them towards
//! log-aesthetic curves and builds segments and Coons patches from them.

pub mod aesthetic;
pub mod cad;
pub mod cage_fit;
pub mod curvature;
pub mod curve;
pub mod document;
pub mod error;
pub mod gregory;
pub mod io;
pub mod memory;
pub mod mesh;
pub mod nusd;
pub mod subdiv;
pub mod surface;

pub use document::Document;
pub use document::Edit;
pub use error::{Error, Result};
pub use mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};

/// Double-precision 3-vector used for all geometry.
pub use glam::DVec3;
