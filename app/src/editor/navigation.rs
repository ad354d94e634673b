//! What the mouse and the keys do the same way in every viewport and every drag: the wheel zooms,
//! a right or middle drag orbits (with Shift, pans), and while a point is being dragged X, Y or Z
//! locks the move to that axis (pressed again, unlocks) and Esc cancels. Written once here, so
//! the Surface and Curves workspaces and every drag behave alike.

use super::interaction::{self, Axis};
use super::shortcuts;
use egui::{Key, PointerButton};
use taut_render::Camera;

/// Turns the camera as the mouse asks over a viewport `height` points tall.
pub fn navigate(camera: &mut Camera, ui: &egui::Ui, response: &egui::Response, height: f32) {
    let (shift, scroll) = ui.ctx().input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y));
    if response.hovered() && scroll != 0.0 {
        camera.zoom(interaction::zoom_factor(scroll / 50.0));
    }
    for button in [PointerButton::Secondary, PointerButton::Middle] {
        if response.dragged_by(button) {
            let delta = response.drag_delta();
            if shift {
                camera.pan(delta.x, delta.y, height);
            } else {
                let (da, de) = interaction::orbit_from_drag(glam::Vec2::new(delta.x, delta.y));
                camera.orbit(da, de);
            }
        }
    }
}

/// The keys of a running drag: X, Y or Z toggles the lock to that axis in `lock` (another axis
/// replaces it); returns true when Esc asks to cancel. The keys are taken from the input, so
/// nothing else sees them.
pub fn drag_keys(ctx: &egui::Context, lock: &mut Option<Axis>) -> bool {
    let (x, y, z, escape) = ctx.input_mut(|i| {
        (
            shortcuts::take_plain(i, Key::X),
            shortcuts::take_plain(i, Key::Y),
            shortcuts::take_plain(i, Key::Z),
            shortcuts::take_plain(i, Key::Escape),
        )
    });
    for (pressed, axis) in [(x, Axis::X), (y, Axis::Y), (z, Axis::Z)] {
        if pressed {
            *lock = if *lock == Some(axis) { None } else { Some(axis) };
        }
    }
    escape
}
