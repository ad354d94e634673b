//! Every modal tool started from its key in the shortcut table (the one listing that Help and
//! the menus read) and cancelled with Esc in the real UI frame: the tool ends, the document is bit
//! for bit what it was before the key, or, for E and I, which make their extrusion or inset at
//! once and then let the mouse set its size (as Blender's do), what the Mesh menu's operation
//! makes; and no undo step is left that changes nothing.

use super::mesh_ops::MeshOp;
use super::mesh_ops_tests::top_face;
use super::panel_tests::{App, cube_editor, frames};
use super::select_modes::SelectMode;
use super::shortcuts::{Action, SHORTCUTS};
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
            editor.selection.clear();
            editor.selection.mode = SelectMode::Face;
            editor.selection.faces = vec![top];
        }
        "edge" => {
            editor.selection.clear();
            editor.selection.mode = SelectMode::Edge;
            editor.selection.edges = vec![EdgeId(0)];
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
    ui.transform.is_some() || ui.loop_cut.is_some() || ui.inset_drag.is_some() || ui.crease_drag.is_some()
}

#[test]
fn every_modal_tool_starts_from_its_listed_key_and_esc_cancels_it_cleanly() {
    let tools: [(Action, &str, AfterEsc); 8] = [
        (Action::Transform(TransformKind::Grab), "vertex", AfterEsc::Unchanged),
        (Action::Transform(TransformKind::Rotate), "face", AfterEsc::Unchanged),
        (Action::Transform(TransformKind::Scale), "face", AfterEsc::Unchanged),
        (Action::Crease, "edge", AfterEsc::Unchanged),
        (Action::Corner, "vertex", AfterEsc::Unchanged),
        (Action::Mesh(MeshOp::LoopCut), "edge", AfterEsc::Unchanged),
        (Action::Mesh(MeshOp::Extrude), "face", AfterEsc::AsTheMenu(MeshOp::Extrude)),
        (Action::Mesh(MeshOp::Inset), "face", AfterEsc::AsTheMenu(MeshOp::Inset)),
    ];
    for (action, selection, after) in tools {
        let subdivision = matches!(action, Action::Crease | Action::Corner);
        // The key comes from the listing; Help shows the same table.
        let shortcut = SHORTCUTS.iter().find(|s| s.action == action).unwrap_or_else(|| panic!("{action:?} has a key"));
        assert!(!super::shortcuts::describe(action).is_empty(), "{action:?} is described in Help");
        let mut h = prepared(selection, subdivision);
        let before = h.state().editor.document.doc().clone();
        let undo_before = h.state().editor.document.can_undo();
        h.hover_at(pos2(640.0, 400.0));
        frames(&mut h);
        let modifiers =
            Modifiers { command: shortcut.command, shift: shortcut.shift, alt: shortcut.alt, ..Default::default() };
        h.key_press_modifiers(modifiers, shortcut.key);
        frames(&mut h);
        assert!(tool_running(&h), "{action:?} ({}) starts its tool", shortcut.label());
        // The mouse moves the tool.
        for k in 1..=3 {
            h.hover_at(pos2(640.0 + 25.0 * k as f32, 400.0 - 15.0 * k as f32));
            frames(&mut h);
        }
        h.key_press(egui::Key::Escape);
        frames(&mut h);
        assert!(!tool_running(&h), "{action:?}: Esc ends the tool");
        let now = h.state().editor.document.doc().clone();
        match after {
            AfterEsc::Unchanged => {
                assert!(now == before && bits(&now) == bits(&before), "{action:?}: Esc puts the document back");
                assert_eq!(h.state().editor.document.can_undo(), undo_before, "{action:?}: no empty undo step");
            }
            AfterEsc::AsTheMenu(op) => {
                let mut menu = prepared(selection, subdivision);
                let app = menu.state_mut();
                app.editor.run_action(Action::Mesh(op), &mut app.ui);
                // The menu's operation with the same size, without a drag.
                let ui = &mut menu.state_mut().ui;
                ui.transform = None;
                ui.inset_drag = None;
                menu.state_mut().editor.document.end_gesture();
                let made = menu.state().editor.document.doc().clone();
                assert!(now == made && bits(&now) == bits(&made), "{action:?}: Esc leaves the menu's {op:?}");
            }
        }
    }
}
