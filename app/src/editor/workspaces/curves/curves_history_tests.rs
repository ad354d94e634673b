//! Coons patches that follow their curves, and deleting curves and patches, driven in
//! egui_kittest as a designer drives them: build a patch from four picked curves, change a curve
//! (a segment's control point, the filter), watch the patch follow, undo, delete with the Delete
//! key and the buttons.

use crate::editor::panel_tests::{App, editor_on};
use crate::editor::primitives;
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use taut_core::DVec3;
use taut_core::curve::{CoonsPatch, DocCurve, SegmentControls};

/// The controls of the first side: a log-aesthetic segment (α = 1) from the origin to
/// (1.5, 1.2, 0), its tangents meeting at `middle`.
fn controls(middle: DVec3) -> SegmentControls {
    SegmentControls { controls: [[0.0; 3], middle.to_array(), [1.5, 1.2, 0.0]], alpha: 1.0 }
}

/// Four curves making a loop: the segment, then three straight polylines back to the origin
/// (the last one noisy, to fair), and an editor on them with the Curves workspace open and a
/// Coons patch built from the four, picked out of order.
fn patch_editor() -> Harness<'static, App> {
    let corners = [DVec3::new(1.5, 1.2, 0.0), DVec3::new(1.5, 3.0, 0.0), DVec3::new(0.0, 3.0, 0.0), DVec3::ZERO];
    let mut curves = vec![DocCurve::segment("segment", controls(DVec3::X)).unwrap()];
    assert!(!curves[0].points.is_empty(), "the segment exists");
    for k in 0..3 {
        let (a, b) = (corners[k], corners[k + 1]);
        let wobble = if k == 2 { 0.02 } else { 0.0 };
        let points = (0..=30)
            .map(|i| {
                a.lerp(b, i as f64 / 30.0) + wobble * ((i * 7 % 5) as f64 - 2.0) * DVec3::X * (i % 30).min(1) as f64
            })
            .collect();
        curves.push(DocCurve::new(format!("side {}", k + 1), points, false));
    }
    let mut doc = primitives::cube();
    doc.curves.curves = curves;
    let mut harness = editor_on(doc);
    harness.get_by_label("Curves workspace").click();
    harness.run_steps(2);
    harness.state_mut().editor.curves.picked = vec![2, 0, 3, 1];
    harness.state_mut().editor.curves.patch_samples = 6;
    harness.run_steps(1);
    harness.get(By::new().label_contains("Build Coons patch")).click();
    harness.run_steps(2);
    let patches = &harness.state().editor.curve_set().patches;
    assert_eq!(patches.len(), 1, "{:?}", harness.state().editor.notice);
    assert_eq!(patches[0].sources, Some([2, 0, 3, 1]), "the patch keeps its curves");
    harness
}

/// Whether one boundary of `patch` runs along `points` (either way), point for point.
fn has_side(patch: &CoonsPatch, points: &[DVec3]) -> bool {
    let same = |b: &[DVec3], p: &[DVec3]| b.len() == p.len() && b.iter().zip(p).all(|(x, y)| x.distance(*y) < 1e-12);
    let reversed: Vec<DVec3> = points.iter().rev().copied().collect();
    patch.boundaries.iter().any(|b| same(b, points) || same(b, &reversed))
}

#[test]
fn a_patch_follows_a_dragged_segment_and_undo_restores_both() {
    let mut harness = patch_editor();
    let before = harness.state().editor.curve_set().clone();
    // What a drag of the middle control point does each frame, as one gesture.
    let editor = &mut harness.state_mut().editor;
    editor.document.begin_gesture();
    for k in 1..=3 {
        editor.set_segment(0, controls(DVec3::new(1.0, -0.03 * k as f64, 0.0)));
    }
    editor.document.end_gesture();
    let set = editor.curve_set().clone();
    let moved = &set.curves[0].points;
    assert!(!moved.is_empty() && moved != &before.curves[0].points, "the segment changed");
    assert!(has_side(&set.patches[0], moved), "the patch runs along the moved segment");
    assert!(!has_side(&set.patches[0], &before.curves[0].points));
    for k in 1..4 {
        assert!(has_side(&set.patches[0], &set.curves[k].points), "side {k} is still a boundary");
    }
    assert_eq!(set.patches[0].sources, before.patches[0].sources);
    editor.undo();
    assert_eq!(editor.curve_set(), &before, "one undo step takes back the curve and the patch");
    editor.redo();
    assert_eq!(editor.curve_set(), &set);
}

#[test]
fn a_patch_whose_curves_no_longer_meet_keeps_its_shape_and_says_so() {
    let mut harness = patch_editor();
    let before = harness.state().editor.curve_set().patches[0].clone();
    let editor = &mut harness.state_mut().editor;
    // The segment's end dragged far from the corner it shared.
    let mut far = controls(DVec3::X);
    far.controls[2] = [3.0, 0.5, 0.0];
    editor.set_segment(0, far);
    let notice = editor.notice.clone().expect("a notice");
    assert!(notice.is_error && notice.text.contains("Coons patch 1 keeps its last shape"), "{notice:?}");
    assert!(notice.text.contains("do not meet") && !notice.text.contains('\n'), "{}", notice.text);
    assert_eq!(editor.curve_set().patches[0], before, "the copy and the history stay");
    // Pulled back, the patch follows again.
    editor.set_segment(0, controls(DVec3::new(1.0, -0.05, 0.0)));
    let set = editor.curve_set();
    assert!(has_side(&set.patches[0], &set.curves[0].points));
}

#[test]
fn a_patch_follows_the_running_filter_live_and_its_result_when_committed() {
    let mut harness = patch_editor();
    let stored = harness.state().editor.curve_set().patches[0].clone();
    harness.state_mut().editor.select_curve(Some(3));
    harness.state_mut().editor.curves.filter.estimate = false;
    // The paper's filter, which takes many passes (the shape-keeping one may be done in three).
    harness.state_mut().editor.curves.filter.keep_shape = false;
    // One pass a frame, so that the run is still going after three frames on any machine.
    harness.state_mut().editor.curves.filter_budget = std::time::Duration::ZERO;
    harness.run_steps(1);
    harness.get_by_label("Run").click();
    harness.run_steps(3);
    let editor = &harness.state().editor;
    let run = editor.curves.run.as_ref().expect("the filter runs");
    assert!(run.status().passes > 0);
    let live = editor.shown_patch(0);
    assert!(has_side(&live, run.points()), "the patch is drawn along the running filter's points");
    assert_eq!(editor.curve_set().patches[0], stored, "the document changes only when the run stops");
    assert_ne!(editor.patches_mesh().unwrap().positions(), stored.mesh().unwrap().positions());
    harness.get_by_label("Stop").click();
    harness.run_steps(2);
    let set = harness.state().editor.curve_set();
    assert!(has_side(&set.patches[0], &set.curves[3].points), "the committed run rebuilt the patch");
    assert_ne!(set.patches[0], stored);
}

#[test]
fn the_delete_key_deletes_a_selected_curve_or_patch_as_one_undo_step() {
    let mut harness = patch_editor();
    let before = harness.state().editor.curve_set().clone();
    // A source curve: the patch keeps its shape without history, and the notice says so.
    harness.get(By::new().label_contains("side 2  (31 points)")).click();
    harness.run_steps(1);
    assert_eq!(harness.state().editor.curves.selected, Some(2));
    harness.key_press(egui::Key::Delete);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    assert_eq!(editor.curve_set().curves.len(), 3);
    assert!(editor.curve_set().curves.iter().all(|c| c.name != "side 2"));
    assert_eq!(editor.curve_set().patches[0].sources, None);
    assert_eq!(editor.curve_set().patches[0].boundaries, before.patches[0].boundaries, "its shape stays");
    let notice = editor.notice.clone().unwrap();
    assert!(notice.text.contains("Coons patch 1 keeps its shape without it"), "{notice:?}");
    assert!(harness.query(By::new().label_contains("fixed shape")).is_some(), "the list says so");
    harness.state_mut().editor.undo();
    assert_eq!(harness.state().editor.curve_set(), &before, "undo brings back the curve and the history");
    harness.run_steps(1);
    // The patch, selected in the list; the Delete button and the key do the same.
    harness.get(By::new().label_contains("Coons patch 1  (follows its curves)")).click();
    harness.run_steps(1);
    assert_eq!((harness.state().editor.curves.selected_patch, harness.state().editor.curves.selected), (Some(0), None));
    harness.key_press(egui::Key::Delete);
    harness.run_steps(2);
    let editor = &harness.state().editor;
    assert!(editor.curve_set().patches.is_empty() && editor.curve_set().curves.len() == 4);
    assert!(editor.document.doc().cage.vertex_count() == 8, "the cage is left alone");
    harness.state_mut().editor.undo();
    assert_eq!(harness.state().editor.curve_set(), &before);
    harness.run_steps(1);
    harness.get(By::new().label_contains("Coons patch 1  (follows")).click();
    harness.run_steps(1);
    harness.get_by_label("Delete patch").click();
    harness.run_steps(2);
    assert!(harness.state().editor.curve_set().patches.is_empty());
    // Help lists the key of the Curves workspace.
    harness.key_press(egui::Key::F1);
    harness.run_steps(3);
    assert!(harness.query(By::new().label_contains("delete the selected curve or Coons patch")).is_some());
}
