//! [`SurfaceSolver::update`]: a changed cage or changed controls taken in with a warm start (a
//! move refreshes only the operator rows that see it and may re-solve locally; a changed
//! connectivity rebuilds the levels and, after a modelling edit of this solver's cage, starts
//! them from the old ones through the edit's provenance: `inherit.rs`).

use super::*;

impl SurfaceSolver {
    /// Applies a changed cage or controls (a `&Document` converts) and warm-starts. A changed
    /// connectivity rebuilds the levels; when the input's lineage says the new cage was made from
    /// this solver's cage by a modelling edit, the surviving vertices start from their solved
    /// state and the levels are re-solved around the edit (see `inherit.rs`), else cold.
    pub fn update<'a>(&mut self, input: impl Into<NusdInput<'a>>) -> Result<()> {
        let doc = input.into();
        doc.validate()?;
        let same_topology = doc.cage.vertex_count() == self.cage.vertex_count()
            && doc.cage.face_count() == self.cage.face_count()
            && (doc.cage.topology_generation() == self.cage.topology_generation()
                || doc.cage.polygons() == self.cage.polygons());
        if !same_topology || frame_of(doc.cage) != self.frame {
            let old = std::mem::replace(self, SurfaceSolver::new(doc)?);
            // A modelling edit of the cage this solver had: its levels start from the old ones.
            if let Some(lineage) = doc.lineage {
                self.inherit(old, lineage)?;
            }
            return Ok(());
        }
        self.source_topology = doc.cage.topology_generation();
        let internal: Vec<DVec3>;
        let positions = if self.frame.is_identity() {
            doc.cage.positions()
        } else {
            internal = doc.cage.positions().iter().map(|&p| self.frame.to_internal(p)).collect();
            &internal
        };
        let moved_flags: Vec<bool> = positions.iter().zip(self.cage.positions()).map(|(a, b)| a != b).collect();
        let moved = moved_flags.contains(&true);
        let controls_changed = doc.fixed != self.fixed
            || doc.vertex_tension != self.vertex_tension
            || doc.edge_tension != self.edge_tension
            || doc.settings.spacing != self.settings.spacing;
        let settings_changed = doc.settings != self.settings;
        if !moved && !controls_changed && !settings_changed {
            return Ok(());
        }
        // Check everything before changing anything: a refused edit leaves the solver as it was.
        let diagonal = if moved { extent(positions)? } else { self.diagonal };
        if moved || doc.fixed != self.fixed {
            check_anchoring(doc.cage, doc.fixed)?;
        }
        if moved {
            self.diagonal = diagonal;
            let level0 = &mut self.levels[0];
            for (v, (&new, &old)) in positions.iter().zip(self.cage.positions()).enumerate() {
                if new != old {
                    level0.state.p[v] = new;
                }
            }
            self.cage.positions_mut().copy_from_slice(positions);
        }
        // A vertex fixed again is interpolated again: back to its cage position at level 0
        // (the change reaches the finer levels through the propagation below).
        for (v, (&now, &was)) in doc.fixed.iter().zip(&self.fixed).enumerate() {
            if now && !was {
                self.levels[0].state.p[v] = self.cage.positions()[v];
            }
        }
        // A reduced λ belongs to the shape that needed it: a moved cage (a gesture past a bad
        // state) starts again from the designer's λ, and reduces it again only if it must.
        if moved
            || doc.settings.lambda != self.settings.lambda
            || doc.vertex_tension != self.vertex_tension
            || doc.edge_tension != self.edge_tension
        {
            self.lambda = doc.settings.lambda;
        }
        // Full operator builds for a changed role or spacing; otherwise only the rows that see a
        // moved vertex, and the tension overrides.
        let rebuild = doc.fixed != self.fixed || doc.settings.spacing != self.settings.spacing;
        self.fixed = doc.fixed.to_vec();
        self.vertex_tension = doc.vertex_tension.to_vec();
        self.edge_tension = doc.edge_tension.to_vec();
        self.settings = doc.settings;
        self.threshold = self.settings.tol * self.diagonal;
        self.levels.truncate(self.settings.levels as usize + 1);
        if moved || controls_changed {
            let controls = Controls {
                fixed: &self.fixed,
                vertex_tension: &self.vertex_tension,
                edge_tension: &self.edge_tension,
                spacing: self.settings.spacing,
            };
            let moved_list: Vec<u32> =
                moved_flags.iter().enumerate().filter(|(_, m)| **m).map(|(v, _)| v as u32).collect();
            refresh_levels(&mut self.levels, &self.cage, &controls, &moved_list, rebuild);
        }
        if controls_changed {
            self.levels.iter_mut().for_each(|l| l.multigrid_failed = false);
        }
        self.choose_local(moved && !controls_changed && !settings_changed, &moved_flags);
        self.propagate_from(0);
        // Fixed cage vertices are interpolated at every level, whatever the levels held before.
        // (Each finer level's record of its coarser level follows, so no later propagation
        // moves them off again.)
        for l in 0..self.levels.len() {
            for (v, &fixed) in self.fixed.iter().enumerate() {
                if fixed {
                    let p = self.cage.positions()[v];
                    self.levels[l].state.p[v] = p;
                    if l > 0 {
                        self.levels[l].synced_p[v] = p;
                    }
                }
            }
        }
        self.restart();
        self.refresh_external();
        Ok(())
    }
}
