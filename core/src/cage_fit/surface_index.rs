//! A triangle mesh indexed for ray casts and closest points: a thin wrapper over parry's
//! `TriMesh`, whose bounding-volume hierarchy answers both queries in about logarithmic time.
//!
//! parry's own vector type is `glam` of another version than Taut's, so points cross the
//! boundary as plain coordinates. Queries take `&self` and are answered independently, so they
//! run in parallel and give the same answers on any number of threads.

use crate::{DVec3, Error, Result};
use parry3d_f64::math::Vector;
use parry3d_f64::query::{PointQuery, PointQueryWithLocation, Ray, RayCast};
use parry3d_f64::shape::TriMesh;
use rayon::prelude::*;

/// Consecutive queries of a [`coherent_blocks`] block: each after the first is bounded by its
/// predecessor's answer.
pub const BLOCK: usize = 32;

/// The points' indices in Morton order over their bounding box (ties by index), so that a block
/// of consecutive ones lies close together whatever order the points came in. Deterministic on
/// any number of threads.
pub fn coherent_order(points: &[DVec3]) -> Vec<u32> {
    let (lo, hi) = crate::mesh::bounding_box(points).unwrap_or((DVec3::ZERO, DVec3::ZERO));
    let extent = (hi - lo).max_element();
    let scale = if extent > 0.0 && extent.is_finite() { f64::from((1u32 << 21) - 1) / extent } else { 0.0 };
    // Spreads the low 21 bits of `x` to every third bit.
    let spread = |x: u64| {
        let mut x = x & 0x1f_ffff;
        x = (x | x << 32) & 0x001f_0000_0000_ffff;
        x = (x | x << 16) & 0x001f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        (x | x << 2) & 0x1249_2492_4924_9249
    };
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            // Non-finite coordinates saturate; they only cost their block its bound.
            let q = ((*p - lo) * scale).to_array().map(|c| c.clamp(0.0, f64::from((1u32 << 21) - 1)) as u64);
            (spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2, i as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// A triangle surface ready for queries.
pub struct SurfaceIndex {
    mesh: TriMesh,
}

impl std::fmt::Debug for SurfaceIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SurfaceIndex({} triangles)", self.mesh.num_triangles())
    }
}

fn to_parry(p: DVec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn from_parry(p: Vector) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

impl SurfaceIndex {
    /// Indexes triangles over positions (indices must be in range).
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Result<Self> {
        let vertices = positions.iter().map(|&p| to_parry(p)).collect();
        let mesh = TriMesh::new(vertices, triangles.to_vec())
            .map_err(|e| Error::Input(format!("cannot index the surface for distance queries ({e})")))?;
        Ok(SurfaceIndex { mesh })
    }

    /// The closest point of the surface to `p`.
    pub fn closest_point(&self, p: DVec3) -> DVec3 {
        from_parry(self.mesh.project_local_point(to_parry(p), false).point)
    }

    /// The closest point of the surface to `p`, the index of its triangle (in the order given to
    /// [`new`](Self::new)) and its barycentric coordinates there.
    pub fn closest_on_triangle(&self, p: DVec3) -> (DVec3, usize, [f64; 3]) {
        let (projection, (triangle, location)) = self.mesh.project_local_point_and_get_location(to_parry(p), false);
        let point = from_parry(projection.point);
        let triangle = triangle as usize;
        let weights = location.barycentric_coordinates().unwrap_or_else(|| {
            // Inside a solid cannot happen for a surface query; weigh the corners evenly.
            [1.0 / 3.0; 3]
        });
        (point, triangle, weights)
    }

    /// [`closest_point`](Self::closest_point) when it is at most `max` from `p`, else `None`;
    /// the search skips every part of the hierarchy farther than `max`, so a good bound (a point
    /// of the surface known to be near) makes it several times faster for the same answer.
    pub fn closest_point_within(&self, p: DVec3, max: f64) -> Option<DVec3> {
        self.mesh.project_local_point_with_max_dist(to_parry(p), false, max).map(|q| from_parry(q.point))
    }

    /// [`closest_on_triangle`](Self::closest_on_triangle) when it is at most `max` from `p`, else
    /// `None` (see [`closest_point_within`](Self::closest_point_within)).
    pub fn closest_on_triangle_within(&self, p: DVec3, max: f64) -> Option<(DVec3, usize, [f64; 3])> {
        let (projection, (triangle, location)) =
            self.mesh.project_local_point_and_get_location_with_max_dist(to_parry(p), false, max)?;
        let weights = location.barycentric_coordinates().unwrap_or([1.0 / 3.0; 3]);
        Some((from_parry(projection.point), triangle as usize, weights))
    }

    /// [`closest_point`](Self::closest_point), searching only as far as `near`, a point of the
    /// surface known to be at least that close (the same answer, several times faster).
    pub fn closest_point_near(&self, p: DVec3, near: Option<DVec3>) -> DVec3 {
        closest_within(near.map(|q| (q - p).length()), |b| self.closest_point_within(p, b), || self.closest_point(p))
    }

    /// [`closest_on_triangle`](Self::closest_on_triangle), searching only as far as `near` (see
    /// [`closest_point_near`](Self::closest_point_near)).
    pub fn closest_on_triangle_near(&self, p: DVec3, near: Option<DVec3>) -> (DVec3, usize, [f64; 3]) {
        closest_within(
            near.map(|q| (q - p).length()),
            |b| self.closest_on_triangle_within(p, b),
            || self.closest_on_triangle(p),
        )
    }

    /// Moves the vertices (the same number, the triangles unchanged) and refits the hierarchy
    /// to them, which costs a fraction of indexing them anew.
    pub fn set_positions(&mut self, positions: &[DVec3]) {
        let vertices: Vec<_> = positions.iter().map(|&p| to_parry(p)).collect();
        self.mesh.set_vertices(&vertices);
    }

    /// The distance from `p` to the surface.
    pub fn distance(&self, p: DVec3) -> f64 {
        (self.closest_point(p) - p).length()
    }

    /// The parameter `t ≤ max` of the first point `origin + t·direction` on the surface
    /// (`direction` of unit length), if any.
    pub fn cast(&self, origin: DVec3, direction: DVec3, max: f64) -> Option<f64> {
        self.mesh.cast_local_ray(&Ray::new(to_parry(origin), to_parry(direction)), max, false)
    }

    /// Like [`cast`](Self::cast), with the index of the triangle met (in the order given to
    /// [`new`](Self::new)).
    pub fn cast_to_triangle(&self, origin: DVec3, direction: DVec3, max: f64) -> Option<(f64, usize)> {
        let ray = Ray::new(to_parry(origin), to_parry(direction));
        let hit = self.mesh.cast_local_ray_and_get_normal(&ray, max, false)?;
        Some((hit.time_of_impact, hit.subshape as usize % self.mesh.num_triangles().max(1)))
    }
}

/// The closest point of a surface to a point by a search bounded by `bound`, the distance to a
/// point of the surface known to be that near, or an unbounded search without one. The bound is
/// widened by a relative 1e-9 (the known point is recomputed in floating point), and should it
/// still miss, the search is repeated without it: the answer is the unbounded search's.
pub(super) fn closest_within<T>(bound: Option<f64>, within: impl Fn(f64) -> Option<T>, unbounded: impl Fn() -> T) -> T {
    bound.filter(|b| b.is_finite()).and_then(|b| within(b * (1.0 + 1e-9) + 1e-300)).unwrap_or_else(unbounded)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_on_a_unit_square_match_closed_forms() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let index = SurfaceIndex::new(&p, &[[0, 1, 2], [0, 2, 3]]).unwrap();
        assert!((index.closest_point(DVec3::new(0.3, 0.6, 2.0)) - DVec3::new(0.3, 0.6, 0.0)).length() < 1e-12);
        assert!((index.distance(DVec3::new(2.0, 0.5, 0.0)) - 1.0).abs() < 1e-12);
        let t = index.cast(DVec3::new(0.5, 0.5, 3.0), -DVec3::Z, 10.0).unwrap();
        assert!((t - 3.0).abs() < 1e-12);
        assert!(index.cast(DVec3::new(0.5, 0.5, 3.0), DVec3::Z, 10.0).is_none());
        assert!(index.cast(DVec3::new(0.5, 0.5, 3.0), -DVec3::Z, 2.0).is_none());
        // Below the diagonal x = y lies the first triangle, above it the second.
        assert_eq!(index.cast_to_triangle(DVec3::new(0.7, 0.2, 1.0), -DVec3::Z, 10.0).map(|h| h.1), Some(0));
        assert_eq!(index.cast_to_triangle(DVec3::new(0.2, 0.7, -1.0), DVec3::Z, 10.0).map(|h| h.1), Some(1));
        // The closest point as a barycentric combination of its triangle's corners.
        for q in [DVec3::new(0.7, 0.2, 1.0), DVec3::new(0.2, 0.7, -1.0), DVec3::new(2.0, -1.0, 0.5)] {
            let (x, t, w) = index.closest_on_triangle(q);
            let [a, b, c] = [[0, 1, 2], [0, 2, 3]][t].map(|i| p[i]);
            assert!((w[0] * a + w[1] * b + w[2] * c - x).length() < 1e-12, "{q}: {x} in {t} at {w:?}");
            assert!((x - index.closest_point(q)).length() < 1e-12);
        }
    }

    #[test]
    fn bounded_queries_answer_as_the_unbounded_ones_within_the_bound_and_refitting_as_a_new_index() {
        // A bumpy sphere of 2,000-odd triangles and points around it.
        let sphere = crate::mesh::primitives::icosphere(3, 1.0).unwrap();
        let bumpy: Vec<DVec3> =
            sphere.positions().iter().map(|p| *p * (1.0 + 0.1 * (5.0 * p.x).sin() * (3.0 * p.y).cos())).collect();
        let triangles = sphere.triangles();
        let mut index = SurfaceIndex::new(&bumpy, &triangles).unwrap();
        let points: Vec<DVec3> = (0..200)
            .map(|k| {
                let t = k as f64 * 0.7;
                DVec3::new(t.sin() * 1.4, (1.3 * t).cos() * 0.9, (0.4 * t).sin() * 1.2) * (0.5 + 0.005 * k as f64)
            })
            .collect();
        for &p in &points {
            let (x, t, w) = index.closest_on_triangle(p);
            let d = (x - p).length();
            // A bound beyond a point of the surface at least as far: the same answer, the same
            // triangle (the search is strict: a bound equal to the distance finds nothing).
            let corner = bumpy[triangles[t][0] as usize];
            let bound = (corner - p).length().max(d) * (1.0 + 1e-9);
            assert_eq!(index.closest_point_within(p, bound), Some(index.closest_point(p)));
            assert_eq!(index.closest_on_triangle_within(p, bound), Some((x, t, w)));
            // A bound short of the distance finds nothing.
            assert_eq!(index.closest_point_within(p, 0.5 * d), None);
            assert_eq!(index.closest_on_triangle_within(p, 0.5 * d), None);
        }
        // Moved vertices, refitted: the answers of an index built on them.
        let moved: Vec<DVec3> = bumpy.iter().map(|p| *p * 1.05 + DVec3::new(0.02, -0.01, 0.03)).collect();
        index.set_positions(&moved);
        let fresh = SurfaceIndex::new(&moved, &triangles).unwrap();
        for &p in &points {
            let (a, b) = (index.closest_on_triangle(p), fresh.closest_on_triangle(p));
            assert!((a.0 - b.0).length() < 1e-12, "{p}: {a:?} vs {b:?}");
            assert!(((a.0 - p).length() - fresh.distance(p)).abs() < 1e-12);
        }
    }

    #[test]
    fn queries_in_coherent_blocks_answer_as_unbounded_searches_on_any_thread_count() {
        let sphere = crate::mesh::primitives::icosphere(4, 1.0).unwrap();
        let bumpy: Vec<DVec3> =
            sphere.positions().iter().map(|p| *p * (1.0 + 0.1 * (5.0 * p.x).sin() * (3.0 * p.y).cos())).collect();
        let index = SurfaceIndex::new(&bumpy, &sphere.triangles()).unwrap();
        // Points around the surface in a scrambled order (a multiplicative hash of the index).
        let n = 5000u64;
        let points: Vec<DVec3> = (0..n)
            .map(|k| {
                let j = (k * 2_654_435_761) % n;
                let t = j as f64 * 0.013;
                let dir = DVec3::new(t.sin() * (0.7 * t).cos(), t.cos() * (0.7 * t).cos(), (0.7 * t).sin());
                dir * (0.6 + 0.8 * ((j * 7919) % 101) as f64 / 100.0)
            })
            .collect();

        let order = coherent_order(&points);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "a permutation");
        // Blocks of the order are compact: their mean extent is a fraction of that of blocks
        // taken in the scrambled input order.
        let extent = |block: &[u32]| {
            let p: Vec<DVec3> = block.iter().map(|&i| points[i as usize]).collect();
            crate::mesh::bounding_box(&p).map_or(0.0, |(lo, hi)| (hi - lo).length())
        };
        let mean = |o: &[u32]| o.chunks(BLOCK).map(extent).sum::<f64>() / o.len().div_ceil(BLOCK) as f64;
        let input: Vec<u32> = (0..n as u32).collect();
        assert!(mean(&order) < 0.5 * mean(&input), "{} vs {}", mean(&order), mean(&input));

        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut silent = super::super::Silent;
                let mut monitor = super::super::Monitor::new(&mut silent);
                let points_near = monitor
                    .map_near(0.0..1.0, &points, |p, near: Option<&DVec3>| index.closest_point_near(p, near.copied()))
                    .unwrap();
                let on_triangles = monitor
                    .map_near(0.0..1.0, &points, |p, near: Option<&(DVec3, usize, [f64; 3])>| {
                        index.closest_on_triangle_near(p, near.map(|n| n.0))
                    })
                    .unwrap();
                (points_near, on_triangles)
            })
        };
        let (points_near, on_triangles) = run(2);
        for (k, &p) in points.iter().enumerate() {
            let unbounded = index.closest_point(p);
            // The same closest point up to a tie between triangles (equally far).
            assert!(((points_near[k] - p).length() - (unbounded - p).length()).abs() < 1e-12, "{k}");
            assert!((on_triangles[k].0 - points_near[k]).length() < 1e-12, "{k}");
        }
        assert_eq!(run(1), (points_near, on_triangles), "the same answers on one thread");
    }
}
