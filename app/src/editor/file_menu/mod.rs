//! The File menu's work: new cages, making a cage from a mesh, the STEP export, and the in-app
//! file browser of the path dialog.

pub mod cage_from_mesh;
pub mod cage_job;
pub mod file_browser;
pub mod new_primitive;
pub mod primitives;
pub mod step_export;
