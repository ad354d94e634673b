//! The lineage of the mirrored whole ([`MirroredWhole`](super::symmetry::MirroredWhole)): after a
//! modelling edit of the half, where each element of the new whole came from in the whole made
//! before, so the NUSD solver of the whole warm-starts after a topology edit with the mirror on as
//! it does with it off (issue 22; `docs/nusd.md`, "Warm start after a topology edit").
//!
//! A whole is a half and its mirror image ([`apply_mirror`](crate::mesh::edit::apply_mirror)):
//! each of its elements is an element of the half on one *side*, the half's own or the image, and
//! an element on the seam (a vertex or an edge in the plane) is both. The new whole's lineage is
//! three maps composed: a new whole's element → the new half's element and its side (the new
//! whole's own provenance), → the old half's element (the half's edit), → the old whole's element
//! on the same side ([`Sides`] of the old whole). So a vertex the half's edit kept is kept on both
//! sides, and its image is the image of the same old vertex; what the edit made (a vertex on an
//! edge, a swept edge, a filled face) is made on both sides, from the old whole's element on that
//! side. A vertex placed on an old edge keeps its place along it: its fraction is turned round
//! where the whole's edge runs the other way from the half's.
//!
//! The seam is where the two sides meet. An element the half's edit brought onto it (a vertex
//! dragged across the plane stops on it, and its edge to the seam joins the seam) was two elements
//! of the old whole, itself and its image, and is one now: it is [`Merged`](VertexOrigin::Merged)
//! from its own old self. An element that left the seam is one old element on both sides, as a
//! deletion's pinched vertex is (both pieces [`Same`](VertexOrigin::Same)).
//!
//! When the half kept its connectivity but the whole did not (a vertex dragged onto the plane, or
//! another plane), the half's edit is the identity. The solver checks every survivor's position,
//! so a vertex the lineage calls the same but that moved starts afresh.

use crate::mesh::edit::{EdgeOrigin, Edited, FaceOrigin, Lineage, Provenance, VertexOrigin};
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::{Error, Result};

/// Side 0: the half itself; side 1: its mirror image.
type PerSide = [Vec<u32>; 2];

/// Where each element of a half lies in a whole made of it: per side, the whole's element (an
/// element on the seam is the same element on both sides).
#[derive(Clone, Debug)]
pub(crate) struct Sides {
    vertices: PerSide,
    edges: PerSide,
    faces: PerSide,
    /// Per side and half edge: the whole's edge runs from the image of the half edge's second end.
    flipped: [Vec<bool>; 2],
    /// The whole's topology generation and vertex, edge and face counts.
    whole_topology: u64,
    whole_counts: (usize, usize, usize),
}

impl Sides {
    /// The sides of `half` in `whole`, the result of mirroring it.
    pub(crate) fn new(half: &PolyMesh, whole: &Edited) -> Result<Sides> {
        let p = &whole.provenance;
        let counts = (half.vertex_count(), half.edge_count(), half.face_count());
        if p.old_counts != counts {
            return Err(Error::Topology(format!(
                "mirror: the whole was made from a half of {:?} vertices, edges and faces, not {counts:?}",
                p.old_counts
            )));
        }
        let vertices = sides_of(
            "vertex",
            counts.0,
            p.vertices.iter().map(|o| match *o {
                VertexOrigin::Same(v) => Some((0, v.0)),
                VertexOrigin::MirrorOf(v) => Some((1, v.0)),
                _ => None,
            }),
        )?;
        let edges = sides_of(
            "edge",
            counts.1,
            p.edges.iter().map(|o| match *o {
                EdgeOrigin::Same(e) => Some((0, e.0)),
                EdgeOrigin::MirrorOf(e) => Some((1, e.0)),
                _ => None,
            }),
        )?;
        let faces = sides_of(
            "face",
            counts.2,
            p.faces.iter().map(|o| match *o {
                FaceOrigin::Same(f) => Some((0, f.0)),
                FaceOrigin::MirrorOf(f) => Some((1, f.0)),
                _ => None,
            }),
        )?;
        let flipped = [0, 1].map(|s| {
            half.edges()
                .map(|e| {
                    let first = half.edge_vertices(e).0;
                    let image = VertexId(vertices[s][first.index()]);
                    whole.mesh.edge_vertices(EdgeId(edges[s][e.index()])).0 != image
                })
                .collect()
        });
        let m = &whole.mesh;
        Ok(Sides {
            vertices,
            edges,
            faces,
            flipped,
            whole_topology: m.topology_generation(),
            whole_counts: (m.vertex_count(), m.edge_count(), m.face_count()),
        })
    }

    fn vertex(&self, side: usize, v: VertexId) -> Result<VertexId> {
        lookup(&self.vertices[side], v.0, "vertex").map(VertexId)
    }

    fn edge(&self, side: usize, e: EdgeId) -> Result<EdgeId> {
        lookup(&self.edges[side], e.0, "edge").map(EdgeId)
    }

    fn face(&self, side: usize, f: FaceId) -> Result<FaceId> {
        lookup(&self.faces[side], f.0, "face").map(FaceId)
    }

    /// A new half vertex's origin in the old half, as an origin in this (old) whole on `side`.
    fn vertex_origin(&self, side: usize, origin: VertexOrigin) -> Result<VertexOrigin> {
        use VertexOrigin::*;
        Ok(match origin {
            Same(v) => Same(self.vertex(side, v)?),
            CopyOf(v) => CopyOf(self.vertex(side, v)?),
            MirrorOf(v) => MirrorOf(self.vertex(side, v)?),
            Merged(v) => Merged(self.vertex(side, v)?),
            OnEdge { edge, t } => {
                let flipped = self.flipped[side][edge.index()];
                OnEdge { edge: self.edge(side, edge)?, t: if flipped { 1.0 - t } else { t } }
            }
        })
    }

    fn edge_origin(&self, side: usize, origin: EdgeOrigin) -> Result<EdgeOrigin> {
        use EdgeOrigin::*;
        Ok(match origin {
            Same(e) => Same(self.edge(side, e)?),
            CopyOf(e) => CopyOf(self.edge(side, e)?),
            MirrorOf(e) => MirrorOf(self.edge(side, e)?),
            SplitFrom(e) => SplitFrom(self.edge(side, e)?),
            Merged(e) => Merged(self.edge(side, e)?),
            SweptFrom(v) => SweptFrom(self.vertex(side, v)?),
            InFace(f) => InFace(self.face(side, f)?),
            New => New,
        })
    }

    fn face_origin(&self, side: usize, origin: FaceOrigin) -> Result<FaceOrigin> {
        use FaceOrigin::*;
        Ok(match origin {
            Same(f) => Same(self.face(side, f)?),
            MirrorOf(f) => MirrorOf(self.face(side, f)?),
            SplitFrom(f) => SplitFrom(self.face(side, f)?),
            Merged(f) => Merged(self.face(side, f)?),
            SweptFrom(e) => SweptFrom(self.edge(side, e)?),
            New => New,
        })
    }

    /// Whether half vertex `v` is its own image (on the seam).
    fn vertex_on_seam(&self, v: usize) -> bool {
        self.vertices[0][v] == self.vertices[1][v]
    }

    /// Whether half edge `e` is its own image (on the seam).
    fn edge_on_seam(&self, e: usize) -> bool {
        self.edges[0][e] == self.edges[1][e]
    }

    fn half_counts(&self) -> (usize, usize, usize) {
        (self.vertices[0].len(), self.edges[0].len(), self.faces[0].len())
    }
}

/// Per side, the whole's element of each half element, from the whole's origins (`Some((side,
/// half element))` for each whole element); an element with no image (on the seam) is its own.
fn sides_of(what: &str, count: usize, origins: impl Iterator<Item = Option<(usize, u32)>>) -> Result<PerSide> {
    let mut sides = [vec![u32::MAX; count], vec![u32::MAX; count]];
    for (i, origin) in origins.enumerate() {
        let Some((side, h)) = origin else {
            return Err(Error::Topology(format!("mirror: whole {what} {i} is neither a half's {what} nor its image")));
        };
        *sides[side].get_mut(h as usize).ok_or_else(|| {
            Error::Topology(format!("mirror: whole {what} {i} names half {what} {h}, but the half has {count}"))
        })? = i as u32;
    }
    let [own, image] = &mut sides;
    for (h, (o, m)) in own.iter().zip(image.iter_mut()).enumerate() {
        if *o == u32::MAX {
            return Err(Error::Topology(format!("mirror: half {what} {h} is missing from the whole")));
        }
        if *m == u32::MAX {
            *m = *o;
        }
    }
    Ok(sides)
}

fn lookup(map: &[u32], i: u32, what: &str) -> Result<u32> {
    map.get(i as usize).copied().ok_or_else(|| {
        Error::Topology(format!("mirror: the half's edit names old {what} {i}, but the half had {}", map.len()))
    })
}

/// The provenance of an edit that changed nothing of `half`: every element is itself.
pub(crate) fn unchanged(half: &PolyMesh) -> Provenance {
    Provenance {
        vertices: half.vertices().map(VertexOrigin::Same).collect(),
        edges: half.edges().map(EdgeOrigin::Same).collect(),
        faces: half.faces().map(FaceOrigin::Same).collect(),
        old_counts: (half.vertex_count(), half.edge_count(), half.face_count()),
    }
}

/// The lineage of the whole `new` (made by mirroring the edited half; `new_sides` its sides) from
/// the whole `old` was made of (the half before `half_edit`): see the module docs. `None` when
/// `half_edit` did not start from the half `old` was made of (its counts differ).
pub(crate) fn whole_lineage(
    old: &Sides,
    half_edit: &Provenance,
    new: &Edited,
    new_sides: &Sides,
) -> Result<Option<Lineage>> {
    if half_edit.old_counts != old.half_counts() {
        return Ok(None);
    }
    let origin = |what: &str, list_len: usize, i: usize| {
        Error::Topology(format!("mirror: the whole names half {what} {i}, but the half's edit made {list_len}"))
    };
    let p = &new.provenance;
    let vertices = p
        .vertices
        .iter()
        .map(|o| {
            let (side, h) = match *o {
                VertexOrigin::Same(h) => (0, h.index()),
                VertexOrigin::MirrorOf(h) => (1, h.index()),
                other => return Err(Error::Topology(format!("mirror: unexpected vertex origin {other:?}"))),
            };
            let from = *half_edit.vertices.get(h).ok_or_else(|| origin("vertex", half_edit.vertices.len(), h))?;
            Ok(match (old.vertex_origin(side, from)?, from) {
                (VertexOrigin::Same(w), VertexOrigin::Same(x))
                    if new_sides.vertex_on_seam(h) && !old.vertex_on_seam(x.index()) =>
                {
                    VertexOrigin::Merged(w)
                }
                (mapped, _) => mapped,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let edges = p
        .edges
        .iter()
        .map(|o| {
            let (side, h) = match *o {
                EdgeOrigin::Same(h) => (0, h.index()),
                EdgeOrigin::MirrorOf(h) => (1, h.index()),
                other => return Err(Error::Topology(format!("mirror: unexpected edge origin {other:?}"))),
            };
            let from = *half_edit.edges.get(h).ok_or_else(|| origin("edge", half_edit.edges.len(), h))?;
            Ok(match (old.edge_origin(side, from)?, from) {
                (EdgeOrigin::Same(w), EdgeOrigin::Same(x))
                    if new_sides.edge_on_seam(h) && !old.edge_on_seam(x.index()) =>
                {
                    EdgeOrigin::Merged(w)
                }
                (mapped, _) => mapped,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let faces = p
        .faces
        .iter()
        .map(|o| {
            let (side, h) = match *o {
                FaceOrigin::Same(h) => (0, h.index()),
                FaceOrigin::MirrorOf(h) => (1, h.index()),
                other => return Err(Error::Topology(format!("mirror: unexpected face origin {other:?}"))),
            };
            let from = *half_edit.faces.get(h).ok_or_else(|| origin("face", half_edit.faces.len(), h))?;
            old.face_origin(side, from)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Some(Lineage {
        from: old.whole_topology,
        to: new.mesh.topology_generation(),
        provenance: Provenance { vertices, edges, faces, old_counts: old.whole_counts },
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;
    use crate::document::modelling::MeshEdit;
    use crate::document::symmetry::MirroredWhole;
    use crate::document::{Document, Edit};
    use crate::mesh::edit::{Axis, MirrorPlane, delete_vertices};
    use crate::mesh::primitives::torus;

    /// The half x ≥ 0 of a 16 × 6 torus about the z axis, mirrored across x = 0.
    fn half_torus() -> Document {
        let cage = torus(16, 6, 2.0, 0.7).unwrap();
        let other_side: Vec<VertexId> = cage.vertices().filter(|&v| cage.position(v).x < -1e-9).collect();
        let mut doc = Document::new(delete_vertices(&cage, &other_side).unwrap().mesh);
        doc.apply(Edit::SetMirror(Some(MirrorPlane::new(Axis::X, 0.0)))).unwrap();
        doc
    }

    fn nearest(doc: &Document, p: DVec3) -> VertexId {
        let d = |v: VertexId| doc.cage.position(v).distance(p);
        doc.cage.vertices().min_by(|&a, &b| d(a).total_cmp(&d(b))).unwrap()
    }

    /// What [`check`] counted.
    #[derive(Debug, Default, PartialEq)]
    struct Tally {
        /// Kept vertices where they were, on each side of the plane (x > 0, x < 0).
        kept: [usize; 2],
        /// Kept vertices that moved.
        moved: usize,
        /// Vertices placed on an edge, in the plane.
        cut_on_seam: usize,
        /// Merged vertices and edges.
        merged: (usize, usize),
    }

    /// What the origins say, checked on the two wholes alone: a kept vertex is where it was (or
    /// counted as moved), a vertex on an old edge at its fraction along it, a kept or split edge
    /// joins (the old selves of) the old edge's ends, a kept or split face has its kept corners and
    /// cut edges on the old face.
    fn check(old: &PolyMesh, new: &PolyMesh, lineage: &Lineage) -> Tally {
        let p = &lineage.provenance;
        assert_eq!((lineage.from, lineage.to), (old.topology_generation(), new.topology_generation()));
        assert_eq!(p.old_counts, (old.vertex_count(), old.edge_count(), old.face_count()));
        assert_eq!(
            (p.vertices.len(), p.edges.len(), p.faces.len()),
            (new.vertex_count(), new.edge_count(), new.face_count())
        );
        let mut tally = Tally::default();
        for (v, origin) in p.vertices.iter().enumerate() {
            let q = new.position(VertexId(v as u32));
            match *origin {
                VertexOrigin::Same(o) if old.position(o) == q => tally.kept[usize::from(q.x < 0.0)] += 1,
                VertexOrigin::Same(_) => tally.moved += 1,
                VertexOrigin::Merged(_) => tally.merged.0 += 1,
                VertexOrigin::OnEdge { edge, t } => {
                    let (a, b) = old.edge_vertices(edge);
                    let (a, b) = (old.position(a), old.position(b));
                    assert!(q.distance(a.lerp(b, t)) < 1e-12, "vertex {v}: {q} is not {t} along {a} → {b}");
                    tally.cut_on_seam += usize::from(q.x == 0.0);
                }
                _ => {}
            }
        }
        // The old vertex a new one is, when the edit kept it.
        let same = |v: VertexId| match p.vertices[v.index()] {
            VertexOrigin::Same(o) => Some(o),
            _ => None,
        };
        let on_edge = |v: VertexId| match p.vertices[v.index()] {
            VertexOrigin::OnEdge { edge, .. } => Some(edge),
            _ => None,
        };
        for e in new.edges() {
            let (a, b) = new.edge_vertices(e);
            match p.edges[e.index()] {
                EdgeOrigin::Same(o) => {
                    let (x, y) = old.edge_vertices(o);
                    for end in [a, b] {
                        match p.vertices[end.index()] {
                            VertexOrigin::Same(w) => assert!(w == x || w == y, "edge {e:?}: {end:?} is old {w:?}"),
                            // One of the old vertices merged into it is named.
                            VertexOrigin::Merged(_) => {}
                            other => panic!("edge {e:?} is kept, but its end {end:?} is {other:?}"),
                        }
                    }
                }
                EdgeOrigin::Merged(_) => tally.merged.1 += 1,
                EdgeOrigin::SplitFrom(o) => {
                    let (cut, end) = if on_edge(a).is_some() { (a, b) } else { (b, a) };
                    assert_eq!(on_edge(cut), Some(o), "edge {e:?}");
                    let (x, y) = old.edge_vertices(o);
                    assert!(same(end).is_some_and(|w| w == x || w == y), "edge {e:?}");
                }
                EdgeOrigin::MirrorOf(o) => {
                    panic!("edge {e:?} is the image of old edge {o:?}: the half's edit made no images")
                }
                _ => {}
            }
        }
        for f in new.faces() {
            let (FaceOrigin::Same(o) | FaceOrigin::SplitFrom(o)) = p.faces[f.index()] else { continue };
            let corners: Vec<VertexId> = old.face_vertices(o).collect();
            let sides: Vec<EdgeId> = old.face_halfedges(o).map(|h| h.edge()).collect();
            for v in new.face_vertices(f) {
                if let Some(w) = same(v) {
                    assert!(corners.contains(&w), "face {f:?}: corner {v:?} (old {w:?}) is not on old face {o:?}");
                }
                if let Some(e) = on_edge(v) {
                    assert!(sides.contains(&e), "face {f:?}: corner {v:?} is on old edge {e:?}, not on old face {o:?}");
                }
            }
        }
        tally
    }

    #[test]
    fn the_new_whole_comes_from_the_old_whole_on_both_sides_and_on_the_seam() {
        let doc = half_torus();
        let mut cache = MirroredWhole::default();
        let old = cache.whole(&doc).unwrap().unwrap();
        assert!(old.lineage().is_none(), "the first whole has nothing before it");
        let v = nearest(&doc, DVec3::new(2.7, 0.0, 0.0));
        let round_the_hole =
            doc.cage.outgoing(v).find(|&h| doc.cage.position(doc.cage.to_vertex(h)).y.abs() < 1e-9).unwrap().edge();
        let (beside, seam) = (nearest(&doc, DVec3::new(1.03, 2.49, 0.0)), nearest(&doc, DVec3::new(0.0, 2.7, 0.0)));
        let beside_the_seam = doc.cage.find_halfedge(beside, seam).unwrap().edge();
        // A face at the top of the tube, away from the seam.
        let centre = |f: FaceId| doc.cage.face_vertices(f).map(|v| doc.cage.position(v)).sum::<DVec3>() / 4.0;
        let target = DVec3::new(2.2, 0.9, 0.6);
        let face = doc.cage.faces().min_by(|&f, &g| centre(f).distance(target).total_cmp(&centre(g).distance(target)));
        let edits = [
            ("extrude", MeshEdit::ExtrudeFaces { faces: vec![face.unwrap().0], distance: 0.1 }),
            ("loop cut round the hole", MeshEdit::LoopCut { edge: round_the_hole.0, fraction: 0.3 }),
            ("delete", MeshEdit::DeleteVertices { vertices: vec![v.0] }),
            // Across the edges from the ring beside the seam to the seam: the image of such an
            // edge runs the other way in the whole (its ends' numbers compare the other way).
            ("loop cut beside the seam", MeshEdit::LoopCut { edge: beside_the_seam.0, fraction: 0.3 }),
        ];
        for (name, edit) in edits {
            let mut after = doc.clone();
            after.apply(Edit::Mesh(edit)).unwrap();
            let new = cache.clone().whole(&after).unwrap().unwrap();
            let lineage = new.lineage().unwrap_or_else(|| panic!("{name}: no lineage"));
            let tally = check(&old.cage, &new.cage, lineage);
            // The edits are local: most of each half is kept.
            let half = old.cage.vertex_count() / 2;
            assert!(tally.kept.iter().all(|&k| k > half / 2), "{name}: {tally:?}, {half} vertices a half");
            let cut_on_seam = if name == "loop cut round the hole" { 2 } else { 0 };
            assert_eq!((tally.moved, tally.cut_on_seam, tally.merged), (0, cut_on_seam, (0, 0)), "{name}");
        }
    }

    #[test]
    fn a_half_that_kept_its_connectivity_gives_its_whole_an_unchanged_lineage() {
        // A hole beside the seam, then a vertex of its rim dragged across the plane: it stops on
        // the plane and is glued to the seam, so the whole changes connectivity and the half not.
        let mut doc = half_torus();
        let beside_the_seam = nearest(&doc, DVec3::new(1.03, 2.49, 0.0));
        doc.apply(Edit::Mesh(MeshEdit::DeleteVertices { vertices: vec![beside_the_seam.0] })).unwrap();
        let mut cache = MirroredWhole::default();
        let old = cache.whole(&doc).unwrap().unwrap();
        let on_plane = |v: VertexId| doc.cage.position(v).x.abs() < 1e-9;
        let rim = doc.cage.vertices().find(|&v| {
            !on_plane(v)
                && doc.cage.outgoing(v).any(|h| doc.cage.is_boundary_edge(h.edge()) && on_plane(doc.cage.to_vertex(h)))
        });
        let rim = rim.unwrap();
        let p = doc.cage.position(rim);
        let mut after = doc.clone();
        after.apply(Edit::MoveVertices(vec![(rim, DVec3::new(-0.1, p.y, p.z))])).unwrap();
        let new = cache.whole(&after).unwrap().unwrap();
        assert_eq!(new.cage.vertex_count() + 1, old.cage.vertex_count(), "the rim vertex's image is gone");
        let tally = check(&old.cage, &new.cage, new.lineage().unwrap());
        // The rim vertex merged with its old image, its edge to the seam with its image.
        assert_eq!(tally.kept[0] + tally.kept[1] + 1, new.cage.vertex_count());
        assert_eq!((tally.moved, tally.cut_on_seam, tally.merged), (0, 0, (1, 1)));
    }

    #[test]
    fn a_whole_of_another_half_has_no_lineage() {
        let doc = half_torus();
        let mut cache = MirroredWhole::default();
        cache.whole(&doc).unwrap();
        let mut after = doc.clone();
        after.apply(Edit::Mesh(MeshEdit::DeleteVertices { vertices: vec![3] })).unwrap();
        assert!(cache.whole(&after).unwrap().unwrap().lineage().is_some());
        // Undo: the half before, which was not made from the one the cache last mirrored.
        assert!(cache.whole(&doc).unwrap().unwrap().lineage().is_none());
        // The edit again (redo) comes from the undone half: its whole from the undone whole.
        let undone = cache.clone().whole(&doc).unwrap().unwrap();
        let redone = cache.whole(&after).unwrap().unwrap();
        assert_eq!(redone.lineage().unwrap().from, undone.cage.topology_generation());
        // A cache that never mirrored the half before knows nothing of it.
        assert!(MirroredWhole::default().whole(&after).unwrap().unwrap().lineage().is_none());
    }
}
