//! The transform toolbar, at the right of the menu bar in the Surface workspace (so the
//! viewport keeps its place): the gizmo toggle (W) and which handles it shows, the pivot
//! (Shift+S cycles it), and snapping: the toggle (Ctrl held while transforming inverts it) and
//! a menu of its steps (the grid step following the zoom, shown, or set by hand; the rotation
//! and scale increments). These are editor settings, not saved in the document.

use crate::editor::gizmo::GizmoMode;
use crate::editor::pivot::Pivot;
use crate::editor::snapping;
use crate::editor::state::EditorState;

impl EditorState {
    /// The toolbar's controls, laid out in the menu bar's row.
    pub(crate) fn transform_toolbar(&mut self, ui: &mut egui::Ui) {
        ui.separator();
        ui.checkbox(&mut self.gizmo.shown, "Gizmo (W)")
            .on_hover_text("Show the transform gizmo at the pivot of the selection (W)");
        egui::ComboBox::from_label("handles")
            .width(70.0)
            .selected_text(self.gizmo.mode.name())
            .show_ui(ui, |ui| {
                for mode in GizmoMode::ALL {
                    ui.selectable_value(&mut self.gizmo.mode, mode, mode.name());
                }
            })
            .response
            .on_hover_text("Which handles the gizmo shows: arrows and planes, rings, scale cubes, or all");
        egui::ComboBox::from_label("pivot (Shift+S)")
            .width(100.0)
            .selected_text(self.gizmo.pivot.name())
            .show_ui(ui, |ui| {
                for pivot in Pivot::ALL {
                    ui.selectable_value(&mut self.gizmo.pivot, pivot, pivot.name());
                }
            })
            .response
            .on_hover_text("What rotate and scale turn about; Shift+right-click places the 3D cursor");
        let view_step = snapping::view_grid_step(&self.view.camera, &self.view.display_frame);
        let snap = &mut self.gizmo.snap;
        ui.checkbox(&mut snap.always, "Snap (Ctrl inverts)")
            .on_hover_text("Moves land on grid steps, rotations on the angle step, scales on the scale step");
        let grid = snap.fixed_step.unwrap_or(view_step);
        ui.menu_button(format!("steps: {grid}, {}°, {}", snap.degrees, snap.scale), |ui| {
            let mut fixed = snap.fixed_step.is_some();
            if ui
                .checkbox(&mut fixed, "grid step set by hand")
                .on_hover_text("Keep the grid step instead of following the zoom")
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
            egui::ComboBox::from_label("snap to")
                .selected_text(snap.target.name())
                .show_ui(ui, |ui| {
                    for target in crate::editor::tools::snap_targets::SnapTarget::ALL {
                        ui.selectable_value(&mut snap.target, target, target.name());
                    }
                })
                .response
                .on_hover_text("What a snapped move lands on: whole grid steps, or the vertex, edge midpoint, face centre or surface under the cursor");
            ui.checkbox(&mut snap.absolute, "absolute grid").on_hover_text(
                "A snapped move puts the selection's centre on the grid instead of moving it by whole steps",
            );
            let label = ui.label("rotate step °");
            ui.add(egui::DragValue::new(&mut snap.degrees).speed(0.5).range(0.01..=180.0))
                .labelled_by(label.id)
                .on_hover_text("The angle step of a snapped rotation, in degrees");
            let label = ui.label("scale step");
            ui.add(egui::DragValue::new(&mut snap.scale).speed(0.01).range(1e-6..=10.0))
                .labelled_by(label.id)
                .on_hover_text("The factor step of a snapped scale");
        })
        .response
        .on_hover_text("The snapping steps: grid, angle, scale");
    }

    /// W: shows or hides the gizmo (the toolbar's check box shows which).
    pub(crate) fn toggle_gizmo(&mut self) {
        self.gizmo.shown = !self.gizmo.shown;
    }

    /// Shift+S: the next pivot (the toolbar's combo shows which).
    pub(crate) fn cycle_pivot(&mut self) {
        self.gizmo.pivot = self.gizmo.pivot.next();
    }
}
