//! Every modal tool started from its key in the shortcut table (the one listing that Help and
//! the menus read) and cancelled with Esc in the real UI frame: the tool ends, the document is bit
//! for bit what it was before the key, or, for E and I, which make their extrusion or inset at
//! once and then let the mouse set its size (as Blender's do), what the Mesh menu's operation
//! makes; and no undo step is left that changes nothing.

use super::mesh_ops::MeshOp;
use super::mesh_ops_tests::top_face;
use super::panel_tests::{App, cube_editor, frames, open_menu_item};
use super::select_modes::SelectMode;
use super::shortcuts::{Action, SHORTCUTS};
use super::tools::TOOLS;
use super::transform::TransformKind;
use egui::{Modifiers, pos2};
use egui_kittest::Harness;
use taut_core::{Document, EdgeId};

/// What Esc leaves.
#[derive(Clone, Copy, Debug)]
enum AfterEsc {
    /// The document as it was before the key.
    Unchanged,
    /// The document the Mesh menu's operation makes (the tool only set its size).
    AsTheMenu(MeshOp),
}

/// The cube with the selection a tool needs: vertex 7 (the default), the top face, or an edge;
/// Catmull–Clark for the crease and corner drags (creases belong to the subdivision schemes),
/// set before the key so that undo holds that step already.
fn prepared(selection: &str, subdivision: bool) -> Harness<'static, App> {
    let mut h = cube_editor();
    let editor = &mut h.state_mut().editor;
    if subdivision {
        editor.edit(taut_core::Edit::SetScheme(taut_core::surface::SchemeKind::CatmullClark));
    }
    match selection {
        "face" => {
            let top = top_face(&editor.document.doc().cage);
            editor.view.selection.clear();
            editor.view.selection.mode = SelectMode::Face;
            editor.view.selection.faces = vec![top];
        }
        "edge" => {
            editor.view.selection.clear();
            editor.view.selection.mode = SelectMode::Edge;
            editor.view.selection.edges = vec![EdgeId(0)];
        }
        _ => {}
    }
    frames(&mut h);
    h
}

fn bits(doc: &Document) -> (Vec<[u64; 3]>, Vec<Vec<u32>>) {
    let positions = doc.cage.positions().iter().map(|p| p.to_array().map(f64::to_bits)).collect();
    (positions, doc.cage.polygons())
}

/// True while any modal tool runs.
fn tool_running(h: &Harness<'static, App>) -> bool {
    let ui = &h.state().ui;
    ui.tool.is_running()
}

/// The selection a listed tool needs and what Esc leaves.
fn needs(action: Action) -> (&'static str, AfterEsc) {
    match action {
        Action::Transform(TransformKind::Grab) | Action::Corner | Action::Tool("measure") => {
            ("vertex", AfterEsc::Unchanged)
        }
        Action::Transform(_) => ("face", AfterEsc::Unchanged),
        Action::Crease | Action::Mesh(MeshOp::LoopCut) => ("edge", AfterEsc::Unchanged),
        Action::Mesh(op @ (MeshOp::Extrude | MeshOp::Inset)) => ("face", AfterEsc::AsTheMenu(op)),
        other => panic!("{other:?} is listed as a tool: say here what it needs"),
    }
}

#[test]
fn every_listed_tool_starts_from_its_key_and_its_menu_entry_and_esc_cancels_it_cleanly() {
    assert_eq!(TOOLS.len(), 9, "the tools a key starts");
    for tool in TOOLS {
        let action = tool.action;
        let (selection, after) = needs(action);
        let subdivision = matches!(action, Action::Crease | Action::Corner);
        // The key comes from the shortcut table, which Help shows.
        let shortcut = SHORTCUTS.iter().find(|s| s.action == action).unwrap_or_else(|| panic!("{action:?} has a key"));
        let help = super::menus::help_text(action);
        match action {
            Action::Tool(_) => assert_eq!(help, tool.description, "{action:?}: Help says what its listing says"),
            _ => assert!(!help.is_empty(), "{action:?} is described in Help"),
        }
        for via_menu in [false, true] {
            let how = if via_menu { "Tools menu" } else { "key" };
            let mut h = prepared(selection, subdivision);
            let before = h.state().editor.document.doc().clone();
            let undo_before = h.state().editor.document.can_undo();
            h.hover_at(pos2(640.0, 400.0));
            frames(&mut h);
            if via_menu {
                open_menu_item(&mut h, &["Tools", &format!("{}  {}", tool.name, shortcut.label())]);
            } else {
                let modifiers = Modifiers {
                    command: shortcut.command,
                    shift: shortcut.shift,
                    alt: shortcut.alt,
                    ..Default::default()
                };
                h.key_press_modifiers(modifiers, shortcut.key);
                frames(&mut h);
            }
            assert!(tool_running(&h), "{action:?} ({}, {how}) starts its tool", shortcut.label());
            // The mouse moves the tool.
            for k in 1..=3 {
                h.hover_at(pos2(640.0 + 25.0 * k as f32, 400.0 - 15.0 * k as f32));
                frames(&mut h);
            }
            h.key_press(egui::Key::Escape);
            frames(&mut h);
            assert!(!tool_running(&h), "{action:?} ({how}): Esc ends the tool");
            let now = h.state().editor.document.doc().clone();
            match after {
                AfterEsc::Unchanged => {
                    assert!(
                        now == before && bits(&now) == bits(&before),
                        "{action:?} ({how}): Esc puts the document back"
                    );
                    assert_eq!(h.state().editor.document.can_undo(), undo_before, "{action:?}: no empty undo step");
                }
                AfterEsc::AsTheMenu(op) => {
                    let mut menu = prepared(selection, subdivision);
                    menu.state_mut().editor.mesh_op(op);
                    let made = menu.state().editor.document.doc().clone();
                    assert!(
                        now == made && bits(&now) == bits(&made),
                        "{action:?} ({how}): Esc leaves the menu's {op:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn esc_during_a_box_select_drops_the_box_and_keeps_the_selection() {
    let mut h = prepared("vertex", false);
    let selected = h.state().editor.view.selection.vertices.clone();
    assert!(!selected.is_empty());
    // A corner of the viewport, away from the cube.
    let from = pos2(300.0, 60.0);
    let press = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    h.hover_at(from);
    frames(&mut h);
    h.input_mut().events.push(press(from, true));
    frames(&mut h);
    for k in 1..=6 {
        h.hover_at(pos2(300.0 + 60.0 * k as f32, 60.0 + 50.0 * k as f32));
        frames(&mut h);
    }
    assert!(h.state().ui.tool.get::<super::tools::box_select::BoxSelect>().is_some(), "a box is drawn");
    h.key_press(egui::Key::Escape);
    frames(&mut h);
    assert!(!tool_running(&h), "Esc drops the box");
    h.input_mut().events.push(press(pos2(660.0, 360.0), false));
    frames(&mut h);
    assert_eq!(h.state().editor.view.selection.vertices, selected, "the selection is as it was");
}

#[test]
fn the_cage_panel_moves_the_median_of_a_face_to_a_typed_value_in_one_undo_step() {
    use egui::accesskit::Role;
    use egui_kittest::kittest::{By, Queryable};
    let mut h = prepared("face", false);
    let before = h.state().editor.document.doc().clone();
    let top: Vec<taut_core::VertexId> = before.cage.vertices().filter(|&v| before.cage.position(v).z > 0.0).collect();
    h.get_by_label("median of 4 vertices (mm)");
    // The Z field: the drag value labelled Z; a click opens it for typing.
    h.get(By::new().role(Role::SpinButton).label("Z")).focus();
    frames(&mut h);
    frames(&mut h);
    // Focused, the field is edited as text with its value selected: typing replaces it.
    h.get(By::new().role(Role::SpinButton).label("Z")).type_text("1.5");
    frames(&mut h);
    h.key_press(egui::Key::Enter);
    frames(&mut h);
    frames(&mut h);
    let cage = &h.state().editor.document.doc().cage;
    for &v in &top {
        let (p, q) = (before.cage.position(v), cage.position(v));
        assert_eq!((q.x, q.y), (p.x, p.y), "x and y stay");
        assert!((q.z - 1.5).abs() < 1e-12, "the top face lands at z = 1.5: {q}");
    }
    h.state_mut().editor.undo();
    assert!(h.state().editor.document.doc() == &before, "one undo step");
}
