//! File ▸ Make cage from mesh… driven as a designer drives it: the menu entry and the dialog
//! reach a fit of a small bumpy sphere written in the test; the cage becomes the document in
//! the Loop scheme as one undo step back to the unsaved work that was open; the ghost, the
//! numbers and the distance view (with its legend) are there and follow edits; Cancel stops a
//! running fit with the document unchanged while the window keeps drawing frames.

use super::document::Edit;
use super::document::tests::temp_dir;
use super::panel_tests::{App, cube_editor, frames, settle};
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};
use taut_core::surface::SchemeKind;
use taut_core::{DVec3, VertexId};

const MENU_ENTRY: &str = "Make cage from mesh…";

/// A sphere of radius about 1 with three bumps a side, from an octahedron split `levels` times
/// (8·4^levels triangles), written as OBJ text by hand.
fn write_bumpy_sphere(path: &Path, levels: u32) {
    let mut positions = vec![DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
    let mut triangles: Vec<[usize; 3]> =
        vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
    for _ in 0..levels {
        let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
        let mut mid = |a: usize, b: usize, positions: &mut Vec<DVec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a] + positions[b]) * 0.5).normalize());
                positions.len() - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let (ab, bc, ca) = (mid(a, b, &mut positions), mid(b, c, &mut positions), mid(c, a, &mut positions));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let mut text = String::new();
    for p in &positions {
        let r = 1.0 + 0.08 * (3.0 * p.x).sin() * (3.0 * p.y).cos();
        text.push_str(&format!("v {} {} {}\n", r * p.x, r * p.y, r * p.z));
    }
    for [a, b, c] in &triangles {
        text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    std::fs::write(path, text).unwrap();
}

fn has_label(harness: &Harness<'_, App>, text: &str) -> bool {
    harness.query_all(By::new().label_contains(text).include_labels()).next().is_some()
}

/// Opens the dialog from the File menu, types the mesh's path and sizes the cage by this face count.
fn fill_dialog(harness: &mut Harness<'_, App>, mesh: &Path, faces: usize) {
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label(MENU_ENTRY).click();
    harness.run_steps(2);
    assert!(harness.state().editor.cage.dialog.is_some(), "the menu entry opens the dialog");
    harness.get_by_label("mesh file (.obj, .stl, .ply, .gltf, .glb)").click();
    harness.run_steps(1);
    harness.get_by_label("mesh file (.obj, .stl, .ply, .gltf, .glb)").type_text(&mesh.display().to_string());
    harness.run_steps(1);
    // The face count is a number field; a designer types it, the test sets it.
    let dialog = harness.state_mut().editor.cage.dialog.as_mut().unwrap();
    dialog.by_faces = true;
    dialog.faces = faces;
    harness.run_steps(1);
    let dialog = harness.state().editor.cage.dialog.clone().unwrap();
    assert_eq!(PathBuf::from(dialog.path), mesh, "the path typed into the dialog");
}

/// Runs frames until the fit has ended (at most a minute). The frame that takes the result asks
/// for another: its panels were drawn before the document changed.
fn wait_for_fit(harness: &mut Harness<'_, App>) {
    let started = Instant::now();
    while harness.state().editor.cage.job.is_some() {
        assert!(started.elapsed() < Duration::from_secs(60), "the fit did not end");
        std::thread::sleep(Duration::from_millis(10));
        harness.step();
        if harness.state().editor.cage.job.is_none() {
            assert!(harness.ctx.has_requested_repaint(), "the frame that ends the fit asks to be drawn again");
        }
        harness.state_mut().editor.step_solver(super::state::SOLVER_BUDGET);
        harness.state_mut().editor.refresh_values();
    }
    frames(harness);
}

/// The cube editor with an unsaved move of vertex 7: the work that must not be lost.
fn editor_with_unsaved_work() -> (Harness<'static, App>, taut_core::Document) {
    let mut harness = cube_editor();
    harness.state_mut().editor.edit(Edit::MoveVertices(vec![(VertexId(7), DVec3::new(0.7, 0.6, 0.65))]));
    settle(&mut harness);
    let before = harness.state().editor.document.doc().clone();
    assert!(harness.state().editor.document.is_dirty());
    (harness, before)
}

#[test]
fn the_menu_and_dialog_reach_a_fit_that_becomes_the_document_with_one_undo_step() {
    let dir = temp_dir("cage-from-mesh");
    let mesh = dir.join("bumpy.obj");
    write_bumpy_sphere(&mesh, 4);
    let (mut harness, before) = editor_with_unsaved_work();
    fill_dialog(&mut harness, &mesh, 300);
    harness.get_by_label("Make cage").click();
    frames(&mut harness);
    assert!(harness.state().editor.cage.job.is_some(), "Make cage starts the fit");
    wait_for_fit(&mut harness);
    settle(&mut harness);

    let editor = &harness.state().editor;
    let doc = editor.document.doc();
    assert_eq!(doc.scheme, SchemeKind::Loop, "the cage opens in the Loop scheme");
    let faces = doc.cage.face_count();
    assert!((240..=360).contains(&faces), "about the 300 faces asked for: {faces}");
    assert!(doc.cage.faces().all(|f| doc.cage.face_valence(f) == 3), "a triangle cage");
    assert_eq!(editor.document.path(), None, "the cage has no .taut file yet: Save asks for one");
    assert_eq!(editor.document.source(), Some(mesh.as_path()));
    assert_eq!(editor.document.title(), "bumpy.obj*");
    assert!(editor.cage.dialog.is_none(), "the dialog closes when the cage is made");
    assert!(editor.surface.as_ref().is_some_and(|s| s.scheme.kind() == SchemeKind::Loop));
    // The original stays beside the cage: the ghost is on and the numbers are in the panel.
    let original = editor.cage.original.as_ref().expect("the original is kept");
    assert!(original.show_ghost && !original.show_distance);
    assert_eq!(original.mesh.face_count(), 8 * 4usize.pow(4));
    let report = &original.report;
    assert_eq!(report.cage_faces, faces);
    // The kept cage is never farther from the original than the QEM cage.
    let fitted = report.fitted().expect("the fit measured its cage");
    if report.kept_round > 0 {
        assert!(fitted.hausdorff <= report.qem.hausdorff && fitted.mean <= report.qem.mean);
    }
    for label in ["Cage from mesh", "QEM only", "fitted", "volume change", "Hausdorff", "kept:", "original as ghost"] {
        assert!(has_label(&harness, label), "the panel shows {label:?}");
    }
    assert!(has_label(&harness, "not saved in the .taut file"), "the panel says the original is not saved");
    let notice = harness.state().editor.notice.clone().unwrap();
    assert!(!notice.is_error && notice.text.contains("Loop cage"), "{}", notice.text);

    // One undo step back to the unsaved work and its file, one redo to the cage.
    let cage = harness.state().editor.document.doc().clone();
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &before, "Ctrl+Z brings back what was open, unsaved move included");
    assert_eq!(editor.document.source(), None);
    assert!(editor.document.is_dirty(), "the move is still unsaved");
    assert!(editor.document.can_undo(), "and its own undo step is still there");
    harness.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    frames(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &cage, "redo brings the cage back");
    assert_eq!(editor.document.source(), Some(mesh.as_path()));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn cancel_stops_a_running_fit_and_the_window_keeps_drawing() {
    let dir = temp_dir("cage-cancel");
    let mesh = dir.join("bumpy.obj");
    write_bumpy_sphere(&mesh, 3);
    let (mut harness, before) = editor_with_unsaved_work();
    // Hold the fit at its first report, so the test sees it running whatever the machine's speed.
    let gate = Arc::new((Mutex::new(false), Condvar::new()));
    harness.state_mut().editor.cage.gate = Some(gate.clone());
    fill_dialog(&mut harness, &mesh, 100);
    harness.get_by_label("Make cage").click();
    frames(&mut harness);
    assert!(harness.state().editor.cage.job.is_some());
    // The frames go on while the fit runs, each quickly: the work is on another thread.
    let mut slowest = Duration::ZERO;
    for _ in 0..20 {
        let started = Instant::now();
        frames(&mut harness);
        slowest = slowest.max(started.elapsed());
    }
    assert!(slowest < Duration::from_millis(500), "a frame took {slowest:?} while the fit ran");
    assert!(harness.state().editor.cage.job.is_some(), "still running");
    assert!(has_label(&harness, "read the mesh"), "the progress bar names the step");
    assert!(!harness.state().editor.busy(), "a running fit does not make the window spin");
    harness.get_by_label("Cancel").click();
    frames(&mut harness);
    assert!(harness.state().editor.cage.job.as_ref().is_none_or(|j| j.cancelling()));
    wait_for_fit(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &before, "Cancel leaves the document as it was");
    assert!(editor.document.is_dirty() && editor.cage.original.is_none());
    let notice = editor.notice.clone().unwrap();
    assert!(notice.text.contains("cancelled"), "{}", notice.text);
    // Released after the cancel: the held thread sees the flag and ends without a result.
    *gate.0.lock().unwrap() = true;
    gate.1.notify_all();
    // Undo still steps back through the designer's own edit only.
    harness.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    frames(&mut harness);
    assert_ne!(harness.state().editor.document.doc(), &before);
    assert!(!harness.state().editor.document.can_undo());
    let _ = std::fs::remove_dir_all(dir);
}

/// The closest distance from `p` to the triangle `a b c`, the textbook way (by regions).
fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return p.distance(a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return p.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return p.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    p.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

/// The shown distance values against a brute-force measure of every surface vertex.
fn check_distances_against_brute_force(harness: &Harness<'_, App>) -> Vec<f64> {
    let editor = &harness.state().editor;
    let original = &editor.cage.original.as_ref().unwrap().mesh;
    let triangles = original.triangles();
    let op = original.positions();
    let view = editor.surface.as_ref().unwrap();
    let brute: Vec<f64> = view
        .mesh()
        .positions()
        .iter()
        .map(|&p| {
            triangles
                .iter()
                .map(|t| point_triangle_distance(p, op[t[0] as usize], op[t[1] as usize], op[t[2] as usize]))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let (values, min, max) = view.values.clone().expect("the distance values are shown");
    let (want_min, want_max) = taut_core::curvature::robust_range(&brute, false);
    let scale = want_max.max(1e-12);
    assert!(
        (min - want_min).abs() <= 1e-9 * scale && (max - want_max).abs() <= 1e-9 * scale,
        "range shown {min}..{max}, brute force {want_min}..{want_max}"
    );
    let expected = taut_render::colormap::normalize(&brute, min, max);
    let worst = values.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "shown distances differ from the brute-force ones by {worst}");
    brute
}

/// Runs frames until the surface and its distance colours have caught up with the document: the
/// distances are measured again only some time after the last measurement (the throttle), so
/// this waits in real time, at most ten seconds.
fn settle_throttled(harness: &mut Harness<'_, App>) {
    let started = Instant::now();
    loop {
        harness.state_mut().editor.step_solver(Duration::from_secs(5));
        harness.state_mut().editor.refresh_values();
        harness.step();
        let editor = &harness.state().editor;
        if !editor.busy() && editor.surface.is_some() {
            break;
        }
        assert!(started.elapsed() < Duration::from_secs(10), "the distance view did not catch up");
        std::thread::sleep(Duration::from_millis(20));
    }
    harness.run_steps(2);
}

#[test]
fn the_distance_view_has_its_legend_and_follows_edits_of_the_cage() {
    let dir = temp_dir("cage-distance");
    let mesh = dir.join("bumpy.obj");
    write_bumpy_sphere(&mesh, 3);
    let mut harness = cube_editor();
    fill_dialog(&mut harness, &mesh, 120);
    harness.get_by_label("Make cage").click();
    frames(&mut harness);
    wait_for_fit(&mut harness);
    settle(&mut harness);
    assert!(harness.state().editor.legend().is_none(), "no colours until asked");
    // Ticked through accessibility: where the panel puts it depends on what is above it, and the
    // Make-cage window may lie over it at this window size.
    harness.get_by_label("colour by distance to original").click_accesskit();
    frames(&mut harness);
    settle_throttled(&mut harness);
    let legend = harness.state().editor.legend().expect("the distance view has a legend");
    assert_eq!(legend.title, "distance to original");
    let first = check_distances_against_brute_force(&harness);
    // Pull one cage vertex far out: the distances follow (after the throttle, within frames).
    let v = VertexId(0);
    let p = harness.state().editor.document.doc().cage.position(v);
    harness.state_mut().editor.edit(Edit::MoveVertices(vec![(v, p * 1.6)]));
    settle_throttled(&mut harness);
    let after = check_distances_against_brute_force(&harness);
    let peak = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
    assert!(peak(&after) > peak(&first) + 0.2, "the pulled vertex stands off the original");
    // The compare view's distance replaces this one, and the ghost can be turned off.
    harness.state_mut().editor.set_compare(super::live::CompareMode::Distance);
    assert!(!harness.state().editor.cage.distance_shown());
    harness.get_by_label("original as ghost").click_accesskit();
    frames(&mut harness);
    assert!(!harness.state().editor.cage.original.as_ref().unwrap().show_ghost);
    // Opening another document forgets the original.
    harness.state_mut().editor.replace_document(super::document::EditorDocument::new(super::primitives::cube(), None));
    assert!(harness.state().editor.cage.original.is_none());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_mesh_that_cannot_be_read_is_reported_and_nothing_changes() {
    let dir = temp_dir("cage-bad");
    let mesh = dir.join("broken.obj");
    std::fs::write(&mesh, "v 0 0 0\nv 1 0 nan\nf 1 2 3\n").unwrap();
    let (mut harness, before) = editor_with_unsaved_work();
    fill_dialog(&mut harness, &mesh, 100);
    harness.get_by_label("Make cage").click();
    frames(&mut harness);
    wait_for_fit(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &before);
    let notice = editor.notice.clone().unwrap();
    assert!(notice.is_error && notice.text.starts_with("could not make a cage"), "{}", notice.text);
    assert!(!notice.text.contains('\n'), "one line");
    assert!(editor.cage.dialog.is_some(), "the dialog stays open to try another file");
    let _ = std::fs::remove_dir_all(dir);
}
