//! A uniform grid over points for "which points lie within `r` of here" queries, used by merge
//! by distance and by the mirror partner search.
//!
//! Cells are at least `2r` wide (the callers make them about `8r`), so the ball of radius `r`
//! round a query point overlaps at most two cells along each axis — its own and, when it crosses
//! a wall, the neighbour beyond — and a query looks at one to eight cells, about two on average
//! for cells `8r` wide. Points are sorted by cell once and each occupied cell maps to its
//! run of that order through a hash map with a cheap multiplicative hash (cell keys are not
//! attacker-chosen in a way that matters: a crowded cell only costs time). Linear for evenly
//! spread points; all points in one cell degrade to quadratic, as any grid does.

use crate::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A fast hasher for small integer keys (a multiply–xorshift mix per word).
#[derive(Default)]
pub(super) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        let x = self.0 ^ (self.0 >> 29);
        x.wrapping_mul(0xbf58_476d_1ce4_e5b9) ^ (x >> 32)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0 ^ x).wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(23);
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
}

/// A cell's integer coordinates, hashed as one mixed word rather than byte by byte.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Cell([i64; 3]);

impl std::hash::Hash for Cell {
    fn hash<H: Hasher>(&self, state: &mut H) {
        let [x, y, z] = self.0.map(|c| c as u64);
        state.write_u64(x ^ y.rotate_left(21) ^ z.rotate_left(42));
    }
}

type Cells = HashMap<Cell, (u32, u32), BuildHasherDefault<CellHasher>>;

/// Points of a set, bucketed by cell.
pub(super) struct PointGrid {
    cell: f64,
    order: Vec<u32>,
    cells: Cells,
}

impl std::fmt::Debug for PointGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PointGrid({} points in {} cells of {})", self.order.len(), self.cells.len(), self.cell)
    }
}

impl PointGrid {
    /// A grid over `points[i]` for each listed `i`, for queries of radius up to `cell / 2`.
    pub fn new(points: &[DVec3], listed: impl Iterator<Item = u32>, cell: f64) -> Self {
        let key = |p: DVec3| cell_of(p, cell);
        let mut keyed: Vec<(Cell, u32)> = listed.map(|i| (Cell(key(points[i as usize])), i)).collect();
        keyed.sort_unstable();
        let mut cells = Cells::with_capacity_and_hasher(keyed.len(), Default::default());
        let mut start = 0;
        while start < keyed.len() {
            let mut end = start + 1;
            while end < keyed.len() && keyed[end].0 == keyed[start].0 {
                end += 1;
            }
            cells.insert(keyed[start].0, (start as u32, end as u32));
            start = end;
        }
        PointGrid { cell, order: keyed.into_iter().map(|(_, i)| i).collect(), cells }
    }

    /// Calls `visit` with every point in the cells that the ball of radius `r` (at most half a
    /// cell) round `p` overlaps: a superset of the points within `r`, which the caller measures.
    /// Along each axis that is the point's own cell and, when the ball crosses a wall, the one
    /// beyond it, so with cells several radii wide most queries read one or two cells.
    pub fn near(&self, p: DVec3, r: f64, mut visit: impl FnMut(u32)) {
        debug_assert!(r <= 0.5 * self.cell);
        let base = cell_of(p, self.cell);
        let (lo, hi) = (cell_of(p - DVec3::splat(r), self.cell), cell_of(p + DVec3::splat(r), self.cell));
        // Per axis: the offsets (−1, 0, +1) of the cells the interval [p − r, p + r] touches.
        let span = |a: usize| (lo[a].saturating_sub(base[a]).max(-1))..=(hi[a].saturating_sub(base[a]).min(1));
        for dx in span(0) {
            for dy in span(1) {
                for dz in span(2) {
                    let at = [base[0].saturating_add(dx), base[1].saturating_add(dy), base[2].saturating_add(dz)];
                    if let Some(&(s, e)) = self.cells.get(&Cell(at)) {
                        for &i in &self.order[s as usize..e as usize] {
                            visit(i);
                        }
                    }
                }
            }
        }
    }
}

fn cell_of(p: DVec3, cell: f64) -> [i64; 3] {
    (p / cell).floor().to_array().map(|c| c as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_within_the_radius_is_visited() {
        // A jittered lattice against brute force, with the radius at the cell's limit.
        let mut points = Vec::new();
        let mut s = 1u64;
        let mut unit = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..600 {
            points.push(DVec3::new(unit(), unit(), unit()) * 3.0 - DVec3::splat(1.0));
        }
        for (r, cell) in [(0.2, 0.4), (0.05, 0.4)] {
            let grid = PointGrid::new(&points, 0..points.len() as u32, cell);
            for (i, &p) in points.iter().enumerate() {
                let mut seen = Vec::new();
                grid.near(p, r, |j| seen.push(j));
                for (j, &q) in points.iter().enumerate() {
                    if p.distance(q) <= r {
                        assert!(seen.contains(&(j as u32)), "{i} misses {j}");
                    }
                }
            }
        }
    }
}
