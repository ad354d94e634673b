//! G, R and S driven by keys, as a designer types them: exact moves, turns and scales, Esc, and
//! the header's readout.

use super::*;
use crate::editor::panel_tests::{cube_editor, frames};
use egui::Modifiers;

#[test]
fn g_x_one_enter_moves_the_selection_by_exactly_one_along_x_in_one_undo_step() {
    let mut h = cube_editor();
    let before = h.state().editor.document.doc().clone();
    let v = taut_core::VertexId(7);
    let p = before.cage.position(v);
    for key in [Key::G, Key::X, Key::Num1, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let doc = h.state().editor.document.doc().clone();
    assert_eq!(doc.cage.position(v), p + DVec3::X, "exactly 1 along x");
    assert!(doc.cage.vertices().filter(|&w| w != v).all(|w| doc.cage.position(w) == before.cage.position(w)));
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc(), &before, "one undo step");
}

/// The readout, read as a designer reads it (the first label of the status bar).
fn header(h: &egui_kittest::Harness<'static, crate::editor::panel_tests::App>) -> String {
    use egui_kittest::kittest::Queryable;
    let readout = h.state().ui.tool.readout(&h.state().editor).expect("a tool runs");
    h.get_by_label(&readout);
    readout
}

#[test]
fn the_header_reads_out_the_typed_move_angle_and_factor() {
    let mut h = cube_editor();
    for key in [Key::G, Key::X, Key::Num1, Key::Period, Key::Num5] {
        h.key_press(key);
        frames(&mut h);
    }
    frames(&mut h);
    assert_eq!(header(&h), "ΔX 1.5000 mm  ΔY 0.0000 mm  ΔZ 0.0000 mm  distance 1.5000 mm");
    h.key_press(Key::Y);
    frames(&mut h);
    frames(&mut h);
    assert_eq!(header(&h), "ΔX 0.0000 mm  ΔY 1.5000 mm  ΔZ 0.0000 mm  distance 1.5000 mm", "the lock moves the value");
    h.key_press(Key::Escape);
    frames(&mut h);
    // The document's unit is the one shown.
    h.state_mut().editor.edit(crate::editor::document::Edit::SetUnits(taut_core::document::LengthUnit::Inch));
    frames(&mut h);
    for key in [Key::G, Key::Y, Key::Num1, Key::Period, Key::Num5] {
        h.key_press(key);
        frames(&mut h);
    }
    frames(&mut h);
    assert_eq!(header(&h), "ΔX 0.0000 in  ΔY 1.5000 in  ΔZ 0.0000 in  distance 1.5000 in");
    h.key_press(Key::Escape);
    frames(&mut h);
    for key in [Key::R, Key::Z, Key::Minus, Key::Num3, Key::Num0] {
        h.key_press(key);
        frames(&mut h);
    }
    frames(&mut h);
    assert_eq!(header(&h), "angle -30.00°");
    h.key_press(Key::Escape);
    frames(&mut h);
    for key in [Key::S, Key::Num2] {
        h.key_press(key);
        frames(&mut h);
    }
    frames(&mut h);
    assert_eq!(header(&h), "factor 2.0000");
    h.key_press(Key::Enter);
    frames(&mut h);
    assert!(h.state().ui.tool.readout(&h.state().editor).is_none(), "the readout goes with the tool");
}

#[test]
fn typed_rotations_and_scales_match_their_closed_forms_and_esc_cancels() {
    let mut h = cube_editor();
    // The top face: centre (0, 0, 0.5).
    let top: Vec<VertexId> =
        (0..8).map(VertexId).filter(|&v| h.state().editor.document.doc().cage.position(v).z > 0.0).collect();
    h.state_mut().editor.view.selection.vertices = top.clone();
    let before = h.state().editor.document.doc().clone();
    for key in [Key::R, Key::Z, Key::Num9, Key::Num0, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let cage = &h.state().editor.document.doc().cage;
    for &v in &top {
        let (p, q) = (before.cage.position(v), cage.position(v));
        // A quarter turn about z through the centre: (x, y) -> (-y, x).
        assert!((q - DVec3::new(-p.y, p.x, p.z)).length() < 1e-12, "{p} -> {q}");
    }
    for key in [Key::S, Key::Num2, Key::Escape] {
        h.key_press(key);
        frames(&mut h);
    }
    let after_rotation = h.state().editor.document.doc().clone();
    h.key_press(Key::S);
    frames(&mut h);
    for key in [Key::Num2, Key::Enter] {
        h.key_press(key);
        frames(&mut h);
    }
    let cage = &h.state().editor.document.doc().cage;
    for &v in &top {
        let (p, q) = (after_rotation.cage.position(v), cage.position(v));
        let c = DVec3::new(0.0, 0.0, 0.5);
        assert!((q - (c + 2.0 * (p - c))).length() < 1e-12, "scaled twice about the centre");
    }
    // Esc put everything back before the second S: the undo history holds R and S only.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc(), &after_rotation);
}

#[test]
fn a_snapped_move_lands_exactly_on_the_vertex_edge_midpoint_or_face_centre_under_the_cursor() {
    use crate::editor::gizmo_tests::pixel_of;
    use crate::editor::panel_tests::settle;
    use crate::editor::tools::snap_targets::SnapTarget;
    for target in [SnapTarget::Vertex, SnapTarget::EdgeMidpoint, SnapTarget::FaceCentre] {
        let mut h = cube_editor();
        settle(&mut h);
        let cage = h.state().editor.document.doc().cage.clone();
        let v = taut_core::VertexId(7);
        let p = cage.position(v);
        // Targets that share no face with vertex 7 (landing on one that does would collapse
        // the face, and the preview waits): the opposite corner, a bottom edge, the bottom face.
        let opposite = -p;
        let goal = match target {
            SnapTarget::Vertex => opposite,
            SnapTarget::EdgeMidpoint => {
                let e = cage
                    .edges()
                    .find(|&e| {
                        let (a, b) = cage.edge_vertices(e);
                        cage.position(a) == opposite && cage.position(b).z < 0.0
                            || cage.position(b) == opposite && cage.position(a).z < 0.0
                    })
                    .unwrap();
                let (a, b) = cage.edge_vertices(e);
                (cage.position(a) + cage.position(b)) * 0.5
            }
            _ => {
                // The bottom face's centre (no corner of it is vertex 7).
                let f = cage.faces().find(|&f| cage.face_vertices(f).all(|w| cage.position(w).z < 0.0)).unwrap();
                cage.face_vertices(f).map(|w| cage.position(w)).sum::<DVec3>() / 4.0
            }
        };
        {
            let snap = &mut h.state_mut().editor.gizmo.snap;
            snap.always = true;
            snap.target = target;
        }
        let near = pixel_of(&h, goal) + glam::Vec2::new(4.0, -3.0);
        let start = pixel_of(&h, p);
        h.hover_at(egui::pos2(start.x, start.y));
        frames(&mut h);
        h.key_press(Key::G);
        frames(&mut h);
        h.hover_at(egui::pos2(near.x, near.y));
        frames(&mut h);
        frames(&mut h);
        let at = h.state().editor.document.doc().cage.position(v);
        assert_eq!(at, goal, "{target:?}: vertex 7 lands on the target");
        let snapped = h.state().ui.tool.get::<Transform>().and_then(|t| t.snapped_to);
        assert_eq!(snapped, Some(goal), "{target:?}: the target is shown");
        h.key_press(Key::Enter);
        frames(&mut h);
        assert_eq!(h.state().editor.document.doc().cage.position(v), goal);
    }
}
