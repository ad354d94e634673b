//! Mirror modelling driven through the real UI frame (egui_kittest): Mesh ▸ Mirror, Shift+M and
//! the panel toggle reach the option; drags and typed G/S of either half move the other by exact
//! reflections and keep plane vertices on the plane; a one-half cage shows the whole surface and
//! the virtual half as ghost lines; Apply mirror is one undo step restored bit for bit; a refused
//! apply leaves the document untouched.

use crate::editor::panel_tests::{App, cube_editor, editor_on, frames, open_menu_item, settle};
use crate::editor::shortcuts::{self, Action};
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use taut_core::mesh::edit::{Axis, MirrorPlane, delete_faces};
use taut_core::{DVec3, Document, VertexId};

/// The cube moved to x ∈ [0, 1] with its face at x = 0 deleted: one half about x = 0.
fn half_box() -> Document {
    let mut cube = crate::editor::primitives::cube().cage;
    for p in cube.positions_mut() {
        p.x += 0.5;
    }
    let x0 = cube.faces().find(|&f| cube.face_vertices(f).all(|v| cube.position(v).x == 0.0)).unwrap();
    Document::new(delete_faces(&cube, &[x0]).unwrap().mesh)
}

fn bits(d: &Document) -> Vec<u64> {
    d.cage.positions().iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect()
}

fn mirror(h: &Harness<'static, App>) -> Option<MirrorPlane> {
    h.state().editor.document.doc().mirror
}

#[test]
fn the_mesh_menu_and_shift_m_turn_the_mirror_on_and_off() {
    let mut h = cube_editor();
    open_menu_item(&mut h, &["Mesh", "Mirror", "Plane Y through the origin"]);
    assert_eq!(mirror(&h), Some(MirrorPlane::new(Axis::Y, 0.0)));
    h.key_press_modifiers(Modifiers::SHIFT, Key::M);
    frames(&mut h);
    assert_eq!(mirror(&h), None, "Shift+M turns it off");
    h.key_press_modifiers(Modifiers::SHIFT, Key::M);
    frames(&mut h);
    assert_eq!(mirror(&h), Some(MirrorPlane::new(Axis::Y, 0.0)), "and back on with the plane last used");
    assert_eq!(shortcuts::label(Action::ToggleMirror), "Shift+M");
    // Through the selection's centre: vertex 7 is at z = 0.5.
    open_menu_item(&mut h, &["Mesh", "Mirror", "Plane Z through the selection's centre"]);
    assert_eq!(mirror(&h), Some(MirrorPlane::new(Axis::Z, 0.5)));
    // Each change is an undo step.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert_eq!(mirror(&h), Some(MirrorPlane::new(Axis::Y, 0.0)));
    // The panel's checkbox toggles it too.
    h.get_by_label("Mirror modelling").click();
    frames(&mut h);
    assert_eq!(mirror(&h), None);
}

#[test]
fn a_drag_and_typed_moves_of_one_half_move_the_other_exactly() {
    let mut h = cube_editor();
    h.state_mut().editor.set_mirror(Axis::X, crate::editor::mirror::MirrorThrough::Origin);
    // Vertex 7 (0.5, 0.5, 0.5) has partner 6 (−0.5, 0.5, 0.5).
    let target = DVec3::new(0.61, 0.4371, 0.73);
    h.state_mut().editor.edit(taut_core::Edit::MoveVertices(vec![(VertexId(7), target)]));
    frames(&mut h);
    let cage = &h.state().editor.document.doc().cage;
    assert_eq!(
        cage.position(VertexId(6)).to_array().map(f64::to_bits),
        [(-target.x).to_bits(), target.y.to_bits(), target.z.to_bits()]
    );
    // G, Y, 0.25, Enter: the partner follows along y, one undo step for both.
    let before = h.state().editor.document.doc().clone();
    for key in [Key::G, Key::Y, Key::Num0, Key::Period, Key::Num2, Key::Num5, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let doc = h.state().editor.document.doc().clone();
    assert_eq!(doc.cage.position(VertexId(7)), target + DVec3::Y * 0.25);
    assert_eq!(doc.cage.position(VertexId(6)), MirrorPlane::new(Axis::X, 0.0).reflect(doc.cage.position(VertexId(7))));
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert_eq!(bits(h.state().editor.document.doc()), bits(&before), "undo restores both halves bit for bit");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut h);
    assert_eq!(bits(h.state().editor.document.doc()), bits(&doc), "redo too");
}

#[test]
fn a_half_shows_the_whole_surface_and_its_plane_vertices_stay_on_the_plane() {
    let mut h = editor_on(half_box());
    h.state_mut().editor.view.selection.vertices = h.state().editor.document.doc().cage.vertices().collect();
    h.state_mut().editor.set_mirror(Axis::X, crate::editor::mirror::MirrorThrough::Origin);
    settle(&mut h);
    let editor = &h.state().editor;
    let surface = editor.surface_mesh().unwrap();
    let (lo, hi) = surface.bounding_box().unwrap();
    assert!(lo.x < -0.9 && hi.x > 0.9, "the surface spans both halves: {lo} .. {hi}");
    assert_eq!(editor.document.doc().cage.vertex_count(), 8, "the document holds the real half only");
    let lines = editor.overlays().on_top_lines;
    let ghost = lines.iter().filter(|l| l.color == crate::editor::mirror::GHOST_COLOUR).count();
    assert_eq!(ghost, 8, "the virtual half's 12 edges less the 4 on the plane, drawn as ghosts");
    // S 1.5 about the centre (x = 0.5) would push the plane vertices to x = −0.25: they stay on it.
    for key in [Key::S, Key::Num1, Key::Period, Key::Num5, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let cage = &h.state().editor.document.doc().cage;
    let on_plane = cage.vertices().filter(|&v| cage.position(v).x == 0.0).count();
    assert_eq!(on_plane, 4, "the four plane vertices are still exactly on x = 0");
    assert!(cage.positions().iter().any(|p| (p.x - 1.25).abs() < 1e-12), "the far side scaled by 1.5 about x = 0.5");
    settle(&mut h);
    let (lo, hi) = h.state().editor.surface_mesh().unwrap().bounding_box().unwrap();
    assert!((lo.x + hi.x).abs() < 1e-9, "the whole surface stays symmetric: {lo} .. {hi}");
}

#[test]
fn apply_mirror_is_one_undo_step_and_a_refused_one_changes_nothing() {
    let mut h = editor_on(half_box());
    h.state_mut().editor.set_mirror(Axis::X, crate::editor::mirror::MirrorThrough::Origin);
    frames(&mut h);
    let before = h.state().editor.document.doc().clone();
    open_menu_item(&mut h, &["Mesh", "Mirror", "Apply mirror"]);
    let after = h.state().editor.document.doc().clone();
    assert_eq!((after.cage.vertex_count(), after.cage.face_count()), (12, 10));
    assert!(after.cage.is_closed());
    assert_eq!(after.mirror, before.mirror, "the option stays on, editing both halves");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc(), &before);
    assert_eq!(bits(h.state().editor.document.doc()), bits(&before));
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut h);
    assert_eq!(bits(h.state().editor.document.doc()), bits(&after));
    // Applying again: the plane now cuts the cage's faces (vertices on both sides): refused.
    let revision = h.state().editor.document.revision();
    open_menu_item(&mut h, &["Mesh", "Mirror", "Apply mirror"]);
    let editor = &h.state().editor;
    assert_eq!(editor.document.revision(), revision, "the document is untouched");
    let notice = editor.notice.as_ref().unwrap();
    assert!(notice.is_error && notice.text.contains("both sides") && !notice.text.contains('\n'), "{notice:?}");
}

#[test]
fn an_unpaired_vertex_is_said_once() {
    let mut h = cube_editor();
    // Vertex 7 moved off symmetry first, then the mirror on: 6 and 7 have no partners.
    h.state_mut().editor.edit(taut_core::Edit::MoveVertices(vec![(VertexId(7), DVec3::new(0.5, 0.5, 0.8))]));
    h.state_mut().editor.set_mirror(Axis::X, crate::editor::mirror::MirrorThrough::Origin);
    let count = |h: &Harness<'static, App>| {
        h.state().editor.messages.iter().filter(|m| m.text.contains("has no partner")).count()
    };
    for z in [0.9, 1.0] {
        h.state_mut().editor.edit(taut_core::Edit::MoveVertices(vec![(VertexId(7), DVec3::new(0.5, 0.5, z))]));
        frames(&mut h);
    }
    assert_eq!(count(&h), 1);
    assert_eq!(h.state().editor.document.doc().cage.position(VertexId(6)), DVec3::new(-0.5, 0.5, 0.5), "moved alone");
}

#[test]
fn the_mirror_plane_is_drawn_while_mirror_is_on_and_lies_in_the_plane() {
    let mut h = cube_editor();
    let plane_lines = |h: &Harness<'static, App>| {
        let data = h.state().editor.overlays();
        let colour = [0.85, 0.25, 0.75, 0.9];
        data.on_top_lines.iter().filter(|l| l.color == colour).cloned().collect::<Vec<_>>()
    };
    assert!(plane_lines(&h).is_empty(), "no mirror, no plane");
    open_menu_item(&mut h, &["Mesh", "Mirror", "Plane Y through the origin"]);
    let lines = plane_lines(&h);
    assert_eq!(lines.len(), 6, "a rectangle and its diagonals");
    let frame = h.state().editor.view.display_frame;
    let cage = &h.state().editor.document.doc().cage;
    let (lo, hi) = taut_core::mesh::bounding_box(cage.positions()).unwrap();
    for l in &lines {
        for p in [l.a, l.b] {
            let q = frame.to_model(p.as_dvec3());
            assert!(q.y.abs() < 1e-6, "on the plane y = 0: {q}");
            assert!(q.x < lo.x || q.x > hi.x, "beyond the cage's extent: {q}");
        }
    }
}
