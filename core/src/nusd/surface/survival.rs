//! Which vertices of a hierarchy re-made after a topology edit are vertices of the old one
//! (issue 22: the warm start after an extrude, a loop cut or a deletion).
//!
//! A vertex of level `k` is named by its parent chain: it is a vertex of level `k − 1` (same
//! index, [`hierarchy`](super::hierarchy)'s stable numbering), the midpoint of an edge of level
//! `k − 1`, or the centre of a face of level `k − 1` that is not a triangle. So it survives an
//! edit when the element it was made from survives: at the cage, a vertex the edit's provenance
//! calls [`Same`](VertexOrigin::Same) as an old vertex and left where it was; at every finer
//! level, an edge whose two ends survive and were joined before, or a face whose corners survive
//! and bounded a face, in the same order, before. A surviving vertex has the same domain
//! position as its old self (the domain is the parents' average), so its solved state is a good
//! start; every other vertex starts from the usual parent average of the level above.
//!
//! The edit's neighbourhood is the set of [`changed`] cage vertices: those that do not survive,
//! or whose ring of faces, neighbours, fixed flag or tension differs from their old self's. Every
//! operator row that differs from the old hierarchy's lies in a cage face at one of them (the
//! rows see only the domain, roles and tensions of the faces around a vertex), so a local solve
//! grown from them ([`super::local`]) re-solves everything the edit touched directly and
//! measures how far its effect reaches beyond.

use crate::mesh::edit::{Provenance, VertexOrigin};
use crate::mesh::{FaceId, HalfedgeId, PolyMesh, VertexId};

/// Marks a vertex with no old self.
pub const NONE: u32 = u32::MAX;

/// Per cage vertex after the edit: the old cage vertex it is (the provenance's `Same`, at the same
/// position), or [`NONE`]. A vertex the edit moved, copied or made starts afresh.
pub fn cage_survivors(new: &PolyMesh, old: &PolyMesh, provenance: &Provenance) -> Vec<u32> {
    provenance
        .vertices
        .iter()
        .enumerate()
        .map(|(v, origin)| match *origin {
            VertexOrigin::Same(o)
                if o.index() < old.vertex_count() && old.position(o) == new.position(VertexId(v as u32)) =>
            {
                o.0
            }
            _ => NONE,
        })
        .collect()
}

/// The survivors of the next finer level, from those of a level (`survivors[v]`: the old vertex
/// of new vertex `v`) and the two levels' meshes (new and old), in the numbering of
/// [`LevelTopology::refine`](super::hierarchy::LevelTopology::refine).
pub fn refined_survivors(new: &PolyMesh, old: &PolyMesh, survivors: &[u32]) -> Vec<u32> {
    let (nv, ne) = (new.vertex_count(), new.edge_count());
    let (old_nv, old_ne) = (old.vertex_count(), old.edge_count());
    // The old index of each old face's centre vertex (triangles have none).
    let mut old_centre = vec![NONE; old.face_count()];
    let mut next = (old_nv + old_ne) as u32;
    for f in old.faces() {
        if old.face_valence(f) != 3 {
            old_centre[f.index()] = next;
            next += 1;
        }
    }
    let mut out = Vec::with_capacity(nv + ne + new.face_count());
    out.extend_from_slice(survivors);
    for e in new.edges() {
        let (a, b) = new.edge_vertices(e);
        out.push(old_halfedge(old, survivors, a, b).map_or(NONE, |h| (old_nv + h.edge().index()) as u32));
    }
    for f in new.faces() {
        if new.face_valence(f) != 3 {
            out.push(old_face(new, old, survivors, f).map_or(NONE, |g| old_centre[g.index()]));
        }
    }
    out
}

/// The old halfedge between the old selves of `a` and `b`, if both survive and were joined.
fn old_halfedge(old: &PolyMesh, survivors: &[u32], a: VertexId, b: VertexId) -> Option<HalfedgeId> {
    let (oa, ob) = (survivors[a.index()], survivors[b.index()]);
    if oa == NONE || ob == NONE {
        return None;
    }
    old.find_halfedge(VertexId(oa), VertexId(ob))
}

/// The old face with the old selves of `f`'s corners, in the same order, if there was one.
fn old_face(new: &PolyMesh, old: &PolyMesh, survivors: &[u32], f: FaceId) -> Option<FaceId> {
    let h = new.face_halfedge(f);
    let start = old_halfedge(old, survivors, new.from_vertex(h), new.to_vertex(h))?;
    let g = old.face(start);
    if !g.is_valid() || old.face_valence(g) != new.face_valence(f) {
        return None;
    }
    let (mut hn, mut ho) = (h, start);
    loop {
        if survivors[new.to_vertex(hn).index()] != old.to_vertex(ho).0 {
            return None;
        }
        hn = new.next(hn);
        ho = old.next(ho);
        if hn == h {
            return Some(g);
        }
    }
}

/// What a cage vertex's operator rows read besides positions: its fixed flag and tension, and the
/// tension of each cage edge (indexed by edge).
#[derive(Clone, Copy, Debug)]
pub struct CageControls<'a> {
    pub fixed: &'a [bool],
    pub vertex_tension: &'a [f64],
    pub edge_tension: &'a [f64],
}

/// The new cage vertices in the edit's neighbourhood (see the module docs), sorted: those without
/// an old self, and those whose faces, neighbours (with their edges' tension), fixed flag or
/// tension differ from their old self's.
pub fn changed(
    new: &PolyMesh,
    old: &PolyMesh,
    survivors: &[u32],
    new_controls: &CageControls<'_>,
    old_controls: &CageControls<'_>,
) -> Vec<u32> {
    new.vertices()
        .filter(|&v| {
            let o = survivors[v.index()];
            if o == NONE {
                return true;
            }
            let (vi, oi) = (v.index(), o as usize);
            if new_controls.fixed[vi] != old_controls.fixed[oi]
                || new_controls.vertex_tension[vi] != old_controls.vertex_tension[oi]
                || new.valence(v) != old.valence(VertexId(o))
            {
                return true;
            }
            !new.outgoing(v).all(|h| {
                let Some(g) = old_halfedge(old, survivors, v, new.to_vertex(h)) else { return false };
                if new_controls.edge_tension[h.edge().index()] != old_controls.edge_tension[g.edge().index()] {
                    return false;
                }
                let f = new.face(h);
                match (f.is_valid(), old.face(g).is_valid()) {
                    (true, true) => old_face(new, old, survivors, f) == Some(old.face(g)),
                    (false, false) => true,
                    _ => false,
                }
            })
        })
        .map(|v| v.0)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::{delete_vertices, extrude_faces, loop_cut};
    use crate::mesh::primitives::torus;
    use crate::nusd::surface::hierarchy::LevelTopology;

    fn controls<'a>(fixed: &'a [bool], vt: &'a [f64], et: &'a [f64]) -> CageControls<'a> {
        CageControls { fixed, vertex_tension: vt, edge_tension: et }
    }

    /// Checks, level by level, that every survivor has the same domain position as its old self
    /// (an independent check: the domain is computed by refinement, the survivors by names).
    fn check_domains(old: &PolyMesh, new: &PolyMesh, provenance: &Provenance, levels: usize) -> Vec<usize> {
        let (mut lo, mut ln) = (LevelTopology::cage(old), LevelTopology::cage(new));
        let mut survivors = cage_survivors(new, old, provenance);
        let mut counts = Vec::new();
        for level in 0..=levels {
            let (po, pn) = (lo.mesh.positions(), ln.mesh.positions());
            let mut count = 0;
            for (v, &o) in survivors.iter().enumerate() {
                if o != NONE {
                    assert!((po[o as usize] - pn[v]).length() < 1e-12, "level {level}: vertex {v} is not old {o}");
                    count += 1;
                }
            }
            counts.push(count);
            if level < levels {
                survivors = refined_survivors(&ln.mesh, &lo.mesh, &survivors);
                lo = lo.refine().unwrap();
                ln = ln.refine().unwrap();
                assert_eq!(survivors.len(), ln.vertex_count());
            }
        }
        counts
    }

    #[test]
    fn survivors_are_the_same_points_of_the_domain_at_every_level() {
        let cage = torus(12, 8, 2.0, 0.7).unwrap();
        let edge = cage.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
        let edits = [
            extrude_faces(&cage, &[FaceId(10)], crate::mesh::edit::FaceGrouping::Region, 0.1).unwrap(),
            loop_cut(&cage, edge, 0.5).unwrap(),
            delete_vertices(&cage, &[VertexId(40)]).unwrap(),
        ];
        for edited in &edits {
            let counts = check_domains(&cage, &edited.mesh, &edited.provenance, 2);
            // Most of the surface survives a local edit, at every level.
            let level2 = LevelTopology::cage(&edited.mesh).refine().unwrap().refine().unwrap().vertex_count();
            assert!(counts[2] as f64 > 0.6 * level2 as f64, "{counts:?} of {level2}");
        }
    }

    #[test]
    fn the_edits_neighbourhood_is_where_the_cage_changed() {
        let cage = torus(12, 8, 2.0, 0.7).unwrap();
        let (n, e) = (cage.vertex_count(), cage.edge_count());
        let (fixed, vt, et) = (vec![true; n], vec![0.0; n], vec![0.0; e]);
        let old = controls(&fixed, &vt, &et);
        // Deleting a vertex of valence 4: its four faces go, its 8 ring vertices change.
        let edited = delete_vertices(&cage, &[VertexId(40)]).unwrap();
        let survivors = cage_survivors(&edited.mesh, &cage, &edited.provenance);
        let m = edited.mesh.vertex_count();
        let (fixed2, vt2, et2) = (vec![true; m], vec![0.0; m], vec![0.0; edited.mesh.edge_count()]);
        let seeds = changed(&edited.mesh, &cage, &survivors, &controls(&fixed2, &vt2, &et2), &old);
        let ring: Vec<u32> = {
            let mut r: Vec<u32> = cage
                .outgoing(VertexId(40))
                .map(|h| cage.face(h))
                .filter(|f| f.is_valid())
                .flat_map(|f| cage.face_vertices(f).collect::<Vec<_>>())
                .filter(|&v| v.0 != 40)
                .map(|v| v.0)
                .collect();
            r.sort_unstable();
            r.dedup();
            r
        };
        let mut old_selves: Vec<u32> = seeds.iter().map(|&v| survivors[v as usize]).collect();
        old_selves.sort_unstable();
        assert_eq!(old_selves, ring);
        // A tension changed at one vertex makes it (only) changed too.
        let mut vt3 = vt2.clone();
        vt3[0] = 1.0;
        let seeds3 = changed(&edited.mesh, &cage, &survivors, &controls(&fixed2, &vt3, &et2), &old);
        assert_eq!(seeds3.len(), seeds.len() + usize::from(!seeds.contains(&0)));
        // The same cage, unedited, has no neighbourhood.
        let same = cage_survivors(
            &cage,
            &cage,
            &crate::mesh::edit::Provenance {
                vertices: (0..n as u32).map(|v| VertexOrigin::Same(VertexId(v))).collect(),
                edges: Vec::new(),
                faces: Vec::new(),
                old_counts: (n, e, cage.face_count()),
            },
        );
        assert!(changed(&cage, &cage, &same, &old, &old).is_empty());
    }
}
