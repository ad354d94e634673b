//! The Curves workspace driven as a designer drives it, in egui_kittest: switching workspaces,
//! importing point files through the path dialog, drawing with pointer events on a plane,
//! fairing live with undo, the plots, a segment's α slider, a Coons patch saved and reopened.

use super::CurveTool;
use crate::editor::document::EditorDocument;
use crate::editor::document::tests::temp_dir;
use crate::editor::panel_tests::{App, editor_on, slider_point, widget_beside_label};
use crate::editor::primitives;
use crate::editor::ui::PathPurpose;
use egui::accesskit::Role;
use egui::{Event, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{By, NodeT, Queryable};
use taut_core::DVec3;
use taut_core::aesthetic::curvature_graph;
use taut_core::curve::{DocCurve, PointSequence, Workspace};

/// An editor on the cube with the Curves workspace open.
fn curves_editor(curves: Vec<DocCurve>) -> Harness<'static, App> {
    let mut doc = primitives::cube();
    doc.curves.curves = curves;
    let mut harness = editor_on(doc);
    harness.get_by_label("Curves workspace").click();
    harness.run_steps(2);
    harness
}

/// A logarithmic spiral ρ = e^{0.3 θ} over 1.2 turns (α = 1), `n` points, with deterministic
/// noise of `noise` of its size across the curve.
fn noisy_spiral(n: usize, noise: f64) -> Vec<DVec3> {
    let mut seed = 12345u64;
    let mut random = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    (0..n)
        .map(|i| {
            let t = 1.0 + 7.5 * i as f64 / (n - 1) as f64;
            let r = (0.3 * t).exp();
            DVec3::new(r * t.cos(), r * t.sin(), 0.0) * (1.0 + noise * random())
        })
        .collect()
}

/// Whether a plain label (or any widget) reading `text` is shown.
fn shows(harness: &Harness<'_, App>, text: &str) -> bool {
    harness.query(By::new().label(text).include_labels()).is_some()
}

/// The text of the first plain label containing `text`.
fn label_containing(harness: &Harness<'_, App>, text: &str) -> Option<String> {
    harness.query(By::new().label_contains(text).include_labels()).map(|n| {
        let node = n.accesskit_node();
        node.label().or_else(|| node.value()).unwrap_or_default()
    })
}

fn lcg_residual(points: &[DVec3]) -> f64 {
    curvature_graph(&PointSequence::new(points.to_vec(), false), Some(DVec3::Z)).fit.expect("an LCG line").residual
}

#[test]
fn the_switch_shows_either_workspace_and_is_saved_with_the_file() {
    let mut harness = editor_on(primitives::cube());
    assert!(shows(&harness, "Cage"), "the surface workspace first");
    harness.get_by_label("Curves workspace").click();
    harness.run_steps(2);
    assert_eq!(harness.state().editor.curves.workspace, Workspace::Curves);
    assert!(shows(&harness, "Curves") && !shows(&harness, "Cage"));
    assert!(shows(&harness, "Log-aesthetic filter"));
    assert!(!harness.state().editor.document.is_dirty(), "switching is no change of the design");
    let path = temp_dir("curves-switch").join("w.taut");
    harness.state_mut().editor.save_as(&path);
    let reopened = EditorDocument::open(&path).unwrap();
    assert_eq!(reopened.doc().curves.view.workspace, Workspace::Curves);
    harness.get_by_label("Surface workspace").click();
    harness.run_steps(2);
    assert!(shows(&harness, "Cage"), "back to the surface workspace");
    assert_eq!(harness.state().editor.curves.workspace, Workspace::Surface);
    // Opening the file shows the workspace it was saved in.
    harness.state_mut().editor.open(&path);
    harness.run_steps(2);
    assert_eq!(harness.state().editor.curves.workspace, Workspace::Curves);
    assert!(shows(&harness, "Log-aesthetic filter"));
}

/// Opens the import dialog, types `path` and confirms.
fn import(harness: &mut Harness<'_, App>, path: &std::path::Path) {
    harness.get_by_label("Import…").click();
    harness.run_steps(2);
    let ui = &mut harness.state_mut().ui;
    assert!(matches!(ui.path_dialog, Some((PathPurpose::ImportCurve, _))), "Import asks for a path");
    ui.path_dialog = Some((PathPurpose::ImportCurve, path.display().to_string()));
    harness.run_steps(1);
    harness.get_by_label("OK").click();
    harness.run_steps(2);
}

#[test]
fn importing_json_adds_a_curve_and_a_bad_csv_row_is_named() {
    let mut harness = curves_editor(Vec::new());
    let dir = temp_dir("curves-import");
    let json = dir.join("arc.json");
    std::fs::write(&json, r#"{"points": [[0, 0], [1, 0.2], [2, 0.7], [3, 1.5]]}"#).unwrap();
    import(&mut harness, &json);
    let editor = &harness.state().editor;
    let curves = &editor.curve_set().curves;
    assert_eq!(curves.len(), 1);
    assert_eq!(curves[0].name, "arc");
    assert_eq!(curves[0].points[2], DVec3::new(2.0, 0.7, 0.0));
    assert_eq!(editor.curves.selected, Some(0));
    assert!(label_containing(&harness, "arc  (4 points)").is_some(), "the list shows it");

    let csv = dir.join("bad.csv");
    std::fs::write(&csv, "x,y\n0,0\n1,zero\n2,1\n").unwrap();
    import(&mut harness, &csv);
    let editor = &harness.state().editor;
    assert_eq!(editor.curve_set().curves.len(), 1, "a bad file adds nothing");
    let notice = editor.notice.clone().expect("a message");
    assert!(
        notice.is_error && notice.text.contains("row 3") && notice.text.contains("'zero' is not a number"),
        "{notice:?}"
    );
    assert!(!notice.text.contains('\n'), "one line: {}", notice.text);

    // Undo takes the import back.
    harness.state_mut().editor.undo();
    assert!(harness.state().editor.curve_set().curves.is_empty());
}

/// Presses the primary button at `from`, moves through `path` and lets go at its end.
fn stroke(harness: &mut Harness<'_, App>, from: Pos2, path: &[Pos2]) {
    let press = |pos, pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    harness.input_mut().events.push(Event::PointerMoved(from));
    harness.run_steps(1);
    harness.input_mut().events.push(press(from, true));
    harness.run_steps(1);
    for &p in path {
        harness.input_mut().events.push(Event::PointerMoved(p));
        harness.run_steps(1);
    }
    harness.input_mut().events.push(press(*path.last().unwrap(), false));
    harness.run_steps(2);
}

#[test]
fn esc_during_a_stroke_drops_it_and_adds_no_curve() {
    let mut harness = curves_editor(Vec::new());
    harness.get_by_label("Draw").click();
    harness.run_steps(1);
    let centre = Pos2::new(270.0 + (1280.0 - 630.0) / 2.0, 400.0);
    let press = |pressed| Event::PointerButton {
        pos: centre,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    harness.input_mut().events.push(Event::PointerMoved(centre));
    harness.run_steps(1);
    harness.input_mut().events.push(press(true));
    harness.run_steps(1);
    for k in 1..=10 {
        harness.input_mut().events.push(Event::PointerMoved(centre + egui::vec2(12.0 * k as f32, 5.0 * k as f32)));
        harness.run_steps(1);
    }
    assert!(harness.state().ui.tool.is_running(), "the stroke is being drawn");
    harness.key_press(egui::Key::Escape);
    harness.run_steps(1);
    assert!(!harness.state().ui.tool.is_running(), "Esc ends the stroke");
    harness.input_mut().events.push(press(false));
    harness.run_steps(2);
    assert!(harness.state().editor.curve_set().curves.is_empty(), "no curve from a dropped stroke");
    assert!(!harness.state().editor.document.can_undo(), "and no undo step");
}

#[test]
fn a_drawn_curve_lies_on_the_chosen_plane() {
    let mut harness = curves_editor(Vec::new());
    harness.get_by_label("Draw").click();
    harness.run_steps(1);
    assert_eq!(harness.state().editor.curves.tool, CurveTool::Draw);
    // The middle of the viewport (between the panels of 270 and 360 points).
    let centre = Pos2::new(270.0 + (1280.0 - 630.0) / 2.0, 400.0);
    let path: Vec<Pos2> = (1..=30)
        .map(|k| {
            let t = k as f32 / 30.0;
            centre + egui::vec2(160.0 * t, -90.0 * (3.0 * t).sin())
        })
        .collect();
    stroke(&mut harness, centre, &path);
    let curves = &harness.state().editor.curve_set().curves;
    assert_eq!(curves.len(), 1, "the stroke became a curve");
    let points = &curves[0].points;
    assert!(points.len() >= 20, "{} points", points.len());
    assert!(points.iter().all(|p| p.z.abs() <= 1e-9 * (1.0 + p.length())), "on z = 0: {points:?}");
    let spread = points[0].distance(points[points.len() - 1]);
    assert!(spread > 0.1, "the curve follows the mouse ({spread})");

    // On the YZ plane, x = 0.
    harness.state_mut().editor.curves.plane = super::DrawPlane::Yz;
    harness.state_mut().editor.view.camera.set_view(taut_render::StandardView::Right);
    harness.run_steps(1);
    stroke(&mut harness, centre, &path);
    let curves = &harness.state().editor.curve_set().curves;
    assert_eq!(curves.len(), 2);
    assert!(curves[1].points.iter().all(|p| p.x.abs() <= 1e-9 * (1.0 + p.length())));
}

#[test]
fn the_live_filter_lowers_the_lcg_residual_and_undo_restores_the_curve_bit_for_bit() {
    let original = noisy_spiral(120, 0.005);
    let mut harness = curves_editor(vec![DocCurve::new("noisy", original.clone(), false)]);
    harness.state_mut().editor.select_curve(Some(0));
    harness.state_mut().editor.curves.filter.estimate = false;
    harness.state_mut().editor.curves.filter.alpha = 1.0;
    // The paper's filter, which drives the LCG to a line whatever it costs in position (the
    // shape-keeping one is checked below).
    harness.state_mut().editor.curves.filter.keep_shape = false;
    harness.run_steps(1);
    harness.get_by_label("Run").click();
    harness.run_steps(1);
    assert!(harness.state().editor.curves.run.is_some(), "Run starts the filter: {:?}", harness.state().editor.notice);
    let mut frames = 0;
    let mut moved_while_running = false;
    while harness.state().editor.curves_busy() && frames < 300 {
        harness.run_steps(1);
        frames += 1;
        let editor = &harness.state().editor;
        if editor.curves_busy() {
            moved_while_running |= editor.shown_points(0) != original.as_slice();
            assert_eq!(editor.curve_set().curves[0].points, original, "the document waits for the run's end");
        }
    }
    if harness.state().editor.curves_busy() {
        harness.get_by_label("Stop").click();
        harness.run_steps(1);
    }
    assert!(moved_while_running || frames <= 1, "the viewport follows the running filter");
    let faired = harness.state().editor.curve_set().curves[0].points.clone();
    let (before, after) = (lcg_residual(&original), lcg_residual(&faired));
    assert!(after < 0.25 * before, "LCG residual {before} → {after}: expected at least a factor of 4");
    assert!(harness.state().editor.document.can_undo());
    harness.state_mut().editor.undo();
    harness.run_steps(1);
    let restored = &harness.state().editor.curve_set().curves[0].points;
    assert!(
        restored.iter().zip(&original).all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits))
    );
    assert!(!harness.state().editor.document.can_undo(), "the run was one undo step");
}

#[test]
fn the_plots_show_the_curvature_and_the_lcg_with_alpha() {
    let mut harness = curves_editor(vec![DocCurve::new("spiral", noisy_spiral(80, 0.0), false)]);
    assert!(label_containing(&harness, "Select a curve").is_some());
    harness.get(By::new().label_contains("spiral  (80 points)")).click();
    harness.run_steps(2);
    assert!(shows(&harness, "curvature κ against arc length s"));
    let text = label_containing(&harness, "LCG: slope α = ").expect("the LCG's slope is shown");
    let alpha: f64 = text.trim_start_matches("LCG: slope α = ").split(',').next().unwrap().parse().unwrap();
    assert!((alpha - 1.0).abs() < 0.05, "a log spiral's LCG slope is 1, the plot says {alpha}");
}

#[test]
fn the_segment_alpha_slider_changes_the_segment_and_keeps_its_ends() {
    let mut harness = curves_editor(Vec::new());
    harness.get_by_label("New segment").click();
    harness.run_steps(2);
    let first = harness.state().editor.curve_set().curves[0].clone();
    let controls = first.segment.expect("a segment");
    assert!(!first.points.is_empty(), "the default segment exists");
    let rail = widget_beside_label(&harness, "segment α", Role::Slider);
    let at = slider_point(rail, 0.3);
    harness.hover_at(at);
    harness.run_steps(1);
    harness.drag_at(at);
    harness.run_steps(1);
    harness.drop_at(at);
    harness.run_steps(2);
    let after = harness.state().editor.curve_set().curves[0].clone();
    let new_alpha = after.segment.unwrap().alpha;
    assert!(new_alpha < 0.0, "30 % along −3…3 is about −1.2, got {new_alpha}");
    assert_eq!(after.segment.unwrap().controls, controls.controls, "the controls stay");
    assert_ne!(after.points, first.points, "the segment changed");
    if !after.points.is_empty() {
        let [p0, _, p2] = controls.points();
        assert!(after.points[0].distance(p0) < 1e-9 && after.points[after.points.len() - 1].distance(p2) < 1e-9);
    } else {
        assert!(label_containing(&harness, "no such segment").is_some(), "said clearly");
    }
}

#[test]
fn a_coons_patch_from_four_curves_lands_in_the_document_and_reopens() {
    // A loop of four sides with small gaps at the corners, one side drawn backwards.
    let c = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.0, 1.5, 0.5), DVec3::new(0.0, 1.5, 0.0)];
    let side = |a: DVec3, b: DVec3, bow: f64| -> Vec<DVec3> {
        (0..=10).map(|k| a.lerp(b, k as f64 / 10.0) + DVec3::new(0.0, 0.0, bow * (k as f64 * 0.314).sin())).collect()
    };
    let mut sides = [side(c[0], c[1], 0.2), side(c[1], c[2], 0.0), side(c[3], c[2], 0.3), side(c[3], c[0], 0.0)];
    sides[1][0] += DVec3::new(0.01, 0.0, 0.0);
    let curves = sides.iter().enumerate().map(|(k, s)| DocCurve::new(format!("side {k}"), s.clone(), false)).collect();
    let mut harness = curves_editor(curves);
    harness.state_mut().editor.curves.picked = vec![0, 2, 1, 3];
    harness.state_mut().editor.curves.patch_samples = 8;
    harness.run_steps(1);
    harness.get(By::new().label_contains("Build Coons patch")).click();
    harness.run_steps(2);
    let editor = &harness.state().editor;
    let patches = &editor.curve_set().patches;
    assert_eq!(patches.len(), 1, "{:?}", editor.notice);
    let mesh = editor.patches_mesh().expect("a mesh");
    assert_eq!(mesh.vertex_count(), 81);
    // The corners are where the sides meet, within the snap.
    for corner in c {
        let nearest = mesh.positions().iter().map(|p| p.distance(corner)).fold(f64::INFINITY, f64::min);
        assert!(nearest < 0.01, "corner {corner} is {nearest} from the patch");
    }
    let path = temp_dir("curves-coons").join("patch.taut");
    harness.state_mut().editor.save_as(&path);
    let reopened = EditorDocument::open(&path).unwrap();
    assert_eq!(reopened.doc().curves, harness.state().editor.curve_set().clone());
    harness.state_mut().editor.undo();
    assert!(harness.state().editor.curve_set().patches.is_empty(), "undo takes the patch back");
}

#[test]
fn dragging_a_control_point_moves_only_it_in_the_segments_plane_as_one_undo_step() {
    let mut harness = curves_editor(Vec::new());
    harness.state_mut().editor.view.camera.set_view(taut_render::StandardView::Top);
    harness.get_by_label("New segment").click();
    harness.run_steps(2);
    let before = harness.state().editor.curve_set().curves[0].segment.expect("a segment");
    let [x, y, w, h] = harness.state().ui.viewport_px.expect("the viewport was laid out").map(|v| v as f32);
    let view = crate::editor::interaction::ViewportRect { min: glam::Vec2::new(x, y), size: glam::Vec2::new(w, h) };
    let editor = &harness.state().editor;
    let middle = editor.view.display_frame.to_display_f64(before.points()[1]);
    let (pixel, _) = crate::editor::interaction::project(&editor.view.camera, &view, middle).expect("on screen");
    let from = Pos2::new(pixel.x, pixel.y);
    let path: Vec<Pos2> = (1..=8).map(|k| from + egui::vec2(4.0 * k as f32, 3.0 * k as f32)).collect();
    stroke(&mut harness, from, &path);
    let after = harness.state().editor.curve_set().curves[0].segment.unwrap();
    let [p0, p1, p2] = after.points();
    assert_eq!([p0.to_array(), p2.to_array()], [before.controls[0], before.controls[2]], "the ends stay");
    assert!(p1.distance(before.points()[1]) > 1e-3, "the middle control followed the mouse");
    let normal = (before.points()[1] - before.points()[0]).cross(before.points()[2] - before.points()[1]).normalize();
    assert!((p1 - p0).dot(normal).abs() < 1e-9, "it stays in the segment's plane");
    harness.state_mut().editor.undo();
    assert_eq!(harness.state().editor.curve_set().curves[0].segment.unwrap(), before, "one undo step");
}

#[test]
fn cage_keys_do_nothing_in_the_curves_workspace() {
    // The cage and its selection are out of sight here: Delete, X, E, G, Tab and Ctrl+A must not
    // touch them, and the Mesh menu is not offered.
    let mut harness = editor_on(primitives::cube());
    harness.state_mut().editor.view.selection.click_vertex(taut_core::VertexId(7), false);
    harness.run_steps(2);
    harness.get_by_label("Curves workspace").click();
    harness.run_steps(2);
    let before = harness.state().editor.document.doc().clone();
    for key in [egui::Key::Delete, egui::Key::X, egui::Key::E, egui::Key::M, egui::Key::Tab] {
        harness.key_press(key);
        harness.run_steps(2);
    }
    harness.key_press(egui::Key::G);
    harness.run_steps(2);
    harness.key_press(egui::Key::Enter);
    harness.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    assert_eq!(editor.document.doc(), &before, "the cage is unchanged");
    assert!(!editor.document.can_undo(), "no undo step was made");
    assert_eq!(editor.view.selection.vertices, vec![taut_core::VertexId(7)], "the cage selection stays");
    assert!(harness.query(By::new().label("Mesh")).is_none(), "no Mesh menu here");
    // Back in the Surface workspace the same key works on the selection.
    harness.get_by_label("Surface workspace").click();
    harness.run_steps(2);
    harness.key_press(egui::Key::X);
    harness.run_steps(2);
    assert_eq!(harness.state().editor.document.doc().cage.vertex_count(), 7, "X deletes the vertex there");
}

/// Clicks the primary button at `at` with `modifiers` held.
fn click_with(harness: &mut Harness<'_, App>, at: Pos2, modifiers: Modifiers) {
    let press = |pressed| Event::PointerButton { pos: at, button: PointerButton::Primary, pressed, modifiers };
    harness.input_mut().events.push(Event::ModifiersChanged(modifiers));
    harness.input_mut().events.push(Event::PointerMoved(at));
    harness.run_steps(1);
    harness.input_mut().events.push(press(true));
    harness.run_steps(1);
    harness.input_mut().events.push(press(false));
    harness.run_steps(1);
    harness.input_mut().events.push(Event::ModifiersChanged(Modifiers::NONE));
    harness.run_steps(1);
}

#[test]
fn shift_click_picks_curves_for_a_patch_and_a_click_on_the_patch_selects_it() {
    // The four sides of a 2 × 1.5 rectangle in the XY plane, seen from the top.
    let c = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.0, 1.5, 0.0), DVec3::new(0.0, 1.5, 0.0)];
    let curves = (0..4)
        .map(|k| {
            let (a, b) = (c[k], c[(k + 1) % 4]);
            DocCurve::new(format!("side {k}"), (0..=10).map(|t| a.lerp(b, t as f64 / 10.0)).collect(), false)
        })
        .collect();
    let mut harness = curves_editor(curves);
    harness.state_mut().editor.view.camera.set_view(taut_render::StandardView::Top);
    harness.state_mut().editor.frame_all();
    harness.run_steps(2);
    let at = |harness: &Harness<'_, App>, p: DVec3| {
        let pixel = crate::editor::gizmo_tests::pixel_of(harness, p);
        Pos2::new(pixel.x, pixel.y)
    };
    let middle = |k: usize| c[k].lerp(c[(k + 1) % 4], 0.5);

    // Shift+click picks a curve and leaves the selection; a second one unpicks it.
    let side = at(&harness, middle(1));
    click_with(&mut harness, side, Modifiers::SHIFT);
    assert_eq!(harness.state().editor.curves.picked, vec![1]);
    assert_eq!(harness.state().editor.curves.selected, None, "picking is not selecting");
    click_with(&mut harness, side, Modifiers::SHIFT);
    assert!(harness.state().editor.curves.picked.is_empty(), "Shift+click again unpicks");
    // A plain click selects it.
    click_with(&mut harness, side, Modifiers::NONE);
    assert_eq!(harness.state().editor.curves.selected, Some(1));

    for k in [2, 0, 3, 1] {
        let side = at(&harness, middle(k));
        click_with(&mut harness, side, Modifiers::SHIFT);
    }
    assert_eq!(harness.state().editor.curves.picked, vec![2, 0, 3, 1], "in the order picked");
    assert!(shows(&harness, "Build Coons patch (4 of 4 picked)"), "the panel counts the viewport's picks");
    harness.get(By::new().label_contains("Build Coons patch")).click();
    harness.run_steps(2);
    assert_eq!(harness.state().editor.curve_set().patches.len(), 1, "{:?}", harness.state().editor.notice);

    // A click inside the patch, away from its sides, selects the patch; outside, nothing.
    let inside = at(&harness, DVec3::new(0.7, 0.6, 0.0));
    click_with(&mut harness, inside, Modifiers::NONE);
    let editor = &harness.state().editor;
    assert_eq!((editor.curves.selected_patch, editor.curves.selected), (Some(0), None));
    let outside = at(&harness, DVec3::new(1.0, 1.9, 0.0));
    let [x, y, w, h] = harness.state().ui.viewport_px.expect("laid out").map(|v| v as f32);
    assert!(egui::Rect::from_min_size(Pos2::new(x, y), egui::vec2(w, h)).contains(outside), "{outside:?}");
    click_with(&mut harness, outside, Modifiers::NONE);
    let editor = &harness.state().editor;
    assert_eq!((editor.curves.selected_patch, editor.curves.selected), (None, None));

    // Undo takes the patch back, and the notice that it was built goes with it.
    assert!(harness.state().editor.notice.is_some(), "building said something");
    harness.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    assert!(editor.curve_set().patches.is_empty() && editor.notice.is_none(), "{:?}", editor.notice);
}

#[test]
fn home_frames_the_curves_and_period_the_selected_one() {
    // Two small curves far from the cube: Home in the Curves workspace frames the curves (not the
    // cage ghost behind them), "." the selected curve alone.
    let arc = |x0: f64, length: f64| -> Vec<DVec3> {
        (0..=20).map(|k| DVec3::new(x0 + length * k as f64 / 20.0, 30.0 + 0.1 * (k as f64 * 0.3).sin(), 0.0)).collect()
    };
    let curves = vec![DocCurve::new("long", arc(40.0, 2.0), false), DocCurve::new("short", arc(43.0, 0.2), false)];
    let mut harness = curves_editor(curves);
    harness.state_mut().editor.view.camera.set_view(taut_render::StandardView::Top);
    harness.run_steps(2);
    let [_, _, width, height] = harness.state().ui.viewport_px.expect("laid out").map(|v| v as f32);
    // The extent on screen of curve `i`, as a fraction of the viewport's width and height.
    let extent = |harness: &Harness<'_, App>, i: usize| {
        let points = harness.state().editor.curve_set().curves[i].points.clone();
        let pixels: Vec<glam::Vec2> =
            points.iter().map(|&p| crate::editor::gizmo_tests::pixel_of(harness, p)).collect();
        let (lo, hi) = pixels.iter().fold((glam::Vec2::MAX, glam::Vec2::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        ((hi.x - lo.x) / width).max((hi.y - lo.y) / height)
    };
    harness.hover_at(Pos2::new(500.0, 400.0));
    harness.key_press(egui::Key::Home);
    harness.run_steps(2);
    let both = extent(&harness, 0).max(extent(&harness, 1));
    assert!(both > 0.4, "Home frames the curves: the long one spans {both} of the viewport");
    harness.state_mut().editor.select_curve(Some(1));
    harness.key_press(egui::Key::Period);
    harness.run_steps(2);
    let short = extent(&harness, 1);
    assert!(short > 0.4, "\".\" frames the selected curve: it spans {short} of the viewport");
    assert!(!harness.state().editor.document.can_undo(), "framing is no change of the design");
    harness.key_press(egui::Key::F1);
    harness.run_steps(2);
    assert!(
        label_containing(&harness, "in the Curves workspace: the selected curve or patch").is_some(),
        "Help lists the key"
    );
}

/// Runs the filter on curve 0 to its end (or 300 frames) and returns the committed points.
fn fair_curve_zero(harness: &mut Harness<'_, App>) -> Vec<DVec3> {
    harness.state_mut().editor.select_curve(Some(0));
    harness.state_mut().editor.curves.filter.estimate = false;
    harness.state_mut().editor.curves.filter.alpha = 1.0;
    harness.run_steps(1);
    harness.get_by_label("Run").click();
    harness.run_steps(1);
    assert!(harness.state().editor.curves.run.is_some(), "Run starts the filter: {:?}", harness.state().editor.notice);
    let mut frames = 0;
    while harness.state().editor.curves_busy() && frames < 300 {
        harness.run_steps(1);
        frames += 1;
    }
    if harness.state().editor.curves_busy() {
        harness.get_by_label("Stop").click();
        harness.run_steps(1);
    }
    harness.state().editor.curve_set().curves[0].points.clone()
}

#[test]
fn keep_the_shape_takes_the_noise_out_where_the_points_were_and_the_paper_filter_does_not() {
    // The exact log spiral the noisy points were taken from, finely: distances to it.
    let exact = noisy_spiral(6000, 0.0);
    let distance = |p: DVec3| {
        exact
            .windows(2)
            .map(|w| {
                let t = ((p - w[0]).dot(w[1] - w[0]) / (w[1] - w[0]).length_squared()).clamp(0.0, 1.0);
                (w[0] + t * (w[1] - w[0])).distance(p)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mean = |points: &[DVec3]| points.iter().map(|p| distance(*p)).sum::<f64>() / points.len() as f64;
    let noisy = noisy_spiral(120, 0.005);
    let mut faired = Vec::new();
    for keep_shape in [true, false] {
        let mut harness = curves_editor(vec![DocCurve::new("noisy", noisy.clone(), false)]);
        assert!(harness.state().editor.curves.filter.keep_shape, "keeping the shape is the default");
        harness.state_mut().editor.curves.filter.keep_shape = keep_shape;
        faired.push(mean(&fair_curve_zero(&mut harness)));
    }
    let before = mean(&noisy);
    let (kept, paper) = (faired[0], faired[1]);
    println!("mean distance to the true spiral: noisy {before:.4}, kept {kept:.4}, paper {paper:.4}");
    assert!(kept < 0.5 * before, "keep the shape: {before} → {kept}");
    assert!(paper > kept, "the paper's filter moves the curve more: {paper} against {kept}");
}
