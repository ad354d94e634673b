//! A triangle mesh indexed for ray casts and closest points: a bounding-volume hierarchy of our
//! own over the triangles in Morton order, built in parallel, with parry's triangle queries at
//! its leaves.
//!
//! The build sorts the triangles by the Morton code of their centroids and splits each range
//! where the codes' highest differing bit changes (a linear BVH, Lauterbach et al. 2009, built
//! top down), with up to `LEAF` triangles in a leaf. The ranges above `PARALLEL` triangles are
//! planned on one thread (binary searches only) and the subtrees below them built side by side,
//! so a million triangles index in a fraction of what parry's one-thread binned build takes.
//! The tree is a function of the sorted codes alone: the same on any number of threads.
//!
//! The searches read a copy of the tree laid out for memory, four children to a node: each node
//! of the binary tree at an even depth takes its children's children (or a child that is a
//! leaf), their boxes in `f32` rounded outwards, by coordinate, in two cache lines. A search then
//! takes half the steps down the binary tree's, each a node whose four boxes are tested together.
//! The leaves read their triangles' corners from the positions renumbered by first use in leaf
//! order, so neighbouring leaves share them and a million triangles' corners take 24 MB, not 72.
//!
//! A closest-point search walks the tree depth first, nearest child first, and skips every box at
//! least as far as the best triangle found (distances squared); the triangle test is parry's
//! (Voronoi regions, so a point on an edge or corner says which). Of triangles equally far, the
//! one numbered first wins, so the answer does not depend on the tree's shape or the order it
//! was walked in (nor on a bound given to a search, as long as the answer lies within it). A ray
//! cast walks it the same way with the boxes' slab tests, the first hit's parameter taking the
//! place of the distance. Every box is widened by a relative 1e-10 of the model's size, so
//! rounding in a box test never hides a triangle. Queries take `&self` and are answered
//! independently, so they run in parallel and give the same answers on any number of threads.
//!
//! parry's own vector type is `glam` of another version than Taut's, so points cross the
//! boundary as plain coordinates.
//!
//! This file holds the index and its searches; `tree.rs` the hierarchy: its nodes, their search
//! layout, the searches' pending stack, and the build.

use crate::{DVec3, Error, Result};
use parry3d_f64::math::Vector;
use parry3d_f64::query::{PointQueryWithLocation, Ray, RayCast};
use parry3d_f64::shape::Triangle;
use rayon::prelude::*;
use tree::{Corners, EMPTY, MAX_TRIANGLES, NONE, Node, Pending, WIDTH, Wide, decode, hierarchy, met, morton, refit};

mod tree;

/// Consecutive queries of a [`coherent_order`] block: each after the first is bounded by its
/// predecessor's answer.
pub const BLOCK: usize = 32;

/// The points' indices in Morton order over their bounding box (ties by index), so that a block
/// of consecutive ones lies close together whatever order the points came in. Deterministic on
/// any number of threads.
pub fn coherent_order(points: &[DVec3]) -> Vec<u32> {
    let (lo, hi) = crate::mesh::bounding_box(points).unwrap_or((DVec3::ZERO, DVec3::ZERO));
    let extent = (hi - lo).max_element();
    let scale = if extent > 0.0 && extent.is_finite() { f64::from((1u32 << 21) - 1) / extent } else { 0.0 };
    // Non-finite coordinates saturate; they only cost their block its bound.
    let mut keyed: Vec<(u64, u32)> =
        points.par_iter().enumerate().map(|(i, p)| (morton(*p, lo, scale), i as u32)).collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// A triangle surface ready for queries.
pub struct SurfaceIndex {
    /// The hierarchy, depth first, as built and refitted.
    nodes: Vec<Node>,
    /// Its inner nodes as the searches read them ([`widen`]); the root first.
    wide: Vec<Wide>,
    /// The triangles' corners by slot (the leaves' order).
    corners: Corners,
    /// The triangle at each slot, as numbered in [`new`](Self::new).
    ids: Vec<u32>,
    /// How far every box is widened beyond its triangles.
    pad: f64,
}

impl std::fmt::Debug for SurfaceIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SurfaceIndex({} triangles, {} nodes)", self.ids.len(), self.nodes.len())
    }
}

fn to_parry(p: DVec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn from_parry(p: Vector) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

/// How far boxes are widened: a relative 1e-10 of the model's size and distance from the origin.
fn padding(positions: &[DVec3]) -> f64 {
    let (lo, hi) = crate::mesh::bounding_box(positions).unwrap_or((DVec3::ZERO, DVec3::ZERO));
    let size = (hi - lo).max_element().max(lo.abs().max(hi.abs()).max_element());
    if size.is_finite() { 1e-10 * size } else { 0.0 }
}

impl SurfaceIndex {
    /// Indexes triangles over positions; an error for no triangles or an index out of range.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Result<Self> {
        let fail = |why: String| Error::Input(format!("cannot index the surface for distance queries ({why})"));
        if triangles.is_empty() {
            return Err(fail("it has no triangles".into()));
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(fail(format!("{} triangles is more than it can number", triangles.len())));
        }
        if let Some(t) = triangles.par_iter().position_first(|t| t.iter().any(|&v| v as usize >= positions.len())) {
            return Err(fail(format!("triangle {t} refers to a vertex past the {} given", positions.len())));
        }
        let centroid = |t: &[u32; 3]| t.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / 3.0;
        // The box of the finite centroids.
        let (lo, hi) = triangles
            .par_iter()
            .map(centroid)
            .filter(|c| c.is_finite())
            .fold(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), c| (lo.min(c), hi.max(c)))
            .reduce(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), (c, d)| (a.min(c), b.max(d)));
        let (lo, hi) = if lo.x <= hi.x { (lo, hi) } else { (DVec3::ZERO, DVec3::ZERO) };
        let extent = (hi - lo).max_element();
        let scale = if extent > 0.0 && extent.is_finite() { f64::from((1u32 << 21) - 1) / extent } else { 0.0 };
        let mut keyed: Vec<(u64, u32)> =
            triangles.par_iter().enumerate().map(|(t, c)| (morton(centroid(c), lo, scale), t as u32)).collect();
        keyed.par_sort_unstable();
        let (keys, ids): (Vec<u64>, Vec<u32>) = keyed.into_par_iter().unzip();
        let corners = Corners::new(triangles, &ids, positions);
        let pad = padding(positions);
        let (nodes, wide) = hierarchy(&keys, &corners, pad);
        Ok(SurfaceIndex { nodes, wide, corners, ids, pad })
    }

    /// Whether the triangle at `slot` was numbered before the one at `other`: of triangles
    /// equally near, that one is the answer, whatever order the tree was walked in.
    fn first(&self, slot: usize, other: usize) -> bool {
        self.ids[slot] < self.ids[other]
    }

    /// Walks the tree for `search`, depth first: at each node on to the child the search meets
    /// first, the others pending, and back to the latest pending child whose bound the search
    /// still keeps.
    fn walk(&self, search: &mut impl Search) {
        let mut pending = Pending::new();
        let mut current = 0u32;
        loop {
            let (count, at) = decode(current);
            if count > 0 {
                for slot in at..at + count {
                    search.triangle(self, slot, self.corners.get(slot));
                }
            } else if let Some(next) = pending.descend(search.children(&self.wide[at])) {
                current = next;
                continue;
            }
            match pending.pop(|bound| search.keep(bound)) {
                Some(next) => current = next,
                None => return,
            }
        }
    }

    /// The closest triangle to `p` nearer than `max`: its slot, the point and where on the
    /// triangle it lies.
    fn nearest(&self, p: DVec3, max: f64) -> Option<(usize, Vector, [f64; 3])> {
        // A positive bound whose square underflows still admits a point at distance 0.
        let best = if max > 0.0 { (max * max).max(f64::from_bits(1)) } else { max * max };
        let mut search = Closest { p, q: to_parry(p), best, found: None };
        self.walk(&mut search);
        search.found
    }

    /// The closest point of the surface to `p` (`p` itself when `p` is not finite).
    pub fn closest_point(&self, p: DVec3) -> DVec3 {
        self.nearest(p, f64::INFINITY).map_or(p, |(_, x, _)| from_parry(x))
    }

    /// The closest point of the surface to `p`, the index of its triangle (in the order given to
    /// [`new`](Self::new)) and its barycentric coordinates there.
    pub fn closest_on_triangle(&self, p: DVec3) -> (DVec3, usize, [f64; 3]) {
        self.closest_on_triangle_within(p, f64::INFINITY).unwrap_or((p, 0, [1.0, 0.0, 0.0]))
    }

    /// [`closest_point`](Self::closest_point) when it is nearer than `max` to `p`, else `None`;
    /// the search skips every part of the hierarchy that far, so a good bound (a point of the
    /// surface known to be near) makes it several times faster for the same answer.
    pub fn closest_point_within(&self, p: DVec3, max: f64) -> Option<DVec3> {
        self.nearest(p, max).map(|(_, x, _)| from_parry(x))
    }

    /// [`closest_on_triangle`](Self::closest_on_triangle) when it is nearer than `max` to `p`,
    /// else `None` (see [`closest_point_within`](Self::closest_point_within)).
    pub fn closest_on_triangle_within(&self, p: DVec3, max: f64) -> Option<(DVec3, usize, [f64; 3])> {
        self.nearest(p, max).map(|(slot, x, w)| (from_parry(x), self.ids[slot] as usize, w))
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

    /// Moves the vertices (the same number, the triangles unchanged) and refits the hierarchy's
    /// boxes to them, which costs a fraction of indexing them anew: the answers are exact, only
    /// the tree's shape is that of the old positions.
    pub fn set_positions(&mut self, positions: &[DVec3]) {
        self.pad = padding(positions);
        self.corners.set_positions(positions);
        self.wide = refit(&mut self.nodes, &self.corners, self.pad);
    }

    /// The distance from `p` to the surface.
    pub fn distance(&self, p: DVec3) -> f64 {
        (self.closest_point(p) - p).length()
    }

    /// The parameter `t ≤ max` of the first point `origin + t·direction` on the surface
    /// (`direction` of unit length), if any.
    pub fn cast(&self, origin: DVec3, direction: DVec3, max: f64) -> Option<f64> {
        self.cast_to_triangle(origin, direction, max).map(|(t, _)| t)
    }

    /// Like [`cast`](Self::cast), with the index of the triangle met (in the order given to
    /// [`new`](Self::new)).
    pub fn cast_to_triangle(&self, origin: DVec3, direction: DVec3, max: f64) -> Option<(f64, usize)> {
        if !(origin.is_finite() && direction.is_finite()) {
            return None;
        }
        let ray = Ray::new(to_parry(origin), to_parry(direction));
        let mut search = FirstHit { origin, inverse: DVec3::ONE / direction, ray, best: max, found: None };
        self.walk(&mut search);
        search.found.map(|(t, slot)| (t, self.ids[slot] as usize))
    }
}

/// What a search does at the tree's leaves and nodes ([`SurfaceIndex::walk`] walks for it).
trait Search {
    /// Tests the triangle at `slot`, whose corners are given.
    fn triangle(&mut self, index: &SurfaceIndex, slot: usize, corners: [Vector; 3]);
    /// Each child of `node` the search meets, with a lower bound of what it can hold ([`met`]),
    /// or [`NONE`].
    fn children(&self, node: &Wide) -> [u64; WIDTH];
    /// Whether a child met with this bound may still hold a better answer.
    fn keep(&self, bound: f64) -> bool;
}

/// A closest-point search: squared distances, the best triangle found so far.
struct Closest {
    p: DVec3,
    q: Vector,
    best: f64,
    found: Option<(usize, Vector, [f64; 3])>,
}

impl Search for Closest {
    #[inline]
    fn triangle(&mut self, index: &SurfaceIndex, slot: usize, [a, b, c]: [Vector; 3]) {
        let (projection, location) = Triangle::new(a, b, c).project_local_point_and_get_location(self.q, false);
        let d = (projection.point - self.q).length_squared();
        if d < self.best || (d == self.best && self.found.is_some_and(|(first, _, _)| index.first(slot, first))) {
            self.best = d;
            // Inside a solid cannot happen for a surface query; weigh the corners evenly.
            let weights = location.barycentric_coordinates().unwrap_or([1.0 / 3.0; 3]);
            self.found = Some((slot, projection.point, weights));
        }
    }

    #[inline]
    fn children(&self, w: &Wide) -> [u64; WIDTH] {
        let d = w.distances_squared(self.p);
        std::array::from_fn(|k| if w.child[k] != EMPTY && d[k] < self.best { met(w.child[k], d[k]) } else { NONE })
    }

    #[inline]
    fn keep(&self, bound: f64) -> bool {
        bound < self.best
    }
}

/// A ray cast: ray parameters, the first hit found so far (its parameter and slot).
struct FirstHit {
    origin: DVec3,
    inverse: DVec3,
    ray: Ray,
    best: f64,
    found: Option<(f64, usize)>,
}

impl Search for FirstHit {
    #[inline]
    fn triangle(&mut self, index: &SurfaceIndex, slot: usize, [a, b, c]: [Vector; 3]) {
        if let Some(t) = Triangle::new(a, b, c).cast_local_ray(&self.ray, self.best, false)
            && self.found.is_none_or(|(_, first)| t < self.best || (t == self.best && index.first(slot, first)))
        {
            self.best = t;
            self.found = Some((t, slot));
        }
    }

    #[inline]
    fn children(&self, w: &Wide) -> [u64; WIDTH] {
        std::array::from_fn(|k| match w.entry(k, self.origin, self.inverse, self.best) {
            Some(t) if w.child[k] != EMPTY => met(w.child[k], t),
            _ => NONE,
        })
    }

    #[inline]
    fn keep(&self, bound: f64) -> bool {
        bound <= self.best
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
    fn of_triangles_equally_near_the_one_numbered_first_is_the_answer() {
        // A unit square split along its diagonal, in both orders, and as a fan of many thin
        // triangles around its centre, where a point above the centre is equally far from all
        // of them (the projections are exact): the answer is the triangle numbered first
        // whichever way the tree was built and walked, bounded or not.
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let above = DVec3::new(0.5, 0.5, 1.0);
        for triangles in [[[0, 1, 2], [0, 2, 3]], [[0, 2, 3], [0, 1, 2]]] {
            let index = SurfaceIndex::new(&p, &triangles).unwrap();
            assert_eq!(index.closest_on_triangle(above).1, 0, "{triangles:?}");
            assert_eq!(index.closest_on_triangle_within(above, 1.5).map(|a| a.1), Some(0));
            assert_eq!(index.cast_to_triangle(above, -DVec3::Z, 10.0), Some((1.0, 0)), "{triangles:?}");
        }
        // A fan of 64 triangles around (0, 0, 0) over a circle, numbered from a rotating start:
        // deep enough for several levels of the hierarchy. (A cast through their shared corner
        // meets them at parameters a rounding apart, so only closest points tie there.)
        for start in [0usize, 17, 40, 63] {
            let mut positions = vec![DVec3::ZERO];
            positions.extend((0..64).map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 64.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            }));
            let triangles: Vec<[u32; 3]> =
                (0..64).map(|k| (k + start) % 64).map(|k| [0, 1 + k as u32, 1 + ((k + 1) % 64) as u32]).collect();
            let index = SurfaceIndex::new(&positions, &triangles).unwrap();
            let (x, t, _) = index.closest_on_triangle(DVec3::new(0.0, 0.0, 2.0));
            assert_eq!((x, t), (DVec3::ZERO, 0), "start {start}");
            assert_eq!(index.closest_on_triangle_within(DVec3::new(0.0, 0.0, 2.0), 2.5).map(|a| a.1), Some(0));
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
