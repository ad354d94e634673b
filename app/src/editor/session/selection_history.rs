//! The selection of each step of the undo history: undo and redo put back the selection the
//! designer had in the state they return to, instead of keeping indices that now name other
//! elements (an edge selected before Triangulate is that edge again after Ctrl+Z).
//!
//! The editor notes the selection with the document's state at the start of every frame, so
//! the selection a step began from is known whatever made the step (a menu, a key, a drag).
//! Entries of states no longer in the history are dropped, so it stays as small as the history.

use crate::editor::document::MAX_UNDO_STEPS;
use crate::editor::state::{EditorState, Selection};
use std::collections::HashMap;

/// The selection last seen in each state of the document.
#[derive(Debug, Default)]
pub struct SelectionHistory {
    by_state: HashMap<u64, Selection>,
}

impl SelectionHistory {
    /// Forgets everything (another document: its states count from zero again).
    pub fn clear(&mut self) {
        self.by_state.clear();
    }
}

impl EditorState {
    /// Notes the selection of the document's current state.
    pub(crate) fn note_selection(&mut self) {
        let history = &mut self.selection_history.by_state;
        let mut selection = self.view.selection.clone();
        (selection.hovered_vertex, selection.hovered_edge, selection.hovered_face) = (None, None, None);
        history.insert(self.document.state(), selection);
        if history.len() > 2 * MAX_UNDO_STEPS + 2 {
            let kept = self.document.history_states();
            history.retain(|state, _| kept.contains(state));
        }
    }

    /// After undo or redo: the selection noted with the state now current, if any.
    pub(crate) fn restore_selection(&mut self) {
        if let Some(selection) = self.selection_history.by_state.get(&self.document.state()) {
            self.view.selection = selection.clone();
        }
        self.prune_selection();
    }
}
