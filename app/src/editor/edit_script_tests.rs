//! A designer's session recorded as an edit script: modelling keys, a loop cut that slides, a
//! move, a crease and an undone step, driven through the real UI frame; the script
//! (`EditorDocument::script`, what File ▸ Save edit script… writes) replayed on the file as
//! opened gives the editor's document bit for bit, and Edit ▸ Undo names each step.

use super::mesh_ops_tests::top_face;
use super::panel_tests::{App, cube_editor, frames};
use super::select_modes::SelectMode;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use taut_core::document::modelling::Script;
use taut_core::{DVec3, EdgeId, Edit};

fn press(h: &mut Harness<'static, App>, modifiers: Modifiers, key: Key) {
    h.key_press_modifiers(modifiers, key);
    frames(h);
    // E goes on to move what it lifted, Ctrl+R to slide the loop: Enter sets them where they are.
    h.key_press(Key::Enter);
    frames(h);
    assert_eq!(h.state().editor.notice.as_ref().filter(|n| n.is_error), None, "{key:?} was refused");
}

#[test]
fn a_recorded_session_replays_to_the_editors_document_bit_for_bit_and_undo_names_its_steps() {
    let mut h = cube_editor();
    let opened = h.state().editor.document.doc().clone();
    // Extrude the top face.
    {
        let editor = &mut h.state_mut().editor;
        let top = top_face(&editor.document.doc().cage);
        editor.view.selection.clear();
        editor.view.selection.mode = SelectMode::Face;
        editor.view.selection.faces = vec![top];
    }
    frames(&mut h);
    press(&mut h, Modifiers::NONE, Key::E);
    assert_eq!(h.state().editor.document.undo_name(), Some("Extrude"));
    // Edit ▸ Undo says what it undoes.
    h.get_by_label("Edit").click();
    frames(&mut h);
    for _ in 0..5 {
        if h.query_by_label("Undo Extrude  Ctrl+Z").is_some() {
            break;
        }
        frames(&mut h);
    }
    h.get_by_label("Undo Extrude  Ctrl+Z").click();
    frames(&mut h);
    assert_eq!(h.state().editor.document.redo_name(), Some("Extrude"));
    assert_eq!(h.state().editor.document.doc().cage.face_count(), 6, "the extrusion is undone");
    // An inset instead (the undone extrusion is not in the script), then a loop cut and slide.
    press(&mut h, Modifiers::NONE, Key::I);
    assert_eq!(h.state().editor.document.undo_name(), Some("Inset"));
    {
        let editor = &mut h.state_mut().editor;
        editor.view.selection.clear();
        editor.view.selection.mode = SelectMode::Edge;
        editor.view.selection.edges = vec![EdgeId(0)];
    }
    frames(&mut h);
    press(&mut h, Modifiers::COMMAND, Key::R);
    // With the mouse over the viewport Ctrl+R previews and Enter cuts; a second Enter sets the
    // slide.
    if h.state().editor.document.in_gesture() {
        h.key_press(Key::Enter);
        frames(&mut h);
    }
    assert_eq!(h.state().editor.document.undo_name(), Some("Loop Cut"));
    // A move, a crease, and X in vertex mode.
    let editor = &mut h.state_mut().editor;
    editor.edit(Edit::MoveVertices(vec![(taut_core::VertexId(3), DVec3::new(-0.4, 0.65, 0.5))]));
    editor.edit(Edit::SetCrease(vec![EdgeId(2)], f64::INFINITY));
    assert!(!editor.document.in_gesture(), "the slide ended");
    assert_eq!(editor.notice.as_ref().filter(|n| n.is_error), None);
    assert_eq!(editor.document.undo_name(), Some("Set Crease"));
    editor.view.selection.clear();
    editor.view.selection.mode = SelectMode::Vertex;
    editor.view.selection.vertices = vec![taut_core::VertexId(1)];
    frames(&mut h);
    press(&mut h, Modifiers::NONE, Key::X);
    assert_eq!(h.state().editor.document.undo_name(), Some("Delete Vertices"));

    let edited = h.state().editor.document.doc().clone();
    assert_ne!(edited.cage.face_count(), opened.cage.face_count());
    let text = h.state().editor.document.script().unwrap().to_json();
    assert!(text.contains("\"op\":\"inset\"") && text.contains("\"op\":\"loop_cut\""), "{text}");
    assert!(!text.contains("extrude"), "an undone step is not in the script: {text}");
    let mut replayed = opened.clone();
    Script::from_json(&text).unwrap().replay(&mut replayed).unwrap();
    assert_eq!(replayed, edited);
    assert_eq!(replayed.to_json(), edited.to_json(), "bit for bit, as the file says it");
    let bits = |d: &taut_core::Document| {
        d.cage.positions().iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>()
    };
    assert_eq!(bits(&replayed), bits(&edited));
}

#[test]
fn a_session_with_a_step_a_script_cannot_say_refuses_to_be_saved_as_one() {
    let mut h = cube_editor();
    let editor = &mut h.state_mut().editor;
    let mut other = editor.document.doc().clone();
    other.cage.set_position(taut_core::VertexId(0), DVec3::new(0.1, 0.2, 0.3));
    editor.edit(Edit::Replace(Box::new(other)));
    let message = editor.document.script().unwrap_err();
    assert!(message.contains("Replace Cage") && !message.contains('\n'), "{message}");
    // Undone, it is no longer part of the session.
    editor.undo();
    assert_eq!(editor.document.script().unwrap().edits.len(), 0);
}

#[test]
fn a_session_on_an_imported_mesh_replays_on_that_mesh_as_taut_edit_opens_it() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/knob.obj");
    let mut editor = super::document::EditorDocument::open(&path).unwrap();
    editor.apply_mesh(taut_core::document::modelling::MeshEdit::Inset { faces: vec![3], distance: 2.0 }).unwrap();
    editor.apply(Edit::SetVertexTension(vec![taut_core::VertexId(5)], 0.5)).unwrap();
    let script = Script::from_json(&editor.script().unwrap().to_json()).unwrap();
    // The editor shows the mesh at its display levels; the script says so first.
    let (mut replayed, _) = taut_core::Document::open(&path, &Default::default()).unwrap();
    assert_ne!(replayed.settings.levels, editor.doc().settings.levels);
    script.replay(&mut replayed).unwrap();
    assert_eq!(replayed.to_json(), editor.doc().to_json());
}
