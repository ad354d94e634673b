//! Cage modelling as document edits: [`MeshEdit`] names one topological operation with
//! everything it needs (the elements, distances, fractions), so the editor, the command line's
//! `taut edit --script` and undo all speak of the same thing.
//!
//! [`MeshEdit::run`] performs the operation of [`crate::mesh::edit`] on the document's cage and
//! carries the fixed flags, tensions, creases, corners and curve-mesh edits to the new cage
//! through the operation's provenance ([`Document::with_edited_cage_reported`]); applied as
//! [`Edit::Mesh`](crate::Edit::Mesh) it is checked like any new cage (valid, anchored) before the
//! document changes, so a refused operation changes nothing and says why in one line.
//!
//! [`Script`] is the JSON form of a list of edits, the format `taut edit --script` reads and the
//! editor's File ▸ Save Edit Script writes (`docs/edit-scripts.md`).

use serde::{Deserialize, Serialize};

use crate::document::Edit;
use crate::document::{Document, SchemeKind};
use crate::gregory::carry::CarryReport;
use crate::mesh::edit::{self, Edited, FaceGrouping, JoinParams, MergeAt, Provenance, Triangulation};
use crate::mesh::{EdgeId, FaceId, VertexId};
use crate::{DVec3, Error, Result};

/// One cage-modelling operation, with its elements given by index in the cage it applies to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshEdit {
    /// Extrudes faces as one region by `distance` along the region's normals.
    ExtrudeFaces {
        faces: Vec<u32>,
        distance: f64,
    },
    /// Extrudes open-boundary edges by `distance`.
    ExtrudeEdges {
        edges: Vec<u32>,
        distance: f64,
    },
    /// Insets faces as one region by `distance`.
    Inset {
        faces: Vec<u32>,
        distance: f64,
    },
    /// Cuts the ring of quads across `edge` at `fraction` of each ring edge (0.5 the middle).
    LoopCut {
        edge: u32,
        fraction: f64,
    },
    DeleteVertices {
        vertices: Vec<u32>,
    },
    DeleteEdges {
        edges: Vec<u32>,
    },
    DeleteFaces {
        faces: Vec<u32>,
    },
    DissolveVertices {
        vertices: Vec<u32>,
    },
    DissolveEdges {
        edges: Vec<u32>,
    },
    DissolveFaces {
        faces: Vec<u32>,
    },
    /// Merges the vertices into one at their centre.
    MergeAtCentre {
        vertices: Vec<u32>,
    },
    /// Merges the vertices closer than `distance` to one another.
    MergeByDistance {
        vertices: Vec<u32>,
        distance: f64,
    },
    /// A face on a closed run of boundary vertices.
    FillVertices {
        vertices: Vec<u32>,
    },
    /// A face on a closed run of boundary edges.
    FillEdges {
        edges: Vec<u32>,
    },
    /// Splits edges at `fraction` of their length from their first vertex.
    SplitEdges {
        edges: Vec<u32>,
        fraction: f64,
    },
    /// An edge across a face between two of its vertices.
    Connect {
        a: u32,
        b: u32,
    },
    /// Turns faces over (all of them when `faces` is absent).
    FlipNormals {
        faces: Option<Vec<u32>>,
    },
    /// Splits faces into triangles by their shortest diagonals (all faces when absent).
    Triangulate {
        faces: Option<Vec<u32>>,
    },
    /// Joins pairs of triangles into quads across the edges (all edges when absent).
    JoinTriangles {
        edges: Option<Vec<u32>>,
    },
    /// Makes the mirror option's virtual half real.
    ApplyMirror,
}

/// A performed [`MeshEdit`]: the new document, where its elements came from, and what became of
/// the curve-mesh edits.
#[derive(Debug)]
pub struct MeshEdited {
    pub doc: Document,
    /// `None` for [`MeshEdit::ApplyMirror`], which keeps every element's number and adds the
    /// other half after them.
    pub provenance: Option<Provenance>,
    pub carried: CarryReport,
}

fn vertices(ids: &[u32]) -> Vec<VertexId> {
    ids.iter().map(|&i| VertexId(i)).collect()
}

fn edges(ids: &[u32]) -> Vec<EdgeId> {
    ids.iter().map(|&i| EdgeId(i)).collect()
}

fn faces(ids: &[u32]) -> Vec<FaceId> {
    ids.iter().map(|&i| FaceId(i)).collect()
}

impl MeshEdit {
    /// The operation's name, as undo and the Mesh menu say it.
    pub fn name(&self) -> &'static str {
        match self {
            MeshEdit::ExtrudeFaces { .. } | MeshEdit::ExtrudeEdges { .. } => "Extrude",
            MeshEdit::Inset { .. } => "Inset",
            MeshEdit::LoopCut { .. } => "Loop Cut",
            MeshEdit::DeleteVertices { .. } => "Delete Vertices",
            MeshEdit::DeleteEdges { .. } => "Delete Edges",
            MeshEdit::DeleteFaces { .. } => "Delete Faces",
            MeshEdit::DissolveVertices { .. } => "Dissolve Vertices",
            MeshEdit::DissolveEdges { .. } => "Dissolve Edges",
            MeshEdit::DissolveFaces { .. } => "Dissolve Faces",
            MeshEdit::MergeAtCentre { .. } => "Merge at Centre",
            MeshEdit::MergeByDistance { .. } => "Merge by Distance",
            MeshEdit::FillVertices { .. } | MeshEdit::FillEdges { .. } => "Fill",
            MeshEdit::SplitEdges { .. } => "Subdivide Edges",
            MeshEdit::Connect { .. } => "Connect",
            MeshEdit::FlipNormals { .. } => "Flip Normals",
            MeshEdit::Triangulate { .. } => "Triangulate",
            MeshEdit::JoinTriangles { .. } => "Join Triangles",
            MeshEdit::ApplyMirror => "Apply Mirror",
        }
    }

    /// Performs the operation on `doc`'s cage and carries the document's properties to the new
    /// cage; `doc` is not changed. Fails with the operation's one-line reason.
    pub fn run(&self, doc: &Document) -> Result<MeshEdited> {
        let cage = &doc.cage;
        let finite = |what: &str, x: f64| {
            if x.is_finite() {
                Ok(x)
            } else {
                Err(Error::Input(format!("{}: the {what} must be a finite number", self.name())))
            }
        };
        let edited: Edited = match self {
            MeshEdit::ExtrudeFaces { faces: f, distance } => {
                edit::extrude_faces(cage, &faces(f), FaceGrouping::Region, finite("distance", *distance)?)?
            }
            MeshEdit::ExtrudeEdges { edges: e, distance } => {
                edit::extrude_boundary_edges(cage, &edges(e), finite("distance", *distance)?)?
            }
            MeshEdit::Inset { faces: f, distance } => {
                edit::inset_faces(cage, &faces(f), FaceGrouping::Region, finite("distance", *distance)?)?
            }
            MeshEdit::LoopCut { edge, fraction } => {
                edit::loop_cut(cage, EdgeId(*edge), finite("fraction", *fraction)?)?
            }
            MeshEdit::DeleteVertices { vertices: v } => edit::delete_vertices(cage, &vertices(v))?,
            MeshEdit::DeleteEdges { edges: e } => edit::delete_edges(cage, &edges(e))?,
            MeshEdit::DeleteFaces { faces: f } => edit::delete_faces(cage, &faces(f))?,
            MeshEdit::DissolveVertices { vertices: v } => edit::dissolve_vertices(cage, &vertices(v))?,
            MeshEdit::DissolveEdges { edges: e } => edit::dissolve_edges(cage, &edges(e))?,
            MeshEdit::DissolveFaces { faces: f } => edit::dissolve_faces(cage, &faces(f))?,
            MeshEdit::MergeAtCentre { vertices: v } => edit::merge_vertices(cage, &vertices(v), MergeAt::Centre)?,
            MeshEdit::MergeByDistance { vertices: v, distance } => {
                edit::merge_by_distance(cage, &vertices(v), finite("distance", *distance)?)?
            }
            MeshEdit::FillVertices { vertices: v } => edit::fill_vertices(cage, &vertices(v))?,
            MeshEdit::FillEdges { edges: e } => edit::fill_edges(cage, &edges(e))?,
            MeshEdit::SplitEdges { edges: e, fraction } => {
                edit::split_edges(cage, &edges(e), finite("fraction", *fraction)?)?
            }
            MeshEdit::Connect { a, b } => edit::connect_vertices(cage, VertexId(*a), VertexId(*b))?,
            MeshEdit::FlipNormals { faces: f } => edit::flip_normals(cage, f.as_deref().map(faces).as_deref())?,
            MeshEdit::Triangulate { faces: f } => {
                edit::triangulate(cage, f.as_deref().map(faces).as_deref(), Triangulation::ShortestDiagonal)?
            }
            MeshEdit::JoinTriangles { edges: e } => {
                edit::join_triangles(cage, e.as_deref().map(edges).as_deref(), &JoinParams::default())?
            }
            MeshEdit::ApplyMirror => {
                let doc = doc.with_mirror_applied()?;
                return Ok(MeshEdited { doc, provenance: None, carried: CarryReport::default() });
            }
        };
        let provenance = edited.provenance.clone();
        let (doc, carried) = doc.with_edited_cage_reported(edited)?;
        Ok(MeshEdited { doc, provenance: Some(provenance), carried })
    }
}

/// The JSON form of a list of edits: what `taut edit --script` replays on a cage, and what the
/// editor saves of a session. Only edits that say everything they do by value are scripted:
/// modelling operations, moves, fixed flags, tensions, creases, corners, the scheme, the mirror
/// option and the settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Script {
    /// The format's version, 1.
    pub taut_edit_script: u32,
    pub edits: Vec<ScriptStep>,
}

/// One step of a [`Script`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ScriptStep {
    Mesh(MeshEdit),
    Document(DocumentStep),
}

/// The document edits a script can hold besides modelling operations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
pub enum DocumentStep {
    /// Moves vertices to absolute positions: `[vertex, [x, y, z]]` pairs.
    MoveVertices {
        moves: Vec<(u32, [f64; 3])>,
    },
    SetFixed {
        vertices: Vec<u32>,
        fixed: bool,
    },
    SetVertexTension {
        vertices: Vec<u32>,
        tension: f64,
    },
    SetEdgeTension {
        edges: Vec<u32>,
        tension: f64,
    },
    /// Crease sharpness: a number ≥ 0, or `"inf"`.
    SetCrease {
        edges: Vec<u32>,
        sharpness: Sharpness,
    },
    /// Corner sharpness: a number ≥ 0, or `"inf"`.
    SetCorner {
        vertices: Vec<u32>,
        sharpness: Sharpness,
    },
    SetScheme {
        scheme: SchemeKind,
    },
    /// The mirror plane (`{"axis": "x", "offset": 0}`), or `null` for off.
    SetMirror {
        plane: Option<crate::mesh::edit::MirrorPlane>,
    },
    /// The document's length unit (`"mm"`, `"cm"`, `"m"` or `"in"`).
    SetUnits {
        units: crate::document::LengthUnit,
    },
    /// NUSD's solver settings, every field (as a `.taut` file writes them).
    SetSolverSettings {
        settings: crate::nusd::SolverSettings,
    },
    /// The subdivision schemes' settings.
    SetSubdivSettings {
        settings: crate::document::SubdivSettings,
    },
}

/// A sharpness: a number, or `"inf"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Sharpness {
    Number(f64),
    Word(String),
}

impl Sharpness {
    fn of(s: f64) -> Sharpness {
        if s == f64::INFINITY { Sharpness::Word("inf".into()) } else { Sharpness::Number(s) }
    }

    fn value(&self) -> Result<f64> {
        match self {
            Sharpness::Number(s) => Ok(*s),
            Sharpness::Word(w) if w == "inf" => Ok(f64::INFINITY),
            Sharpness::Word(w) => Err(Error::Input(format!("'{w}' is not a sharpness (a number ≥ 0, or \"inf\")"))),
        }
    }
}

impl ScriptStep {
    /// The scripted form of an edit, or `None` for one a script does not hold (a whole new
    /// document, the curves, the curve-mesh edits).
    pub fn of(edit: &Edit) -> Option<ScriptStep> {
        let ids = |v: &[VertexId]| v.iter().map(|v| v.0).collect::<Vec<_>>();
        let eids = |e: &[EdgeId]| e.iter().map(|e| e.0).collect::<Vec<_>>();
        let step = match edit {
            Edit::Mesh(op) => return Some(ScriptStep::Mesh(op.clone())),
            Edit::MoveVertices(moves) => {
                DocumentStep::MoveVertices { moves: moves.iter().map(|(v, p)| (v.0, p.to_array())).collect() }
            }
            Edit::SetFixed(v, fixed) => DocumentStep::SetFixed { vertices: ids(v), fixed: *fixed },
            Edit::SetVertexTension(v, tau) => DocumentStep::SetVertexTension { vertices: ids(v), tension: *tau },
            Edit::SetEdgeTension(e, tau) => DocumentStep::SetEdgeTension { edges: eids(e), tension: *tau },
            Edit::SetCrease(e, s) => DocumentStep::SetCrease { edges: eids(e), sharpness: Sharpness::of(*s) },
            Edit::SetCorner(v, s) => DocumentStep::SetCorner { vertices: ids(v), sharpness: Sharpness::of(*s) },
            Edit::SetScheme(scheme) => DocumentStep::SetScheme { scheme: *scheme },
            Edit::SetMirror(plane) => DocumentStep::SetMirror { plane: *plane },
            Edit::SetUnits(units) => DocumentStep::SetUnits { units: *units },
            Edit::SetSettings(settings) => DocumentStep::SetSolverSettings { settings: *settings },
            Edit::SetSubdivSettings(settings) => DocumentStep::SetSubdivSettings { settings: *settings },
            _ => return None,
        };
        Some(ScriptStep::Document(step))
    }

    /// The edit this step stands for.
    pub fn edit(&self) -> Result<Edit> {
        let ids = |v: &[u32]| vertices(v);
        Ok(match self {
            ScriptStep::Mesh(op) => Edit::Mesh(op.clone()),
            ScriptStep::Document(step) => match step {
                DocumentStep::MoveVertices { moves } => {
                    Edit::MoveVertices(moves.iter().map(|&(v, p)| (VertexId(v), DVec3::from_array(p))).collect())
                }
                DocumentStep::SetFixed { vertices: v, fixed } => Edit::SetFixed(ids(v), *fixed),
                DocumentStep::SetVertexTension { vertices: v, tension } => Edit::SetVertexTension(ids(v), *tension),
                DocumentStep::SetEdgeTension { edges: e, tension } => Edit::SetEdgeTension(edges(e), *tension),
                DocumentStep::SetCrease { edges: e, sharpness } => Edit::SetCrease(edges(e), sharpness.value()?),
                DocumentStep::SetCorner { vertices: v, sharpness } => Edit::SetCorner(ids(v), sharpness.value()?),
                DocumentStep::SetScheme { scheme } => Edit::SetScheme(*scheme),
                DocumentStep::SetMirror { plane } => Edit::SetMirror(*plane),
                DocumentStep::SetUnits { units } => Edit::SetUnits(*units),
                DocumentStep::SetSolverSettings { settings } => Edit::SetSettings(*settings),
                DocumentStep::SetSubdivSettings { settings } => Edit::SetSubdivSettings(*settings),
            },
        })
    }
}

impl Script {
    /// Reads a script; a malformed one is refused with serde's one-line reason.
    pub fn from_json(text: &str) -> Result<Script> {
        let script: Script =
            serde_json::from_str(text).map_err(|e| Error::Input(format!("the edit script cannot be read: {e}")))?;
        if script.taut_edit_script != 1 {
            return Err(Error::Input(format!(
                "the edit script is version {}; this Taut reads version 1",
                script.taut_edit_script
            )));
        }
        Ok(script)
    }

    /// The script as JSON text, one step a line.
    pub fn to_json(&self) -> String {
        let mut text = format!("{{\"taut_edit_script\": {}, \"edits\": [\n", self.taut_edit_script);
        for (k, step) in self.edits.iter().enumerate() {
            let line = serde_json::to_string(step).expect("a script step is plain data");
            text.push_str("  ");
            text.push_str(&line);
            text.push_str(if k + 1 < self.edits.len() { ",\n" } else { "\n" });
        }
        text.push_str("]}\n");
        text
    }

    /// Applies every step to `doc` in order; the first refused step stops the replay, naming
    /// its number (from 1) and why, and `doc` is then as the steps before it left it.
    pub fn replay(&self, doc: &mut Document) -> Result<()> {
        for (k, step) in self.edits.iter().enumerate() {
            let refused = |e: Error| Error::Input(format!("edit {} of the script: {e}", k + 1));
            let edit = step.edit().map_err(refused)?;
            doc.apply(edit).map_err(refused)?;
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "modelling_tests.rs"]
mod tests;
