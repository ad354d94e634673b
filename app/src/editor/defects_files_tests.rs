//! The editor against what a designer found with files, framing and panels (issue 19, part C):
//! Save As over a file without asking, a typed Open path lost after "Discard changes", a new
//! cube cut by the viewport's edges, a viewport that jumped with the message bar, a cage dialog
//! whose default failed on Blender's monkey, and a clipped LCG plot. Each test drives the real
//! [`EditorState::ui`](super::state::EditorState::ui) with egui_kittest.

use super::document::{Edit, EditorDocument};
use super::panel_tests::{App, cube_editor, editor_on, frames, settle};
use super::primitives;
use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, NodeT, Queryable};
use std::path::{Path, PathBuf};
use taut_core::{DVec3, VertexId};

/// A saved cube in a fresh folder: its path and its bytes.
fn saved_cube(name: &str) -> (PathBuf, Vec<u8>) {
    let path = super::document::tests::temp_dir(name).join("cage.taut");
    EditorDocument::new(primitives::cube(), None).save_as(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    (path, bytes)
}

/// Types `text` into the path field (replacing what it offers) and presses Enter.
fn type_path(harness: &mut Harness<'_, App>, text: &str) {
    harness.get_by_role(Role::TextInput).click();
    harness.run_steps(1);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::A);
    harness.get_by_role(Role::TextInput).type_text(text);
    harness.run_steps(1);
    harness.key_press(Key::Enter);
    harness.run_steps(3);
}

fn has_label(harness: &Harness<'_, App>, text: &str) -> bool {
    harness.query_all(By::new().label_contains(text).include_labels()).next().is_some()
}

/// Save As onto a file that exists asks, naming it; Cancel leaves the file byte for byte and the
/// document unsaved; Replace writes it.
#[test]
fn save_as_over_an_existing_file_asks_first() {
    let (path, bytes) = saved_cube("replace");
    let mut harness = cube_editor();
    harness.state_mut().editor.edit(Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.3))]));
    harness.run_steps(2);
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    harness.run_steps(2);
    type_path(&mut harness, &path.display().to_string());
    assert_eq!(std::fs::read(&path).unwrap(), bytes, "Save As wrote over the file without asking");
    let question = format!("{} exists already. Replace it?", path.display());
    assert!(has_label(&harness, &question), "the question names the file");
    harness.get_by_label("Cancel").click();
    harness.run_steps(3);
    assert!(!has_label(&harness, &question), "Cancel closes the question");
    assert_eq!(std::fs::read(&path).unwrap(), bytes, "Cancel keeps the file byte for byte");
    let editor = &harness.state().editor;
    assert!(editor.document.is_dirty() && editor.document.path().is_none(), "Cancel keeps the document as it was");

    // The same path from the system dialog's side (it hands back a path) asks too.
    let mut ui_state = std::mem::take(&mut harness.state_mut().ui);
    harness.state_mut().editor.path_chosen(super::ui::PathPurpose::SaveAs, path.clone(), &mut ui_state);
    harness.state_mut().ui = ui_state;
    harness.run_steps(2);
    assert_eq!(std::fs::read(&path).unwrap(), bytes);
    harness.get_by_label("Replace").click();
    harness.run_steps(3);
    assert_ne!(std::fs::read(&path).unwrap(), bytes, "Replace writes the file");
    let editor = &harness.state().editor;
    assert!(!editor.document.is_dirty() && editor.document.path() == Some(path.as_path()));
}

/// Ctrl+O on unsaved work: the path typed into the field is kept through "save changes?" and
/// opened after "Discard changes"; Cancel keeps the work. File ▸ Type a path to open… asks too.
#[test]
fn the_typed_open_path_survives_discard_changes() {
    let (path, _) = saved_cube("open-discard");
    let mut doc = primitives::cube();
    doc.cage.positions_mut()[0] = DVec3::new(-0.5, -0.5, -0.5);
    let mut harness = editor_on(doc);
    let moved = Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.3))]);
    harness.state_mut().editor.edit(moved);
    harness.run_steps(2);
    let work = harness.state().editor.document.doc().clone();
    let text = path.display().to_string();
    for answer in ["Cancel", "Discard changes"] {
        harness.key_press_modifiers(Modifiers::COMMAND, Key::O);
        harness.run_steps(2);
        // The designer types at once: the path field has the keyboard.
        harness.input_mut().events.push(egui::Event::Text(text.clone()));
        harness.run_steps(1);
        harness.key_press(Key::Enter);
        harness.run_steps(2);
        assert_eq!(harness.state().editor.document.doc(), &work, "the work was replaced without asking");
        harness.get_by_label(answer).click();
        harness.run_steps(3);
    }
    let editor = &harness.state().editor;
    assert_eq!(editor.document.path(), Some(path.as_path()), "the typed file is open: {:?}", editor.notice);
    assert_eq!(editor.document.doc(), &primitives::cube());

    // The menu's path field asks before it drops unsaved work as well.
    harness.state_mut().editor.edit(Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.3))]));
    harness.run_steps(1);
    let work = harness.state().editor.document.doc().clone();
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label("Type a path to open…").click();
    harness.run_steps(2);
    harness.input_mut().events.push(egui::Event::Text(text.clone()));
    harness.run_steps(1);
    harness.key_press(Key::Enter);
    harness.run_steps(2);
    assert_eq!(harness.state().editor.document.doc(), &work, "the typed path replaced the work without asking");
    assert!(has_label(&harness, "Save the changes to cage.taut first?"));
}

/// "Save changes?" ▸ Save on an untitled document asks for a path, saves there and then opens
/// the file that was asked for; cancelling that Save As keeps the work open and unsaved.
#[test]
fn save_on_an_untitled_document_then_opens_what_was_asked() {
    let (other, _) = saved_cube("save-then-open");
    let target = other.with_file_name("my-work.taut");
    let mut doc = primitives::cube();
    doc.cage.positions_mut()[0] = DVec3::new(-0.5, -0.5, -0.5);
    let mut harness = editor_on(doc);
    harness.state_mut().editor.edit(Edit::MoveVertices(vec![(VertexId(7), DVec3::splat(1.3))]));
    harness.run_steps(2);
    let work = harness.state().editor.document.doc().clone();
    let ask_to_open = |harness: &mut Harness<'_, App>| {
        let mut ui_state = std::mem::take(&mut harness.state_mut().ui);
        harness.state_mut().editor.path_chosen(super::ui::PathPurpose::Open, other.clone(), &mut ui_state);
        harness.state_mut().ui = ui_state;
        harness.run_steps(2);
        harness.get_by_label("Save").click();
        harness.run_steps(3);
    };

    // Cancelled Save As: nothing opens, the work stays.
    ask_to_open(&mut harness);
    harness.get_by_label("Cancel").click();
    harness.run_steps(3);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &work);
    assert!(editor.document.is_dirty() && editor.document.path().is_none());
    assert!(harness.state().ui.after_save.is_none(), "the waiting Open went with the cancelled Save As");

    // Saved: the work is in its file, then the asked-for file opens.
    ask_to_open(&mut harness);
    type_path(&mut harness, &target.display().to_string());
    let saved = taut_core::Document::load(&target).expect("the work was saved");
    assert_eq!(saved.cage.positions(), work.cage.positions());
    let editor = &harness.state().editor;
    assert_eq!(editor.document.path(), Some(other.as_path()), "the asked-for file opened: {:?}", editor.notice);
    assert_eq!(editor.document.doc(), &primitives::cube());
}

/// The smoothed surface's box in normalised device coordinates as the viewport shows it.
fn projected_box(harness: &Harness<'_, App>) -> (glam::Vec2, glam::Vec2) {
    let editor = &harness.state().editor;
    let (aspect, _) = editor.viewport_shape;
    let camera = editor.view.camera;
    let clip = camera.clip_from_view(aspect) * camera.view_from_world();
    let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
    for &p in editor.surface_mesh().expect("a surface").positions() {
        let q = clip.project_point3(editor.view.display_frame.point(p)).truncate();
        lo = lo.min(q);
        hi = hi.max(q);
    }
    (lo, hi)
}

/// Asserts the surface lies inside the viewport with a margin, and fills a good part of it.
fn assert_framed(harness: &Harness<'_, App>, what: &str) {
    let (lo, hi) = projected_box(harness);
    assert!(
        lo.x >= -0.98 && lo.y >= -0.98 && hi.x <= 0.98 && hi.y <= 0.98,
        "{what}: the surface leaves the view: {lo} {hi}"
    );
    let fill = ((hi.x - lo.x) / 2.0).max((hi.y - lo.y) / 2.0);
    assert!(fill > 0.6, "{what}: the surface fills only {:.0} % of the view", 100.0 * fill);
}

/// File ▸ New ▸ Cube, every other New, and Open, frame the whole surface with a margin.
#[test]
fn new_and_opened_documents_frame_the_whole_surface() {
    let mut harness = editor_on(primitives::grid_patch(4, 3));
    settle(&mut harness);
    for name in ["Cube", "Pentagonal prism", "Grid patch", "Cylinder"] {
        harness.get_by_label("File").click();
        harness.run_steps(2);
        harness.get_by_label("New").click();
        harness.run_steps(2);
        harness.get_by_label(name).click();
        harness.run_steps(2);
        settle(&mut harness);
        assert_framed(&harness, name);
    }
    let (path, _) = saved_cube("frame-open");
    harness.state_mut().editor.open(&path);
    settle(&mut harness);
    assert_framed(&harness, "Open");
}

/// The viewport keeps its rectangle whether a message shows or not.
#[test]
fn the_viewport_does_not_move_with_the_message_bar() {
    let mut harness = cube_editor();
    settle(&mut harness);
    let without = harness.state().ui.viewport_px;
    harness.state_mut().editor.notify("a message, to show the bar", false);
    harness.run_steps(2);
    assert!(has_label(&harness, "a message, to show the bar"), "the message shows");
    assert_eq!(harness.state().ui.viewport_px, without, "the message changed the viewport");
    harness.get_by_label("×").click();
    harness.run_steps(2);
    assert!(harness.state().editor.notice.is_none());
    assert_eq!(harness.state().ui.viewport_px, without);
}

fn monkey() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/blender/monkey.obj")
}

/// The Make cage dialog as it opens fits Blender's 968-triangle monkey; Browse says why it is off
/// where there is no system file dialog, and the path field stays.
#[test]
fn the_cage_dialog_default_fits_blenders_monkey() {
    let mut harness = cube_editor();
    harness.ctx.global_style_mut(|s| s.interaction.tooltip_delay = 0.0);
    harness.run_steps(2);
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label("Make cage from mesh…").click();
    harness.run_steps(2);
    let browse = harness.get_by_label("Browse…");
    assert!(browse.accesskit_node().is_disabled(), "Browse would only open another path field");
    browse.hover();
    harness.run_steps(3);
    assert!(has_label(&harness, "No system file dialog is available"), "Browse says why it is off");
    let field = "mesh file (.obj, .stl, .ply, .gltf, .glb)";
    harness.get_by_label(field).click();
    harness.run_steps(1);
    harness.get_by_label(field).type_text(&monkey().display().to_string());
    harness.run_steps(1);
    harness.get_by_label("Make cage").click();
    harness.run_steps(1);
    let started = std::time::Instant::now();
    while harness.state().editor.cage.job.is_some() {
        assert!(started.elapsed() < std::time::Duration::from_secs(120), "the fit did not end");
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames(&mut harness);
    }
    frames(&mut harness);
    let editor = &harness.state().editor;
    let notice = editor.notice.as_ref().expect("a message");
    assert!(!notice.is_error, "the default failed: {}", notice.text);
    let report = &editor.cage.original.as_ref().expect("the cage was made").report;
    assert_eq!(report.input_triangles, 968);
    assert!(report.cage_faces < 968);

    // The panel's explanations are at the UI's text size (they were at the small size).
    harness.run_steps(2);
    for text in ["The original is not saved in the .taut file", "times: read"] {
        let node = harness.get(By::new().label_contains(text).include_labels());
        let (rect, full) = (node.rect(), node.accesskit_node().value().or(node.accesskit_node().label()).unwrap());
        // Laid out again at the body size and the label's own width: the same lines, so the same
        // height when the label is drawn at the body size.
        let body = harness.ctx.global_style().text_styles[&egui::TextStyle::Body].clone();
        let galley =
            harness.ctx.fonts_mut(|f| f.layout(full.to_string(), body, egui::Color32::WHITE, rect.width() + 0.5));
        assert!(
            (galley.size().y - rect.height()).abs() < 1.0,
            "{text:?} is drawn {} high, {} at the body size",
            rect.height(),
            galley.size().y
        );
    }
}

/// In the Curves workspace the LCG plot lies wholly inside the right panel, on a laptop's window
/// with α estimated per piece (a label a piece above it).
#[test]
fn the_lcg_plot_fits_in_the_curves_panel() {
    let mut doc = primitives::cube();
    // Two log spirals joined: pieces of differing α.
    let spiral: Vec<DVec3> = (0..120)
        .map(|i| {
            let t = 1.0 + 7.5 * f64::from(i) / 119.0;
            let r = if t < 4.0 { (0.3 * t).exp() } else { (0.3 * 4.0f64).exp() * (0.1 * (t - 4.0)).exp() };
            DVec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    doc.curves.curves = vec![taut_core::curve::DocCurve::new("spiral", spiral, false)];
    let mut harness = editor_on(doc);
    harness.set_size(egui::vec2(1280.0, 720.0));
    harness.run_steps(2);
    harness.get_by_label("Curves workspace").click();
    harness.run_steps(2);
    harness.get(By::new().label_contains("spiral  (120 points)")).click();
    harness.run_steps(2);
    harness.get_by_label("estimate α per piece").click();
    harness.run_steps(3);
    let status = harness.get(By::new().label_contains("Coons patches").include_labels()).rect();
    // The plots are the panel's two widgets without a role of their own, the LCG plot below.
    let plots: Vec<egui::Rect> = harness
        .query_all(By::new())
        .filter(|n| n.accesskit_node().role() == Role::Unknown && n.accesskit_node().bounding_box().is_some())
        .map(|n| n.rect())
        .filter(|r| r.left() >= 1280.0 - 360.0 && r.top() > 40.0)
        .collect();
    let [curvature, lcg] = plots[..] else { panic!("expected the two plots in the panel, found {plots:?}") };
    assert!(lcg.top() > curvature.bottom());
    // Below the plot's frame come its axis numbers and name.
    let axis = 30.0;
    assert!(
        lcg.bottom() + axis <= status.top(),
        "the LCG plot is cut off: {lcg:?}, the status bar at {}",
        status.top()
    );
    assert!((lcg.height() - curvature.height()).abs() < 1.0, "the LCG plot is clipped: {lcg:?} against {curvature:?}");
    assert!(lcg.height() >= 60.0, "the plots are too small to read: {lcg:?}");
}

/// The surface's box in points on the screen, as the viewport shows it.
fn model_box_in_points(harness: &Harness<'_, App>) -> egui::Rect {
    let [x, y, w, h] = harness.state().ui.viewport_px.expect("the viewport was laid out").map(|v| v as f32);
    let (lo, hi) = projected_box(harness);
    let to_point = |ndc: glam::Vec2| egui::pos2(x + (ndc.x + 1.0) * 0.5 * w, y + (1.0 - ndc.y) * 0.5 * h);
    egui::Rect::from_two_pos(to_point(lo), to_point(hi))
}

/// The legend of a view, found by its title, is an egui label (the UI's font) in a strip at the
/// viewport's right, and the framed model stays out of the strip.
fn assert_legend_beside_the_model(harness: &mut Harness<'_, App>, title: &str) {
    harness.key_press(Key::Home);
    harness.run_steps(2);
    let label = harness
        .query_all(By::new().label_contains(title).include_labels())
        .map(|n| n.rect())
        .find(|r| r.left() > 260.0 && r.right() < 1280.0 - 270.0)
        .unwrap_or_else(|| panic!("no legend titled {title:?} drawn with the UI's font in the viewport"));
    let [x, _, w, _] = harness.state().ui.viewport_px.unwrap().map(|v| v as f32);
    let strip_left = x + w - super::legend::LEGEND_WIDTH;
    assert!(label.left() >= strip_left, "the title {label:?} is not in the strip from {strip_left}");
    let model = model_box_in_points(harness);
    assert!(model.right() <= strip_left, "{title}: the model {model:?} reaches under the legend from {strip_left}");
    assert!(model.width() > 0.5 * (strip_left - x), "{title}: the model is framed too small: {model:?}");
    // A message over the viewport's bottom leaves the legend's lowest number in sight.
    // (A long one: it wraps at the width the message has.)
    let text = "a message over the viewport, ".repeat(12);
    harness.state_mut().editor.notify(text.clone(), false);
    harness.run_steps(2);
    let message = harness.get(By::new().label(&text).include_labels()).rect();
    assert!(message.right() <= strip_left, "the message {message:?} covers the legend from {strip_left}");
}

/// The curvature legend and the curve mesh's continuity legend sit beside the model.
#[test]
fn legends_are_drawn_beside_the_framed_model() {
    let mut harness = cube_editor();
    harness.state_mut().editor.view.display.mode = super::state::DisplayMode::Curvature;
    settle(&mut harness);
    let title = harness.state().editor.legend().expect("a legend").title;
    assert_legend_beside_the_model(&mut harness, &title);

    let mut harness = cube_editor();
    harness.state_mut().editor.view.selection.clear();
    settle(&mut harness);
    harness.get(By::new().role(Role::ComboBox).label("scheme")).click();
    harness.run_steps(2);
    harness.get_by_label(taut_core::surface::SchemeKind::CurveMesh.display_name()).click();
    frames(&mut harness);
    settle(&mut harness);
    harness.get_by_label("Continuity").click();
    frames(&mut harness);
    harness.run_steps(2);
    assert!(harness.state().editor.curve_mesh_legend().is_some());
    assert_legend_beside_the_model(&mut harness, "G2 jump");
}
