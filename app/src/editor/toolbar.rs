//! The transform toolbar above the viewport of the Surface workspace: the gizmo toggle (W) and
//! which handles it shows, the pivot (Shift+S cycles it), and snapping: the toggle (Ctrl held
//! while transforming inverts it), the grid step (following the view, shown, or fixed) and the
//! rotation and scale increments. These are editor settings, not saved in the document.

use super::gizmo::GizmoMode;
use super::pivot::Pivot;
use super::snapping;
use super::state::EditorState;

impl EditorState {
    /// The toolbar's row.
    pub(super) fn transform_toolbar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.checkbox(&mut self.gizmo.shown, "Gizmo (W)")
                .on_hover_text("Show the transform gizmo at the pivot of the selection (W)");
            egui::ComboBox::from_label("handles")
                .selected_text(self.gizmo.mode.name())
                .show_ui(ui, |ui| {
                    for mode in GizmoMode::ALL {
                        ui.selectable_value(&mut self.gizmo.mode, mode, mode.name());
                    }
                })
                .response
                .on_hover_text("Which handles the gizmo shows: arrows and planes, rings, scale cubes, or all");
            ui.separator();
            egui::ComboBox::from_label("pivot (Shift+S)")
                .selected_text(self.gizmo.pivot.name())
                .show_ui(ui, |ui| {
                    for pivot in Pivot::ALL {
                        ui.selectable_value(&mut self.gizmo.pivot, pivot, pivot.name());
                    }
                })
                .response
                .on_hover_text("What rotate and scale turn about; Shift+right-click places the 3D cursor");
            ui.separator();
            let view_step = snapping::view_grid_step(&self.camera, &self.display_frame);
            let snap = &mut self.gizmo.snap;
            ui.checkbox(&mut snap.always, "Snap (Ctrl inverts)")
                .on_hover_text("Moves land on grid steps, rotations on the angle step, scales on the scale step");
            let mut fixed = snap.fixed_step.is_some();
            if ui
                .checkbox(&mut fixed, "manual grid")
                .on_hover_text("Keep the grid step fixed instead of following the zoom")
                .changed()
            {
                snap.fixed_step = fixed.then_some(view_step);
            }
            match &mut snap.fixed_step {
                Some(step) => {
                    let label = ui.label("grid step");
                    ui.add(egui::DragValue::new(step).speed(0.01).range(1e-9..=1e9))
                        .labelled_by(label.id)
                        .on_hover_text("The grid step of a snapped move, in model units");
                }
                None => {
                    ui.label(format!("grid step {view_step} (follows the zoom)"));
                }
            }
            let label = ui.label("rotate step °");
            ui.add(egui::DragValue::new(&mut snap.degrees).speed(0.5).range(0.01..=180.0))
                .labelled_by(label.id)
                .on_hover_text("The angle step of a snapped rotation, in degrees");
            let label = ui.label("scale step");
            ui.add(egui::DragValue::new(&mut snap.scale).speed(0.01).range(1e-6..=10.0))
                .labelled_by(label.id)
                .on_hover_text("The factor step of a snapped scale");
        });
    }

    /// W: shows or hides the gizmo.
    pub(super) fn toggle_gizmo(&mut self) {
        self.gizmo.shown = !self.gizmo.shown;
        self.notify(if self.gizmo.shown { "gizmo shown (W hides it)" } else { "gizmo hidden (W shows it)" }, false);
    }

    /// Shift+S: the next pivot.
    pub(super) fn cycle_pivot(&mut self) {
        self.gizmo.pivot = self.gizmo.pivot.next();
        self.notify(format!("pivot: {} (Shift+S for the next)", self.gizmo.pivot.name()), false);
    }
}
