//! The editor a designer opens: a winit window with egui panels around a wgpu viewport that
//! draws with the render crate. The UI sends edits to the [`document::EditorDocument`] (one
//! place that applies them and records undo), the [`state::EditorState`] keeps the live NUSD
//! solver in step with it, and [`window`] runs a frame as input → edits → solve → render.

pub mod cage_from_mesh;
pub mod cage_job;
#[cfg(test)]
mod cage_tests;
pub mod curve_mesh_edit;
mod curve_mesh_panel;
pub mod curves;
mod curves_history;
mod curves_keys;
mod curves_panels;
mod curves_render;
mod curves_viewport;
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
mod display_panel;
pub mod document;
#[cfg(test)]
mod edit_script_tests;
mod extrude_move;
pub mod files;
pub mod gizmo;
#[cfg(test)]
mod gizmo_tests;
pub mod inset_drag;
pub mod interaction;
mod legend;
pub mod live;
pub mod loop_slide;
pub mod menus;
pub mod mesh_ops;
#[cfg(test)]
mod mesh_ops_tests;
pub mod mirror;
#[cfg(test)]
mod modelling_gesture_tests;
mod navigation;
pub mod new_primitive;
#[cfg(test)]
mod panel_tests;
mod panels;
pub mod pivot;
pub mod primitives;
#[cfg(test)]
mod scheme_tests;
pub mod select_modes;
mod selection_history;
pub mod shortcuts;
pub mod snapping;
pub mod state;
pub mod step_export;
#[cfg(test)]
mod step_export_tests;
mod toolbar;
pub mod transform;
pub mod ui;
mod viewport;
pub mod window;
pub mod xray;
