//! The editor's frame as a loop: input → commands → apply → solve → draw. While egui lays out
//! the panels, menus and keys, nothing of theirs changes the document or starts a tool: they
//! emit a [`Command`], and [`EditorState::apply_commands`] runs the frame's commands in order
//! once the layout is done, through the one place that applies edits and records undo
//! ([`crate::editor::document::EditorDocument::apply`]). The window then steps the solver and
//! draws. A panel therefore never sees half of its own frame's change, and a key and a menu
//! entry run the very same command.
//!
//! A running tool ([`crate::editor::tools::tool`]) is the exception that proves the rule: it
//! has the pointer for the whole gesture, and its edits are applied as it makes them, inside
//! the gesture it opened, because each of its steps reads where the last one left the cage
//! (a loop cut's new vertices, an inset's ring).

use crate::editor::document::Edit;
use crate::editor::shortcuts::Action;
use crate::editor::state::EditorState;
use crate::editor::ui::UiState;

/// What a panel, a menu or a key asks of the session this frame.
#[derive(Clone, Debug)]
pub enum Command {
    /// An edit of the document (one undo step, or part of the open gesture).
    Edit(Edit),
    /// What a shortcut or a menu entry does (the shortcut table's action).
    Action(Action),
    /// Closes the gesture a slider or a field drag opened, after the edit of the frame it was
    /// let go in.
    EndGesture,
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
                }
            }
        }
        any
    }
}
