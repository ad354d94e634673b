//! The clipping plane as a designer uses it: switched on in the Display panel, its handle
//! dragged along its axis (Esc puts it back), and what the surface tools pick through the cut.

use super::*;
use crate::editor::defects_mode_tests::press;
use crate::editor::gizmo_tests::viewport;
use crate::editor::panel_tests::{cube_editor, frames, settle};
use crate::editor::tools::clip_plane_drag::ClipPlaneDrag;
use egui::pos2;
use egui_kittest::kittest::Queryable;
use taut_render::StandardView;

/// The cube's editor, its surface settled, seen from the front and zoomed out.
fn front_cube() -> egui_kittest::Harness<'static, crate::editor::panel_tests::App> {
    let mut h = cube_editor();
    settle(&mut h);
    h.state_mut().editor.view.camera.set_view(StandardView::Front);
    h.state_mut().editor.view.camera.distance *= 2.0;
    frames(&mut h);
    h
}

#[test]
fn the_display_panel_switches_the_plane_on_through_the_middle_of_the_surface() {
    let mut h = front_cube();
    assert!(h.state().editor.clip_plane().is_none());
    h.get_by_label("clipping plane").click();
    frames(&mut h);
    let editor = &h.state().editor;
    let clip = editor.view.display.clip.expect("on");
    let (lo, hi) = editor.surface_mesh().unwrap().bounding_box().unwrap();
    assert_eq!((clip.axis, clip.flip), (2, false), "normal to z, cutting the top away");
    assert!((clip.offset - 0.5 * (lo.z + hi.z)).abs() < 1e-12);
    // The renderer's plane in display coordinates: the surface's top vertex is cut, its bottom kept.
    let plane = editor.clip_plane().unwrap();
    let frame = editor.view.display_frame;
    let side = |p: DVec3| plane.truncate().as_dvec3().dot(frame.to_display_f64(p)) - f64::from(plane.w);
    assert!(side(hi) > 0.0 && side(lo) < 0.0);
    // Its outline is drawn over the surface: four lines more than with the plane off.
    let with = editor.overlays().on_top_lines.len();
    h.state_mut().editor.view.display.clip = None;
    let without = h.state().editor.overlays().on_top_lines.len();
    assert_eq!(with, without + 4);
    h.state_mut().editor.view.display.clip = Some(clip);
    frames(&mut h);
    h.get_by_label("flip").click();
    frames(&mut h);
    assert!(h.state().editor.view.display.clip.unwrap().flip);
    h.get_by_label("clipping plane").click();
    frames(&mut h);
    assert!(h.state().editor.clip_plane().is_none(), "off again");
}

#[test]
fn dragging_the_handle_moves_the_plane_along_its_axis_under_the_mouse_and_esc_puts_it_back() {
    let mut h = front_cube();
    let (lo, hi) = h.state().editor.surface_mesh().unwrap().bounding_box().unwrap();
    h.state_mut().editor.view.display.clip = Some(ClipSettings::through_middle(0, lo, hi));
    frames(&mut h);
    let view = viewport(&h);
    let (base, tip, _) = h.state().editor.clip_handle(&view).expect("the handle is in view");
    assert!(tip.x > base.x + 10.0, "seen from the front, the x handle points right: {base} {tip}");
    let before = h.state().editor.view.display.clip.unwrap();
    let drag = |h: &mut egui_kittest::Harness<'static, crate::editor::panel_tests::App>, to: glam::Vec2| {
        h.hover_at(pos2(tip.x, tip.y));
        frames(h);
        press(h, tip, true);
        for k in 1..=4 {
            let at = tip + (to - tip) * (k as f32 / 4.0);
            h.hover_at(pos2(at.x, at.y));
            frames(h);
        }
    };
    // 40 points right (and some up, which an x drag ignores).
    drag(&mut h, tip + glam::Vec2::new(40.0, -15.0));
    assert!(h.state().ui.tool.get::<ClipPlaneDrag>().is_some(), "the press on the handle drags the plane");
    let readout = h.state().ui.tool.readout(&h.state().editor).unwrap();
    assert!(readout.starts_with("clipping plane X = "), "{readout}");
    press(&mut h, tip + glam::Vec2::new(40.0, -15.0), false);
    assert!(h.state().ui.tool.get::<ClipPlaneDrag>().is_none(), "letting go ends the drag");
    let after = h.state().editor.view.display.clip.unwrap();
    assert_eq!((after.axis, after.flip), (before.axis, before.flip));
    // The handle's base followed the mouse: 40 points right of where it was.
    let (moved_base, _, _) = h.state().editor.clip_handle(&view).unwrap();
    assert!(
        (moved_base.x - base.x - 40.0).abs() < 0.5 && (moved_base.y - base.y).abs() < 0.5,
        "{base} -> {moved_base}"
    );
    assert!(after.offset > before.offset);
    assert_eq!(h.state().editor.document.doc(), &crate::editor::primitives::cube(), "the document is untouched");

    // Esc during a drag puts the plane back where the drag began.
    let (_, tip, _) = h.state().editor.clip_handle(&view).unwrap();
    let tip_now = tip;
    h.hover_at(pos2(tip_now.x, tip_now.y));
    frames(&mut h);
    press(&mut h, tip_now, true);
    for k in 1..=3 {
        h.hover_at(pos2(tip_now.x - 20.0 * k as f32, tip_now.y));
        frames(&mut h);
    }
    assert_ne!(h.state().editor.view.display.clip.unwrap(), after);
    h.key_press(egui::Key::Escape);
    frames(&mut h);
    press(&mut h, tip_now - glam::Vec2::new(60.0, 0.0), false);
    assert_eq!(h.state().editor.view.display.clip.unwrap(), after, "Esc puts it back");
}

#[test]
fn the_surface_is_picked_where_it_is_seen_through_the_cut() {
    let mut h = front_cube();
    let view = viewport(&h);
    let centre = view.min + 0.5 * view.size;
    let (lo, hi) = h.state().editor.surface_mesh().unwrap().bounding_box().unwrap();
    let near = h.state().editor.surface_under(&view, centre).expect("the surface is under the centre");
    assert!(near.y < 0.5 * (lo.y + hi.y), "uncut, the near side (−y, towards the front view's eye): {near}");
    // Cut away the near half (y below the middle): the far side is what is seen and picked.
    h.state_mut().editor.view.display.clip =
        Some(ClipSettings { flip: true, ..ClipSettings::through_middle(1, lo, hi) });
    let far = h.state().editor.surface_under(&view, centre).expect("the far side is seen");
    assert!(far.y > 0.5 * (lo.y + hi.y), "{far}");
}
