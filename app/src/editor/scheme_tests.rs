//! The editor with every scheme: the selector (undoable, saved), the controls each scheme has
//! (tension for NUSD, crease sharpness and Shift+E for subdivision), and the compare view.

use super::document::Edit;
use super::live::CompareMode;
use super::panel_tests::{App, cube_editor, frames, settle};
use egui::accesskit::Role;
use egui::{Key, Modifiers, pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use taut_core::surface::{ColourBy, Phase, SchemeKind};
use taut_core::{EdgeId, VertexId};

/// Chooses a scheme in the Surface panel's combo box, as a designer does.
fn choose_scheme(harness: &mut Harness<'_, App>, scheme: SchemeKind) {
    harness.get(By::new().role(Role::ComboBox).label("scheme")).click();
    harness.run_steps(2);
    harness.get_by_label(scheme.display_name()).click();
    frames(harness);
    harness.run_steps(2);
}

fn has_label(harness: &Harness<'_, App>, text: &str) -> bool {
    harness.query_all(By::new().label_contains(text).include_labels()).next().is_some()
}

#[test]
fn the_scheme_selector_is_undoable_and_each_scheme_shows_its_controls() {
    let mut harness = cube_editor();
    settle(&mut harness);
    assert!(has_label(&harness, "vertex tension τ"), "NUSD shows tension");
    choose_scheme(&mut harness, SchemeKind::CatmullClark);
    settle(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc().scheme, SchemeKind::CatmullClark);
    let view = editor.surface.as_ref().expect("a surface");
    assert_eq!(view.scheme.kind(), SchemeKind::CatmullClark);
    assert!(view.scheme.normals().is_some(), "the limit surface brings its normals");
    assert!(editor.progress.as_ref().unwrap().summary.contains("Catmull–Clark"));
    // Subdivision: crease controls instead of tension (vertex 7 alone: no edge to crease).
    assert!(!has_label(&harness, "vertex tension τ"));
    assert!(has_label(&harness, "Select cage edges"), "a hint says how to crease");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(harness.state().editor.document.doc().scheme, SchemeKind::Nusd, "Ctrl+Z undoes the scheme");
    // Loop on a cage of quads is refused, saying what to do.
    choose_scheme(&mut harness, SchemeKind::Loop);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc().scheme, SchemeKind::Nusd);
    let notice = editor.notice.as_ref().expect("a message");
    assert!(notice.is_error && notice.text.contains("triangulate"), "{}", notice.text);
}

#[test]
fn creases_are_set_by_slider_and_by_shift_e_with_the_mouse() {
    let mut harness = cube_editor();
    harness.state_mut().editor.edit(Edit::SetScheme(SchemeKind::CatmullClark));
    let edges = vec![EdgeId(0), EdgeId(3)];
    harness.state_mut().editor.view.selection.vertices.clear();
    harness.state_mut().editor.view.selection.edges = edges.clone();
    settle(&mut harness);
    assert!(has_label(&harness, "crease sharpness s"));
    let crease = |h: &Harness<'_, App>| {
        edges.iter().map(|e| h.state().editor.document.doc().crease[e.index()]).collect::<Vec<_>>()
    };
    // Shift+E, the mouse 150 points to the right, a click: s = 1.5 on both edges, one undo step.
    let view = harness.state().ui.viewport_px.unwrap();
    let start = pos2(view[0] as f32 + 200.0, view[1] as f32 + 200.0);
    harness.hover_at(start);
    frames(&mut harness);
    harness.key_press_modifiers(Modifiers::SHIFT, Key::E);
    frames(&mut harness);
    assert!(
        harness.state().ui.tool.get::<crate::editor::tools::crease_drag::CreaseDrag>().is_some(),
        "Shift+E starts creasing"
    );
    for k in 1..=6 {
        harness.hover_at(pos2(start.x + 25.0 * k as f32, start.y));
        frames(&mut harness);
    }
    harness.drag_at(pos2(start.x + 150.0, start.y));
    frames(&mut harness);
    harness.drop_at(pos2(start.x + 150.0, start.y));
    frames(&mut harness);
    assert!(harness.state().ui.tool.get::<crate::editor::tools::crease_drag::CreaseDrag>().is_none());
    assert_eq!(crease(&harness), vec![1.5, 1.5]);
    assert_eq!(harness.state().editor.view.selection.edges, edges, "the click that sets the crease selects nothing");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(crease(&harness), vec![0.0, 0.0], "one Ctrl+Z undoes the whole Shift+E drag");
    // Esc puts the crease back as it was.
    harness.key_press_modifiers(Modifiers::SHIFT, Key::E);
    frames(&mut harness);
    harness.hover_at(pos2(start.x + 300.0, start.y));
    frames(&mut harness);
    assert!(crease(&harness)[0] > 0.0, "the crease follows the mouse");
    harness.key_press(Key::Escape);
    frames(&mut harness);
    assert_eq!(crease(&harness), vec![0.0, 0.0], "Esc cancels");
    // The cancelled drag left no step: the next Ctrl+Z undoes the scheme change before it.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(harness.state().editor.document.doc().scheme, SchemeKind::Nusd);
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut harness);
    // Under NUSD, Shift+E says creases belong to subdivision.
    harness.state_mut().editor.edit(Edit::SetScheme(SchemeKind::Nusd));
    harness.key_press_modifiers(Modifiers::SHIFT, Key::E);
    frames(&mut harness);
    assert!(harness.state().ui.tool.get::<crate::editor::tools::crease_drag::CreaseDrag>().is_none());
    assert!(harness.state().editor.notice.as_ref().unwrap().text.contains("subdivision schemes"));
}

#[test]
fn corners_are_set_by_shift_v_and_the_panel_and_the_surface_keeps_a_sharp_corner() {
    let mut harness = cube_editor();
    harness.state_mut().editor.edit(Edit::SetScheme(SchemeKind::CatmullClark));
    // Vertex 7 is selected in the cube editor.
    settle(&mut harness);
    assert!(has_label(&harness, "corner sharpness"));
    let corner = |h: &Harness<'_, App>| h.state().editor.document.doc().corner[7];
    let view = harness.state().ui.viewport_px.unwrap();
    let start = pos2(view[0] as f32 + 200.0, view[1] as f32 + 200.0);
    harness.hover_at(start);
    frames(&mut harness);
    harness.key_press_modifiers(Modifiers::SHIFT, Key::V);
    frames(&mut harness);
    assert!(
        harness.state().ui.tool.get::<crate::editor::tools::crease_drag::CreaseDrag>().is_some(),
        "Shift+V starts sharpening"
    );
    for k in 1..=4 {
        harness.hover_at(pos2(start.x + 50.0 * k as f32, start.y));
        frames(&mut harness);
    }
    harness.key_press(Key::Enter);
    frames(&mut harness);
    assert_eq!(corner(&harness), 2.0, "200 points to the right: sharpness 2");
    // The panel's checkbox makes it a sharp corner: the limit surface passes through the vertex.
    harness.get_by_label("sharp corner").click();
    settle(&mut harness);
    assert_eq!(corner(&harness), f64::INFINITY);
    let editor = &harness.state().editor;
    let cage_vertex = editor.document.doc().cage.position(VertexId(7));
    let surface = editor.surface_mesh().expect("the limit surface");
    assert_eq!(surface.position(VertexId(7)), cage_vertex, "a sharp corner stays where it is");
    // The overlay draws it, once deselected, as a filled dot in the crease colour.
    harness.state_mut().editor.view.selection.clear();
    let editor = &harness.state().editor;
    let points = editor.overlays().points;
    let at = editor.view.display_frame.point(cage_vertex);
    assert!(points.iter().any(|p| (p.position - at).length() < 1e-5 && p.color == taut_render::overlay::CREASE));
    // One Ctrl+Z at a time undoes the checkbox, then the whole Shift+V drag.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(corner(&harness), 2.0);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_eq!(corner(&harness), 0.0);
    // Under NUSD, Shift+V says corners belong to subdivision.
    harness.state_mut().editor.edit(Edit::SetScheme(SchemeKind::Nusd));
    harness.key_press_modifiers(Modifiers::SHIFT, Key::V);
    frames(&mut harness);
    assert!(harness.state().ui.tool.get::<crate::editor::tools::crease_drag::CreaseDrag>().is_none());
    assert!(harness.state().editor.notice.as_ref().unwrap().text.contains("subdivision schemes"));
}

#[test]
fn the_compare_view_shows_the_other_scheme_as_ghost_or_distance() {
    let mut harness = cube_editor();
    settle(&mut harness);
    harness.state_mut().editor.set_compare(CompareMode::Ghost);
    settle(&mut harness);
    let editor = &harness.state().editor;
    let other = editor.comparison.as_ref().expect("the other scheme's surface");
    assert_eq!(other.scheme.kind(), SchemeKind::CatmullClark);
    assert_eq!(other.scheme.progress().phase, Phase::Done);
    // Distance: the surface is coloured by its distance to the Catmull–Clark surface. NUSD passes
    // through the cube's corners, Catmull–Clark shrinks inside them.
    harness.state_mut().editor.set_compare(CompareMode::Distance);
    settle(&mut harness);
    harness.state_mut().editor.refresh_values();
    let editor = &harness.state().editor;
    assert_eq!(editor.colour_by(), ColourBy::Distance);
    let legend = editor.legend().expect("a legend");
    assert_eq!(legend.title, "distance");
    let distances = editor.comparison.as_ref().unwrap().distances.clone().expect("measured");
    // The cube's corners are where the two surfaces part most.
    let corner = distances[VertexId(7).index()];
    let largest = distances.iter().copied().fold(0.0, f64::max);
    let smallest = distances.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(corner > 0.99 * largest && corner > 1.1 * smallest, "corner {corner}, from {smallest} to {largest}");
    // Edits reach the compared surface too.
    harness.state_mut().editor.edit(Edit::SetVertexTension(vec![VertexId(7)], 2.0));
    settle(&mut harness);
    harness.state_mut().editor.set_compare(CompareMode::Off);
    assert!(harness.state().editor.comparison.is_none());
}
