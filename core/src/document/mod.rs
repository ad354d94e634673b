//! The cage document: what a designer saves in a `.taut` file.
//!
//! A cage (positions and polygons), the surface scheme that makes a surface of it, and each
//! scheme's controls and settings: for NUSD a fixed flag and a tension τ per vertex and a tension τ
//! per edge (dimensionless, `docs/nusd.md`, "Scale-free tension") and the solver settings; for the
//! subdivision schemes a crease sharpness per edge, a corner sharpness per vertex and the number of
//! levels. The file is JSON with a format name and version; floating-point values are written in
//! their shortest exact form, so saving and loading reproduces the document bit for bit.
//!
//! Format versions: 1 had no scheme (NUSD), creases or subdivision settings; 2 adds them. Every
//! version-1 file opens as a NUSD document. An infinitely sharp crease is written `"inf"` (JSON
//! has no infinity). The optional key `corner` (version 2) lists `[vertex, sharpness]` pairs of
//! the sharp vertices, absent when there are none. The optional key `curve_mesh` holds the curve mesh's edit state
//! ([`crate::document::curve_mesh_edits`]); absent, the curve mesh is as the cage builds it.
//!
//! The optional key `curves` holds the Curves workspace's curves, segments and Coons patches
//! ([`CurveSet`]); it is written only when there are some, so files without curves are as before.
//! The optional key `mirror` holds the mirror option ([`crate::document::symmetry`]), absent when off.
//! The optional key `reference_images` lists the pictures the designer models over
//! ([`crate::document::reference_images`]), absent when there are none.

pub mod curve_mesh_edits;
pub mod edit;
pub mod modelling;
pub mod reference_images;
mod scheme;
pub mod symmetry;
mod symmetry_lineage;
pub mod units;

pub use edit::Edit;
pub use reference_images::{ReferenceImage, ReferencePlane};
pub use units::LengthUnit;

use crate::curve::CurveSet;
use crate::curve::set::CurvesFile;
use crate::document::curve_mesh_edits::CurveMeshCache;
use crate::gregory::CurveMeshEdits;
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::nusd::SolverSettings;
pub(crate) use crate::nusd::check_tension;
use crate::{DVec3, Error, Result};
pub use scheme::{SchemeKind, SubdivSettings};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `format` field of a `.taut` file.
pub const FORMAT_NAME: &str = "taut-cage";
/// The newest `.taut` version this build writes and reads.
pub const FORMAT_VERSION: u32 = 2;

/// A cage with its scheme and its per-vertex and per-edge controls.
#[derive(Clone, Debug)]
pub struct Document {
    /// The control cage.
    pub cage: PolyMesh,
    /// How the surface is made from the cage.
    pub scheme: SchemeKind,
    /// NUSD, per vertex: true when the surface must pass through it.
    pub fixed: Vec<bool>,
    /// NUSD, per vertex: dimensionless tension τ ≥ 0.
    pub vertex_tension: Vec<f64>,
    /// NUSD, per cage edge (indexed by [`EdgeId`]): dimensionless tension τ ≥ 0.
    pub edge_tension: Vec<f64>,
    /// Subdivision, per cage edge: crease sharpness s ≥ 0 (0 smooth, `f64::INFINITY` sharp).
    pub crease: Vec<f64>,
    /// Subdivision, per cage vertex: corner sharpness s ≥ 0 (0 smooth, `f64::INFINITY` a vertex
    /// the surface keeps: OpenSubdiv's corner, Blender's vertex crease).
    pub corner: Vec<f64>,
    /// NUSD solver settings.
    pub settings: SolverSettings,
    /// Subdivision settings.
    pub subdiv: SubdivSettings,
    /// Curves, log-aesthetic segments and Coons patches (the Curves workspace).
    pub curves: CurveSet,
    /// Curve mesh: the edited curve-mesh vertices and curves ([`crate::document::curve_mesh_edits`]).
    pub curve_mesh: CurveMeshEdits,
    /// The last curve mesh built for this document or a clone of it.
    pub(crate) curve_cache: CurveMeshCache,
    /// The mirror option: the plane the cage is modelled symmetric about ([`crate::document::symmetry`]).
    pub mirror: Option<crate::mesh::edit::MirrorPlane>,
    /// The mirror partners last found for this document or a clone of it.
    pub(crate) mirror_cache: crate::document::symmetry::PartnerCache,
    /// Pictures drawn behind or over the model ([`crate::document::reference_images`]).
    pub reference_images: Vec<ReferenceImage>,
    /// What one model unit is ([`crate::document::units`]).
    pub units: LengthUnit,
    /// The modelling edit that made this cage from the one before, kept so the NUSD solver can
    /// warm-start the new levels from the old ones ([`lineage`](Self::lineage)). Not saved, and
    /// not part of the document's value (equality ignores it).
    pub(crate) lineage: Option<std::sync::Arc<crate::mesh::edit::Lineage>>,
}

impl Document {
    /// A NUSD document for a cage: every vertex fixed, no tension, no crease, default settings.
    pub fn new(cage: PolyMesh) -> Self {
        let n = cage.vertex_count();
        let e = cage.edge_count();
        Document {
            cage,
            scheme: SchemeKind::Nusd,
            fixed: vec![true; n],
            vertex_tension: vec![0.0; n],
            edge_tension: vec![0.0; e],
            crease: vec![0.0; e],
            corner: vec![0.0; n],
            settings: SolverSettings::default(),
            subdiv: SubdivSettings::default(),
            curves: CurveSet::default(),
            curve_mesh: CurveMeshEdits::default(),
            curve_cache: CurveMeshCache::default(),
            mirror: None,
            mirror_cache: Default::default(),
            reference_images: Vec::new(),
            units: LengthUnit::default(),
            lineage: None,
        }
    }

    /// The same document in another scheme (its other controls kept).
    pub fn with_scheme(mut self, scheme: SchemeKind) -> Self {
        self.scheme = scheme;
        self
    }

    /// Sets the crease sharpness of the cage edge between `a` and `b`.
    pub fn set_crease(&mut self, a: VertexId, b: VertexId, sharpness: f64) -> Result<()> {
        let e = self.edge_between(a, b)?;
        check_sharpness(sharpness, || format!("edge {}-{}", a.0, b.0))?;
        self.crease[e.index()] = sharpness;
        Ok(())
    }

    /// Sets the corner sharpness of cage vertex `v`.
    pub fn set_corner(&mut self, v: VertexId, sharpness: f64) -> Result<()> {
        if v.index() >= self.cage.vertex_count() {
            return Err(Error::Input(format!(
                "a corner names vertex {}, but the cage has {} vertices",
                v.0,
                self.cage.vertex_count()
            )));
        }
        check_sharpness(sharpness, || format!("vertex {}", v.0))?;
        self.corner[v.index()] = sharpness;
        Ok(())
    }

    /// This document on an edited cage: every per-vertex and per-edge control carried along by
    /// the edit's provenance ([`crate::mesh::edit`]): what continues or copies an old element keeps
    /// its value; made vertices are fixed with no tension (a vertex placed on an edge is fixed
    /// only when both ends of the edge were), made edges smooth with no tension.
    /// Curve-mesh edits follow by [`crate::gregory::carry`]'s rule (see
    /// [`with_edited_cage_reported`](Self::with_edited_cage_reported) for what was dropped).
    pub fn with_edited_cage(&self, edited: crate::mesh::edit::Edited) -> Result<Document> {
        Ok(self.with_edited_cage_reported(edited)?.0)
    }

    /// [`with_edited_cage`](Self::with_edited_cage), with what carrying the curve-mesh edits kept
    /// and dropped.
    pub fn with_edited_cage_reported(
        &self,
        edited: crate::mesh::edit::Edited,
    ) -> Result<(Document, crate::gregory::carry::CarryReport)> {
        use crate::mesh::edit::{CarryRule, carry_edge_property, carry_vertex_property};
        let p = &edited.provenance;
        let from = self.cage.topology_generation();
        let mut doc = Document {
            fixed: crate::mesh::edit::carry_fixed_flags(&self.fixed, &self.cage, p)?,
            vertex_tension: carry_vertex_property(&self.vertex_tension, p, &CarryRule::new_elements(0.0))?,
            edge_tension: carry_edge_property(&self.edge_tension, p, &CarryRule::new_elements(0.0))?,
            crease: carry_edge_property(&self.crease, p, &CarryRule::new_elements(0.0))?,
            corner: carry_vertex_property(&self.corner, p, &CarryRule::new_elements(0.0))?,
            cage: edited.mesh,
            scheme: self.scheme,
            settings: self.settings,
            subdiv: self.subdiv,
            curves: self.curves.clone(),
            curve_mesh: CurveMeshEdits::default(),
            curve_cache: CurveMeshCache::default(),
            mirror: self.mirror,
            mirror_cache: Default::default(),
            reference_images: self.reference_images.clone(),
            units: self.units,
            lineage: None,
        };
        let to = doc.cage.topology_generation();
        // An edit that found nothing to change returns a copy of the cage: nothing to carry.
        if to != from {
            doc.lineage = Some(std::sync::Arc::new(crate::mesh::edit::Lineage { from, to, provenance: p.clone() }));
        }
        let carried = doc.carry_curve_mesh_edits(self, Some(p))?;
        doc.validate()?;
        Ok((doc, carried))
    }

    /// The modelling edit that made this document's cage from an earlier cage, while the cage still
    /// has the connectivity that edit gave it (`None` after any other change of connectivity, or
    /// for a document loaded from a file).
    pub fn lineage(&self) -> Option<&crate::mesh::edit::Lineage> {
        self.lineage.as_deref().filter(|l| l.to == self.cage.topology_generation())
    }

    /// Refuses a scheme the cage cannot have, saying what to do (Loop needs triangles, a curve mesh
    /// a cage it can be built on: built here, and kept for the surface).
    pub fn check_scheme(&self, scheme: SchemeKind) -> Result<()> {
        if scheme == SchemeKind::CurveMesh {
            self.curve_mesh().map_err(|e| Error::Topology(format!("no curve mesh can be built on this cage: {e}")))?;
        }
        if scheme == SchemeKind::Loop
            && let Some(f) = self.cage.faces().find(|&f| self.cage.face_valence(f) != 3)
        {
            return Err(Error::Topology(format!(
                "Loop subdivision needs a cage of triangles, but face {} has {} sides; triangulate the cage first",
                f.0,
                self.cage.face_valence(f)
            )));
        }
        Ok(())
    }

    /// Sets the tension of the cage edge between `a` and `b`.
    pub fn set_edge_tension(&mut self, a: VertexId, b: VertexId, tau: f64) -> Result<()> {
        let e = self.edge_between(a, b)?;
        check_tension(tau, || format!("edge {}-{}", a.0, b.0))?;
        self.edge_tension[e.index()] = tau;
        Ok(())
    }

    /// Sets the tension of a cage vertex.
    pub fn set_vertex_tension(&mut self, v: VertexId, tau: f64) -> Result<()> {
        self.check_vertex(v)?;
        check_tension(tau, || format!("vertex {}", v.0))?;
        self.vertex_tension[v.index()] = tau;
        Ok(())
    }

    /// Marks a cage vertex fixed (interpolated) or moving (approximated).
    pub fn set_fixed(&mut self, v: VertexId, fixed: bool) -> Result<()> {
        self.check_vertex(v)?;
        self.fixed[v.index()] = fixed;
        Ok(())
    }

    /// The cage edge joining two vertices, or a clear error.
    pub fn edge_between(&self, a: VertexId, b: VertexId) -> Result<EdgeId> {
        self.check_vertex(a)?;
        self.check_vertex(b)?;
        self.cage
            .find_halfedge(a, b)
            .map(|h| h.edge())
            .ok_or_else(|| Error::Input(format!("vertices {} and {} are not joined by a cage edge", a.0, b.0)))
    }

    fn check_vertex(&self, v: VertexId) -> Result<()> {
        if v.index() < self.cage.vertex_count() {
            Ok(())
        } else {
            Err(Error::Input(format!(
                "vertex {} does not exist (the cage has {} vertices, numbered from 0)",
                v.0,
                self.cage.vertex_count()
            )))
        }
    }

    /// Checks that every array matches the cage and every value is allowed.
    pub fn validate(&self) -> Result<()> {
        let n = self.cage.vertex_count();
        if self.fixed.len() != n || self.vertex_tension.len() != n || self.corner.len() != n {
            return Err(Error::Input(format!(
                "the cage has {n} vertices but {} fixed flags, {} vertex tensions and {} corner sharpnesses",
                self.fixed.len(),
                self.vertex_tension.len(),
                self.corner.len()
            )));
        }
        for (v, &s) in self.corner.iter().enumerate() {
            check_sharpness(s, || format!("vertex {v}"))?;
        }
        if self.edge_tension.len() != self.cage.edge_count() || self.crease.len() != self.cage.edge_count() {
            return Err(Error::Input(format!(
                "the cage has {} edges but {} edge tensions and {} crease sharpnesses",
                self.cage.edge_count(),
                self.edge_tension.len(),
                self.crease.len()
            )));
        }
        // The tensions and the solver settings, as the NUSD solver checks them.
        crate::nusd::surface::NusdInput::from(self).validate()?;
        for e in self.cage.edges() {
            let (a, b) = self.cage.edge_vertices(e);
            check_sharpness(self.crease[e.index()], || format!("edge {}-{}", a.0, b.0))?;
        }
        self.subdiv.validate()?;
        self.curves.validate()?;
        Document::check_mirror(self.mirror)?;
        self.reference_images.iter().try_for_each(ReferenceImage::validate)?;
        self.check_curve_mesh_edits()
    }

    /// Opens a file as a document, the one way the editor and the command line both open one: a
    /// `.taut` document as saved, or a mesh (any format [`crate::io`] imports) as a NUSD cage with
    /// every vertex fixed and the default settings, with what the import repaired.
    pub fn open(
        path: &Path,
        options: &crate::io::ImportOptions,
    ) -> Result<(Document, Option<crate::io::ImportReport>)> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("taut")) {
            return Ok((Document::load(path)?, None));
        }
        let (mesh, report) = crate::io::import_mesh_with(path, options)?;
        let doc = Document::new(mesh);
        doc.validate().map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
        Ok((doc, Some(report)))
    }

    /// The document as `.taut` JSON text.
    pub fn to_json(&self) -> String {
        let file = TautFile {
            format: FORMAT_NAME.to_string(),
            version: FORMAT_VERSION,
            scheme: Some(self.scheme),
            positions: self.cage.positions().iter().map(|p| p.to_array()).collect(),
            faces: self.cage.polygons(),
            fixed: Some(self.fixed.clone()),
            vertex_tension: Some(self.vertex_tension.clone()),
            edge_tension: self
                .cage
                .edges()
                .filter(|e| self.edge_tension[e.index()] != 0.0)
                .map(|e| {
                    let (a, b) = self.cage.edge_vertices(e);
                    EdgeTension(a.0, b.0, self.edge_tension[e.index()])
                })
                .collect(),
            crease: self
                .cage
                .edges()
                .filter(|e| self.crease[e.index()] != 0.0)
                .map(|e| {
                    let (a, b) = self.cage.edge_vertices(e);
                    Crease(a.0, b.0, Sharpness::from(self.crease[e.index()]))
                })
                .collect(),
            corner: (0..self.corner.len())
                .filter(|&v| self.corner[v] != 0.0)
                .map(|v| Corner(v as u32, Sharpness::from(self.corner[v])))
                .collect(),
            settings: self.settings,
            subdivision: Some(self.subdiv),
            curves: self.curves.to_file(),
            curve_mesh: (!self.curve_mesh.is_empty()).then(|| self.curve_mesh.clone()),
            mirror: self.mirror.map(Into::into),
            reference_images: self.reference_images.clone(),
            units: (self.units != LengthUnit::default()).then_some(self.units),
        };
        serde_json::to_string_pretty(&file).expect("a document always serialises")
    }

    /// Parses `.taut` JSON text; `origin` names the source in messages.
    pub fn from_json(text: &str, origin: &Path) -> Result<Self> {
        let file: TautFile =
            serde_json::from_str(text).map_err(|e| Error::format(origin, format!("not a valid .taut file: {e}")))?;
        if file.format != FORMAT_NAME {
            return Err(Error::format(origin, format!("format is '{}', expected '{FORMAT_NAME}'", file.format)));
        }
        if file.version == 0 || file.version > FORMAT_VERSION {
            return Err(Error::format(
                origin,
                format!(
                    "format version {} is not supported by this Taut (it reads versions 1 to {FORMAT_VERSION})",
                    file.version
                ),
            ));
        }
        let positions = file.positions.iter().map(|&p| DVec3::from_array(p)).collect();
        let cage = PolyMesh::from_polygons(positions, &file.faces).map_err(|e| Error::format(origin, e.to_string()))?;
        let n = cage.vertex_count();
        let mut doc = Document::new(cage);
        // A missing key means the default for every vertex; a present one must have one entry
        // per vertex (an empty list included: it is a mistake, not a shorthand).
        if let Some(fixed) = file.fixed {
            doc.fixed = fixed;
        }
        if let Some(tension) = file.vertex_tension {
            doc.vertex_tension = tension;
        }
        doc.settings = file.settings;
        if file.version == 1
            && (file.scheme.is_some()
                || !file.crease.is_empty()
                || !file.corner.is_empty()
                || file.subdivision.is_some()
                || file.curve_mesh.is_some())
        {
            return Err(Error::format(
                origin,
                "a version-1 file has no scheme, crease, corner, subdivision or curve_mesh keys (they came with version 2)",
            ));
        }
        doc.scheme = file.scheme.unwrap_or(SchemeKind::Nusd);
        doc.subdiv = file.subdivision.unwrap_or_default();
        if let Some(curves) = file.curves {
            doc.curves = CurveSet::from_file(curves).map_err(|e| Error::format(origin, e.to_string()))?;
        }
        if doc.fixed.len() != n || doc.vertex_tension.len() != n {
            return Err(Error::format(
                origin,
                format!(
                    "{n} vertices but {} fixed flags and {} vertex tensions",
                    doc.fixed.len(),
                    doc.vertex_tension.len()
                ),
            ));
        }
        for EdgeTension(a, b, tau) in file.edge_tension {
            doc.set_edge_tension(VertexId(a), VertexId(b), tau).map_err(|e| Error::format(origin, e.to_string()))?;
        }
        for Crease(a, b, s) in file.crease {
            let s = s.value().map_err(|m| Error::format(origin, format!("crease {a}-{b}: {m}")))?;
            doc.set_crease(VertexId(a), VertexId(b), s).map_err(|e| Error::format(origin, e.to_string()))?;
        }
        for Corner(v, s) in file.corner {
            let s = s.value().map_err(|m| Error::format(origin, format!("corner {v}: {m}")))?;
            doc.set_corner(VertexId(v), s).map_err(|e| Error::format(origin, e.to_string()))?;
        }
        doc.curve_mesh = file.curve_mesh.unwrap_or_default().normalized();
        doc.mirror = file.mirror.map(Into::into);
        doc.reference_images = file.reference_images;
        doc.units = file.units.unwrap_or_default();
        doc.validate().map_err(|e| Error::format(origin, e.to_string()))?;
        if !doc.curve_mesh.is_empty() {
            // The edits must fit the curve mesh this cage builds; the build is kept for the editor.
            doc.curve_mesh().map_err(|e| Error::format(origin, format!("curve_mesh: {e}")))?;
        }
        Ok(doc)
    }

    /// Reads a `.taut` file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = crate::io::file::read_regular_text(path)?;
        Self::from_json(&text, path)
    }

    /// Writes a `.taut` file atomically: a half-written file never replaces a good one.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::io::write_atomic(path, self.to_json().as_bytes())
    }
}

impl PartialEq for Document {
    fn eq(&self, other: &Self) -> bool {
        self.cage.positions() == other.cage.positions()
            && same_faces(&self.cage, &other.cage)
            && self.fixed == other.fixed
            && self.vertex_tension == other.vertex_tension
            && self.edge_tension == other.edge_tension
            && self.crease == other.crease
            && self.corner == other.corner
            && self.scheme == other.scheme
            && self.settings == other.settings
            && self.subdiv == other.subdiv
            && self.curves == other.curves
            && self.curve_mesh == other.curve_mesh
            && self.mirror == other.mirror
            && self.reference_images == other.reference_images
            && self.units == other.units
    }
}

/// Whether two cages have the same faces, corner by corner (without building their face lists:
/// the undo history compares documents of 20,000 faces).
fn same_faces(a: &PolyMesh, b: &PolyMesh) -> bool {
    a.face_count() == b.face_count() && a.faces().all(|f| a.face_vertices(f).eq(b.face_vertices(f)))
}

impl<'a> From<&'a Document> for crate::nusd::surface::NusdInput<'a> {
    fn from(doc: &'a Document) -> Self {
        crate::nusd::surface::NusdInput {
            cage: &doc.cage,
            fixed: &doc.fixed,
            vertex_tension: &doc.vertex_tension,
            edge_tension: &doc.edge_tension,
            settings: doc.settings,
            lineage: doc.lineage(),
        }
    }
}

pub(crate) fn check_sharpness(s: f64, what: impl Fn() -> String) -> Result<()> {
    if s >= 0.0 {
        Ok(())
    } else {
        Err(Error::Input(format!("crease sharpness of {} must be a number ≥ 0 (or infinite), not {s}", what())))
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TautFile {
    format: String,
    version: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    scheme: Option<SchemeKind>,
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    fixed: Option<Vec<bool>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    vertex_tension: Option<Vec<f64>>,
    #[serde(default)]
    edge_tension: Vec<EdgeTension>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    crease: Vec<Crease>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    corner: Vec<Corner>,
    #[serde(default)]
    settings: SolverSettings,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    subdivision: Option<SubdivSettings>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    curves: Option<CurvesFile>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    curve_mesh: Option<CurveMeshEdits>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mirror: Option<crate::document::symmetry::MirrorFile>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    reference_images: Vec<ReferenceImage>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    units: Option<LengthUnit>,
}

#[derive(Serialize, Deserialize)]
struct EdgeTension(u32, u32, f64);

#[derive(Serialize, Deserialize)]
struct Crease(u32, u32, Sharpness);

#[derive(Serialize, Deserialize)]
struct Corner(u32, Sharpness);

/// A sharpness in the file: a number, or `"inf"` for an infinitely sharp crease.
#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum Sharpness {
    Number(f64),
    Word(String),
}

impl From<f64> for Sharpness {
    fn from(s: f64) -> Self {
        if s == f64::INFINITY { Sharpness::Word("inf".into()) } else { Sharpness::Number(s) }
    }
}

impl Sharpness {
    fn value(&self) -> std::result::Result<f64, String> {
        match self {
            Sharpness::Number(s) => Ok(*s),
            Sharpness::Word(w) if w == "inf" => Ok(f64::INFINITY),
            Sharpness::Word(w) => Err(format!("'{w}' is not a sharpness (a number ≥ 0, or \"inf\")")),
        }
    }
}

#[cfg(test)]
mod tests;
