//! G, R and S as in Blender: grab (move), rotate and scale the selected cage vertices about
//! their median centre. The mouse drives it (grab: in the view plane, or along a locked axis as
//! a drag does; rotate: the angle the cursor turns about the centre on screen; scale: the ratio
//! of the cursor's distances from the centre on screen); X, Y or Z locks an axis (again:
//! unlocks); typed numbers (digits, '.', '-', Backspace) give the exact distance, angle in
//! degrees or factor; Enter or a click confirms, Esc or a right click cancels. The whole
//! transform is one undo step (one gesture).
//!
//! Typed values without an axis: grab moves along X, rotate turns about Z, scale scales evenly.
//! Weak where Blender does more: no plane locks (Shift+X), no pivot other than the median
//! centre, no snapping and no on-screen gizmo yet.

use super::document::Edit;
use super::interaction::{self, Axis, ViewportRect};
use super::shortcuts;
use super::state::EditorState;
use super::ui::UiState;
use egui::Key;
use glam::DMat3;
use glam::Vec2;
use taut_core::{DVec3, VertexId};

/// Which transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TransformKind {
    Grab,
    Rotate,
    Scale,
}

/// A transform under way.
#[derive(Clone, Debug)]
pub struct Transform {
    pub kind: TransformKind,
    /// The vertices and where they were, in model coordinates.
    pub start: Vec<(VertexId, DVec3)>,
    pub centre: DVec3,
    /// The pointer when the transform began (the first position seen).
    pub mouse_start: Option<Vec2>,
    pub mouse_now: Option<Vec2>,
    pub axis: Option<Axis>,
    /// What has been typed.
    pub typed: String,
}

/// Where the vertices go for a typed `value` (a distance, degrees or a factor).
pub fn typed_positions(t: &Transform, value: f64) -> Vec<(VertexId, DVec3)> {
    let c = t.centre;
    match t.kind {
        TransformKind::Grab => {
            let offset = t.axis.unwrap_or(Axis::X).direction() * value;
            t.start.iter().map(|&(v, p)| (v, p + offset)).collect()
        }
        TransformKind::Rotate => {
            let turn = DMat3::from_axis_angle(t.axis.unwrap_or(Axis::Z).direction(), value.to_radians());
            t.start.iter().map(|&(v, p)| (v, c + turn * (p - c))).collect()
        }
        TransformKind::Scale => scaled(t, value),
    }
}

fn scaled(t: &Transform, factor: f64) -> Vec<(VertexId, DVec3)> {
    let c = t.centre;
    let k = match t.axis {
        None => DVec3::splat(factor),
        Some(a) => DVec3::ONE + (factor - 1.0) * a.direction(),
    };
    t.start.iter().map(|&(v, p)| (v, c + k * (p - c))).collect()
}

impl EditorState {
    /// Starts G, R or S on the selection; a message when nothing is selected.
    pub(super) fn start_transform(&mut self, kind: TransformKind, ui_state: &mut UiState) {
        let cage = &self.document.doc().cage;
        let start: Vec<(VertexId, DVec3)> =
            self.selected_vertices_with_edge_ends().into_iter().map(|v| (v, cage.position(v))).collect();
        if start.is_empty() {
            self.notify("select the cage vertices, edges or faces to transform first", true);
            return;
        }
        let centre = start.iter().map(|&(_, p)| p).sum::<DVec3>() / start.len() as f64;
        self.document.begin_gesture();
        ui_state.transform = Some(Transform {
            kind,
            start,
            centre,
            mouse_start: ui_state.pointer,
            mouse_now: ui_state.pointer,
            axis: None,
            typed: String::new(),
        });
    }

    /// The keys while transforming: axis locks, typed numbers, Enter and Esc. Nothing else runs.
    pub(super) fn transform_keys(&mut self, ctx: &egui::Context, ui_state: &mut UiState) {
        let Some(t) = &mut ui_state.transform else { return };
        let mut finish = None;
        ctx.input_mut(|i| {
            for (key, axis) in [(Key::X, Axis::X), (Key::Y, Axis::Y), (Key::Z, Axis::Z)] {
                if shortcuts::take_plain(i, key) {
                    t.axis = if t.axis == Some(axis) { None } else { Some(axis) };
                }
            }
            let digits = [
                (Key::Num0, '0'),
                (Key::Num1, '1'),
                (Key::Num2, '2'),
                (Key::Num3, '3'),
                (Key::Num4, '4'),
                (Key::Num5, '5'),
                (Key::Num6, '6'),
                (Key::Num7, '7'),
                (Key::Num8, '8'),
                (Key::Num9, '9'),
                (Key::Period, '.'),
                (Key::Minus, '-'),
            ];
            for (key, c) in digits {
                if shortcuts::take_plain(i, key) {
                    t.typed.push(c);
                }
            }
            if shortcuts::take_plain(i, Key::Backspace) {
                t.typed.pop();
            }
            if shortcuts::take_plain(i, Key::Enter) {
                finish = Some(true);
            } else if shortcuts::take_plain(i, Key::Escape) {
                finish = Some(false);
            }
            // Typed characters arrive as text too: drop them so no widget sees them.
            i.events.retain(|e| !matches!(e, egui::Event::Text(_)));
        });
        self.update_transform(None, ui_state);
        if let Some(keep) = finish {
            self.finish_transform(keep, ui_state);
        }
    }

    /// Moves the vertices where the typed value or the mouse says.
    pub(super) fn update_transform(&mut self, view: Option<&ViewportRect>, ui_state: &mut UiState) {
        let Some(t) = &ui_state.transform else { return };
        let moved = if let Ok(value) = t.typed.parse::<f64>() {
            if !value.is_finite() {
                return;
            }
            typed_positions(t, value)
        } else {
            let (Some(view), Some(from), Some(to)) = (view, t.mouse_start, t.mouse_now) else { return };
            self.mouse_positions(t, view, from, to)
        };
        self.edit(Edit::MoveVertices(moved));
    }

    fn mouse_positions(&self, t: &Transform, view: &ViewportRect, from: Vec2, to: Vec2) -> Vec<(VertexId, DVec3)> {
        let frame = self.display_frame;
        match t.kind {
            TransformKind::Grab => {
                let start: Vec<(VertexId, DVec3)> =
                    t.start.iter().map(|&(v, p)| (v, frame.to_display_f64(p))).collect();
                interaction::drag_positions(&self.camera, view, &start, from, to, t.axis)
                    .into_iter()
                    .map(|(v, p)| (v, frame.to_model(p)))
                    .collect()
            }
            TransformKind::Rotate | TransformKind::Scale => {
                let Some((c, _)) = interaction::project(&self.camera, view, frame.to_display_f64(t.centre)) else {
                    return t.start.clone();
                };
                let (a, b) = (from - c, to - c);
                if a.length() < 1.0 || b.length() < 1.0 {
                    return t.start.clone();
                }
                if t.kind == TransformKind::Scale {
                    scaled(t, f64::from(b.length() / a.length()))
                } else {
                    // Screen y runs down: a counter-clockwise turn on screen is a negative perp.
                    let degrees = f64::from(-a.perp_dot(b).atan2(a.dot(b))).to_degrees();
                    typed_positions(t, degrees)
                }
            }
        }
    }

    /// Ends the transform: keeps it (one undo step) or puts every vertex back.
    pub(super) fn finish_transform(&mut self, keep: bool, ui_state: &mut UiState) {
        let Some(t) = ui_state.transform.take() else { return };
        if !keep {
            self.edit(Edit::MoveVertices(t.start));
        }
        self.document.end_gesture();
    }

    /// The viewport while transforming: the mouse drives it, a click confirms, a right click
    /// cancels, and a line of text says what is happening.
    pub(super) fn transform_viewport(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        view: &ViewportRect,
        mouse: Option<Vec2>,
        ui_state: &mut UiState,
    ) {
        if let (Some(t), Some(m)) = (&mut ui_state.transform, mouse) {
            t.mouse_start.get_or_insert(m);
            if t.mouse_now != Some(m) {
                t.mouse_now = Some(m);
                self.update_transform(Some(view), ui_state);
            }
        }
        if response.clicked_by(egui::PointerButton::Primary) {
            self.finish_transform(true, ui_state);
        } else if response.clicked_by(egui::PointerButton::Secondary) {
            self.finish_transform(false, ui_state);
        }
        if let Some(t) = &ui_state.transform {
            let what = match t.kind {
                TransformKind::Grab => "move",
                TransformKind::Rotate => "rotate (degrees)",
                TransformKind::Scale => "scale",
            };
            let axis = t.axis.map_or("free".to_string(), |a| format!("along {a:?}"));
            let typed = if t.typed.is_empty() { String::new() } else { format!(" {}", t.typed) };
            ui.painter().text(
                response.rect.left_top() + egui::vec2(8.0, 8.0),
                egui::Align2::LEFT_TOP,
                format!("{what} {axis}{typed}: X, Y, Z lock an axis, type a value, Enter or click sets, Esc cancels"),
                egui::FontId::proportional(14.0),
                egui::Color32::WHITE,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::panel_tests::{cube_editor, frames};
    use egui::Modifiers;

    #[test]
    fn g_x_one_enter_moves_the_selection_by_exactly_one_along_x_in_one_undo_step() {
        let mut h = cube_editor();
        let before = h.state().editor.document.doc().clone();
        let v = taut_core::VertexId(7);
        let p = before.cage.position(v);
        for key in [Key::G, Key::X, Key::Num1, Key::Enter] {
            h.key_press(key);
            frames(&mut h);
        }
        let doc = h.state().editor.document.doc().clone();
        assert_eq!(doc.cage.position(v), p + DVec3::X, "exactly 1 along x");
        assert!(doc.cage.vertices().filter(|&w| w != v).all(|w| doc.cage.position(w) == before.cage.position(w)));
        h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        frames(&mut h);
        assert_eq!(h.state().editor.document.doc(), &before, "one undo step");
    }

    #[test]
    fn typed_rotations_and_scales_match_their_closed_forms_and_esc_cancels() {
        let mut h = cube_editor();
        // The top face: centre (0, 0, 0.5).
        let top: Vec<VertexId> =
            (0..8).map(VertexId).filter(|&v| h.state().editor.document.doc().cage.position(v).z > 0.0).collect();
        h.state_mut().editor.selection.vertices = top.clone();
        let before = h.state().editor.document.doc().clone();
        for key in [Key::R, Key::Z, Key::Num9, Key::Num0, Key::Enter] {
            h.key_press(key);
            frames(&mut h);
        }
        let cage = &h.state().editor.document.doc().cage;
        for &v in &top {
            let (p, q) = (before.cage.position(v), cage.position(v));
            // A quarter turn about z through the centre: (x, y) -> (-y, x).
            assert!((q - DVec3::new(-p.y, p.x, p.z)).length() < 1e-12, "{p} -> {q}");
        }
        for key in [Key::S, Key::Num2, Key::Escape] {
            h.key_press(key);
            frames(&mut h);
        }
        let after_rotation = h.state().editor.document.doc().clone();
        h.key_press(Key::S);
        frames(&mut h);
        for key in [Key::Num2, Key::Enter] {
            h.key_press(key);
            frames(&mut h);
        }
        let cage = &h.state().editor.document.doc().cage;
        for &v in &top {
            let (p, q) = (after_rotation.cage.position(v), cage.position(v));
            let c = DVec3::new(0.0, 0.0, 0.5);
            assert!((q - (c + 2.0 * (p - c))).length() < 1e-12, "scaled twice about the centre");
        }
        // Esc put everything back before the second S: the undo history holds R and S only.
        h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        frames(&mut h);
        assert_eq!(h.state().editor.document.doc(), &after_rotation);
    }
}
