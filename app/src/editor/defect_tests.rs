//! The editor against what a designer found trying it: shortcuts that ignored Shift, mixed
//! selections shown as one vertex's values, a box that forgot Shift, a path field that ignored
//! Enter, messages running off the window, missing glyphs, controls without tooltips, a legend
//! covering the model. Each test drives the real [`EditorState::ui`] with egui_kittest.

use super::document::{Edit, EditorDocument};
use super::panel_tests::{App, cube_editor, editor_on, frames, settle, slider_point, widget_beside_label};
use super::primitives;
use super::shortcuts::{Action, SHORTCUTS, Shortcut};
use super::state::DisplayMode;
use super::ui::PathPurpose;
use egui::accesskit::{Role, Toggled};
use egui::{Key, Modifiers, pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, NodeT, Queryable};
use taut_core::VertexId;

/// The text a node shows: AccessKit keeps a label's text in its value.
fn text_of(node: &egui_kittest::Node<'_>) -> Option<String> {
    if node.accesskit_node().role() == Role::Label { node.value() } else { node.accesskit_node().label() }
}

fn modifiers(command: bool, shift: bool, alt: bool) -> Modifiers {
    let mut m = Modifiers::NONE;
    if command {
        m |= Modifiers::COMMAND;
    }
    if shift {
        m |= Modifiers::SHIFT;
    }
    if alt {
        m |= Modifiers::ALT;
    }
    m
}

/// The action bound to `key` with exactly these modifiers, if any.
fn bound(key: Key, command: bool, shift: bool, alt: bool) -> Option<Action> {
    SHORTCUTS
        .iter()
        .find(|s| s.key == key && s.command == command && s.shift == shift && s.alt == alt)
        .map(|s| s.action)
}

/// Presses `key` with `m` in a fresh editor and returns the actions it ran.
fn actions_of(key: Key, m: Modifiers) -> Vec<Action> {
    let mut harness = cube_editor();
    harness.run_steps(2);
    harness.state_mut().ui.action_log.clear();
    harness.key_press_modifiers(m, key);
    harness.run_steps(2);
    harness.state().ui.action_log.clone()
}

/// Every shortcut the menus list runs its action with exactly its modifiers; with Shift added or
/// removed (or Alt added) it runs the other binding of that combination, or nothing.
#[test]
fn every_shortcut_matches_its_modifiers_exactly() {
    for s in SHORTCUTS {
        let Shortcut { key, command, shift, alt, action } = *s;
        assert_eq!(actions_of(key, modifiers(command, shift, alt)), vec![action], "{}", s.label());
        let toggled = bound(key, command, !shift, alt);
        assert_eq!(
            actions_of(key, modifiers(command, !shift, alt)),
            toggled.into_iter().collect::<Vec<_>>(),
            "{} with Shift {}",
            s.label(),
            if shift { "released" } else { "added" }
        );
        assert_eq!(
            actions_of(key, modifiers(command, shift, true)),
            bound(key, command, shift, true).into_iter().collect::<Vec<_>>(),
            "{} with Alt",
            s.label()
        );
    }
}

/// The menus show exactly the table's keys, so what they say is what the keys do.
#[test]
fn the_menus_and_help_list_the_shortcut_table() {
    let mut harness = cube_editor();
    harness.run_steps(2);
    for menu in ["File", "Edit", "View", "Help"] {
        harness.get_by_label(menu).click();
        harness.run_steps(2);
        let labels: Vec<String> = harness.query_all_by_role(Role::Button).filter_map(|n| text_of(&n)).collect();
        for s in SHORTCUTS {
            let listed = labels.iter().any(|l| l.ends_with(&format!("  {}", s.label())));
            let first = SHORTCUTS.iter().find(|t| t.action == s.action) == Some(s);
            let in_this_menu = labels.iter().any(|l| l.starts_with(super::shortcuts::describe(s.action)));
            if first && in_this_menu {
                assert!(listed, "the {menu} menu shows {:?} without {}", s.action, s.label());
            }
        }
        harness.key_press(Key::Escape);
        harness.run_steps(2);
    }
    // Help ▸ Keyboard shortcuts names every key of the table.
    harness.key_press(Key::F1);
    harness.run_steps(3);
    let text: Vec<String> = harness.query_all_by_role(Role::Label).filter_map(|n| text_of(&n)).collect();
    for s in SHORTCUTS {
        assert!(text.iter().any(|t| t.contains(&s.label())), "Help does not list {}", s.label());
    }
}

fn temp_taut(name: &str) -> std::path::PathBuf {
    let dir = super::document::tests::temp_dir(name);
    dir.join("cage.taut")
}

/// Ctrl+Shift+Z redoes (it once undid), Ctrl+Shift+S asks where to save and writes nothing (it
/// once saved over the file), Ctrl+S saves.
#[test]
fn redo_and_save_as_keep_their_shift() {
    let path = temp_taut("shift-keys");
    let mut doc = EditorDocument::new(primitives::cube(), None);
    doc.save_as(&path).unwrap();
    let mut harness = editor_on(primitives::cube());
    harness.state_mut().editor.replace_document(doc);
    harness.run_steps(2);
    let saved = std::fs::read(&path).unwrap();
    harness.state_mut().editor.edit(Edit::SetVertexTension(vec![VertexId(3)], 2.0));
    let tau = |h: &Harness<'_, App>| h.state().editor.document.doc().vertex_tension[3];
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_steps(1);
    assert_eq!(tau(&harness), 0.0, "Ctrl+Z undoes");
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    harness.run_steps(1);
    assert_eq!(tau(&harness), 2.0, "Ctrl+Shift+Z redoes");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    harness.run_steps(1);
    assert_eq!(tau(&harness), 2.0, "Ctrl+Y redoes");

    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    harness.run_steps(2);
    assert!(matches!(harness.state().ui.path_dialog, Some((PathPurpose::SaveAs, _))), "Ctrl+Shift+S asks for a path");
    assert_eq!(std::fs::read(&path).unwrap(), saved, "Ctrl+Shift+S wrote over the file");
    assert!(harness.state().editor.document.is_dirty());
    harness.key_press(Key::Escape);
    harness.run_steps(2);
    assert!(harness.state().ui.path_dialog.is_none());
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_steps(2);
    assert!(!harness.state().editor.document.is_dirty(), "Ctrl+S saves");
    assert_ne!(std::fs::read(&path).unwrap(), saved);
}

/// Enter in the path field confirms it.
#[test]
fn enter_confirms_the_path_field() {
    let path = temp_taut("enter");
    let mut harness = cube_editor();
    harness.run_steps(2);
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    harness.run_steps(2);
    let field = harness.get_by_role(Role::TextInput);
    field.click();
    harness.run_steps(1);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::A);
    harness.get_by_role(Role::TextInput).type_text(&path.display().to_string());
    harness.run_steps(1);
    harness.key_press(Key::Enter);
    harness.run_steps(3);
    assert!(harness.state().ui.path_dialog.is_none(), "Enter closed the dialog");
    assert!(path.exists(), "Enter saved to the typed path");
    assert_eq!(harness.state().editor.document.path(), Some(path.as_path()));
}

/// An opened mesh suggests names beside it, never the mesh itself.
#[test]
fn paths_suggested_for_an_opened_mesh_are_named_after_it() {
    let dir = super::document::tests::temp_dir("suggest");
    let obj = dir.join("bracket.obj");
    taut_core::io::export_obj(&primitives::cube().cage, &obj).unwrap();
    let mut harness = cube_editor();
    harness.state_mut().editor.open(&obj);
    let editor = &harness.state().editor;
    assert_eq!(editor.suggested_path(PathPurpose::SaveAs), dir.join("bracket.taut").display().to_string());
    assert_eq!(editor.suggested_path(PathPurpose::ExportObj), dir.join("bracket-surface.obj").display().to_string());
    assert_eq!(editor.suggested_path(PathPurpose::ExportGlb), dir.join("bracket-surface.glb").display().to_string());
    assert_eq!(editor.suggested_path(PathPurpose::Open), "");
}

/// A multi-selection with different values shows them as mixed, and a change sets them all.
#[test]
fn mixed_selections_show_mixed_values_and_set_all() {
    let mut harness = cube_editor();
    harness.state_mut().editor.edit(Edit::SetVertexTension(vec![VertexId(1)], 8.0));
    harness.state_mut().editor.edit(Edit::SetFixed(vec![VertexId(2)], false));
    harness.state_mut().editor.view.selection.vertices = vec![VertexId(0), VertexId(1), VertexId(2)];
    settle(&mut harness);
    let labels: Vec<String> = harness.query_all_by_role(Role::Label).filter_map(|n| text_of(&n)).collect();
    assert!(labels.iter().any(|l| l.starts_with("mixed: 0.00 to 8.00")), "{labels:?}");
    assert!(labels.iter().any(|l| l.contains("over-flattens")), "τ = 8 is marked: {labels:?}");
    let fixed = harness.get(By::new().role(Role::CheckBox).label_contains("fixed"));
    assert_eq!(fixed.accesskit_node().toggled(), Some(Toggled::Mixed), "the fixed box shows mixed");
    fixed.click();
    frames(&mut harness);
    let doc = harness.state().editor.document.doc().clone();
    assert!([0, 1, 2].iter().all(|&v| doc.fixed[v]), "a click fixes them all");
    // The slider's useful range ends at 4; dragging it sets the three vertices alike.
    let rail = widget_beside_label(&harness, "vertex tension τ", Role::Slider);
    harness.hover_at(slider_point(rail, 0.5));
    frames(&mut harness);
    harness.drag_at(slider_point(rail, 0.5));
    frames(&mut harness);
    for k in 1..=5 {
        harness.hover_at(slider_point(rail, 0.5 + 0.1 * k as f32));
        frames(&mut harness);
    }
    // Past the end of the rail: the slider stops at its range's end.
    let beyond = pos2(rail.right() + 40.0, rail.center().y);
    harness.hover_at(beyond);
    frames(&mut harness);
    harness.drop_at(beyond);
    frames(&mut harness);
    let doc = harness.state().editor.document.doc().clone();
    assert_eq!(doc.vertex_tension[0], 4.0, "the right end of the slider is τ = 4");
    assert!([0, 1, 2].iter().all(|&v| doc.vertex_tension[v] == 4.0), "{:?}", &doc.vertex_tension[..3]);
}

/// The rubber band adds when Shift was held as it began, even if Shift comes up first.
#[test]
fn a_shift_box_adds_even_when_shift_is_released_first() {
    for (shift, expected_kept) in [(true, true), (false, false)] {
        let mut harness = cube_editor();
        settle(&mut harness);
        let view = harness.state().ui.viewport_px.unwrap();
        // A small box in the viewport's top left corner, where there is no cage vertex.
        let (x, y) = (view[0] as f32 + 12.0, view[1] as f32 + 12.0);
        let m = if shift { Modifiers::SHIFT } else { Modifiers::NONE };
        harness.input_mut().events.push(egui::Event::ModifiersChanged(m));
        harness.hover_at(pos2(x, y));
        frames(&mut harness);
        harness.input_mut().events.push(egui::Event::PointerButton {
            pos: pos2(x, y),
            button: egui::PointerButton::Primary,
            pressed: true,
            modifiers: m,
        });
        frames(&mut harness);
        for k in 1..=4 {
            harness.hover_at(pos2(x + 8.0 * k as f32, y + 6.0 * k as f32));
            frames(&mut harness);
        }
        assert!(
            harness.state().ui.tool.get::<crate::editor::tools::box_select::BoxSelect>().is_some(),
            "a box is being drawn"
        );
        harness.input_mut().events.push(egui::Event::ModifiersChanged(Modifiers::NONE));
        frames(&mut harness);
        harness.input_mut().events.push(egui::Event::PointerButton {
            pos: pos2(x + 32.0, y + 24.0),
            button: egui::PointerButton::Primary,
            pressed: false,
            modifiers: Modifiers::NONE,
        });
        frames(&mut harness);
        let kept = harness.state().editor.view.selection.vertices.contains(&VertexId(7));
        assert_eq!(kept, expected_kept, "shift {shift}: the selection was {}", if kept { "kept" } else { "cleared" });
    }
}

/// Every text the editor shows can be drawn with its fonts (a status-bar button once showed a
/// missing-glyph box), the menus and the help window included.
#[test]
fn every_text_has_its_glyphs() {
    let mut harness = cube_editor();
    harness.state_mut().editor.notify("a message, to show the strip", true);
    settle(&mut harness);
    let check = |harness: &mut Harness<'_, App>, what: &str| {
        let texts: Vec<String> =
            harness.query_all(By::new()).flat_map(|n| [n.accesskit_node().label(), n.value()]).flatten().collect();
        let ctx = harness.ctx.clone();
        for text in texts {
            let missing: String = text
                .chars()
                .filter(|&c| {
                    !c.is_whitespace() && !ctx.fonts_mut(|f| f.has_glyph(&egui::FontId::proportional(14.0), c))
                })
                .collect();
            assert!(missing.is_empty(), "{what}: {text:?} has no glyph for {missing:?}");
        }
    };
    check(&mut harness, "the window");
    for menu in ["File", "Edit", "View", "Help"] {
        harness.get_by_label(menu).click();
        harness.run_steps(2);
        check(&mut harness, menu);
        harness.key_press(Key::Escape);
        harness.run_steps(2);
    }
    harness.key_press(Key::F1);
    harness.run_steps(3);
    check(&mut harness, "Keyboard shortcuts");
    harness.state_mut().editor.view.display.mode = DisplayMode::Curvature;
    harness.run_steps(3);
    check(&mut harness, "the curvature panel");
}

/// Every control of the side panels explains itself in a tooltip.
#[test]
fn every_control_has_a_tooltip() {
    for mode in [DisplayMode::Zebra, DisplayMode::Curvature] {
        let mut harness = cube_editor();
        harness.state_mut().editor.view.display.mode = mode;
        harness.state_mut().editor.view.display.show_curves = true;
        harness.ctx.global_style_mut(|s| s.interaction.tooltip_delay = 0.0);
        settle(&mut harness);
        let roles = [Role::Slider, Role::CheckBox, Role::RadioButton, Role::ComboBox, Role::SpinButton];
        let controls: Vec<(String, egui::Rect)> = harness
            .query_all(By::new())
            .filter(|n| roles.contains(&n.accesskit_node().role()))
            .map(|n| (format!("{:?} {:?}", n.accesskit_node().role(), n.accesskit_node().label()), n.rect()))
            .filter(|(_, r)| r.left() < 270.0 || r.left() > 1280.0 - 280.0)
            .collect();
        assert!(controls.len() > 10, "found only {} controls", controls.len());
        for (name, rect) in controls {
            let before = harness.query_all_by_role(Role::Label).count();
            harness.hover_at(rect.center());
            harness.run_steps(3);
            let after = harness.query_all_by_role(Role::Label).count();
            assert!(after > before, "{name} has no tooltip");
            harness.hover_at(pos2(640.0, 400.0));
            harness.run_steps(2);
        }
    }
}

/// A long message wraps inside the window instead of running off it, and every message stays in
/// the history, the oldest forgotten first.
#[test]
fn messages_wrap_and_are_kept_in_a_history() {
    let mut harness = cube_editor();
    let long = format!("could not open /a/very/long/path/{}: it is not a cage", "folder/".repeat(40));
    harness.state_mut().editor.notify(long.clone(), true);
    settle(&mut harness);
    let label = harness.get(By::new().role(Role::Label).label(&long));
    assert!(label.rect().right() <= 1280.0 + 0.5, "the message runs off the window: {:?}", label.rect());
    assert!(label.rect().height() > 30.0, "the message is not wrapped: {:?}", label.rect());
    for k in 0..250 {
        harness.state_mut().editor.notify(format!("message {k}"), false);
    }
    let messages = &harness.state().editor.messages;
    assert_eq!(messages.len(), super::state::MAX_MESSAGES);
    assert_eq!(messages.last().unwrap().text, "message 249");
    harness.state_mut().ui.show_messages = true;
    harness.run_steps(3);
    let shown = harness.query_all(By::new().label("message 249")).count();
    assert!(shown >= 2, "the history window lists the messages (shown {shown} times)");
}

/// Framed in the curvature view, the model stays left of the legend and fills most of the view.
#[test]
fn the_legend_never_covers_the_framed_model() {
    let mut harness = editor_on(
        taut_core::Document::from_json(
            include_str!("../../../assets/default.taut"),
            std::path::Path::new("default.taut"),
        )
        .unwrap(),
    );
    harness.state_mut().editor.view.display.mode = DisplayMode::Curvature;
    settle(&mut harness);
    harness.key_press(Key::Home);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    let (aspect, margin) = editor.viewport_shape;
    assert!(margin > 0.05, "the legend takes a margin ({margin})");
    let camera = editor.view.camera;
    let clip = camera.clip_from_view(aspect) * camera.view_from_world();
    let surface = &editor.surface_mesh().unwrap();
    let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
    for &p in surface.positions() {
        let q = clip.project_point3(editor.view.display_frame.point(p)).truncate();
        lo = lo.min(q);
        hi = hi.max(q);
    }
    // NDC x runs −1..1 across the viewport; the legend holds the right `margin` of it.
    assert!(hi.x <= 1.0 - 2.0 * margin + 1e-3, "the model reaches x = {} under the legend (margin {margin})", hi.x);
    assert!(lo.x >= -1.0 && lo.y >= -1.0 && hi.y <= 1.0, "the model leaves the view: {lo} {hi}");
    let fill = ((hi.x - lo.x) / (2.0 - 2.0 * margin)).max((hi.y - lo.y) / 2.0);
    assert!(fill > 0.8, "the framed model fills only {:.0} % of the view", 100.0 * fill);
}

/// Unfixing every vertex (Ctrl+A, untick "fixed") once made the surface vanish; now the edit is
/// refused with a message that says which vertices to fix, and nothing changes.
#[test]
fn unfixing_what_holds_the_surface_is_refused_with_what_to_fix() {
    let mut harness = cube_editor();
    settle(&mut harness);
    let before = harness.state().editor.document.doc().clone();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::A);
    frames(&mut harness);
    let fixed = harness.get(By::new().role(Role::CheckBox).label_contains("fixed"));
    fixed.click();
    frames(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &before, "the refused edit changed the document");
    assert!(!editor.document.can_undo());
    let notice = editor.notice.as_ref().expect("a message says why");
    assert!(notice.is_error && notice.text.contains("fix at least 4 of vertices"), "{}", notice.text);
    assert!(editor.surface.is_some() && editor.surface_error.is_none(), "the surface stays");
    // Freeing the top four of a cube would flatten it onto the bottom: refused too, by name.
    let top: Vec<VertexId> = (0..8).map(VertexId).filter(|&v| before.cage.position(v).z > 0.0).collect();
    harness.state_mut().editor.edit(Edit::SetFixed(top.clone(), false));
    let text = harness.state().editor.notice.as_ref().unwrap().text.clone();
    assert!(text.contains("all in one plane") && text.contains(&format!("vertices {}", top[0].0)), "{text}");
    assert_eq!(harness.state().editor.document.doc(), &before);
}
