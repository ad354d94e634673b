//! The Reference images panel driven as a designer drives it (egui_kittest on the real
//! [`EditorState::ui`](super::state::EditorState::ui)): a picture added through the panel and the
//! in-app file browser, undone; one from another folder copied next to the document first; a
//! document naming a picture outside its folder opens, says so, and does not read it.

use super::document::tests::temp_dir;
use super::files::RecentFiles;
use super::panel_tests::App;
use super::primitives;
use super::state::EditorState;
use super::ui::UiState;
use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use std::path::{Path, PathBuf};
use taut_core::document::{ReferenceImage, ReferencePlane};

/// A cube saved as `cage.taut` in a fresh folder, and an editor on it tall enough to show the
/// whole settings panel.
fn saved_cube_editor(name: &str, doc: taut_core::Document) -> (Harness<'static, App>, PathBuf) {
    let folder = temp_dir(name);
    (editor_in(&folder, doc), folder)
}

/// An editor on `doc` saved as `cage.taut` in `folder`.
fn editor_in(folder: &Path, doc: taut_core::Document) -> Harness<'static, App> {
    let path = folder.join("cage.taut");
    doc.save(&path).unwrap();
    let editor =
        EditorState::new(super::document::EditorDocument::open(&path).unwrap(), RecentFiles::in_folder(folder), None);
    let ui = UiState { no_native_dialogs: true, ..Default::default() };
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1280.0, 1600.0))
        .with_accessibility_check(false)
        .build_ui_state(|ui, app: &mut App| app.editor.ui(ui, &mut app.ui), App { editor, ui });
    harness.run_steps(2);
    harness
}

/// A PNG of `w × h` red pixels.
fn write_png(path: &Path, w: u32, h: u32) {
    image::RgbaImage::from_pixel(w, h, image::Rgba([230, 20, 20, 255])).save(path).unwrap();
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

#[test]
fn a_picture_added_through_the_panel_is_shown_and_undone_in_one_step() {
    let (mut harness, folder) = saved_cube_editor("refimg-add", primitives::cube());
    write_png(&folder.join("front.png"), 8, 4);
    harness.get_by_label("Add reference image…").click();
    harness.run_steps(2);
    assert!(has_label(&harness, "front.png"), "the browser lists the document's folder and its pictures");
    type_path(&mut harness, &folder.join("front.png").display().to_string());
    let editor = &harness.state().editor;
    let images = &editor.document.doc().reference_images;
    assert_eq!(images.len(), 1, "{:?}", editor.messages);
    assert_eq!(images[0].path, "front.png", "kept relative to the document");
    assert!(images[0].width > 0.0 && images[0].visible);
    assert!(editor.document.is_dirty());
    let picture = editor.references.picture("front.png").expect("the picture was read");
    assert_eq!(picture.pixels.dimensions(), (8, 4));
    // Its controls are in the panel; ticking "in front" is a step of its own.
    harness.get_by_label("in front").click();
    harness.run_steps(2);
    assert!(harness.state().editor.document.doc().reference_images[0].in_front);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_steps(2);
    assert!(!harness.state().editor.document.doc().reference_images[0].in_front);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    assert!(editor.document.doc().reference_images.is_empty(), "undo removes the image");
    assert!(!editor.document.is_dirty());
    // Saved and opened again, the image is where it was put.
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    harness.run_steps(2);
    harness.key_press_modifiers(Modifiers::COMMAND, Key::S);
    harness.run_steps(2);
    let reopened = taut_core::Document::load(&folder.join("cage.taut")).unwrap();
    assert_eq!(reopened.reference_images, harness.state().editor.document.doc().reference_images);
}

#[test]
fn a_picture_from_another_folder_is_copied_next_to_the_document_when_asked() {
    let (mut harness, folder) = saved_cube_editor("refimg-copy", primitives::cube());
    let elsewhere = temp_dir("refimg-copy-source").join("side.png");
    write_png(&elsewhere, 4, 4);
    harness.get_by_label("Add reference image…").click();
    harness.run_steps(2);
    type_path(&mut harness, &elsewhere.display().to_string());
    assert!(harness.state().editor.document.doc().reference_images.is_empty(), "nothing added before the answer");
    assert!(has_label(&harness, "is outside the document's folder"));
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(!folder.join("side.png").exists() && harness.state().editor.document.doc().reference_images.is_empty());
    harness.get_by_label("Add reference image…").click();
    harness.run_steps(2);
    type_path(&mut harness, &elsewhere.display().to_string());
    harness.get_by_label("Copy next to the document").click();
    harness.run_steps(2);
    assert_eq!(std::fs::read(folder.join("side.png")).unwrap(), std::fs::read(&elsewhere).unwrap());
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc().reference_images[0].path, "side.png");
    assert!(editor.references.picture("side.png").is_some());
}

#[test]
fn a_document_naming_a_picture_outside_its_folder_opens_says_so_and_reads_nothing() {
    let mut doc = primitives::cube();
    doc.reference_images = vec![
        ReferenceImage::new("../outside.png", ReferencePlane::Front, 2.0),
        ReferenceImage::new("gone.png", ReferencePlane::Top, 2.0),
        ReferenceImage::new("broken.png", ReferencePlane::Side, 2.0),
    ];
    let outer = temp_dir("refimg-outside");
    let folder = outer.join("doc");
    std::fs::create_dir_all(&folder).unwrap();
    // The picture outside is a real one: only the refusal keeps it from being read.
    write_png(&outer.join("outside.png"), 4, 4);
    std::fs::write(folder.join("broken.png"), b"\x89PNG\r\n\x1a\n truncated").unwrap();
    let harness = editor_in(&folder, doc);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc().reference_images.len(), 3, "the document opens with every image listed");
    assert!(editor.references.picture("../outside.png").is_none(), "the picture outside was read");
    let messages: Vec<&str> = editor.messages.iter().map(|m| m.text.as_str()).collect();
    let told = |what: &str| messages.iter().filter(|m| m.contains(what)).count();
    assert_eq!(told("reference image ../outside.png points outside the document's folder"), 1, "{messages:?}");
    assert_eq!(told("reference image gone.png not found next to the document"), 1, "{messages:?}");
    assert_eq!(told("reference image broken.png: cannot decode it"), 1, "{messages:?}");
    assert!(messages.iter().all(|m| !m.contains('\n')), "one line each: {messages:?}");
    assert!(has_label(&harness, "points outside the document's folder"), "the panel says why beside the image");
}

/// Dragging the opacity slider fades the picture as it moves and is one undo step.
#[test]
fn dragging_the_opacity_slider_is_one_undo_step() {
    let mut doc = primitives::cube();
    doc.reference_images.push(ReferenceImage::new("front.png", ReferencePlane::Front, 2.0));
    let folder = temp_dir("refimg-opacity");
    write_png(&folder.join("front.png"), 4, 4);
    let mut harness = editor_in(&folder, doc);
    let opacity = |h: &Harness<'_, App>| h.state().editor.document.doc().reference_images[0].opacity;
    let rail = super::panel_tests::widget_beside_label(&harness, "opacity", Role::Slider);
    let start = super::panel_tests::slider_point(rail, 1.0);
    harness.hover_at(start);
    harness.run_steps(1);
    harness.drag_at(start);
    harness.run_steps(1);
    let mut seen = Vec::new();
    let mut last = start;
    for k in 1..=6 {
        last = super::panel_tests::slider_point(rail, 1.0 - 0.1 * k as f32);
        harness.hover_at(last);
        harness.run_steps(1);
        seen.push(opacity(&harness));
    }
    harness.drop_at(last);
    harness.run_steps(2);
    let faded = opacity(&harness);
    assert!((0.3..0.5).contains(&faded), "dragged to about 0.4, got {faded} ({seen:?})");
    assert!(seen.windows(2).all(|w| w[1] <= w[0]) && seen[0] < 1.0, "the picture fades as it moves: {seen:?}");
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    harness.run_steps(2);
    assert_eq!(opacity(&harness), 1.0, "one Ctrl+Z undoes the whole drag");
    assert!(!harness.state().editor.document.can_undo(), "the drag was more than one undo step");
}
