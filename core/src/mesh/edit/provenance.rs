//! Where every element of an edited cage came from, and how per-element properties follow.
//!
//! An edit rebuilds the mesh, and the builder numbers edges afresh: an index that named one edge
//! before may name another after. So every edit returns, for each new vertex, edge and face, an
//! *origin* naming the old element it continues or was made from, and the document carries its
//! properties (fixed flags, vertex and edge tension, crease sharpness, face attributes) through
//! [`carry_vertex_property`], [`carry_edge_property`] and [`carry_face_property`].
//!
//! # The rule (one for every property)
//! - An element that **continues** an old one takes its value: [`Same`](EdgeOrigin::Same) (kept,
//!   perhaps moved or with a vertex more), [`CopyOf`](EdgeOrigin::CopyOf) (the cap of an
//!   extrusion, the inner ring of an inset: an extruded edge takes the tension and sharpness of
//!   the edge it came from, an extruded vertex its fixed flag and tension),
//!   [`MirrorOf`](EdgeOrigin::MirrorOf) (the mirrored half, so a mirrored cage smooths
//!   symmetrically), [`SplitFrom`](EdgeOrigin::SplitFrom) (both halves of a split edge keep its
//!   values; both pieces of a split face keep its values) and [`Merged`](EdgeOrigin::Merged)
//!   (merged elements keep the values of the *first* of them: the first vertex of an explicit
//!   merge, or the lowest old index where the merge has no order).
//! - An element **made** by the edit takes the rule's value for new elements
//!   ([`CarryRule::new`]): a vertex placed on an old edge ([`VertexOrigin::OnEdge`], loop cut
//!   and split: no tension; its fixed flag by [`carry_fixed_flags`], below), an edge across an old face
//!   ([`EdgeOrigin::InFace`]: smooth, no tension), the side edge an extrusion sweeps from a
//!   vertex ([`EdgeOrigin::SweptFrom`]), the wall an extrusion sweeps from an edge
//!   ([`FaceOrigin::SweptFrom`]), and what a fill makes from nothing (`New`).
//!
//! - A vertex placed on an old edge is **fixed only when both ends of that edge were fixed**
//!   ([`carry_fixed_flags`]): a loop cut through a free (approximated) region stays free, so
//!   the surface there keeps its shape instead of being pinned to the new cage points, and a cut
//!   between fixed points interpolates as its neighbours do. Every other made vertex is fixed.
//!
//! The task that asked for this rule said "new vertices are fixed"; copies made by extrude,
//! inset and mirror are read here as continuing their source (they keep its fixed flag and
//! tension) because a mirrored vertex that lost its tension would break the symmetry of the
//! smoothed surface, and an extruded cap that keeps its edges' tension should keep its corners'
//! too. Only vertices placed on edges are new.

use crate::mesh::{EdgeId, FaceId, VertexId};
use crate::{Error, Result};

/// Where a vertex of an edited cage came from.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum VertexOrigin {
    /// The old vertex, perhaps moved. (Where a deletion leaves an old vertex pinched between
    /// separate fans of faces, it is split and each piece is `Same` as the old vertex.)
    Same(VertexId),
    /// A copy of the old vertex made by an extrusion or an inset.
    CopyOf(VertexId),
    /// The mirror image of the old vertex (apply mirror).
    MirrorOf(VertexId),
    /// Several old vertices merged into one; it keeps the values of this one (the first).
    Merged(VertexId),
    /// A new vertex on an old edge, at fraction `t` from the edge's first vertex
    /// ([`PolyMesh::edge_vertices`](crate::PolyMesh::edge_vertices)`(edge).0`).
    OnEdge { edge: EdgeId, t: f64 },
}

/// Where an edge of an edited cage came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum EdgeOrigin {
    /// The old edge, perhaps with moved ends.
    Same(EdgeId),
    /// A copy of the old edge between copies of its ends (extrusion cap, inset ring), or an
    /// edge inside an extruded region whose ends moved with it (one a copy, one the old vertex).
    CopyOf(EdgeId),
    /// The mirror image of the old edge.
    MirrorOf(EdgeId),
    /// One of the two halves of a split old edge (split, loop cut).
    SplitFrom(EdgeId),
    /// Several old edges merged into one (merge, dissolve); it keeps this one's values.
    Merged(EdgeId),
    /// The side edge an extrusion or inset sweeps from an old vertex to its copy.
    SweptFrom(VertexId),
    /// A new edge across an old face (loop cut, connect, triangulate).
    InFace(FaceId),
    /// A new edge with no source (the closing edge of a fill).
    New,
}

/// Where a face of an edited cage came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FaceOrigin {
    /// The old face, perhaps moved or with more or fewer corners.
    Same(FaceId),
    /// The mirror image of the old face.
    MirrorOf(FaceId),
    /// A piece of a split old face (loop cut, connect, triangulate).
    SplitFrom(FaceId),
    /// Several old faces merged into one (dissolve, join); it keeps this one's values.
    Merged(FaceId),
    /// A wall an extrusion or inset sweeps from an old edge.
    SweptFrom(EdgeId),
    /// A face made from nothing (fill).
    New,
}

impl VertexOrigin {
    /// The old vertex whose values this vertex takes, if any.
    pub fn source(self) -> Option<VertexId> {
        match self {
            VertexOrigin::Same(v) | VertexOrigin::CopyOf(v) | VertexOrigin::MirrorOf(v) | VertexOrigin::Merged(v) => {
                Some(v)
            }
            VertexOrigin::OnEdge { .. } => None,
        }
    }
}

impl EdgeOrigin {
    /// The old edge whose values this edge takes, if any.
    pub fn source(self) -> Option<EdgeId> {
        match self {
            EdgeOrigin::Same(e)
            | EdgeOrigin::CopyOf(e)
            | EdgeOrigin::MirrorOf(e)
            | EdgeOrigin::SplitFrom(e)
            | EdgeOrigin::Merged(e) => Some(e),
            EdgeOrigin::SweptFrom(_) | EdgeOrigin::InFace(_) | EdgeOrigin::New => None,
        }
    }
}

impl FaceOrigin {
    /// The old face whose values this face takes, if any.
    pub fn source(self) -> Option<FaceId> {
        match self {
            FaceOrigin::Same(f) | FaceOrigin::MirrorOf(f) | FaceOrigin::SplitFrom(f) | FaceOrigin::Merged(f) => Some(f),
            FaceOrigin::SweptFrom(_) | FaceOrigin::New => None,
        }
    }
}

/// The origins of every element of an edited cage, and the sizes of the cage it was made from.
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// Per new vertex.
    pub vertices: Vec<VertexOrigin>,
    /// Per new edge (indexed by the new [`EdgeId`]).
    pub edges: Vec<EdgeOrigin>,
    /// Per new face.
    pub faces: Vec<FaceOrigin>,
    /// Vertices, edges and faces of the cage before the edit.
    pub old_counts: (usize, usize, usize),
}

/// The edit that made one cage from another, for what keeps state between cages (the NUSD
/// solver's warm start after a topology edit): the topology generations
/// ([`PolyMesh::topology_generation`](crate::PolyMesh::topology_generation)) of the cage before
/// and after, and the edit's provenance. A holder of state for the cage `from` may carry it onto
/// the cage `to` through `provenance`; for any other pair of cages it means nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct Lineage {
    /// Topology generation of the cage before the edit.
    pub from: u64,
    /// Topology generation of the cage the edit made.
    pub to: u64,
    pub provenance: Provenance,
}

/// How a property fills the elements an edit made without a source (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct CarryRule<T> {
    /// The value of a made element: for fixed flags `true`, for tensions and sharpness `0.0`.
    pub new: T,
}

impl<T> CarryRule<T> {
    /// A rule giving made elements `value`.
    pub fn new_elements(value: T) -> Self {
        CarryRule { new: value }
    }
}

/// Per-vertex values of the edited cage from those of the old one (`old` has one value per old
/// vertex), by the rule of the module docs.
pub fn carry_vertex_property<T: Clone>(old: &[T], provenance: &Provenance, rule: &CarryRule<T>) -> Result<Vec<T>> {
    carry(old, provenance.old_counts.0, "vertex", &provenance.vertices, |o| o.source().map(VertexId::index), rule)
}

/// Per-edge values of the edited cage (indexed by new [`EdgeId`]) from those of the old one.
pub fn carry_edge_property<T: Clone>(old: &[T], provenance: &Provenance, rule: &CarryRule<T>) -> Result<Vec<T>> {
    carry(old, provenance.old_counts.1, "edge", &provenance.edges, |o| o.source().map(EdgeId::index), rule)
}

/// Per-face values of the edited cage from those of the old one.
pub fn carry_face_property<T: Clone>(old: &[T], provenance: &Provenance, rule: &CarryRule<T>) -> Result<Vec<T>> {
    carry(old, provenance.old_counts.2, "face", &provenance.faces, |o| o.source().map(FaceId::index), rule)
}

/// The fixed flags of the edited cage: carried as [`carry_vertex_property`] carries them, with
/// made vertices fixed, except that a vertex placed on an old edge ([`VertexOrigin::OnEdge`]) is
/// fixed only when both ends of that edge were (`old_mesh` is the cage before the edit).
pub fn carry_fixed_flags(old: &[bool], old_mesh: &crate::mesh::PolyMesh, provenance: &Provenance) -> Result<Vec<bool>> {
    let mut fixed = carry_vertex_property(old, provenance, &CarryRule::new_elements(true))?;
    if old_mesh.vertex_count() != old.len() {
        return Err(Error::Input(format!(
            "the cage had {} vertices but {} fixed flags were given to carry over",
            old_mesh.vertex_count(),
            old.len()
        )));
    }
    for (flag, origin) in fixed.iter_mut().zip(&provenance.vertices) {
        if let VertexOrigin::OnEdge { edge, .. } = *origin {
            if edge.index() >= old_mesh.edge_count() {
                return Err(Error::Input(format!(
                    "edit provenance names old edge {}, but the cage had only {}",
                    edge.0,
                    old_mesh.edge_count()
                )));
            }
            let (a, b) = old_mesh.edge_vertices(edge);
            *flag = old[a.index()] && old[b.index()];
        }
    }
    Ok(fixed)
}

fn carry<T: Clone, O: Copy>(
    old: &[T],
    expected: usize,
    what: &str,
    origins: &[O],
    source: impl Fn(O) -> Option<usize>,
    rule: &CarryRule<T>,
) -> Result<Vec<T>> {
    if old.len() != expected {
        return Err(Error::Input(format!(
            "the cage had {expected} {what} values before the edit, but {} were given to carry over",
            old.len()
        )));
    }
    origins
        .iter()
        .map(|&o| match source(o) {
            Some(i) => old.get(i).cloned().ok_or_else(|| {
                Error::Input(format!("edit provenance names old {what} {i}, but the cage had only {expected}"))
            }),
            None => Ok(rule.new.clone()),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn provenance() -> Provenance {
        Provenance {
            vertices: vec![
                VertexOrigin::Same(VertexId(1)),
                VertexOrigin::OnEdge { edge: EdgeId(0), t: 0.5 },
                VertexOrigin::Merged(VertexId(0)),
            ],
            edges: vec![EdgeOrigin::SplitFrom(EdgeId(1)), EdgeOrigin::InFace(FaceId(0)), EdgeOrigin::CopyOf(EdgeId(0))],
            faces: vec![FaceOrigin::New, FaceOrigin::SplitFrom(FaceId(0))],
            old_counts: (2, 2, 1),
        }
    }

    #[test]
    fn sources_are_carried_and_made_elements_take_the_rule() {
        let p = provenance();
        let fixed = carry_vertex_property(&[false, false], &p, &CarryRule::new_elements(true)).unwrap();
        assert_eq!(fixed, vec![false, true, false]);
        let tension = carry_edge_property(&[0.25, 2.0], &p, &CarryRule::new_elements(0.0)).unwrap();
        assert_eq!(tension, vec![2.0, 0.0, 0.25]);
        let names = carry_face_property(&["a"], &p, &CarryRule::new_elements("-")).unwrap();
        assert_eq!(names, vec!["-", "a"]);
    }

    #[test]
    fn a_vertex_on_an_edge_is_fixed_only_when_both_ends_are() {
        use crate::mesh::edit::loop_cut;
        let cube = crate::PolyMesh::from_polygons(
            (0..8).map(|i| glam::DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64)).collect(),
            &[
                vec![0, 2, 3, 1],
                vec![4, 5, 7, 6],
                vec![0, 1, 5, 4],
                vec![2, 6, 7, 3],
                vec![0, 4, 6, 2],
                vec![1, 3, 7, 5],
            ],
        )
        .unwrap();
        // Free vertex 0 only: the cut ring of an edge at it puts new vertices on four edges.
        let mut old = vec![true; 8];
        old[0] = false;
        for e in cube.edges() {
            let edited = loop_cut(&cube, e, 0.5).unwrap();
            let fixed = carry_fixed_flags(&old, &cube, &edited.provenance).unwrap();
            for (v, origin) in edited.provenance.vertices.iter().enumerate() {
                let expected = match *origin {
                    VertexOrigin::OnEdge { edge, .. } => {
                        let (a, b) = cube.edge_vertices(edge);
                        a.0 != 0 && b.0 != 0
                    }
                    VertexOrigin::Same(w) => w.0 != 0,
                    other => panic!("a loop cut made {other:?}"),
                };
                assert_eq!(fixed[v], expected, "vertex {v} ({origin:?}) after cutting across {e:?}");
            }
        }
        let err = carry_fixed_flags(&old[..7], &cube, &loop_cut(&cube, EdgeId(0), 0.5).unwrap().provenance);
        assert!(err.is_err());
    }

    #[test]
    fn wrong_lengths_and_stale_provenance_are_refused() {
        let p = provenance();
        let err = carry_edge_property(&[1.0; 3], &p, &CarryRule::new_elements(0.0)).unwrap_err().to_string();
        assert!(err.contains("2 edge values") && err.contains("3 were given"), "{err}");
        let mut stale = provenance();
        stale.edges[0] = EdgeOrigin::Same(EdgeId(9));
        let err = carry_edge_property(&[1.0; 2], &stale, &CarryRule::new_elements(0.0)).unwrap_err().to_string();
        assert!(err.contains("old edge 9"), "{err}");
    }
}
