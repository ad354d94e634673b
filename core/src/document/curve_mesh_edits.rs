//! The curve mesh of a [`Document`]: its edit state, the core [`Edit`]s that change it, and a
//! cache of the built curve mesh.
//!
//! What the document saves is the cage and [`Document::curve_mesh`], the curve mesh's edit state
//! ([`CurveMeshEdits`]: the edited vertices and curves with their values). The curve mesh itself is
//! a pure function of the two ([`CurveMesh::from_cage`], then [`CurveMesh::set_edits`]), so a
//! reopened file shows the same patches bit for bit, and undo only needs the edit state.
//!
//! The curve-mesh edits ([`Edit::MoveCurveMeshVertices`], [`Edit::SetCurveMeshNormal`],
//! [`Edit::RotateCurveMeshNormal`], [`Edit::MoveCurveMeshInnerPoint`],
//! [`Edit::SetCurveMeshEdits`], [`Edit::RebuildCurveMesh`]) are tried on a copy of the curve
//! mesh: every index, value and count is checked by the curve mesh's own edits, and a refused
//! edit changes nothing. They are allowed in any scheme (the curve mesh of any buildable cage
//! exists), though only the curve-mesh scheme shows them. A change of the cage (a move of cage
//! points, a topology edit) carries the edits onto the new cage's curve mesh by the rule of
//! [`crate::gregory::carry`]; where the new cage cannot be built into a curve mesh, the cage change is
//! refused while there are edits to carry.
//!
//! Building a curve mesh costs a Catmull–Clark refinement two levels down and a fit per edge, far
//! more than an edit, so the last one built is kept in a [`CurveMeshCache`] shared by the clones of
//! a document (the editor's undo snapshots, the copy an edit is tried on) and used when it was
//! built from the same cage and edits; otherwise the curve mesh is built anew.

use crate::document::Document;
use crate::document::Edit;
use crate::gregory::build::BuildReport;
use crate::gregory::carry::{CarryReport, carry_edits, continuing_vertices, roles};
use crate::gregory::curve_mesh::{CurveMesh, CurveMeshEdits};
use crate::mesh::PolyMesh;
use crate::mesh::VertexId;
use crate::mesh::edit::Provenance;
use crate::{DVec3, Error, Result};
use glam::DQuat;
use std::sync::{Arc, Mutex};

/// How far from the cage (in cage sizes, the bounding box's diagonal) an edited curve-mesh point
/// may lie.
pub const MAX_EDIT_REACH: f64 = 1e6;

/// The last curve mesh built for a document or one of its clones (shared between them).
#[derive(Clone, Default)]
pub struct CurveMeshCache(Arc<Mutex<Option<Cached>>>);

struct Cached {
    topology: u64,
    positions: Vec<DVec3>,
    edits: CurveMeshEdits,
    mesh: Arc<CurveMesh>,
    report: Arc<BuildReport>,
}

impl std::fmt::Debug for CurveMeshCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let built = self.0.lock().map(|c| c.is_some()).unwrap_or(false);
        write!(f, "CurveMeshCache({})", if built { "built" } else { "empty" })
    }
}

impl CurveMeshCache {
    fn get(&self, doc: &Document) -> Option<(Arc<CurveMesh>, Arc<BuildReport>)> {
        let cached = self.0.lock().ok()?;
        let c = cached.as_ref()?;
        (c.topology == doc.cage.topology_generation()
            && c.edits == doc.curve_mesh
            && bitwise_equal(&c.positions, doc.cage.positions()))
        .then(|| (c.mesh.clone(), c.report.clone()))
    }

    fn put(&self, doc: &Document, mesh: Arc<CurveMesh>, report: Arc<BuildReport>) {
        if let Ok(mut cached) = self.0.lock() {
            *cached = Some(Cached {
                topology: doc.cage.topology_generation(),
                positions: doc.cage.positions().to_vec(),
                edits: doc.curve_mesh.clone(),
                mesh,
                report,
            });
        }
    }
}

fn bitwise_equal(a: &[DVec3], b: &[DVec3]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits))
}

/// The vertex, curve and patch counts of the curve mesh [`CurveMesh::from_cage`] builds on
/// `cage`, from the cage's counts alone: the cage's own when it is all quads, else those of one
/// Catmull–Clark step (a vertex per cage vertex, edge and face; two curves per cage edge and one
/// per face corner; a patch per face corner).
pub fn curve_mesh_shape(cage: &PolyMesh) -> [u32; 3] {
    let corners: usize = cage.faces().map(|f| cage.face_valence(f)).sum();
    let (v, e, f) = (cage.vertex_count(), cage.edge_count(), cage.face_count());
    if corners == 4 * f {
        [v as u32, e as u32, f as u32]
    } else {
        [(v + e + f) as u32, (2 * e + corners) as u32, corners as u32]
    }
}

/// True for the edits that change the curve mesh's edit state.
pub fn is_curve_mesh_edit(edit: &Edit) -> bool {
    matches!(
        edit,
        Edit::MoveCurveMeshVertices(_)
            | Edit::SetCurveMeshNormal(..)
            | Edit::RotateCurveMeshNormal(..)
            | Edit::MoveCurveMeshInnerPoint { .. }
            | Edit::SetCurveMeshEdits(_)
            | Edit::RebuildCurveMesh
    )
}

impl Document {
    /// The curve mesh of the cage with the document's curve-mesh edits, and the figures of its
    /// build from the cage: the cached one when it belongs to this cage and these edits, else
    /// built (and cached). Errors: the cage has no curve mesh (no faces, a zero-length edge, a
    /// vertex without a tangent plane), or the edits do not fit it.
    pub fn curve_mesh(&self) -> Result<(Arc<CurveMesh>, Arc<BuildReport>)> {
        if let Some(hit) = self.curve_cache.get(self) {
            return Ok(hit);
        }
        let (mut mesh, report) = CurveMesh::from_cage(&self.cage)?;
        if !self.curve_mesh.is_empty() {
            mesh.set_edits(&self.curve_mesh)?;
        }
        let (mesh, report) = (Arc::new(mesh), Arc::new(report));
        self.curve_cache.put(self, mesh.clone(), report.clone());
        Ok((mesh, report))
    }

    /// Checks what can be checked of the curve-mesh edits without building the curve mesh: they
    /// belong to a curve mesh of this cage's counts, every index is in range and listed once, in
    /// ascending order, every value finite. ([`Document::curve_mesh`] checks the rest: unit
    /// normals, inner points in their tangent planes.)
    pub fn check_curve_mesh_edits(&self) -> Result<()> {
        let e = &self.curve_mesh;
        if e.is_empty() {
            return Ok(());
        }
        let shape = curve_mesh_shape(&self.cage);
        if e.shape != shape {
            return Err(Error::Input(format!(
                "the curve-mesh edits are for {} vertices, {} curves and {} patches, but this cage's curve mesh has {}, {} and {}",
                e.shape[0], e.shape[1], e.shape[2], shape[0], shape[1], shape[2]
            )));
        }
        let ascending = |ids: &mut dyn Iterator<Item = u32>, bound: u32, what: &str| -> Result<()> {
            let mut last = None;
            for i in ids {
                if i >= bound || last.is_some_and(|l| i <= l) {
                    return Err(Error::Input(format!(
                        "curve-mesh edits: {what} {i} is out of range (0 to {}), listed twice or out of order",
                        bound.saturating_sub(1)
                    )));
                }
                last = Some(i);
            }
            Ok(())
        };
        ascending(&mut e.vertices.iter().map(|v| v.vertex), shape[0], "vertex")?;
        ascending(&mut e.curves.iter().map(|c| c.curve), shape[1], "curve")?;
        let finite = |x: &[f64]| x.iter().all(|c| c.is_finite());
        if let Some(v) = e.vertices.iter().find(|v| !finite(&v.position) || !finite(&v.normal)) {
            return Err(Error::Input(format!(
                "curve-mesh edits: vertex {} has a value that is not a number",
                v.vertex
            )));
        }
        if let Some(c) = e.curves.iter().find(|c| !c.inner.iter().all(|p| finite(p))) {
            return Err(Error::Input(format!("curve-mesh edits: curve {} has a value that is not a number", c.curve)));
        }
        // A finite but absurd value (1e308) overflows the patches' arithmetic into inf and NaN: a
        // point must lie within a million cage sizes of the cage.
        if let Some((lo, hi)) = self.cage.bounding_box() {
            let centre = 0.5 * (lo + hi);
            let reach = MAX_EDIT_REACH * (hi - lo).length().max(f64::MIN_POSITIVE);
            let far = |p: &[f64; 3]| (DVec3::from_array(*p) - centre).length() > reach;
            if let Some(v) = e.vertices.iter().find(|v| far(&v.position)) {
                return Err(Error::Input(format!(
                    "curve-mesh edits: vertex {} is placed more than {MAX_EDIT_REACH:e} cage sizes away from the cage",
                    v.vertex
                )));
            }
            if let Some(c) = e.curves.iter().find(|c| c.inner.iter().any(far)) {
                return Err(Error::Input(format!(
                    "curve-mesh edits: curve {} has a control point more than {MAX_EDIT_REACH:e} cage sizes away from the cage",
                    c.curve
                )));
            }
        }
        Ok(())
    }

    /// Tries a curve-mesh edit on a copy of the curve mesh: the new edit state and curve mesh,
    /// or `None` when the edit changes nothing.
    fn try_curve_mesh_edit(&self, edit: &Edit) -> Result<Option<(CurveMeshEdits, CurveMesh, Arc<BuildReport>)>> {
        let (current, report) =
            self.curve_mesh().map_err(|e| Error::Input(format!("the cage has no curve mesh to edit: {e}")))?;
        let mut mesh = (*current).clone();
        let refuse = |e: Error| Error::Input(format!("cannot edit the curve mesh: {e}"));
        match edit {
            Edit::MoveCurveMeshVertices(moves) => {
                for &(v, p) in moves {
                    if v.index() < mesh.vertex_count() && mesh.vertex_position(v) == p {
                        continue;
                    }
                    mesh.move_vertex(v, p).map_err(refuse)?;
                }
            }
            Edit::SetCurveMeshNormal(v, n) => {
                let unchanged = v.index() < mesh.vertex_count() && n.is_finite() && mesh.vertex_normal(*v) == *n;
                if !unchanged {
                    mesh.set_vertex_normal(*v, *n).map_err(refuse)?;
                }
            }
            Edit::RotateCurveMeshNormal(v, q) => {
                if *q != DQuat::IDENTITY {
                    mesh.rotate_tangent_plane(*v, *q).map_err(refuse)?;
                }
            }
            Edit::MoveCurveMeshInnerPoint { curve, end, position } => {
                mesh.move_inner_point(*curve, *end, *position).map_err(refuse)?;
            }
            Edit::SetCurveMeshEdits(edits) => {
                mesh.set_edits(edits).map_err(refuse)?;
            }
            Edit::RebuildCurveMesh => {
                mesh.set_edits(&CurveMeshEdits::default()).map_err(refuse)?;
            }
            _ => return Err(Error::Input("not a curve-mesh edit".into())),
        }
        let edits = mesh.edits().normalized();
        Ok((edits != self.curve_mesh).then_some((edits, mesh, report)))
    }

    /// Checks a curve-mesh edit completely (by trying it) without changing the document.
    pub(crate) fn check_curve_mesh_edit(&self, edit: &Edit) -> Result<()> {
        self.try_curve_mesh_edit(edit).map(|_| ())
    }

    /// True when a curve-mesh edit would change the edit state (false also when it is refused).
    pub(crate) fn changed_by_curve_mesh_edit(&self, edit: &Edit) -> bool {
        matches!(self.try_curve_mesh_edit(edit), Ok(Some(_)))
    }

    /// Applies a curve-mesh edit; a refused one changes nothing.
    pub(crate) fn apply_curve_mesh_edit(&mut self, edit: &Edit) -> Result<bool> {
        let Some((edits, mesh, report)) = self.try_curve_mesh_edit(edit)? else { return Ok(false) };
        self.curve_mesh = edits;
        self.curve_cache.put(self, Arc::new(mesh), report);
        Ok(true)
    }

    /// After this document's cage replaced `before`'s (moved points when `provenance` is `None`, a
    /// topology edit with its provenance otherwise): `before`'s curve-mesh edits carried onto this
    /// cage's curve mesh by [`crate::gregory::carry`]'s rule, replacing this document's edit state.
    pub fn carry_curve_mesh_edits(
        &mut self,
        before: &Document,
        provenance: Option<&Provenance>,
    ) -> Result<CarryReport> {
        if before.curve_mesh.is_empty() {
            self.curve_mesh = CurveMeshEdits::default();
            return Ok(CarryReport::default());
        }
        let (old, _) = before.curve_mesh()?;
        let (mut base, report) = CurveMesh::from_cage(&self.cage).map_err(|e| {
            Error::Input(format!(
                "refused: the curve mesh cannot be built on the changed cage ({e}), so its edits would be lost; \
                 rebuild the curve mesh from the cage first to discard them"
            ))
        })?;
        let source: Vec<Option<VertexId>> = match provenance {
            None if old.vertex_count() == base.vertex_count() => base.topology().vertices().map(Some).collect(),
            None => {
                return Err(Error::Input(
                    "carrying curve-mesh edits: the cage's topology changed without an edit's provenance".into(),
                ));
            }
            Some(p) => continuing_vertices(&roles(&before.cage)?, &roles(&self.cage)?, p),
        };
        let (edits, carried) = carry_edits(&old, &base, &source)?;
        base.set_edits(&edits)?;
        self.curve_mesh = edits;
        self.curve_cache.put(self, Arc::new(base), Arc::new(report));
        Ok(carried)
    }
}
