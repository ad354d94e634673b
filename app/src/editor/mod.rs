//! The editor a designer opens: a winit window with egui panels around a wgpu viewport that
//! draws with the render crate. The UI sends edits to the [`document::EditorDocument`] (one
//! place that applies them and records undo), the [`state::EditorState`] keeps the live NUSD
//! solver in step with it, and [`window`] runs a frame as input → edits → solve → render.

pub mod cage_from_mesh;
pub mod cage_job;
#[cfg(test)]
mod cage_tests;
pub mod curve_mesh_edit;
pub mod curves;
mod curves_history;
mod curves_keys;
mod curves_panels;
mod curves_render;
mod curves_viewport;
#[cfg(test)]
mod defect_tests;
pub mod document;
pub mod files;
pub mod interaction;
pub mod live;
pub mod menus;
pub mod mesh_ops;
#[cfg(test)]
mod mesh_ops_tests;
pub mod new_primitive;
#[cfg(test)]
mod panel_tests;
mod panels;
pub mod primitives;
#[cfg(test)]
mod scheme_tests;
pub mod select_modes;
pub mod shortcuts;
pub mod state;
pub mod transform;
pub mod ui;
mod viewport;
pub mod window;
