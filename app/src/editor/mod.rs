//! The editor a designer opens: a winit window with egui panels around a wgpu viewport that
//! draws with the render crate. The UI sends edits to the [`document::EditorDocument`] (one
//! place that applies them and records undo), the [`state::EditorState`] keeps the live NUSD
//! solver in step with it, and [`window`] runs a frame as input → edits → solve → render.

pub mod file_menu;
pub mod gpu;
pub mod session;
pub mod tools;
pub mod workspaces;

// The modules of the folders, at the editor's level as before the folders: `super::document`
// and `crate::editor::document` name the same module.
pub use file_menu::{cage_from_mesh, cage_job, new_primitive, primitives, step_export};
pub use gpu::window;
use session::selection_history;
pub use session::{document, files, live, state};
pub use tools::{gizmo, pivot, snapping, transform};
pub use workspaces::curves::workspace as curves;
use workspaces::curves::{curves_history, curves_keys, curves_render};
use workspaces::surface::legend;
pub use workspaces::surface::{curve_mesh_edit, mesh_ops, mirror, select_modes, xray};

#[cfg(test)]
mod cage_tests;
#[cfg(test)]
mod defect_tests;
#[cfg(test)]
mod defects_files_tests;
#[cfg(test)]
mod defects_mode_tests;
#[cfg(test)]
mod defects_solver_tests;
#[cfg(test)]
mod defects_xray_tests;
#[cfg(test)]
mod edit_script_tests;
#[cfg(test)]
mod gizmo_tests;
pub mod interaction;
pub mod menus;
#[cfg(test)]
mod mesh_ops_tests;
#[cfg(test)]
mod modelling_gesture_tests;
mod navigation;
#[cfg(test)]
mod panel_tests;
#[cfg(test)]
mod reference_images_tests;
#[cfg(test)]
mod scheme_tests;
pub mod shortcuts;
#[cfg(test)]
mod step_export_tests;
#[cfg(test)]
mod tool_cancel_tests;
pub mod ui;
pub(crate) mod viewport;
