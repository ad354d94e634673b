//! The document's mirror option: a plane `x`, `y` or `z = offset` across which the cage is
//! symmetric, as Blender's mirror modelling works.
//!
//! Two layouts of the cage under the option, told apart by its positions alone
//! ([`Document::mirror_halves`]):
//! - **One half** (every vertex on one side of the plane or on it): the surface of every scheme
//!   but the curve mesh is made on the *mirrored whole* ([`MirroredWhole`]: the cage made whole by
//!   [`apply_mirror`], rebuilt only when the half's connectivity or the set of its plane vertices
//!   changes, so a drag only moves positions and NUSD warm-starts; after a modelling edit of the
//!   half the new whole keeps its lineage from the old one, so NUSD warm-starts then too). The
//!   designer edits the real half; the virtual half follows exactly (bitwise reflections).
//! - **Both halves** (a symmetric cage, or one after Apply mirror): editing either half edits the
//!   other. [`Document::apply`] expands every move of cage points with [`mirror_moves`] (the
//!   partner goes to the reflection; both partners moved meet at the nearest symmetric pair), and
//!   fixed flags, tensions and creases go to the partner elements too.
//!
//! In both, a vertex on the plane stays on it (its normal coordinate is kept at the offset), and
//! in the one-half layout a vertex moved across the plane stops on it, as Blender's *clipping*
//! does (otherwise the cage would no longer be one half). Partners and plane vertices are found
//! by [`mirror_partners`] with [`DEFAULT_MIRROR_TOLERANCE`] of the cage's diagonal, fresh for
//! each edit (linear in the cage; about a millisecond on 20,000 faces).
//!
//! Weak: the curve-mesh scheme is drawn on the real half only, since its edits are numbered on
//! the half's curve mesh (apply the mirror to model a curve mesh symmetrically). A vertex of a
//! symmetric cage with no partner moves alone ([`Document::unpaired_vertices`] says which, so the
//! editor can tell the designer). The methods are standard modelling practice, not from Taut's
//! papers.
//!
//! In the `.taut` file the option is the optional key `"mirror": {"axis": "x", "offset": 0.0}`,
//! absent when off.

use crate::document::Document;
use crate::document::Edit;
use crate::document::SchemeKind;
use crate::document::symmetry_lineage::{self, Sides};
use crate::mesh::edit::{
    Axis, CarryRule, DEFAULT_MIRROR_TOLERANCE, Edited, Lineage, MirrorPartner, MirrorPlane, Provenance, VertexOrigin,
    apply_mirror, carry_edge_property, carry_vertex_property, mirror_moves, mirror_partners,
};
use crate::mesh::{EdgeId, VertexId};
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};

/// How a cage lies about the document's mirror plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MirrorHalves {
    /// Every vertex on one side of the plane or on it: the other half is virtual.
    OneHalf,
    /// Vertices on both sides: edits go to both.
    BothHalves,
    /// Every vertex on the plane: nothing to mirror.
    InPlane,
}

impl Document {
    /// The mirror plane's partners of every cage vertex, or `None` when the option is off.
    pub fn mirror_partners(&self) -> Result<Option<Vec<MirrorPartner>>> {
        self.mirror.map(|plane| self.partners_for(plane)).transpose()
    }

    /// The partners across `plane`: the cached ones while they still hold ([`PartnerCache`]),
    /// else found afresh.
    fn partners_for(&self, plane: MirrorPlane) -> Result<Vec<MirrorPartner>> {
        let mut cache = self.mirror_cache.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((topology, cached_plane, partners)) = cache.as_ref()
            && *topology == self.cage.topology_generation()
            && *cached_plane == plane
            && self.partners_still_hold(plane, partners)
        {
            return Ok(partners.clone());
        }
        let partners = mirror_partners(&self.cage, plane, DEFAULT_MIRROR_TOLERANCE)?;
        *cache = Some((self.cage.topology_generation(), plane, partners.clone()));
        Ok(partners)
    }

    /// Whether partners found earlier still describe the cage (see [`PartnerCache`]).
    fn partners_still_hold(&self, plane: MirrorPlane, partners: &[MirrorPartner]) -> bool {
        if partners.len() != self.cage.vertex_count() {
            return false;
        }
        let tol = DEFAULT_MIRROR_TOLERANCE * self.cage.bounding_diagonal();
        let one_half = self.mirror_halves() == Some(MirrorHalves::OneHalf);
        let p = self.cage.positions();
        partners.iter().enumerate().all(|(v, partner)| match *partner {
            MirrorPartner::OnPlane => plane.distance(p[v]).abs() <= tol,
            MirrorPartner::Partner(w) => {
                plane.distance(p[v]).abs() > tol && p[w.index()].distance(plane.reflect(p[v])) <= tol
            }
            // With nothing across the plane, no vertex can have gained a partner.
            MirrorPartner::Unpaired => one_half && plane.distance(p[v]).abs() > tol,
        })
    }

    /// How the cage lies about the mirror plane, or `None` when the option is off.
    pub fn mirror_halves(&self) -> Option<MirrorHalves> {
        let plane = self.mirror?;
        let tol = DEFAULT_MIRROR_TOLERANCE * self.cage.bounding_diagonal();
        let (mut below, mut above) = (false, false);
        for &p in self.cage.positions() {
            let d = plane.distance(p);
            below |= d < -tol;
            above |= d > tol;
        }
        Some(match (below, above) {
            (true, true) => MirrorHalves::BothHalves,
            (false, false) => MirrorHalves::InPlane,
            _ => MirrorHalves::OneHalf,
        })
    }

    /// Of `vertices`, those off the plane with no partner in a cage with both halves (they move
    /// alone); empty when the option is off or the cage is one half.
    pub fn unpaired_vertices(&self, vertices: &[VertexId]) -> Result<Vec<VertexId>> {
        if self.mirror_halves() != Some(MirrorHalves::BothHalves) {
            return Ok(Vec::new());
        }
        let partners = self.mirror_partners()?.unwrap_or_default();
        Ok(vertices.iter().copied().filter(|v| partners.get(v.index()) == Some(&MirrorPartner::Unpaired)).collect())
    }

    /// The document with its virtual half made real ("Apply mirror"): the mirrored elements
    /// carry the fixed flags, tensions and creases of their sources; the option stays on, now
    /// editing both halves. Refused when the option is off or the cage is not one half that can
    /// be mirrored (vertices on both sides: a face would cross the plane).
    pub fn with_mirror_applied(&self) -> Result<Document> {
        let plane = self
            .mirror
            .ok_or_else(|| Error::Input("apply mirror: the mirror is off; choose a mirror plane first".into()))?;
        let edited = apply_mirror(&self.cage, plane, DEFAULT_MIRROR_TOLERANCE)?;
        let mut whole = self.with_edited_cage(edited)?;
        whole.mirror = Some(plane);
        Ok(whole)
    }

    /// `edit` (already checked) with the partner elements added under the mirror option: moves
    /// by [`mirror_moves`] (plane vertices kept on the plane, a half's vertices kept on its side),
    /// fixed flags, vertex tension and corner sharpness to partner vertices, edge tension and creases to the edge
    /// between the partners' ends. Other edits, and every edit with the option off, as they are.
    pub(crate) fn with_mirror_partners(&self, edit: Edit) -> Result<Edit> {
        let Some(plane) = self.mirror else { return Ok(edit) };
        if !matches!(
            edit,
            Edit::MoveVertices(_)
                | Edit::SetFixed(..)
                | Edit::SetVertexTension(..)
                | Edit::SetEdgeTension(..)
                | Edit::ResetTension { .. }
                | Edit::SetCrease(..)
                | Edit::SetCorner(..)
        ) {
            return Ok(edit);
        }
        let partners = self.partners_for(plane)?;
        let vertices = |vs: Vec<VertexId>| with_partner_vertices(&partners, vs);
        let edges = |es: Vec<EdgeId>| self.with_partner_edges(&partners, es);
        Ok(match edit {
            Edit::MoveVertices(moves) => {
                let mut moved = mirror_moves(&partners, plane, &moves)?;
                if self.mirror_halves() == Some(MirrorHalves::OneHalf) {
                    clip_to_side(self, plane, &mut moved);
                }
                Edit::MoveVertices(moved)
            }
            Edit::SetFixed(vs, fixed) => Edit::SetFixed(vertices(vs), fixed),
            Edit::SetVertexTension(vs, tau) => Edit::SetVertexTension(vertices(vs), tau),
            Edit::SetEdgeTension(es, tau) => Edit::SetEdgeTension(edges(es), tau),
            Edit::ResetTension { vertices: vs, edges: es } => {
                Edit::ResetTension { vertices: vertices(vs), edges: edges(es) }
            }
            Edit::SetCrease(es, s) => Edit::SetCrease(edges(es), s),
            Edit::SetCorner(vs, s) => Edit::SetCorner(vertices(vs), s),
            other => other,
        })
    }

    fn with_partner_edges(&self, partners: &[MirrorPartner], mut edges: Vec<EdgeId>) -> Vec<EdgeId> {
        let image = |v: VertexId| match partners[v.index()] {
            MirrorPartner::OnPlane => Some(v),
            MirrorPartner::Partner(w) => Some(w),
            MirrorPartner::Unpaired => None,
        };
        let mut seen = vec![false; self.cage.edge_count()];
        edges.iter().for_each(|e| seen[e.index()] = true);
        for k in 0..edges.len() {
            let (a, b) = self.cage.edge_vertices(edges[k]);
            let Some(h) = image(a).zip(image(b)).and_then(|(x, y)| self.cage.find_halfedge(x, y)) else { continue };
            if !std::mem::replace(&mut seen[h.edge().index()], true) {
                edges.push(h.edge());
            }
        }
        edges
    }

    /// Checks the mirror option's plane.
    pub(crate) fn check_mirror(mirror: Option<MirrorPlane>) -> Result<()> {
        match mirror {
            Some(plane) if !plane.offset.is_finite() => {
                Err(Error::Input(format!("the mirror plane's offset must be a finite number, not {}", plane.offset)))
            }
            _ => Ok(()),
        }
    }
}

fn with_partner_vertices(partners: &[MirrorPartner], mut vertices: Vec<VertexId>) -> Vec<VertexId> {
    let mut seen = vec![false; partners.len()];
    vertices.iter().for_each(|v| seen[v.index()] = true);
    for k in 0..vertices.len() {
        if let MirrorPartner::Partner(w) = partners[vertices[k].index()]
            && !std::mem::replace(&mut seen[w.index()], true)
        {
            vertices.push(w);
        }
    }
    vertices
}

/// One half's vertices moved across the plane stop on it (Blender's clipping).
fn clip_to_side(doc: &Document, plane: MirrorPlane, moved: &mut [(VertexId, crate::DVec3)]) {
    let tol = DEFAULT_MIRROR_TOLERANCE * doc.cage.bounding_diagonal();
    let side = doc.cage.positions().iter().map(|&p| plane.distance(p)).find(|d| d.abs() > tol).unwrap_or(0.0);
    for (_, p) in moved.iter_mut() {
        if plane.distance(*p) * side < 0.0 {
            *p = plane.project(*p);
        }
    }
}

/// The partners last found for a document or one of its clones (shared between them), so a drag
/// does not search for them every frame: they are used again while the connectivity and plane are
/// the same and every pair still lies within the tolerance of each other's reflection, every plane
/// vertex on the plane, and (only in a one-half cage, where nothing can pair) every unpaired vertex
/// off it; otherwise they are found afresh. Weak: a pair that still holds is kept even if a
/// third vertex has since come nearer than the partner (two vertices within the tolerance of
/// each other, 1e-6 of the cage's size).
#[derive(Clone, Default)]
pub(crate) struct PartnerCache(Arc<Mutex<Option<CachedPartners>>>);

/// The topology generation and plane the partners were found for, and the partners.
type CachedPartners = (u64, MirrorPlane, Vec<MirrorPartner>);

impl std::fmt::Debug for PartnerCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PartnerCache")
    }
}

/// Where a vertex of the mirrored whole takes its position from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Source {
    Copy(VertexId),
    Project(VertexId),
    Reflect(VertexId),
}

/// The mirrored whole of a one-half document, for its surface: built by [`apply_mirror`] once
/// per connectivity and set of plane vertices, then only re-positioned. The whole's first
/// vertices are the half's, so cage vertex `i` of the surface is the document's vertex `i`.
///
/// Each whole built after another carries its lineage from that one ([`Document::lineage`],
/// composed in `symmetry_lineage.rs`) when the half is the one the previous whole was made of,
/// edited by the modelling edit the document keeps (or unchanged), so the NUSD surface
/// warm-starts after a topology edit with the mirror on. Any other half (an undo, a file loaded)
/// gives a whole with no lineage: a cold start.
#[derive(Clone, Debug, Default)]
pub struct MirroredWhole {
    /// The half's topology generation, plane and plane vertices the template was built for.
    key: Option<(u64, Axis, u64, Vec<bool>)>,
    template: Option<Template>,
}

/// The whole's connectivity for one key, where its positions come from, where the half's
/// elements lie in it, and its lineage from the whole before.
#[derive(Clone, Debug)]
struct Template {
    edited: Edited,
    sources: Vec<Source>,
    sides: Sides,
    lineage: Option<Arc<Lineage>>,
}

impl MirroredWhole {
    /// The document to make the surface of: the mirrored whole when the option is on, the cage is
    /// one half and the scheme is not the curve mesh; `None` to use the document itself. An error
    /// says why the half cannot be mirrored (the editor then shows the half).
    pub fn whole(&mut self, doc: &Document) -> Result<Option<Document>> {
        let Some(plane) = doc.mirror else { return Ok(None) };
        if doc.scheme == SchemeKind::CurveMesh || doc.mirror_halves() != Some(MirrorHalves::OneHalf) {
            return Ok(None);
        }
        let tol = DEFAULT_MIRROR_TOLERANCE * doc.cage.bounding_diagonal();
        let on_plane: Vec<bool> = doc.cage.positions().iter().map(|&p| plane.distance(p).abs() <= tol).collect();
        let key = (doc.cage.topology_generation(), plane.axis, plane.offset.to_bits(), on_plane);
        if self.key.as_ref() != Some(&key) || self.template.is_none() {
            let previous = self.template.take().zip(self.key.take());
            let edited = apply_mirror(&doc.cage, plane, DEFAULT_MIRROR_TOLERANCE)?;
            let sources = edited
                .provenance
                .vertices
                .iter()
                .map(|o| match *o {
                    VertexOrigin::Same(v) if key.3[v.index()] => Ok(Source::Project(v)),
                    VertexOrigin::Same(v) => Ok(Source::Copy(v)),
                    VertexOrigin::MirrorOf(v) => Ok(Source::Reflect(v)),
                    other => Err(Error::Topology(format!("mirror: unexpected vertex origin {other:?}"))),
                })
                .collect::<Result<Vec<_>>>()?;
            let sides = Sides::new(&doc.cage, &edited)?;
            let lineage = match previous {
                Some((old, (half_topology, ..))) => {
                    // The half's edit since the previous whole: none, or the document's last one.
                    let unchanged_half;
                    let half_edit = if half_topology == doc.cage.topology_generation() {
                        unchanged_half = symmetry_lineage::unchanged(&doc.cage);
                        Some(&unchanged_half)
                    } else {
                        doc.lineage().filter(|l| l.from == half_topology).map(|l| &l.provenance)
                    };
                    match half_edit {
                        Some(p) => symmetry_lineage::whole_lineage(&old.sides, p, &edited, &sides)?.map(Arc::new),
                        None => None,
                    }
                }
                None => None,
            };
            self.template = Some(Template { edited, sources, sides, lineage });
            self.key = Some(key);
        }
        let Some(t) = &self.template else { return Ok(None) };
        let mut whole = whole_document(doc, plane, &t.edited.mesh, &t.edited.provenance, &t.sources)?;
        whole.lineage = t.lineage.clone();
        Ok(Some(whole))
    }
}

fn whole_document(
    doc: &Document,
    plane: MirrorPlane,
    template: &crate::PolyMesh,
    p: &Provenance,
    sources: &[Source],
) -> Result<Document> {
    let mut cage = template.clone();
    let half = doc.cage.positions();
    for (q, s) in cage.positions_mut().iter_mut().zip(sources) {
        *q = match *s {
            Source::Copy(v) => half[v.index()],
            Source::Project(v) => plane.project(half[v.index()]),
            Source::Reflect(v) => plane.reflect(half[v.index()]),
        };
    }
    let mut whole = Document::new(cage);
    whole.fixed = carry_vertex_property(&doc.fixed, p, &CarryRule::new_elements(true))?;
    whole.vertex_tension = carry_vertex_property(&doc.vertex_tension, p, &CarryRule::new_elements(0.0))?;
    whole.edge_tension = carry_edge_property(&doc.edge_tension, p, &CarryRule::new_elements(0.0))?;
    whole.crease = carry_edge_property(&doc.crease, p, &CarryRule::new_elements(0.0))?;
    whole.corner = carry_vertex_property(&doc.corner, p, &CarryRule::new_elements(0.0))?;
    whole.scheme = doc.scheme;
    whole.settings = doc.settings;
    whole.subdiv = doc.subdiv;
    Ok(whole)
}

/// The `mirror` key of a `.taut` file.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MirrorFile {
    axis: AxisName,
    offset: f64,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
enum AxisName {
    X,
    Y,
    Z,
}

impl From<MirrorPlane> for MirrorFile {
    fn from(plane: MirrorPlane) -> Self {
        let axis = match plane.axis {
            Axis::X => AxisName::X,
            Axis::Y => AxisName::Y,
            Axis::Z => AxisName::Z,
        };
        MirrorFile { axis, offset: plane.offset }
    }
}

impl From<MirrorFile> for MirrorPlane {
    fn from(file: MirrorFile) -> Self {
        let axis = match file.axis {
            AxisName::X => Axis::X,
            AxisName::Y => Axis::Y,
            AxisName::Z => Axis::Z,
        };
        MirrorPlane::new(axis, file.offset)
    }
}

#[cfg(test)]
#[path = "symmetry_tests.rs"]
mod tests;
