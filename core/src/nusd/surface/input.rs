//! [`NusdInput`]: what a NUSD surface solve reads of a document (the cage, its fixed flags and
//! tensions, and the solver settings), so the solver depends on its own inputs and not on the
//! document that holds them (`Document` converts with `NusdInput::from`).

use crate::Result;
use crate::mesh::PolyMesh;
use crate::mesh::edit::Lineage;
use crate::nusd::{SolverSettings, check_tension};

/// The cage and the NUSD controls and settings of a surface solve.
#[derive(Clone, Copy, Debug)]
pub struct NusdInput<'a> {
    pub cage: &'a PolyMesh,
    /// Per vertex: the surface passes through it.
    pub fixed: &'a [bool],
    /// Per vertex: the tension τ ≥ 0.
    pub vertex_tension: &'a [f64],
    /// Per edge: the tension τ ≥ 0.
    pub edge_tension: &'a [f64],
    pub settings: SolverSettings,
    /// The modelling edit that made `cage` from an earlier cage, if known: a solver of that
    /// earlier cage warm-starts from its own levels through it (see `SurfaceSolver::update`).
    pub lineage: Option<&'a Lineage>,
}

impl NusdInput<'_> {
    /// One value per vertex and per edge, every tension finite and ≥ 0, the settings in range.
    pub fn validate(&self) -> Result<()> {
        let (n, e) = (self.cage.vertex_count(), self.cage.edge_count());
        if self.fixed.len() != n || self.vertex_tension.len() != n || self.edge_tension.len() != e {
            return Err(crate::Error::Input(format!(
                "the cage has {n} vertices and {e} edges but {} fixed flags, {} vertex tensions and {} edge tensions",
                self.fixed.len(),
                self.vertex_tension.len(),
                self.edge_tension.len()
            )));
        }
        for (v, &t) in self.vertex_tension.iter().enumerate() {
            check_tension(t, || format!("vertex {v}"))?;
        }
        for edge in self.cage.edges() {
            let (a, b) = self.cage.edge_vertices(edge);
            check_tension(self.edge_tension[edge.index()], || format!("edge {}-{}", a.0, b.0))?;
        }
        self.settings.validate()
    }
}
