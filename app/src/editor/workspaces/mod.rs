//! The editor's two workspaces.

pub mod curves;
pub mod surface;
