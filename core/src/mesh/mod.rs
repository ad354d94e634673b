//! The polygon mesh every part of Taut shares: cages, refined levels and exported surfaces.
//!
//! A halfedge structure over arbitrary polygons with open boundaries. Halfedges come in twin
//! pairs (`2e`, `2e + 1`), boundary halfedges have no face and are linked around their boundary
//! loop, so one-ring traversal works the same on the boundary and inside. Construction checks the
//! connectivity and refuses what the structure cannot represent (a non-manifold edge or vertex,
//! inconsistent orientation) with a message naming the offending vertices; it never panics on
//! bad input.
//!
//! Connectivity and geometry are separate: positions can change without touching the topology.
//! Two counters let caches know what changed: [`PolyMesh::generation`] is bumped by every edit,
//! [`PolyMesh::topology_generation`] only when the connectivity is rebuilt.

mod build;
pub mod edge_sort;
pub mod edit;
mod handles;
pub mod primitives;
pub mod sections;
pub(crate) mod union_find;
pub mod visibility;

pub use handles::{EdgeId, FaceId, HalfedgeId, VertexId};

use crate::DVec3;
use std::sync::atomic::{AtomicU64, Ordering};

/// Source of unique topology generations, so two meshes built separately never share one.
static NEXT_TOPOLOGY: AtomicU64 = AtomicU64::new(1);

/// A polygon mesh with full adjacency.
#[derive(Clone, Debug)]
pub struct PolyMesh {
    positions: Vec<DVec3>,
    vertex_halfedge: Vec<HalfedgeId>,
    halfedge_to: Vec<VertexId>,
    halfedge_next: Vec<HalfedgeId>,
    halfedge_prev: Vec<HalfedgeId>,
    halfedge_face: Vec<FaceId>,
    face_halfedge: Vec<HalfedgeId>,
    generation: u64,
    topology_generation: u64,
}

/// The arrays of a [`PolyMesh`], for [`PolyMesh::from_halfedges`].
pub(crate) struct HalfedgeArrays {
    pub positions: Vec<DVec3>,
    pub vertex_halfedge: Vec<HalfedgeId>,
    pub halfedge_to: Vec<VertexId>,
    pub halfedge_next: Vec<HalfedgeId>,
    pub halfedge_prev: Vec<HalfedgeId>,
    pub halfedge_face: Vec<FaceId>,
    pub face_halfedge: Vec<HalfedgeId>,
}

impl PolyMesh {
    /// Builds a mesh from vertex positions and faces given as lists of vertex indices
    /// (counter-clockwise seen from outside). Fails with a clear message on non-finite
    /// coordinates, indices out of range, faces with fewer than three or repeated vertices,
    /// non-manifold edges or vertices, and inconsistent orientation.
    ///
    /// Vertices used by no face are kept (so numbering is preserved) as isolated vertices.
    pub fn from_polygons<F: AsRef<[u32]>>(positions: Vec<DVec3>, faces: &[F]) -> crate::Result<Self> {
        build::build(positions, faces)
    }

    /// Like [`PolyMesh::from_polygons`], with the faces in compressed rows: face `f` is
    /// `indices[offsets[f]..offsets[f + 1]]` (`offsets` starts at 0 and has one entry more than
    /// there are faces).
    pub fn from_face_list(positions: Vec<DVec3>, offsets: &[u32], indices: &[u32]) -> crate::Result<Self> {
        build::build_flat(positions, offsets, indices)
    }

    /// A mesh from halfedge arrays that already satisfy its invariants (the refinement derives
    /// each level's halfedges from the level above, `subdiv::topology`); checked by
    /// [`PolyMesh::validate`] in debug builds.
    pub(crate) fn from_halfedges(arrays: HalfedgeArrays) -> Self {
        let HalfedgeArrays {
            positions,
            vertex_halfedge,
            halfedge_to,
            halfedge_next,
            halfedge_prev,
            halfedge_face,
            face_halfedge,
        } = arrays;
        let mesh = PolyMesh {
            positions,
            vertex_halfedge,
            halfedge_to,
            halfedge_next,
            halfedge_prev,
            halfedge_face,
            face_halfedge,
            generation: 0,
            topology_generation: fresh_topology_generation(),
        };
        debug_assert_eq!(mesh.validate(), Ok(()));
        mesh
    }

    /// Number of vertices (isolated ones included).
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_halfedge.len()
    }
    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.halfedge_to.len() / 2
    }
    /// Number of halfedges (twice the edges).
    pub fn halfedge_count(&self) -> usize {
        self.halfedge_to.len()
    }

    /// All vertex handles.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = VertexId> + use<> {
        (0..self.positions.len() as u32).map(VertexId)
    }
    /// All face handles.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = FaceId> + use<> {
        (0..self.face_halfedge.len() as u32).map(FaceId)
    }
    /// All edge handles.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = EdgeId> + use<> {
        (0..(self.halfedge_to.len() / 2) as u32).map(EdgeId)
    }

    /// Position of a vertex.
    #[inline]
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.positions[v.index()]
    }
    /// All positions, indexed by vertex.
    #[inline]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Moves one vertex.
    pub fn set_position(&mut self, v: VertexId, p: DVec3) {
        self.positions[v.index()] = p;
        self.generation += 1;
    }
    /// Mutable access to all positions; counts as an edit.
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        self.generation += 1;
        &mut self.positions
    }

    /// Bumped by every edit of positions or connectivity.
    pub fn generation(&self) -> u64 {
        self.generation
    }
    /// Changes only when the connectivity changes; unique across meshes.
    pub fn topology_generation(&self) -> u64 {
        self.topology_generation
    }

    /// The vertex a halfedge points to.
    #[inline]
    pub fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        self.halfedge_to[h.index()]
    }
    /// The vertex a halfedge starts from.
    #[inline]
    pub fn from_vertex(&self, h: HalfedgeId) -> VertexId {
        self.halfedge_to[h.twin().index()]
    }
    /// Next halfedge around the same face (or boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge_next[h.index()]
    }
    /// Previous halfedge around the same face (or boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedge_prev[h.index()]
    }
    /// The face left of a halfedge, invalid on the boundary.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> FaceId {
        self.halfedge_face[h.index()]
    }
    /// One halfedge of a face.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        self.face_halfedge[f.index()]
    }
    /// One outgoing halfedge of a vertex; for a boundary vertex the outgoing boundary halfedge.
    /// Invalid for an isolated vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        self.vertex_halfedge[v.index()]
    }

    /// True for a halfedge without a face.
    #[inline]
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        !self.face(h).is_valid()
    }
    /// True for an edge with a face on one side only.
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.is_boundary_halfedge(e.halfedge(0)) || self.is_boundary_halfedge(e.halfedge(1))
    }
    /// True for a vertex on an open boundary.
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        let h = self.vertex_halfedge(v);
        h.is_valid() && self.is_boundary_halfedge(h)
    }
    /// True for a vertex used by no face.
    pub fn is_isolated(&self, v: VertexId) -> bool {
        !self.vertex_halfedge(v).is_valid()
    }
    /// True when the mesh has no open boundary.
    pub fn is_closed(&self) -> bool {
        self.halfedge_face.iter().all(|f| f.is_valid())
    }

    /// The two end vertices of an edge.
    pub fn edge_vertices(&self, e: EdgeId) -> (VertexId, VertexId) {
        let h = e.halfedge(0);
        (self.from_vertex(h), self.to_vertex(h))
    }

    /// The halfedge from `a` to `b`, if they are joined by an edge.
    pub fn find_halfedge(&self, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
        self.outgoing(a).find(|&h| self.to_vertex(h) == b)
    }

    /// Outgoing halfedges of a vertex, in rotation order; starts with the boundary halfedge on
    /// the boundary.
    pub fn outgoing(&self, v: VertexId) -> Outgoing<'_> {
        let start = self.vertex_halfedge(v);
        Outgoing { mesh: self, start, current: start }
    }

    /// Neighbouring vertices (joined by an edge), in rotation order.
    pub fn vertex_neighbors(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.outgoing(v).map(|h| self.to_vertex(h))
    }

    /// Number of edges at a vertex.
    pub fn valence(&self, v: VertexId) -> usize {
        self.outgoing(v).count()
    }

    /// Halfedges of a face, in order.
    pub fn face_halfedges(&self, f: FaceId) -> FaceLoop<'_> {
        let start = self.face_halfedge(f);
        FaceLoop { mesh: self, start, current: start }
    }

    /// Vertices of a face, in order.
    pub fn face_vertices(&self, f: FaceId) -> impl Iterator<Item = VertexId> + '_ {
        self.face_halfedges(f).map(|h| self.from_vertex(h))
    }

    /// Number of vertices of a face.
    pub fn face_valence(&self, f: FaceId) -> usize {
        self.face_halfedges(f).count()
    }

    /// Faces as lists of vertex indices (the inverse of [`PolyMesh::from_polygons`]).
    pub fn polygons(&self) -> Vec<Vec<u32>> {
        self.faces().map(|f| self.face_vertices(f).map(|v| v.0).collect()).collect()
    }

    /// Faces split into triangles (a fan from each face's first vertex), as index triples.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(self.face_count() * 2);
        let mut ring = Vec::new();
        for f in self.faces() {
            ring.clear();
            ring.extend(self.face_vertices(f).map(|v| v.0));
            for k in 1..ring.len() - 1 {
                out.push([ring[0], ring[k], ring[k + 1]]);
            }
        }
        out
    }

    /// Area vector of a face (Newell's method): normal direction times area; exact for planar
    /// polygons and a sensible average for warped ones.
    pub fn face_area_vector(&self, f: FaceId) -> DVec3 {
        let mut sum = DVec3::ZERO;
        for h in self.face_halfedges(f) {
            let a = self.position(self.from_vertex(h));
            let b = self.position(self.to_vertex(h));
            sum += a.cross(b);
        }
        0.5 * sum
    }

    /// Area-weighted unit vertex normals (zero for isolated or degenerate vertices). Computed on
    /// the mesh moved to the origin and scaled to unit size, so a cage of size 1e-200 (whose area
    /// vectors would underflow to zero) or 1e300 (overflow) gets the same normals as at size 1.
    pub fn vertex_normals(&self) -> Vec<DVec3> {
        let mut normals = vec![DVec3::ZERO; self.vertex_count()];
        let Some((lo, hi)) = self.bounding_box() else { return normals };
        let centre = lo * 0.5 + hi * 0.5;
        let half = (hi * 0.5 - lo * 0.5).max_element();
        // Divided rather than multiplied by the reciprocal, which overflows for a subnormal half.
        let half = if half > 0.0 && half.is_finite() { half } else { 1.0 };
        let unit = |v: VertexId| (self.position(v) - centre) / half;
        for f in self.faces() {
            let mut n = DVec3::ZERO;
            for h in self.face_halfedges(f) {
                n += unit(self.from_vertex(h)).cross(unit(self.to_vertex(h)));
            }
            for v in self.face_vertices(f) {
                normals[v.index()] += n;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        normals
    }

    /// Axis-aligned bounding box `(min, max)`; `None` for a mesh without vertices.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        bounding_box(&self.positions)
    }

    /// Length of the bounding-box diagonal (0 for an empty mesh), without underflow or overflow
    /// of the squares: a cage 1e-200 across has a diagonal near 1e-200, not 0. Infinite only when
    /// the diagonal itself exceeds the largest `f64`.
    pub fn bounding_diagonal(&self) -> f64 {
        self.bounding_box().map_or(0.0, |(lo, hi)| diagonal_length(lo, hi))
    }

    /// Length of an edge.
    pub fn edge_length(&self, e: EdgeId) -> f64 {
        let (a, b) = self.edge_vertices(e);
        (self.position(b) - self.position(a)).length()
    }

    /// Euler characteristic V − E + F (isolated vertices count).
    pub fn euler_characteristic(&self) -> i64 {
        self.vertex_count() as i64 - self.edge_count() as i64 + self.face_count() as i64
    }

    /// Checks every connectivity invariant; used after edits in tests and debug builds.
    pub fn validate(&self) -> Result<(), String> {
        build::validate(self)
    }
}

/// Length of the diagonal from `lo` to `hi`, computed from halves scaled by their largest
/// component so that neither the difference nor the squares overflow or underflow.
pub fn diagonal_length(lo: DVec3, hi: DVec3) -> f64 {
    let plain = (hi - lo).length();
    if plain.is_finite() && plain > 1e-150 && plain < 1e150 {
        return plain; // no square under- or overflowed
    }
    let half = 0.5 * hi - 0.5 * lo;
    let m = half.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        return 2.0 * m;
    }
    2.0 * m * (half / m).length()
}

/// Bounding box of a point set.
pub fn bounding_box(points: &[DVec3]) -> Option<(DVec3, DVec3)> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
}

/// Iterator over the outgoing halfedges of a vertex.
#[derive(Debug)]
pub struct Outgoing<'a> {
    mesh: &'a PolyMesh,
    start: HalfedgeId,
    current: HalfedgeId,
}

impl Iterator for Outgoing<'_> {
    type Item = HalfedgeId;
    fn next(&mut self) -> Option<HalfedgeId> {
        if !self.current.is_valid() {
            return None;
        }
        let h = self.current;
        let next = self.mesh.prev(h).twin();
        self.current = if next == self.start { HalfedgeId::INVALID } else { next };
        Some(h)
    }
}

/// Iterator over the halfedges of a face.
#[derive(Debug)]
pub struct FaceLoop<'a> {
    mesh: &'a PolyMesh,
    start: HalfedgeId,
    current: HalfedgeId,
}

impl Iterator for FaceLoop<'_> {
    type Item = HalfedgeId;
    fn next(&mut self) -> Option<HalfedgeId> {
        if !self.current.is_valid() {
            return None;
        }
        let h = self.current;
        let next = self.mesh.next(h);
        self.current = if next == self.start { HalfedgeId::INVALID } else { next };
        Some(h)
    }
}

fn fresh_topology_generation() -> u64 {
    NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed)
}
