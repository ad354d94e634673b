//! A left drag that begins away from the cage draws a rubber band; letting go selects what is
//! inside, in the select mode's elements. Shift held when the band begins adds to the
//! selection (letting go of Shift before the button does not change what it does); Esc drops
//! the band and leaves the selection as it was.

use crate::editor::interaction::ViewportRect;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool, escape};
use glam::Vec2;

/// A rubber band being drawn: its corners, and whether it adds to the selection.
#[derive(Clone, Copy, Debug)]
pub struct BoxSelect {
    from: Vec2,
    to: Vec2,
    add: bool,
    /// Where it was let go: the view the band is read in.
    view: Option<ViewportRect>,
}

/// Starts a band at `origin`.
pub(crate) fn start(origin: Vec2, add: bool) -> Box<dyn Tool> {
    Box::new(BoxSelect { from: origin, to: origin, add, view: None })
}

impl Tool for BoxSelect {
    fn keys(&mut self, _editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        escape(ctx)
    }

    fn pointer(&mut self, _editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.dragged()
            && let Some(m) = pointer.mouse
        {
            self.to = m;
        }
        self.view = Some(pointer.view);
        pointer.release()
    }

    fn overlay(&self, _editor: &EditorState, painter: &egui::Painter, _view: &ViewportRect) {
        let r = egui::Rect::from_two_pos(egui::pos2(self.from.x, self.from.y), egui::pos2(self.to.x, self.to.y));
        painter.rect_stroke(
            r,
            0.0,
            egui::Stroke::new(1.0, egui::Color32::from_rgb(255, 170, 60)),
            egui::StrokeKind::Inside,
        );
    }

    fn status(&self, _editor: &EditorState) -> String {
        let how = if self.add { "adds to" } else { "replaces" };
        format!("box select: let go to select what is inside (it {how} the selection), Esc drops the box")
    }

    /// Let go: what is inside becomes (or joins) the selection.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End) {
        let (End::Keep, Some(view)) = (end, self.view) else { return };
        if !self.add {
            editor.view.selection.clear();
        }
        let cage = editor.display_cage();
        let boxed = editor.box_cage(&view, &cage, self.from, self.to);
        editor.box_select_in_mode(boxed);
    }

    fn navigates(&self) -> bool {
        true
    }

    fn shows_gizmo(&self) -> bool {
        true
    }
}
