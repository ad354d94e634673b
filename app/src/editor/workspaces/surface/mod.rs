//! The Surface workspace: the cage panels, the Mesh menu's operations, selection modes, mirror,
//! X-ray, the curve-mesh scheme's controls, the colour legend, the draft and highlight views'
//! settings, sections, the clipping plane and the reference images.

pub mod analysis_views;
pub mod clipping;
pub mod curve_mesh_edit;
pub mod curve_mesh_panel;
pub mod display_panel;
pub mod legend;
pub mod mesh_ops;
pub mod mirror;
pub mod panels;
pub mod reference_images;
pub mod sections;
pub mod select_modes;
pub mod xray;
