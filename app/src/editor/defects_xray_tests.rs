//! The back of the cage is not picked unseen: with X-ray off (the default) a click, a box or an
//! edge pick lands only on what the cage's front leaves in view, and the hidden parts are drawn
//! dimmer; Alt+Z (or View ▸ X-ray) turns X-ray on, and then the back is picked and drawn alike.

use super::defects_mode_tests::click;
use super::gizmo_tests::{drag_along, pixel_of, viewport};
use super::panel_tests::{App, cube_editor, frames};
use super::select_modes::SelectMode;
use egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use taut_core::{DVec3, EdgeId, VertexId};
use taut_render::StandardView;

/// A cube editor in the perspective view, nothing selected, and the corner its front hides.
fn cube_from_above() -> (Harness<'static, App>, VertexId) {
    let mut h = cube_editor();
    h.state_mut().editor.view.camera.set_view(StandardView::Perspective);
    h.state_mut().editor.view.selection.clear();
    // Settled, so that the display frame (which follows the surface) stays put.
    for _ in 0..400 {
        if !h.state().editor.busy() {
            break;
        }
        frames(&mut h);
    }
    frames(&mut h);
    let seen = h.state().editor.cage_seen().expect("X-ray is off in a new editor");
    let hidden: Vec<VertexId> =
        (0..seen.vertices.len()).filter(|&i| !seen.vertices[i]).map(|i| VertexId(i as u32)).collect();
    // Seen from off every axis, a cube shows seven corners and hides the eighth.
    assert_eq!(hidden.len(), 1, "{:?}", seen.vertices);
    // The hidden corner is the one farthest from the eye.
    let editor = &h.state().editor;
    let cage = &editor.document.doc().cage;
    let eye = editor.view.display_frame.to_model(editor.view.camera.eye().as_dvec3());
    let far = cage
        .vertices()
        .max_by(|&a, &b| (cage.position(a) - eye).length().total_cmp(&(cage.position(b) - eye).length()));
    assert_eq!(far, Some(hidden[0]));
    (h, hidden[0])
}

fn alt_z(h: &mut Harness<'_, App>) {
    h.key_press_modifiers(Modifiers::ALT, Key::Z);
    frames(h);
}

#[test]
fn a_click_on_the_hidden_corner_selects_it_only_with_x_ray() {
    let (mut h, far) = cube_from_above();
    // Where the corner is drawn now (the display frame follows the surface as it settles).
    let at = |h: &Harness<'_, App>| pixel_of(h, h.state().editor.document.doc().cage.position(far));
    let p = at(&h);
    click(&mut h, p);
    assert!(!h.state().editor.view.selection.vertices.contains(&far), "a hidden corner is not picked");
    let notice = h.state().editor.notice.clone().expect("the click says why nothing was picked");
    assert!(notice.text.contains("behind the cage's front") && notice.text.contains("Alt+Z"), "{}", notice.text);
    assert!(!h.state().editor.overlays().points.is_empty());

    alt_z(&mut h);
    assert!(h.state().editor.view.display.xray, "Alt+Z turns X-ray on");
    h.get_by_label("X-ray");
    let p = at(&h);
    click(&mut h, p);
    assert_eq!(h.state().editor.view.selection.vertices, vec![far], "with X-ray the corner behind is picked");

    alt_z(&mut h);
    assert!(!h.state().editor.view.display.xray, "Alt+Z again turns it off");
    h.state_mut().editor.view.selection.clear();
    let p = at(&h);
    click(&mut h, p);
    assert!(!h.state().editor.view.selection.vertices.contains(&far));
}

#[test]
fn a_box_over_the_whole_cube_catches_only_the_corners_in_view_unless_x_ray() {
    let (mut h, far) = cube_from_above();
    let v = viewport(&h);
    let (from, to) = (v.min + glam::Vec2::splat(4.0), v.min + v.size - glam::Vec2::splat(4.0));
    drag_along(&mut h, &[from, (from + to) / 2.0, to]);
    let mut caught = h.state().editor.view.selection.vertices.clone();
    caught.sort();
    let expected: Vec<VertexId> = (0..8).map(VertexId).filter(|&v| v != far).collect();
    assert_eq!(caught, expected, "the box leaves out the corner behind");

    h.state_mut().editor.view.selection.clear();
    alt_z(&mut h);
    drag_along(&mut h, &[from, (from + to) / 2.0, to]);
    assert_eq!(h.state().editor.view.selection.vertices.len(), 8, "with X-ray the box catches every corner");
}

#[test]
fn a_hidden_edge_is_not_picked_for_a_crease_and_is_drawn_dimmer() {
    let (mut h, far) = cube_from_above();
    h.state_mut().editor.view.selection.mode = SelectMode::Edge;
    frames(&mut h);
    let cage = h.state().editor.document.doc().cage.clone();
    let edges: Vec<EdgeId> = cage
        .edges()
        .filter(|&e| {
            let (a, b) = cage.edge_vertices(e);
            a == far || b == far
        })
        .collect();
    assert_eq!(edges.len(), 3);
    let seen = h.state().editor.cage_seen().unwrap();
    assert!(edges.iter().all(|&e| !seen.edge(e)), "the three edges at the hidden corner are hidden");
    assert_eq!(seen.edges.iter().filter(|&&s| s).count(), 9);

    // A point a third of the way along a hidden edge from the hidden corner: no seen edge passes
    // within the pick radius there on this view (checked), so a click must select nothing.
    let (a, b) = cage.edge_vertices(edges[0]);
    let at = |h: &Harness<'_, App>| {
        let (pa, pb) = (pixel_of(h, cage.position(a)), pixel_of(h, cage.position(b)));
        let (near, other) = if a == far { (pa, pb) } else { (pb, pa) };
        near + (other - near) / 3.0
    };
    let p = at(&h);
    click(&mut h, p);
    assert!(h.state().editor.view.selection.edges.is_empty(), "{:?}", h.state().editor.view.selection.edges);

    // The overlay draws the hidden edges first and faint, the rest at full strength.
    let lines = h.state().editor.overlays().on_top_lines;
    let faint = lines.iter().filter(|l| l.color[3] < 0.5).count();
    assert_eq!(faint, 3);
    assert!(lines[..3].iter().all(|l| l.color[3] < 0.5) && lines[3..].iter().all(|l| l.color[3] >= 0.5));

    alt_z(&mut h);
    let p = at(&h);
    click(&mut h, p);
    assert_eq!(h.state().editor.view.selection.edges, vec![edges[0]], "with X-ray the hidden edge is picked");
    let lines = h.state().editor.overlays().on_top_lines;
    assert!(lines.iter().all(|l| l.color[3] >= 0.5), "with X-ray nothing is dimmed");
}

#[test]
fn the_menus_and_help_name_alt_z_and_hidden_parts_follow_the_camera() {
    let (mut h, far) = cube_from_above();
    assert_eq!(super::shortcuts::label(super::shortcuts::Action::ToggleXray), "Alt+Z");
    // Seen from the other side, the far corner comes into view and its opposite is hidden.
    let opposite = {
        let cage = &h.state().editor.document.doc().cage;
        let p = cage.position(far);
        let centre = cage.vertices().map(|v| cage.position(v)).sum::<DVec3>() / 8.0;
        cage.vertices()
            .max_by(|&a, &b| (cage.position(a) - p).length().total_cmp(&(cage.position(b) - p).length()))
            .filter(|&v| (cage.position(v) - centre).dot(p - centre) < 0.0)
            .unwrap()
    };
    let camera = &mut h.state_mut().editor.view.camera;
    camera.orbit(180.0, 0.0);
    camera.elevation = -camera.elevation;
    frames(&mut h);
    let seen = h.state().editor.cage_seen().unwrap();
    assert!(seen.vertex(far), "the corner now in front is seen");
    assert!(!seen.vertex(opposite), "the corner now behind is hidden");
}
