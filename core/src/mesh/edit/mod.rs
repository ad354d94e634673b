//! Topological edits of the cage: extrude, inset, loop cut, split, connect, delete, dissolve,
//! merge, fill, flip, triangulate, join, and mirror symmetry.
//!
//! Every edit is a free function that takes the cage (`&PolyMesh`, never changed) and returns an
//! [`Edited`]: a new, valid mesh and the [`Provenance`] of each of its vertices, edges and faces,
//! or a one-line error saying what was refused and why, naming the element. The document carries
//! fixed flags, tensions and crease sharpness across an edit with [`carry_fixed_flags`], [`carry_vertex_property`],
//! [`carry_edge_property`] and [`carry_face_property`], by the one rule in [`provenance`].
//!
//! | file | edits |
//! | --- | --- |
//! | `extrude.rs` | [`extrude_faces`] (region or individual), [`extrude_boundary_edges`] |
//! | `inset.rs` | [`inset_faces`] (region or individual) |
//! | `loop_cut.rs` | [`loop_cut`] |
//! | `split.rs` | [`split_edges`], [`connect_vertices`] |
//! | `delete.rs` | [`delete_vertices`], [`delete_edges`], [`delete_faces`] |
//! | `dissolve.rs` | [`dissolve_edges`], [`dissolve_faces`], [`dissolve_vertices`] |
//! | `merge.rs` | [`merge_vertices`] (centre, first, last), [`merge_by_distance`] |
//! | `fill.rs` | [`fill_edges`], [`fill_vertices`] |
//! | `orient.rs` | [`flip_normals`] |
//! | `triangulate.rs`, `join.rs` | [`triangulate`] (fan, shortest diagonal), [`join_triangles`] |
//! | `mirror.rs` | [`mirror_partners`], [`mirror_moves`], [`apply_mirror`] |
//!
//! Each edit builds the new face list in one pass over the old mesh and rebuilds the halfedge
//! structure with [`PolyMesh::from_face_list`] (`draft.rs`), so it is linear in the size of the
//! cage (the bench `mesh_edit` times them on a 20 000-face cage); the rebuilt mesh is checked with
//! [`PolyMesh::validate`] in debug builds. The operations follow Blender's edit mode where a
//! designer would expect them to; where they differ (a pinched vertex after a delete is split, a
//! loop cut that meets a triangle is refused rather than stopped) the file of the operation says
//! so. The methods are standard mesh editing rather than from Taut's papers. Nothing here runs
//! in parallel, so results do not depend on the number of threads.

mod delete;
mod dissolve;
mod draft;
mod extrude;
mod fill;
mod inset;
mod join;
mod lift;
mod loop_cut;
mod merge;
mod mirror;
mod orient;
pub mod provenance;
mod spatial;
mod split;
mod triangulate;

#[cfg(test)]
pub(crate) mod fixtures;
#[cfg(test)]
mod tests;

pub use delete::{delete_edges, delete_faces, delete_vertices};
pub use dissolve::{dissolve_edges, dissolve_faces, dissolve_vertices};
pub use extrude::{MAX_MITRE, extrude_boundary_edges, extrude_faces};
pub use fill::{fill_edges, fill_vertices};
pub use inset::inset_faces;
pub use join::{JoinParams, join_score, join_triangles};
pub use loop_cut::loop_cut;
pub use merge::{MergeAt, merge_by_distance, merge_vertices};
pub use mirror::{
    Axis, DEFAULT_MIRROR_TOLERANCE, MirrorPartner, MirrorPlane, apply_mirror, mirror_moves, mirror_partners,
};
pub use orient::flip_normals;
pub use provenance::{
    CarryRule, EdgeOrigin, FaceOrigin, Lineage, Provenance, VertexOrigin, carry_edge_property, carry_face_property,
    carry_fixed_flags, carry_vertex_property,
};
pub use split::{connect_vertices, split_edges};
pub use triangulate::{Triangulation, triangulate};

use crate::mesh::PolyMesh;

/// The result of an edit: the new cage and where each of its elements came from.
#[derive(Clone, Debug)]
pub struct Edited {
    /// The edited cage: a new topology generation, unless the edit found nothing to change
    /// (merge by distance with nothing close, join with no pair to join), which returns a copy.
    pub mesh: PolyMesh,
    /// Origins of its vertices, edges and faces in the cage before the edit.
    pub provenance: Provenance,
}

/// Whether selected faces are extruded or inset together or one by one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceGrouping {
    /// Connected selected faces act as one region, with walls only on the region's border.
    Region,
    /// Each face on its own, with walls on all its edges.
    Individual,
}
