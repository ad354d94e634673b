//! The solver's side of local re-solves ([`crate::nusd::surface::local`]): when to solve
//! locally, the regions of the levels in a cycle, the truncation check that grows them, and
//! propagation of changes between levels that touches only what changed.

use super::SurfaceSolver;
use crate::DVec3;
use crate::nusd::surface::kernel::State;
use crate::nusd::surface::local::{Children, FIRST_WIDTH, GROWTH, MAX_SHARE, Region, TRUNCATION_SHARE, prolong_add_on};

/// A local solve under way: the moved cage vertices and the width of the regions.
#[derive(Clone, Debug)]
pub(super) struct LocalSolve {
    pub seeds: Vec<u32>,
    /// Names this set of seeds (regions grown from it are reused).
    pub id: u64,
    pub width: usize,
}

/// The state a level's solve started from, for roll-backs and the truncation check: the whole
/// level, or the vertices of its region (in region order).
#[derive(Clone, Debug)]
pub(super) struct Snapshot {
    pub vertices: Option<Vec<u32>>,
    pub p: Vec<DVec3>,
    pub r: Vec<DVec3>,
}

impl Snapshot {
    pub fn of(state: &State, region: Option<&Region>) -> Snapshot {
        match region {
            None => Snapshot { vertices: None, p: state.p.clone(), r: state.r.clone() },
            Some(region) => Snapshot {
                vertices: Some(region.vertices.clone()),
                p: region.vertices.iter().map(|&v| state.p[v as usize]).collect(),
                r: region.vertices.iter().map(|&v| state.r[v as usize]).collect(),
            },
        }
    }

    /// Puts the level back where its solve started.
    pub fn restore(&self, state: &mut State) {
        match &self.vertices {
            None => *state = State::new(self.p.clone(), self.r.clone()),
            Some(vertices) => {
                for (k, &v) in vertices.iter().enumerate() {
                    state.p[v as usize] = self.p[k];
                    state.r[v as usize] = self.r[k];
                }
            }
        }
    }

    /// The snapshot over a larger region (or the whole level): vertices outside the old one
    /// have not moved since the solve started, so their start is where they are.
    pub fn widened(&self, state: &State, region: Option<&Region>) -> Snapshot {
        let mut out = Snapshot::of(state, region);
        let Some(old) = &self.vertices else { return self.clone() };
        match &out.vertices {
            None => {
                for (k, &v) in old.iter().enumerate() {
                    out.p[v as usize] = self.p[k];
                    out.r[v as usize] = self.r[k];
                }
            }
            Some(new) => {
                let mut j = 0;
                for (k, &v) in old.iter().enumerate() {
                    while j < new.len() && new[j] < v {
                        j += 1;
                    }
                    if j < new.len() && new[j] == v {
                        out.p[j] = self.p[k];
                        out.r[j] = self.r[k];
                    }
                }
            }
        }
        out
    }
}

impl SurfaceSolver {
    /// Decides, at an edit, whether the levels are re-solved locally: only moved cage
    /// vertices, multigrid on, and the last solve finished or itself local (its seeds are kept).
    pub(super) fn choose_local(&mut self, positions_only: bool, moved: &[bool]) {
        let seeds: Vec<u32> = moved.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
        let finished = self.phase == crate::nusd::surface::Phase::Done;
        self.epoch += 1;
        let id = self.epoch;
        self.local = match self.local.take() {
            _ if !(positions_only && self.multigrid && self.local_allowed && !seeds.is_empty()) => None,
            Some(mut local) if !finished => {
                let before = local.seeds.clone();
                local.seeds.extend(seeds);
                local.seeds.sort_unstable();
                local.seeds.dedup();
                if local.seeds != before {
                    local.id = id;
                }
                local.width = FIRST_WIDTH;
                Some(local)
            }
            Some(local) if finished && local.seeds == seeds => Some(LocalSolve { width: FIRST_WIDTH, ..local }),
            _ if finished => Some(LocalSolve { seeds, id, width: FIRST_WIDTH }),
            _ => None,
        };
        if self.local.is_none() {
            self.go_whole();
        } else {
            let seeds = self.local.as_ref().map_or_else(Vec::new, |l| l.seeds.clone());
            let n = self.levels[0].vertex_count();
            self.levels[0].touched.add(&seeds, n);
        }
    }

    /// Ends local solving: every level is solved whole from now on.
    pub(super) fn go_whole(&mut self) {
        self.local = None;
        for level in &mut self.levels {
            if level.region.is_some() {
                level.set_region(None, 0);
            }
        }
        self.levels[0].touched.set_all();
    }

    /// Sets the regions of the levels the active level's cycles use (every level from the
    /// coarsest grid up to it) for the current width, in a new epoch. Returns false, having
    /// gone back to whole levels, when a region would cover too much of its level.
    pub(super) fn set_regions(&mut self) -> bool {
        let Some(local) = &self.local else { return false };
        let (seeds, id, width) = (local.seeds.clone(), local.id, local.width);
        self.epoch += 1;
        let epoch = self.epoch;
        let low = self.coarsest().min(self.active);
        let mut regions = Vec::new();
        for k in low..=self.active {
            let level = &self.levels[k];
            if level.region.as_ref().is_some_and(|r| r.seeds_id == id && r.width == width) {
                continue;
            }
            let region = Region::around(&level.operator, &level.topology.mesh, k, &seeds, id, width);
            if region.len() as f64 > MAX_SHARE * level.vertex_count() as f64 {
                self.go_whole();
                return false;
            }
            regions.push((k, region));
        }
        for (k, region) in regions {
            self.levels[k].set_region(Some(region), epoch);
        }
        for k in low..=self.active {
            self.levels[k].epoch = epoch;
        }
        true
    }

    /// At the start of a level's solve: its regions (or the whole level), its snapshot, and
    /// the record that its vertices there will change.
    pub(super) fn start_level(&mut self) {
        let local = self.local.is_some() && self.set_regions();
        // The finest level built passes nothing on: a finer one is made from all of it.
        let last = self.active + 1 == self.levels.len();
        let level = &mut self.levels[self.active];
        if !local {
            if level.region.is_some() {
                level.set_region(None, 0);
            }
            level.touched.set_all();
        } else if let Some(region) = level.region.as_ref().filter(|_| !last) {
            let (vertices, n) = (region.vertices.clone(), level.vertex_count());
            level.touched.add(&vertices, n);
        }
        self.snapshot = Some(Snapshot::of(&level.state, level.region.as_ref()));
    }

    /// At convergence of the active level in a local solve: true when the change beyond the
    /// region is small enough (it is then kept for the level's report); otherwise the region
    /// grows (or the level goes whole) and the solve goes on.
    /// `remaining` is the estimated distance to the region's own fixed point.
    pub(super) fn local_accepts(&mut self, remaining: f64) -> bool {
        self.truncation = 0.0;
        let Some(local) = &self.local else { return true };
        let level = &self.levels[self.active];
        let (Some(region), Some(snapshot)) = (&level.region, &self.snapshot) else { return true };
        let tail = region.truncation(&level.operator, &snapshot.p, &level.state.p);
        if tail <= TRUNCATION_SHARE * self.threshold {
            // Small enough: accepted once the region's own solve is close enough too.
            if remaining + tail < self.threshold {
                self.truncation = tail;
                return true;
            }
            return false;
        }
        let width = local.width + GROWTH;
        if let Some(local) = &mut self.local {
            local.width = width;
        }
        let old = self.snapshot.take().expect("checked above");
        let whole = !self.set_regions();
        let last = self.active + 1 == self.levels.len();
        let level = &mut self.levels[self.active];
        if whole {
            level.touched.set_all();
        } else if let Some(region) = level.region.as_ref().filter(|_| !last) {
            let (vertices, n) = (region.vertices.clone(), level.vertex_count());
            level.touched.add(&vertices, n);
        }
        self.snapshot = Some(old.widened(&level.state, level.region.as_ref()));
        self.cycle.reset();
        self.monitor.reset();
        self.blocks.reset();
        false
    }

    /// Adds the change of level `k` since the finer levels last absorbed it to every finer
    /// level, level by level, touching only the vertices that changed.
    pub(super) fn propagate_from(&mut self, k: usize) {
        self.propagate_through(k, self.levels.len() - 1);
    }

    /// [`propagate_from`](Self::propagate_from) down to level `last` only (the levels below
    /// keep a record of what they have not passed on).
    pub(super) fn propagate_through(&mut self, k: usize, last: usize) {
        let count = self.levels.len();
        for l in k + 1..count.min(last + 1) {
            let (coarse, fine) = self.levels.split_at_mut(l);
            let (coarse, fine) = (&mut coarse[l - 1], &mut fine[0]);
            match coarse.touched.take() {
                None => {
                    let delta_p: Vec<DVec3> = coarse.state.p.iter().zip(&fine.synced_p).map(|(a, b)| *a - *b).collect();
                    let delta_r: Vec<DVec3> = coarse.state.r.iter().zip(&fine.synced_r).map(|(a, b)| *a - *b).collect();
                    fine.topology.prolong_add(&delta_p, &mut fine.state.p);
                    fine.topology.prolong_add(&delta_r, &mut fine.state.r);
                    fine.synced_p.clone_from(&coarse.state.p);
                    fine.synced_r.clone_from(&coarse.state.r);
                    fine.touched.set_all();
                }
                Some(list) => {
                    if list.is_empty() {
                        continue;
                    }
                    let n = coarse.vertex_count();
                    self.delta_p.resize(n, DVec3::ZERO);
                    self.delta_r.resize(n, DVec3::ZERO);
                    for &c in &list {
                        let c = c as usize;
                        self.delta_p[c] = coarse.state.p[c] - fine.synced_p[c];
                        self.delta_r[c] = coarse.state.r[c] - fine.synced_r[c];
                        fine.synced_p[c] = coarse.state.p[c];
                        fine.synced_r[c] = coarse.state.r[c];
                    }
                    let children = fine.children.get_or_insert_with(|| Children::of(&fine.topology, n)).of_set(&list);
                    prolong_add_on(&fine.topology, &children, &self.delta_p[..n], &mut fine.state.p);
                    prolong_add_on(&fine.topology, &children, &self.delta_r[..n], &mut fine.state.r);
                    for &c in &list {
                        self.delta_p[c as usize] = DVec3::ZERO;
                        self.delta_r[c as usize] = DVec3::ZERO;
                    }
                    if l + 1 < count {
                        let n = fine.vertex_count();
                        fine.touched.add(&children, n);
                    }
                }
            }
        }
    }
}
