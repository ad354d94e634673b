//! What keeps a NUSD surface from collapsing: enough fixed cage vertices, per connected part.
//!
//! The converged surface is an affine combination of the fixed vertices' positions. Without
//! tension the fixed point is linear in them, and it reproduces constants (all fixed vertices at
//! one point give `P ≡ that point`, `R ≡ 0`), so the weights of each surface point sum to one;
//! tension only adds tangential differences `β (P_j − P_i)_t / s`, which keep that property. So
//! the surface of a connected part of the cage lies in the affine hull of that part's fixed
//! vertices:
//! - a **closed** part needs fixed vertices spanning space (four not in one plane): with all of
//!   them in one plane its closed surface comes out flat, on one line it collapses onto the line,
//!   at one point it shrinks to the point, and with none the system has no unique solution (the
//!   iteration drifts and shrinks);
//! - on an **open** part every boundary loop is a closed NUSD polyline through its own fixed
//!   vertices alone (`docs/nusd.md`, "Open boundaries"), so each loop needs fixed vertices not on
//!   one line: with two (the least the polyline command accepts) the loop collapses onto the
//!   segment between them and the patch pinches to it. The interior is then solved against its
//!   loops.
//!
//! "In one plane" is relative: within [`FLAT_TOLERANCE`] of the part's bounding-box diagonal, so
//! the check is invariant under similarity transforms and works at any size. A part whose every
//! vertex lies in that plane (a flat cage) is accepted: its flat result is what the cage is.
//! Weak spot: the rule is the hull dimension only; fixed vertices nearly in one plane (just over
//! the tolerance) pass and give a very thin surface.

use crate::mesh::{HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};

/// Fixed vertices closer than this fraction of their part's diagonal to a point, line or plane
/// count as lying on it.
pub const FLAT_TOLERANCE: f64 = 1e-6;

/// Most vertices or ranges a message lists before it says how many more there are.
const LIST_LIMIT: usize = 12;

/// Checks that every connected part of the cage has fixed vertices enough to anchor its surface
/// (see the [module docs](self)). `fixed` has one flag per cage vertex. The error is one line
/// naming the part, its fixed vertices and the vertices to fix.
pub fn check_anchoring(cage: &PolyMesh, fixed: &[bool]) -> Result<()> {
    if fixed.len() != cage.vertex_count() {
        return Err(Error::Input(format!(
            "the cage has {} vertices but {} fixed flags",
            cage.vertex_count(),
            fixed.len()
        )));
    }
    for part in components(cage) {
        let scale = Scale::of(cage, &part);
        let loops = boundary_loops(cage, &part);
        if loops.is_empty() {
            check_set(cage, fixed, &part, 3, &scale, &format!("component of vertices {}", ranges(&part)))?;
        } else {
            for boundary in &loops {
                let name = format!("the open boundary through vertices {}", ranges(boundary));
                check_set(cage, fixed, boundary, 2, &scale, &name)?;
            }
        }
    }
    Ok(())
}

/// Positions of one part mapped to a frame of unit size, so that no product overflows or
/// underflows whatever the size of the cage.
struct Scale {
    origin: DVec3,
    inverse: f64,
}

impl Scale {
    fn of(cage: &PolyMesh, part: &[VertexId]) -> Scale {
        let points: Vec<DVec3> = part.iter().map(|&v| cage.position(v)).collect();
        let (lo, hi) = crate::mesh::bounding_box(&points).unwrap_or((DVec3::ZERO, DVec3::ZERO));
        // Halves first: `hi − lo` itself can overflow for coordinates near ±1e308.
        let half = 0.5 * hi - 0.5 * lo;
        let m = half.abs().max_element();
        let inverse = if m > 0.0 && m.is_finite() { 1.0 / m } else { 1.0 };
        Scale { origin: 0.5 * hi + 0.5 * lo, inverse }
    }

    /// A position in the part's unit frame (the part spans at most [-1, 1] on every axis).
    fn map(&self, p: DVec3) -> DVec3 {
        p * self.inverse - self.origin * self.inverse
    }
}

/// The affine hull of some points in a unit frame: its dimension (−1 for no point) and a way to
/// measure the distance of any point from it.
struct Hull {
    dimension: i32,
    origin: DVec3,
    /// Orthonormal directions spanning the hull (as many as the dimension, at most 2 kept: a
    /// three-dimensional hull contains every point).
    axes: Vec<DVec3>,
}

impl Hull {
    /// Greedy farthest-point construction: a point, the farthest from it, the farthest from
    /// their line, the farthest from that plane. Each distance is compared with `tolerance`.
    fn of(points: &[DVec3], tolerance: f64) -> Hull {
        let Some(&origin) = points.first() else { return Hull { dimension: -1, origin: DVec3::ZERO, axes: vec![] } };
        let mut hull = Hull { dimension: 0, origin, axes: Vec::new() };
        while hull.dimension < 3 {
            let (far, distance) = points
                .iter()
                .map(|&p| (p, hull.distance(p)))
                .fold((origin, 0.0), |best, x| if x.1 > best.1 { x } else { best });
            if distance <= tolerance {
                break;
            }
            hull.dimension += 1;
            if hull.dimension < 3 {
                hull.axes.push(hull.offset(far).normalize());
            }
        }
        hull
    }

    /// The part of `p − origin` not in the hull's span.
    fn offset(&self, p: DVec3) -> DVec3 {
        let mut d = p - self.origin;
        for &a in &self.axes {
            d -= d.dot(a) * a;
        }
        d
    }

    fn distance(&self, p: DVec3) -> f64 {
        if self.dimension >= 3 { 0.0 } else { self.offset(p).length() }
    }
}

/// Refuses when the fixed vertices among `set` span fewer than `needed` dimensions (3 for a
/// closed part, 2 for a boundary loop) while some vertex of `set` lies off their hull.
fn check_set(cage: &PolyMesh, fixed: &[bool], set: &[VertexId], needed: i32, scale: &Scale, name: &str) -> Result<()> {
    let anchors: Vec<VertexId> = set.iter().copied().filter(|v| fixed[v.index()]).collect();
    let points: Vec<DVec3> = anchors.iter().map(|&v| scale.map(cage.position(v))).collect();
    // The unit frame spans at most 2·√3 across; the tolerance is relative to the part's diagonal.
    let tolerance = FLAT_TOLERANCE * 2.0 * 3f64.sqrt();
    let hull = Hull::of(&points, tolerance);
    if hull.dimension >= needed {
        return Ok(());
    }
    let off: Vec<VertexId> = set
        .iter()
        .copied()
        .filter(|v| {
            !fixed[v.index()] && (hull.dimension < 0 || hull.distance(scale.map(cage.position(*v))) > tolerance)
        })
        .collect();
    if off.is_empty() && hull.dimension >= 0 {
        // Every vertex lies in the hull already (a flat cage): the flat result is the cage's.
        return Ok(());
    }
    let closed = needed == 3;
    let subject = if closed { "its closed surface" } else { "that boundary" };
    let (what, fate) = match hull.dimension {
        -1 => ("has no fixed vertex".to_string(), format!("{subject} has nothing to hold it and shrinks away")),
        0 if anchors.len() == 1 => {
            (format!("has only vertex {} fixed", anchors[0].0), format!("{subject} would shrink to that point"))
        }
        0 => (
            format!("has fixed vertices {}, all at one point", list(&anchors)),
            format!("{subject} would shrink to that point"),
        ),
        1 => (
            format!("has fixed vertices {}, all on one line", list(&anchors)),
            format!("{subject} would collapse onto that line"),
        ),
        _ => (
            format!("has fixed vertices {}, all in one plane", list(&anchors)),
            format!("{subject} would flatten into that plane"),
        ),
    };
    // A closed part needs four fixed vertices spanning space, a loop three spanning a plane.
    let missing = needed - hull.dimension;
    let shape = if closed { "not all in one plane" } else { "not all on one line" };
    let advice = match (hull.dimension, missing) {
        (-1, _) => format!("fix at least {missing} of vertices {} ({shape})", list(&off)),
        (_, 1) => format!("fix at least one of vertices {}", list(&off)),
        _ => format!("fix at least {missing} more of vertices {} ({shape} with the fixed ones)", list(&off)),
    };
    Err(Error::Input(format!("{name} {what}: {fate}; {advice}")))
}

/// Connected parts of the cage (vertices joined by edges), each sorted, in order of their
/// smallest vertex. Isolated vertices belong to no part.
fn components(cage: &PolyMesh) -> Vec<Vec<VertexId>> {
    let n = cage.vertex_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for e in cage.edges() {
        let (a, b) = cage.edge_vertices(e);
        let (ra, rb) = (root(&mut parent, a.0), root(&mut parent, b.0));
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
    let mut index_of_root = vec![u32::MAX; n];
    let mut parts: Vec<Vec<VertexId>> = Vec::new();
    for v in cage.vertices() {
        if cage.is_isolated(v) {
            continue;
        }
        let r = root(&mut parent, v.0) as usize;
        if index_of_root[r] == u32::MAX {
            index_of_root[r] = parts.len() as u32;
            parts.push(Vec::new());
        }
        parts[index_of_root[r] as usize].push(v);
    }
    parts
}

/// The open boundary loops of one part, each as its vertices in loop order.
fn boundary_loops(cage: &PolyMesh, part: &[VertexId]) -> Vec<Vec<VertexId>> {
    let mut seen = std::collections::HashSet::new();
    let mut loops = Vec::new();
    for &v in part {
        for h in cage.outgoing(v) {
            if !cage.is_boundary_halfedge(h) || seen.contains(&h) {
                continue;
            }
            let mut vertices = Vec::new();
            let mut g: HalfedgeId = h;
            while seen.insert(g) {
                vertices.push(cage.from_vertex(g));
                g = cage.next(g);
            }
            vertices.sort_unstable();
            vertices.dedup();
            loops.push(vertices);
        }
    }
    loops
}

/// "0–7, 9, 12–14": sorted vertices as ranges, shortened past [`LIST_LIMIT`] ranges.
fn ranges(vertices: &[VertexId]) -> String {
    let mut sorted: Vec<u32> = vertices.iter().map(|v| v.0).collect();
    sorted.sort_unstable();
    sorted.dedup();
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for v in sorted {
        match runs.last_mut() {
            Some((_, end)) if *end + 1 == v => *end = v,
            _ => runs.push((v, v)),
        }
    }
    let shown: Vec<String> = runs
        .iter()
        .take(LIST_LIMIT)
        .map(|&(a, b)| match b - a {
            0 => a.to_string(),
            1 => format!("{a}, {b}"),
            _ => format!("{a}–{b}"),
        })
        .collect();
    let rest: u32 = runs.iter().skip(LIST_LIMIT).map(|&(a, b)| b - a + 1).sum();
    if rest > 0 { format!("{}, … ({rest} more)", shown.join(", ")) } else { shown.join(", ") }
}

/// Vertices one by one ("0, 1, 2, 3"), or as ranges when there are many.
fn list(vertices: &[VertexId]) -> String {
    if vertices.len() <= LIST_LIMIT {
        vertices.iter().map(|v| v.0.to_string()).collect::<Vec<_>>().join(", ")
    } else {
        ranges(vertices)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(scale: f64) -> PolyMesh {
        let p =
            (0..8).map(|i| scale * DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
        let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    /// An open 3 × 2 quad grid, bent so no four vertices of it are in one plane by accident.
    fn patch() -> PolyMesh {
        let mut p = Vec::new();
        for j in 0..3 {
            for i in 0..4 {
                let (x, y) = (i as f64, j as f64);
                p.push(DVec3::new(x, y, 0.3 * x * x - 0.2 * y * y + 0.1 * x * y));
            }
        }
        let faces: Vec<[u32; 4]> =
            (0..2u32).flat_map(|j| (0..3u32).map(move |i| j * 4 + i)).map(|v| [v, v + 1, v + 5, v + 4]).collect();
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    fn flags(n: usize, fixed: &[u32]) -> Vec<bool> {
        (0..n as u32).map(|v| fixed.contains(&v)).collect()
    }

    fn refusal(cage: &PolyMesh, fixed: &[u32]) -> String {
        check_anchoring(cage, &flags(cage.vertex_count(), fixed)).unwrap_err().to_string()
    }

    #[test]
    fn a_closed_part_needs_fixed_vertices_spanning_space() {
        let c = cube(1.0);
        let none = refusal(&c, &[]);
        assert!(none.starts_with("component of vertices 0–7 has no fixed vertex"), "{none}");
        assert!(none.contains("fix at least 4 of vertices 0, 1, 2, 3, 4, 5, 6, 7 (not all in one plane)"), "{none}");
        let one = refusal(&c, &[3]);
        assert!(one.contains("has only vertex 3 fixed") && one.contains("shrink to that point"), "{one}");
        assert!(one.contains("fix at least 3 more of vertices 0, 1, 2, 4, 5, 6, 7"), "{one}");
        let line = refusal(&c, &[0, 1]);
        assert!(line.contains("all on one line") && line.contains("fix at least 2 more"), "{line}");
        // The bottom face: every other vertex is off its plane.
        let plane = refusal(&c, &[0, 1, 2, 3]);
        assert_eq!(
            plane,
            "component of vertices 0–7 has fixed vertices 0, 1, 2, 3, all in one plane: its closed surface would \
             flatten into that plane; fix at least one of vertices 4, 5, 6, 7"
        );
        // A diagonal plane through four vertices: the other four are off it.
        let diagonal = refusal(&c, &[0, 3, 4, 7]);
        assert!(diagonal.contains("fix at least one of vertices 1, 2, 5, 6"), "{diagonal}");
        for ok in [&[0, 1, 2, 4][..], &[0, 3, 5, 6], &[0, 1, 2, 3, 4, 5, 6, 7]] {
            check_anchoring(&c, &flags(8, ok)).unwrap();
        }
    }

    #[test]
    fn every_open_boundary_loop_needs_fixed_vertices_off_one_line() {
        let p = patch();
        // The 3 × 2 patch has one loop of its 10 boundary vertices (5 and 6 are inside).
        let corners = [0, 3, 8, 11];
        check_anchoring(&p, &flags(12, &corners)).unwrap();
        let two = refusal(&p, &[0, 11, 5, 6]);
        assert!(two.starts_with("the open boundary through vertices 0–4, 7–11 has fixed vertices 0, 11"), "{two}");
        assert!(two.contains("collapse onto that line") && two.contains("fix at least one of vertices"), "{two}");
        let none = refusal(&p, &[5, 6]);
        assert!(none.contains("has no fixed vertex") && none.contains("fix at least 3 of vertices"), "{none}");
        // Interior vertices need not be fixed, and coplanar boundary vertices are fine: a flat
        // patch is a valid result.
        check_anchoring(&p, &flags(12, &[0, 1, 2])).unwrap();
    }

    #[test]
    fn each_part_is_checked_on_its_own() {
        // Two cubes side by side: the second is anchored, the first is not.
        let (a, b) = (cube(1.0), cube(1.0));
        let mut positions = a.positions().to_vec();
        positions.extend(b.positions().iter().map(|&p| p + DVec3::new(3.0, 0.0, 0.0)));
        let mut faces = a.polygons();
        faces.extend(b.polygons().into_iter().map(|f| f.into_iter().map(|v| v + 8).collect::<Vec<_>>()));
        let two = PolyMesh::from_polygons(positions, &faces).unwrap();
        let err = refusal(&two, &[0, 1, 2, 3, 8, 9, 10, 12]);
        assert!(err.starts_with("component of vertices 0–7 has fixed vertices 0, 1, 2, 3"), "{err}");
        let err = refusal(&two, &[0, 1, 2, 4, 8]);
        assert!(err.starts_with("component of vertices 8–15 has only vertex 8 fixed"), "{err}");
        check_anchoring(&two, &flags(16, &[0, 1, 2, 4, 9, 10, 12, 15])).unwrap();
    }

    #[test]
    fn the_rule_is_the_same_at_every_size_and_position() {
        for scale in [1e-200, 1e-30, 1.0, 1e30, 1e300] {
            let mut c = cube(scale);
            let rotation = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
            for p in c.positions_mut() {
                *p = rotation * *p + DVec3::splat(0.25 * scale);
            }
            assert!(refusal(&c, &[0, 1, 2, 3]).contains("all in one plane"), "scale {scale}");
            check_anchoring(&c, &flags(8, &[0, 1, 2, 4])).unwrap();
            // Just off the plane by much more than the tolerance: anchored.
            let lifted = c.position(VertexId(3)) + 1e-4 * scale * (rotation * DVec3::Z);
            c.set_position(VertexId(3), lifted);
            check_anchoring(&c, &flags(8, &[0, 1, 2, 3])).unwrap();
        }
    }

    #[test]
    fn a_flat_cage_is_accepted_as_it_is() {
        // A closed "pillow" whose vertices all lie in one plane: the flat result is the cage.
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let pillow = PolyMesh::from_polygons(p, &[[0, 1, 2, 3], [0, 3, 2, 1]]).unwrap();
        check_anchoring(&pillow, &flags(4, &[0, 1, 2])).unwrap();
        assert!(refusal(&pillow, &[0]).contains("has only vertex 0 fixed"));
    }

    #[test]
    fn long_lists_are_shortened() {
        let v: Vec<VertexId> = (0..40).filter(|i| i % 2 == 0).map(VertexId).collect();
        let text = ranges(&v);
        assert!(text.ends_with("… (8 more)"), "{text}");
        assert_eq!(ranges(&[VertexId(4), VertexId(2), VertexId(3), VertexId(9)]), "2–4, 9");
    }
}
