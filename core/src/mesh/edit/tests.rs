//! Cross-operation tests of the edits.
