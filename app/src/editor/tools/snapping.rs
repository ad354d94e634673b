//! Snapping while transforming, as Blender's increment snap: with the toolbar's snap toggle on,
//! or while Ctrl is held (Ctrl inverts the toggle), a move lands on whole multiples of a grid
//! step, a rotation on multiples of 5° and a scale on multiples of 0.1. The grid step follows the
//! view's scale: the power of ten nearest to a tenth of the height the view shows at the camera's
//! target, so about ten grid steps span the viewport whatever the zoom. It can be fixed instead.
//!
//! The offset of a move is snapped component by component in world axes (an axis-locked move
//! along its axis, a move along a custom direction along it), so the moved points land on the
//! step's multiples relative to where they began: Blender's "increment" snap. With "absolute
//! grid" on (the steps menu), a move instead puts the selection's centre on the grid itself, the
//! multiples of the step in model coordinates, in every component the move is free in (a locked
//! axis or plane keeps its coordinate; a move along a custom direction, such as extrude's
//! normal, stays an increment snap): Blender's "absolute grid" snap. Typed values are never
//! snapped.

use glam::DVec3;
use taut_render::{Camera, DisplayFrame};

/// The snap settings of the toolbar.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapSettings {
    /// Snap without holding Ctrl (Ctrl then turns it off).
    pub always: bool,
    /// A fixed grid step in model units; `None` follows the view.
    pub fixed_step: Option<f64>,
    /// Rotation increment in degrees.
    pub degrees: f64,
    /// Scale increment.
    pub scale: f64,
    /// Moves put the selection's centre on the grid instead of moving by whole steps.
    pub absolute: bool,
    /// What a snapped move lands on: grid steps, or geometry ([`crate::editor::tools::snap_targets`]).
    pub target: crate::editor::tools::snap_targets::SnapTarget,
}

impl Default for SnapSettings {
    fn default() -> Self {
        SnapSettings {
            always: false,
            fixed_step: None,
            degrees: 5.0,
            scale: 0.1,
            absolute: false,
            target: Default::default(),
        }
    }
}

impl SnapSettings {
    /// Whether a transform snaps now, with Ctrl held or not.
    pub fn active(&self, ctrl: bool) -> bool {
        self.always != ctrl
    }

    /// The grid step of a move, in model units: the fixed one or the one the view asks for.
    pub fn grid_step(&self, camera: &Camera, frame: &DisplayFrame) -> f64 {
        match self.fixed_step {
            Some(step) if step.is_finite() && step > 0.0 => step,
            _ => view_grid_step(camera, frame),
        }
    }
}

/// The view's grid step in model units: the power of ten nearest (in ratio) to a tenth of the
/// height seen at the camera's target (the camera lives in display units, `frame.scale` model
/// units each).
pub fn view_grid_step(camera: &Camera, frame: &DisplayFrame) -> f64 {
    let height = 2.0 * f64::from(camera.distance) * (f64::from(camera.fov_y).to_radians() * 0.5).tan() * frame.scale;
    let tenth = height / 10.0;
    if !(tenth.is_finite() && tenth > 0.0) {
        return 1.0;
    }
    10f64.powi(tenth.log10().round() as i32)
}

/// `x` rounded to the nearest multiple of `step` (unchanged for a step that is not positive).
pub fn to_multiple(x: f64, step: f64) -> f64 {
    if step > 0.0 && step.is_finite() { (x / step).round() * step } else { x }
}

/// A move's offset snapped to multiples of `step` in every world component.
pub fn snap_offset(offset: DVec3, step: f64) -> DVec3 {
    DVec3::new(to_multiple(offset.x, step), to_multiple(offset.y, step), to_multiple(offset.z, step))
}

/// The offset that puts `centre + offset` on the multiples of `step` in every component the
/// move changes (a component the offset leaves exactly zero is locked and stays).
pub fn snap_to_grid(centre: DVec3, offset: DVec3, step: f64) -> DVec3 {
    DVec3::from_array(std::array::from_fn(|k| {
        if offset[k] == 0.0 { 0.0 } else { to_multiple(centre[k] + offset[k], step) - centre[k] }
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_step_is_a_power_of_ten_near_a_tenth_of_the_view() {
        let mut camera = Camera::default();
        let frame = DisplayFrame { origin: DVec3::ZERO, scale: 4.4 };
        for distance in [0.01f32, 0.3, 1.0, 5.0, 42.0, 1e4] {
            camera.distance = distance;
            let step = view_grid_step(&camera, &frame);
            let height = 4.4 * 2.0 * f64::from(distance) * (f64::from(camera.fov_y).to_radians() / 2.0).tan();
            assert!((step.log10() - step.log10().round()).abs() < 1e-12, "{step} is a power of ten");
            // Within a factor √10 of a tenth of the height.
            let ratio = step / (height / 10.0);
            assert!((1.0 / 10f64.sqrt()..=10f64.sqrt()).contains(&ratio), "{distance}: {step} for {height}");
        }
    }

    #[test]
    fn snapped_offsets_are_multiples_of_the_step_and_ctrl_inverts_the_toggle() {
        let o = snap_offset(DVec3::new(0.26, -0.74, 0.0), 0.25);
        assert_eq!(o, DVec3::new(0.25, -0.75, 0.0));
        assert_eq!(to_multiple(7.4, 5.0), 5.0);
        assert_eq!(to_multiple(7.6, 5.0), 10.0);
        assert_eq!(to_multiple(3.0, 0.0), 3.0);
        let s = SnapSettings::default();
        assert!(!s.active(false) && s.active(true));
        let s = SnapSettings { always: true, ..s };
        assert!(s.active(false) && !s.active(true));
        let frame = DisplayFrame { origin: DVec3::ZERO, scale: 2.0 };
        let camera = Camera::default();
        assert_eq!(s.grid_step(&camera, &frame), view_grid_step(&camera, &frame));
        let fixed = SnapSettings { fixed_step: Some(0.5), ..s };
        assert_eq!(fixed.grid_step(&camera, &frame), 0.5);
    }
}
