//! File ▸ Export surface as STEP… driven as a designer drives it (egui_kittest on the real
//! [`EditorState::ui`](super::state::EditorState::ui), no system file dialog): the entry is off
//! for Loop and says why; the options dialog, then the path field, write a STEP solid of the
//! Catmull–Clark cube; a file there is replaced only after "Replace it?"; a failed export writes
//! nothing and says why in one line; a one-half cage under the mirror option exports its whole.
//! The export runs on its own thread: the tests run frames until it has ended.

use super::document::Edit;
use super::document::tests::temp_dir;
use super::mesh_ops::MeshOp;
use super::panel_tests::{App, cube_editor, frames};
use super::step_export::{LOOP_REFUSAL, MENU_ENTRY};
use egui::accesskit::Role;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, NodeT, Queryable};
use std::path::Path;
use taut_core::cad::LengthUnit;
use taut_core::surface::SchemeKind;

fn has_label(harness: &Harness<'_, App>, text: &str) -> bool {
    harness.query_all(By::new().label_contains(text).include_labels()).next().is_some()
}

/// Opens the File menu and waits for the STEP entry to show.
fn open_file_menu(h: &mut Harness<'_, App>) {
    if h.query_by_label(MENU_ENTRY).is_some() {
        return;
    }
    h.get_by_label("File").click();
    frames(h);
    for _ in 0..5 {
        if h.query_by_label(MENU_ENTRY).is_some() {
            return;
        }
        frames(h);
    }
    panic!("File has no {MENU_ENTRY} entry");
}

/// A Catmull–Clark cube, as the scheme selector leaves it.
fn catmull_clark_cube() -> Harness<'static, App> {
    let mut h = cube_editor();
    h.state_mut().editor.view.selection.clear();
    h.state_mut().editor.edit(Edit::SetScheme(SchemeKind::CatmullClark));
    frames(&mut h);
    h
}

/// File ▸ Export surface as STEP…, Export… in its dialog, then `path` typed into the path field
/// (replacing what it offers) and Enter.
fn export_through_the_menu(h: &mut Harness<'_, App>, path: &Path) {
    open_file_menu(h);
    h.get_by_label(MENU_ENTRY).click();
    h.run_steps(2);
    assert!(has_label(h, "Export the surface as STEP"), "the options dialog opened");
    export_from_the_dialog(h, path);
}

/// Export… in the open options dialog, then `path` typed into the path field and Enter.
fn export_from_the_dialog(h: &mut Harness<'_, App>, path: &Path) {
    h.get_by_label("Export…").click();
    h.run_steps(2);
    let field = h.get_by_role(Role::TextInput);
    field.click();
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.get_by_role(Role::TextInput).type_text(&path.display().to_string());
    h.run_steps(1);
    h.key_press(Key::Enter);
    h.run_steps(3);
    wait_for_the_export(h);
}

/// Runs frames until the export's thread has ended and its message is shown.
fn wait_for_the_export(h: &mut Harness<'_, App>) {
    for _ in 0..3000 {
        if h.state().ui.step_export.job.is_none() {
            h.run_steps(1);
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.run_steps(1);
    }
    panic!("the STEP export did not end within a minute");
}

/// The entry is there and on for NUSD and Catmull–Clark; for a Loop surface it is off and its
/// hover text says why.
#[test]
fn the_step_entry_is_off_for_loop_and_says_why() {
    let mut h = cube_editor();
    h.ctx.global_style_mut(|s| s.interaction.tooltip_delay = 0.0);
    open_file_menu(&mut h);
    assert!(!h.get_by_label(MENU_ENTRY).accesskit_node().is_disabled(), "on for NUSD");
    h.get_by_label("File").click();
    h.run_steps(2);
    assert!(h.query_by_label(MENU_ENTRY).is_none(), "the menu closed");

    h.state_mut().editor.view.selection.clear();
    h.state_mut().editor.mesh_op(MeshOp::Triangulate);
    h.state_mut().editor.edit(Edit::SetScheme(SchemeKind::Loop));
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc().scheme, SchemeKind::Loop);
    open_file_menu(&mut h);
    let entry = h.get_by_label(MENU_ENTRY);
    assert!(entry.accesskit_node().is_disabled(), "off for Loop");
    entry.hover();
    h.run_steps(3);
    assert!(has_label(&h, LOOP_REFUSAL), "the entry says why it is off");
    h.get_by_label(MENU_ENTRY).click();
    h.run_steps(2);
    assert!(h.state().ui.step_export.dialog.is_none(), "a click on the entry that is off opens nothing");
}

/// The options dialog offers 1e-4 of the cube's diagonal in millimetres and the path field the
/// document's name with .step; Export writes a STEP solid and reports it.
#[test]
fn exporting_a_catmull_clark_cube_writes_a_step_solid() {
    let dir = temp_dir("step-export");
    let path = dir.join("cube.step");
    let mut h = catmull_clark_cube();
    open_file_menu(&mut h);
    h.get_by_label(MENU_ENTRY).click();
    h.run_steps(2);
    let (options, default) = h.state().ui.step_export.dialog.expect("the options dialog opened");
    let diagonal = 3f64.sqrt();
    assert!((default - 1e-4 * diagonal).abs() < 1e-12, "default tolerance {default}");
    assert_eq!((options.tolerance, options.units), (default, LengthUnit::Millimetre));
    assert!(has_label(&h, "tolerance") && has_label(&h, "units"));
    // Another unit is offered and remembered for the next export.
    let radio = |unit: &'static str| By::new().role(Role::RadioButton).label(unit);
    h.get(radio("cm")).click();
    h.run_steps(1);
    assert!(has_label(&h, "in"));
    h.get_by_label("Export…").click();
    h.run_steps(2);
    let (purpose, offered) = h.state().ui.path_dialog.clone().expect("the path field opened");
    assert_eq!(purpose, super::ui::PathPurpose::ExportStep);
    assert_eq!(offered, "untitled.step", "an untitled document offers untitled.step");
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    assert!(!path.exists(), "Cancel in the path field writes nothing");
    open_file_menu(&mut h);
    h.get_by_label(MENU_ENTRY).click();
    h.run_steps(2);
    assert_eq!(h.state().ui.step_export.dialog.map(|d| d.0.units), Some(LengthUnit::Centimetre));
    h.get(radio("mm")).click();
    h.run_steps(1);
    export_from_the_dialog(&mut h, &path);
    assert!(h.state().ui.step_export.dialog.is_none(), "Export closes the options");
    let text = std::fs::read_to_string(&path).expect("the STEP file was written");
    assert!(text.starts_with("ISO-10303-21;"), "{}", &text[..text.len().min(80)]);
    assert!(text.contains("MANIFOLD_SOLID_BREP"), "a closed cube is a solid");
    assert!(text.contains("SI_UNIT(.MILLI.,.METRE.)"), "millimetres by default");
    let notice = h.state().editor.notice.clone().expect("a message");
    assert!(!notice.is_error, "{}", notice.text);
    for part in ["exported", "6 faces", "1 solid", "within", "normals"] {
        assert!(notice.text.contains(part), "{part} in {}", notice.text);
    }
    assert!(!notice.text.contains('\n'));
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 1, "only the STEP file: {leftovers:?}");

    // A saved document offers its own name.
    let saved = dir.join("my-part.taut");
    h.state_mut().editor.save_as(&saved);
    let offered = h.state().editor.suggested_path(super::ui::PathPurpose::ExportStep);
    assert_eq!(Path::new(&offered), dir.join("my-part.step"));
    let _ = std::fs::remove_dir_all(dir);
}

/// A file at the path: "Replace it?" names it, Cancel leaves it byte for byte, Replace writes it.
#[test]
fn exporting_onto_a_file_asks_first_and_cancel_keeps_it() {
    let dir = temp_dir("step-replace");
    let path = dir.join("part.step");
    std::fs::write(&path, "keep me").unwrap();
    let mut h = catmull_clark_cube();
    export_through_the_menu(&mut h, &path);
    let question = format!("{} exists already. Replace it?", path.display());
    assert!(has_label(&h, &question), "the question names the file");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "keep me", "nothing is written before the answer");
    h.get_by_label("Cancel").click();
    h.run_steps(3);
    assert!(!has_label(&h, &question), "Cancel closes the question");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "keep me", "Cancel keeps the file");

    export_through_the_menu(&mut h, &path);
    h.get_by_label("Replace").click();
    h.run_steps(3);
    wait_for_the_export(&mut h);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("ISO-10303-21;"), "Replace writes the STEP file");
    let _ = std::fs::remove_dir_all(dir);
}

/// A folder as the path, or a name that is not .step: nothing is written and the message is one
/// line saying why.
#[test]
fn a_failed_export_writes_nothing_and_says_why_in_one_line() {
    let dir = temp_dir("step-fails");
    let folder = dir.join("out.step");
    std::fs::create_dir(&folder).unwrap();
    let mut h = catmull_clark_cube();
    export_through_the_menu(&mut h, &folder);
    assert!(!has_label(&h, "Replace it?"), "a folder is not offered for replacing");
    let notice = h.state().editor.notice.clone().expect("a message");
    assert!(notice.is_error && notice.text.contains("folder"), "{}", notice.text);
    assert_eq!(notice.text.lines().count(), 1, "one line: {}", notice.text);
    assert!(folder.is_dir() && std::fs::read_dir(&folder).unwrap().next().is_none(), "the folder is untouched");
    let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(entries.len(), 1, "nothing beside the folder: {entries:?}");

    let cage = dir.join("cage.taut");
    export_through_the_menu(&mut h, &cage);
    let notice = h.state().editor.notice.clone().expect("a message");
    assert!(notice.is_error && notice.text.contains(".step"), "{}", notice.text);
    assert!(!cage.exists(), "a .taut name is refused, not written as STEP");
    let _ = std::fs::remove_dir_all(dir);
}

/// Under the mirror option a one-half cage exports the whole surface it shows: a closed solid of
/// both halves, not the open half.
#[test]
fn a_mirrored_half_exports_the_whole_solid() {
    let dir = temp_dir("step-mirror");
    let path = dir.join("whole.step");
    let mut cube = super::primitives::cube().cage;
    for p in cube.positions_mut() {
        p.x += 0.5;
    }
    let x0 = cube.faces().find(|&f| cube.face_vertices(f).all(|v| cube.position(v).x == 0.0)).unwrap();
    let half = taut_core::Document::new(taut_core::mesh::edit::delete_faces(&cube, &[x0]).unwrap().mesh);
    let mut h = super::panel_tests::editor_on(half);
    let editor = &mut h.state_mut().editor;
    editor.view.selection.vertices = editor.document.doc().cage.vertices().collect();
    editor.set_mirror(taut_core::mesh::edit::Axis::X, super::mirror::MirrorThrough::Origin);
    editor.edit(Edit::SetScheme(SchemeKind::CatmullClark));
    frames(&mut h);
    export_through_the_menu(&mut h, &path);
    let notice = h.state().editor.notice.clone().expect("a message");
    assert!(notice.text.contains("10 faces, 1 solid"), "{}", notice.text);
    assert!(std::fs::read_to_string(&path).unwrap().contains("MANIFOLD_SOLID_BREP"));
    assert_eq!(h.state().editor.document.doc().cage.face_count(), 5, "the document keeps its half");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn file_units_set_the_documents_unit_as_one_undo_step_and_the_step_export_follows() {
    let mut h = catmull_clark_cube();
    assert_eq!(h.state().editor.document.doc().units, LengthUnit::Millimetre);
    open_file_menu(&mut h);
    h.get_by_label("Units (mm)").click();
    frames(&mut h);
    h.get(By::new().role(Role::RadioButton).label("inches (in)")).click();
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc().units, LengthUnit::Inch);
    // The export's options start in the document's unit.
    h.key_press(egui::Key::Escape);
    frames(&mut h);
    open_file_menu(&mut h);
    h.get_by_label(MENU_ENTRY).click();
    h.run_steps(2);
    assert_eq!(h.state().ui.step_export.dialog.map(|d| d.0.units), Some(LengthUnit::Inch));
    h.state_mut().ui.step_export.dialog = None;
    h.state_mut().editor.undo();
    frames(&mut h);
    assert_eq!(h.state().editor.document.doc().units, LengthUnit::Millimetre, "undo puts the unit back");
}
