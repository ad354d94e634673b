//! What every modal tool is: one [`Tool`] trait (keys, the viewport's pointer, an overlay, a
//! status line, an end that keeps or cancels) and one [`ActiveTool`] that owns the running
//! tool's state, so the viewport and the keyboard hand their input to whichever tool runs
//! without knowing which it is. The tools the designer starts from a key or a menu are listed
//! once, in [`super::TOOLS`]; the ones a press starts (a vertex drag, a box, a curve stroke)
//! start from the viewport that owns the press.
//!
//! A tool that changes the document opens a gesture when it starts (one undo step for the
//! whole tool), emits its edits while it runs, and closes the gesture when it ends: kept, the
//! step stays; cancelled, it first puts back what it changed, so Esc leaves the document bit for
//! bit as it was.

use crate::editor::interaction::ViewportRect;
use crate::editor::shortcuts::take_plain;
use crate::editor::state::EditorState;
use egui::Key;
use glam::Vec2;
use std::any::Any;
use std::fmt::Debug;

/// How a tool's frame ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// It goes on.
    Continue,
    /// It ends, keeping what it did (Enter, a click, the button let go).
    Keep,
    /// It ends, putting back what it did (Esc, a right click).
    Cancel,
}

/// How a tool is ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    Keep,
    Cancel,
    /// The cage it worked on was replaced under it (a file opened from the menu while it ran):
    /// it ends without touching the new one.
    Abandon,
}

/// The viewport as a tool sees it in one frame.
pub struct Pointer<'a> {
    pub ui: &'a egui::Ui,
    pub response: &'a egui::Response,
    pub view: ViewportRect,
    /// The pointer over the viewport, in points.
    pub mouse: Option<Vec2>,
}

impl Pointer<'_> {
    pub fn clicked(&self) -> bool {
        self.response.clicked_by(egui::PointerButton::Primary)
    }

    pub fn right_clicked(&self) -> bool {
        self.response.clicked_by(egui::PointerButton::Secondary)
    }

    /// The primary button drags (a drag tool's movement).
    pub fn dragged(&self) -> bool {
        self.response.dragged_by(egui::PointerButton::Primary)
    }

    /// The primary button was let go after a drag.
    pub fn drag_stopped(&self) -> bool {
        self.response.drag_stopped_by(egui::PointerButton::Primary)
    }

    /// A click keeps the tool's work, a right click cancels it.
    pub fn clicks(&self) -> Flow {
        if self.clicked() {
            Flow::Keep
        } else if self.right_clicked() {
            Flow::Cancel
        } else {
            Flow::Continue
        }
    }

    /// Letting go of the button after a drag keeps the drag.
    pub fn release(&self) -> Flow {
        if self.drag_stopped() { Flow::Keep } else { Flow::Continue }
    }

    pub fn modifiers(&self) -> egui::Modifiers {
        self.ui.ctx().input(|i| i.modifiers)
    }

    /// Writes the tool's status line at the viewport's top left.
    pub fn say(&self, text: &str) {
        let rect = self.response.rect;
        self.ui.painter_at(rect).text(
            rect.left_top() + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            text,
            egui::FontId::proportional(14.0),
            egui::Color32::WHITE,
        );
    }
}

/// Enter keeps, Esc cancels (each taken only without modifiers).
pub fn enter_or_escape(ctx: &egui::Context) -> Flow {
    let (enter, escape) = ctx.input_mut(|i| (take_plain(i, Key::Enter), take_plain(i, Key::Escape)));
    if escape {
        Flow::Cancel
    } else if enter {
        Flow::Keep
    } else {
        Flow::Continue
    }
}

/// Esc cancels; nothing else is taken (the drags that end when the button is let go).
pub fn escape(ctx: &egui::Context) -> Flow {
    if ctx.input_mut(|i| take_plain(i, Key::Escape)) { Flow::Cancel } else { Flow::Continue }
}

/// The cage's topology when a tool began: another one (a file opened from the menu while the
/// tool ran, an undo past its start) makes the tool stale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CageStamp(u64);

impl CageStamp {
    pub fn now(editor: &EditorState) -> Self {
        CageStamp(editor.document.doc().cage.topology_generation())
    }

    pub fn is_stale(self, editor: &EditorState) -> bool {
        self != Self::now(editor)
    }
}

/// Ends a tool that moves cage vertices: cancelled, they go back to `start`; the gesture
/// closes either way.
pub fn end_vertex_move(editor: &mut EditorState, start: Vec<(taut_core::VertexId, taut_core::DVec3)>, end: End) {
    if end == End::Cancel {
        editor.emit(crate::editor::document::Edit::MoveVertices(start));
    }
    editor.emit_end_gesture();
}

/// Any value as `dyn Any`, so the running tool can be asked what it is.
pub trait AsAny: Any {
    fn as_any(&self) -> &dyn Any;
}

impl<T: Any> AsAny for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// A modal tool: while it runs it has the keyboard and the viewport's primary button.
pub trait Tool: AsAny + Debug {
    /// The keys while it runs (Enter, Esc, typed numbers, axis locks); keys it does not take go
    /// nowhere: nothing else runs.
    fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> Flow;

    /// The pointer over the viewport: press, drag, release, clicks.
    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow;

    /// What it draws over the viewport besides its status line.
    fn overlay(&self, _editor: &EditorState, _painter: &egui::Painter, _view: &ViewportRect) {}

    /// The line that says what is happening and which keys do what.
    fn status(&self, editor: &EditorState) -> String;

    /// The numbers of the running change for the header (a move's ΔX ΔY ΔZ and distance, an
    /// angle, a factor, a thickness), when it has any.
    fn readout(&self, _editor: &EditorState) -> Option<String> {
        None
    }

    /// Ends it: keeps its undo step, or puts back what it changed first.
    fn end(self: Box<Self>, editor: &mut EditorState, end: End);

    /// Whether the cage it works on was replaced under it.
    fn is_stale(&self, _editor: &EditorState) -> bool {
        false
    }

    /// Whether the camera keeps its mouse (orbit, pan, zoom) and the cage its hover while it
    /// runs: the drags that follow a press do; the ones that follow the bare mouse do not.
    fn navigates(&self) -> bool {
        false
    }

    /// Whether the transform gizmo is drawn while it runs.
    fn shows_gizmo(&self) -> bool {
        false
    }
}

/// The running tool, if any: the only place a tool's state lives.
#[derive(Debug, Default)]
pub struct ActiveTool(Option<Box<dyn Tool>>);

impl ActiveTool {
    pub fn is_running(&self) -> bool {
        self.0.is_some()
    }

    /// The running tool, when it is a `T` (for tests and for what is drawn around it).
    pub fn get<T: Tool>(&self) -> Option<&T> {
        self.0.as_deref().and_then(|t| AsAny::as_any(t).downcast_ref())
    }

    /// The running tool's numbers for the header.
    pub fn readout(&self, editor: &EditorState) -> Option<String> {
        self.0.as_ref().and_then(|t| t.readout(editor))
    }

    /// Whether the running tool lets the camera navigate.
    pub fn navigates(&self) -> bool {
        self.0.as_ref().is_none_or(|t| t.navigates())
    }

    /// Whether the gizmo is drawn now (no tool, or one that shows it).
    pub fn shows_gizmo(&self) -> bool {
        self.0.as_ref().is_none_or(|t| t.shows_gizmo())
    }

    /// Runs `tool`; a tool running already is kept first (a second key cannot leave an undo
    /// step half open).
    pub fn start(&mut self, editor: &mut EditorState, tool: Box<dyn Tool>) {
        self.end(editor, End::Keep);
        self.0 = Some(tool);
    }

    /// Ends the running tool, if any.
    pub fn end(&mut self, editor: &mut EditorState, end: End) {
        if let Some(tool) = self.0.take() {
            tool.end(editor, end);
        }
    }

    /// Hands the keyboard to the running tool; false when none runs.
    pub fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> bool {
        self.step(editor, |tool, editor| tool.keys(editor, ctx))
    }

    /// Hands the viewport's pointer to the running tool and writes its status line; false when
    /// none runs.
    pub fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> bool {
        let ran = self.step(editor, |tool, editor| tool.pointer(editor, pointer));
        if let Some(tool) = &self.0 {
            tool.overlay(editor, &pointer.ui.painter_at(pointer.response.rect), &pointer.view);
            pointer.say(&tool.status(editor));
        }
        ran
    }

    fn step(&mut self, editor: &mut EditorState, run: impl FnOnce(&mut dyn Tool, &mut EditorState) -> Flow) -> bool {
        let Some(mut tool) = self.0.take() else { return false };
        if tool.is_stale(editor) {
            tool.end(editor, End::Abandon);
            return true;
        }
        match run(tool.as_mut(), editor) {
            Flow::Continue => self.0 = Some(tool),
            Flow::Keep => tool.end(editor, End::Keep),
            Flow::Cancel => tool.end(editor, End::Cancel),
        }
        true
    }
}
