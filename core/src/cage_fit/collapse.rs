//! The last edge collapses of a simplification, each checked to keep the surface a manifold of
//! the same topology (Garland and Heckbert 1997, with the link condition of Dey et al. 1999).
//!
//! meshoptimizer keeps the topology of borders and seams but not always that of the surface:
//! near a low face count it may flatten a handle into two triangles on the same three corners,
//! or leave an edge with three triangles (seen on a scanned coupling of genus 9, whose cage
//! could not go below 744 triangles where MeshLab reaches 186). Such a cage cannot be
//! subdivided. So the simplifier stops at the smallest valid count meshoptimizer reaches, and
//! this file collapses on from there, cheapest first:
//! - each vertex carries the area-weighted quadric of its triangles' planes, summed as vertices
//!   merge;
//! - an edge collapses to the point its quadric is least at (optimal placement), or to the
//!   better of its ends and middle where that point is ill-determined, or onto a locked end;
//! - a collapse is allowed only when the two ends' common neighbours are exactly the corners
//!   opposite the edge (the link condition: the surface stays a manifold of the same genus) and
//!   no remaining triangle turns over or becomes a sliver.
//!
//! Deterministic: the heap orders equal costs by vertex indices.

use crate::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A symmetric 4 × 4 quadric `[A b; bᵀ c]` of the squared distance to planes.
#[derive(Clone, Copy, Debug, Default)]
struct Quadric {
    a: [f64; 6],
    b: [f64; 3],
    c: f64,
}

impl Quadric {
    /// `weight` times the squared distance to the plane through `p` with unit normal `n`.
    fn plane(n: DVec3, p: DVec3, weight: f64) -> Self {
        let d = -n.dot(p);
        let w = weight;
        Quadric {
            a: [w * n.x * n.x, w * n.x * n.y, w * n.x * n.z, w * n.y * n.y, w * n.y * n.z, w * n.z * n.z],
            b: [w * n.x * d, w * n.y * d, w * n.z * d],
            c: w * d * d,
        }
    }

    fn add(&self, o: &Quadric) -> Quadric {
        let mut q = *self;
        for k in 0..6 {
            q.a[k] += o.a[k];
        }
        for k in 0..3 {
            q.b[k] += o.b[k];
        }
        q.c += o.c;
        q
    }

    fn eval(&self, p: DVec3) -> f64 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let quad = xx * p.x * p.x
            + 2.0 * xy * p.x * p.y
            + 2.0 * xz * p.x * p.z
            + yy * p.y * p.y
            + 2.0 * yz * p.y * p.z
            + zz * p.z * p.z;
        (quad + 2.0 * (self.b[0] * p.x + self.b[1] * p.y + self.b[2] * p.z) + self.c).max(0.0)
    }

    /// The point where the quadric is least, if well determined.
    fn minimiser(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let m = glam::DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz));
        let det = m.determinant();
        let scale = (xx + yy + zz).powi(3);
        if det.abs() <= 1e-9 * scale || !det.is_finite() {
            return None;
        }
        let p = m.inverse() * -DVec3::from_array(self.b);
        p.is_finite().then_some(p)
    }
}

/// A candidate collapse in the heap: cheapest first, ties by vertex indices.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Candidate {
    cost: f64,
    u: u32,
    v: u32,
    stamps: (u32, u32),
}

impl Eq for Candidate {}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        other.cost.total_cmp(&self.cost).then_with(|| (other.u, other.v).cmp(&(self.u, self.v)))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The mesh being collapsed.
struct Collapser {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    alive: Vec<bool>,
    /// Per vertex: the triangles that use it (dead ones pruned lazily).
    around: Vec<Vec<u32>>,
    quadrics: Vec<Quadric>,
    locked: Vec<bool>,
    stamp: Vec<u32>,
    faces: usize,
}

impl Collapser {
    fn live_around(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.around[v as usize].iter().copied().filter(|&t| self.alive[t as usize])
    }

    fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut n: Vec<u32> =
            self.live_around(v).flat_map(|t| self.triangles[t as usize]).filter(|&w| w != v).collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// Where the edge would collapse to and at what cost; `None` when both ends are locked.
    fn placement(&self, u: u32, v: u32) -> Option<(DVec3, f64)> {
        let (lu, lv) = (self.locked[u as usize], self.locked[v as usize]);
        let q = self.quadrics[u as usize].add(&self.quadrics[v as usize]);
        let (pu, pv) = (self.positions[u as usize], self.positions[v as usize]);
        let p = match (lu, lv) {
            (true, true) => return None,
            (true, false) => pu,
            (false, true) => pv,
            (false, false) => q
                .minimiser()
                .filter(|p| (*p - 0.5 * (pu + pv)).length() <= 2.0 * (pu - pv).length())
                .unwrap_or_else(|| {
                    let mid = 0.5 * (pu + pv);
                    [pu, pv, mid].into_iter().min_by(|a, b| q.eval(*a).total_cmp(&q.eval(*b))).unwrap_or(mid)
                }),
        };
        Some((p, q.eval(p)))
    }

    fn push(&self, heap: &mut BinaryHeap<Candidate>, u: u32, v: u32) {
        let (u, v) = if u < v { (u, v) } else { (v, u) };
        if let Some((_, cost)) = self.placement(u, v) {
            heap.push(Candidate { cost, u, v, stamps: (self.stamp[u as usize], self.stamp[v as usize]) });
        }
    }

    /// Collapses `v` into `u` at `p` when the link condition holds and no triangle turns over.
    fn try_collapse(&mut self, u: u32, v: u32, p: DVec3) -> bool {
        let shared: Vec<u32> = self.live_around(u).filter(|&t| self.triangles[t as usize].contains(&v)).collect();
        if shared.is_empty() {
            return false;
        }
        let (nu, nv) = (self.neighbours(u), self.neighbours(v));
        let common = nu.iter().filter(|w| nv.binary_search(w).is_ok()).count();
        if common != shared.len() || self.faces < shared.len() + 4 {
            return false;
        }
        // No remaining triangle of either end may turn over or collapse to a sliver.
        for w in [u, v] {
            for t in self.live_around(w) {
                let tri = self.triangles[t as usize];
                if tri.contains(&u) && tri.contains(&v) {
                    continue;
                }
                let corners = tri.map(|c| self.positions[c as usize]);
                let moved = tri.map(|c| if c == u || c == v { p } else { self.positions[c as usize] });
                let before = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                let after = (moved[1] - moved[0]).cross(moved[2] - moved[0]);
                if before.dot(after) <= 0.2 * before.length() * after.length() {
                    return false;
                }
                let longest = (0..3).map(|k| (moved[(k + 1) % 3] - moved[k]).length_squared()).fold(0.0, f64::max);
                if after.length() < 1e-3 * longest {
                    return false;
                }
            }
        }
        for &t in &shared {
            self.alive[t as usize] = false;
        }
        self.faces -= shared.len();
        let moved: Vec<u32> = self.live_around(v).collect();
        for &t in &moved {
            for c in &mut self.triangles[t as usize] {
                if *c == v {
                    *c = u;
                }
            }
        }
        let mut merged: Vec<u32> = self.live_around(u).chain(moved).collect();
        merged.sort_unstable();
        merged.dedup();
        self.around[u as usize] = merged;
        self.around[v as usize].clear();
        self.positions[u as usize] = p;
        self.quadrics[u as usize] = self.quadrics[u as usize].add(&self.quadrics[v as usize]);
        self.locked[u as usize] |= self.locked[v as usize];
        self.stamp[u as usize] += 1;
        self.stamp[v as usize] += 1;
        true
    }
}

/// Collapses edges of a manifold triangle mesh until it has at most `target_faces` triangles or
/// no allowed collapse is left. `locked` vertices do not move. Returns the kept triangles over
/// the input's vertex numbering and the vertices' positions (moved ones updated).
pub fn collapse_to(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    locked: &[bool],
    target_faces: usize,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let n = positions.len();
    let mut around = vec![Vec::new(); n];
    let mut quadrics = vec![Quadric::default(); n];
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| positions[i as usize]);
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        let plane = cross.try_normalize().map(|normal| Quadric::plane(normal, a, area));
        for &i in tri {
            around[i as usize].push(t as u32);
            if let Some(q) = plane {
                quadrics[i as usize] = quadrics[i as usize].add(&q);
            }
        }
    }
    let mut state = Collapser {
        positions: positions.to_vec(),
        triangles: triangles.to_vec(),
        alive: vec![true; triangles.len()],
        around,
        quadrics,
        locked: locked.to_vec(),
        stamp: vec![0; n],
        faces: triangles.len(),
    };
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let mut heap = BinaryHeap::new();
    for (u, v) in edges {
        state.push(&mut heap, u, v);
    }
    while state.faces > target_faces {
        let Some(c) = heap.pop() else { break };
        if (state.stamp[c.u as usize], state.stamp[c.v as usize]) != c.stamps {
            continue;
        }
        let Some((p, _)) = state.placement(c.u, c.v) else { continue };
        // Collapse onto the locked end if there is one (it keeps its index).
        let (keep, gone) = if state.locked[c.v as usize] { (c.v, c.u) } else { (c.u, c.v) };
        if state.try_collapse(keep, gone, p) {
            for w in state.neighbours(keep) {
                state.push(&mut heap, keep, w);
            }
        }
    }
    let kept = state.triangles.iter().zip(&state.alive).filter(|(_, a)| **a).map(|(t, _)| *t).collect();
    (state.positions, kept)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::PolyMesh;

    /// A torus of `m × n` quads split into triangles.
    fn torus(m: usize, n: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for i in 0..m {
            for j in 0..n {
                let (a, b) = (i as f64 / m as f64 * std::f64::consts::TAU, j as f64 / n as f64 * std::f64::consts::TAU);
                p.push(DVec3::new((2.0 + 0.7 * b.cos()) * a.cos(), (2.0 + 0.7 * b.cos()) * a.sin(), 0.7 * b.sin()));
            }
        }
        let id = |i: usize, j: usize| ((i % m) * n + j % n) as u32;
        let mut t = Vec::new();
        for i in 0..m {
            for j in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (p, t)
    }

    #[test]
    fn a_torus_keeps_its_genus_and_stays_manifold_down_to_few_faces() {
        let (p, t) = torus(40, 20);
        for target in [400, 100, 30] {
            let (q, kept) = collapse_to(&p, &t, &vec![false; p.len()], target);
            assert!(kept.len() <= target + 2, "{target}: {} faces", kept.len());
            let used: std::collections::BTreeSet<u32> = kept.iter().flatten().copied().collect();
            let mut edges: Vec<(u32, u32)> = kept
                .iter()
                .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
                .collect();
            edges.sort_unstable();
            edges.dedup();
            // Euler characteristic of a torus: V − E + F = 0.
            assert_eq!(used.len() as i64 - edges.len() as i64 + kept.len() as i64, 0, "{target}");
            // A manifold surface: PolyMesh accepts it (every edge has two triangles, consistently oriented).
            let map: std::collections::BTreeMap<u32, u32> =
                used.iter().enumerate().map(|(k, &v)| (v, k as u32)).collect();
            let positions = used.iter().map(|&v| q[v as usize]).collect();
            let faces: Vec<[u32; 3]> = kept.iter().map(|t| t.map(|v| map[&v])).collect();
            let mesh = PolyMesh::from_polygons(positions, &faces).unwrap();
            assert!(mesh.vertices().all(|v| !mesh.is_boundary_vertex(v)));
            // Optimal placement keeps the vertices near the torus (tube radius 0.7 about the core circle).
            for &v in &used {
                let x = q[v as usize];
                let core = 2.0 * DVec3::new(x.x, x.y, 0.0).normalize();
                let off = ((x - core).length() - 0.7).abs();
                assert!(off < 0.35, "{target}: vertex {v} is {off} off the tube");
            }
        }
    }

    #[test]
    fn locked_vertices_stay_and_the_quadric_minimiser_is_exact_on_a_corner() {
        let (p, t) = torus(12, 8);
        let locked: Vec<bool> = (0..p.len()).map(|v| v % 3 == 0).collect();
        let (q, kept) = collapse_to(&p, &t, &locked, 60);
        for v in kept.iter().flatten() {
            if locked[*v as usize] {
                assert_eq!(q[*v as usize], p[*v as usize]);
            }
        }
        // Three planes x = 1, y = 2, z = 3 meet at (1, 2, 3).
        let q = [DVec3::X, DVec3::Y, DVec3::Z]
            .into_iter()
            .zip([1.0, 2.0, 3.0])
            .map(|(n, d)| Quadric::plane(n, n * d, 1.0))
            .fold(Quadric::default(), |a, b| a.add(&b));
        let m = q.minimiser().unwrap();
        assert!((m - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12, "{m}");
        assert!(q.eval(m) < 1e-20);
        assert!((q.eval(DVec3::ZERO) - 14.0).abs() < 1e-12);
    }
}
