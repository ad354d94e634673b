//! [`Edit`]: every change a designer can make to a [`Document`], with the one validator the
//! editor's undo and the command line's flags both go through.
//!
//! An edit is checked completely against the document before anything changes
//! ([`Document::apply`]), so a refused edit leaves the document as it was and says why in one
//! line. Besides each value's own range, an edit must leave a NUSD surface anchored: a surface
//! without enough fixed vertices collapses or flattens (see
//! [`check_anchoring`](crate::nusd::surface::check_anchoring)), so the edit that would do that is
//! refused, naming the vertices to fix. The curve-mesh edits are tried on the document's curve
//! mesh ([`crate::document::curve_mesh_edits`]), and a move of cage points carries the curve-mesh edits
//! onto the moved cage's curve mesh ([`crate::gregory::carry`]), or is refused when it cannot.

use crate::document::curve_mesh_edits::is_curve_mesh_edit;
use crate::document::reference_images::checked_relative;
use crate::document::{Document, ReferenceImage, SchemeKind, SubdivSettings, check_sharpness, check_tension};
use crate::gregory::CurveMeshEdits;
use crate::mesh::{EdgeId, VertexId};
use crate::nusd::SolverSettings;
use crate::{DVec3, Error, Result};

/// One change to a document.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Edit {
    /// Moves cage vertices to absolute positions.
    MoveVertices(Vec<(VertexId, DVec3)>),
    /// Marks vertices fixed (the NUSD surface passes through them) or moving.
    SetFixed(Vec<VertexId>, bool),
    /// Sets the NUSD tension τ of vertices.
    SetVertexTension(Vec<VertexId>, f64),
    /// Sets the NUSD tension τ of cage edges.
    SetEdgeTension(Vec<EdgeId>, f64),
    /// Sets the tension of the given vertices and edges back to 0.
    ResetTension {
        /// Vertices whose tension becomes 0.
        vertices: Vec<VertexId>,
        /// Edges whose tension becomes 0.
        edges: Vec<EdgeId>,
    },
    /// Sets the crease sharpness of cage edges (subdivision schemes; `f64::INFINITY` is sharp).
    SetCrease(Vec<EdgeId>, f64),
    /// Sets the sharpness of cage vertices (subdivision schemes' corners; `f64::INFINITY` keeps
    /// the vertex where it is).
    SetCorner(Vec<VertexId>, f64),
    /// Replaces the NUSD solver settings.
    SetSettings(SolverSettings),
    /// Replaces the subdivision settings.
    SetSubdivSettings(SubdivSettings),
    /// Chooses the surface scheme.
    SetScheme(SchemeKind),
    /// Replaces the curves, segments and Coons patches (the Curves workspace). Boxed, as
    /// [`Edit::Replace`]; the set's view state is not taken (it is no change of the design).
    SetCurves(Box<crate::curve::CurveSet>),
    /// Replaces the whole document (a new cage, an undoable topology change). Boxed: a document
    /// is far larger than the other edits.
    Replace(Box<Document>),
    /// Moves curve-mesh vertices (indices of the curve mesh) to absolute positions; each one's
    /// tangent plane and the inner control points next to it move with it.
    MoveCurveMeshVertices(Vec<(VertexId, DVec3)>),
    /// Turns a curve-mesh vertex's tangent plane to a normal (by the smallest rotation); the inner
    /// control points next to it turn with it.
    SetCurveMeshNormal(VertexId, DVec3),
    /// Rotates a curve-mesh vertex's tangent plane about the vertex by a unit quaternion.
    RotateCurveMeshNormal(VertexId, glam::DQuat),
    /// Moves the inner control point of a curve next to its end vertex `end` towards `position`,
    /// projected onto that vertex's tangent plane.
    MoveCurveMeshInnerPoint {
        /// The curve (an edge of the curve mesh).
        curve: EdgeId,
        /// The end vertex whose leg it is.
        end: VertexId,
        /// Where the control point goes (before the projection).
        position: DVec3,
    },
    /// Sets the whole curve-mesh edit state (a cancelled drag puts back the state before it).
    SetCurveMeshEdits(CurveMeshEdits),
    /// Discards every curve-mesh edit: the curve mesh as the cage builds it ("Rebuild from cage").
    RebuildCurveMesh,
    /// Turns the mirror option on with a plane, or off ([`crate::document::symmetry`]).
    SetMirror(Option<crate::mesh::edit::MirrorPlane>),
    /// What one model unit is (lengths stay as they are: this says what they mean).
    SetUnits(crate::document::LengthUnit),
    /// A cage-modelling operation ([`crate::document::modelling`]): performed on the cage, the document's
    /// properties carried to the new cage, and checked as a new cage is.
    Mesh(crate::document::modelling::MeshEdit),
    /// Adds a reference image at the end of the list; its path must stay inside the document's
    /// folder ([`crate::document::reference_images::checked_relative`]).
    AddReferenceImage(ReferenceImage),
    /// Removes the reference image at an index.
    RemoveReferenceImage(usize),
    /// Replaces the reference image at an index (its placement, look or file).
    SetReferenceImage(usize, ReferenceImage),
}

impl Edit {
    /// What the edit does, as undo names it ("Undo Extrude").
    pub fn name(&self) -> &'static str {
        match self {
            Edit::MoveVertices(_) => "Move",
            Edit::SetFixed(_, true) => "Fix Vertices",
            Edit::SetFixed(_, false) => "Free Vertices",
            Edit::SetVertexTension(..) | Edit::SetEdgeTension(..) => "Set Tension",
            Edit::ResetTension { .. } => "Reset Tension",
            Edit::SetCrease(..) => "Set Crease",
            Edit::SetCorner(..) => "Set Corner",
            Edit::SetSettings(_) => "Smoothing Settings",
            Edit::SetSubdivSettings(_) => "Subdivision Settings",
            Edit::SetScheme(_) => "Change Scheme",
            Edit::SetCurves(_) => "Edit Curves",
            Edit::Replace(_) => "Replace Cage",
            Edit::MoveCurveMeshVertices(_) => "Move Curve-Mesh Vertex",
            Edit::SetCurveMeshNormal(..) | Edit::RotateCurveMeshNormal(..) => "Turn Tangent Plane",
            Edit::MoveCurveMeshInnerPoint { .. } => "Move Tangent Handle",
            Edit::SetCurveMeshEdits(_) => "Curve-Mesh Edits",
            Edit::RebuildCurveMesh => "Rebuild Curve Mesh",
            Edit::SetMirror(Some(_)) => "Mirror On",
            Edit::SetMirror(None) => "Mirror Off",
            Edit::SetUnits(_) => "Units",
            Edit::Mesh(op) => op.name(),
            Edit::AddReferenceImage(_) => "Add Reference Image",
            Edit::RemoveReferenceImage(_) => "Remove Reference Image",
            Edit::SetReferenceImage(..) => "Edit Reference Image",
        }
    }
}

impl Document {
    /// Checks `edit` completely and applies it; a refused edit changes nothing and says why.
    /// Returns whether the document changed (an edit that sets what is already there does not).
    pub fn apply(&mut self, edit: Edit) -> Result<bool> {
        // A modelling operation is its new document, checked as any new document is.
        let edit = match edit {
            Edit::Mesh(op) => Edit::Replace(Box::new(op.run(self)?.doc)),
            edit => edit,
        };
        if is_curve_mesh_edit(&edit) {
            return self.apply_curve_mesh_edit(&edit);
        }
        self.check_edit(&edit)?;
        // Under the mirror option, the partners across the plane are edited too.
        let edit = self.with_mirror_partners(edit)?;
        if !self.changed_by(&edit) {
            return Ok(false);
        }
        let carry_curve_mesh = matches!(edit, Edit::MoveVertices(_)) && !self.curve_mesh.is_empty();
        if let Edit::Replace(new) = &edit {
            // The new document is checked as it is, without a copy of this one.
            if self.anchoring_matters(&edit) {
                crate::nusd::surface::check_anchoring(&new.cage, &new.fixed)
                    .map_err(|e| Error::Input(format!("refused: {e}")))?;
            }
            self.perform(edit);
        } else if self.anchoring_matters(&edit) || carry_curve_mesh {
            let mut after = self.clone();
            let anchoring = self.anchoring_matters(&edit);
            after.perform(edit);
            if anchoring {
                crate::nusd::surface::check_anchoring(&after.cage, &after.fixed)
                    .map_err(|e| Error::Input(format!("refused: {e}")))?;
            }
            if carry_curve_mesh {
                after.carry_curve_mesh_edits(self, None)?;
            }
            *self = after;
        } else {
            self.perform(edit);
        }
        Ok(true)
    }

    /// Checks a whole new document as [`apply`](Self::apply) of [`Edit::Replace`] would, without
    /// copying this one: the new document when it differs, `None` when it is the same (a topology
    /// change of a large cage pays for one document, not three).
    pub fn checked_replacement(&self, new: Box<Document>) -> Result<Option<Document>> {
        let edit = Edit::Replace(new);
        self.check_edit(&edit)?;
        if !self.changed_by(&edit) {
            return Ok(None);
        }
        if self.anchoring_matters(&edit)
            && let Edit::Replace(new) = &edit
        {
            crate::nusd::surface::check_anchoring(&new.cage, &new.fixed)
                .map_err(|e| Error::Input(format!("refused: {e}")))?;
        }
        Ok(match edit {
            Edit::Replace(new) => Some(*new),
            _ => None,
        })
    }

    /// Checks an edit against the document without changing it.
    pub fn check_edit(&self, edit: &Edit) -> Result<()> {
        match edit {
            Edit::MoveVertices(moves) => {
                for &(v, p) in moves {
                    self.check_vertex_for(v, "move")?;
                    if !p.is_finite() {
                        return Err(Error::Input(format!(
                            "cannot move vertex {} to ({}, {}, {}): coordinates must be finite numbers",
                            v.0, p.x, p.y, p.z
                        )));
                    }
                }
                Ok(())
            }
            Edit::SetFixed(vertices, _) => vertices.iter().try_for_each(|&v| self.check_vertex_for(v, "fix or free")),
            Edit::SetVertexTension(vertices, tau) => {
                check_tension(*tau, || "the selection".to_string())?;
                vertices.iter().try_for_each(|&v| self.check_vertex_for(v, "set the tension of"))
            }
            Edit::SetEdgeTension(edges, tau) => {
                check_tension(*tau, || "the selection".to_string())?;
                edges.iter().try_for_each(|&e| self.check_edge_for(e, "set the tension of"))
            }
            Edit::ResetTension { vertices, edges } => {
                vertices.iter().try_for_each(|&v| self.check_vertex_for(v, "reset the tension of"))?;
                edges.iter().try_for_each(|&e| self.check_edge_for(e, "reset the tension of"))
            }
            Edit::SetCrease(edges, s) => {
                check_sharpness(*s, || "the selection".to_string())?;
                edges.iter().try_for_each(|&e| self.check_edge_for(e, "set the crease of"))
            }
            Edit::SetCorner(vertices, s) => {
                check_sharpness(*s, || "the selection".to_string())?;
                vertices.iter().try_for_each(|&v| self.check_vertex_for(v, "set the corner sharpness of"))
            }
            Edit::SetSettings(settings) => {
                settings.validate().map_err(|e| Error::Input(format!("smoothing settings: {e}")))
            }
            Edit::SetSubdivSettings(settings) => settings.validate(),
            Edit::SetScheme(scheme) => self.check_scheme(*scheme),
            Edit::SetCurves(set) => {
                set.validate_content().map_err(|e| Error::Input(format!("cannot use the curves: {e}")))
            }
            Edit::Replace(new) => {
                new.cage.validate().map_err(|e| Error::Input(format!("cannot use the new cage: {e}")))?;
                new.validate().map_err(|e| Error::Input(format!("cannot use the new cage: {e}")))?;
                if !new.curve_mesh.is_empty() {
                    new.curve_mesh().map_err(|e| Error::Input(format!("cannot use the new curve-mesh edits: {e}")))?;
                }
                Ok(())
            }
            Edit::MoveCurveMeshVertices(_)
            | Edit::SetCurveMeshNormal(..)
            | Edit::RotateCurveMeshNormal(..)
            | Edit::MoveCurveMeshInnerPoint { .. }
            | Edit::SetCurveMeshEdits(_)
            | Edit::RebuildCurveMesh => self.check_curve_mesh_edit(edit),
            Edit::SetMirror(plane) => Document::check_mirror(*plane),
            Edit::SetUnits(_) => Ok(()),
            Edit::Mesh(op) => self.check_edit(&Edit::Replace(Box::new(op.run(self)?.doc))),
            Edit::AddReferenceImage(image) => {
                image.validate()?;
                checked_relative(&image.path).map(|_| ())
            }
            Edit::RemoveReferenceImage(index) => self.check_reference_index(*index),
            Edit::SetReferenceImage(index, image) => {
                self.check_reference_index(*index)?;
                image.validate()?;
                // An image a file brought in with a refused path can still be hidden, moved or
                // faded; only a new path must be safe.
                if image.path != self.reference_images[*index].path {
                    checked_relative(&image.path)?;
                }
                Ok(())
            }
        }
    }

    fn check_reference_index(&self, index: usize) -> Result<()> {
        let n = self.reference_images.len();
        if index < n {
            Ok(())
        } else {
            Err(Error::Input(format!("there is no reference image {index}: the document has {n}")))
        }
    }

    fn check_vertex_for(&self, v: VertexId, action: &str) -> Result<()> {
        let n = self.cage.vertex_count();
        if v.index() < n {
            Ok(())
        } else {
            Err(Error::Input(format!("cannot {action} vertex {}: the cage has {n} vertices, numbered from 0", v.0)))
        }
    }

    fn check_edge_for(&self, e: EdgeId, action: &str) -> Result<()> {
        let n = self.cage.edge_count();
        if e.index() < n {
            Ok(())
        } else {
            Err(Error::Input(format!("cannot {action} edge {}: the cage has {n} edges, numbered from 0", e.0)))
        }
    }

    /// True when a checked edit would change the document.
    pub fn changed_by(&self, edit: &Edit) -> bool {
        match edit {
            Edit::MoveVertices(moves) => moves.iter().any(|&(v, p)| self.cage.position(v) != p),
            Edit::SetFixed(vertices, fixed) => vertices.iter().any(|v| self.fixed[v.index()] != *fixed),
            Edit::SetVertexTension(vertices, tau) => vertices.iter().any(|v| self.vertex_tension[v.index()] != *tau),
            Edit::SetEdgeTension(edges, tau) => edges.iter().any(|e| self.edge_tension[e.index()] != *tau),
            Edit::ResetTension { vertices, edges } => {
                vertices.iter().any(|v| self.vertex_tension[v.index()] != 0.0)
                    || edges.iter().any(|e| self.edge_tension[e.index()] != 0.0)
            }
            Edit::SetCrease(edges, s) => edges.iter().any(|e| self.crease[e.index()] != *s),
            Edit::SetCorner(vertices, s) => vertices.iter().any(|v| self.corner[v.index()] != *s),
            Edit::SetSettings(settings) => self.settings != *settings,
            Edit::SetSubdivSettings(settings) => self.subdiv != *settings,
            Edit::SetScheme(scheme) => self.scheme != *scheme,
            Edit::SetCurves(set) => self.curves != **set,
            Edit::Replace(new) => *self != **new,
            Edit::MoveCurveMeshVertices(_)
            | Edit::SetCurveMeshNormal(..)
            | Edit::RotateCurveMeshNormal(..)
            | Edit::MoveCurveMeshInnerPoint { .. }
            | Edit::SetCurveMeshEdits(_)
            | Edit::RebuildCurveMesh => self.changed_by_curve_mesh_edit(edit),
            Edit::SetMirror(plane) => self.mirror != *plane,
            Edit::SetUnits(units) => self.units != *units,
            // Every operation that is not refused changes the cage.
            Edit::Mesh(_) => true,
            Edit::AddReferenceImage(_) | Edit::RemoveReferenceImage(_) => true,
            Edit::SetReferenceImage(index, image) => self.reference_images[*index] != *image,
        }
    }

    /// Whether the edit can change what holds a NUSD surface: the fixed flags, the positions of a
    /// cage with moving vertices, the scheme becoming NUSD, a new cage.
    fn anchoring_matters(&self, edit: &Edit) -> bool {
        let nusd_after = match edit {
            Edit::SetScheme(s) => *s == SchemeKind::Nusd,
            Edit::Replace(new) => new.scheme == SchemeKind::Nusd,
            _ => self.scheme == SchemeKind::Nusd,
        };
        nusd_after
            && match edit {
                Edit::SetFixed(..) | Edit::SetScheme(_) | Edit::Replace(_) => true,
                // Fixed vertices alone keep their hull when nothing else moves them.
                Edit::MoveVertices(_) => self.fixed.iter().any(|&f| !f),
                _ => false,
            }
    }

    /// Applies a checked edit.
    fn perform(&mut self, edit: Edit) {
        match edit {
            Edit::MoveVertices(moves) => {
                let positions = self.cage.positions_mut();
                for (v, p) in moves {
                    positions[v.index()] = p;
                }
            }
            Edit::SetFixed(vertices, fixed) => vertices.iter().for_each(|v| self.fixed[v.index()] = fixed),
            Edit::SetVertexTension(vertices, tau) => vertices.iter().for_each(|v| self.vertex_tension[v.index()] = tau),
            Edit::SetEdgeTension(edges, tau) => edges.iter().for_each(|e| self.edge_tension[e.index()] = tau),
            Edit::ResetTension { vertices, edges } => {
                vertices.iter().for_each(|v| self.vertex_tension[v.index()] = 0.0);
                edges.iter().for_each(|e| self.edge_tension[e.index()] = 0.0);
            }
            Edit::SetCrease(edges, s) => edges.iter().for_each(|e| self.crease[e.index()] = s),
            Edit::SetCorner(vertices, s) => vertices.iter().for_each(|v| self.corner[v.index()] = s),
            Edit::SetSettings(settings) => self.settings = settings,
            Edit::SetSubdivSettings(settings) => self.subdiv = settings,
            Edit::SetScheme(scheme) => self.scheme = scheme,
            Edit::SetCurves(set) => {
                let view = self.curves.view;
                self.curves = *set;
                self.curves.view = view;
                self.curves.view.selected = self.curves.view.selected.filter(|&s| s < self.curves.curves.len());
            }
            Edit::Replace(new) => *self = *new,
            // Applied by `apply_curve_mesh_edit`, which needs to try them first.
            Edit::MoveCurveMeshVertices(_)
            | Edit::SetCurveMeshNormal(..)
            | Edit::RotateCurveMeshNormal(..)
            | Edit::MoveCurveMeshInnerPoint { .. }
            | Edit::SetCurveMeshEdits(_)
            | Edit::RebuildCurveMesh => {}
            Edit::SetMirror(plane) => self.mirror = plane,
            Edit::SetUnits(units) => self.units = units,
            // Turned into its new document by `apply` before it gets here.
            Edit::Mesh(op) => {
                if let Ok(done) = op.run(self) {
                    *self = done.doc;
                }
            }
            Edit::AddReferenceImage(image) => self.reference_images.push(image),
            Edit::RemoveReferenceImage(index) => {
                self.reference_images.remove(index);
            }
            Edit::SetReferenceImage(index, image) => self.reference_images[index] = image,
        }
    }
}
