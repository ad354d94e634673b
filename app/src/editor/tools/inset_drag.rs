//! Inset then set the thickness, as Blender's I: the inset is made at once (at the Mesh menu's
//! thickness, a fifth of the mean edge length of the faces) and then the mouse scales the
//! thickness by the ratio of the cursor's distances from the faces' centre on screen (away
//! from it: thicker), or a typed number gives it exactly; a click or Enter sets it; Esc or a
//! right click leaves the inset at the menu's thickness. Inset and thickness are one undo step.
//!
//! A new thickness moves only the inner ring, to where the core's [`inset_faces`] at that
//! thickness puts it, through `Edit::MoveVertices`. A thickness the core refuses (one that
//! would fold the ring over) keeps the last one that worked and says why in the status line.

use crate::editor::document::Edit;
use crate::editor::interaction;
use crate::editor::mesh_ops::{self, MeshOp, OFFSET_FRACTION};
use crate::editor::shortcuts;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{CageStamp, End, Flow, Pointer, Tool, enter_or_escape};
use glam::Vec2;
use taut_core::mesh::edit::{FaceGrouping, VertexOrigin, inset_faces};
use taut_core::{DVec3, Document, FaceId, VertexId};

/// An inset whose thickness follows the mouse.
#[derive(Clone, Debug)]
pub struct InsetDrag {
    /// The document before the inset.
    original: Box<Document>,
    faces: Vec<FaceId>,
    /// The inner ring's vertices in the inset cage.
    ring: Vec<VertexId>,
    /// The faces' centre, in model coordinates.
    centre: DVec3,
    /// The menu's thickness, and the one now.
    base: f64,
    pub thickness: f64,
    mouse_start: Option<Vec2>,
    typed: String,
    refusal: Option<String>,
    /// The inset cage's topology: another one (a file opened meanwhile) ends the drag.
    topology: CageStamp,
}

/// I: inset the selected faces, then let the mouse set the thickness.
pub(crate) fn start(editor: &mut EditorState, mouse: Option<Vec2>) -> Option<Box<dyn Tool>> {
    let doc = editor.document.doc();
    let cage = &doc.cage;
    let faces = mesh_ops::picked(cage, editor).faces;
    let base = OFFSET_FRACTION * mesh_ops::mean_edge_length(cage, &mesh_ops::face_edges(cage, &faces));
    let original = Box::new(doc.clone());
    editor.document.begin_gesture();
    let revision = editor.document.revision();
    editor.mesh_op(MeshOp::Inset);
    if editor.document.revision() == revision {
        editor.document.end_gesture();
        return None;
    }
    let Ok(edited) = inset_faces(&original.cage, &faces, FaceGrouping::Region, base) else {
        editor.document.end_gesture();
        return None;
    };
    let ring = (0..edited.provenance.vertices.len() as u32)
        .map(VertexId)
        .filter(|v| matches!(edited.provenance.vertices[v.index()], VertexOrigin::CopyOf(_)))
        .collect();
    let corners: Vec<DVec3> =
        faces.iter().flat_map(|&f| original.cage.face_vertices(f)).map(|v| original.cage.position(v)).collect();
    let centre = corners.iter().copied().sum::<DVec3>() / corners.len().max(1) as f64;
    Some(Box::new(InsetDrag {
        original,
        faces,
        ring,
        centre,
        base,
        thickness: base,
        mouse_start: mouse,
        typed: String::new(),
        refusal: None,
        topology: CageStamp::now(editor),
    }))
}

impl InsetDrag {
    /// Puts the inner ring where an inset of `thickness` puts it.
    fn set_thickness(&mut self, editor: &mut EditorState, thickness: f64) {
        if !thickness.is_finite() || thickness == self.thickness {
            return;
        }
        match inset_faces(&self.original.cage, &self.faces, FaceGrouping::Region, thickness) {
            Ok(edited) => {
                self.thickness = thickness;
                self.refusal = None;
                let moves = self.ring.iter().map(|&v| (v, edited.mesh.position(v))).collect();
                editor.emit(Edit::MoveVertices(moves));
            }
            Err(e) => self.refusal = Some(e.to_string()),
        }
    }
}

impl Tool for InsetDrag {
    /// Digits, Enter, Esc.
    fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        ctx.input_mut(|i| {
            shortcuts::take_typed_number(i, &mut self.typed, false);
            i.events.retain(|e| !matches!(e, egui::Event::Text(_)));
        });
        if let Ok(t) = self.typed.parse::<f64>() {
            self.set_thickness(editor, t);
        }
        enter_or_escape(ctx)
    }

    /// The thickness follows the cursor's distance from the faces' centre on screen.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        let centre = editor.view.display_frame.to_display_f64(self.centre);
        let centre = interaction::project(&editor.view.camera, &pointer.view, centre);
        if let (Some((c, _)), Some(m), true) = (centre, pointer.mouse, self.typed.is_empty()) {
            let start = *self.mouse_start.get_or_insert(m);
            let (a, b) = ((start - c).length(), (m - c).length());
            if a >= 1.0 {
                self.set_thickness(editor, self.base * f64::from(b / a));
            }
        }
        pointer.clicks()
    }

    fn readout(&self, _editor: &EditorState) -> Option<String> {
        Some(format!("inset thickness {:.4}", self.thickness))
    }

    fn status(&self, _editor: &EditorState) -> String {
        let why = self.refusal.as_ref().map_or(String::new(), |r| format!(" ({r})"));
        format!(
            "inset thickness {:.4}{why}: move the mouse or type it, click or Enter sets, Esc keeps {:.4}",
            self.thickness, self.base
        )
    }

    /// The thickness now (kept) or the menu's (cancelled).
    fn end(mut self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            let base = self.base;
            self.set_thickness(editor, base);
        }
        editor.emit_end_gesture();
    }

    fn is_stale(&self, editor: &EditorState) -> bool {
        self.topology.is_stale(editor)
    }

    fn navigates(&self) -> bool {
        true
    }
}
