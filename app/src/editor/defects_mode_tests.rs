//! The select mode a designer is in is never a surprise: the status bar names it, a new
//! document starts in vertex mode, the Cage panel's hint speaks of the mode's own elements, and
//! a click that selects nothing in this mode, where an element of another mode lies, says so.

use super::gizmo_tests::{pixel_of, viewport};
use super::panel_tests::{App, cube_editor, frames, settle};
use super::select_modes::SelectMode;
use egui::{Key, Modifiers, PointerButton, pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use taut_render::StandardView;

/// The primary button pressed or let go at `at`, then a frame.
pub(super) fn press(h: &mut Harness<'_, App>, at: glam::Vec2, pressed: bool) {
    let event = egui::Event::PointerButton {
        pos: pos2(at.x, at.y),
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    h.input_mut().events.push(event);
    frames(h);
}

/// A click at `at`, the pointer moved there first.
pub(super) fn click(h: &mut Harness<'_, App>, at: glam::Vec2) {
    h.hover_at(pos2(at.x, at.y));
    frames(h);
    press(h, at, true);
    press(h, at, false);
}

#[test]
fn the_status_bar_names_the_select_mode_and_a_new_document_starts_in_vertex_mode() {
    let mut h = cube_editor();
    frames(&mut h);
    h.get_by_label("vertex mode");
    h.key_press(Key::Tab);
    h.key_press(Key::Tab);
    frames(&mut h);
    assert_eq!(h.state().editor.view.selection.mode, SelectMode::Face);
    h.get_by_label("face mode");
    h.state_mut().editor.view.selection.clear();
    frames(&mut h);
    h.get_by_label_contains("Face mode: click a cage face");
    let fresh = super::document::EditorDocument::new(super::primitives::cube(), None);
    h.state_mut().editor.replace_document(fresh);
    frames(&mut h);
    assert_eq!(h.state().editor.view.selection.mode, SelectMode::Vertex, "New and Open start in vertex mode");
    h.get_by_label("vertex mode");
    h.get_by_label_contains("Vertex mode: click a cage vertex");
}

#[test]
fn a_click_beside_a_corner_in_face_mode_says_that_a_vertex_is_there() {
    let mut h = cube_editor();
    h.state_mut().editor.view.camera.set_view(StandardView::Perspective);
    h.state_mut().editor.view.selection.clear();
    frames(&mut h);
    h.state_mut().editor.view.selection.mode = SelectMode::Face;
    // The view is framed again while the surface settles: the pixels are read once it has.
    settle(&mut h);
    frames(&mut h);
    // The corner drawn farthest from the cube's centre is on its outline: 5 px further out no
    // face lies under the mouse, but the corner is within the 8 px a vertex is picked at.
    let cage = h.state().editor.document.doc().cage.clone();
    let mean = cage.vertices().map(|v| cage.position(v)).sum::<taut_core::DVec3>() / cage.vertex_count() as f64;
    let centre = pixel_of(&h, mean);
    let corner = cage
        .vertices()
        .map(|v| pixel_of(&h, cage.position(v)))
        .max_by(|a, b| a.distance(centre).total_cmp(&b.distance(centre)))
        .unwrap();
    let at = corner + 5.0 * (corner - centre).normalize();
    assert!(viewport(&h).size.x > 0.0);
    click(&mut h, at);
    assert!(h.state().editor.view.selection.is_empty(), "nothing selected in face mode");
    let notice = h.state().editor.notice.clone().expect("the click says why nothing was selected");
    assert!(notice.text.contains("face mode: no face there") && notice.text.contains("a vertex"), "{}", notice.text);
    // The same click on empty space far from the cube stays silent.
    h.state_mut().editor.notice = None;
    let v = viewport(&h);
    click(&mut h, v.min + glam::Vec2::new(12.0, v.size.y - 12.0));
    assert_eq!(h.state().editor.notice, None);
}
