//! NUSD behind the surface seam: the hierarchical [`SurfaceSolver`] and the surface it draws.
//!
//! The solver iterates level by level over many [`advance`](SurfaceScheme::advance) calls; after
//! each call the finest level built so far is copied into the mesh this scheme shows, so the
//! picture follows the solve. NUSD has no exact normals of its own (the renderer and the
//! exporters estimate them from the mesh); it offers its second derivative `|R|` as the field
//! `"r"`.

use super::{Budget, FieldInfo, Phase, Progress, SchemeKind, SurfaceScheme};
use crate::document::Document;
use crate::mesh::PolyMesh;
use crate::nusd::surface::SurfaceSolver;
use crate::{DVec3, Result};

pub(super) const FIELDS: &[FieldInfo] = &[FieldInfo { key: "r", title: "NUSD |R|" }];

/// NUSD as a [`SurfaceScheme`].
#[derive(Debug)]
pub struct NusdSurface {
    solver: SurfaceSolver,
    mesh: PolyMesh,
    /// The solver's work the mesh shows.
    shown_work: Option<(usize, Phase)>,
}

impl NusdSurface {
    /// The solver for a document (nothing iterated yet).
    pub fn new(doc: &Document) -> Result<Self> {
        let solver = SurfaceSolver::new(doc)?;
        let mesh = solver.surface();
        Ok(NusdSurface { solver, mesh, shown_work: None })
    }

    /// The solver, for what only NUSD has (per-level reports, the stopping threshold).
    pub fn solver(&self) -> &SurfaceSolver {
        &self.solver
    }

    /// Copies the finest level's positions into the shown mesh (its connectivity when a new
    /// level was built).
    fn sync(&mut self) {
        let status = self.solver.status();
        let work = (status.total_iterations, status.phase);
        let topology = self.solver.surface_topology();
        if self.mesh.topology_generation() != topology.topology_generation() {
            self.mesh = topology.clone();
        } else if self.shown_work == Some(work) {
            return;
        }
        self.mesh.positions_mut().copy_from_slice(self.solver.surface_positions());
        self.shown_work = Some(work);
    }
}

impl SurfaceScheme for NusdSurface {
    fn kind(&self) -> SchemeKind {
        SchemeKind::Nusd
    }

    fn update(&mut self, doc: &Document) -> Result<()> {
        self.solver.update(doc)?;
        self.shown_work = None;
        self.sync();
        Ok(())
    }

    fn advance(&mut self, budget: Budget) -> Progress {
        if self.solver.status().phase == Phase::Iterating {
            self.solver.advance(budget);
        }
        self.sync();
        self.progress()
    }

    fn progress(&self) -> Progress {
        let s = self.solver.status();
        let converged = s.converged(self.solver.reports());
        let state = match s.phase {
            Phase::Iterating => "settling",
            Phase::Done if converged => "converged",
            Phase::Done => "stopped at the iteration cap",
            Phase::Diverged => "diverged (rolled back)",
        };
        let mut summary = format!(
            "NUSD level {}/{}  iterations {}  step {:.2e}  {state}",
            s.level, s.levels, s.total_iterations, s.last_step
        );
        if s.lambda != self.solver.settings().lambda {
            summary += &format!("  λ reduced to {}", s.lambda);
        }
        Progress { phase: s.phase, converged, summary, work: s.total_iterations }
    }

    fn take_events(&mut self) -> Vec<String> {
        self.solver.take_events()
    }

    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn normals(&self) -> Option<&[DVec3]> {
        None
    }

    fn curves(&self) -> Vec<Vec<DVec3>> {
        let positions = self.mesh.positions();
        self.solver
            .cage_edge_curves()
            .into_iter()
            .map(|(_, chain)| chain.iter().filter_map(|v| positions.get(v.index()).copied()).collect())
            .collect()
    }

    fn fields(&self) -> &'static [FieldInfo] {
        FIELDS
    }

    fn field(&self, key: &str) -> Option<Vec<f64>> {
        let r = self.solver.surface_second_derivatives();
        (key == "r" && r.len() == self.mesh.vertex_count()).then(|| r.iter().map(|r| r.length()).collect())
    }

    fn report(&self) -> Vec<String> {
        let lambda = self.solver.settings().lambda;
        let mut lines: Vec<String> = self
            .solver
            .reports()
            .iter()
            .map(|r| {
                format!(
                    "level {}: {} vertices, {} iterations, final step {:.3e}, estimated distance to convergence {:.3e}{}{}",
                    r.level,
                    r.vertices,
                    r.iterations,
                    r.last_step,
                    r.remaining,
                    if r.converged { "" } else { " (iteration cap reached, not converged)" },
                    if r.lambda != lambda { format!(" (λ reduced to {})", r.lambda) } else { String::new() },
                )
            })
            .collect();
        let status = self.solver.status();
        lines.push(format!("threshold {:.3e} (tol {} × diagonal)", status.threshold, self.solver.settings().tol));
        lines
    }
}
