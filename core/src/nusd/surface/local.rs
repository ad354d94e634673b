//! Local re-solves after a drag: the levels are re-converged only around the moved cage
//! vertices, with the truncation measured (issue 13).
//!
//! Every level's system is pinned at the fixed cage vertices, so the change a drag makes to a
//! level's fixed point dies off quickly with the distance from the moved vertex: measured on a
//! 1 024-face torus cage, one ring of cage faces away it is already below the tolerance, and
//! the rest of a million-vertex surface changes by far less. Re-solving the whole level spends
//! nearly all its work where nothing changes. So after an edit that only moved cage vertices
//! (and a solve that had finished, or a local one still under way), each level is solved on a
//! *region*: the vertices within `W` cage rings of the moved vertices (in steps of the level's
//! stencil: `W · 2^level` steps), the rest held at their converged values as boundary data. The
//! multigrid cycles and the plain iteration run unchanged on the region (coarse grids use the
//! region of their own level, which nests: a coarse vertex is the fine vertex of the same
//! index), and the level's fixed point inside the region is the plain iteration's with that
//! boundary data.
//!
//! The truncation is measured, not assumed. The change of the level since its solve began is
//! taken per band of one cage ring ([`Region::band`]); with the largest change `m_k` in band
//! `k`, the change decays by `q = m_{W-2} / m_{W-3}` a ring, and what the held vertices miss is
//! estimated as the geometric tail `m_{W-2} · q / (1 − q)` (the last band, next to the held
//! vertices, is pulled towards zero by them and is not used). A change that does not decay
//! (`q` over [`FLAT`]) is not the drag's response but the previous solve polishing its own
//! error (a solve stops within its threshold, not at the fixed point), which that solve's
//! estimate already bounded; it counts once, as `m_{W-2}`. When the tail is over
//! [`TRUNCATION_SHARE`] of the threshold, the region grows by two rings and the cycles go on
//! from where they are; when the region would cover more than [`MAX_SHARE`] of a level, the solve
//! goes on over the whole level. The tail is added to the level's reported distance to the fixed
//! point, and the level is accepted only when that sum is under the threshold.
//!
//! Where it is weak: the tail assumes the change keeps decaying geometrically beyond the region,
//! which holds while fixed cage vertices pin the surface all round; with many unfixed cage
//! vertices the change spreads far and the region grows to the whole level (no loss, no gain).

use super::hierarchy::LevelTopology;
use super::operator::{Operator, Role};
use crate::DVec3;
use crate::mesh::{PolyMesh, VertexId};
use rayon::prelude::*;

/// The largest share of a level's vertices a region may cover before the level is solved whole.
pub const MAX_SHARE: f64 = 0.4;
/// Cage rings of a first region.
pub const FIRST_WIDTH: usize = 4;
/// Rings a region grows by when its truncation is too large.
pub const GROWTH: usize = 2;
/// The truncation accepted, as a fraction of the threshold.
pub const TRUNCATION_SHARE: f64 = 0.5;
/// A ratio of successive bands' changes from which the change counts as flat (see
/// [`Region::truncation`]).
pub const FLAT: f64 = 0.8;
/// Region vertices per parallel task; smaller regions are done on one thread (waking the
/// pool costs more than the work).
const CHUNK: usize = 4096;

/// `f` of every listed vertex, in order: on several threads for long lists, with the same
/// result for any number of threads.
pub fn map_vertices<T: Send>(vertices: &[u32], f: impl Fn(u32) -> T + Sync + Send) -> Vec<T> {
    let mut out = Vec::new();
    map_vertices_into(vertices, &mut out, f);
    out
}

/// [`map_vertices`] into a buffer kept between calls (a sweep of a large region would
/// otherwise map fresh pages every time).
pub fn map_vertices_into<T: Send>(vertices: &[u32], out: &mut Vec<T>, f: impl Fn(u32) -> T + Sync + Send) {
    if vertices.len() < 2 * CHUNK {
        out.clear();
        out.extend(vertices.iter().map(|&v| f(v)));
    } else {
        vertices.par_iter().with_min_len(CHUNK).map(|&v| f(v)).collect_into_vec(out);
    }
}

/// The vertices of one level that a local solve iterates.
#[derive(Clone, Debug, Default)]
pub struct Region {
    /// Which set of seeds it was grown from (the solver's count of local solves).
    pub seeds_id: u64,
    /// Cage rings around the seeds.
    pub width: usize,
    /// The vertices, sorted.
    pub vertices: Vec<u32>,
    /// Per vertex of `vertices`: its distance from the seeds in cage rings (stencil steps over
    /// `2^level`, rounded down).
    pub band: Vec<u32>,
    /// The fixed vertices among `vertices` (their `R` is recomputed).
    pub fixed: Vec<u32>,
}

impl Region {
    /// The vertices of a level (`level` refinements of the cage, connectivity `mesh`) within
    /// `width` cage rings of the seeds (cage vertices, which keep their index at every level), by
    /// a breadth-first search over the mesh's edges. (Not over the operator's stencil: a vertex on
    /// an open boundary reads only its two boundary neighbours, so a search over the stencil from
    /// a boundary seed would never leave the boundary, though the vertices inside read it.)
    pub fn around(op: &Operator, mesh: &PolyMesh, level: usize, seeds: &[u32], seeds_id: u64, width: usize) -> Region {
        let n = op.role.len();
        let steps_per_ring = 1u32 << level.min(30);
        let limit = (width as u32).saturating_mul(steps_per_ring);
        let mut distance = vec![u32::MAX; n];
        let mut queue: Vec<u32> = Vec::new();
        for &s in seeds {
            if (s as usize) < n && distance[s as usize] == u32::MAX {
                distance[s as usize] = 0;
                queue.push(s);
            }
        }
        let mut head = 0;
        while head < queue.len() {
            let v = queue[head] as usize;
            head += 1;
            let d = distance[v];
            if d >= limit {
                continue;
            }
            for j in mesh.vertex_neighbors(VertexId(v as u32)) {
                if distance[j.index()] == u32::MAX {
                    distance[j.index()] = d + 1;
                    queue.push(j.0);
                }
            }
        }
        queue.sort_unstable();
        let band = queue.iter().map(|&v| distance[v as usize] / steps_per_ring).collect();
        let fixed = queue.iter().copied().filter(|&v| op.role[v as usize] == Role::Fixed).collect();
        Region { seeds_id, width, vertices: queue, band, fixed }
    }

    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// The estimated change beyond the region (see the module docs) from the change of every
    /// region vertex since the level's solve began (`start`, in region order) to `now`.
    pub fn truncation(&self, op: &Operator, start: &[DVec3], now: &[DVec3]) -> f64 {
        let bands = self.width + 1;
        let mut largest = vec![0.0f64; bands];
        for (k, &v) in self.vertices.iter().enumerate() {
            if op.role[v as usize] != Role::Moving {
                continue;
            }
            let b = (self.band[k] as usize).min(bands - 1);
            let d = (now[v as usize] - start[k]).length();
            largest[b] = if d.is_nan() { f64::NAN } else { largest[b].max(d) };
        }
        if self.width < 3 {
            return f64::INFINITY;
        }
        let (inner, outer) = (largest[self.width - 3], largest[self.width - 2]);
        if outer.is_nan() || inner.is_nan() {
            return f64::NAN;
        }
        if outer == 0.0 {
            return 0.0;
        }
        let q = outer / inner;
        if q < FLAT {
            outer * q / (1.0 - q)
        } else {
            // Not a decaying response: the polishing of the previous solve's own error, which
            // that solve's estimate bounded; what it adds beyond is taken as the edge's change.
            outer
        }
    }
}

/// `fine[v] += ` the parent average of `coarse_delta`, for the listed fine vertices only.
pub fn prolong_add_on(topology: &LevelTopology, vertices: &[u32], coarse_delta: &[DVec3], fine: &mut [DVec3]) {
    let (offsets, parents) = (&topology.parent_offsets, &topology.parents);
    let add = map_vertices(vertices, |v| {
        let range = offsets[v as usize] as usize..offsets[v as usize + 1] as usize;
        let count = range.len() as f64;
        let sum: DVec3 = parents[range].iter().map(|&p| coarse_delta[p as usize]).sum();
        sum / count
    });
    for (&v, a) in vertices.iter().zip(add) {
        fine[v as usize] += a;
    }
}

/// The children of every coarse vertex (the fine vertices that have it as a parent), as a CSR
/// list: the transpose of [`LevelTopology::parents`].
#[derive(Clone, Debug, Default)]
pub struct Children {
    pub offsets: Vec<u32>,
    pub children: Vec<u32>,
    /// Per fine vertex, scratch for [`Children::of_set`] (all false between calls).
    mark: Vec<bool>,
}

impl Children {
    pub fn of(topology: &LevelTopology, coarse_count: usize) -> Children {
        let n = topology.vertex_count();
        let mut offsets = vec![0u32; coarse_count + 1];
        for &p in &topology.parents {
            offsets[p as usize + 1] += 1;
        }
        for c in 0..coarse_count {
            offsets[c + 1] += offsets[c];
        }
        let mut fill = offsets.clone();
        let mut children = vec![0u32; topology.parents.len()];
        for v in 0..n {
            for &p in &topology.parents[topology.parent_offsets[v] as usize..topology.parent_offsets[v + 1] as usize] {
                children[fill[p as usize] as usize] = v as u32;
                fill[p as usize] += 1;
            }
        }
        Children { offsets, children, mark: vec![false; n] }
    }

    /// The children of the listed coarse vertices, without repeats (in the order met).
    pub fn of_set(&mut self, coarse: &[u32]) -> Vec<u32> {
        let mut out = Vec::new();
        for &c in coarse {
            for &v in &self.children[self.offsets[c as usize] as usize..self.offsets[c as usize + 1] as usize] {
                if !self.mark[v as usize] {
                    self.mark[v as usize] = true;
                    out.push(v);
                }
            }
        }
        for &v in &out {
            self.mark[v as usize] = false;
        }
        out
    }
}

/// Where a level's residual buffer may be nonzero.
#[derive(Clone, Debug)]
pub enum Support {
    /// Anywhere.
    All,
    /// Only at these vertices.
    Some(Vec<u32>),
}

impl Default for Support {
    fn default() -> Self {
        Support::Some(Vec::new())
    }
}

/// Which vertices of a level may differ from what the next finer level last absorbed: all, or
/// a list (in the order recorded, without repeats; a mark per vertex keeps it so in O(1)).
#[derive(Clone, Debug, Default)]
pub struct Touched {
    all: bool,
    list: Vec<u32>,
    mark: Vec<bool>,
}

impl Touched {
    /// Every vertex.
    pub fn everything() -> Touched {
        Touched { all: true, ..Default::default() }
    }

    /// Records that any vertex may have changed.
    pub fn set_all(&mut self) {
        self.clear_list();
        self.all = true;
    }

    /// Records the vertices (of a level of `n`).
    pub fn add(&mut self, vertices: &[u32], n: usize) {
        if self.all {
            return;
        }
        if self.mark.len() != n {
            self.mark = vec![false; n];
        }
        for &v in vertices {
            if !self.mark[v as usize] {
                self.mark[v as usize] = true;
                self.list.push(v);
            }
        }
    }

    /// The record, leaving it empty: `None` for every vertex.
    pub fn take(&mut self) -> Option<Vec<u32>> {
        if std::mem::take(&mut self.all) {
            self.clear_list();
            return None;
        }
        for &v in &self.list {
            self.mark[v as usize] = false;
        }
        Some(std::mem::take(&mut self.list))
    }

    fn clear_list(&mut self) {
        for &v in &self.list {
            self.mark[v as usize] = false;
        }
        self.list.clear();
    }
}
