//! The navigation triad in the viewport's bottom-left corner, as Blender's: the world axes as
//! the camera sees them (X red, Y green, Z blue; the negative ends as faint balls). A click on an
//! axis's end looks along it (X: the right view, −X: the left, Y: the back, −Y: the front, Z:
//! the top, −Z: the bottom); a left drag on the triad orbits the camera, and Esc puts the view
//! back as it was. The triad is drawn by egui over the viewport, so it is on top of everything.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool, escape};
use egui::{Color32, Pos2, Stroke};
use glam::Vec2;
use taut_render::{Camera, StandardView};

/// The triad's radius and its margin from the viewport's corner, in points.
pub const TRIAD_RADIUS: f32 = 40.0;
const MARGIN: f32 = 14.0;
/// How near an axis's end a click must land, in points.
const END_RADIUS: f32 = 9.0;

const AXES: [(glam::Vec3, &str, [u8; 3], StandardView, StandardView); 3] = [
    (glam::Vec3::X, "X", [230, 70, 80], StandardView::Right, StandardView::Left),
    (glam::Vec3::Y, "Y", [120, 200, 60], StandardView::Back, StandardView::Front),
    (glam::Vec3::Z, "Z", [70, 140, 240], StandardView::Top, StandardView::Bottom),
];

/// The triad's centre in a viewport.
pub fn centre(view: &ViewportRect) -> Vec2 {
    Vec2::new(view.min.x + MARGIN + TRIAD_RADIUS, view.min.y + view.size.y - MARGIN - TRIAD_RADIUS)
}

/// Every axis end on screen: where it is, its depth towards the viewer (larger: nearer), its
/// label, colour, and the view a click on it gives.
fn ends(camera: &Camera, view: &ViewportRect) -> Vec<(Vec2, f32, &'static str, Color32, StandardView, bool)> {
    let c = centre(view);
    let (right, up, back) = (camera.right(), camera.up(), camera.backward());
    let mut out = Vec::new();
    for (d, name, [r, g, b], positive, negative) in AXES {
        for (sign, view_of, is_positive) in [(1.0, positive, true), (-1.0, negative, false)] {
            let w = d * sign;
            let screen = c + Vec2::new(w.dot(right), -w.dot(up)) * TRIAD_RADIUS;
            out.push((screen, w.dot(back), name, Color32::from_rgb(r, g, b), view_of, is_positive));
        }
    }
    out
}

/// The view a click at `mouse` asks for: the nearest axis end within reach (the one in front
/// when two overlap).
pub fn pick(camera: &Camera, view: &ViewportRect, mouse: Vec2) -> Option<StandardView> {
    ends(camera, view)
        .into_iter()
        .filter(|e| e.0.distance(mouse) <= END_RADIUS)
        .min_by(|a, b| (a.0.distance(mouse) - a.1).total_cmp(&(b.0.distance(mouse) - b.1)))
        .map(|e| e.4)
}

/// Where the end that gives `standard` is drawn.
#[cfg(test)]
pub fn end_of(camera: &Camera, view: &ViewportRect, standard: StandardView) -> Option<Vec2> {
    ends(camera, view).into_iter().find(|e| e.4 == standard).map(|e| e.0)
}

/// Whether `mouse` is over the triad.
pub fn contains(view: &ViewportRect, mouse: Vec2) -> bool {
    mouse.distance(centre(view)) <= TRIAD_RADIUS + END_RADIUS
}

/// The projection's name above the triad ("Persp" or "Ortho"), which a click toggles as numpad 5
/// does (Blender's navigation gizmo has the same switch).
pub fn projection_button(view: &ViewportRect) -> egui::Rect {
    let c = centre(view);
    let top = c.y - TRIAD_RADIUS - END_RADIUS - 4.0;
    egui::Rect::from_min_max(Pos2::new(c.x - 22.0, top - 16.0), Pos2::new(c.x + 22.0, top))
}

/// Whether `mouse` is over [`projection_button`].
pub fn over_projection_button(view: &ViewportRect, mouse: Vec2) -> bool {
    projection_button(view).contains(Pos2::new(mouse.x, mouse.y))
}

/// Draws the triad, the far ends first, and the projection's name above it.
pub fn draw(painter: &egui::Painter, camera: &Camera, view: &ViewportRect, hovered: bool, mouse: Option<Vec2>) {
    let c = centre(view);
    let pos = |p: Vec2| Pos2::new(p.x, p.y);
    let button = projection_button(view);
    let over_button = mouse.is_some_and(|m| over_projection_button(view, m));
    painter.rect_filled(button, 4.0, Color32::from_white_alpha(if over_button { 40 } else { 14 }));
    let name = if camera.orthographic { "Ortho" } else { "Persp" };
    painter.text(
        button.center(),
        egui::Align2::CENTER_CENTER,
        name,
        egui::FontId::proportional(11.0),
        Color32::LIGHT_GRAY,
    );
    let ring = if hovered { Color32::from_white_alpha(40) } else { Color32::from_white_alpha(14) };
    painter.circle_filled(pos(c), TRIAD_RADIUS + END_RADIUS, ring);
    let mut ends = ends(camera, view);
    ends.sort_by(|a, b| a.1.total_cmp(&b.1));
    for (p, _, name, colour, _, positive) in ends {
        if positive {
            painter.line_segment([pos(c), pos(p)], Stroke::new(2.0, colour));
            painter.circle_filled(pos(p), 7.0, colour);
            painter.text(pos(p), egui::Align2::CENTER_CENTER, name, egui::FontId::proportional(11.0), Color32::BLACK);
        } else {
            painter.circle_filled(pos(p), 6.0, colour.gamma_multiply(0.35));
            painter.circle_stroke(pos(p), 6.0, Stroke::new(1.0, colour));
        }
    }
}

/// A left drag that began on the triad: the camera orbits with it.
#[derive(Clone, Debug)]
pub struct TriadOrbit {
    /// The camera when the drag began (Esc puts it back).
    before: Camera,
}

/// Starts orbiting from the triad.
pub(crate) fn start_orbit(editor: &EditorState) -> Box<dyn Tool> {
    Box::new(TriadOrbit { before: editor.view.camera })
}

impl Tool for TriadOrbit {
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        escape(ctx)
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged() {
            let delta = pointer.response.drag_delta();
            let (da, de) = interaction::orbit_from_drag(Vec2::new(delta.x, delta.y));
            editor.view.camera.orbit(da, de);
        }
        pointer.release()
    }

    fn status(&self, _editor: &EditorState) -> String {
        "orbiting from the triad: let go to keep the view, Esc puts it back".into()
    }

    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            editor.view.camera = self.before;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::defects_mode_tests::{click, press};
    use crate::editor::gizmo_tests::viewport;
    use crate::editor::panel_tests::{cube_editor, frames, settle};
    use egui::pos2;

    #[test]
    fn a_click_on_an_axis_end_looks_along_it_and_a_drag_orbits_until_esc() {
        let mut h = cube_editor();
        // A new document is framed again while its surface settles: click once it has.
        settle(&mut h);
        frames(&mut h);
        let view = viewport(&h);
        for (standard, (azimuth, elevation)) in
            [(StandardView::Top, (0.0, 90.0)), (StandardView::Right, (90.0, 0.0)), (StandardView::Front, (0.0, 0.0))]
        {
            let at = end_of(&h.state().editor.view.camera, &view, standard).unwrap();
            let before = h.state().editor.view.camera;
            click(&mut h, at);
            let camera = h.state().editor.view.camera;
            assert_eq!((camera.azimuth, camera.elevation), (azimuth, elevation), "{standard:?}");
            assert_eq!((camera.target, camera.distance), (before.target, before.distance), "only the direction turns");
            assert_eq!(h.state().editor.document.doc(), &crate::editor::primitives::cube(), "nothing else happens");
        }
        // A drag from the triad's centre orbits; Esc puts the view back.
        let before = h.state().editor.view.camera;
        let c = centre(&view);
        h.hover_at(pos2(c.x, c.y));
        frames(&mut h);
        press(&mut h, c, true);
        for k in 1..=4 {
            h.hover_at(pos2(c.x + 12.0 * k as f32, c.y));
            frames(&mut h);
        }
        assert!(h.state().editor.view.camera.azimuth != before.azimuth, "the drag orbits");
        assert!(h.state().ui.tool.get::<TriadOrbit>().is_some());
        h.key_press(egui::Key::Escape);
        frames(&mut h);
        press(&mut h, c + Vec2::new(48.0, 0.0), false);
        assert_eq!(h.state().editor.view.camera, before, "Esc puts the view back");
        assert!(h.state().editor.view.selection.vertices == vec![taut_core::VertexId(7)], "the selection is untouched");
    }

    #[test]
    fn five_and_the_button_over_the_triad_switch_between_perspective_and_orthographic() {
        let mut h = cube_editor();
        settle(&mut h);
        frames(&mut h);
        let view = viewport(&h);
        let before = h.state().editor.view.camera;
        assert!(!before.orthographic, "a new document opens in perspective");
        h.key_press(egui::Key::Num5);
        frames(&mut h);
        let camera = h.state().editor.view.camera;
        assert!(camera.orthographic, "5 switches to orthographic");
        assert_eq!(Camera { orthographic: false, ..camera }, before, "and changes nothing else");
        // What lies at the target stays under the same pixel.
        let target = camera.target.as_dvec3();
        let persp = interaction::project(&before, &view, target).unwrap().0;
        let ortho = interaction::project(&camera, &view, target).unwrap().0;
        assert!(persp.distance(ortho) < 1e-3);
        let button = projection_button(&view).center();
        click(&mut h, Vec2::new(button.x, button.y));
        assert!(!h.state().editor.view.camera.orthographic, "the button over the triad switches back");
        assert_eq!(h.state().editor.view.selection.vertices, vec![taut_core::VertexId(7)], "the click selects nothing");
        // Shift+5 is not a shortcut: the projection stays.
        h.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::Num5);
        frames(&mut h);
        assert!(!h.state().editor.view.camera.orthographic);
    }

    #[test]
    fn a_new_document_opens_in_the_three_quarter_view_whatever_the_last_one_showed() {
        let mut h = cube_editor();
        h.state_mut().editor.view.camera.set_view(StandardView::Bottom);
        let fresh = crate::editor::document::EditorDocument::new(crate::editor::primitives::prism(5), None);
        h.state_mut().editor.replace_document(fresh);
        frames(&mut h);
        let camera = h.state().editor.view.camera;
        assert_eq!((camera.azimuth, camera.elevation), (30.0, 25.0), "from the front, right and above");
    }
}
