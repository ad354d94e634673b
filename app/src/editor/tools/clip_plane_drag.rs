//! Dragging the clipping plane's handle: the plane follows the mouse along its normal (the
//! point of the axis nearest the mouse ray, as a gizmo's axis drag), the header shows where it
//! is; letting go keeps it, Esc puts it back. The plane is a view setting, not part of the
//! document: nothing is recorded for undo.

use crate::editor::interaction::{self, Axis};
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool, escape};
use crate::editor::workspaces::surface::clipping::ClipSettings;
use glam::{DVec3, Vec2};

#[derive(Clone, Debug)]
pub struct ClipPlaneDrag {
    /// The plane when the drag began (Esc puts it back).
    before: ClipSettings,
    /// The handle's base in display coordinates, and where the press was.
    anchor: DVec3,
    mouse_start: Vec2,
}

/// Starts dragging the clipping plane from a press at `mouse` on its handle.
pub(crate) fn start(editor: &EditorState, view: &interaction::ViewportRect, mouse: Vec2) -> Option<Box<dyn Tool>> {
    let before = editor.view.display.clip?;
    let (_, _, anchor) = editor.clip_handle(view)?;
    Some(Box::new(ClipPlaneDrag { before, anchor, mouse_start: mouse }))
}

impl ClipPlaneDrag {
    fn axis(&self) -> Axis {
        [Axis::X, Axis::Y, Axis::Z][self.before.axis.min(2)]
    }
}

impl Tool for ClipPlaneDrag {
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        escape(ctx)
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged()
            && let Some(mouse) = pointer.mouse
        {
            let moved = interaction::drag_positions(
                &editor.view.camera,
                &pointer.view,
                &[(taut_core::VertexId(0), self.anchor)],
                self.mouse_start,
                mouse,
                Some(self.axis()),
            );
            let k = self.before.axis.min(2);
            let along = (moved[0].1 - self.anchor)[k] * editor.view.display_frame.scale;
            if along.is_finite() {
                editor.view.display.clip = Some(ClipSettings { offset: self.before.offset + along, ..self.before });
            }
        }
        pointer.release()
    }

    fn overlay(&self, editor: &EditorState, painter: &egui::Painter, view: &interaction::ViewportRect) {
        editor.draw_clip_handle(painter, view, true);
    }

    fn status(&self, _editor: &EditorState) -> String {
        "moving the clipping plane: let go to keep it, Esc puts it back".into()
    }

    fn readout(&self, editor: &EditorState) -> Option<String> {
        let now = editor.view.display.clip?;
        let name = ["X", "Y", "Z"][now.axis.min(2)];
        let unit = editor.document.doc().units;
        Some(format!(
            "clipping plane {name} = {}  Δ{name} {}",
            unit.length(now.offset),
            unit.length(now.offset - self.before.offset)
        ))
    }

    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        if end == End::Cancel {
            editor.view.display.clip = Some(self.before);
        }
    }
}
