//! The modelling keys and the Mesh menu driven through the real UI frame (egui_kittest): each key
//! or entry reaches its operation (the cage's counts change as the operation's closed form says),
//! undo and redo restore the document bit for bit, and a refused request changes nothing and
//! says why.

use super::mesh_ops::MeshOp;
use super::panel_tests::{App, cube_editor, frames};
use super::select_modes::SelectMode;
use super::shortcuts::Action;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use taut_core::{Document, FaceId, PolyMesh, VertexId};

fn counts(h: &Harness<'_, App>) -> (usize, usize, usize) {
    let c = &h.state().editor.document.doc().cage;
    (c.vertex_count(), c.edge_count(), c.face_count())
}

pub(super) fn top_face(cage: &PolyMesh) -> FaceId {
    cage.faces().find(|&f| cage.face_vertices(f).all(|v| cage.position(v).z > 0.0)).unwrap()
}

/// The cube editor in face mode with the top face selected.
fn top_face_selected() -> Harness<'static, App> {
    let mut h = cube_editor();
    let editor = &mut h.state_mut().editor;
    let top = top_face(&editor.document.doc().cage);
    editor.view.selection.clear();
    editor.view.selection.mode = SelectMode::Face;
    editor.view.selection.faces = vec![top];
    frames(&mut h);
    h
}

/// Bit-level identity of two documents (positions compared by their bits, not as floats).
fn same_bits(a: &Document, b: &Document) -> bool {
    let bits =
        |d: &Document| d.cage.positions().iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    a == b && bits(a) == bits(b) && a.cage.polygons() == b.cage.polygons()
}

/// Presses `key` with `modifiers`, then checks counts, undo and redo.
fn check_key(mut h: Harness<'static, App>, modifiers: Modifiers, key: Key, expected: (usize, usize, usize)) {
    let before = h.state().editor.document.doc().clone();
    h.key_press_modifiers(modifiers, key);
    frames(&mut h);
    // E goes on to move what it lifted, Ctrl+R to slide the loop: Enter sets them where they are.
    h.key_press(Key::Enter);
    frames(&mut h);
    assert_eq!(h.state().editor.notice.as_ref().filter(|n| n.is_error), None, "{key:?} was refused");
    assert_eq!(counts(&h), expected, "{key:?}");
    let after = h.state().editor.document.doc().clone();
    after.validate().unwrap();
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(same_bits(h.state().editor.document.doc(), &before), "{key:?}: one undo restores the cube");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut h);
    assert!(same_bits(h.state().editor.document.doc(), &after), "{key:?}: redo restores the edit");
}

#[test]
fn e_extrudes_the_top_face_and_keeps_it_selected_above_the_old_one() {
    let mut h = top_face_selected();
    h.key_press(Key::E);
    frames(&mut h);
    // A quad extruded from a closed cube: 4 new vertices, 4 side and 4 cap edges, 4 walls.
    assert_eq!(counts(&h), (12, 20, 10));
    let editor = &h.state().editor;
    let cage = &editor.document.doc().cage;
    assert_eq!(editor.view.selection.faces.len(), 1);
    let cap = editor.view.selection.faces[0];
    assert!(cage.face_vertices(cap).all(|v| cage.position(v).z > 0.5 + 1e-9), "the cap rose along +z");
    assert!(cage.face_vertices(cap).all(|v| v.index() >= 8 || cage.position(v).z > 0.5));
    check_key(top_face_selected(), Modifiers::NONE, Key::E, (12, 20, 10));
}

#[test]
fn an_extruded_cap_keeps_the_fixed_flags_of_the_corners_it_was_lifted_from() {
    // Free two corners of the top face: their copies on the cap are free, the other two fixed,
    // and the corners left behind keep their flags too (the carry rule of the core's provenance).
    let mut h = top_face_selected();
    let cage = h.state().editor.document.doc().cage.clone();
    let corners: Vec<VertexId> = cage.face_vertices(top_face(&cage)).collect();
    let free = [corners[0], corners[2]];
    h.state_mut().editor.edit(taut_core::Edit::SetFixed(free.to_vec(), false));
    h.key_press(Key::E);
    frames(&mut h);
    let editor = &h.state().editor;
    let (doc, cap) = (editor.document.doc(), editor.view.selection.faces[0]);
    for v in doc.cage.face_vertices(cap) {
        // The copy sits straight above its source corner.
        let source = corners
            .iter()
            .copied()
            .find(|&c| (doc.cage.position(c).truncate() - doc.cage.position(v).truncate()).length() < 1e-12)
            .unwrap();
        assert_eq!(doc.fixed[v.index()], !free.contains(&source), "{v:?} above {source:?}");
        assert_eq!(doc.fixed[source.index()], !free.contains(&source));
    }
}

#[test]
fn each_modelling_key_reaches_its_operation_and_undoes_in_one_step() {
    // I: an inset quad inside the top face with a ring of 4 quads.
    check_key(top_face_selected(), Modifiers::NONE, Key::I, (12, 20, 10));
    // X in face mode: the top face goes, the cube is open.
    check_key(top_face_selected(), Modifiers::NONE, Key::X, (8, 12, 5));
    check_key(top_face_selected(), Modifiers::NONE, Key::Delete, (8, 12, 5));
    // X in vertex mode on vertex 7: it and its three faces go.
    check_key(cube_editor(), Modifiers::NONE, Key::X, (7, 9, 3));
    // Ctrl+R on one selected edge: a ring of 4 quads split, 4 new vertices.
    let mut h = cube_editor();
    h.state_mut().editor.view.selection.vertices.clear();
    h.state_mut().editor.view.selection.edges = vec![taut_core::EdgeId(0)];
    check_key(h, Modifiers::COMMAND, Key::R, (12, 20, 10));
    // M on the two ends of an edge: one vertex fewer, the two faces at the edge become triangles.
    let mut h = cube_editor();
    let (a, b) = h.state().editor.document.doc().cage.edge_vertices(taut_core::EdgeId(0));
    h.state_mut().editor.view.selection.vertices = vec![a, b];
    check_key(h, Modifiers::NONE, Key::M, (7, 11, 6));
}

#[test]
fn f_fills_the_hole_a_delete_left() {
    let mut h = top_face_selected();
    h.key_press(Key::X);
    frames(&mut h);
    assert_eq!(counts(&h), (8, 12, 5));
    // The hole's rim: every boundary edge, in edge mode.
    let editor = &mut h.state_mut().editor;
    let cage = editor.document.doc().cage.clone();
    editor.view.selection.clear();
    editor.view.selection.mode = SelectMode::Edge;
    editor.view.selection.edges = cage.edges().filter(|&e| cage.is_boundary_edge(e)).collect();
    assert_eq!(editor.view.selection.edges.len(), 4);
    check_key(h, Modifiers::NONE, Key::F, (8, 12, 6));
}

#[test]
fn refused_requests_change_nothing_and_say_why() {
    // E with nothing selected, M with one vertex, Ctrl+R with nothing under the mouse.
    for (select, key, modifiers, words) in [
        (Vec::new(), Key::E, Modifiers::NONE, "select faces"),
        (vec![VertexId(7)], Key::M, Modifiers::NONE, "two or more vertices"),
        (Vec::new(), Key::R, Modifiers::COMMAND, "point at an edge"),
    ] {
        let mut h = cube_editor();
        h.state_mut().editor.view.selection.vertices = select;
        let before = h.state().editor.document.doc().clone();
        let revision = h.state().editor.document.revision();
        h.key_press_modifiers(modifiers, key);
        frames(&mut h);
        let editor = &h.state().editor;
        assert!(same_bits(editor.document.doc(), &before));
        assert_eq!(editor.document.revision(), revision);
        assert!(!editor.document.can_undo());
        let notice = editor.notice.as_ref().expect("a message");
        assert!(notice.is_error && notice.text.contains(words), "{key:?}: {}", notice.text);
        assert!(!notice.text.contains('\n'));
    }
    // The core refuses: inset of a whole closed cube by a fifth of an edge is fine, but
    // extruding all six faces as one region has no mean normal.
    let mut h = top_face_selected();
    let all: Vec<FaceId> = h.state().editor.document.doc().cage.faces().collect();
    h.state_mut().editor.view.selection.faces = all.clone();
    let before = h.state().editor.document.doc().clone();
    h.key_press(Key::E);
    frames(&mut h);
    let editor = &h.state().editor;
    assert!(same_bits(editor.document.doc(), &before));
    assert!(editor.notice.as_ref().is_some_and(|n| n.is_error && n.text.contains("extrude")));
    assert_eq!(editor.view.selection.faces, all, "a refused edit keeps the selection");
}

#[test]
fn the_mesh_menu_reaches_every_operation_and_tab_cycles_the_modes() {
    let mut h = top_face_selected();
    h.get_by_label("Mesh").click();
    frames(&mut h);
    // The menu opens a frame after the click.
    for _ in 0..5 {
        if h.query_by_label(MeshOp::Triangulate.label()).is_some() {
            break;
        }
        frames(&mut h);
    }
    h.get_by_label(MeshOp::Triangulate.label()).click();
    frames(&mut h);
    // Triangulating the selected top face: one more face and one more edge.
    assert_eq!(counts(&h), (8, 13, 7));
    assert!(h.state().ui.action_log.contains(&Action::Mesh(MeshOp::Triangulate)));

    let mut h = cube_editor();
    for mode in [SelectMode::Edge, SelectMode::Face, SelectMode::Vertex] {
        h.key_press(Key::Tab);
        frames(&mut h);
        assert_eq!(h.state().editor.view.selection.mode, mode);
    }
    // A lone vertex spans no edge, so the round trip through edge mode dropped it (as in Blender).
    assert!(h.state().editor.view.selection.is_empty());
    // Ctrl+L from one vertex selects the whole cube.
    h.state_mut().editor.view.selection.vertices = vec![VertexId(7)];
    h.key_press_modifiers(Modifiers::COMMAND, Key::L);
    frames(&mut h);
    assert_eq!(h.state().editor.view.selection.vertices.len(), 8);
    // The frame-selection key moved to "." (F is fill).
    h.key_press(Key::Period);
    frames(&mut h);
    assert_eq!(h.state().ui.action_log.last(), Some(&Action::FrameSelection));
}

#[test]
fn the_status_bar_and_the_cage_panel_count_selected_faces() {
    let h = top_face_selected();
    let label = |text: &str| h.query(egui_kittest::kittest::By::new().label(text).include_labels()).is_some();
    assert!(label("0 vertices, 0 edges, 1 face selected"), "the status bar counts the face");
    assert!(label("0 vertices, 0 edges, 1 face"), "the cage panel counts the face");
}

#[test]
fn a_mesh_operation_says_which_curve_mesh_edits_it_dropped() {
    use taut_core::surface::SchemeKind;
    use taut_core::{DVec3, Edit};
    let mut h = cube_editor();
    {
        let editor = &mut h.state_mut().editor;
        let mut doc = editor.document.doc().clone().with_scheme(SchemeKind::CurveMesh);
        let p = doc.curve_mesh().unwrap().0.vertex_position(VertexId(5));
        doc.apply(Edit::MoveCurveMeshVertices(vec![(VertexId(5), p + DVec3::Z * 0.1)])).unwrap();
        // The cage is edited in the other schemes; the curve-mesh edits stay in the document.
        let doc = doc.with_scheme(SchemeKind::Nusd);
        assert_eq!(doc.curve_mesh.vertices.len(), 1);
        editor.document.apply(Edit::Replace(Box::new(doc))).unwrap();
        editor.view.selection.clear();
        editor.view.selection.vertices = vec![VertexId(5)];
    }
    frames(&mut h);
    h.key_press(Key::X);
    frames(&mut h);
    let editor = &h.state().editor;
    assert_eq!(editor.document.doc().cage.vertex_count(), 7, "X deleted the vertex");
    assert!(editor.document.doc().curve_mesh.vertices.is_empty(), "its curve-mesh edit could not follow");
    let notice = editor.notice.as_ref().expect("a message says so");
    assert!(notice.text.contains("dropped") && !notice.is_error, "{}", notice.text);
}
