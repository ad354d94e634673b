//! The Curves workspace: drawing and fairing curves, Coons patches, their panels and keys.

pub mod curves_history;
pub mod curves_keys;
pub mod curves_panels;
pub mod curves_render;
pub mod curves_viewport;
pub mod workspace;
