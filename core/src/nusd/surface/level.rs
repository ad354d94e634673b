//! One level of a surface solve and the level set-up: its domain, operator and multigrid
//! transfer, built once and afterwards brought up to date only where the cage changed.
//!
//! After a drag only the cage faces around the moved vertices change their domain, and at level
//! `l` only their descendants: a vertex's domain is the average of its parents', so it changes
//! exactly when a parent's does. The operator rows that see such a vertex (its own and its
//! neighbours') are recomputed ([`Operator::refresh`]), bit for bit what a full build gives; a
//! full build happens only when the connectivity, a fixed flag or the pattern of tensions
//! changed, or when the spacing clamp (`1e-9` of the diagonal) starts to matter.

use super::direct::Direct;
use super::hierarchy::LevelTopology;
use super::irregular::IrregularBlocks;
use super::kernel::{Forcing, State};
use super::local::{Children, Region, Support, Touched};
use super::multigrid::{Grid, Transfer, Work};
use super::operator::{Controls, Operator, Role};
use crate::DVec3;
use crate::mesh::PolyMesh;

/// A level: connectivity, domain, operator, its own solution, and the scratch it needs as a
/// coarse grid.
#[derive(Clone, Debug)]
pub(super) struct Level {
    pub topology: LevelTopology,
    pub domain: Vec<DVec3>,
    pub operator: Operator,
    pub state: State,
    /// The coarser level's P and R when this level last absorbed them.
    pub synced_p: Vec<DVec3>,
    pub synced_r: Vec<DVec3>,
    /// Restriction to the coarser level (none at level 0).
    pub transfer: Option<Transfer>,
    /// Multigrid scratch as a coarse grid, made on first use.
    pub work: Option<Work>,
    /// Residual buffer for multigrid, made on first use.
    pub residual: Forcing,
    /// Largest contraction per V-cycle measured at this level: the rate assumed for the
    /// stopping estimate before a solve has measured its own.
    pub cycle_rate: f64,
    /// Multigrid diverged on this level (strong tension): it is solved by the plain iteration
    /// until the tensions or fixed flags change.
    pub multigrid_failed: bool,
    /// The vertices a local solve iterates (see [`super::local`]); `None`: all.
    pub region: Option<Region>,
    /// The local solve's epoch this level's region belongs to.
    pub epoch: u64,
    /// Where the residual buffer may be nonzero (a region's grids need it zero outside).
    pub residual_support: Support,
    /// Which vertices may differ from what the next finer level last absorbed.
    pub touched: Touched,
    /// The children of each coarser vertex at this level, made on first use.
    pub children: Option<Children>,
    /// The factorised system of a small level without tension, made on first use (see
    /// [`super::direct`]).
    pub direct: Direct,
    /// The exact solves around its extraordinary vertices, made on first use (see
    /// [`super::irregular`]).
    pub irregular: Option<IrregularBlocks>,
    /// The P and R this level started from when it was made, kept until the level is refined
    /// (see [`extrapolate_start`]); `None` once used, or after the cage changed.
    pub start: Option<(Vec<DVec3>, Vec<DVec3>)>,
}

/// The contraction per V-cycle assumed until one is measured.
pub const PRIOR_CYCLE_RATE: f64 = 0.5;
/// The least contraction ever assumed (a level that once contracted faster is not trusted to
/// do so again by more than this).
pub const MIN_CYCLE_RATE: f64 = 0.25;

impl Level {
    /// Level 0: the cage, starting at its own positions with `R = 0`.
    pub fn cage(cage: &PolyMesh, controls: &Controls<'_>) -> Level {
        let topology = LevelTopology::cage(cage);
        let domain = cage.positions().to_vec();
        let operator = Operator::build(&topology, &domain, cage, controls);
        let n = domain.len();
        Level {
            state: State::new(domain.clone(), vec![DVec3::ZERO; n]),
            topology,
            domain,
            operator,
            synced_p: Vec::new(),
            synced_r: Vec::new(),
            transfer: None,
            work: None,
            residual: Forcing::default(),
            cycle_rate: PRIOR_CYCLE_RATE,
            multigrid_failed: false,
            region: None,
            epoch: 0,
            residual_support: Support::default(),
            touched: Touched::everything(),
            children: None,
            direct: Direct::Unmade,
            irregular: None,
            start: None,
        }
    }

    /// The next finer level, starting from this level's solution prolonged, its new vertices
    /// moved by their own curvature term (see [`corrected_start`]); with `extrapolate`, and
    /// where neither level has tension, plus half the correction this level's own solve made,
    /// prolonged (see [`extrapolate_start`]).
    pub fn refine(&self, cage: &PolyMesh, controls: &Controls<'_>, extrapolate: bool) -> crate::Result<Level> {
        let topology = self.topology.refine()?;
        let n = topology.vertex_count();
        let mut domain = vec![DVec3::ZERO; n];
        topology.prolong(&self.domain, &mut domain);
        let mut p = vec![DVec3::ZERO; n];
        let mut r = vec![DVec3::ZERO; n];
        topology.prolong(&self.state.p, &mut p);
        topology.prolong(&self.state.r, &mut r);
        let operator = Operator::build(&topology, &domain, cage, controls);
        if extrapolate
            && operator.overrides.is_empty()
            && let Some((start_p, start_r)) = &self.start
        {
            extrapolate_start(
                &topology,
                &operator,
                [(&self.state.p, start_p, &mut p), (&self.state.r, start_r, &mut r)],
            );
        }
        corrected_start(&operator, self.vertex_count(), &r, &mut p);
        let start = Some((p.clone(), r.clone()));
        let transfer = Some(Transfer::new(&topology, self.topology.vertex_count()));
        Ok(Level {
            topology,
            domain,
            operator,
            state: State::new(p, r),
            synced_p: self.state.p.clone(),
            synced_r: self.state.r.clone(),
            transfer,
            work: None,
            residual: Forcing::default(),
            cycle_rate: PRIOR_CYCLE_RATE,
            multigrid_failed: false,
            region: None,
            epoch: 0,
            residual_support: Support::default(),
            touched: Touched::everything(),
            children: None,
            direct: Direct::Unmade,
            irregular: None,
            start,
        })
    }

    pub fn has_moving(&self) -> bool {
        self.operator.role.contains(&Role::Moving)
    }

    pub fn vertex_count(&self) -> usize {
        self.topology.vertex_count()
    }

    /// This level's part in a cycle whose top is `top` (scratch made on first use).
    pub fn grid(&mut self, is_top: bool) -> Grid<'_> {
        let n = self.vertex_count();
        if self.residual.r.len() != n {
            self.residual = Forcing::zeros(n);
            self.residual_support = Support::Some(self.region.as_ref().map_or_else(Vec::new, |r| r.vertices.clone()));
        }
        if self.region.is_none() {
            self.residual_support = Support::All;
        }
        let Level { topology, operator, transfer, state, work, residual, region, epoch, .. } = self;
        let work = if is_top { None } else { Some(work.get_or_insert_with(|| Work::new(n))) };
        Grid {
            topology,
            operator,
            transfer: transfer.as_ref(),
            state,
            work,
            residual,
            region: region.as_ref(),
            epoch: *epoch,
        }
    }

    /// Sets the region a local solve iterates (`None`: the whole level) and its epoch; the
    /// residual buffer is cleared outside it.
    pub fn set_region(&mut self, region: Option<Region>, epoch: u64) {
        if let Some(region) = &region
            && self.residual.r.len() == self.vertex_count()
        {
            match &self.residual_support {
                Support::All => self.residual = Forcing::zeros(self.vertex_count()),
                Support::Some(list) => {
                    for &v in list {
                        self.residual.r[v as usize] = DVec3::ZERO;
                        self.residual.p[v as usize] = DVec3::ZERO;
                    }
                }
            }
            self.residual_support = Support::Some(region.vertices.clone());
        }
        self.region = region;
        self.epoch = epoch;
    }
}

/// The share of a level's own correction (its solution less its start) added, prolonged, to the
/// start of the next finer level in a fresh solve.
///
/// Each level's fixed point is the same surface at a finer sampling, and the levels converge to
/// their limit about linearly in the spacing: on the default scene a vertex moves between levels
/// `k` and `k + 1` by 0.33–0.50 of what it moved between `k − 1` and `k` (measured at levels 2–6
/// on the vertices of levels 1 and 2). So the next level's correction is about half this one's,
/// the first-order Richardson step. Measured on the default scene (levels 1–5, fixed and with
/// the waist unfixed): 0.5 brings levels 2–3 from 4 cycles to 3 and keeps 4–5 at 3; 0.4 and 0.6
/// leave level 2 at 4 cycles in one of the two cases. Only the start moves, not the fixed point.
pub const START_EXTRAPOLATION: f64 = 0.5;

/// Adds [`START_EXTRAPOLATION`] times the prolonged correction `solved − start` of the coarser
/// level to each moving vertex of the new level's start, for P and for R.
fn extrapolate_start(topology: &LevelTopology, operator: &Operator, parts: [(&[DVec3], &[DVec3], &mut [DVec3]); 2]) {
    let n = topology.vertex_count();
    let mut fine = vec![DVec3::ZERO; n];
    for (solved, start, out) in parts {
        let correction: Vec<DVec3> = solved.iter().zip(start).map(|(a, b)| *a - *b).collect();
        topology.prolong(&correction, &mut fine);
        for (v, out) in out.iter_mut().enumerate() {
            if operator.role[v] == Role::Moving {
                *out += START_EXTRAPOLATION * fine[v];
            }
        }
    }
}

/// Moves each new moving vertex (index `coarse_count` and up) of a level just made from its
/// parents' average by `−K_v R_v`, `R_v` its own start (the parents' average of the converged
/// coarse `R`): where its own equation `ΔP_v = K_v R_v` puts it when its neighbours lie on the
/// coarse surface (on a polyline, the cubic through the two parents). Only the start changes,
/// not the fixed point.
fn corrected_start(operator: &Operator, coarse_count: usize, r: &[DVec3], p: &mut [DVec3]) {
    for v in coarse_count..p.len() {
        if operator.role[v] == Role::Moving {
            p[v] -= operator.k[v] * r[v];
        }
    }
}

/// Brings every level's domain and operator up to date with a cage whose positions changed at
/// the vertices listed in `moved` (none, after a change of tension values). `rebuild` forces
/// full operator builds (a fixed flag, the spacing or the pattern of tensions changed). Only the
/// descendants of the moved vertices are visited (their domain is an average of their parents').
pub(super) fn refresh_levels(
    levels: &mut [Level],
    cage: &PolyMesh,
    controls: &Controls<'_>,
    moved: &[u32],
    rebuild: bool,
) {
    let mut dirty = moved.to_vec();
    for &v in &dirty {
        levels[0].domain[v as usize] = cage.positions()[v as usize];
    }
    for l in 0..levels.len() {
        if l > 0 {
            let (coarse, fine) = levels.split_at_mut(l);
            let (coarse, fine) = (&coarse[l - 1], &mut fine[0]);
            let count = coarse.vertex_count();
            let children = fine.children.get_or_insert_with(|| Children::of(&fine.topology, count));
            let fine_dirty = children.of_set(&dirty);
            let topology = &fine.topology;
            for &v in &fine_dirty {
                let v = v as usize;
                let ps =
                    &topology.parents[topology.parent_offsets[v] as usize..topology.parent_offsets[v + 1] as usize];
                // The same average as the prolongation that made the domain, so bit for bit equal.
                let sum: DVec3 = ps.iter().map(|&c| coarse.domain[c as usize]).sum();
                fine.domain[v] = sum / ps.len() as f64;
            }
            dirty = fine_dirty;
        }
        let level = &mut levels[l];
        level.direct = Direct::Unmade;
        level.irregular = None;
        level.start = None;
        if rebuild || !level.operator.refresh(&level.topology, &level.domain, cage, controls, &dirty) {
            level.operator = Operator::build(&level.topology, &level.domain, cage, controls);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn same(a: &Operator, b: &Operator) -> bool {
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        a.role == b.role
            && bits(&a.k) == bits(&b.k)
            && a.neighbors == b.neighbors
            && bits(&a.weight_p) == bits(&b.weight_p)
            && bits(&a.weight_r) == bits(&b.weight_r)
            && a.fixed == b.fixed
            && a.override_offsets == b.override_offsets
            && a.overrides.len() == b.overrides.len()
            && a.overrides.iter().zip(&b.overrides).all(|(x, y)| {
                (x.slot, x.source, x.other) == (y.slot, y.source, y.other)
                    && (x.beta.to_bits(), x.spacing.to_bits(), x.other_spacing.to_bits())
                        == (y.beta.to_bits(), y.spacing.to_bits(), y.other_spacing.to_bits())
            })
    }

    #[test]
    fn refreshing_after_drags_and_tension_changes_equals_a_full_build() {
        let mut cage = PolyMesh::from_polygons(
            (0..12).map(|i| DVec3::new((i % 4) as f64, (i / 4) as f64, 0.1 * ((i * 7) % 5) as f64)).collect(),
            &[[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [4, 5, 9, 8], [5, 6, 10, 9], [6, 7, 11, 10]],
        )
        .unwrap();
        let fixed = vec![true; 12];
        let mut vt = vec![0.0; 12];
        vt[5] = 1.5;
        let mut et = vec![0.0; cage.edge_count()];
        et[3] = 2.0;
        let controls = |vt: &'static [f64], et: &'static [f64], fixed: &'static [bool]| Controls {
            fixed,
            vertex_tension: vt,
            edge_tension: et,
            spacing: Default::default(),
        };
        let (vt, et, fixed): (&'static [f64], &'static [f64], &'static [bool]) =
            (Vec::leak(vt), Vec::leak(et), Vec::leak(fixed));
        let c = controls(vt, et, fixed);
        let mut levels = vec![Level::cage(&cage, &c)];
        for _ in 0..3 {
            let finer = levels.last().unwrap().refine(&cage, &c, false).unwrap();
            levels.push(finer);
        }
        let mut changed_rows = 0;
        for (step, v) in [5usize, 0, 11, 6].into_iter().enumerate() {
            let before: Vec<Operator> = levels.iter().map(|l| l.operator.clone()).collect();
            let p = cage.position(crate::VertexId(v as u32)) + DVec3::new(0.05, -0.03, 0.08 * step as f64);
            cage.set_position(crate::VertexId(v as u32), p);
            refresh_levels(&mut levels, &cage, &c, &[v as u32], false);
            for (l, level) in levels.iter().enumerate() {
                let full = Operator::build(&level.topology, &level.domain, &cage, &c);
                assert!(same(&level.operator, &full), "drag {step}, level {l}: refresh differs from a full build");
                let mut full_domain = vec![DVec3::ZERO; level.vertex_count()];
                if l > 0 {
                    level.topology.prolong(&levels[l - 1].domain, &mut full_domain);
                    assert_eq!(level.domain, full_domain);
                }
                changed_rows += level.operator.k.iter().zip(&before[l].k).filter(|(a, b)| a != b).count();
            }
        }
        assert!(changed_rows > 0);
        // A new tension value with the same pattern refreshes the overrides only.
        let vt2: &'static [f64] = Vec::leak(vt.iter().map(|t| t * 2.0).collect());
        let c2 = controls(vt2, et, fixed);
        refresh_levels(&mut levels, &cage, &c2, &[], false);
        for level in &levels {
            assert!(same(&level.operator, &Operator::build(&level.topology, &level.domain, &cage, &c2)));
        }
        // A new pattern (a tension where there was none) falls back to a full build.
        let mut vt3 = vt2.to_vec();
        vt3[0] = 1.0;
        let c3 = controls(Vec::leak(vt3), et, fixed);
        let top = levels.last_mut().unwrap();
        assert!(!top.operator.refresh(&top.topology, &top.domain, &cage, &c3, &[]));
    }
}
