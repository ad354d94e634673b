//! The draft and highlight views in the Display panel, as a designer picks them: the radio
//! buttons switch the renderer's mode, the pull and tube controls reach it, and the draft view
//! shows its legend's three classes.

use super::*;
use crate::editor::panel_tests::{cube_editor, frames, settle};
use crate::editor::state::DisplayMode;
use egui_kittest::kittest::Queryable;

#[test]
fn settings_become_the_renderer_modes() {
    let mut s = AnalysisSettings { pull_negative: true, draft_angle: 5.0, ..Default::default() };
    assert_eq!(s.draft_mode(), SurfaceMode::Draft { pull: Pull::Direction(-DVec3::Z), angle_degrees: 5.0 });
    s.pull = PullAxis::View;
    assert_eq!(s.pull(), Pull::View, "the view direction has no sign");
    // 10 model units on a model of half-extent 50 are 0.2 display units.
    s.tube_spacing = 10.0;
    s.tube_axis = 1;
    let frame = taut_render::DisplayFrame { origin: DVec3::ZERO, scale: 50.0 };
    let SurfaceMode::Highlight(tubes) = s.highlight_mode(&frame) else { panic!("not highlight lines") };
    assert_eq!((tubes.direction, tubes.spacing, tubes.count), (DVec3::Y, 0.2, analysis::DEFAULT_TUBE_COUNT));
}

#[test]
fn the_display_panel_offers_draft_and_highlight_with_their_controls() {
    let mut harness = cube_editor();
    settle(&mut harness);
    assert!(harness.query_by_label("below 3°: needs draft").is_none(), "no draft legend in zebra");

    harness.get_by_label("draft").click();
    frames(&mut harness);
    let editor = &harness.state().editor;
    assert_eq!(editor.view.display.mode, DisplayMode::Draft);
    assert_eq!(editor.surface_mode(), SurfaceMode::Draft { pull: Pull::Direction(DVec3::Z), angle_degrees: 3.0 });
    for words in ["draft ≥ 3°", "below 3°: needs draft", "draft ≤ −3°: undercut"] {
        assert!(harness.query_by_label(words).is_some(), "the legend shows {words:?}");
    }
    harness.get_by_label("negative (the other mould half)").click();
    frames(&mut harness);
    let mode = harness.state().editor.surface_mode();
    assert_eq!(mode, SurfaceMode::Draft { pull: Pull::Direction(-DVec3::Z), angle_degrees: 3.0 });
    harness.get_by_label("view").click();
    frames(&mut harness);
    assert_eq!(harness.state().editor.surface_mode(), SurfaceMode::Draft { pull: Pull::View, angle_degrees: 3.0 });
    assert!(harness.query_by_label("negative (the other mould half)").is_none(), "the view has no sign");

    harness.get_by_label("highlight").click();
    frames(&mut harness);
    assert!(harness.query_by_label("below 3°: needs draft").is_none(), "the draft legend goes");
    harness.get_by_label("y").click();
    frames(&mut harness);
    let SurfaceMode::Highlight(tubes) = harness.state().editor.surface_mode() else { panic!("not highlight lines") };
    assert_eq!(tubes.direction, DVec3::Y, "the tubes follow the y button");
    assert_eq!(tubes.count, analysis::DEFAULT_TUBE_COUNT);
}
