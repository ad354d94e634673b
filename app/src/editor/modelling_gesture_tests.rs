//! The modelling gestures driven through the real UI frame (egui_kittest): E extrudes and moves
//! along the region's normal in one undo step (typed, by the mouse, or left in place with Esc),
//! and Ctrl+R previews a loop, cuts it with a click and slides it to where the core's cut at
//! that fraction puts it, in one undo step, or cancels the whole cut with Esc.

use super::gizmo_tests::pixel_of;
use super::mesh_ops::OFFSET_FRACTION;
use super::mesh_ops_tests::top_face;
use super::panel_tests::{App, cube_editor, frames};
use super::select_modes::SelectMode;
use egui::{Key, Modifiers, PointerButton, pos2};
use egui_kittest::Harness;
use taut_core::mesh::edit::{self, FaceGrouping};
use taut_core::{DVec3, Document, EdgeId};
use taut_render::StandardView;

/// The cube in face mode with its top face selected, zoomed out in the front view.
fn top_face_selected() -> Harness<'static, App> {
    let mut h = cube_editor();
    let editor = &mut h.state_mut().editor;
    let top = top_face(&editor.document.doc().cage);
    editor.view.selection.clear();
    editor.view.selection.mode = SelectMode::Face;
    editor.view.selection.faces = vec![top];
    editor.view.camera.set_view(StandardView::Front);
    editor.view.camera.distance *= 2.0;
    frames(&mut h);
    frames(&mut h);
    h
}

fn bits(doc: &Document) -> Vec<[u64; 3]> {
    doc.cage.positions().iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

/// What the core's region extrusion of the top face gives, at the Mesh menu's offset.
fn extruded(doc: &Document) -> Document {
    let cage = &doc.cage;
    let f = top_face(cage);
    let edges: Vec<EdgeId> = cage.face_halfedges(f).map(|h| h.edge()).collect();
    let mean = edges.iter().map(|&e| cage.edge_length(e)).sum::<f64>() / edges.len() as f64;
    let edited = edit::extrude_faces(cage, &[f], FaceGrouping::Region, OFFSET_FRACTION * mean).unwrap();
    doc.with_edited_cage(edited).unwrap()
}

fn click(h: &mut Harness<'_, App>, button: PointerButton, at: glam::Vec2) {
    for pressed in [true, false] {
        h.input_mut().events.push(egui::Event::PointerButton {
            pos: pos2(at.x, at.y),
            button,
            pressed,
            modifiers: Modifiers::NONE,
        });
        frames(h);
    }
}

#[test]
fn e_then_a_typed_distance_lifts_the_cap_along_its_normal_in_one_undo_step() {
    let mut h = top_face_selected();
    let before = h.state().editor.document.doc().clone();
    let lifted = extruded(&before);
    for key in [Key::E, Key::Num1, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let doc = h.state().editor.document.doc().clone();
    assert_eq!(doc.cage.polygons(), lifted.cage.polygons());
    let cap: Vec<_> = doc.cage.face_vertices(h.state().editor.view.selection.faces[0]).collect();
    for v in doc.cage.vertices() {
        let (p, q) = (lifted.cage.position(v), doc.cage.position(v));
        if cap.contains(&v) {
            // The top face's normal is +z exactly: x and y keep their bits, z rises by 1.
            assert_eq!((q.x.to_bits(), q.y.to_bits()), (p.x.to_bits(), p.y.to_bits()));
            assert_eq!(q.z, p.z + 1.0);
        } else {
            assert_eq!(q.to_array().map(f64::to_bits), p.to_array().map(f64::to_bits), "{v:?} stays");
        }
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    let undone = h.state().editor.document.doc();
    assert!(undone == &before && bits(undone) == bits(&before), "one undo step back to the cube, bit for bit");
}

#[test]
fn e_then_the_mouse_moves_along_the_normal_and_esc_leaves_the_extrusion_in_place() {
    // The mouse: up the screen in the front view lifts the cap along z only; a click sets.
    let mut h = top_face_selected();
    let before = h.state().editor.document.doc().clone();
    let lifted = extruded(&before);
    let start = pixel_of(&h, DVec3::new(0.0, 0.0, 0.6));
    h.hover_at(pos2(start.x, start.y));
    frames(&mut h);
    h.key_press(Key::E);
    frames(&mut h);
    assert!(
        h.state().ui.tool.get::<crate::editor::transform::Transform>().is_some_and(|t| t.direction == Some(DVec3::Z)),
        "locked to +z"
    );
    for k in 1..=4 {
        h.hover_at(pos2(start.x + 5.0 * k as f32, start.y - 15.0 * k as f32));
        frames(&mut h);
    }
    click(&mut h, PointerButton::Primary, start + glam::Vec2::new(20.0, -60.0));
    assert!(h.state().ui.tool.get::<crate::editor::transform::Transform>().is_none());
    let doc = h.state().editor.document.doc().clone();
    let cap: Vec<_> = doc.cage.face_vertices(h.state().editor.view.selection.faces[0]).collect();
    for &v in &cap {
        let (p, q) = (lifted.cage.position(v), doc.cage.position(v));
        assert_eq!((q.x.to_bits(), q.y.to_bits()), (p.x.to_bits(), p.y.to_bits()), "along z only");
        assert!(q.z > p.z + 0.05, "lifted further: {} -> {}", p.z, q.z);
    }
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(bits(h.state().editor.document.doc()) == bits(&before), "one undo step");

    // Esc: the extrusion stays as the extrusion made it, and is still one undo step.
    let mut h = top_face_selected();
    h.hover_at(pos2(start.x, start.y));
    frames(&mut h);
    h.key_press(Key::E);
    frames(&mut h);
    h.hover_at(pos2(start.x, start.y - 40.0));
    frames(&mut h);
    h.key_press(Key::Escape);
    frames(&mut h);
    let doc = h.state().editor.document.doc().clone();
    assert!(doc == lifted && bits(&doc) == bits(&lifted), "the extrusion, unmoved");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(bits(h.state().editor.document.doc()) == bits(&before));
    assert!(!h.state().editor.document.can_undo());
}

/// The cube in the front view, zoomed out, with nothing selected, and an edge facing the
/// camera whose middle is clear of every other edge: the bottom front edge, from x = −½ to ½.
fn cube_with_front_edge() -> (Harness<'static, App>, EdgeId) {
    let mut h = cube_editor();
    let editor = &mut h.state_mut().editor;
    editor.view.selection.clear();
    editor.view.camera.set_view(StandardView::Perspective);
    editor.view.camera.distance *= 2.0;
    let cage = &editor.document.doc().cage;
    let edge = cage
        .edges()
        .find(|&e| {
            let (a, b) = cage.edge_vertices(e);
            let (p, q) = (cage.position(a), cage.position(b));
            p.y == -0.5 && q.y == -0.5 && p.z == -0.5 && q.z == -0.5
        })
        .unwrap();
    frames(&mut h);
    frames(&mut h);
    (h, edge)
}

/// The cube with the mouse over the middle of its front edge and Ctrl+R pressed: the document
/// before and the pixels of the edge's ends.
fn ctrl_r_over_the_front_edge() -> (Harness<'static, App>, EdgeId, Document, [glam::Vec2; 2]) {
    let (mut h, edge) = cube_with_front_edge();
    let before = h.state().editor.document.doc().clone();
    let (a, b) = before.cage.edge_vertices(edge);
    let (pa, pb) = (pixel_of(&h, before.cage.position(a)), pixel_of(&h, before.cage.position(b)));
    let middle = (pa + pb) * 0.5;
    h.hover_at(pos2(middle.x, middle.y));
    frames(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::R);
    frames(&mut h);
    (h, edge, before, [pa, pb])
}

#[test]
fn ctrl_r_previews_then_a_click_cuts_and_the_mouse_slides_to_the_cores_cut_in_one_undo_step() {
    let (mut h, edge, before, [pa, pb]) = ctrl_r_over_the_front_edge();
    let middle = (pa + pb) * 0.5;
    frames(&mut h);
    match h.state().ui.tool.get::<crate::editor::tools::loop_slide::LoopCutTool>() {
        Some(super::tools::loop_slide::LoopCutTool::Preview { edge: Some(e), lines, refusal: None }) => {
            assert_eq!(*e, edge);
            assert_eq!(lines.len(), 4, "the ring round the cube: four new edges");
        }
        other => panic!("no preview: {other:?}"),
    }
    assert_eq!(h.state().editor.document.doc(), &before, "a preview changes nothing");
    click(&mut h, PointerButton::Primary, middle);
    assert_eq!(h.state().editor.document.doc().cage.vertex_count(), 12, "cut");
    // Slide to 30 % of the way along the edge on screen (pixels are snapped by nothing).
    let to = pa + (pb - pa) * 0.3 + glam::Vec2::new(0.0, 6.0);
    h.hover_at(pos2(to.x, to.y));
    frames(&mut h);
    let fraction = f64::from((to - pa).dot(pb - pa) / (pb - pa).length_squared());
    assert!((fraction - 0.3).abs() < 0.01);
    let reference = before.with_edited_cage(edit::loop_cut(&before.cage, edge, fraction).unwrap()).unwrap();
    let doc = h.state().editor.document.doc().clone();
    assert!(doc == reference && bits(&doc) == bits(&reference), "the slide lands on the core's cut at {fraction}");
    click(&mut h, PointerButton::Primary, to);
    assert!(h.state().ui.tool.get::<crate::editor::tools::loop_slide::LoopCutTool>().is_none());
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(bits(h.state().editor.document.doc()) == bits(&before), "cut and slide are one undo step");
    assert!(!h.state().editor.document.can_undo());
}

#[test]
fn esc_while_sliding_cancels_the_whole_cut_and_leaves_no_undo_step() {
    let (mut h, _, before, [pa, pb]) = ctrl_r_over_the_front_edge();
    let middle = (pa + pb) * 0.5;
    click(&mut h, PointerButton::Primary, middle);
    h.hover_at(pos2(pa.x + 10.0, pa.y));
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc().cage.vertex_count(), 12);
    h.key_press(Key::Escape);
    frames(&mut h);
    let doc = h.state().editor.document.doc();
    assert!(doc == &before && bits(doc) == bits(&before));
    assert!(!h.state().editor.document.can_undo(), "nothing to undo");
    assert!(h.state().ui.tool.get::<crate::editor::tools::loop_slide::LoopCutTool>().is_none());
}

/// What the core's region inset of the top face gives at `thickness`.
fn inset(doc: &Document, thickness: f64) -> Document {
    let f = top_face(&doc.cage);
    doc.with_edited_cage(edit::inset_faces(&doc.cage, &[f], FaceGrouping::Region, thickness).unwrap()).unwrap()
}

#[test]
fn i_then_a_typed_or_dragged_thickness_lands_on_the_cores_inset_in_one_undo_step() {
    // Typed: exactly the core's inset at 0.1.
    let mut h = top_face_selected();
    let before = h.state().editor.document.doc().clone();
    for key in [Key::I, Key::Period, Key::Num1, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let reference = inset(&before, 0.1);
    let doc = h.state().editor.document.doc().clone();
    assert!(doc == reference && bits(&doc) == bits(&reference), "the inset at 0.1");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(bits(h.state().editor.document.doc()) == bits(&before) && !h.state().editor.document.can_undo());

    // The mouse: away from the face's centre on screen thickens it, by the ratio of distances.
    let mut h = top_face_selected();
    let centre = pixel_of(&h, DVec3::new(0.0, 0.0, 0.5));
    let start = centre + glam::Vec2::new(40.0, 0.0);
    h.hover_at(pos2(start.x, start.y));
    frames(&mut h);
    h.key_press(Key::I);
    frames(&mut h);
    let end = centre + glam::Vec2::new(60.0, 0.0);
    h.hover_at(pos2(end.x, end.y));
    frames(&mut h);
    let thickness = h
        .state()
        .ui
        .tool
        .get::<crate::editor::tools::inset_drag::InsetDrag>()
        .expect("the thickness follows the mouse")
        .thickness;
    let base = OFFSET_FRACTION * 1.0;
    let expected = base * f64::from((end - centre).length() / (start - centre).length());
    assert!((thickness - expected).abs() < 1e-12, "{thickness} vs {expected}");
    let reference = inset(&before, thickness);
    assert!(bits(h.state().editor.document.doc()) == bits(&reference));
    // Esc: back to the menu's thickness, the inset kept.
    h.key_press(Key::Escape);
    frames(&mut h);
    let reference = inset(&before, base);
    assert!(
        bits(h.state().editor.document.doc()) == bits(&reference)
            && h.state().ui.tool.get::<crate::editor::tools::inset_drag::InsetDrag>().is_none()
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert!(bits(h.state().editor.document.doc()) == bits(&before), "one undo step");
}

#[test]
fn a_cage_replaced_under_a_gesture_ends_it_and_is_left_untouched() {
    // G, a loop slide and an inset drag, each interrupted by a new document (File ▸ New from
    // the menu while the gesture runs): the gesture ends and the new cage is not moved.
    for keys in [vec![(Modifiers::NONE, Key::G)], vec![(Modifiers::COMMAND, Key::R)], vec![(Modifiers::NONE, Key::I)]] {
        let mut h = top_face_selected();
        h.state_mut().editor.view.selection.edges = vec![EdgeId(0)];
        let at = pixel_of(&h, DVec3::new(0.3, 0.0, 0.5));
        for (modifiers, key) in keys {
            h.key_press_modifiers(modifiers, key);
            frames(&mut h);
        }
        let ui = &h.state().ui;
        assert!(ui.tool.is_running(), "a gesture runs");
        let fresh = super::primitives::cube();
        h.state_mut().editor.replace_document(super::document::EditorDocument::new(fresh.clone(), None));
        for k in 0..3 {
            h.hover_at(pos2(at.x + 15.0 * k as f32, at.y - 10.0 * k as f32));
            frames(&mut h);
        }
        let ui = &h.state().ui;
        assert!(!ui.tool.is_running(), "the gesture ended");
        let doc = h.state().editor.document.doc();
        assert!(doc == &fresh && bits(doc) == bits(&fresh), "the new cage is untouched");
    }
}
