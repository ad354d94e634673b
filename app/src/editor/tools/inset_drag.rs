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
use crate::editor::interaction::{self, ViewportRect};
use crate::editor::mesh_ops::{self, MeshOp, OFFSET_FRACTION};
use crate::editor::shortcuts;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;
use egui::Key;
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
    topology: u64,
}

impl EditorState {
    /// I: inset the selected faces, then let the mouse set the thickness.
    pub(crate) fn inset_and_drag(&mut self, ui_state: &mut UiState) {
        let doc = self.document.doc();
        let cage = &doc.cage;
        let faces = mesh_ops::picked(cage, self).faces;
        let base = OFFSET_FRACTION * mesh_ops::mean_edge_length(cage, &mesh_ops::face_edges(cage, &faces));
        let original = Box::new(doc.clone());
        self.document.begin_gesture();
        let revision = self.document.revision();
        self.mesh_op(MeshOp::Inset);
        if self.document.revision() == revision {
            self.document.end_gesture();
            return;
        }
        let Ok(edited) = inset_faces(&original.cage, &faces, FaceGrouping::Region, base) else {
            self.document.end_gesture();
            return;
        };
        let ring = (0..edited.provenance.vertices.len() as u32)
            .map(VertexId)
            .filter(|v| matches!(edited.provenance.vertices[v.index()], VertexOrigin::CopyOf(_)))
            .collect();
        let corners: Vec<DVec3> =
            faces.iter().flat_map(|&f| original.cage.face_vertices(f)).map(|v| original.cage.position(v)).collect();
        let centre = corners.iter().copied().sum::<DVec3>() / corners.len().max(1) as f64;
        ui_state.inset_drag = Some(InsetDrag {
            original,
            faces,
            ring,
            centre,
            base,
            thickness: base,
            mouse_start: ui_state.pointer,
            typed: String::new(),
            refusal: None,
            topology: self.document.doc().cage.topology_generation(),
        });
    }

    /// Puts the inner ring where an inset of `thickness` puts it.
    fn set_inset_thickness(&mut self, thickness: f64, ui_state: &mut UiState) {
        let Some(d) = &mut ui_state.inset_drag else { return };
        if !thickness.is_finite() || thickness == d.thickness {
            return;
        }
        match inset_faces(&d.original.cage, &d.faces, FaceGrouping::Region, thickness) {
            Ok(edited) => {
                d.thickness = thickness;
                d.refusal = None;
                let moves = d.ring.iter().map(|&v| (v, edited.mesh.position(v))).collect();
                self.edit(Edit::MoveVertices(moves));
            }
            Err(e) => d.refusal = Some(e.to_string()),
        }
    }

    /// Ends the drag: the thickness now (`keep`) or the menu's.
    fn finish_inset(&mut self, keep: bool, ui_state: &mut UiState) {
        if !keep && let Some(base) = ui_state.inset_drag.as_ref().map(|d| d.base) {
            self.set_inset_thickness(base, ui_state);
        }
        ui_state.inset_drag = None;
        self.document.end_gesture();
    }

    /// The keys while the thickness follows the mouse: digits, Enter, Esc; nothing else runs.
    pub(crate) fn inset_keys(&mut self, ctx: &egui::Context, ui_state: &mut UiState) -> bool {
        self.drop_stale_inset(ui_state);
        let Some(d) = &mut ui_state.inset_drag else { return false };
        let (mut enter, mut escape) = (false, false);
        ctx.input_mut(|i| {
            shortcuts::take_typed_number(i, &mut d.typed, false);
            enter = shortcuts::take_plain(i, Key::Enter);
            escape = shortcuts::take_plain(i, Key::Escape);
            i.events.retain(|e| !matches!(e, egui::Event::Text(_)));
        });
        if let Ok(t) = d.typed.parse::<f64>() {
            self.set_inset_thickness(t, ui_state);
        }
        if escape {
            self.finish_inset(false, ui_state);
        } else if enter {
            self.finish_inset(true, ui_state);
        }
        true
    }

    /// Ends the drag without touching the cage when the cage was replaced under it.
    fn drop_stale_inset(&mut self, ui_state: &mut UiState) {
        let topology = self.document.doc().cage.topology_generation();
        if ui_state.inset_drag.as_ref().is_some_and(|d| d.topology != topology) {
            ui_state.inset_drag = None;
            self.document.end_gesture();
        }
    }

    /// The viewport while the thickness follows the mouse.
    pub(crate) fn inset_viewport(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        view: &ViewportRect,
        mouse: Option<Vec2>,
        ui_state: &mut UiState,
    ) {
        self.drop_stale_inset(ui_state);
        let Some(d) = &mut ui_state.inset_drag else { return };
        let centre = interaction::project(&self.camera, view, self.display_frame.to_display_f64(d.centre));
        if let (Some((c, _)), Some(m), true) = (centre, mouse, d.typed.is_empty()) {
            let start = *d.mouse_start.get_or_insert(m);
            let (a, b) = ((start - c).length(), (m - c).length());
            if a >= 1.0 {
                let thickness = d.base * f64::from(b / a);
                self.set_inset_thickness(thickness, ui_state);
            }
        }
        if response.clicked_by(egui::PointerButton::Primary) {
            self.finish_inset(true, ui_state);
        } else if response.clicked_by(egui::PointerButton::Secondary) {
            self.finish_inset(false, ui_state);
        }
        let Some(d) = &ui_state.inset_drag else { return };
        let why = d.refusal.as_ref().map_or(String::new(), |r| format!(" ({r})"));
        ui.painter_at(response.rect).text(
            response.rect.left_top() + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            format!(
                "inset thickness {:.4}{why}: move the mouse or type it, click or Enter sets, Esc keeps {:.4}",
                d.thickness, d.base
            ),
            egui::FontId::proportional(14.0),
            egui::Color32::WHITE,
        );
    }
}
