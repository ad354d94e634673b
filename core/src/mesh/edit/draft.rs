//! The scaffolding every edit shares: a draft face list that is rebuilt into a [`PolyMesh`] in
//! linear time, with the provenance of every element, and the selection and corner tables the
//! edits read the old mesh through.
//!
//! An edit copies the old positions (each vertex [`VertexOrigin::Same`]), adds vertices and
//! faces, and calls [`Draft::finish`]: vertices the edit left unused are removed (vertices that
//! were isolated before stay), the mesh is built with [`PolyMesh::from_face_list`], and each new
//! edge's origin is found from its ends and faces (see [`Draft::finish`]), unless the edit gave
//! it explicitly. A build failure comes back as the builder's message prefixed with the edit's
//! name, naming vertices by their old numbers.

use super::Edited;
use super::provenance::{EdgeOrigin, FaceOrigin, Provenance, VertexOrigin};
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use std::collections::HashMap;

/// A face list under construction, over old vertices (same numbers) and new ones (after them).
#[derive(Debug)]
pub(super) struct Draft<'m> {
    pub old: &'m PolyMesh,
    pub op: &'static str,
    pub positions: Vec<DVec3>,
    pub vertex_origin: Vec<VertexOrigin>,
    offsets: Vec<u32>,
    indices: Vec<u32>,
    face_origin: Vec<FaceOrigin>,
    edge_hints: HashMap<(u32, u32), EdgeOrigin>,
    removed: Vec<u32>,
}

impl<'m> Draft<'m> {
    /// A draft with every old vertex (as [`VertexOrigin::Same`]) and no faces.
    pub fn new(old: &'m PolyMesh, op: &'static str) -> Self {
        let mut offsets = Vec::with_capacity(old.face_count() + 1);
        offsets.push(0);
        Draft {
            old,
            op,
            positions: old.positions().to_vec(),
            vertex_origin: old.vertices().map(VertexOrigin::Same).collect(),
            offsets,
            indices: Vec::with_capacity(old.halfedge_count() + 16),
            face_origin: Vec::with_capacity(old.face_count()),
            edge_hints: HashMap::new(),
            removed: Vec::new(),
        }
    }

    /// Adds a vertex and returns its draft number.
    pub fn add_vertex(&mut self, p: DVec3, origin: VertexOrigin) -> u32 {
        self.positions.push(p);
        self.vertex_origin.push(origin);
        (self.positions.len() - 1) as u32
    }

    /// Adds a face through draft vertices.
    pub fn push_face(&mut self, vertices: impl IntoIterator<Item = u32>, origin: FaceOrigin) {
        self.indices.extend(vertices);
        self.offsets.push(self.indices.len() as u32);
        self.face_origin.push(origin);
    }

    /// Adds an old face unchanged, as [`FaceOrigin::Same`].
    pub fn keep_face(&mut self, f: FaceId) {
        let old = self.old;
        self.push_face(old.face_vertices(f).map(|v| v.0), FaceOrigin::Same(f));
    }

    /// Removes an old vertex even if it was isolated before (no face may use it).
    pub fn remove_vertex(&mut self, v: VertexId) {
        self.removed.push(v.0);
    }

    /// Gives the edge between draft vertices `a` and `b` an explicit origin.
    pub fn hint_edge(&mut self, a: u32, b: u32, origin: EdgeOrigin) {
        self.edge_hints.insert((a.min(b), a.max(b)), origin);
    }

    /// Builds the mesh and its provenance.
    ///
    /// An edge without an explicit origin is, in this order: [`EdgeOrigin::SweptFrom`] `v` when
    /// its ends are `v` and a copy of `v`; `Same`, `MirrorOf` or `CopyOf` the old edge between
    /// the sources of its ends (`Same` when both ends are old vertices, `MirrorOf` when one is a
    /// mirror image); [`EdgeOrigin::SplitFrom`] `e` when one end lies on old edge `e` and the
    /// other is an end of `e`; [`EdgeOrigin::InFace`] `f` when both its faces are pieces of old
    /// face `f`; otherwise [`EdgeOrigin::New`].
    pub fn finish(self) -> Result<Edited> {
        let Draft { old, op, positions, vertex_origin, offsets, indices, face_origin, edge_hints, removed } = self;
        if face_origin.is_empty() {
            return Err(Error::Topology(format!("{op}: the cage would have no faces left; keep at least one face")));
        }
        let n = positions.len();
        let mut used = vec![false; n];
        for &v in &indices {
            used[v as usize] = true;
        }
        let mut isolated: Vec<bool> =
            (0..n).map(|v| v < old.vertex_count() && old.is_isolated(VertexId::from_index(v))).collect();
        for &v in &removed {
            debug_assert!(!used[v as usize], "{op} removes vertex {v} but a face still uses it");
            isolated[v as usize] = false;
        }
        let keep = |v: usize| used[v] || isolated[v];
        let mut new_of_draft = vec![u32::MAX; n];
        let mut draft_of_new = Vec::with_capacity(n);
        for v in 0..n {
            if keep(v) {
                new_of_draft[v] = draft_of_new.len() as u32;
                draft_of_new.push(v as u32);
            }
        }
        let wrap = |e: Error| match e {
            Error::Topology(m) => Error::Topology(format!("{op}: {m}")),
            Error::Input(m) => Error::Input(format!("{op}: {m}")),
            other => other,
        };
        let mesh = if draft_of_new.len() == n {
            PolyMesh::from_face_list(positions, &offsets, &indices).map_err(wrap)?
        } else {
            let compact_positions = draft_of_new.iter().map(|&v| positions[v as usize]).collect();
            let compact: Vec<u32> = indices.iter().map(|&v| new_of_draft[v as usize]).collect();
            match PolyMesh::from_face_list(compact_positions, &offsets, &compact) {
                Ok(mesh) => mesh,
                // Build again in draft numbering so the message names the old vertex numbers.
                Err(e) => return Err(wrap(PolyMesh::from_face_list(positions, &offsets, &indices).err().unwrap_or(e))),
            }
        };
        let vertices: Vec<VertexOrigin> = draft_of_new.iter().map(|&v| vertex_origin[v as usize]).collect();
        let edges = mesh
            .edges()
            .map(|e| {
                let (a, b) = mesh.edge_vertices(e);
                let (da, db) = (draft_of_new[a.index()], draft_of_new[b.index()]);
                if let Some(&hint) = edge_hints.get(&(da.min(db), da.max(db))) {
                    return hint;
                }
                let faces = [e.halfedge(0), e.halfedge(1)].map(|h| mesh.face(h));
                infer_edge(
                    old,
                    vertices[a.index()],
                    vertices[b.index()],
                    faces.map(|f| f.is_valid().then(|| face_origin[f.index()])),
                )
            })
            .collect();
        debug_assert!(mesh.validate().is_ok(), "{op} built an invalid mesh: {:?}", mesh.validate());
        let provenance = Provenance {
            vertices,
            edges,
            faces: face_origin,
            old_counts: (old.vertex_count(), old.edge_count(), old.face_count()),
        };
        Ok(Edited { mesh, provenance })
    }
}

fn infer_edge(old: &PolyMesh, a: VertexOrigin, b: VertexOrigin, faces: [Option<FaceOrigin>; 2]) -> EdgeOrigin {
    use VertexOrigin::*;
    match (a, b) {
        (Same(x), CopyOf(y)) | (CopyOf(x), Same(y)) if x == y => return EdgeOrigin::SweptFrom(x),
        (OnEdge { edge, .. }, other) | (other, OnEdge { edge, .. }) => {
            let (p, q) = old.edge_vertices(edge);
            if other.source().is_some_and(|v| v == p || v == q) {
                return EdgeOrigin::SplitFrom(edge);
            }
        }
        _ => {}
    }
    if let (Some(x), Some(y)) = (a.source(), b.source())
        && let Some(h) = old.find_halfedge(x, y)
    {
        let e = h.edge();
        return match (a, b) {
            (Same(_) | Merged(_), Same(_) | Merged(_)) => EdgeOrigin::Same(e),
            (MirrorOf(_), _) | (_, MirrorOf(_)) => EdgeOrigin::MirrorOf(e),
            _ => EdgeOrigin::CopyOf(e),
        };
    }
    match faces {
        [Some(FaceOrigin::SplitFrom(f)), Some(FaceOrigin::SplitFrom(g))] if f == g => EdgeOrigin::InFace(f),
        _ => EdgeOrigin::New,
    }
}

/// The result of an edit that changes nothing: a copy of the cage (same topology generation)
/// with every element [`Same`](VertexOrigin::Same) as itself.
pub(super) fn unchanged(mesh: &PolyMesh) -> Edited {
    let provenance = Provenance {
        vertices: mesh.vertices().map(VertexOrigin::Same).collect(),
        edges: mesh.edges().map(EdgeOrigin::Same).collect(),
        faces: mesh.faces().map(FaceOrigin::Same).collect(),
        old_counts: (mesh.vertex_count(), mesh.edge_count(), mesh.face_count()),
    };
    Edited { mesh: mesh.clone(), provenance }
}

/// A selection as a mask over `count` elements; refuses an empty selection and unknown numbers.
pub(super) fn mask(
    op: &str,
    what: &str,
    count: usize,
    selected: impl ExactSizeIterator<Item = usize>,
) -> Result<Vec<bool>> {
    if selected.len() == 0 {
        return Err(Error::Input(format!("{op}: nothing selected; select at least one {what}")));
    }
    let mut mask = vec![false; count];
    for i in selected {
        if i >= count {
            return Err(Error::Input(format!(
                "{op}: {what} {i} does not exist (the cage has {count} {}, numbered from 0)",
                if what == "vertex" { "vertices".to_string() } else { format!("{what}s") }
            )));
        }
        mask[i] = true;
    }
    Ok(mask)
}

pub(super) fn face_mask(op: &str, mesh: &PolyMesh, faces: &[FaceId]) -> Result<Vec<bool>> {
    mask(op, "face", mesh.face_count(), faces.iter().map(|f| f.index()))
}

pub(super) fn edge_mask(op: &str, mesh: &PolyMesh, edges: &[EdgeId]) -> Result<Vec<bool>> {
    mask(op, "edge", mesh.edge_count(), edges.iter().map(|e| e.index()))
}

pub(super) fn vertex_mask(op: &str, mesh: &PolyMesh, vertices: &[VertexId]) -> Result<Vec<bool>> {
    mask(op, "vertex", mesh.vertex_count(), vertices.iter().map(|v| v.index()))
}

/// A finite number in the open interval (0, 1), or a message saying what was wrong.
pub(super) fn check_fraction(op: &str, t: f64) -> Result<()> {
    if t.is_finite() && t > 0.0 && t < 1.0 {
        Ok(())
    } else {
        Err(Error::Input(format!(
            "{op}: the position along the edge must be between 0 and 1 (not at an end), not {t:?}"
        )))
    }
}

/// The corners of the old faces: corner `c` of face `f` is `offsets[f] + k` for its `k`-th
/// vertex, and `of_halfedge[h]` is the corner where face halfedge `h` starts.
#[derive(Debug)]
pub(super) struct Corners {
    pub offsets: Vec<u32>,
    pub halfedge: Vec<HalfedgeId>,
    pub of_halfedge: Vec<u32>,
}

impl Corners {
    pub fn new(mesh: &PolyMesh) -> Self {
        let mut offsets = Vec::with_capacity(mesh.face_count() + 1);
        let mut halfedge = Vec::with_capacity(mesh.halfedge_count());
        let mut of_halfedge = vec![u32::MAX; mesh.halfedge_count()];
        offsets.push(0);
        for f in mesh.faces() {
            for h in mesh.face_halfedges(f) {
                of_halfedge[h.index()] = halfedge.len() as u32;
                halfedge.push(h);
            }
            offsets.push(halfedge.len() as u32);
        }
        Corners { offsets, halfedge, of_halfedge }
    }

    /// The corners of face `f`.
    pub fn of_face(&self, f: FaceId) -> std::ops::Range<usize> {
        self.offsets[f.index()] as usize..self.offsets[f.index() + 1] as usize
    }

    /// Groups the corners of the faces in `inside` into fans: corners at the same vertex whose
    /// faces are joined, around that vertex, through edges with a face of `inside` on both sides
    /// and for which `joins` is true. Returns a fan number per corner (dense, in corner order;
    /// `u32::MAX` for corners of other faces) and the number of fans.
    pub fn fans(&self, mesh: &PolyMesh, inside: &[bool], joins: impl Fn(EdgeId) -> bool) -> (Vec<u32>, usize) {
        let mut parent: Vec<u32> = (0..self.halfedge.len() as u32).collect();
        fn root(parent: &mut [u32], mut c: u32) -> u32 {
            while parent[c as usize] != c {
                parent[c as usize] = parent[parent[c as usize] as usize];
                c = parent[c as usize];
            }
            c
        }
        let union = |parent: &mut Vec<u32>, a: u32, b: u32| {
            let (ra, rb) = (root(parent, a), root(parent, b));
            if ra != rb {
                let (lo, hi) = (ra.min(rb), ra.max(rb));
                parent[hi as usize] = lo;
            }
        };
        let in_set = |f: FaceId| f.is_valid() && inside[f.index()];
        for e in mesh.edges() {
            let (h, t) = (e.halfedge(0), e.halfedge(1));
            if in_set(mesh.face(h)) && in_set(mesh.face(t)) && joins(e) {
                union(&mut parent, self.of_halfedge[h.index()], self.of_halfedge[mesh.next(t).index()]);
                union(&mut parent, self.of_halfedge[t.index()], self.of_halfedge[mesh.next(h).index()]);
            }
        }
        let mut fan = vec![u32::MAX; self.halfedge.len()];
        let mut count = 0usize;
        for f in mesh.faces().filter(|&f| inside[f.index()]) {
            for c in self.of_face(f) {
                let r = root(&mut parent, c as u32) as usize;
                if fan[r] == u32::MAX {
                    fan[r] = count as u32;
                    count += 1;
                }
                fan[c] = fan[r];
            }
        }
        (fan, count)
    }
}

/// Unit normal of a face, or `None` when it has no area.
pub(super) fn face_normal(mesh: &PolyMesh, f: FaceId) -> Option<DVec3> {
    let a = mesh.face_area_vector(f);
    let scale = mesh.face_halfedges(f).map(|h| mesh.edge_length(h.edge())).fold(0.0, f64::max);
    (a.length() > 1e-12 * scale * scale).then(|| a.normalize())
}
