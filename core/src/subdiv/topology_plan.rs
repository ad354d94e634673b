//! The plan of one split ([`super::SplitTopology::split`]): where every child element of a parent
//! face and halfedge goes, and the child halfedges derived from it, by index functions for every
//! rule and per parent halfedge for a split into quads.

use super::SplitRule;
use crate::DVec3;
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use rayon::prelude::*;
use std::mem::MaybeUninit;

/// The four halfedge arrays of a child mesh.
pub(super) struct ChildHalfedges {
    pub(super) to: Vec<VertexId>,
    pub(super) next: Vec<HalfedgeId>,
    pub(super) prev: Vec<HalfedgeId>,
    pub(super) face: Vec<FaceId>,
}

impl ChildHalfedges {
    /// `nh` child halfedges written by `fill`, which gets the four arrays cut at `ends`
    /// (increasing child halfedge indices, the last one `nh`) into consecutive pieces and must
    /// write every entry of every piece once, in order ([`HalfedgeSlices::push`]).
    ///
    /// The arrays are not cleared first: they are megabytes at a fine level (8 MB at level 3 of a
    /// 2,048-face cage), and clearing them took a tenth of the level's split. Panics, leaving
    /// nothing, if a piece is left short.
    #[allow(unsafe_code)]
    fn fill(
        nh: usize,
        ends: &[usize],
        fill: impl for<'a> FnOnce(Vec<HalfedgeSlices<'a>>) -> Vec<HalfedgeSlices<'a>>,
    ) -> Self {
        let mut out = ChildHalfedges {
            to: Vec::with_capacity(nh),
            next: Vec::with_capacity(nh),
            prev: Vec::with_capacity(nh),
            face: Vec::with_capacity(nh),
        };
        {
            // The pieces go to `fill` by value and come back: a piece held in a local while it is
            // filled keeps its cursor in a register (through a reference into a vector it was
            // reloaded after every write).
            let pieces = fill(HalfedgeSlices::cut(&mut out, nh, ends));
            assert!(
                pieces.iter().all(|p| p.written == p.to.len())
                    && pieces.iter().map(|p| p.to.len()).sum::<usize>() == nh,
                "a child halfedge was left unwritten by its split's fill"
            );
        }
        // SAFETY: each array has capacity for `nh` entries (`with_capacity`). `cut` splits the
        // first `nh` entries of each array's spare capacity into disjoint pieces that cover them
        // (it asserts the last end is `nh`). This module makes pieces nowhere else and changes a
        // piece's `written` only in `push`, so the pieces `fill` hands back are disjoint parts of
        // that range (a `&mut` each), and the assert above holds that they are `nh` entries in
        // all, so all of it. `push` writes entry `written` of each of its piece's four slices
        // (of one length) and only then counts it (a write past the piece's end panics at the
        // slice index), so a piece whose count is its length has every entry of its four slices
        // written, and the assert holds that for every piece. The first `nh` entries of each
        // array are therefore initialised; they are plain integers, with no drop.
        unsafe {
            out.to.set_len(nh);
            out.next.set_len(nh);
            out.prev.set_len(nh);
            out.face.set_len(nh);
        }
        out
    }
}

/// One rayon task's share of [`ChildHalfedges`] while it is filled: the entries `first..` of
/// each array, of which the first `written` are written.
struct HalfedgeSlices<'a> {
    first: u32,
    written: usize,
    to: &'a mut [MaybeUninit<VertexId>],
    next: &'a mut [MaybeUninit<HalfedgeId>],
    prev: &'a mut [MaybeUninit<HalfedgeId>],
    face: &'a mut [MaybeUninit<FaceId>],
}

impl<'a> HalfedgeSlices<'a> {
    /// The first `nh` entries of `all`'s spare capacity cut at `ends` (increasing child halfedge
    /// indices, the last one `nh`) into consecutive pieces.
    fn cut(all: &'a mut ChildHalfedges, nh: usize, ends: &[usize]) -> Vec<Self> {
        assert_eq!(ends.last().copied().unwrap_or(0), nh, "the pieces cover every child halfedge");
        let mut to = &mut all.to.spare_capacity_mut()[..nh];
        let mut next = &mut all.next.spare_capacity_mut()[..nh];
        let mut prev = &mut all.prev.spare_capacity_mut()[..nh];
        let mut face = &mut all.face.spare_capacity_mut()[..nh];
        let mut first = 0;
        let mut out = Vec::with_capacity(ends.len());
        for &end in ends {
            let k = end - first;
            let (a, rest_to) = std::mem::take(&mut to).split_at_mut(k);
            let (b, rest_next) = std::mem::take(&mut next).split_at_mut(k);
            let (c, rest_prev) = std::mem::take(&mut prev).split_at_mut(k);
            let (d, rest_face) = std::mem::take(&mut face).split_at_mut(k);
            out.push(HalfedgeSlices { first: first as u32, written: 0, to: a, next: b, prev: c, face: d });
            (to, next, prev, face) = (rest_to, rest_next, rest_prev, rest_face);
            first = end;
        }
        out
    }

    /// Writes child halfedge `x`, the piece's next entry.
    #[inline(always)]
    fn push(&mut self, x: u32, to: u32, next: u32, prev: u32, face: FaceId) {
        let i = self.written;
        debug_assert_eq!(x as usize, self.first as usize + i, "child halfedges are written in order");
        self.to[i].write(VertexId(to));
        self.next[i].write(HalfedgeId(next));
        self.prev[i].write(HalfedgeId(prev));
        self.face[i].write(face);
        self.written = i + 1;
    }
}

/// Child elements made per rayon task.
pub(super) const PARALLEL_CHUNK: usize = 4096;

/// What the child halfedges are derived from: the parent mesh and, per parent face and
/// halfedge, where its children go.
///
/// Child edges (the vertices' and faces' numbering is in the module docs): parent halfedge `h`
/// gives child edge `h`, the half of its edge at its origin (halfedge `2h` from the origin to the
/// edge point, `2h + 1` back), so the halves of parent edge `e` are child edges `2e` and `2e + 1`.
/// Every parent halfedge with a face then gives one edge inside that face, numbered after the
/// halves in halfedge order: from its edge point to the face point (a face split into quads) or
/// to the previous halfedge's edge point (a triangle split in four). As [`PolyMesh`] requires,
/// halfedge `2c` of child edge `c` runs from its lower vertex to its higher.
pub(super) struct Plan<'a> {
    pub(super) parent: &'a PolyMesh,
    /// `4 · parent edges`: the first child halfedge inside a face.
    pub(super) halves: u32,
    /// Per parent halfedge: its corner index in its face (from the face's first halfedge); empty
    /// on an [`indexed`](Plan::indexed) plan, where it follows from the index.
    corners: Vec<u32>,
    /// Per parent halfedge: the number of halfedges with a face before it; empty on an indexed
    /// plan, where every slot is its halfedge ([`Plan::slot`]).
    slots: Vec<u32>,
    /// The parent halfedges with a face, in order (the inverse of `slots`); empty with `slots`.
    interiors: Vec<u32>,
    /// Per parent face: its first child face (one entry more, the child face count); empty on an
    /// indexed plan, where it is `4f` ([`Plan::first_child`]).
    first_children: Vec<u32>,
    pub(super) face_point: Vec<VertexId>,
    pub(super) face_point_face: Vec<FaceId>,
    /// When the parent is itself a split into quads: that split's [`Plan::halves`].
    made_by_quads: Option<u32>,
    /// Whether the parent, made by quads and closed, is split into quads again: corners, slots,
    /// interior halfedges and first children are then functions of the indices and their arrays
    /// are empty (read them through [`Plan::slot`], [`Plan::first_child`], …).
    indexed: bool,
}

impl<'a> Plan<'a> {
    /// The plan of splitting `parent` by `rule`. `made_by_quads`: when `parent` is itself the
    /// child of a split into quads, that split's [`Plan::halves`]; the faces are then all quads
    /// and every halfedge's corner follows from its index ([`Plan::quad_child_corner`]), so
    /// nothing is walked to find them.
    pub(super) fn new(parent: &'a PolyMesh, rule: SplitRule, made_by_quads: Option<u32>) -> Self {
        let (nv, ne, nf) = (parent.vertex_count(), parent.edge_count(), parent.face_count());
        let np = parent.halfedge_count();
        // Closed below a split into quads: every halfedge has a face, and its slot is its index.
        let closed_quads = made_by_quads.is_some() && 4 * nf == np;
        // Split into quads again, closed: the quad fill reads corners, slots and first children
        // as functions of the indices ([`Plan::quad_halfedges`]), so their arrays are not made.
        let indexed = closed_quads && rule == SplitRule::Quads;
        let (first_children, face_point, face_point_face, corners) = match made_by_quads {
            Some(halves) => {
                // Every face a quad, split into 4 (quads, or quads around a face point for
                // `Mixed`; `Triangles` refuses quads before planning).
                let indices = |n: usize| (0..n as u32).into_par_iter().with_min_len(PARALLEL_CHUNK);
                let ((face_point, face_point_face), (first_children, corners)) = rayon::join(
                    || {
                        rayon::join(
                            || indices(nf).map(|f| VertexId((nv + ne) as u32 + f)).collect(),
                            || indices(nf).map(FaceId).collect(),
                        )
                    },
                    || {
                        if indexed {
                            return (Vec::new(), Vec::new());
                        }
                        let corner = |h: u32| {
                            if parent.face(HalfedgeId(h)).is_valid() {
                                Plan::quad_child_corner(halves, h)
                            } else {
                                u32::MAX
                            }
                        };
                        (indices(nf + 1).map(|f| 4 * f).collect(), indices(np).map(corner).collect())
                    },
                );
                (first_children, face_point, face_point_face, corners)
            }
            None => Plan::walked_faces(parent, rule),
        };
        let (slots, interiors) = match (closed_quads, indexed) {
            (_, true) => (Vec::new(), Vec::new()),
            (true, false) => {
                let identity = || (0..np as u32).into_par_iter().with_min_len(PARALLEL_CHUNK).collect::<Vec<u32>>();
                rayon::join(identity, identity)
            }
            (false, _) => Plan::slots(&corners),
        };
        Plan {
            parent,
            halves: 4 * ne as u32,
            corners,
            slots,
            interiors,
            first_children,
            face_point,
            face_point_face,
            made_by_quads,
            indexed,
        }
    }

    /// Parent halfedge `h`'s corner index in its face, from the face's first halfedge (`h` must
    /// have a face).
    #[cfg(test)]
    #[inline(always)]
    pub(super) fn corner(&self, h: u32) -> u32 {
        match self.made_by_quads.filter(|_| self.indexed) {
            Some(halves) => Plan::quad_child_corner(halves, h),
            None => self.corners[h as usize],
        }
    }

    /// The number of parent halfedges with a face before halfedge `h`.
    #[inline(always)]
    pub(super) fn slot(&self, h: u32) -> u32 {
        if self.indexed { h } else { self.slots[h as usize] }
    }

    /// The parent halfedge with a face in slot `s`.
    #[cfg(test)]
    #[inline(always)]
    pub(super) fn interior_halfedge(&self, s: u32) -> u32 {
        if self.indexed { s } else { self.interiors[s as usize] }
    }

    /// The number of parent halfedges with a face.
    pub(super) fn interior_count(&self) -> usize {
        if self.indexed { self.parent.halfedge_count() } else { self.interiors.len() }
    }

    /// Parent face `f`'s first child face (`f` may be the face count: then the child face count).
    #[inline(always)]
    pub(super) fn first_child(&self, f: usize) -> u32 {
        if self.indexed { 4 * f as u32 } else { self.first_children[f] }
    }

    /// Per parent halfedge, the number of halfedges with a face before it (its slot), and the
    /// halfedges with a face in order, from the corners (`u32::MAX` on the boundary). By chunks:
    /// each chunk's halfedges with a face counted in parallel, the counts summed, then each chunk
    /// numbered from its sum.
    fn slots(corner: &[u32]) -> (Vec<u32>, Vec<u32>) {
        let counts: Vec<u32> =
            corner.par_chunks(PARALLEL_CHUNK).map(|c| c.iter().filter(|&&k| k != u32::MAX).count() as u32).collect();
        let firsts: Vec<u32> = counts
            .iter()
            .scan(0, |sum, &c| {
                let first = *sum;
                *sum += c;
                Some(first)
            })
            .collect();
        let with_faces = counts.iter().sum::<u32>() as usize;
        let mut slot = vec![0u32; corner.len()];
        let mut interior = vec![0u32; with_faces];
        let mut pieces = Vec::with_capacity(counts.len());
        let mut rest = &mut interior[..];
        for &c in &counts {
            let (piece, tail) = std::mem::take(&mut rest).split_at_mut(c as usize);
            pieces.push(piece);
            rest = tail;
        }
        slot.par_chunks_mut(PARALLEL_CHUNK)
            .zip(corner.par_chunks(PARALLEL_CHUNK))
            .zip(pieces)
            .zip(firsts)
            .enumerate()
            .for_each(|(k, (((slot, corner), interior), first))| {
                let mut next = first;
                let mut inner = interior.iter_mut();
                for (i, (s, &c)) in slot.iter_mut().zip(corner).enumerate() {
                    *s = next;
                    if c != u32::MAX {
                        *inner.next().expect("counted") = (k * PARALLEL_CHUNK + i) as u32;
                        next += 1;
                    }
                }
            });
        (slot, interior)
    }

    /// A child of a split into quads, halfedge `h` of its face: the quad at corner `k` of a parent
    /// face is `2k' → H + 2s → H + 2s' + 1 → odd half` ([`Plan::quad_halfedges`], with the
    /// parent's `H` = `halves`), and its first halfedge is the even half.
    #[inline]
    pub(super) fn quad_child_corner(halves: u32, h: u32) -> u32 {
        match (h < halves, h & 1) {
            (true, 0) => 0,
            (false, 0) => 1,
            (false, _) => 2,
            (true, _) => 3,
        }
    }

    /// The first child face, face point and corner of every face and halfedge of any `parent`,
    /// by walking its faces.
    #[allow(clippy::type_complexity)]
    fn walked_faces(parent: &PolyMesh, rule: SplitRule) -> (Vec<u32>, Vec<VertexId>, Vec<FaceId>, Vec<u32>) {
        let (nv, ne, nf) = (parent.vertex_count(), parent.edge_count(), parent.face_count());
        let valence: Vec<u32> = (0..nf as u32)
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(|f| parent.face_valence(FaceId(f)) as u32)
            .collect();
        let mut first_child = Vec::with_capacity(nf + 1);
        let mut face_point = vec![VertexId::INVALID; nf];
        let mut face_point_face = Vec::new();
        let mut children = 0u32;
        for (f, &n) in valence.iter().enumerate() {
            first_child.push(children);
            let quads = match rule {
                SplitRule::Quads => true,
                SplitRule::Triangles => false,
                SplitRule::Mixed => n != 3,
            };
            if quads {
                face_point[f] = VertexId((nv + ne + face_point_face.len()) as u32);
                face_point_face.push(FaceId(f as u32));
                children += n;
            } else {
                children += 4;
            }
        }
        first_child.push(children);
        // A halfedge's corner: the steps back round its face to the face's first halfedge.
        let corner: Vec<u32> = (0..parent.halfedge_count() as u32)
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(|h| {
                let f = parent.face(HalfedgeId(h));
                if !f.is_valid() {
                    return u32::MAX;
                }
                let (first, mut at, mut k) = (parent.face_halfedge(f), HalfedgeId(h), 0);
                while at != first {
                    at = parent.prev(at);
                    k += 1;
                }
                k
            })
            .collect();
        (first_child, face_point, face_point_face, corner)
    }

    pub(super) fn vertex_count(&self) -> usize {
        self.parent.vertex_count() + self.parent.edge_count() + self.face_point_face.len()
    }

    /// The child halfedges of any rule, each a function of its index alone.
    pub(super) fn halfedges(&self, nh: usize) -> ChildHalfedges {
        let ends: Vec<usize> = (1..=nh.div_ceil(PARALLEL_CHUNK)).map(|k| (k * PARALLEL_CHUNK).min(nh)).collect();
        ChildHalfedges::fill(nh, &ends, |pieces| {
            pieces
                .into_par_iter()
                .map(|mut s| {
                    for x in s.first..s.first + s.to.len() as u32 {
                        s.push(x, self.to(x).0, self.next(x), self.prev(x), self.face(x));
                    }
                    s
                })
                .collect()
        })
    }

    /// The child halfedges of a split into quads, filled per parent halfedge `h`: the two halves
    /// `2h`, `2h + 1` of its edge and the two halfedges `H + 2 slot(h)`, `+ 1` of the edge from its
    /// edge point to its face point (`H` = [`Plan::halves`]). Each child halfedge is a function of
    /// the few parent elements round `h`, read once for all four rather than once per child
    /// halfedge and array as [`Plan::to`], [`Plan::next`], … do (the same values: the tests
    /// compare both). The quad at corner `h` of face `f` (prev `p`) is
    /// `2h → H + 2 slot(h) → H + 2 slot(p) + 1 → 2 (p ^ 1) + 1`.
    pub(super) fn quad_halfedges(&self, nh: usize) -> ChildHalfedges {
        let parent = self.parent;
        let (halves, nv) = (self.halves, parent.vertex_count() as u32);
        let np = parent.halfedge_count();
        // Tasks by ranges of parent halfedges; each writes one piece of the halves and one of
        // the edges inside faces.
        let starts: Vec<usize> = (0..np.div_ceil(PARALLEL_CHUNK)).map(|k| k * PARALLEL_CHUNK).collect();
        let interior_at = |h: usize| if h == np { self.interior_count() } else { self.slot(h as u32) as usize };
        let half_ends: Vec<usize> = starts.iter().map(|&h| 2 * (h + PARALLEL_CHUNK).min(np)).collect();
        let inner_ends: Vec<usize> =
            starts.iter().map(|&h| halves as usize + 2 * interior_at((h + PARALLEL_CHUNK).min(np))).collect();
        let ends: Vec<usize> = half_ends.into_iter().chain(inner_ends).collect();
        ChildHalfedges::fill(nh, &ends, |mut half_pieces| {
            let inner_pieces = half_pieces.split_off(starts.len());
            let pieces = half_pieces.into_par_iter().zip(inner_pieces).zip(starts);
            let filled: Vec<(HalfedgeSlices, HalfedgeSlices)> = match self.made_by_quads.filter(|_| self.indexed) {
                // Below a split into quads of a closed cage, slots, first child faces, corners and
                // face points are functions of the indices (the same values the arrays hold).
                Some(above) => {
                    let first_face_point = (nv as usize + parent.edge_count()) as u32;
                    pieces
                        .map(|((mut half, mut inner), h0)| {
                            self.fill_quads(
                                &mut half,
                                &mut inner,
                                h0 as u32..(h0 + PARALLEL_CHUNK).min(np) as u32,
                                |h| halves + 2 * h,
                                |f, h| FaceId(4 * f.0 + Plan::quad_child_corner(above, h)),
                                |f| first_face_point + f.0,
                            );
                            (half, inner)
                        })
                        .collect()
                }
                None => pieces
                    .map(|((mut half, mut inner), h0)| {
                        self.fill_quads(
                            &mut half,
                            &mut inner,
                            h0 as u32..(h0 + PARALLEL_CHUNK).min(np) as u32,
                            |h| halves + 2 * self.slot(h),
                            |f, h| self.corner_face(f, h),
                            |f| self.face_point[f.index()].0,
                        );
                        (half, inner)
                    })
                    .collect(),
            };
            let (mut half, inner): (Vec<_>, Vec<_>) = filled.into_iter().unzip();
            half.extend(inner);
            half
        })
    }

    /// [`Plan::quad_halfedges`] of parent halfedges `range`, with the plan's slots (`inside`),
    /// child faces (`corner_face`) and face points given as functions.
    #[inline(always)]
    fn fill_quads(
        &self,
        half: &mut HalfedgeSlices,
        inner: &mut HalfedgeSlices,
        range: std::ops::Range<u32>,
        inside: impl Fn(u32) -> u32,
        corner_face: impl Fn(FaceId, u32) -> FaceId,
        face_point: impl Fn(FaceId) -> u32,
    ) {
        let parent = self.parent;
        let nv = parent.vertex_count() as u32;
        for h in range {
            let id = HalfedgeId(h);
            let (t, m) = (h ^ 1, nv + (h >> 1));
            let (f, ft) = (parent.face(id), parent.face(HalfedgeId(t)));
            let (next, prev) = (parent.next(id).0, parent.prev(id).0);
            let twin_next = parent.next(HalfedgeId(t)).0;
            // 2h: from h's origin to its edge point.
            let (after, face) =
                if f.is_valid() { (inside(h), corner_face(f, h)) } else { (2 * t + 1, FaceId::INVALID) };
            half.push(2 * h, m, after, 2 * (prev ^ 1) + 1, face);
            // 2h + 1: back to the origin, in the twin's face at the corner of the twin's next.
            let (before, face) =
                if ft.is_valid() { (inside(t) + 1, corner_face(ft, twin_next)) } else { (2 * t, FaceId::INVALID) };
            half.push(2 * h + 1, parent.to_vertex(HalfedgeId(t)).0, 2 * twin_next, before, face);
            if f.is_valid() {
                let b = inside(h);
                inner.push(b, face_point(f), inside(prev) + 1, 2 * h, corner_face(f, h));
                inner.push(b + 1, m, 2 * t + 1, inside(next), corner_face(f, next));
            }
        }
    }

    /// The edge point on parent halfedge `h`'s edge.
    #[inline(always)]
    pub(super) fn edge_point(&self, h: u32) -> u32 {
        self.parent.vertex_count() as u32 + (h >> 1)
    }

    #[inline(always)]
    pub(super) fn next_of(&self, h: u32) -> u32 {
        self.parent.next(HalfedgeId(h)).0
    }

    #[inline(always)]
    pub(super) fn prev_of(&self, h: u32) -> u32 {
        self.parent.prev(HalfedgeId(h)).0
    }

    /// The parent face of halfedge `h` and its face point (invalid for a triangle split in four);
    /// `None` on the boundary.
    #[inline(always)]
    pub(super) fn face_of(&self, h: u32) -> Option<(FaceId, VertexId)> {
        let f = self.parent.face(HalfedgeId(h));
        f.is_valid().then(|| (f, self.face_point[f.index()]))
    }

    /// The child face at the corner where parent halfedge `h` of face `f` starts.
    #[inline(always)]
    pub(super) fn corner_face(&self, f: FaceId, h: u32) -> FaceId {
        FaceId(self.first_children[f.index()] + self.corners[h as usize])
    }

    /// The child halfedge from vertex `x` to vertex `y` on the interior edge of parent halfedge `h`.
    /// This and the index functions below read the plan's arrays: not on an indexed plan.
    #[inline(always)]
    pub(super) fn inside(&self, h: u32, x: u32, y: u32) -> u32 {
        self.halves + 2 * self.slots[h as usize] + u32::from(x > y)
    }

    /// For child halfedge `x` inside a face: the parent halfedge it comes from, its face, the face
    /// point (invalid for a triangle), and whether `x` runs from `h`'s edge point to the previous
    /// edge point (a triangle's corner-triangle side).
    #[inline(always)]
    pub(super) fn interior(&self, x: u32) -> (u32, FaceId, VertexId, bool) {
        let h = self.interiors[((x - self.halves) >> 1) as usize];
        let (f, point) = self.face_of(h).expect("interior edges lie in faces");
        let (mh, mp) = (self.edge_point(h), self.edge_point(self.prev_of(h)));
        (h, f, point, !point.is_valid() && x == self.inside(h, mh, mp))
    }

    #[inline(always)]
    pub(super) fn to(&self, x: u32) -> VertexId {
        if x < self.halves {
            let h = x >> 1;
            return if x & 1 == 0 { VertexId(self.edge_point(h)) } else { self.parent.from_vertex(HalfedgeId(h)) };
        }
        let (h, _, point, back) = self.interior(x);
        match (point.is_valid(), x & 1, back) {
            (true, 0, _) => point,
            (false, _, true) => VertexId(self.edge_point(self.prev_of(h))),
            _ => VertexId(self.edge_point(h)),
        }
    }

    #[inline(always)]
    pub(super) fn face(&self, x: u32) -> FaceId {
        if x < self.halves {
            let h = x >> 1;
            // The half back to the origin lies in the twin's face, at the corner of its next.
            let (side, corner) = if x & 1 == 0 { (h, h) } else { (h ^ 1, self.next_of(h ^ 1)) };
            return self.face_of(side).map_or(FaceId::INVALID, |(f, _)| self.corner_face(f, corner));
        }
        let (h, f, point, back) = self.interior(x);
        if point.is_valid() {
            self.corner_face(f, if x & 1 == 0 { h } else { self.next_of(h) })
        } else if back {
            self.corner_face(f, h)
        } else {
            FaceId(self.first_children[f.index()] + 3)
        }
    }

    #[inline(always)]
    pub(super) fn next(&self, x: u32) -> u32 {
        if x < self.halves {
            let h = x >> 1;
            if x & 1 == 1 {
                return 2 * self.next_of(h ^ 1);
            }
            let mh = self.edge_point(h);
            return match self.face_of(h) {
                None => 2 * (h ^ 1) + 1,
                Some((_, point)) if point.is_valid() => self.inside(h, mh, point.0),
                Some(_) => self.inside(h, mh, self.edge_point(self.prev_of(h))),
            };
        }
        let (h, _, point, back) = self.interior(x);
        let p = self.prev_of(h);
        match (point.is_valid(), x & 1, back) {
            (true, 0, _) => self.inside(p, point.0, self.edge_point(p)),
            (true, _, _) => 2 * (h ^ 1) + 1,
            (false, _, true) => 2 * (p ^ 1) + 1,
            (false, _, false) => {
                let n = self.next_of(h);
                self.inside(n, self.edge_point(h), self.edge_point(n))
            }
        }
    }

    #[inline(always)]
    pub(super) fn prev(&self, x: u32) -> u32 {
        if x < self.halves {
            let h = x >> 1;
            if x & 1 == 0 {
                return 2 * (self.prev_of(h) ^ 1) + 1;
            }
            let t = h ^ 1;
            let mt = self.edge_point(t);
            return match self.face_of(t) {
                None => 2 * t,
                Some((_, point)) if point.is_valid() => self.inside(t, point.0, mt),
                Some(_) => {
                    let n = self.next_of(t);
                    self.inside(n, self.edge_point(n), mt)
                }
            };
        }
        let (h, _, point, back) = self.interior(x);
        match (point.is_valid(), x & 1, back) {
            (true, 0, _) | (false, _, true) => 2 * h,
            (true, _, _) => {
                let n = self.next_of(h);
                self.inside(n, self.edge_point(n), point.0)
            }
            (false, _, false) => {
                let p = self.prev_of(h);
                self.inside(p, self.edge_point(self.prev_of(p)), self.edge_point(p))
            }
        }
    }

    pub(super) fn vertex_halfedge(&self, v: u32) -> HalfedgeId {
        let (nv, ne) = (self.parent.vertex_count() as u32, self.parent.edge_count() as u32);
        if v < nv {
            let h = self.parent.vertex_halfedge(VertexId(v));
            return if h.is_valid() { HalfedgeId(2 * h.0) } else { HalfedgeId::INVALID };
        }
        if v < nv + ne {
            // A boundary edge point's outgoing halfedge must be its boundary one.
            let e = v - nv;
            let boundary_first = self.parent.is_boundary_halfedge(HalfedgeId(2 * e));
            return HalfedgeId(if boundary_first { 4 * e + 3 } else { 4 * e + 1 });
        }
        let f = self.face_point_face[(v - nv - ne) as usize];
        let h = self.parent.face_halfedge(f).0;
        HalfedgeId(self.halves + 2 * self.slot(h) + u32::from(v > self.edge_point(h)))
    }

    /// Per child face, its first halfedge and its parent face, filled in parallel by ranges of
    /// parent faces (the children of a range of parent faces are a range of child faces).
    pub(super) fn face_halfedges_and_parents(&self) -> (Vec<HalfedgeId>, Vec<FaceId>) {
        let children = self.first_child(self.parent.face_count()) as usize;
        let mut halfedges = vec![HalfedgeId::INVALID; children];
        let mut parents = vec![FaceId::INVALID; children];
        let nf = self.parent.face_count();
        let mut pieces = Vec::with_capacity(nf.div_ceil(PARALLEL_CHUNK));
        let (mut rest_h, mut rest_p) = (&mut halfedges[..], &mut parents[..]);
        for f0 in (0..nf).step_by(PARALLEL_CHUNK) {
            let f1 = (f0 + PARALLEL_CHUNK).min(nf);
            let k = (self.first_child(f1) - self.first_child(f0)) as usize;
            let (h, tail_h) = std::mem::take(&mut rest_h).split_at_mut(k);
            let (p, tail_p) = std::mem::take(&mut rest_p).split_at_mut(k);
            pieces.push((f0..f1, h, p));
            (rest_h, rest_p) = (tail_h, tail_p);
        }
        pieces.into_par_iter().for_each(|(faces, halfedges, parents)| {
            let mut at = 0;
            for f in faces {
                let f = FaceId(f as u32);
                let first = self.parent.face_halfedge(f).0;
                if self.face_point[f.index()].is_valid() {
                    for h in self.parent.face_halfedges(f) {
                        halfedges[at] = HalfedgeId(2 * h.0);
                        parents[at] = f;
                        at += 1;
                    }
                } else {
                    let (h1, h2) = (self.next_of(first), self.prev_of(first));
                    let [m0, m1, m2] = [first, h1, h2].map(|h| self.edge_point(h));
                    let corners = [2 * first, 2 * (first ^ 1) + 1, self.inside(h2, m2, m1), self.inside(h1, m0, m1)];
                    for c in corners {
                        halfedges[at] = HalfedgeId(c);
                        parents[at] = f;
                        at += 1;
                    }
                }
            }
        });
        (halfedges, parents)
    }

    /// The linear prolongation: parent vertices kept, edge points at midpoints, face points at
    /// centroids.
    pub(super) fn positions(&self) -> Vec<DVec3> {
        let parent = self.parent;
        let mut out = Vec::with_capacity(self.vertex_count());
        out.extend_from_slice(parent.positions());
        out.par_extend((0..parent.edge_count() as u32).into_par_iter().with_min_len(PARALLEL_CHUNK).map(|e| {
            let (a, b) = parent.edge_vertices(EdgeId(e));
            0.5 * (parent.position(a) + parent.position(b))
        }));
        out.par_extend(self.face_point_face.par_iter().with_min_len(PARALLEL_CHUNK).map(|&f| {
            let (sum, n) = parent.face_vertices(f).fold((DVec3::ZERO, 0), |(s, n), v| (s + parent.position(v), n + 1));
            sum / n as f64
        }));
        out
    }
}
