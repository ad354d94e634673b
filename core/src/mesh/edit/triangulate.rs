//! Triangulating faces: a fan from each face's first corner, or ears cut by shortest diagonal.
//!
//! [`Triangulation::Fan`] joins the first corner to every other; it is exact for convex faces
//! and gives overlapping triangles on a non-convex one. [`Triangulation::ShortestDiagonal`]
//! clips ears (a corner whose two neighbours can be joined inside the face): of the convex
//! corners whose ear holds no other corner, the one with the shortest diagonal goes first, so a
//! quad is cut along its shorter diagonal and thin slivers are avoided where the shape allows
//! (diagonals within a relative 1e-9 of each other tie, and the first corner wins).
//! Corners are tested in the face's mean plane (Newell normal), so a strongly warped face is
//! cut as its projection. A diagonal that already exists as another edge of the cage, or that an
//! earlier face was already cut along, is never used (it would double the edge: two quads that
//! share two opposite corners, as Blender's monkey has, must be cut along different diagonals);
//! a fan that would need one is refused naming the face.
//! Degenerate faces (no area) fall back to the shortest diagonals. Each face costs O(n²) in its
//! corner count n.

use super::Edited;
use super::draft::{Draft, face_mask};
use super::provenance::FaceOrigin;
use crate::mesh::{FaceId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use std::collections::HashSet;

/// How faces are cut into triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Triangulation {
    /// From each face's first corner.
    Fan,
    /// Ear by ear, shortest diagonal first.
    ShortestDiagonal,
}

/// Cuts the selected faces (every face when `faces` is `None`) into triangles; triangles stay.
pub fn triangulate(mesh: &PolyMesh, faces: Option<&[FaceId]>, method: Triangulation) -> Result<Edited> {
    const OP: &str = "triangulate";
    let mask = match faces {
        Some(faces) => face_mask(OP, mesh, faces)?,
        None => vec![true; mesh.face_count()],
    };
    let mut draft = Draft::new(mesh, OP);
    let mut ring: Vec<u32> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // The diagonals cut so far, as (lower, higher) vertex: edges from then on.
    let mut cut: HashSet<(u32, u32)> = HashSet::new();
    for f in mesh.faces() {
        if !mask[f.index()] || mesh.face_valence(f) == 3 {
            draft.keep_face(f);
            continue;
        }
        ring.clear();
        ring.extend(mesh.face_vertices(f).map(|v| v.0));
        triangles.clear();
        match method {
            Triangulation::Fan => {
                if let Some(k) = (2..ring.len() - 1).find(|&k| joined(mesh, &cut, ring[0], ring[k])) {
                    return Err(Error::Topology(format!(
                        "{OP}: corners {} and {} of face {} are already joined by another edge, so a fan from \
                         the first corner would double it; use the shortest-diagonal method",
                        ring[0], ring[k], f.0
                    )));
                }
                triangles.extend((1..ring.len() - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
            }
            Triangulation::ShortestDiagonal if ring.len() == 4 && split_quad(mesh, &cut, f, &ring, &mut triangles) => {}
            Triangulation::ShortestDiagonal => clip_ears(mesh, &cut, f, &ring, &mut triangles).ok_or_else(|| {
                Error::Topology(format!(
                    "{OP}: face {} cannot be cut into triangles without doubling an existing edge",
                    f.0
                ))
            })?,
        }
        for &t in &triangles {
            draft.push_face(t, FaceOrigin::SplitFrom(f));
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if mesh.find_halfedge(VertexId(a), VertexId(b)).is_none() {
                    cut.insert((a.min(b), a.max(b)));
                }
            }
        }
    }
    draft.finish()
}

/// Whether `a` and `b` are joined by an edge of the cage or by a diagonal already `cut`.
fn joined(mesh: &PolyMesh, cut: &HashSet<(u32, u32)>, a: u32, b: u32) -> bool {
    mesh.find_halfedge(VertexId(a), VertexId(b)).is_some() || cut.contains(&(a.min(b), a.max(b)))
}

/// A quad cut along its shorter diagonal (ties to the one from the first corner) when that
/// diagonal lies inside it and is not an edge already, else along the other one under the same
/// conditions; false when neither qualifies (ear clipping then decides). Quads are most faces
/// of a cage, so this spares [`clip_ears`]'s allocations.
fn split_quad(mesh: &PolyMesh, cut: &HashSet<(u32, u32)>, f: FaceId, ring: &[u32], out: &mut Vec<[u32; 3]>) -> bool {
    let p: [DVec3; 4] = std::array::from_fn(|k| mesh.position(VertexId(ring[k])));
    let normal = mesh.face_area_vector(f);
    let inside = |k: usize| {
        let (a, b, c, d) = (p[k], p[(k + 1) % 4], p[(k + 2) % 4], p[(k + 3) % 4]);
        (b - a).cross(c - a).dot(normal) > 0.0 && (c - a).cross(d - a).dot(normal) > 0.0
    };
    let (d02, d13) = (p[0].distance(p[2]), p[1].distance(p[3]));
    let order = if d02 <= d13 * (1.0 + 1e-9) { [0, 1] } else { [1, 0] };
    for k in order {
        if inside(k) && !joined(mesh, cut, ring[k], ring[k + 2]) {
            out.extend([[ring[k], ring[k + 1], ring[k + 2]], [ring[k + 2], ring[(k + 3) % 4], ring[k]]]);
            return true;
        }
    }
    false
}

/// Ear clipping of one face; `None` when every remaining diagonal already exists.
fn clip_ears(
    mesh: &PolyMesh,
    cut: &HashSet<(u32, u32)>,
    f: FaceId,
    ring: &[u32],
    out: &mut Vec<[u32; 3]>,
) -> Option<()> {
    let n = ring.len();
    let p: Vec<DVec3> = ring.iter().map(|&v| mesh.position(VertexId(v))).collect();
    let normal = mesh.face_area_vector(f).normalize_or_zero();
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut alive = vec![true; n];
    // An ear's rank: (tier, diagonal length); tier 0 is a proper ear, 1 a convex corner whose ear
    // holds another corner, 2 any other corner, 3 a corner whose diagonal already exists.
    let rank = |i: usize, prev: &[usize], next: &[usize], alive: &[bool]| -> (u8, f64) {
        let (a, b, c) = (prev[i], i, next[i]);
        if joined(mesh, cut, ring[a], ring[c]) {
            return (3, f64::INFINITY);
        }
        let length = p[a].distance(p[c]);
        let turn = (p[b] - p[a]).cross(p[c] - p[b]).dot(normal);
        if turn <= 0.0 {
            return (2, length);
        }
        let side = |u: DVec3, v: DVec3, q: DVec3| (v - u).cross(q - u).dot(normal);
        let holds = (0..n).any(|q| {
            alive[q]
                && q != a
                && q != b
                && q != c
                && side(p[a], p[b], p[q]) >= 0.0
                && side(p[b], p[c], p[q]) >= 0.0
                && side(p[c], p[a], p[q]) >= 0.0
        });
        (u8::from(holds), length)
    };
    let mut ranks: Vec<(u8, f64)> = (0..n).map(|i| rank(i, &prev, &next, &alive)).collect();
    let mut left = n;
    // The lowest tier, then the shortest diagonal; lengths within a relative 1e-9 of the
    // shortest count as equal and the first corner wins, so a symmetric face (a rectangle, a
    // regular polygon) is cut the same way after rounding moves its lengths apart.
    let pick = |ranks: &[(u8, f64)], alive: &[bool]| {
        let live = || (0..n).filter(|&i| alive[i]);
        let tier = live().map(|i| ranks[i].0).min()?;
        let shortest = live().filter(|&i| ranks[i].0 == tier).map(|i| ranks[i].1).fold(f64::INFINITY, f64::min);
        live().find(|&i| ranks[i].0 == tier && ranks[i].1 <= shortest * (1.0 + 1e-9))
    };
    while left > 3 {
        let mut best = pick(&ranks, &alive)?;
        if ranks[best].0 > 0 {
            // Only the clipped corner's neighbours were re-ranked; an ear that held the clipped
            // corner may have become proper since, so look at all of them before settling.
            for i in (0..n).filter(|&i| alive[i]) {
                ranks[i] = rank(i, &prev, &next, &alive);
            }
            best = pick(&ranks, &alive)?;
        }
        if ranks[best].0 == 3 {
            return None;
        }
        let (a, c) = (prev[best], next[best]);
        out.push([ring[a], ring[best], ring[c]]);
        alive[best] = false;
        next[a] = c;
        prev[c] = a;
        left -= 1;
        ranks[a] = rank(a, &prev, &next, &alive);
        ranks[c] = rank(c, &prev, &next, &alive);
    }
    let a = (0..n).find(|&i| alive[i])?;
    out.push([ring[a], ring[next[a]], ring[next[next[a]]]]);
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::edit::EdgeOrigin;
    use crate::mesh::edit::fixtures::{check, counts, cube, prism};

    #[test]
    fn triangulating_keeps_the_surface_and_its_area() {
        for method in [Triangulation::Fan, Triangulation::ShortestDiagonal] {
            let cube = cube();
            let edited = triangulate(&cube, None, method).unwrap();
            check(&cube, &edited);
            assert_eq!(counts(&edited.mesh), (8, 18, 12));
            let p = prism(5);
            let edited = triangulate(&p, None, method).unwrap();
            check(&p, &edited);
            assert_eq!(counts(&edited.mesh), (10, 24, 16));
            let area = |m: &PolyMesh| m.faces().map(|f| m.face_area_vector(f).length()).sum::<f64>();
            assert!((area(&edited.mesh) - area(&p)).abs() < 1e-12);
            let diagonals = edited.provenance.edges.iter().filter(|o| matches!(o, EdgeOrigin::InFace(_))).count();
            assert_eq!(diagonals, 9);
        }
        let cube = cube();
        let edited = triangulate(&cube, Some(&[FaceId(2)]), Triangulation::Fan).unwrap();
        assert_eq!(counts(&edited.mesh), (8, 13, 7));
    }

    fn single(points: &[[f64; 2]]) -> PolyMesh {
        let p = points.iter().map(|&[x, y]| DVec3::new(x, y, 0.0)).collect();
        PolyMesh::from_polygons(p, &[(0..points.len() as u32).collect::<Vec<_>>()]).unwrap()
    }

    #[test]
    fn the_shorter_diagonal_of_a_quad_is_cut() {
        let quad = single(&[[0.0, 0.0], [2.0, 0.0], [2.5, 1.0], [0.5, 1.0]]);
        let edited = triangulate(&quad, None, Triangulation::ShortestDiagonal).unwrap();
        let e = edited.mesh.edges().find(|&e| !edited.mesh.is_boundary_edge(e)).unwrap();
        let (a, b) = edited.mesh.edge_vertices(e);
        assert_eq!((a.0, b.0), (1, 3));
        let fan = triangulate(&quad, None, Triangulation::Fan).unwrap();
        assert!(fan.mesh.find_halfedge(VertexId(0), VertexId(2)).is_some());
    }

    #[test]
    fn ears_of_a_non_convex_face_stay_inside_it() {
        // An L: a fan from corner 4 (the reflex corner's neighbour) would fold.
        let l = single(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]);
        let edited = triangulate(&l, None, Triangulation::ShortestDiagonal).unwrap();
        check(&l, &edited);
        let m = &edited.mesh;
        assert_eq!(m.face_count(), 4);
        let total: f64 = m.faces().map(|f| m.face_area_vector(f).z).sum();
        assert!((total - 3.0).abs() < 1e-12);
        assert!(m.faces().all(|f| m.face_area_vector(f).z > 0.0), "every triangle keeps the face's orientation");
    }

    #[test]
    fn quads_that_share_two_opposite_corners_are_cut_along_different_diagonals() {
        // Blender's monkey has quads with two opposite corners in common; cut along that diagonal
        // twice, it would border four triangles.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/blender/monkey.obj");
        let (monkey, _) = crate::io::import_mesh(&path).unwrap();
        let opposite = |f: FaceId| {
            let r: Vec<u32> = monkey.face_vertices(f).map(|v| v.0).collect();
            if r.len() == 4 { vec![(r[0].min(r[2]), r[0].max(r[2])), (r[1].min(r[3]), r[1].max(r[3]))] } else { vec![] }
        };
        let mut seen = HashSet::new();
        let shared = monkey.faces().flat_map(opposite).filter(|&d| !seen.insert(d)).count();
        assert!(shared > 0, "the monkey has quads sharing a diagonal");
        let edited = triangulate(&monkey, None, Triangulation::ShortestDiagonal).unwrap();
        check(&monkey, &edited);
        assert!(edited.mesh.faces().all(|f| edited.mesh.face_valence(f) == 3));
        let triangles: usize = monkey.faces().map(|f| monkey.face_valence(f) - 2).sum();
        assert_eq!(edited.mesh.face_count(), triangles);
        assert_eq!(edited.mesh.vertex_count(), monkey.vertex_count());
    }

    #[test]
    fn a_diagonal_that_already_exists_is_never_used() {
        // A quad 0-1-2-3 with a triangle folded over it through 0 and 2.
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let m = PolyMesh::from_polygons(p, &[vec![0, 1, 2, 3], vec![1, 0, 2]]).unwrap();
        let err = triangulate(&m, Some(&[FaceId(0)]), Triangulation::Fan).unwrap_err().to_string();
        assert!(err.contains("already joined"), "{err}");
        let edited = triangulate(&m, Some(&[FaceId(0)]), Triangulation::ShortestDiagonal).unwrap();
        check(&m, &edited);
        assert!(edited.mesh.find_halfedge(VertexId(1), VertexId(3)).is_some());
        assert!(triangulate(&m, Some(&[FaceId(4)]), Triangulation::Fan).is_err());
    }
}
