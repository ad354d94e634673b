//! The editor's frame as a loop: input → commands → apply → solve → draw. While egui lays out
//! the panels, menus and keys, nothing of theirs changes the document or starts a tool: they
//! emit a [`Command`], and [`EditorState::apply_commands`] runs the frame's commands in order
//! once the layout is done, through the one place that applies edits and records undo
//! ([`crate::editor::document::EditorDocument::apply`]). The window then steps the solver and
//! draws. A panel therefore never sees half of its own frame's change, and a key and a menu
//! entry run the very same command.
//!
//! A running tool ([`crate::editor::tools::tool`]) emits its steps the same way: the edits of a
//! drag, the values put back by Esc, the end of its gesture. Only a tool's start changes the
//! document at once (a loop cut or an inset needs the new cage's vertices to go on); a start
//! runs from a key or a menu entry, so it runs here already, while the commands are applied.

use crate::editor::document::Edit;
use crate::editor::shortcuts::Action;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;

/// What a panel, a menu, a key or a running tool asks of the session this frame.
pub enum Command {
    /// An edit of the document (one undo step, or part of the open gesture).
    Edit(Edit),
    /// What a shortcut or a menu entry does (the shortcut table's action).
    Action(Action),
    /// Closes the gesture a slider, a field drag or a tool opened, after the edit of the frame
    /// it was let go in.
    EndGesture,
    /// A change that reads the document it leaves (the Curves workspace's curve set keeps its
    /// selection valid; a cut undone prunes the selection): run in its turn.
    Run(Box<dyn FnOnce(&mut EditorState)>),
}

impl std::fmt::Debug for Command {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Command::Edit(edit) => write!(f, "Edit({})", edit.name()),
            Command::Action(action) => write!(f, "Action({action:?})"),
            Command::EndGesture => write!(f, "EndGesture"),
            Command::Run(_) => write!(f, "Run"),
        }
    }
}

impl EditorState {
    /// Asks for `edit` at the end of the frame.
    pub fn emit(&mut self, edit: Edit) {
        self.commands.push(Command::Edit(edit));
    }

    /// Asks for what `action`'s shortcut does at the end of the frame.
    pub fn emit_action(&mut self, action: Action) {
        self.commands.push(Command::Action(action));
    }

    /// Closes the open gesture at the end of the frame.
    pub(crate) fn emit_end_gesture(&mut self) {
        self.commands.push(Command::EndGesture);
    }

    /// Runs `change` at the end of the frame, in its turn among the other commands.
    pub(crate) fn emit_run(&mut self, change: impl FnOnce(&mut EditorState) + 'static) {
        self.commands.push(Command::Run(Box::new(change)));
    }

    /// Runs the frame's commands in the order they were emitted (the one place they are
    /// applied); true when there were any.
    pub fn apply_commands(&mut self, ui_state: &mut UiState) -> bool {
        let any = !self.commands.is_empty();
        // A command can emit more (an action that edits): they run in the same pass.
        while !self.commands.is_empty() {
            for command in std::mem::take(&mut self.commands) {
                match command {
                    Command::Edit(edit) => self.edit(edit),
                    Command::Action(action) => self.run_action(action, ui_state),
                    Command::EndGesture => self.document.end_gesture(),
                    Command::Run(change) => change(self),
                }
            }
        }
        any
    }
}
