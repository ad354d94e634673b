//! Merging vertices: several vertices become one, at their centre or at the first or last of
//! them, or every cluster of vertices closer than a threshold becomes one.
//!
//! Each face is renumbered through the merge and loses the corners that now repeat their
//! neighbour; a face left with fewer than three corners has collapsed (a triangle whose edge was
//! merged away) and goes, as in an edge collapse, and edges merged onto each other become one.
//! Refused with a message: a merge that folds a face onto itself (two corners that are not
//! neighbours merged), that leaves a face without area, that would make a non-manifold edge or
//! vertex (the mesh builder names it), or that leaves no face at all.
//!
//! Values: an explicit merge keeps the values of the first vertex listed, or of the last for
//! [`MergeAt::Last`] (the one that stays where it is); a merge by distance keeps those of the
//! lowest-numbered vertex of each cluster and places it at the cluster's centre, so the result
//! does not depend on the order the vertices were given in. Clusters are found single-linkage
//! (a chain of close vertices is one cluster) with a uniform grid of cells ([`super::spatial`]), so
//! the search is linear for evenly spread vertices.

use super::Edited;
use super::draft::{Draft, vertex_mask};
use super::provenance::{EdgeOrigin, VertexOrigin};
use super::spatial::PointGrid;
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use std::collections::HashMap;

/// Where an explicit merge puts the merged vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MergeAt {
    /// At the mean of the merged vertices' positions.
    Centre,
    /// At the first vertex listed.
    First,
    /// At the last vertex listed.
    Last,
}

/// Merges the listed vertices (at least two) into one.
pub fn merge_vertices(mesh: &PolyMesh, vertices: &[VertexId], at: MergeAt) -> Result<Edited> {
    const OP: &str = "merge vertices";
    vertex_mask(OP, mesh, vertices)?;
    let mut unique: Vec<VertexId> = Vec::with_capacity(vertices.len());
    for &v in vertices {
        if !unique.contains(&v) {
            unique.push(v);
        }
    }
    if unique.len() < 2 {
        return Err(Error::Input(format!("{OP}: select at least two different vertices to merge")));
    }
    let kept = if at == MergeAt::Last { *unique.last().unwrap() } else { unique[0] };
    let position = match at {
        MergeAt::Centre => unique.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / unique.len() as f64,
        MergeAt::First | MergeAt::Last => mesh.position(kept),
    };
    let mut target: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    for &v in &unique {
        target[v.index()] = kept.0;
    }
    merge(mesh, &target, &[(kept, position)], OP)
}

/// Merges every cluster of the listed vertices lying within `threshold` of each other (chained),
/// each at its centre. Nothing closer than the threshold leaves the cage as it was.
pub fn merge_by_distance(mesh: &PolyMesh, vertices: &[VertexId], threshold: f64) -> Result<Edited> {
    const OP: &str = "merge by distance";
    if !(threshold.is_finite() && threshold > 0.0) {
        return Err(Error::Input(format!(
            "{OP}: the distance must be a finite number greater than 0, not {threshold:?}"
        )));
    }
    let mask = vertex_mask(OP, mesh, vertices)?;
    let listed = || mesh.vertices().filter(|v| mask[v.index()]).map(|v| v.0);
    // Cells no finer than a billionth of the cage, so a tiny threshold cannot overflow the keys.
    let cell = (8.0 * threshold).max(1e-9 * mesh.bounding_diagonal()).max(f64::MIN_POSITIVE);
    let grid = PointGrid::new(mesh.positions(), listed(), cell);
    let mut parent: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for v in listed() {
        let p = mesh.positions()[v as usize];
        grid.near(p, threshold, |w| {
            if w < v && mesh.positions()[w as usize].distance(p) <= threshold {
                let (rv, rw) = (root(&mut parent, v), root(&mut parent, w));
                parent[rv.max(rw) as usize] = rv.min(rw);
            }
        });
    }
    let target: Vec<u32> = (0..mesh.vertex_count() as u32).map(|v| root(&mut parent, v)).collect();
    let mut sum = vec![(DVec3::ZERO, 0usize); mesh.vertex_count()];
    for v in mesh.vertices() {
        let s = &mut sum[target[v.index()] as usize];
        *s = (s.0 + mesh.position(v), s.1 + 1);
    }
    let kept: Vec<(VertexId, DVec3)> = mesh
        .vertices()
        .filter(|v| target[v.index()] == v.0 && sum[v.index()].1 > 1)
        .map(|v| (v, sum[v.index()].0 / sum[v.index()].1 as f64))
        .collect();
    if kept.is_empty() {
        return Ok(super::draft::unchanged(mesh));
    }
    merge(mesh, &target, &kept, OP)
}

/// Renumbers every vertex to `target` (a kept vertex, or itself) and places the kept ones.
fn merge(mesh: &PolyMesh, target: &[u32], kept: &[(VertexId, DVec3)], op: &'static str) -> Result<Edited> {
    let mut draft = Draft::new(mesh, op);
    for &(v, p) in kept {
        draft.positions[v.index()] = p;
        draft.vertex_origin[v.index()] = VertexOrigin::Merged(v);
    }
    let mut merged: Vec<bool> = mesh.vertices().map(|v| target[v.index()] != v.0).collect();
    for &(v, _) in kept {
        merged[v.index()] = true;
    }
    let mut ring: Vec<u32> = Vec::new();
    let mut scratch: Vec<u32> = Vec::new();
    for f in mesh.faces() {
        if !mesh.face_vertices(f).any(|v| merged[v.index()]) {
            draft.keep_face(f);
            continue;
        }
        ring.clear();
        for v in mesh.face_vertices(f) {
            let t = target[v.index()];
            if ring.last() != Some(&t) {
                ring.push(t);
            }
        }
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            continue; // collapsed
        }
        if let Some(v) = repeated(&ring, &mut scratch) {
            return Err(Error::Topology(format!(
                "{op}: merging would fold face {} onto itself at vertex {v} (two of its corners that are not \
                 neighbours would become one)",
                f.0
            )));
        }
        let point = |k: usize| draft.positions[ring[k % ring.len()] as usize];
        let area: DVec3 = (0..ring.len()).map(|k| point(k).cross(point(k + 1))).sum();
        let scale = (0..ring.len()).map(|k| point(k).distance(point(k + 1))).fold(0.0, f64::max);
        if area.length() <= 1e-12 * scale * scale {
            return Err(Error::Topology(format!(
                "{op}: merging would leave face {} with no area (its corners would lie on a line)",
                f.0
            )));
        }
        draft.push_face(ring.iter().copied(), super::provenance::FaceOrigin::Same(f));
    }
    // Edges touching a merged vertex: the old edges that land on one new edge keep the values of
    // the lowest-numbered of them.
    let mut landed: HashMap<(u32, u32), (EdgeId, usize)> = HashMap::new();
    for e in mesh.edges() {
        let (a, b) = mesh.edge_vertices(e);
        let (ta, tb) = (target[a.index()], target[b.index()]);
        if (merged[a.index()] || merged[b.index()]) && ta != tb {
            let entry = landed.entry((ta.min(tb), ta.max(tb))).or_insert((e, 0));
            *entry = (entry.0.min(e), entry.1 + 1);
        }
    }
    for e in mesh.edges() {
        let (a, b) = mesh.edge_vertices(e);
        let (ta, tb) = (target[a.index()], target[b.index()]);
        if !(merged[a.index()] || merged[b.index()]) {
            continue;
        }
        if let Some(&(first, count)) = landed.get(&(ta.min(tb), ta.max(tb))) {
            draft.hint_edge(ta, tb, if count == 1 { EdgeOrigin::Same(first) } else { EdgeOrigin::Merged(first) });
        }
    }
    for v in mesh.vertices().filter(|v| target[v.index()] != v.0) {
        draft.remove_vertex(v);
    }
    // The builder's advice (split the vertex, flip a face) does not fit a merge: replace it.
    draft.finish().map_err(|e| match e {
        Error::Topology(m) => Error::Topology(format!(
            "{}; the merge is refused, as the cage must stay a manifold surface",
            m.split(';').next().unwrap_or(&m)
        )),
        other => other,
    })
}

/// A vertex that occurs twice in `ring`, if any (`scratch` is reused between calls).
pub(super) fn repeated(ring: &[u32], scratch: &mut Vec<u32>) -> Option<u32> {
    scratch.clear();
    scratch.extend_from_slice(ring);
    scratch.sort_unstable();
    scratch.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::FaceOrigin;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, house};

    #[test]
    fn merging_the_ends_of_an_edge_collapses_it() {
        let cube = cube();
        for (at, expected) in
            [(MergeAt::Centre, DVec3::new(0.5, 0.0, 0.0)), (MergeAt::First, DVec3::ZERO), (MergeAt::Last, DVec3::X)]
        {
            let edited = merge_vertices(&cube, &[VertexId(0), VertexId(1)], at).unwrap();
            check(&cube, &edited);
            let m = &edited.mesh;
            assert_eq!(counts(m), (7, 11, 6));
            assert!(m.is_closed());
            assert_eq!(m.faces().filter(|&f| m.face_valence(f) == 3).count(), 2);
            let kept = if at == MergeAt::Last { 1 } else { 0 };
            let v =
                m.vertices().find(|&v| edited.provenance.vertices[v.index()] == VertexOrigin::Merged(VertexId(kept)));
            assert_eq!(m.position(v.unwrap()), expected);
            // The merged vertex keeps the tension of the first (the last for MergeAt::Last).
            let tension: Vec<f64> = cube.vertices().map(|v| 1.0 + v.0 as f64).collect();
            let carried = crate::mesh::edit::carry_vertex_property(
                &tension,
                &edited.provenance,
                &crate::mesh::edit::CarryRule::new_elements(0.0),
            )
            .unwrap();
            let at = m.vertices().find(|&v| m.position(v) == expected).unwrap();
            assert_eq!(carried[at.index()], 1.0 + kept as f64);
            assert!(!carried.contains(&(2.0 - kept as f64)), "the other vertex's value is gone");
        }
    }

    #[test]
    fn a_collapsed_triangle_goes_and_its_sides_become_one_edge() {
        let h = house();
        let edited = merge_vertices(&h, &[VertexId(4), VertexId(8)], MergeAt::First).unwrap();
        check(&h, &edited);
        assert_eq!(counts(&edited.mesh), (8, 13, 7));
        assert!(edited.mesh.is_closed());
        // Edges 5-8 and 5-4 landed on one edge, which keeps the lower-numbered one's values.
        let e = edited.mesh.find_halfedge(VertexId(4), VertexId(5)).unwrap().edge();
        let old = |a, b| h.find_halfedge(VertexId(a), VertexId(b)).unwrap().edge();
        assert_eq!(edited.provenance.edges[e.index()], EdgeOrigin::Merged(old(4, 5).min(old(5, 8))));
        assert_eq!(edited.provenance.faces.iter().filter(|o| matches!(o, FaceOrigin::Same(_))).count(), 7);
    }

    #[test]
    fn welding_two_patches_by_distance() {
        // Two 2 × 2 grids side by side with their own copies of the seam vertices.
        let a = grid(2);
        let mut positions = a.positions().to_vec();
        positions.extend(a.positions().iter().map(|&p| p + DVec3::new(2.0, 0.0, 0.0)));
        let mut faces = a.polygons();
        faces.extend(a.polygons().into_iter().map(|f| f.into_iter().map(|v| v + 9).collect::<Vec<_>>()));
        let two = PolyMesh::from_polygons(positions, &faces).unwrap();
        let all: Vec<VertexId> = two.vertices().collect();
        let edited = merge_by_distance(&two, &all, 1e-9).unwrap();
        check(&two, &edited);
        assert_eq!(counts(&edited.mesh), (15, 22, 8));
        assert_eq!(edited.mesh.euler_characteristic(), 1);
        let merged = edited.provenance.edges.iter().filter(|o| matches!(o, EdgeOrigin::Merged(_))).count();
        assert_eq!(merged, 2);
        // Nothing close: nothing changes.
        let edited = merge_by_distance(&a, &[VertexId(0), VertexId(1)], 0.5).unwrap();
        assert_eq!(counts(&edited.mesh), counts(&a));
        // Chained: with a threshold of 1 the whole grid row 0..=2 joins one cluster, which folds.
        assert!(merge_by_distance(&a, &all[..9], 1.0).is_err());
    }

    #[test]
    fn bad_merges_are_refused_with_a_message() {
        let cube = cube();
        // Three fins sharing a spine: welding it gives an edge with three faces.
        let mut p = Vec::new();
        let mut faces = Vec::new();
        for k in 0..3 {
            let a = std::f64::consts::TAU * k as f64 / 3.0;
            let d = DVec3::new(a.cos(), a.sin(), 0.0);
            let base = p.len() as u32;
            p.extend([DVec3::ZERO, DVec3::Z, DVec3::Z + d, d]);
            // Alternate the fins' orientation so the welded spine runs both ways.
            faces.push(if k == 1 {
                [base, base + 1, base + 2, base + 3]
            } else {
                [base, base + 3, base + 2, base + 1]
            });
        }
        let fins = PolyMesh::from_polygons(p, &faces).unwrap();
        let all: Vec<VertexId> = fins.vertices().collect();
        let cases = [
            (merge_vertices(&cube, &[VertexId(0), VertexId(3)], MergeAt::Centre).err(), "fold face 0"),
            (merge_vertices(&cube, &[VertexId(0), VertexId(7)], MergeAt::Centre).err(), "non-manifold"),
            (merge_by_distance(&fins, &all, 1e-9).err(), "non-manifold edge"),
            (merge_vertices(&cube, &[VertexId(0)], MergeAt::Centre).err(), "at least two"),
            (merge_vertices(&cube, &[VertexId(0), VertexId(0)], MergeAt::Centre).err(), "at least two"),
            (merge_vertices(&cube, &[VertexId(0), VertexId(9)], MergeAt::Centre).err(), "vertex 9 does not exist"),
            (merge_by_distance(&cube, &[VertexId(0)], -1.0).err(), "greater than 0"),
            (merge_by_distance(&cube, &all_of(&cube), 2.0).err(), "no faces left"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
        }
    }

    fn all_of(m: &PolyMesh) -> Vec<VertexId> {
        m.vertices().collect()
    }
}
