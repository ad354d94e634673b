//! Step 3: where each limit point of the cage should go on the original (the paper §2.3).
//!
//! The paper casts the half-line from the cage vertex `A` through its limit point `B` and,
//! among the hits, keeps the one with the smallest `|X − A| + |X − B|`. Taken literally that
//! can pick a far surface (across an ear, through a thin part), so Taut casts the whole line
//! through `B` both ways but only up to one local edge length `h` (the mean length of the cage
//! edges at the vertex) from `B`. Along the line, `|X − A| + |X − B|` grows with the distance
//! from `B` on either side of the segment `AB`, so the first hit from `B` in each direction is
//! the best of its side and the rule needs only two first-hit casts. With no hit within `h`,
//! the target is the closest point of the original. When `A ≈ B` the line is the cage's vertex
//! normal. A vertex on an open border aims at its own position: borders are locked during
//! simplification, so it is a vertex of the original's border, and the boundary curve of the
//! limit surface then interpolates the original's border vertices (the paper has no borders).

use super::surface_index::SurfaceIndex;
use crate::DVec3;
use crate::mesh::PolyMesh;

/// Below this fraction of the local edge length, `A` and `B` are taken as one point.
const SAME_POINT: f64 = 1e-9;

/// How one cage vertex found its target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Found {
    /// A ray hit within one local edge length of the limit point.
    Ray,
    /// No such hit: the closest point of the original.
    Closest,
    /// A border vertex: its own position.
    Border,
}

/// Local edge length at each cage vertex: the mean length of its edges.
pub fn local_edge_lengths(cage: &PolyMesh) -> Vec<f64> {
    cage.vertices()
        .map(|v| {
            let p = cage.position(v);
            let (sum, count) =
                cage.vertex_neighbors(v).fold((0.0, 0usize), |(s, c), u| (s + (cage.position(u) - p).length(), c + 1));
            if count == 0 { 0.0 } else { sum / count as f64 }
        })
        .collect()
}

/// The target of cage vertex `i`: `a` its position, `b` its limit point, `normal` the cage's
/// vertex normal there, `h` the local edge length, `border` whether it lies on an open border.
pub fn target(original: &SurfaceIndex, a: DVec3, b: DVec3, normal: DVec3, h: f64, border: bool) -> (DVec3, Found) {
    if border {
        return (a, Found::Border);
    }
    let along = b - a;
    let direction =
        if along.length() > SAME_POINT * h { along.normalize() } else { normal.try_normalize().unwrap_or(DVec3::ZERO) };
    if direction != DVec3::ZERO && h > 0.0 {
        let forward = original.cast(b, direction, h);
        let backward = original.cast(b, -direction, h);
        // Cost |X − A| + |X − B| of a hit t from B: forward 2t + |AB|; backward |AB| while
        // within the segment, then |AB| + 2 (t − |AB|).
        let gap = along.length();
        let cost_forward = forward.map(|t| 2.0 * t + gap);
        let cost_backward = backward.map(|t| gap + 2.0 * (t - gap).max(0.0));
        let best = match (cost_forward, cost_backward) {
            (Some(f), Some(bk)) if f < bk => forward.map(|t| b + t * direction),
            (_, Some(_)) => backward.map(|t| b - t * direction),
            (Some(_), None) => forward.map(|t| b + t * direction),
            (None, None) => None,
        };
        if let Some(x) = best {
            return (x, Found::Ray);
        }
    }
    (original.closest_point(b), Found::Closest)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two parallel planes z = 0 and z = 1 (a thin part), as one index.
    fn slab() -> SurfaceIndex {
        let mut p = Vec::new();
        for z in [0.0, 1.0] {
            p.extend([
                DVec3::new(-9.0, -9.0, z),
                DVec3::new(9.0, -9.0, z),
                DVec3::new(9.0, 9.0, z),
                DVec3::new(-9.0, 9.0, z),
            ]);
        }
        SurfaceIndex::new(&p, &[[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]]).unwrap()
    }

    #[test]
    fn the_near_surface_wins_over_a_far_one() {
        let s = slab();
        // A above the bottom plane, B just below A: the half-line A→B hits z = 0; z = 1 lies
        // behind A. Both are on the line; the rule keeps z = 0 (between A and B is impossible).
        let (x, how) = target(&s, DVec3::new(0.0, 0.0, 0.3), DVec3::new(0.0, 0.0, 0.2), DVec3::Z, 0.5, false);
        assert_eq!(how, Found::Ray);
        assert!((x - DVec3::ZERO).length() < 1e-12, "{x}");
        // With a window smaller than the distance to either plane: the closest point.
        let (x, how) = target(&s, DVec3::new(0.0, 0.0, 0.45), DVec3::new(0.0, 0.0, 0.4), DVec3::Z, 0.1, false);
        assert_eq!(how, Found::Closest);
        assert!((x - DVec3::ZERO).length() < 1e-12, "{x}");
    }

    #[test]
    fn a_hit_between_a_and_b_is_preferred_and_borders_stay() {
        let s = slab();
        // Segment A–B crosses z = 1: forward from B, z = 0 is 0.9 away (cost 2·0.9 + |AB|);
        // backward, z = 1 lies inside the segment (cost |AB|), and wins.
        let (x, how) = target(&s, DVec3::new(0.0, 0.0, 1.2), DVec3::new(0.0, 0.0, 0.9), DVec3::Z, 1.0, false);
        assert_eq!(how, Found::Ray);
        assert!((x - DVec3::Z).length() < 1e-12, "{x}");
        // A = B: the normal decides.
        let (x, _) = target(&s, DVec3::new(1.0, 2.0, 0.3), DVec3::new(1.0, 2.0, 0.3), DVec3::Z, 0.5, false);
        assert!((x - DVec3::new(1.0, 2.0, 0.0)).length() < 1e-12, "{x}");
        let a = DVec3::new(5.0, 5.0, 5.0);
        assert_eq!(target(&s, a, DVec3::ZERO, DVec3::Z, 1.0, true), (a, Found::Border));
    }
}
