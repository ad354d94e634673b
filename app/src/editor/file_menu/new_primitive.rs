//! File ▸ New ▸ UV sphere, icosphere, torus or quad grid with a chosen number of segments: a
//! small dialog with the counts, then the core's primitive (`taut_core::mesh::primitives`) as a
//! new document, every vertex fixed as the other primitives are. A count the core refuses (out of
//! its range) shows its one-line message and keeps the current document.

use crate::editor::document::EditorDocument;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;
use taut_core::mesh::primitives;
use taut_core::{Document, PolyMesh};

/// The primitives with segment counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimitiveKind {
    UvSphere,
    Icosphere,
    Torus,
    QuadGrid,
}

impl PrimitiveKind {
    pub const ALL: [PrimitiveKind; 4] =
        [PrimitiveKind::UvSphere, PrimitiveKind::Icosphere, PrimitiveKind::Torus, PrimitiveKind::QuadGrid];

    pub fn label(self) -> &'static str {
        match self {
            PrimitiveKind::UvSphere => "UV sphere (quads)…",
            PrimitiveKind::Icosphere => "Icosphere…",
            PrimitiveKind::Torus => "Torus…",
            PrimitiveKind::QuadGrid => "Quad grid…",
        }
    }

    /// The names of the two counts (the icosphere has one) and their defaults.
    fn counts(self) -> [(&'static str, u32); 2] {
        match self {
            PrimitiveKind::UvSphere => [("segments around", 8), ("rings pole to pole", 4)],
            PrimitiveKind::Icosphere => [("subdivisions", 1), ("", 0)],
            PrimitiveKind::Torus => [("segments around the axis", 12), ("segments around the tube", 6)],
            PrimitiveKind::QuadGrid => [("cells along x", 4), ("cells along y", 4)],
        }
    }

    /// The cage, about 2 units across and centred on the origin, or the core's message.
    pub fn make(self, a: u32, b: u32) -> Result<PolyMesh, String> {
        match self {
            PrimitiveKind::UvSphere => primitives::uv_sphere(a, b, 1.0),
            PrimitiveKind::Icosphere => primitives::icosphere(a, 1.0),
            PrimitiveKind::Torus => primitives::torus(a, b, 1.0, 0.4),
            PrimitiveKind::QuadGrid => primitives::quad_grid(a, b, 2.0, 2.0),
        }
        .map_err(|e| e.to_string())
    }
}

/// The open dialog: which primitive and its two counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NewPrimitive {
    pub kind: PrimitiveKind,
    pub counts: [u32; 2],
}

impl NewPrimitive {
    pub fn new(kind: PrimitiveKind) -> Self {
        let [(_, a), (_, b)] = kind.counts();
        NewPrimitive { kind, counts: [a, b] }
    }
}

/// A document of a new primitive cage: every vertex fixed, as File ▸ New's other cages.
pub fn document(cage: PolyMesh) -> Document {
    Document::new(cage)
}

impl EditorState {
    /// The File ▸ New entries with counts (inside the New menu).
    pub(crate) fn new_primitive_items(&mut self, ui: &mut egui::Ui, ui_state: &mut UiState) {
        for kind in PrimitiveKind::ALL {
            if ui.button(kind.label()).clicked() {
                ui_state.new_primitive = Some(NewPrimitive::new(kind));
            }
        }
    }

    /// The dialog, while open: counts, Create and Cancel.
    pub(crate) fn new_primitive_dialog(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let Some(mut dialog) = ui_state.new_primitive.take() else { return };
        let mut answer = None;
        egui::Modal::new(egui::Id::unique("new primitive")).show(ctx, |ui| {
            ui.label(format!("New {}", dialog.kind.label().trim_end_matches('…')));
            for (k, (name, _)) in dialog.kind.counts().into_iter().enumerate() {
                if !name.is_empty() {
                    ui.horizontal(|ui| {
                        ui.label(name);
                        ui.add(egui::DragValue::new(&mut dialog.counts[k]).range(0..=256));
                    });
                }
            }
            ui.horizontal(|ui| {
                if ui.button("Create").clicked() {
                    answer = Some(true);
                }
                if ui.button("Cancel").clicked() {
                    answer = Some(false);
                }
            });
        });
        match answer {
            Some(true) => match dialog.kind.make(dialog.counts[0], dialog.counts[1]) {
                Ok(cage) => {
                    let mut doc = document(cage);
                    doc.settings.levels = crate::editor::document::display_levels(doc.cage.face_count());
                    if self.document.is_dirty() {
                        ui_state.pending = Some(crate::editor::ui::Pending::NewDocument(Box::new(doc)));
                    } else {
                        self.replace_document(EditorDocument::new(doc, None));
                    }
                }
                Err(message) => {
                    self.notify(message, true);
                    ui_state.new_primitive = Some(dialog);
                }
            },
            Some(false) => {}
            None => ui_state.new_primitive = Some(dialog),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::panel_tests::{cube_editor, frames};
    use egui_kittest::kittest::Queryable;

    #[test]
    fn file_new_makes_each_primitive_with_the_chosen_counts() {
        // Closed forms: UV sphere n·(m−1)+2 vertices and n·m faces; icosphere 10·4^s+2 vertices;
        // torus a·b vertices and faces; grid (x+1)(y+1) vertices and x·y faces.
        let cases = [
            (PrimitiveKind::UvSphere, [6, 5], (6 * 4 + 2, 30)),
            (PrimitiveKind::Icosphere, [1, 0], (42, 80)),
            (PrimitiveKind::Torus, [9, 5], (45, 45)),
            (PrimitiveKind::QuadGrid, [3, 2], (12, 6)),
        ];
        for (kind, counts, (nv, nf)) in cases {
            let mut h = cube_editor();
            h.get_by_label("File").click();
            frames(&mut h);
            for _ in 0..5 {
                if h.query_by_label("New").is_some() {
                    break;
                }
                frames(&mut h);
            }
            h.get_by_label("New").hover();
            frames(&mut h);
            for _ in 0..5 {
                if h.query_by_label(kind.label()).is_some() {
                    break;
                }
                frames(&mut h);
            }
            h.get_by_label(kind.label()).click();
            frames(&mut h);
            h.state_mut().ui.new_primitive.as_mut().expect("the dialog opened").counts = counts;
            frames(&mut h);
            h.get_by_label("Create").click();
            frames(&mut h);
            let editor = &h.state().editor;
            let cage = &editor.document.doc().cage;
            assert_eq!((cage.vertex_count(), cage.face_count()), (nv, nf), "{kind:?}");
            editor.document.doc().validate().unwrap();
            assert!(h.state().ui.new_primitive.is_none());
        }
    }

    #[test]
    fn counts_out_of_range_keep_the_document_and_say_why() {
        let mut h = cube_editor();
        h.state_mut().ui.new_primitive = Some(NewPrimitive { kind: PrimitiveKind::Torus, counts: [2, 5] });
        frames(&mut h);
        let before = h.state().editor.document.revision();
        h.get_by_label("Create").click();
        frames(&mut h);
        let editor = &h.state().editor;
        assert_eq!(editor.document.revision(), before);
        assert_eq!(editor.document.doc().cage.face_count(), 6);
        assert!(editor.notice.as_ref().is_some_and(|n| n.is_error && !n.text.contains('\n')));
        assert!(h.state().ui.new_primitive.is_some(), "the dialog stays open to fix the count");
    }
}
