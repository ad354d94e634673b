//! The warm start after a topology edit (issue 22): the levels of the edited cage start from the
//! solved levels of the cage before, through the edit's [`Lineage`].
//!
//! Every level the old solver had built is made again for the new cage (the same refinement a
//! cold solve makes), and each vertex that survived the edit ([`survival`]) takes its old
//! solved `P` and `R`; the others start from the parent average of the level above, as in a cold
//! solve. Then, when the old solve had finished, the levels are re-solved *locally* around the
//! edit's neighbourhood (the changed cage vertices) exactly as after a drag ([`super::super::local`]):
//! the truncation beyond the region is measured, the region grows until it is small, and a region
//! that would cover too much of a level becomes the whole level. The fixed point is the cold
//! solve's; only the start differs. When the old solve had not finished (an edit in the middle
//! of a solve), the states are still carried but every level is solved whole.

use super::local_solve::LocalSolve;
use super::*;
use crate::mesh::edit::Lineage;
use crate::nusd::surface::local::{FIRST_WIDTH, Touched};
use crate::nusd::surface::survival::{self, CageControls, NONE};

impl SurfaceSolver {
    /// Takes the solved levels of `old` (the solver of the cage `lineage` starts from) as the
    /// start of this fresh solver of the edited cage. Does nothing when the two solves are not
    /// comparable (another frame or other settings) or nothing survived.
    pub(super) fn inherit(&mut self, old: SurfaceSolver, lineage: &Lineage) -> Result<()> {
        self.multigrid = old.multigrid;
        self.local_allowed = old.local_allowed;
        if old.frame != self.frame || old.settings != self.settings || lineage.from != old.source_topology {
            return Ok(());
        }
        let mut survivors = survival::cage_survivors(&self.cage, &old.cage, &lineage.provenance);
        if survivors.iter().all(|&o| o == NONE) {
            return Ok(());
        }
        let seeds = survival::changed(
            &self.cage,
            &old.cage,
            &survivors,
            &CageControls {
                fixed: &self.fixed,
                vertex_tension: &self.vertex_tension,
                edge_tension: &self.edge_tension,
            },
            &CageControls { fixed: &old.fixed, vertex_tension: &old.vertex_tension, edge_tension: &old.edge_tension },
        );
        let depth = (old.levels.len() - 1).min(self.settings.levels as usize);
        self.take_survivors(0, &old.levels[0], &survivors);
        for k in 1..=depth {
            survivors = survival::refined_survivors(
                &self.levels[k - 1].topology.mesh,
                &old.levels[k - 1].topology.mesh,
                &survivors,
            );
            let controls = Controls {
                fixed: &self.fixed,
                vertex_tension: &self.vertex_tension,
                edge_tension: &self.edge_tension,
                spacing: self.settings.spacing,
            };
            // Made from the coarser level as it now starts, so a new vertex starts at the
            // parent average of the inherited states and the record of what the finer level has
            // absorbed (its `synced_p`) is that start.
            let finer = self.levels[k - 1].refine(&self.cage, &controls, false)?;
            self.levels.push(finer);
            self.take_survivors(k, &old.levels[k], &survivors);
            let level = &mut self.levels[k];
            level.cycle_rate = old.levels[k].cycle_rate;
            level.multigrid_failed = old.levels[k].multigrid_failed;
        }
        // Nothing is waiting to be passed on: each finer level was made from its coarser one.
        // Their starts are not kept: the survivors carry their own solution, so a level's
        // correction says nothing of the next (see `Level::refine`).
        for level in &mut self.levels {
            level.touched = Touched::default();
            level.start = None;
        }
        let finished = old.phase == Phase::Done && old.reports.iter().all(|r| r.converged);
        if finished && self.multigrid && self.local_allowed && !seeds.is_empty() {
            self.epoch += 1;
            let n = self.levels[0].vertex_count();
            self.levels[0].touched.add(&seeds, n);
            self.local = Some(LocalSolve { seeds, id: self.epoch, width: FIRST_WIDTH });
        } else {
            self.go_whole();
        }
        self.inherited = depth + 1;
        self.refresh_external();
        Ok(())
    }

    /// Sets the surviving vertices of level `k` to their old solved state; fixed cage vertices
    /// stay at their cage positions.
    fn take_survivors(&mut self, k: usize, old: &Level, survivors: &[u32]) {
        let state = &mut self.levels[k].state;
        for (v, &o) in survivors.iter().enumerate() {
            if o != NONE {
                state.p[v] = old.state.p[o as usize];
                state.r[v] = old.state.r[o as usize];
            }
        }
        for (v, &fixed) in self.fixed.iter().enumerate() {
            if fixed {
                state.p[v] = self.cage.positions()[v];
            }
        }
    }

    /// How many levels (the cage counted) the latest topology edit's warm start took from the
    /// solve before it: 0 when the solve started cold (no lineage, or nothing comparable).
    pub fn inherited_levels(&self) -> usize {
        self.inherited
    }
}
