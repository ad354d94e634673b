//! Creases as Blender and OpenSubdiv users know them: a sharpness `s ≥ 0` per cage edge.
//!
//! `0` is smooth, `f64::INFINITY` infinitely sharp. Semi-sharp values follow OpenSubdiv's default
//! *uniform* creasing (`Sdc::Options::CREASE_UNIFORM`, DeRose, Kass and Truong 1998): an edge's
//! halves get `s − 1` at the next level (0 once `s ≤ 1`), so the crease rules apply for `⌊s⌋`
//! levels and the fraction blends crease and smooth rules at the level where it runs out.
//! (OpenSubdiv's alternative, Chaikin creasing, is not implemented.)
//!
//! The rule of a vertex comes from the number of sharp (`s > 0`) edges at it: none is
//! [`Rule::Smooth`], one a [`Rule::Dart`] (refined like a smooth vertex), two a [`Rule::Crease`],
//! three or more a [`Rule::Corner`]. When the rule of a vertex changes between a level and the
//! next (sharpness running out), its new position blends the parent rule's mask and the child
//! rule's by the *fractional weight*: the mean sharpness of the edges that go from sharp to
//! smooth, clamped to 1 (`Sdc::Crease::ComputeFractionalWeightAtVertex`).
//!
//! A vertex can be sharp too (OpenSubdiv's *corner* vertices, Blender's vertex crease): a
//! vertex sharpness `s > 0` makes it a [`Rule::Corner`] whatever its edges, decremented level by
//! level like an edge's, and counted in the fractional weight when it runs out (with the edges
//! that run out at the same level, as OpenSubdiv does). An interior vertex of valence 2 whose two
//! edges are sharp starts with the smaller of their sharpness added to its own
//! ([`starting_corners`]), as OpenSubdiv (through Blender) refines it.
//!
//! Boundaries are interpolated "edge only" (OpenSubdiv's `VTX_BOUNDARY_EDGE_ONLY`;
//! `docs/subdivision.md` §1): a boundary edge is infinitely sharp, so a boundary vertex is a crease
//! along its two boundary edges (also a valence-2 corner of a single face, which is therefore *not*
//! pinned), and a corner when another sharp edge ends on it. A sharpness given to a boundary edge
//! is ignored.

use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::{Error, Result};

/// The rule of a vertex, from the sharp edges at it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// No sharp edge.
    Smooth,
    /// One sharp edge: refined with the smooth rule.
    Dart,
    /// Two sharp edges (every boundary vertex).
    Crease,
    /// Three or more sharp edges: the vertex stays where it is.
    Corner,
}

impl Rule {
    /// The rule of a vertex of sharpness `vertex` (0: not a corner) with `sharp_edges` sharp
    /// edges: a sharp vertex is a corner whatever its edges.
    pub fn of(vertex: f64, sharp_edges: usize) -> Self {
        if vertex > 0.0 { Rule::Corner } else { Rule::from_sharp_edges(sharp_edges) }
    }

    /// The rule of a vertex with `sharp_edges` sharp edges.
    pub fn from_sharp_edges(sharp_edges: usize) -> Self {
        match sharp_edges {
            0 => Rule::Smooth,
            1 => Rule::Dart,
            2 => Rule::Crease,
            _ => Rule::Corner,
        }
    }
}

/// The sharpness of an edge's halves one level down (uniform creasing).
#[inline]
pub fn child_sharpness(s: f64) -> f64 {
    if s > 1.0 { s - 1.0 } else { 0.0 }
}

/// Checks designer sharpness values (one per cage edge, or none for a smooth cage) and returns
/// the effective sharpness of every cage edge: boundary edges infinitely sharp.
pub fn effective_sharpness(cage: &PolyMesh, sharpness: &[f64]) -> Result<Vec<f64>> {
    if !sharpness.is_empty() && sharpness.len() != cage.edge_count() {
        return Err(Error::Input(format!(
            "{} crease sharpness values for a cage of {} edges; give one per cage edge (or none)",
            sharpness.len(),
            cage.edge_count()
        )));
    }
    let mut out = Vec::with_capacity(cage.edge_count());
    for e in cage.edges() {
        let s = sharpness.get(e.index()).copied().unwrap_or(0.0);
        if s.is_nan() || s < 0.0 {
            let (a, b) = cage.edge_vertices(e);
            return Err(Error::Input(format!(
                "the crease on the edge between vertices {} and {} has sharpness {s}; use a number ≥ 0 (∞ for a sharp crease)",
                a.0, b.0
            )));
        }
        out.push(if cage.is_boundary_edge(e) { f64::INFINITY } else { s });
    }
    Ok(out)
}

/// Checks designer vertex sharpness values (one per cage vertex, or none) and returns them.
pub fn effective_corners(cage: &PolyMesh, corners: &[f64]) -> Result<Vec<f64>> {
    if corners.is_empty() {
        return Ok(vec![0.0; cage.vertex_count()]);
    }
    if corners.len() != cage.vertex_count() {
        return Err(Error::Input(format!(
            "{} vertex sharpness values for a cage of {} vertices; give one per cage vertex (or none)",
            corners.len(),
            cage.vertex_count()
        )));
    }
    if let Some(v) = corners.iter().position(|s| s.is_nan() || *s < 0.0) {
        return Err(Error::Input(format!(
            "vertex {v} has sharpness {}; use a number ≥ 0 (∞ for a sharp corner)",
            corners[v]
        )));
    }
    Ok(corners.to_vec())
}

/// The vertex sharpness the refinement starts from: the designer's `corners` (checked by
/// [`effective_corners`]), plus, at an interior vertex of valence 2 whose two edges are both
/// sharp (effective sharpness `sharpness`), the smaller of the two. Such a vertex is therefore a
/// corner for as long as its crease lasts, and counts in the fractional weight when it runs out.
/// This is what OpenSubdiv does (measured through Blender 3.4's modifier on a cage whose two
/// quads share two edges at a vertex: with creases s₁ ≤ s₂ through it and vertex sharpness c,
/// the vertex blends as a corner of sharpness c + s₁); the plain crease rule there, which Taut
/// used before, is 3 % of the size away after two levels.
pub fn starting_corners(cage: &PolyMesh, sharpness: &[f64], corners: &[f64]) -> Result<Vec<f64>> {
    let mut out = effective_corners(cage, corners)?;
    for v in cage.vertices() {
        if cage.valence(v) != 2 || cage.is_boundary_vertex(v) {
            continue;
        }
        let mut edges = cage.outgoing(v).map(|h| sharp(sharpness, h.edge()));
        if let (Some(a), Some(b)) = (edges.next(), edges.next())
            && a > 0.0
            && b > 0.0
        {
            out[v.index()] += a.min(b);
        }
    }
    Ok(out)
}

/// Per-vertex sharpness from `(v, s)` corners (the command line's `--corner V=S`): an error names
/// a vertex the cage does not have or a bad value. Later entries replace earlier ones.
pub fn corners_from_pairs(cage: &PolyMesh, corners: &[(VertexId, f64)]) -> Result<Vec<f64>> {
    let mut out = vec![0.0; cage.vertex_count()];
    for &(v, s) in corners {
        if v.index() >= cage.vertex_count() {
            return Err(Error::Input(format!(
                "a corner names vertex {}, but the cage has {} vertices",
                v.0,
                cage.vertex_count()
            )));
        }
        if s.is_nan() || s < 0.0 {
            return Err(Error::Input(format!(
                "the corner at vertex {} has sharpness {s}; use a number ≥ 0 (∞ for a sharp corner)",
                v.0
            )));
        }
        out[v.index()] = s;
    }
    Ok(out)
}

/// Per-edge sharpness from `(a, b, s)` creases given by vertex pairs (the command line's
/// `--crease A-B=S`): an error names a pair that is not a cage edge or a bad value. Later entries
/// for the same edge replace earlier ones; unnamed edges are smooth.
pub fn sharpness_from_pairs(cage: &PolyMesh, creases: &[(VertexId, VertexId, f64)]) -> Result<Vec<f64>> {
    let mut out = vec![0.0; cage.edge_count()];
    for &(a, b, s) in creases {
        let n = cage.vertex_count();
        if a.index() >= n || b.index() >= n {
            return Err(Error::Input(format!(
                "a crease names vertices {} and {}, but the cage has {n} vertices",
                a.0, b.0
            )));
        }
        let Some(h) = cage.find_halfedge(a, b) else {
            return Err(Error::Input(format!(
                "there is no cage edge between vertices {} and {}; a crease must lie on a cage edge",
                a.0, b.0
            )));
        };
        if s.is_nan() || s < 0.0 {
            return Err(Error::Input(format!(
                "the crease between vertices {} and {} has sharpness {s}; use a number ≥ 0 (∞ for a sharp crease)",
                a.0, b.0
            )));
        }
        out[h.edge().index()] = s;
    }
    Ok(out)
}

/// The fractional weight of a vertex of sharpness `vertex` whose incident edges have sharpness
/// `parent`: the mean sharpness of those (the vertex included) that become smooth one level
/// down, clamped to 1 (0 when none does).
pub(crate) fn fractional_weight(vertex: f64, parent: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for s in std::iter::once(vertex).chain(parent) {
        if s > 0.0 && child_sharpness(s) <= 0.0 {
            sum += s;
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { (sum / count as f64).min(1.0) }
}

/// The sharpness of `e` in `sharp`, a per-edge table of a level; an empty table is a level with
/// no sharp edge (the fresh path passes none there, so its rules read no table).
#[inline]
pub(crate) fn sharp(sharpness: &[f64], e: EdgeId) -> f64 {
    sharpness.get(e.index()).copied().unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;

    #[test]
    fn uniform_creasing_decrements_and_blends() {
        assert_eq!(child_sharpness(2.5), 1.5);
        assert_eq!(child_sharpness(1.0), 0.0);
        assert_eq!(child_sharpness(0.3), 0.0);
        assert_eq!(child_sharpness(f64::INFINITY), f64::INFINITY);
        // Two edges running out (0.5 and 1.0) and one staying sharp: weight (0.5 + 1)/2.
        assert_eq!(fractional_weight(0.0, [0.5, 1.0, 3.0, 0.0].into_iter()), 0.75);
        assert_eq!(fractional_weight(0.0, [3.0, f64::INFINITY].into_iter()), 0.0);
        // A vertex of sharpness 0.5 running out with an edge of 1.0: (0.5 + 1)/2.
        assert_eq!(fractional_weight(0.5, [1.0, 2.0].into_iter()), 0.75);
        assert_eq!(Rule::of(0.3, 0), Rule::Corner);
        assert_eq!(Rule::of(0.0, 2), Rule::Crease);
        assert_eq!(Rule::from_sharp_edges(1), Rule::Dart);
        assert_eq!(Rule::from_sharp_edges(4), Rule::Corner);
    }

    #[test]
    fn bad_sharpness_is_refused_and_boundaries_are_sharp() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
        let m = PolyMesh::from_polygons(p, &[[0, 1, 2], [1, 3, 2]]).unwrap();
        let diagonal = m.find_halfedge(VertexId(1), VertexId(2)).unwrap().edge();
        let mut s = vec![0.0; m.edge_count()];
        s[diagonal.index()] = 1.5;
        let eff = effective_sharpness(&m, &s).unwrap();
        for e in m.edges() {
            assert_eq!(eff[e.index()], if e == diagonal { 1.5 } else { f64::INFINITY });
        }
        s[diagonal.index()] = f64::NAN;
        let err = effective_sharpness(&m, &s).unwrap_err().to_string();
        assert!(err.contains("between vertices 1 and 2") && err.contains("≥ 0"), "{err}");
        assert!(effective_sharpness(&m, &[1.0]).unwrap_err().to_string().contains("one per cage edge"));
        let err = sharpness_from_pairs(&m, &[(VertexId(0), VertexId(3), 1.0)]).unwrap_err().to_string();
        assert!(err.contains("no cage edge between vertices 0 and 3"), "{err}");
        let err = sharpness_from_pairs(&m, &[(VertexId(1), VertexId(2), -1.0)]).unwrap_err().to_string();
        assert!(err.contains("sharpness -1"), "{err}");
        let pairs = sharpness_from_pairs(&m, &[(VertexId(2), VertexId(1), 2.0)]).unwrap();
        assert_eq!(pairs[diagonal.index()], 2.0);
    }
}
