//! The curve-mesh scheme in the editor, as a designer uses it: choosing it, dragging a curve-mesh
//! vertex with the mouse (one undo step, redo bit for bit, Esc puts it back), the continuity
//! overlay and its legend, and "Rebuild from cage" asking before it discards the edits.

use super::Handle;
use crate::editor::interaction::{self, ViewportRect};
use crate::editor::panel_tests::{App, cube_editor, frames, settle, surface_positions};
use egui::accesskit::Role;
use egui::{Key, Modifiers, pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use taut_core::surface::SchemeKind;
use taut_core::{DVec3, VertexId};

/// An editor on the cube, switched to the curve mesh through the Surface panel's selector.
fn curve_mesh_editor() -> Harness<'static, App> {
    let mut harness = cube_editor();
    harness.state_mut().editor.view.selection.clear();
    settle(&mut harness);
    harness.get(By::new().role(Role::ComboBox).label("scheme")).click();
    harness.run_steps(2);
    harness.get_by_label(SchemeKind::CurveMesh.display_name()).click();
    frames(&mut harness);
    settle(&mut harness);
    harness
}

/// The viewport in points (the harness draws at one pixel per point).
fn viewport(harness: &Harness<'_, App>) -> ViewportRect {
    let [x, y, w, h] = harness.state().ui.viewport_px.expect("the viewport was laid out");
    ViewportRect { min: glam::Vec2::new(x as f32, y as f32), size: glam::Vec2::new(w as f32, h as f32) }
}

/// Where a model point lands in the viewport.
fn pixel_of(harness: &Harness<'_, App>, p: DVec3) -> glam::Vec2 {
    let editor = &harness.state().editor;
    let display = editor.view.display_frame.to_display_f64(p);
    interaction::project(&editor.view.camera, &viewport(harness), display).expect("in front of the camera").0
}

fn button(harness: &mut Harness<'_, App>, pressed: bool, at: glam::Vec2) {
    harness.input_mut().events.push(egui::Event::PointerButton {
        pos: pos2(at.x, at.y),
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    });
    frames(harness);
}

/// Presses on `from`, moves to `to` in four steps; releases unless `hold`.
fn drag(harness: &mut Harness<'_, App>, from: glam::Vec2, to: glam::Vec2, hold: bool) {
    harness.hover_at(pos2(from.x, from.y));
    frames(harness);
    button(harness, true, from);
    for k in 1..=4 {
        let m = from + (to - from) * (k as f32 / 4.0);
        harness.hover_at(pos2(m.x, m.y));
        frames(harness);
    }
    if !hold {
        button(harness, false, to);
    }
}

/// The curve-mesh vertex nearest the camera (so that no other one hides it), with its position.
fn front_vertex(harness: &Harness<'_, App>) -> (VertexId, DVec3) {
    let editor = &harness.state().editor;
    let cm = editor.curve_mesh_surface().expect("the curve-mesh surface").curve_mesh();
    let view = viewport(harness);
    cm.topology()
        .vertices()
        .map(|v| (v, cm.vertex_position(v)))
        .min_by(|a, b| {
            let depth = |p: DVec3| {
                interaction::project(&editor.view.camera, &view, editor.view.display_frame.to_display_f64(p)).unwrap().1
            };
            depth(a.1).total_cmp(&depth(b.1))
        })
        .unwrap()
}

fn bits(points: &[DVec3]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

#[test]
fn a_dragged_curve_mesh_vertex_follows_the_cursor_in_one_undo_step() {
    let mut harness = curve_mesh_editor();
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc().scheme, SchemeKind::CurveMesh);
    let cm = editor.curve_mesh_surface().expect("the curve-mesh surface").curve_mesh();
    assert_eq!(cm.patch_count(), 6, "a patch per cube face");
    let cage_before = bits(editor.document.doc().cage.positions());
    let surface_before = surface_positions(&harness);
    let (v, p) = front_vertex(&harness);
    let from = pixel_of(&harness, p);
    let to = from + glam::Vec2::new(40.0, -25.0);
    drag(&mut harness, from, to, false);

    let doc = harness.state().editor.document.doc().clone();
    assert_eq!(bits(doc.cage.positions()), cage_before, "the cage does not move");
    assert_eq!(doc.curve_mesh.vertices.len(), 1, "one vertex edited: {:?}", doc.curve_mesh);
    assert_eq!(doc.curve_mesh.vertices[0].vertex, v.0);
    let moved = DVec3::from_array(doc.curve_mesh.vertices[0].position);
    let landed = pixel_of(&harness, moved);
    assert!(landed.distance(to) < 0.5, "the vertex lands under the cursor: {landed} vs {to}");
    assert_eq!(harness.state().editor.curve_mesh.selected, vec![v], "the dragged vertex is selected");
    let surface_edited = surface_positions(&harness);
    assert_ne!(bits(&surface_edited), bits(&surface_before), "the surface follows");
    // Only the three patches around the valence-3 vertex were rebuilt.
    let changed = harness.state().editor.curve_mesh_surface().unwrap().last_changed().unwrap().patches.len();
    assert_eq!(changed, 3);

    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert!(harness.state().editor.document.doc().curve_mesh.is_empty(), "one Ctrl+Z undoes the whole drag");
    assert_eq!(bits(&surface_positions(&harness)), bits(&surface_before), "undo restores the surface bit for bit");
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut harness);
    assert_eq!(*harness.state().editor.document.doc(), doc, "redo brings the edit back");
    assert_eq!(bits(&surface_positions(&harness)), bits(&surface_edited), "and its surface bit for bit");
}

#[test]
fn escape_during_a_drag_puts_the_curve_mesh_back() {
    let mut harness = curve_mesh_editor();
    let before = harness.state().editor.document.doc().clone();
    let (_, p) = front_vertex(&harness);
    let from = pixel_of(&harness, p);
    drag(&mut harness, from, from + glam::Vec2::new(30.0, 30.0), true);
    assert!(!harness.state().editor.document.doc().curve_mesh.is_empty(), "the drag moved the vertex");
    harness.key_press(Key::Escape);
    frames(&mut harness);
    button(&mut harness, false, from + glam::Vec2::new(30.0, 30.0));
    assert!(harness.state().editor.document.doc().curve_mesh.is_empty(), "Esc cancelled the drag");
    assert_eq!(*harness.state().editor.document.doc(), before, "exactly as before");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    let scheme = harness.state().editor.document.doc().scheme;
    assert_eq!(scheme, SchemeKind::Nusd, "a cancelled drag left no undo step: Ctrl+Z undoes the scheme");
}

#[test]
fn the_selected_vertex_offers_its_legs_and_normal_and_the_normal_tip_turns_the_plane() {
    let mut harness = curve_mesh_editor();
    let (v, p) = front_vertex(&harness);
    harness.state_mut().editor.curve_mesh.selected = vec![v];
    frames(&mut harness);
    let handles = harness.state().editor.curve_mesh_handles();
    let legs = handles.iter().filter(|(h, _)| matches!(h, Handle::Inner { end, .. } if *end == v)).count();
    assert_eq!(legs, 3, "a leg per curve at the valence-3 vertex");
    let (_, tip) = *handles.iter().find(|(h, _)| *h == Handle::Normal(v)).expect("a normal handle");
    let n_before = harness.state().editor.curve_mesh_surface().unwrap().curve_mesh().vertex_normal(v);
    assert!(((tip - p).normalize() - n_before).length() < 1e-12, "the handle sits on the normal");
    let from = pixel_of(&harness, tip);
    drag(&mut harness, from, from + glam::Vec2::new(25.0, 0.0), false);
    let editor = &harness.state().editor;
    let cm = editor.curve_mesh_surface().unwrap().curve_mesh();
    let n_after = cm.vertex_normal(v);
    assert!(n_after.angle_between(n_before) > 1e-3, "the tangent plane turned");
    assert_eq!(cm.vertex_position(v), p, "the vertex stays");
    for h in cm.topology().outgoing(v) {
        let q = cm.inner_point(h.edge(), v).unwrap();
        assert!((q - p).dot(n_after).abs() < 1e-9 * (q - p).length().max(1.0), "the legs lie in the new plane");
    }
}

#[test]
fn the_continuity_overlay_measures_g1_and_follows_an_edit() {
    let mut harness = curve_mesh_editor();
    assert!(harness.state().editor.curve_mesh_legend().is_none(), "off at first");
    harness.get_by_label("Continuity").click();
    frames(&mut harness);
    harness.run_steps(1);
    let editor = &harness.state().editor;
    let m = editor.measured_continuity().expect("measured once switched on");
    assert_eq!(m.curves.len(), 12, "every cube edge is a shared curve");
    assert!(m.report.max_normal_angle <= 1e-6, "G1 across every curve: {}", m.report.max_normal_angle);
    let legend = editor.overlays().legend.expect("a legend");
    assert!(legend.title.contains("G2"), "{}", legend.title);
    let jump_before = m.report.max_curvature_jump;
    let (_, p) = front_vertex(&harness);
    let from = pixel_of(&harness, p);
    drag(&mut harness, from, from + glam::Vec2::new(0.0, -60.0), false);
    frames(&mut harness);
    let m = harness.state().editor.measured_continuity().expect("measured again after the edit");
    assert!(m.report.max_normal_angle <= 1e-6, "still G1 after the move: {}", m.report.max_normal_angle);
    assert_ne!(m.report.max_curvature_jump, jump_before, "the G2 figures follow the edit");
    harness.get_by_label("Continuity").click();
    frames(&mut harness);
    assert!(harness.state().editor.overlays().legend.is_none(), "switched off, the legend goes");
}

#[test]
fn rebuild_from_cage_asks_before_it_discards_the_edits() {
    let mut harness = curve_mesh_editor();
    let (v, p) = front_vertex(&harness);
    harness
        .state_mut()
        .editor
        .edit(crate::editor::document::Edit::MoveCurveMeshVertices(vec![(v, p + DVec3::new(0.1, 0.2, -0.1))]));
    frames(&mut harness);
    harness.run_steps(1);
    let edited = harness.state().editor.document.doc().curve_mesh.clone();
    assert!(!edited.is_empty());
    harness.get_by_label("Rebuild from cage…").click();
    frames(&mut harness);
    harness.run_steps(1);
    assert_eq!(harness.state().editor.document.doc().curve_mesh, edited, "asking discards nothing");
    harness.get_by_label("Keep edits").click();
    frames(&mut harness);
    harness.run_steps(1);
    assert_eq!(harness.state().editor.document.doc().curve_mesh, edited, "kept");
    assert!(harness.query_by_label("Discard edits").is_none(), "the question is gone");
    harness.get_by_label("Rebuild from cage…").click();
    frames(&mut harness);
    harness.run_steps(1);
    harness.get_by_label("Discard edits").click();
    frames(&mut harness);
    assert!(harness.state().editor.document.doc().curve_mesh.is_empty(), "discarded");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(harness.state().editor.document.doc().curve_mesh, edited, "undo brings the edits back");
}
