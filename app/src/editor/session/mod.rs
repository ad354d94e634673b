//! The session: the open document with its undo history and journal, the editor's state, the
//! live surface kept in step with the document, and what the editor keeps on disk.

pub mod commands;
pub mod document;
pub mod files;
pub mod framing;
pub mod live;
pub mod selection_history;
pub mod state;
